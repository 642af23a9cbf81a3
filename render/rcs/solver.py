"""User-level radar cross-section: quality presets, polarisations and an error estimate.

:func:`compute_rcs` wraps :class:`csuas.render.rcs.engine.SbrEngine` for a grid
of frequencies x aspects (monostatic) or x receivers (bistatic) in one launch
and returns an :class:`RcsResult` with every polarisation, the discretisation
error estimate and the cost.

Error estimate. The single reflection of every fully lit facet is integrated
exactly (:meth:`csuas.render.rcs.engine.SbrEngine._exact_first_hits`); what the
tube grid still samples (partly shadowed facets, multiple reflections, thin-shell
transmission) is a lattice rule whose error changes with the grid's placement.
The run is made of ``K`` replicas (default :data:`REPLICAS`), each on the same
tube grid shifted by an independent uniform random offset (a Cranley-Patterson
randomisation: each replica's field is an unbiased estimate of the grid-free
field where the footprint integrals are exact). The result is the mean complex
field; its standard error ``SE = s / sqrt(K)`` comes from the spread ``s`` of the
replicas, and

    error_db = -20 log10(1 - c_K SE / |E|),    c_K^2 = F_p(2, 2(K - 1)),

where ``K |mean - E|^2 / s^2`` follows ``F(2, 2(K - 1))`` for a complex-Gaussian
replica error (Hotelling's T^2 for two components). At the level
``p = BOUND_LEVEL = 0.99`` (``c_4 = 3.31``) the bound covered the true error in
96 % of a test population of 148 cases (spheres ka 3-50, the NASA almond, plates,
corner reflectors off axis, the drone; ``tests/test_rcs_error_estimate.py``);
at ``p = 0.95`` only 93 %, since coarse grids err with heavier tails. When
``c_K SE >= |E|`` no bound exists and ``error_db`` is infinite. The replicas
cost no extra over one grid of twice the density: the preset densities were
halved when the estimate moved from a half-density rerun to replicas.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.units import wavelength_m
from csuas.render.quality import RCS

from .edge_residual import residual_relative
from .engine import BATCH_SIZE_CPU, DEFAULT_GRID_SHIFT, POWER_CUTOFF, Jobs, SbrEngine
from .geometry import load_target
from .model_error import db_from_relative, floor_error_db, model_error_db, total_bound_db
from .thin_wire import wire_field

#: Quality presets from :data:`csuas.render.quality.RCS`: name -> ``{"rays_per_wavelength", "max_bounces"}``.
QUALITY_PRESETS = RCS.presets(lambda name, **values: values)

#: Smallest error estimate [dB]: the float32 arithmetic of the engine, measured at most 0.0033 dB against
#: the float64 faceted-PO oracle (NASA almond nulls 40 dB below its peak; spheres ka 3-50 below 0.0002 dB).
ERROR_FLOOR_DB = 0.01

#: Confidence level of the Gaussian replica model behind the error bound. The replica errors of a
#: coarse tube grid have heavier tails than a Gaussian, so the model's 95 % bound covered only 93 % of
#: the test population (tests/test_rcs_error_estimate.py); its 99 % bound covers at least 95 % there.
BOUND_LEVEL = 0.99

#: Grid replicas of a run with an error estimate (module docstring); 1 without one.
REPLICAS = 4

#: Seed of the replicas' grid offsets: the same offsets every run, so that results are reproducible.
REPLICA_SEED = 20_141


def replica_shifts(replicas: int) -> np.ndarray:
    """Grid offsets (K, 2) of the replicas, in tube spacings: independent and uniform, seeded.

    One replica keeps the engine's default offset (:data:`csuas.render.rcs.engine.DEFAULT_GRID_SHIFT`).
    """
    if replicas == 1:
        return np.asarray([DEFAULT_GRID_SHIFT], float)
    return np.random.default_rng(REPLICA_SEED).uniform(0.0, 1.0, (replicas, 2))


def coverage_factor(replicas: int) -> float:
    """c_K of the module docstring: the bound on |error| in units of the standard error."""
    from scipy.stats import f

    return float(np.sqrt(f.ppf(BOUND_LEVEL, 2, 2 * (replicas - 1))))


def lower_side_db(relative, db_per_decade: float):
    """The larger side of an error bound in dB: -X log10(1 - e) for a relative half-width e, inf from e >= 1.

    ``db_per_decade`` X is 20 for a bound on an amplitude, 10 for one on a power.
    """
    e = np.asarray(relative, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(e < 1.0, -db_per_decade * np.log10(1.0 - np.minimum(e, 0.999999)), np.inf)


def replica_error_db(amplitudes: np.ndarray, known_error=0.0) -> tuple[np.ndarray, np.ndarray]:
    """Mean amplitude and the error bound of its power [dB] (at :data:`BOUND_LEVEL`) from replicas on axis 0.

    Parameters
    ----------
    amplitudes : ndarray complex (K, ...)
        Field of each replica, K >= 2.
    known_error : ndarray (...) or float
        A bound of the amplitude's error from elsewhere [m] (the thin wires' segments), added to ``c_K SE``.

    Returns
    -------
    mean : ndarray complex (...)
    error_db : ndarray (...)
        ``-20 log10(1 - c_K SE / |mean|)`` [dB], at least :data:`ERROR_FLOOR_DB`; ``inf`` where the
        bound reaches |mean|; the floor where the replicas agree exactly (even on a zero field).
    """
    k = amplitudes.shape[0]
    mean = amplitudes.mean(axis=0)
    spread = np.sqrt(np.sum(np.abs(amplitudes - mean) ** 2, axis=0) / (k - 1))
    with np.errstate(divide="ignore", invalid="ignore"):
        error = lower_side_db((coverage_factor(k) * spread / np.sqrt(k) + known_error) / np.abs(mean), 20.0)
    # replicas that agree exactly (a field of exactly integrated facets only, or none) carry no grid error
    error = np.where((spread == 0.0) & (np.asarray(known_error) == 0.0), 0.0, error)
    return mean, np.maximum(error, ERROR_FLOOR_DB)


#: Polarisation name -> (receive index, transmit index); 0 = V (theta-hat), 1 = H (phi-hat).
POLARISATIONS = {"VV": (0, 0), "HH": (1, 1), "HV": (1, 0), "VH": (0, 1)}

#: dBsm reported for a zero cross-section (no tube hit the target): finite, never -inf.
DBSM_FLOOR = -300.0


def to_dbsm(sigma_m2):
    """10 log10(sigma / 1 m^2), floored at :data:`DBSM_FLOOR` (0 m^2 gives -300 dBsm)."""
    return np.maximum(10.0 * np.log10(np.maximum(np.asarray(sigma_m2, float), 1e-300)), DBSM_FLOOR)


@dataclass
class RcsResult:
    """RCS of a target over frequencies x aspects (x receivers).

    Attributes
    ----------
    sigma_m2 : ndarray (F, A, M, 2, 2)
        RCS [m^2] for receive (V, H) x transmit (V, H); see :data:`POLARISATIONS`.
    error_db : ndarray (F, A, M, 2, 2) or None
        Discretisation error estimate [dB] (module docstring).
    frequency_ghz : ndarray (F,)
    azimuth_deg, elevation_deg : ndarray (A,)
        Incidence (transmitter) directions [deg], docs/command-line.md convention.
    observe_azimuth_deg, observe_elevation_deg : ndarray (A, M)
        Receiver directions [deg]; equal to the incidence for monostatic.
    rays_per_wavelength, max_bounces : float, int
        Accuracy knobs used.
    tubes : int
        Tubes launched over all replicas (the ``rays`` of docs/command-line.md).
    ray_casts : int
        Ray-scene queries (tubes x bounces, and the visibility rays of the exact first hits).
    exits_by_bounce : ndarray
        Tubes radiating after 0 (missed), 1, 2, ... bounces.
    time_s : float
        Wall time of one replica's share of the run [s]; ``error_time_s`` the other replicas' share,
        the cost of the error estimate.
    replicas : int
        Shifted grids averaged (module docstring); 1 without an error estimate.
    model_error_db : ndarray (F,) or None
        Bound of physical optics' own error against the exact answer [dB]
        (:mod:`csuas.render.rcs.model_error`, from the target's bounding radius).
    truncated_sigma_m2 : ndarray (F, A, 2) or None
        RCS [m^2] the tubes still alive at the bounce limit could add, per transmit polarisation (V, H)
        (:class:`csuas.render.rcs.engine.TraceResult` ``live_sigma_m2``, mean of the replicas).
    edge_residual_m : ndarray (F, A, M, 2, 2) or None
        Bound [m] of the edge waves first-order PTD misses (:mod:`csuas.render.rcs.edge_residual`);
        None without edge diffraction or edges.
    """

    sigma_m2: np.ndarray
    error_db: np.ndarray | None
    frequency_ghz: np.ndarray
    azimuth_deg: np.ndarray
    elevation_deg: np.ndarray
    observe_azimuth_deg: np.ndarray
    observe_elevation_deg: np.ndarray
    rays_per_wavelength: float
    max_bounces: int
    tubes: int
    ray_casts: int
    exits_by_bounce: np.ndarray
    time_s: float
    error_time_s: float = 0.0
    target_name: str = ""
    materials: list = field(default_factory=list)
    variant: str = ""
    replicas: int = 1
    model_error_db: np.ndarray | None = None
    truncated_sigma_m2: np.ndarray | None = None
    edge_residual_m: np.ndarray | None = None

    def rcs_m2(self, polarisation: str = "VV") -> np.ndarray:
        """RCS (F, A, M) [m^2] of one polarisation ("VV", "HH", "HV", "VH")."""
        rx, tx = _polarisation(polarisation)
        return self.sigma_m2[..., rx, tx]

    def rcs_dbsm(self, polarisation: str = "VV") -> np.ndarray:
        """RCS (F, A, M) [dBsm] of one polarisation, floored at -300 dBsm."""
        return to_dbsm(self.rcs_m2(polarisation))

    def error_estimate_db(self, polarisation: str = "VV") -> np.ndarray | None:
        """Error estimate (F, A, M) [dB] of one polarisation, or None when not computed."""
        if self.error_db is None:
            return None
        rx, tx = _polarisation(polarisation)
        return self.error_db[..., rx, tx]

    def truncation_db(self, polarisation: str = "VV") -> np.ndarray | None:
        """The bounce limit's term (F, A, M) [dB]: relative amplitude sqrt(truncated sigma / sigma).

        The tubes still alive at the limit re-radiating once more at random phase (their sum's rms);
        0 dB where none is alive, ``inf`` where they could outweigh the result.
        """
        if self.truncated_sigma_m2 is None:
            return None
        _, tx = _polarisation(polarisation)
        sigma = self.rcs_m2(polarisation)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(sigma > 0.0, self.truncated_sigma_m2[..., tx][..., None] / sigma, np.inf)
        return db_from_relative(np.sqrt(np.where(self.truncated_sigma_m2[..., tx][..., None] > 0.0, ratio, 0.0)))

    def edge_residual_db(self, polarisation: str = "VV") -> np.ndarray | None:
        """The edge waves' term (F, A, M) [dB] of the bound (:mod:`csuas.render.rcs.edge_residual`), or None
        without edge diffraction or edges."""
        if self.edge_residual_m is None:
            return None
        rx, tx = _polarisation(polarisation)
        return db_from_relative(residual_relative(self.edge_residual_m[..., rx, tx], self.rcs_m2(polarisation)))

    def bound_db(self, polarisation: str = "VV") -> np.ndarray | None:
        """Bound (F, A, M) [dB] against the exact answer: discretisation, PO's model error and floor, truncation and
        the edge waves PTD misses (with edge diffraction) together.

        None without an error estimate or a model term; ``inf`` where a term has no bound.
        """
        disc = self.error_estimate_db(polarisation)
        if disc is None or self.model_error_db is None:
            return None
        truncation, edges = self.truncation_db(polarisation), self.edge_residual_db(polarisation)
        return total_bound_db(
            disc,
            self.model_error_db[:, None, None],
            self.model_floor_db(polarisation),
            0.0 if truncation is None else truncation,
            0.0 if edges is None else edges,
        )

    def model_floor_db(self, polarisation: str = "VV") -> np.ndarray:
        """PO's absolute-amplitude floor (F, A, M) [dB] on this result (:func:`model_error.floor_error_db`)."""
        return floor_error_db(self.frequency_ghz[:, None, None], self.rcs_m2(polarisation))

    @property
    def rays_x_bounces_per_s(self) -> float:
        """Ray-scene intersection queries per second of the main run [1/s]."""
        return self.ray_casts / self.time_s if self.time_s > 0 else float("nan")


def _polarisation(name: str) -> tuple[int, int]:
    key = str(name).upper()
    if key not in POLARISATIONS:
        raise ParameterError("polarisation", name, ", ".join(POLARISATIONS))
    return POLARISATIONS[key]


#: Largest bounce limit accepted: a tube that has not left a drone-sized target after 50 reflections
#: carries a negligible field (each reflection off a lossy part loses energy), and the per-bounce
#: output arrays grow with the limit.
MAX_BOUNCES = 50


def resolve_quality(quality: str | None, rays_per_wavelength=None, max_bounces=None) -> tuple[float, int]:
    """Tube density and bounce limit from a preset name and explicit overrides."""
    if quality is None:
        quality = "standard"
    if quality not in QUALITY_PRESETS:
        raise ParameterError("quality", quality, ", ".join(QUALITY_PRESETS))
    preset = QUALITY_PRESETS[quality]
    n = preset["rays_per_wavelength"] if rays_per_wavelength is None else rays_per_wavelength
    b = preset["max_bounces"] if max_bounces is None else max_bounces
    try:
        n = float(n)
    except (TypeError, ValueError):
        raise ParameterError("rays_per_wavelength", rays_per_wavelength, "a number >= 1") from None
    if not (math.isfinite(n) and n >= 1.0):
        raise ParameterError("rays_per_wavelength", rays_per_wavelength, "a number >= 1")
    if isinstance(b, bool) or not isinstance(b, (int, np.integer)) or not (1 <= b <= MAX_BOUNCES):
        raise ParameterError("max_bounces", max_bounces, f"an integer from 1 to {MAX_BOUNCES}")
    return n, int(b)


#: Measured throughput of the SBR engine on 2 CPU cores [tube bounces / s] (README, "SBR throughput").
TUBE_BOUNCES_PER_S_CPU = 9.5e6


def estimate_tubes(bounding_radius_m: float, frequency_ghz: float, rays_per_wavelength: float) -> int:
    """Upper bound of the tubes of one aspect: the square grid over the target's bounding disc.

    The engine launches tubes over the projected hull, which lies inside the disc of radius
    ``bounding_radius_m``; spacing = lambda / rays_per_wavelength.
    """
    spacing = wavelength_m(frequency_ghz) / rays_per_wavelength
    return int((math.ceil(2.0 * bounding_radius_m / spacing) + 1) ** 2)


def estimate_seconds(tubes: float, max_bounces: int) -> float:
    """Rough wall time of tracing ``tubes`` tubes on 2 CPU cores [s], assuming two bounces each.

    Most tubes of a drone leave after one or two reflections; ``max_bounces`` caps the count.
    """
    return tubes * min(2, max_bounces) / TUBE_BOUNCES_PER_S_CPU


#: Resident memory of a process with Dr.Jit and an SBR engine of a drone, before tracing [B], and per tube
#: of the grid in flight [B]: a sweep of 7 aspects of the DJI Mini 4 Pro at 35 GHz (``csuas bench --only
#: cost_models``, 2 CPU cores) peaked at 398, 677 and 803 MB for grids of 6.4e4, 2.5e5 and 1e6 tubes.
ENGINE_PROCESS_BYTES = 370e6
TUBE_BYTES = 450.0


def estimate_peak_bytes(tubes_per_grid: float) -> float:
    """Peak resident memory of tracing grids of ``tubes_per_grid`` tubes (one aspect's), on CPU [B].

    A grid's tubes are in flight together, at most ``BATCH_SIZE_CPU`` of them, so the memory stops
    growing there whatever the aspects, replicas and frequencies.
    """
    return ENGINE_PROCESS_BYTES + TUBE_BYTES * min(float(tubes_per_grid), float(BATCH_SIZE_CPU))


_ENGINES: dict = {}


def get_engine(target, material=None, batch_size=None, shell_thickness_m=None) -> SbrEngine:
    """An :class:`SbrEngine` for a target, reused for the same mesh object, material and shells."""
    if isinstance(target, SbrEngine):
        return target
    key = (id(target), repr(material), batch_size, shell_thickness_m)
    cached = _ENGINES.get(key)
    if cached is not None and cached[0] is target:
        return cached[1]
    engine = SbrEngine(load_target(target, material, shell_thickness_m), batch_size=batch_size)
    if len(_ENGINES) > 8:
        _ENGINES.clear()
    _ENGINES[key] = (target, engine)
    return engine


def _edge_amplitude(engine: SbrEngine, az, el, frequency_ghz, observe_az, observe_el):
    """PTD fringe amplitude (J, M, 2, 2) of the engine's edges [m] and the bound R (J, M, 2, 2) [m] of the
    waves it misses (:mod:`csuas.render.rcs.edge_residual`)."""
    from .edge_residual import residual_amplitude
    from .edges import edge_amplitude, edge_visibility

    n_f = len(az) // len(observe_az)
    oaz, oel = np.tile(observe_az, (n_f, 1)), np.tile(observe_el, (n_f, 1))
    visible = edge_visibility(engine, engine.edges, az, el, oaz, oel)
    return (
        edge_amplitude(engine.edges, az, el, frequency_ghz, oaz, oel, visible=visible),
        residual_amplitude(engine.edges, az, el, frequency_ghz, oaz, oel, visible),
    )


def _receivers(az, el, observe_azimuth_deg, observe_elevation_deg) -> tuple[np.ndarray, np.ndarray]:
    """Receiver directions (A, M) [deg]: the incidence (monostatic) or the observe angles broadcast."""
    if observe_azimuth_deg is None and observe_elevation_deg is None:
        return az[:, None], el[:, None]
    if observe_azimuth_deg is None or observe_elevation_deg is None:
        raise ParameterError(
            "observe_elevation_deg" if observe_elevation_deg is None else "observe_azimuth_deg",
            None,
            "both observe angles, or neither (monostatic)",
        )
    oaz, oel = np.broadcast_arrays(
        np.atleast_1d(np.asarray(observe_azimuth_deg, float)), np.atleast_1d(np.asarray(observe_elevation_deg, float))
    )
    oaz = np.broadcast_to(oaz if oaz.ndim == 2 else oaz[None, :], (len(az), oaz.shape[-1]))
    oel = np.broadcast_to(oel if oel.ndim == 2 else oel[None, :], (len(az), oel.shape[-1]))
    return oaz, oel


@dataclass(frozen=True)
class RcsAspects:
    """The grid a run computes: frequencies x transmitter directions x receivers.

    Attributes
    ----------
    frequency_ghz : np.ndarray (F,)
        Radar frequencies [GHz], finite and > 0.
    azimuth_deg, elevation_deg : np.ndarray (A,)
        Directions from the target toward the transmitter [deg].
    observe_azimuth_deg, observe_elevation_deg : np.ndarray (A, M)
        Receiver directions [deg]; the transmitter's own for monostatic RCS.
    """

    frequency_ghz: np.ndarray
    azimuth_deg: np.ndarray
    elevation_deg: np.ndarray
    observe_azimuth_deg: np.ndarray
    observe_elevation_deg: np.ndarray

    @classmethod
    def of(
        cls, frequency_ghz, azimuth_deg=0.0, elevation_deg=0.0, observe_azimuth_deg=None, observe_elevation_deg=None
    ):
        """Checked and broadcast grid (arguments as :func:`compute_rcs` takes them).

        Raises
        ------
        ParameterError
            A non-positive or non-finite frequency, or angles out of range.
        """
        freq = np.atleast_1d(np.asarray(frequency_ghz, dtype=float)).ravel()
        bad = ~(np.isfinite(freq) & (freq > 0))
        if len(freq) == 0 or bad.any():
            raise ParameterError("frequency_ghz", float(freq[bad][0]) if bad.any() else [], "0 < f < inf GHz")
        az, el = np.broadcast_arrays(
            np.atleast_1d(np.asarray(azimuth_deg, float)), np.atleast_1d(np.asarray(elevation_deg, float))
        )
        az, el = az.ravel(), el.ravel()
        oaz, oel = _receivers(az, el, observe_azimuth_deg, observe_elevation_deg)
        return cls(freq, az, el, oaz, oel)


@dataclass(frozen=True)
class RcsTracing:
    """How a run traces (resolved from a quality preset and its overrides by :func:`compute_rcs`).

    Attributes
    ----------
    rays_per_wavelength : float
        Tube density N.
    max_bounces : int
    error_estimate : bool
        Trace :data:`REPLICAS` shifted grids and bound the error from their spread.
    radiate : {"exit", "all"}
        Radiate at each tube's last hit (Ling et al.) or at every hit.
    power_cutoff : float
        Relative tube power below which a tube stops.
    edge_diffraction : bool
        Add the PTD fringe field of the target's edges (:mod:`csuas.render.rcs.edges`).
    """

    rays_per_wavelength: float
    max_bounces: int
    error_estimate: bool = True
    radiate: str = "exit"
    power_cutoff: float = POWER_CUTOFF
    edge_diffraction: bool = False


def compute_rcs(
    target,
    frequency_ghz,
    azimuth_deg=0.0,
    elevation_deg=0.0,
    *,
    observe_azimuth_deg=None,
    observe_elevation_deg=None,
    material=None,
    quality: str | None = "standard",
    rays_per_wavelength=None,
    max_bounces=None,
    error_estimate: bool = True,
    radiate: str = "exit",
    batch_size: int | None = None,
    shell_thickness_m: float | None = None,
    power_cutoff: float = POWER_CUTOFF,
    edge_diffraction: bool = False,
) -> RcsResult:
    """Radar cross-section of a mesh by SBR-PO for frequencies x aspects (the keyword form of :func:`rcs_of`).

    Parameters
    ----------
    target : trimesh.Trimesh, TargetMesh, SbrEngine, str or Path
        Mesh (metres), mesh file, drone preset name, or a prepared engine.
    frequency_ghz : float or array_like (F,)
        Radar frequencies [GHz].
    azimuth_deg, elevation_deg : float or array_like, broadcast to (A,)
        Directions from the target toward the transmitter [deg] (docs/command-line.md).
    observe_azimuth_deg, observe_elevation_deg : array_like (M,) or (A, M), optional
        Receiver directions [deg] for bistatic RCS; default monostatic.
    material : str or material, optional
        One material for all faces (``"pec"``, ITU or drone material name);
        default: a preset's part materials, PEC for a plain mesh.
    shell_thickness_m : float, optional
        Dielectric materials become thin shells of this thickness [m] (0:
        half-spaces); default: drone presets' plastics are 2 mm shells,
        anything else a half-space (:func:`load_target`).
    quality : {"draft", "standard", "reference"}
        Preset of :data:`QUALITY_PRESETS`; ``rays_per_wavelength`` and
        ``max_bounces`` override it.
    error_estimate : bool
        Trace :data:`REPLICAS` shifted grids and bound the error from their spread (module
        docstring); False traces one grid (a quarter of the time) without an estimate.
    radiate : {"exit", "all"}
        Radiate at each tube's last hit (Ling et al.) or at every hit.
    batch_size : int, optional
        Tubes in flight (memory bound); default by device.
    power_cutoff : float
        Relative tube power below which a tube stops (bounds the branching at
        thin shells); see :data:`csuas.render.rcs.engine.POWER_CUTOFF`.
    edge_diffraction : bool
        Add the fringe field of the target's conducting wedge edges and sheet rims
        (PTD, :mod:`csuas.render.rcs.edges`), shadow-tested by one ray per edge.

    Returns
    -------
    RcsResult

    Raises
    ------
    ParameterError
        Non-positive or non-finite frequency, ``rays_per_wavelength < 1``,
        ``max_bounces < 1``, angles out of range, unknown material or preset.
    """
    n, bounces = resolve_quality(quality, rays_per_wavelength, max_bounces)
    aspects = RcsAspects.of(frequency_ghz, azimuth_deg, elevation_deg, observe_azimuth_deg, observe_elevation_deg)
    engine = get_engine(target, material, batch_size, shell_thickness_m)
    tracing = RcsTracing(n, bounces, error_estimate, radiate, power_cutoff, edge_diffraction)
    return rcs_of(engine, aspects, tracing)


def rcs_of(engine: SbrEngine, aspects: RcsAspects, tracing: RcsTracing) -> RcsResult:
    """Radar cross-section of a prepared engine's target over a grid, with its error estimate.

    Parameters
    ----------
    engine : SbrEngine
        The target, prepared (:func:`get_engine`).
    aspects : RcsAspects
        Frequencies x transmitter directions x receivers.
    tracing : RcsTracing
        Tube density, bounces, replicas and the optional terms.

    Returns
    -------
    RcsResult
    """
    freq, az, el = aspects.frequency_ghz, aspects.azimuth_deg, aspects.elevation_deg
    oaz, oel = aspects.observe_azimuth_deg, aspects.observe_elevation_deg
    n_f, n_a = len(freq), len(az)
    f_job = np.repeat(freq, n_a)
    shifts = replica_shifts(REPLICAS if tracing.error_estimate else 1)
    replicas = len(shifts)
    jobs = Jobs.build(
        np.tile(az, n_f * replicas),
        np.tile(el, n_f * replicas),
        np.tile(f_job, replicas),
        tracing.rays_per_wavelength,
        np.tile(oaz, (n_f * replicas, 1)),
        np.tile(oel, (n_f * replicas, 1)),
        np.repeat(shifts, n_f * n_a, axis=0),
    )
    main = engine.trace(jobs, tracing.max_bounces, tracing.radiate, tracing.power_cutoff)
    shape = (n_f, n_a, oaz.shape[1], 2, 2)
    amplitude = main.amplitude.reshape((replicas, *shape))
    edge_residual = None
    if tracing.edge_diffraction and len(engine.edges) > 0:
        edge, edge_residual = _edge_amplitude(engine, np.tile(az, n_f), np.tile(el, n_f), f_job, oaz, oel)
        amplitude = amplitude + edge.reshape(shape)
    wire_error, wire_start = 0.0, time.perf_counter()
    if engine.target.wires is not None:
        wire, wire_error = wire_field(
            engine.target.wires,
            f_job,
            (np.tile(az, n_f), np.tile(el, n_f)),
            (np.tile(oaz, (n_f, 1)), np.tile(oel, (n_f, 1))),
        )
        amplitude, wire_error = amplitude + wire.reshape(shape), wire_error.reshape(shape)
    error_db, error_time = None, 0.0
    if replicas > 1:
        amplitude, error_db = replica_error_db(amplitude, wire_error)
        error_time = main.time_s * (replicas - 1) / replicas
    sigma = 4.0 * math.pi * np.abs(amplitude.reshape(shape)) ** 2
    return RcsResult(
        sigma,
        error_db,
        freq,
        az,
        el,
        np.asarray(oaz),
        np.asarray(oel),
        tracing.rays_per_wavelength,
        tracing.max_bounces,
        int(main.tubes.sum()),
        int(main.ray_casts),
        main.exits_by_bounce,
        main.time_s - error_time + time.perf_counter() - wire_start,
        error_time,
        engine.target.name,
        [m.name for m in engine.target.materials],
        engine.variant,
        replicas,
        model_error_db(freq, engine.target.bounding_radius_m),
        main.live_sigma_m2.reshape(replicas, n_f, n_a, 2).mean(axis=0),
        None if edge_residual is None else edge_residual.reshape(shape),
    )
