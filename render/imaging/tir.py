"""Thermal-infrared rendering: band radiance, apparent Delta T and the MRTD range.

Method: docs/simulation.md; the paper's Sections 2.3.2 and 4.4.

Each part of the target is a graybody of band emissivity eps (the material's
``emissivity_lwir`` or ``emissivity_mwir``) at its ``temperature_k``: it
emits eps L_band(T) (:func:`csuas.core.radiometry.band_radiance`) and reflects
1 - eps of what reaches it, the uniform surroundings at ``surroundings_k`` and
the other parts (path tracing). The background behind the target is a
graybody (eps_bg, T_bg) reflecting the same surroundings:

    L_b = eps_bg L_band(T_bg) + (1 - eps_bg) L_band(T_surr).

Apparent temperatures are radiance temperatures
(:func:`csuas.core.radiometry.radiance_temperature`); Delta T = T_r(target) -
T_r(background), silhouette-averaged (``delta_t_k``), at the sensor after the
path (:func:`csuas.render.imaging.path.tir_path`). Beside it the paper's
linear Delta T (Eq. 26, :func:`csuas.core.tir.delta_t_linear`). The range
where the rendered Delta T meets the MRTD at the target's spatial frequency
f(R) = lp n_TTPF R / d_crit (Eqs. 24, 27-29) is solved by
:func:`csuas.core.tir.tir_mrtd_range` (physical convention) from the
rendered inherent Delta T and the rendered d_crit.
"""

from __future__ import annotations

import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.mrtd import ParametricMrtd
from csuas.core.radiometry import BANDS_UM, band_radiance, radiance_temperature
from csuas.core.tir import delta_t_linear, tir_mrtd_range
from csuas.defaults import load_parameters
from csuas.render.imaging.common import prepare, progress_printer, window_notes
from csuas.render.imaging.measure import measure_window
from csuas.render.imaging.path import NO_PATH, thermal_fog_at, tir_path
from csuas.render.imaging.quality import resolve_quality
from csuas.render.imaging.records import RenderSettings, ThermalScene, ThermalSensor, View
from csuas.render.imaging.result import ImagingResult
from csuas.render.imaging.scene import build_tir_scene, path_integrator, target_parts
from csuas.render.imaging.trace import Sampling, trace_window


def default_mrtd(ifov_rad: float, band: str = "lwir") -> ParametricMrtd:
    """The parametric MRTD of :mod:`csuas.core.mrtd` for a camera of this IFOV [rad] and band.

    NETD, f-number and pitch are the ``[tir]`` defaults of ``defaults/parameters.toml``
    (50 mK, f/1, 10 um: Table 25 and the default MRTD curve).
    """
    tir = load_parameters()["tir"]
    return ParametricMrtd.from_datasheet(
        netd_mk=tir["netd_mk"]["value"],
        ifov_rad=ifov_rad,
        f_number=tir["f_number"]["value"],
        pitch_um=tir["pitch_um"]["value"],
        band=band,
    )


def area_weighted_graybody(target, band: str) -> tuple[float, float]:
    """Surface-area-weighted emissivity and temperature of the target's parts (for Eq. 26)."""
    parts = target_parts(target)
    area = np.array([p.mesh.area for p in parts])
    eps = np.array([getattr(p.material, f"emissivity_{band}") for p in parts])
    temp = np.array([p.material.temperature_k for p in parts])
    return float(np.sum(area * eps) / area.sum()), float(np.sum(area * temp) / area.sum())


def render_tir(
    target,
    view: View,
    sensor: ThermalSensor = ThermalSensor(),
    scene: ThermalScene = ThermalScene(),
    *,
    atmosphere: bool = False,
    reflected_surroundings: bool = False,
    linear_reference=None,
    settings: RenderSettings = RenderSettings(),
) -> ImagingResult:
    """Render the target in a thermal band and measure apparent Delta T and the MRTD range.

    Parameters
    ----------
    target : str, Drone or list of parts
        See :func:`csuas.render.imaging.eo.render_eo`.
    view : View
        Slant range, aspect and pixel offset (:class:`~csuas.render.imaging.records.View`).
    sensor : ThermalSensor
        Camera, band, MRTD curve and task (Table 25); IFOV = HFOV / N_H (Eq. 15, = pitch / focal,
        Eq. 22, for the defaults).
    scene : ThermalScene
        Background graybody, surroundings and air (Table 27).
    atmosphere : bool
        Attenuation at ``scene.extinction_db_km`` and path radiance at ``scene.air_temperature_k``
        over the range; off: no path.
    reflected_surroundings : bool
        Uniform surroundings at ``scene.surroundings_k`` reflected by target and background; off:
        nothing reflected (the thermal case of docs/validation.md without reflected surroundings).
    linear_reference : (emissivity, temperature_k) or None
        Target values for the paper's linear Delta T (Eq. 26); None: area-weighted parts.
    settings : RenderSettings
        As in :func:`csuas.render.imaging.eo.render_eo`.
    """
    from csuas.render.backend import use_variant

    _check_thermal(sensor, scene, atmosphere, reflected_surroundings)
    band, progress = sensor.band, settings.progress
    surroundings_k = scene.surroundings_k if reflected_surroundings else None
    fog = thermal_fog_at(scene, view)  # the fog on the render's own path (range and elevation)
    extinction_db_km = scene.extinction_db_km + fog[0] if atmosphere else None
    t0 = time.perf_counter()
    q = resolve_quality(settings.quality)
    r, normalised, framing = prepare(target, view, sensor, full=settings.full_frame)
    l_surr = 0.0 if surroundings_k is None else float(band_radiance(surroundings_k, band))
    l_bg = scene.emissivity_bg * float(band_radiance(scene.t_bg_k, band)) + (1.0 - scene.emissivity_bg) * l_surr
    use_variant("ad_mono", settings.variant)
    mitsuba_scene = build_tir_scene(normalised, band=band, surroundings_radiance=l_surr)
    if progress is not None and not callable(progress):
        progress = progress_printer(f"render tir {r:g} m", progress)
    sampling = Sampling(q.n_side, q.n_batches, settings.seed, channels=1)
    tally = trace_window(mitsuba_scene, path_integrator(settings.max_depth), framing, sampling, progress=progress)
    path = tir_path(r, extinction_db_km, scene.air_temperature_k, band, scene.rain_db_km, scene.convention, fog)

    def to_temperature(radiance):
        return radiance_temperature(radiance, band)

    m = measure_window(tally, [l_bg], path, (1.0,), to_temperature)
    inherent = measure_window(tally, [l_bg], NO_PATH, (1.0,), to_temperature)
    m.values["delta_t_inherent_k"] = inherent.values["delta_t_k"]
    m.stderr["delta_t_inherent_k"] = inherent.stderr["delta_t_k"]
    eps_t, t_t = linear_reference or area_weighted_graybody(target, band)
    m.values["delta_t_linear_k"] = float(delta_t_linear(eps_t, t_t, scene.emissivity_bg, scene.t_bg_k))
    _mrtd_figures(m, inherent, sensor, framing.sensor.ifov_rad, r, extinction_db_km, scene)
    notes = list(m.notes)
    if sensor.lp_task * sensor.n_ttpf <= 0:
        notes.append("n_ttpf * lp_task = 0: the MRTD range is unbounded")
    notes += window_notes(framing.window, tally)
    return ImagingResult(
        "tir",
        band,
        r,
        float(view.azimuth_deg),
        float(view.elevation_deg),
        framing.sensor.ifov_rad,
        framing.window,
        m.values,
        m.stderr,
        m.image,
        m.coverage,
        "W m^-2 sr^-1",
        ("L",),
        list(path.terms),
        q,
        tally.samples,
        tally.n_side**2 * tally.n_batches,
        time.perf_counter() - t0,
        notes,
    )


def _check_thermal(sensor: ThermalSensor, scene: ThermalScene, atmosphere: bool, reflected_surroundings: bool) -> None:
    """The scene's values that the render's switches use are given, the band is known and eps_bg in [0, 1]."""
    if atmosphere and scene.extinction_db_km is None:
        raise ParameterError("extinction_db_km", None, "a number [dB/km] when atmosphere=True")
    if reflected_surroundings and scene.surroundings_k is None:
        raise ParameterError("surroundings_k", None, "a temperature > 0 K when reflected_surroundings=True")
    if sensor.band not in BANDS_UM:
        raise ParameterError("band", sensor.band, ", ".join(BANDS_UM))
    if not 0.0 <= scene.emissivity_bg <= 1.0:
        raise ParameterError("emissivity_bg", scene.emissivity_bg, "0 <= x <= 1")


def _mrtd_figures(
    m, inherent, sensor: ThermalSensor, ifov_rad: float, range_m: float, extinction_db_km, scene: ThermalScene
) -> None:
    """Add the MRTD range (Eqs. 24, 27-29) of the rendered inherent Delta T and d_crit, with its error, to ``m``.

    The path is the scene's (its air temperature and convention) at ``extinction_db_km`` (None: no path).

    Also the target's spatial frequency f(R) = lp n_TTPF R / d_crit and the MRTD there, and the rendered d_crit.
    """
    values, stderr = m.values, m.stderr
    dt0, dt0_se = inherent.values["delta_t_k"], inherent.stderr["delta_t_k"]
    lp_task, n_ttpf, band = sensor.lp_task, sensor.n_ttpf, sensor.band
    curve = sensor.mrtd if sensor.mrtd is not None else default_mrtd(ifov_rad, band)
    d_crit = values["pixels_across_dcrit"] * ifov_rad * range_m
    d_crit_se = stderr["pixels_across_dcrit"] * ifov_rad * range_m
    sigma = 0.0 if extinction_db_km is None else float(extinction_db_km)
    t_bg_app = inherent.values["background_temperature_apparent_k"]

    def mrtd_range(dt, d):
        if lp_task * n_ttpf <= 0:
            return float("inf")
        if d <= 0 or dt == 0:
            return 0.0
        res = tir_mrtd_range(
            mrtd=curve,
            d_crit_m=d,
            lp_task=lp_task,
            n_ttpf=n_ttpf,
            delta_t0_k=dt,
            extinction_db_km=sigma,
            convention=scene.convention,
            t_bg_app_k=t_bg_app,
            air_temperature_k=scene.air_temperature_k,
            band=band,
        )
        return float(np.asarray(res.range_m))

    r_mrtd = mrtd_range(dt0, d_crit)
    values["mrtd_range_m"] = r_mrtd
    stderr["mrtd_range_m"] = float(
        np.hypot(
            mrtd_range(dt0 + np.copysign(dt0_se, dt0), d_crit) - r_mrtd, mrtd_range(dt0, d_crit + d_crit_se) - r_mrtd
        )
    )
    if d_crit > 0 and lp_task * n_ttpf > 0:
        freq = lp_task * n_ttpf * range_m / d_crit
        values["target_frequency_cy_rad"] = freq
        values["mrtd_at_range_k"] = float(curve(freq))
    values["d_crit_rendered_m"], stderr["d_crit_rendered_m"] = d_crit, d_crit_se
