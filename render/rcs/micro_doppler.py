"""Micro-Doppler of a drone's spinning rotors: the slow-time field, its spectrum and the blade flashes.

The rotor blades of a preset (its propeller parts built as blades,
:func:`csuas.drone_models.build_drone` ``propellers="blades"``) turn about each part's ``spin_axis``: a
multirotor's or helicopter's vertical axis, a fixed-wing pusher's flight axis +x. Each rotor is held in
its own frame, whose z is the spin axis (rows of :func:`rotor_frame`; the identity, and no arithmetic at
all, for a +z rotor), and the radar's direction is turned into that frame. At each slow-time sample the
complex monostatic physical-optics amplitude of every rotor is the faceted-PO integral of
:func:`csuas.render.rcs.facet_po.facet_po_amplitude` over its blades turned by the rotor's angle. Turning
a rotor by ``psi`` about its axis through ``c`` equals turning the radar direction ``d`` by ``-psi``
(azimuth ``az - psi`` in the rotor's frame) with the phase ``exp(2 j k (d - d_psi) . c)``, so each sample is
one aspect of the rotor at rest. The radar's elevation in a rotor's frame is its elevation above the rotor
plane, ``beta`` of :func:`csuas.core.micro_doppler.rotor_plane_elevation_deg` (Eq. MD-6), which sets the
tip Doppler. The body (every other part) is static: its RCS is one SBR-PO
run (:func:`csuas.render.rcs.solver.compute_rcs`) and it adds a constant of that magnitude, phase 0
(the engine returns powers, not the body's phase against the blades), i.e. the zero-Doppler line,
with the run's bound against the exact answer (standard quality, VV). The blades' facet integrals
are exact (float64), so their field has no discretisation error; PO's own model error for blades a
few wavelengths long and a fraction of one wide is not bounded here.

Model limits (stated in every result): blades and body are perfect conductors (an upper bound; the
presets' plastic blades reflect less, the RF materials are issue 26 Section 2's open item); PO with
back-face culling only, so no shadowing of blades by the body or by each other and no multiple
reflections between them; blades are rigid and flat (no twist, no flapping); the rotation rate is
the same for every rotor, diagonal pairs turning the same way (the X-quadcopter convention; which
pair turns clockwise is assumed and does not change the magnitude spectrum's lines); a helicopter's
tail rotor stays still, part of the body; a pusher turns counter-clockwise about +x (assumed, the same
magnitudes either way).

The spectrum is the FFT of the windowed series, normalised by the window's coherent gain so that a
line of amplitude ``a`` reads ``4 pi |a|^2 / lambda^2`` [m^2], the RCS of that line. Lines lie at
multiples of the flash rate (:func:`csuas.core.micro_doppler.line_spacing_hz`); complex samples alias
unless ``PRF >= 2 f_tip`` (:func:`csuas.core.micro_doppler.max_tip_doppler_hz`, Eq. MD-5), which
:func:`micro_doppler` refuses unless asked to flag it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from csuas.base.cost import Estimate
from csuas.base.errors import ParameterError, raise_all
from csuas.core.micro_doppler import line_spacing_hz, max_tip_doppler_hz
from csuas.core.units import wavelength_m

from .facet_po import CHUNK_ELEMENTS, facet_po_amplitude

#: Rotor rate without one given [rpm]: the dataset renders' 6000 rpm (render/imaging/sequence.py).
#: Assumed, not a published figure: small quadcopters hover at roughly 5000-10000 rpm.
DEFAULT_ROTOR_RPM = 6000.0

#: Spectral windows: name -> (window function of the sample count).
WINDOWS = {"hann": lambda n: np.hanning(n + 1)[:-1], "rectangular": np.ones}

MODEL_LIMITS = (
    "perfectly conducting blades and body (upper bound; the presets' plastic blades reflect less); "
    "PO without shadowing or multiple reflections between blades and body; rigid flat blades; "
    "one rotation rate for every rotor, diagonal pairs co-rotating (assumed); tail rotors still; body phase 0; "
    "PO's model error for thin blades not bounded"
)


@dataclass
class Rotor:
    """One rotor in its own frame (z its spin axis): its blade mesh at rest, a point of its axis, its spin (+1
    counter-clockwise about the axis), blades and tip radius; ``frame`` the rows of :func:`rotor_frame` that
    turn body-frame vectors into it (None: the axis is the body's +z and the frames coincide)."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    centre_m: np.ndarray
    spin: int
    n_blades: int
    tip_radius_m: float
    frame: np.ndarray | None = None

    @property
    def spin_axis(self) -> np.ndarray:
        """The rotor's axis in the body frame (unit vector)."""
        return np.array([0.0, 0.0, 1.0]) if self.frame is None else self.frame[2].copy()


def rotor_frame(spin_axis) -> np.ndarray | None:
    """Rows (e1, e2, a) of a right-handed frame whose third axis is the unit spin axis ``a``: e1 = z x a
    normalised (x when ``a`` is -z), e2 = a x e1. None for ``a`` = +z (the body frame itself)."""
    axis = np.asarray(spin_axis, float)
    norm = float(np.linalg.norm(axis))
    if not (np.isfinite(norm) and norm > 0):
        raise ParameterError("spin_axis", spin_axis, "a finite non-zero 3-vector")
    axis = axis / norm
    if np.array_equal(axis, [0.0, 0.0, 1.0]):
        return None
    across = np.cross([0.0, 0.0, 1.0], axis)
    e1 = across / np.linalg.norm(across) if np.linalg.norm(across) > 1e-12 else np.array([1.0, 0.0, 0.0])
    return np.stack([e1, np.cross(axis, e1), axis])


def rotor_about(name: str, mesh, spin_axis, spin: int, n_blades: int) -> Rotor:
    """A rotor of a blade mesh given in the body frame (trimesh) turning about ``spin_axis`` through the mesh's
    centroid (the blades are equally spaced, so it lies on the axis), held in its own frame (:func:`rotor_frame`);
    its tip radius the farthest vertex from the axis."""
    frame = rotor_frame(spin_axis)
    vertices, centre = np.asarray(mesh.vertices, float), np.asarray(mesh.centroid, float)
    if frame is not None:
        vertices, centre = vertices @ frame.T, frame @ centre
    radius = float(np.max(np.linalg.norm(vertices[:, :2] - centre[:2], axis=1)))
    return Rotor(name, vertices, np.asarray(mesh.faces, np.int64), centre, spin, n_blades, radius, frame)


def rotor_aspect_deg(rotor: Rotor, azimuth_deg, elevation_deg) -> tuple:
    """The radar's azimuth and elevation in ``rotor``'s frame [deg]: the elevation is that above the rotor
    plane (Eq. MD-6). Unchanged, without arithmetic, for a +z rotor."""
    if rotor.frame is None:
        return azimuth_deg, elevation_deg
    from csuas.drone_models.geometry import direction_vector

    d = direction_vector(azimuth_deg, elevation_deg) @ rotor.frame.T
    azimuth = np.degrees(np.arctan2(d[..., 1], d[..., 0]))
    return azimuth, np.degrees(np.arcsin(np.clip(d[..., 2], -1.0, 1.0)))


@dataclass
class MicroDopplerResult:
    """Slow-time field and spectrum of a drone's rotors (module docstring)."""

    time_s: np.ndarray
    field_m: np.ndarray
    frequency_hz: np.ndarray
    spectrum_m2: np.ndarray
    lines: list
    flash_period_s: float
    line_spacing_hz: float
    max_tip_doppler_hz: float
    aliased: bool
    rcs_spinning_m2: float
    rcs_at_rest_m2: float
    body_rcs_m2: float
    body_bound_db: float
    window: str
    time_cost_s: float
    rotors: list = field(default_factory=list)


def drone_rotors(preset: str) -> tuple[list, object]:
    """The rotors of a preset (blades) and the drone without them (the static body).

    Parameters
    ----------
    preset : str
        A multirotor, helicopter or fixed-wing preset of :func:`csuas.drone_models.list_presets` (every part
        with a ``spin_axis``).

    Returns
    -------
    (list of Rotor, Drone)
    """
    from csuas.drone_models.presets import build_drone, list_presets, preset_parameters

    if preset not in list_presets():
        raise ParameterError("preset", preset, "a drone preset with rotor blades: " + ", ".join(list_presets()))
    _, params, _ = preset_parameters(preset)
    n_blades = int(getattr(params, "n_blades", 2))
    drone = build_drone(preset, propellers="blades")
    blades = [p for p in drone.parts if p.spin_axis is not None]
    if not blades:
        raise ParameterError("preset", preset, "a preset with rotor or propeller blades")
    rotors = []
    for i, part in enumerate(blades):
        diagonal = "front_left" in part.name or "rear_right" in part.name
        spin = (1 if diagonal else -1) if len(blades) == 4 else (1 if i % 2 == 0 else -1)
        rotors.append(rotor_about(part.name, part.mesh, part.spin_axis, spin, n_blades))
    body = drone.__class__(
        name=drone.name, mass_kg=drone.mass_kg, parts=[p for p in drone.parts if p.spin_axis is None]
    )
    return rotors, body


def rotor_field(rotor: Rotor, rotation_rate_hz: float, time_s, frequency_ghz: float, azimuth_deg, elevation_deg):
    """Complex PO amplitude [m^2] of one rotor at each time (module docstring), PEC blades.

    Parameters
    ----------
    rotor : Rotor
    rotation_rate_hz : float
        Rotation rate [rev/s]; the rotor turns ``rotor.spin * 360 * rate * t`` degrees.
    time_s : array_like (T,)
        Slow time [s].
    frequency_ghz : float
        Radar frequency [GHz].
    azimuth_deg, elevation_deg : float
        Direction from the drone toward the radar [deg] (docs/command-line.md convention), body frame.

    Returns
    -------
    ndarray complex (T,)
        ``sigma(t) = 4 pi |a(t)|^2 / lambda^2``.
    """
    from csuas.drone_models.geometry import direction_vector

    azimuth_deg, elevation_deg = rotor_aspect_deg(rotor, azimuth_deg, elevation_deg)  # in the rotor's frame
    psi_deg = rotor.spin * 360.0 * rotation_rate_hz * np.asarray(time_s, float)
    turned_az = (azimuth_deg - psi_deg + 180.0) % 360.0 - 180.0
    k = 2.0 * np.pi / wavelength_m(frequency_ghz)
    d = direction_vector(azimuth_deg, elevation_deg)
    turned = direction_vector(turned_az, np.full_like(turned_az, elevation_deg))
    shift = np.exp(2j * k * ((d - turned) @ rotor.centre_m))
    return shift * facet_po_amplitude(rotor.vertices, rotor.faces, frequency_ghz, turned_az, elevation_deg)


def spectrum_m2(field_m, window: str = "hann") -> tuple[np.ndarray, np.ndarray]:
    """Windowed FFT power of a slow-time field [m^2 of PO amplitude squared], zero Doppler centred.

    Parameters
    ----------
    field_m : ndarray complex (T,)
        Slow-time PO amplitude [m^2].
    window : {"hann", "rectangular"}
        Window (periodic Hann, or none); the FFT is divided by the window's sum (coherent gain), so a
        line of amplitude ``a`` reads ``|a|^2``.

    Returns
    -------
    (bin index order, power) : (ndarray int (T,), ndarray (T,))
        FFT bin indices ``-T/2 .. T/2 - 1`` and ``|a|^2`` per bin.
    """
    if window not in WINDOWS:
        raise ParameterError("window", window, ", ".join(WINDOWS))
    weights = WINDOWS[window](len(field_m))
    transform = np.fft.fftshift(np.fft.fft(weights * field_m)) / weights.sum()
    bins = np.fft.fftshift(np.fft.fftfreq(len(field_m), 1.0 / len(field_m))).astype(int)
    return bins, np.abs(transform) ** 2


def spectral_lines(frequency_hz, power, spacing_hz: float, max_doppler_hz: float) -> list:
    """The spectrum at each multiple ``m * spacing_hz`` within ``+-max_doppler_hz``: the nearest bin.

    Returns
    -------
    list of dict
        ``{"order": m, "frequency_hz": bin frequency, "power": bin value}``, ``m`` ascending.
    """
    step = frequency_hz[1] - frequency_hz[0]
    orders = np.arange(-int(max_doppler_hz // spacing_hz), int(max_doppler_hz // spacing_hz) + 1)
    lines = []
    for m in orders:
        index = int(np.argmin(np.abs(frequency_hz - m * spacing_hz)))
        if abs(frequency_hz[index] - m * spacing_hz) <= step / 2.0:
            lines.append({"order": int(m), "frequency_hz": float(frequency_hz[index]), "power": float(power[index])})
    return lines


def _check_sampling(frequency_ghz, rpm, prf_hz, dwell_s, aspect_deg, window) -> None:
    checks = [
        ("frequency_ghz", frequency_ghz, "0 < f <= 300 GHz", 0.0 < frequency_ghz <= 300.0),
        ("rpm", rpm, "0 < rpm <= 100,000", 0.0 < rpm <= 100_000.0),
        ("prf_hz", prf_hz, "0 < PRF <= 10 MHz", 0.0 < prf_hz <= 1e7),
        ("dwell_s", dwell_s, "0 < dwell <= 10 s", 0.0 < dwell_s <= 10.0),
        ("azimuth_deg", aspect_deg[0], "-360..360", -360.0 <= aspect_deg[0] <= 360.0),
        ("elevation_deg", aspect_deg[1], "-90..90", -90.0 <= aspect_deg[1] <= 90.0),
        ("window", window, ", ".join(WINDOWS), window in WINDOWS),
    ]
    raise_all([ParameterError(name, value, allowed) for name, value, allowed, ok in checks if not ok])
    samples = prf_hz * dwell_s
    if samples < 16 or samples > 2_000_000:
        raise ParameterError("dwell_s", dwell_s, f"16 to 2,000,000 samples at PRF {prf_hz:g} Hz")


#: Wall time of one facet of the blades at one slow-time sample [s] (faceted PO, float64): 6.5e-7 s measured
#: (``csuas bench --only cost_models``: 1000 to 16,000 samples x 480 facets of the Mini 4 Pro, 2.7-7.3 s, on
#: the shared 2 CPU cores at load 2.0), rounded up to cover a busier machine.
SECONDS_PER_SAMPLE_FACET = 1.0e-6
#: Wall time besides the blades' samples [s]: the process's start, the body's SBR engine and run and the plot
#: (the intercept of the same measurement, 2.4 s at load 2.0).
OVERHEAD_SECONDS = 2.0
#: Arrays held per slow-time sample besides one per rotor [complex128 each]: times, turned directions,
#: the sum, the windowed FFT, spectrum and frequency axis.
ARRAYS_PER_SAMPLE = 8
#: Peak memory per element of one chunk of the facet integral (samples x facets of a rotor, at most
#: ``facet_po.CHUNK_ELEMENTS``) [B]: 48 MB more at 16,000 than at 1000 samples of 120-facet rotors.
CHUNK_ELEMENT_BYTES = 55.0


@dataclass
class MicroDopplerPlan:
    """A checked micro-Doppler request: its rotors and body, before any field is computed."""

    preset: str
    frequency_ghz: float
    prf_hz: float
    samples: int
    rate_hz: float
    aspect_deg: tuple
    window: str
    rotors: list
    body: object
    tip_doppler_hz: float
    aliased: bool


def plan_micro_doppler(
    preset: str,
    frequency_ghz: float,
    prf_hz: float,
    dwell_s: float,
    rpm: float = DEFAULT_ROTOR_RPM,
    aspect_deg: tuple = (0.0, 10.0),
    window: str = "hann",
    allow_aliasing: bool = False,
) -> MicroDopplerPlan:
    """Check a request and build the preset's rotors (cheap); the parameters of :func:`micro_doppler`.

    Raises
    ------
    ParameterError
        Out-of-range input, or ``PRF < 2 f_tip`` without ``allow_aliasing``.
    """
    _check_sampling(frequency_ghz, rpm, prf_hz, dwell_s, aspect_deg, window)
    rotors, body = drone_rotors(preset)
    rate = rpm / 60.0
    tip = max(
        float(max_tip_doppler_hz(r.tip_radius_m, rate, frequency_ghz, rotor_aspect_deg(r, *aspect_deg)[1]))
        for r in rotors
    )
    aliased = bool(prf_hz < 2.0 * tip)
    if aliased and not allow_aliasing:
        raise ParameterError("prf_hz", prf_hz, f">= 2 x the blade-tip Doppler {tip:.1f} Hz = {2 * tip:.1f} Hz")
    samples = int(round(prf_hz * dwell_s))
    return MicroDopplerPlan(
        preset, frequency_ghz, prf_hz, samples, rate, tuple(aspect_deg), window, rotors, body, tip, aliased
    )


def estimate_cost(plan: MicroDopplerPlan) -> Estimate:
    """Wall time on 2 CPU cores and peak memory of :func:`simulate` (samples x blade facets, the body's SBR run)."""
    from .solver import REPLICAS, estimate_peak_bytes, estimate_seconds, estimate_tubes, resolve_quality

    facets = sum(len(r.faces) for r in plan.rotors)
    mesh = plan.body.mesh()
    radius = float(np.max(np.linalg.norm(mesh.vertices - mesh.bounding_box.centroid, axis=1)))
    rays_per_wavelength, bounces = resolve_quality("standard")
    tubes = estimate_tubes(radius, plan.frequency_ghz, rays_per_wavelength)
    seconds = OVERHEAD_SECONDS + plan.samples * facets * SECONDS_PER_SAMPLE_FACET
    seconds += estimate_seconds(tubes * REPLICAS, bounces)
    chunk = min(plan.samples * max(len(r.faces) for r in plan.rotors), CHUNK_ELEMENTS)
    held = plan.samples * 16.0 * (len(plan.rotors) + ARRAYS_PER_SAMPLE) + CHUNK_ELEMENT_BYTES * chunk
    what = f"micro-Doppler of {plan.samples:,} samples x {facets} blade facets and the body's SBR run"
    return Estimate(what, seconds, estimate_peak_bytes(tubes) + held)


def simulate(plan: MicroDopplerPlan) -> MicroDopplerResult:
    """The slow-time field and spectrum of a planned request (module docstring)."""
    from .solver import compute_rcs

    start = time.perf_counter()
    rotors, rate, frequency_ghz, prf_hz = plan.rotors, plan.rate_hz, plan.frequency_ghz, plan.prf_hz
    azimuth, elevation = plan.aspect_deg
    times = np.arange(plan.samples) / prf_hz
    fields = [rotor_field(r, rate, times, frequency_ghz, azimuth, elevation) for r in rotors]
    blades = np.sum(fields, axis=0)
    at_rest = sum(rotor_field(r, 0.0, times[:1], frequency_ghz, azimuth, elevation)[0] for r in rotors)
    body_rcs = compute_rcs(plan.body.mesh(), frequency_ghz, azimuth, elevation, quality="standard")
    body_m2 = float(body_rcs.rcs_m2("VV")[0, 0, 0])
    body_bound = body_rcs.bound_db("VV")
    wavelength = wavelength_m(frequency_ghz)
    total = blades + np.sqrt(body_m2 / (4.0 * np.pi)) * wavelength
    bins, power = spectrum_m2(total, plan.window)
    to_m2 = 4.0 * np.pi / wavelength**2
    frequency_hz = bins * prf_hz / len(times)
    spacing = line_spacing_hz(rotors[0].n_blades, rate)
    lines = spectral_lines(frequency_hz, power * to_m2, spacing, min(plan.tip_doppler_hz, prf_hz / 2.0))
    return MicroDopplerResult(
        times,
        total,
        frequency_hz,
        power * to_m2,
        lines,
        1.0 / spacing,
        spacing,
        plan.tip_doppler_hz,
        plan.aliased,
        float(np.mean(np.abs(blades) ** 2) * to_m2),
        float(np.abs(at_rest) ** 2 * to_m2),
        body_m2,
        float(body_bound[0, 0, 0]) if body_bound is not None else float("inf"),
        plan.window,
        time.perf_counter() - start,
        [
            {
                "name": r.name,
                "spin": r.spin,
                "n_blades": r.n_blades,
                "tip_radius_m": r.tip_radius_m,
                "spin_axis": r.spin_axis.tolist(),
                "elevation_above_rotor_plane_deg": float(rotor_aspect_deg(r, azimuth, elevation)[1]),
            }
            for r in rotors
        ],
    )


def micro_doppler(
    preset: str,
    frequency_ghz: float,
    prf_hz: float,
    dwell_s: float,
    rpm: float = DEFAULT_ROTOR_RPM,
    aspect_deg: tuple = (0.0, 10.0),
    window: str = "hann",
    allow_aliasing: bool = False,
) -> MicroDopplerResult:
    """Micro-Doppler of a preset's rotors over one dwell (module docstring): :func:`plan_micro_doppler`, then
    :func:`simulate`.

    Parameters
    ----------
    preset : str
        Drone preset with rotor blades.
    frequency_ghz : float
        Radar frequency [GHz].
    prf_hz, dwell_s : float
        Pulse repetition frequency [Hz] (one complex sample per pulse) and dwell [s].
    rpm : float
        Rotor rate [rev/min], every rotor (:data:`DEFAULT_ROTOR_RPM`, assumed).
    aspect_deg : (float, float)
        Azimuth and elevation from the drone toward the radar [deg].
    window : {"hann", "rectangular"}
        Spectral window (:func:`spectrum_m2`).
    allow_aliasing : bool
        Flag ``PRF < 2 f_tip`` in the result instead of refusing it.

    Raises
    ------
    ParameterError
        Out-of-range input, or ``PRF < 2 f_tip`` without ``allow_aliasing``.
    """
    return simulate(plan_micro_doppler(preset, frequency_ghz, prf_hz, dwell_s, rpm, aspect_deg, window, allow_aliasing))
