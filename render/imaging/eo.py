"""Visible-band (EO) rendering of a target at a slant range (docs/simulation.md, paper Sections 2.3.1, 4.3).

Scene: the target's parts as Lambertian surfaces of albedo
``material.reflectance_rgb`` (linear sRGB), lit by the sun (a directional
emitter) and a uniform sky over a uniform ground. The scenario's illuminance
E_v [lx] is the horizontal illuminance, split by ``diffuse_fraction`` f_d:

    sky luminance      L_sky = f_d E_v / pi                [cd m^-2]
    sun illuminance    E_sun = (1 - f_d) E_v / sin(h_sun)  [lx], normal to the sun's rays
    ground luminance   L_gnd = rho_gnd E_v / pi            [cd m^-2]

The default f_d = 0.15 is a typical clear-sky diffuse fraction of global
illuminance at mid sun elevations (Duffie & Beckman, Solar Engineering of
Thermal Processes, ch. 2; Perez et al., Solar Energy 44, 1990); the default
ground albedo 0.2 the usual land value. The background behind the target is
the horizon sky (``background="sky"``: L_b = L_sky, Koschmieder's horizon)
or a Lambertian surface of reflectance rho_b under E_v just behind the target
(L_b = rho_b E_v / pi), so that Eq. 4 holds for a target facing the sun.

Images are in luminance units (RGB with Y = 0.2126 R + 0.7152 G + 0.0722 B,
Rec. 709/sRGB primaries) [cd m^-2]; figures use Y.
"""

from __future__ import annotations

import math
import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.eo import contrast_limited_range_m
from csuas.drone_models.geometry import direction_vector
from csuas.render.imaging.common import prepare, progress_printer, window_notes
from csuas.render.imaging.measure import measure_window
from csuas.render.imaging.path import NO_PATH, eo_path, fog_layer_at
from csuas.render.imaging.quality import resolve_quality
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
from csuas.render.imaging.result import ImagingResult
from csuas.render.imaging.scene import build_eo_scene, path_integrator
from csuas.render.imaging.trace import Sampling, trace_window

#: Luminance weights of linear Rec. 709 / sRGB primaries (ITU-R BT.709).
LUMINANCE_WEIGHTS = (0.2126, 0.7152, 0.0722)


def sun_and_sky(
    illuminance_lx: float, diffuse_fraction: float, sun_elevation_deg: float, ground_reflectance: float
) -> dict:
    """Split a horizontal illuminance into sun, sky and ground (module docstring).

    Returns
    -------
    dict
        ``sun_irradiance_lx`` (normal to the rays), ``sky_radiance``,
        ``ground_radiance`` [cd m^-2].
    """
    checks = (
        ("illuminance_lx", illuminance_lx, 0.0, 2e5),
        ("diffuse_fraction", diffuse_fraction, 0.0, 1.0),
        ("ground_reflectance", ground_reflectance, 0.0, 1.0),
    )
    for name, value, lo, hi in checks:
        if not (math.isfinite(value) and lo <= value <= hi):
            raise ParameterError(name, value, f"{lo:g} <= x <= {hi:g}")
    if not (0.0 < sun_elevation_deg <= 90.0):
        raise ParameterError("sun_elevation_deg", sun_elevation_deg, "0 < x <= 90 (sun above the horizon)")
    return {
        "sun_irradiance_lx": (1.0 - diffuse_fraction) * illuminance_lx / math.sin(math.radians(sun_elevation_deg)),
        "sky_radiance": diffuse_fraction * illuminance_lx / math.pi,
        "ground_radiance": ground_reflectance * illuminance_lx / math.pi,
    }


def _range_figures(m, range_m, sensor: EoSensor, path, convention: str) -> None:
    """Add the rendered Johnson range (Eq. 18) and the contrast-limited range (Eq. 21, the path's convention)."""
    cycles = 2.0 * sensor.lp_task * sensor.n_ttpf
    if cycles > 0:
        m.values["johnson_range_rendered_m"] = range_m * m.values["pixels_across_dcrit"] / cycles
        m.stderr["johnson_range_rendered_m"] = range_m * m.stderr["pixels_across_dcrit"] / cycles
    else:
        m.values["johnson_range_rendered_m"] = float("inf")
        m.notes.append("n_ttpf * lp_task = 0: the Johnson range is unbounded")
    beta = next((t["value"] for t in path.terms if t["name"] == "extinction_per_km"), 0.0)
    c0 = min(abs(m.values["contrast_inherent"]), 1.0)
    m.values["contrast_limited_range_m"] = float(contrast_limited_range_m(c0, sensor.c_min, beta, convention))


def render_eo(
    target,
    view: View,
    sensor: EoSensor = EoSensor(),
    light: Daylight = Daylight(),
    *,
    atmosphere: bool = False,
    settings: RenderSettings = RenderSettings(),
) -> ImagingResult:
    """Render the target in the visible band and measure its figures.

    Parameters
    ----------
    target : str, Drone or list of parts
        Drone preset name, a :class:`~csuas.drone_models.Drone`, or parts
        with ``name``, ``mesh`` (closed, outward), ``material``.
    view : View
        Slant range, aspect and pixel offset (:class:`~csuas.render.imaging.records.View`).
    sensor : EoSensor
        Camera and task (Table 22): IFOV = HFOV / N_H (Eq. 15); ``johnson_range_rendered_m``
        is the range where the rendered d_crit spans 2 lp n_TTPF pixels (Eq. 18), from pixels
        across d_crit scaling as 1/R; ``contrast_limited_range_m`` solves C0 tau(R) = c_min
        (Eq. 21, :func:`csuas.core.eo.contrast_limited_range_m`, physical convention) with C0
        the rendered inherent contrast (Eq. 3).
    light : Daylight
        Sun, sky, ground, background (Table 11, module docstring) and visibility.
    atmosphere : bool
        Koschmieder transmittance and airlight over the range at ``light.visibility_km``
        (Eqs. 19-21), with ``light``'s rain, fog layer and convention
        (:func:`csuas.render.imaging.path.eo_path`); off: no path, and the contrast-limited range is
        unbounded (JSON null).
    settings : RenderSettings
        Quality, seed, path length, full frame, progress and variant.
    """
    if atmosphere and light.visibility_km is None:
        raise ParameterError("visibility_km", None, "a visibility > 0 km when atmosphere=True")
    visibility_km = light.visibility_km if atmosphere else None
    progress = settings.progress
    t0 = time.perf_counter()
    q = resolve_quality(settings.quality)
    r, normalised, framing = prepare(target, view, sensor, full=settings.full_frame)
    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    l_bg = _background_luminance(light, sky)
    scene = _daylight_scene(normalised, view, light, sky, settings.variant)
    if progress is not None and not callable(progress):
        progress = progress_printer(f"render eo {r:g} m", progress)
    sampling = Sampling(q.n_side, q.n_batches, settings.seed, channels=3)
    tally = trace_window(scene, path_integrator(settings.max_depth), framing, sampling, progress=progress)
    path = eo_path(
        r,
        visibility_km,
        sensor.wavelength_nm,
        sky["sky_radiance"],
        light.rain_extinction_per_km,
        light.convention,
        fog_layer_at(light.fog_layer, view),  # the layer's share of the render's own path
    )
    m = measure_window(tally, np.full(3, l_bg), path, LUMINANCE_WEIGHTS)
    inherent = measure_window(tally, np.full(3, l_bg), NO_PATH, LUMINANCE_WEIGHTS)
    for name in ("contrast", "contrast_weber"):
        m.values[f"{name}_inherent"], m.stderr[f"{name}_inherent"] = inherent.values[name], inherent.stderr[name]
    _range_figures(m, r, sensor, path, light.convention)
    notes = list(m.notes)
    if visibility_km is None:
        notes.append("no atmosphere: the contrast-limited range is unbounded (null)")
    notes += window_notes(framing.window, tally)
    m.values.update(
        sun_irradiance_lx=sky["sun_irradiance_lx"],
        sky_radiance=sky["sky_radiance"],
        ground_radiance=sky["ground_radiance"],
    )
    return ImagingResult(
        "eo",
        "visible",
        r,
        float(view.azimuth_deg),
        float(view.elevation_deg),
        framing.sensor.ifov_rad,
        framing.window,
        m.values,
        m.stderr,
        m.image,
        m.coverage,
        "cd m^-2",
        ("R", "G", "B"),
        list(path.terms),
        q,
        tally.samples,
        tally.n_side**2 * tally.n_batches,
        time.perf_counter() - t0,
        notes,
    )


def _background_luminance(light: Daylight, sky: dict) -> float:
    """L_b [cd m^-2]: the horizon sky, or a Lambertian background of reflectance rho_b, rho_b E_v / pi."""
    background = light.background
    if isinstance(background, str):
        if background != "sky":
            raise ParameterError("background", background, "'sky' or a reflectance 0..1")
        return sky["sky_radiance"]
    if not (0.0 <= float(background) <= 1.0):
        raise ParameterError("background", background, "'sky' or a reflectance 0..1")
    return float(background) * light.illuminance_lx / math.pi


def _daylight_scene(normalised, view: View, light: Daylight, sky: dict, variant: str | None):
    """The Mitsuba scene of the target under the sun (behind the sensor unless placed), sky and ground."""
    from csuas.render.backend import use_variant

    sun_az = view.azimuth_deg if light.sun_azimuth_deg is None else light.sun_azimuth_deg
    use_variant("ad_rgb", variant)
    to_sun = normalised.to_render(direction_vector(sun_az, light.sun_elevation_deg))
    return build_eo_scene(
        normalised,
        sun_direction_render=to_sun,
        sun_irradiance=sky["sun_irradiance_lx"],
        sky_radiance=sky["sky_radiance"],
        ground_radiance=sky["ground_radiance"],
        up_render=normalised.to_render([0.0, 0.0, 1.0]),
    )
