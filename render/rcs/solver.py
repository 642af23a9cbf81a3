"""User-level radar cross-section: quality presets, polarisations and an error estimate.

:func:`compute_rcs` wraps :class:`csuas.render.rcs.engine.SbrEngine` for a grid
of frequencies x aspects (monostatic) or x receivers (bistatic) in one launch
and returns an :class:`RcsResult` with every polarisation, the discretisation
error estimate and the cost.

Error estimate. The dominant discretisation error of SBR-PO is the
staircase truncation of the illuminated area by tubes of size ``d = lambda/N``
(error proportional to ``perimeter * d / area``, ``docs/validation.md``),
so it halves when ``N`` doubles. The run is repeated at ``N/2`` (a quarter
of the tubes, 25 % extra time) and ``error_db = |dB(sigma_N) - dB(sigma_N/2)|``
estimates the error of the ``N`` result (Richardson's estimate for a
first-order method). Below ``N = 2`` the second run uses the same density on
a grid shifted by half a tube instead.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.units import wavelength_m

from .engine import DEFAULT_GRID_SHIFT, POWER_CUTOFF, Jobs, SbrEngine
from .geometry import load_target

#: Quality presets: tube density N [rays per wavelength] and maximum bounces. Measured errors
#: against closed forms are in :data:`PRESET_MEASURED_ERROR_DB` (see convergence.py).
QUALITY_PRESETS = {
    "draft": {"rays_per_wavelength": 4.0, "max_bounces": 3},
    "standard": {"rays_per_wavelength": 10.0, "max_bounces": 5},
    "reference": {"rays_per_wavelength": 20.0, "max_bounces": 8},
}

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
        Tubes launched in the main run (the ``rays`` of docs/command-line.md).
    ray_casts : int
        Ray-scene intersection queries of the main run (tubes x bounces).
    exits_by_bounce : ndarray
        Tubes radiating after 0 (missed), 1, 2, ... bounces.
    time_s : float
        Wall time of the main run [s]; ``error_time_s`` the extra run's.
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
) -> RcsResult:
    """Radar cross-section of a mesh by SBR-PO for frequencies x aspects.

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
        Also run at half the density to estimate the error (+25 % time).
    radiate : {"exit", "all"}
        Radiate at each tube's last hit (Ling et al.) or at every hit.
    batch_size : int, optional
        Tubes in flight (memory bound); default by device.
    power_cutoff : float
        Relative tube power below which a tube stops (bounds the branching at
        thin shells); see :data:`csuas.render.rcs.engine.POWER_CUTOFF`.

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
    freq = np.atleast_1d(np.asarray(frequency_ghz, dtype=float)).ravel()
    bad = ~(np.isfinite(freq) & (freq > 0))
    if len(freq) == 0 or bad.any():
        raise ParameterError("frequency_ghz", float(freq[bad][0]) if bad.any() else [], "0 < f < inf GHz")
    az, el = np.broadcast_arrays(
        np.atleast_1d(np.asarray(azimuth_deg, float)), np.atleast_1d(np.asarray(elevation_deg, float))
    )
    az, el = az.ravel(), el.ravel()
    n_f, n_a = len(freq), len(az)
    if observe_azimuth_deg is None and observe_elevation_deg is None:
        oaz, oel = az[:, None], el[:, None]
    elif observe_azimuth_deg is None or observe_elevation_deg is None:
        raise ParameterError(
            "observe_elevation_deg" if observe_elevation_deg is None else "observe_azimuth_deg",
            None,
            "both observe angles, or neither (monostatic)",
        )
    else:
        oaz, oel = np.broadcast_arrays(
            np.atleast_1d(np.asarray(observe_azimuth_deg, float)),
            np.atleast_1d(np.asarray(observe_elevation_deg, float)),
        )
        oaz = np.broadcast_to(oaz if oaz.ndim == 2 else oaz[None, :], (n_a, oaz.shape[-1]))
        oel = np.broadcast_to(oel if oel.ndim == 2 else oel[None, :], (n_a, oel.shape[-1]))
    engine = get_engine(target, material, batch_size, shell_thickness_m)
    f_job = np.repeat(freq, n_a)

    def build(density, shift):
        return Jobs.build(
            np.tile(az, n_f), np.tile(el, n_f), f_job, density, np.tile(oaz, (n_f, 1)), np.tile(oel, (n_f, 1)), shift
        )

    main = engine.trace(build(n, DEFAULT_GRID_SHIFT), bounces, radiate, power_cutoff)
    shape = (n_f, n_a, oaz.shape[1], 2, 2)
    sigma = main.sigma_m2.reshape(shape)
    error_db, error_time = None, 0.0
    if error_estimate:
        coarse_n, shift = (n / 2.0, DEFAULT_GRID_SHIFT) if n >= 2.0 else (n, np.add(DEFAULT_GRID_SHIFT, 0.5))
        coarse = engine.trace(build(coarse_n, shift), bounces, radiate, power_cutoff)
        error_db = np.abs(to_dbsm(sigma) - to_dbsm(coarse.sigma_m2.reshape(shape)))
        error_time = coarse.time_s
    return RcsResult(
        sigma,
        error_db,
        freq,
        az,
        el,
        np.asarray(oaz),
        np.asarray(oel),
        n,
        bounces,
        int(main.tubes.sum()),
        int(main.ray_casts),
        main.exits_by_bounce,
        main.time_s,
        error_time,
        engine.target.name,
        [m.name for m in engine.target.materials],
        engine.variant,
    )
