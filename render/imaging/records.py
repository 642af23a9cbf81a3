"""What an EO or thermal render is given: resolved sensor, light, view and settings records.

The renderers (:func:`csuas.render.imaging.eo.render_eo`, :func:`csuas.render.imaging.tir.render_tir`)
take these records plus explicit per-effect switches (``atmosphere=``, ``reflected_surroundings=``),
so what a render simulates is visible in its call: an effect left off is neither built nor paid
for. ``from_params`` builds a record from a scenario sensor's resolved parameters
(docs/scenarios.md), the one place where scenario keys meet the renderer.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from csuas.core.mrtd import sensor_mrtd

#: Share of the horizontal illuminance that comes from the sky in clear daylight (csuas.render.imaging.eo).
DEFAULT_DIFFUSE_FRACTION = 0.15


@dataclass(frozen=True)
class View:
    """Where the sensor looks from.

    Attributes
    ----------
    range_m : float
        Slant range sensor-target [m].
    azimuth_deg, elevation_deg : float
        Direction from the target toward the sensor, in the drone's body frame
        (docs/command-line.md) [deg].
    target_offset_px : (float, float)
        Offset of the target's centre from the default pixel centre [px].
    """

    range_m: float
    azimuth_deg: float = 0.0
    elevation_deg: float = 0.0
    target_offset_px: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class EoSensor:
    """A visible-band camera (Table 22) and the Johnson task it serves.

    Attributes
    ----------
    hfov_deg, n_h, n_v : float, int, int
        Field of view [deg] and pixels; IFOV = HFOV / N_H (Eq. 15).
    wavelength_nm : float
        Wavelength of the Kruse extinction (Eqs. 19-20) [nm].
    lp_task, n_ttpf : float
        Line pairs (Table 20) and TTPF multiplier (Table 21) of the rendered Johnson range (Eq. 18).
    c_min : float
        Minimum contrast (Table 24) of the contrast-limited range (Eq. 21).
    """

    hfov_deg: float = 10.0
    n_h: int = 1920
    n_v: int = 1080
    wavelength_nm: float = 550.0
    lp_task: float = 1.0
    n_ttpf: float = 1.0
    c_min: float = 0.05

    @classmethod
    def from_params(cls, params: dict) -> EoSensor:
        """The record of a scenario's resolved EO sensor parameters."""
        return cls(**{name: params[name] for name in cls.__dataclass_fields__})


@dataclass(frozen=True)
class ThermalSensor:
    """A thermal camera (Table 25) and the MRTD task it serves.

    Attributes
    ----------
    hfov_deg, n_h, n_v : float, int, int
        Field of view [deg] and pixels; IFOV = HFOV / N_H (Eq. 15; pitch / focal, Eq. 22).
    band : {"lwir", "mwir"}
        8-12 um or 3-5 um.
    mrtd : callable or None
        MRTD curve (cy/rad -> K) with ``max_frequency``; None: the diffraction-limited
        default of :func:`csuas.render.imaging.tir.default_mrtd`.
    lp_task, n_ttpf : float
        Line pairs (Table 20) and TTPF multiplier (Table 21) of the MRTD range.
    """

    hfov_deg: float = 36.67
    n_h: int = 1280
    n_v: int = 720
    band: str = "lwir"
    mrtd: Callable | None = None
    lp_task: float = 1.0
    n_ttpf: float = 1.0

    @classmethod
    def from_params(cls, params: dict) -> ThermalSensor:
        """The record of a scenario's resolved TIR sensor parameters, with its MRTD curve."""

        names = [name for name in cls.__dataclass_fields__ if name != "mrtd"]
        return cls(**{name: params[name] for name in names}, mrtd=sensor_mrtd(params))


@dataclass(frozen=True)
class Daylight:
    """Sun, sky, ground and background of a visible-band render, and the air's visibility.

    Attributes
    ----------
    illuminance_lx : float
        Horizontal illuminance E_v (Table 11) [lx].
    diffuse_fraction, sun_elevation_deg, ground_reflectance : float
        Split of the illuminance between sun and sky [-], sun elevation [deg] and the ground's
        Lambertian reflectance [-] (docs/simulation.md).
    sun_azimuth_deg : float or None
        Sun azimuth in the body frame [deg]; None puts the sun behind the sensor.
    background : "sky" or float
        Horizon sky, or the reflectance of a Lambertian background.
    visibility_km : float or None
        Visibility of the Koschmieder transmittance and airlight [km]; used when the render's
        ``atmosphere`` switch is on.
    rain_extinction_per_km : float
        Extinction of the scene's rain [1/km], added to the visibility's with the atmosphere on (physical).
    convention : {"paper", "physical"}
        How the path's extinction enters its transmittance (:func:`csuas.render.imaging.path.eo_path`).
    fog_layer : FogLayer, (float, float) or None
        Physical only: a fog layer whose share of the render's own path its range and elevation decide
        (:class:`FogLayer`), or a fixed (L_fog / R, clear visibility [km]) of the slant path
        (:func:`csuas.core.ranges.eo_path_inputs`); None: the visibility fills the path.
    cloud_cover : float
        Share of the sky under seeded clouds (0..1) of a full frame's ``"clear_sky"`` background
        (:func:`csuas.render.imaging.frame.eo_frame`); the window render's uniform sky has none.
    """

    illuminance_lx: float = 70000.0
    diffuse_fraction: float = DEFAULT_DIFFUSE_FRACTION
    sun_azimuth_deg: float | None = None
    sun_elevation_deg: float = 45.0
    ground_reflectance: float = 0.2
    background: str | float = "sky"
    visibility_km: float | None = None
    rain_extinction_per_km: float = 0.0
    cloud_cover: float = 0.0
    convention: str = "physical"
    fog_layer: tuple | None = None


@dataclass(frozen=True)
class FogLayer:
    """A fog layer from the ground to ``top_m``, seen by a sensor ``sensor_height_m`` above the same ground.

    A render takes the layer's share of its own path from its range and elevation
    (:func:`csuas.render.imaging.path.fog_layer_at`); above the top the air has ``clear_visibility_km``
    (:func:`csuas.core.ranges.fog_layer_geometry`).
    """

    sensor_height_m: float
    top_m: float
    clear_visibility_km: float


@dataclass(frozen=True)
class ThermalScene:
    """Background, surroundings and air of a thermal render (Table 27).

    Attributes
    ----------
    t_bg_k, emissivity_bg : float
        Background graybody [K], [-].
    surroundings_k : float or None
        Temperature of the uniform surroundings reflected by target and background [K]; used
        when the render's ``reflected_surroundings`` switch is on.
    extinction_db_km : float or None
        Path attenuation [dB/km] without the fog; used when the render's ``atmosphere`` switch is on.
    air_temperature_k : float
        Air temperature of the path radiance [K].
    rain_db_km : float
        The part of ``extinction_db_km`` that is rain [dB/km] (listed as its own term).
    convention : {"paper", "physical"}
        How the attenuation enters the path (:func:`csuas.render.imaging.path.tir_path`).
    fog_db_km : float
        The fog's attenuation where it fills the path [dB/km] (physical), added to ``extinction_db_km`` on the
        render's path (:func:`csuas.render.imaging.path.thermal_fog_at`); 0: no fog.
    fog_layer : FogLayer or None
        The fog's layer, whose share of the render's path scales ``fog_db_km``; None: the fog fills the path.
    """

    t_bg_k: float = 298.15
    emissivity_bg: float = 0.77
    surroundings_k: float | None = None
    extinction_db_km: float | None = None
    air_temperature_k: float = 293.15
    rain_db_km: float = 0.0
    convention: str = "physical"
    fog_db_km: float = 0.0
    fog_layer: FogLayer | None = None


@dataclass(frozen=True)
class RenderSettings:
    """How hard to work, and how to report it.

    Attributes
    ----------
    quality : str or Quality
        ``draft``, ``standard``, ``reference`` or a :class:`~csuas.render.imaging.quality.Quality`.
    seed : int
        Random seed (results are deterministic for a given seed).
    max_depth : int
        Path length of the path tracer (3: sun, sky and one inter-reflection).
    full_frame : bool
        Render the whole sensor frame instead of the window (benchmark).
    progress : callable(fraction) or file-like or None
        Progress callback, or a stream (e.g. ``sys.stderr``) for text progress.
    variant : str or None
        Exact Mitsuba variant (else CUDA, then LLVM).
    """

    quality: object = "standard"
    seed: int = 0
    max_depth: int = 3
    full_frame: bool = False
    progress: object = None
    variant: str | None = None
