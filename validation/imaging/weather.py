"""Weather in the renders against the closed forms of the path ``csuas range`` applies (docs/validation.md).

* Koschmieder: the rendered Weber contrast of a flat Lambertian plate against the horizon sky, in a scenario's
  fog at several ranges, against C(R) = C0 exp(-beta R) (Koschmieder 1924), with C0 the plate's closed form
  (sun on the plate, half the sky and half the ground seen by a vertical face: E = E_sun cos(i) + pi L_sky / 2 +
  pi L_ground / 2, L = rho E / pi) and beta the extinction ``csuas range`` lists for the scenario's EO sensor;
* Beer-Lambert with path radiance: the rendered thermal Delta T of a graybody plate in a scenario's rain against
  T(tau eps_t L(T_t) + (1 - tau) L(T_air)) - T(tau eps_b L(T_b) + (1 - tau) L(T_air)), tau = 10^(-a R / 10)
  with the attenuation a the thermal range lists (Table 27 plus the rain's);
* fog in the thermal path: the rendered LWIR Delta T of the same plate in fog against the same closed form, the
  attenuation Table 27's plus the fog's (LOWTRAN 7's advection fog, Shettle & Fenn 1979, in the LWIR band);
* a confuser in a dataset frame: a gull pasted on the horizon sky in uniform fog, its contrast with the frame's
  path at its own range over its contrast without, against exp(-beta R) (Koschmieder);
* layered fog: the EO render's path transmittance of a scenario with ``fog_top_m`` against an absorbing Mitsuba
  fog slab (:func:`csuas.render.imaging.fog_slab.fog_slab_transmittance`) times the clear air's exp(-beta L_clear),
  and the layer's airlight on a slant path against a scattering slab lit by the uniform sky
  (:func:`csuas.validation.imaging.medium.layered_medium_vs_analytic_airlight`);
* the EO render through Mitsuba's participating medium (``csuas render --atmosphere-method medium``) against its
  analytic path: equal within Monte Carlo error in uniform, isotropic fog under uniform light, the difference
  stated under forward scattering and on a slant path across a fog layer's top
  (:mod:`csuas.validation.imaging.medium_checks`).

Each figure is a :class:`csuas.base.checks.Check` with its Monte Carlo standard error and time.
"""

from __future__ import annotations

import math
import time

import numpy as np

from csuas.base.checks import Check
from csuas.core.radiometry import band_radiance, radiance_temperature
from csuas.core.ranges import evaluate
from csuas.core.scenario import parse_scenario
from csuas.render.imaging.eo import render_eo
from csuas.render.imaging.fog_slab import fog_slab_transmittance
from csuas.render.imaging.modes import scenario_daylight, scenario_thermal_scene
from csuas.render.imaging.path import eo_path, fog_layer_at
from csuas.render.imaging.quality import Quality
from csuas.render.imaging.records import Daylight, RenderSettings, ThermalSensor, View
from csuas.render.imaging.targets import plate
from csuas.render.imaging.tir import render_tir
from csuas.validation.imaging.medium import layered_medium_vs_analytic_airlight
from csuas.validation.imaging.medium_checks import medium_checks

#: Standard errors of the Monte Carlo estimate a check allows.
N_SIGMA = 4.0
#: The fog of the Koschmieder checks (visibility [m]) and the ranges rendered in it [m].
FOG_VISIBILITY_M, FOG_RANGES_M = 500.0, (100.0, 150.0, 250.0, 400.0)
#: The plate of the EO checks: reflectance, and the daylight's diffuse share, sun elevation and ground reflectance.
PLATE_REFLECTANCE = 0.05
#: The rain of the thermal checks [mm/h] and the ranges rendered in it [m].
RAIN_RATE_MM_H, RAIN_RANGES_M = 30.0, (100.0, 250.0, 400.0)
#: The thermal plate (emissivity, temperature [K]) against Table 27's background (0.77, 298.15 K).
THERMAL_PLATE = (0.68, 288.15)
#: What float32 radiances of the render allow on a Delta T [K] (1e-7 relative on ~10 W m^-2 sr^-1: ~1e-5 K).
FLOAT32_K = 1e-4
#: Layered fog: (sensor height, drone height) [m] 300 m apart on the ground under a 50 m top (200 m visibility).
LAYER_CASES, LAYER_TOP_M, LAYER_GROUND_M, LAYER_VISIBILITY_M = ((2.0, 102.0), (120.0, 10.0)), 50.0, 300.0, 200.0


def _scenario(environment: dict, sensors: dict, altitude_m: float = 0.0):
    """A physical-convention scenario of the given environment and sensors."""
    return parse_scenario(
        {
            "convention": "physical",
            "target": {"altitude_m": altitude_m},
            "environment": environment,
            "sensors": sensors,
        }
    )


def plate_contrast_closed_form(light: Daylight, reflectance: float) -> float:
    """Inherent Weber contrast of a vertical Lambertian plate facing the sensor against the horizon sky.

    The sun stands behind the sensor at ``light.sun_elevation_deg`` (incidence i = that elevation on the plate);
    a vertical face sees half the sky dome and half the ground (view factors 1/2):
    L_t = rho (E_sun cos(i) + pi L_sky / 2 + pi L_ground / 2) / pi, C0 = (L_t - L_sky) / L_sky.
    """
    e_v = light.illuminance_lx
    elevation = math.radians(light.sun_elevation_deg)
    sun_normal = (1.0 - light.diffuse_fraction) * e_v / math.sin(elevation)
    sky = light.diffuse_fraction * e_v / math.pi
    ground = light.ground_reflectance * e_v / math.pi
    target = reflectance * (sun_normal * math.cos(elevation) + math.pi * (sky + ground) / 2.0) / math.pi
    return (target - sky) / sky


def koschmieder_checks(quality, seed: int = 0) -> tuple:
    """Rendered contrast of a plate in fog at :data:`FOG_RANGES_M` vs C0 exp(-beta R) (checks and figure rows)."""
    sc = _scenario({"fog_visibility_m": FOG_VISIBILITY_M}, {"eo": {"modality": "eo"}})
    beta = float(evaluate(sc)["eo"].term("kruse_extinction").value)
    light = scenario_daylight(sc, sc.sensors["eo"])
    c0 = plate_contrast_closed_form(light, PLATE_REFLECTANCE)
    checks, rows = [], []
    for r in FOG_RANGES_M:
        res = render_eo(
            plate(reflectance=PLATE_REFLECTANCE),
            View(r),
            light=light,
            atmosphere=True,
            settings=RenderSettings(quality=quality, seed=seed),
        )
        expected = c0 * math.exp(-beta * r / 1000.0)
        se = res.stderr["contrast_weber"]
        rows.append((r, res.values["contrast_weber"], se, expected))
        checks.append(
            Check(
                f"imaging.weather.koschmieder.{r:g}m",
                expected,
                res.values["contrast_weber"],
                N_SIGMA * se,
                "-",
                error_estimate=se,
                time_s=res.time_s,
                source=f"Koschmieder C0 exp(-beta R): C0 = {c0:.4f} (Lambertian plate, closed form), beta = "
                f"{beta:.4g} /km (csuas range, fog V = {FOG_VISIBILITY_M:g} m, physical)",
                tolerance_source=f"{N_SIGMA:g} Monte Carlo standard errors (batches of the render)",
                method=f"Mitsuba EO render of a 1 m plate (reflectance {PLATE_REFLECTANCE:g}) against the horizon sky, "
                f"the scenario's path (csuas render), {res.quality.name} quality",
                details={
                    "transmittance": math.exp(-beta * r / 1000.0),
                    "c0_rendered": res.values["contrast_weber_inherent"],
                },
            )
        )
    return checks, rows


def thermal_path_checks(quality, seed: int = 0) -> list:
    """Rendered LWIR Delta T of a graybody plate in rain vs Beer-Lambert with the air's path radiance."""
    sc = _scenario({"rain_rate_mm_h": RAIN_RATE_MM_H}, {"tir": {"modality": "tir", "model": "mrtd"}})
    return _thermal_plate_checks(
        sc,
        RAIN_RANGES_M,
        "thermal_beer_lambert",
        f"Table 27 + Marshall-Palmer rain {RAIN_RATE_MM_H:g} mm/h",
        "the scenario's path",
        RenderSettings(quality=quality, seed=seed),
    )


#: The fog of the thermal checks (visibility [m]) and the ranges rendered in it [m].
THERMAL_FOG_M, THERMAL_FOG_RANGES_M = 400.0, (100.0, 200.0)


def thermal_fog_checks(quality, seed: int = 0) -> list:
    """Rendered LWIR Delta T of a graybody plate in fog vs Beer-Lambert with the air's path radiance."""
    sc = _scenario({"fog_visibility_m": THERMAL_FOG_M}, {"tir": {"modality": "tir", "model": "mrtd"}})
    fog_db_km = float(np.asarray(evaluate(sc)["tir"].term("fog_extinction_db_km").value))
    return _thermal_plate_checks(
        sc,
        THERMAL_FOG_RANGES_M,
        "thermal_fog",
        f"Table 27 + fog {fog_db_km:.4g} dB/km, LOWTRAN 7 advection fog of Shettle & Fenn 1979 at "
        f"V = {THERMAL_FOG_M:g} m",
        "the scenario's fog",
        RenderSettings(quality=quality, seed=seed),
    )


def _thermal_plate_checks(sc, ranges_m, kind: str, extinction_source: str, path: str, settings) -> list:
    """A graybody plate's rendered LWIR Delta T at each range through the scenario's thermal path against
    Beer-Lambert with the air's path radiance, tau = 10^(-a R/10) with the a ``csuas range`` applies."""
    sigma = float(np.asarray(evaluate(sc)["tir"].term("extinction_db_km").value))
    scene = scenario_thermal_scene(sc, sc.sensors["tir"])  # rendered without reflected surroundings
    eps_t, t_t = THERMAL_PLATE
    checks = []
    for r in ranges_m:
        res = render_tir(
            plate(emissivity=eps_t, temperature_k=t_t),
            View(r),
            sensor=ThermalSensor(band="lwir"),
            scene=scene,
            atmosphere=True,
            settings=settings,
        )
        tau = 10.0 ** (-sigma * r / 1e4)
        air = (1.0 - tau) * band_radiance(scene.air_temperature_k, "lwir")
        target = radiance_temperature(tau * eps_t * band_radiance(t_t, "lwir") + air, "lwir")
        background = radiance_temperature(tau * scene.emissivity_bg * band_radiance(scene.t_bg_k, "lwir") + air, "lwir")
        se = res.stderr["delta_t_k"]
        checks.append(
            Check(
                f"imaging.weather.{kind}.{r:g}m",
                float(target - background),
                res.values["delta_t_k"],
                N_SIGMA * se + FLOAT32_K,
                "K",
                error_estimate=se,
                time_s=res.time_s,
                source=f"Beer-Lambert with path radiance, tau = 10^(-a R/10), a = {sigma:.4g} dB/km (csuas range: "
                f"{extinction_source}), air at {scene.air_temperature_k:g} K",
                tolerance_source=f"{N_SIGMA:g} Monte Carlo standard errors (0 on a uniform plate) + {FLOAT32_K:g} K "
                "for the render's float32 radiances (measured 8e-7 K)",
                method=f"Mitsuba LWIR render of a 1 m graybody plate (eps {eps_t:g}, {t_t:g} K) against the Table 27 "
                f"background, {path}, {res.quality.name} quality",
                details={"transmittance": tau},
            )
        )
    return checks


#: A confuser in fog: the visibility [m], its ranges [m] and the float64 rounding a ratio of sums carries.
CONFUSER_FOG_M, CONFUSER_RANGES_M, FLOAT64_RATIO = 200.0, (80.0, 160.0), 1e-9


def confuser_fog_checks(quality, seed: int = 0) -> list:
    """A gull pasted in a frame with the path at its own range in uniform fog: contrast ratio vs exp(-beta R)."""
    from csuas.render.imaging.confusers import eo_confusers, eo_render_settings
    from csuas.render.imaging.eo import sun_and_sky
    from csuas.render.imaging.path import eo_path_at
    from csuas.render.imaging.records import EoSensor

    sc = _scenario({"fog_visibility_m": CONFUSER_FOG_M}, {"eo": {"modality": "eo"}})
    beta = float(evaluate(sc)["eo"].term("kruse_extinction").value)
    light = scenario_daylight(sc, sc.sensors["eo"])
    sensor = EoSensor(hfov_deg=4.0, n_h=320, n_v=240, wavelength_nm=sc.sensors["eo"].params["wavelength_nm"])
    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    horizon = float(sky["sky_radiance"])
    render = eo_render_settings(sensor, light, quality, seed, {"f_number": 2.0, "pixel_pitch_um": 2.9}, 288.15)
    checks = []
    for r in CONFUSER_RANGES_M:
        draw = {"class": "gull", "range_m": r, "azimuth_deg": 70.0, "elevation_deg": -10.0, "target_offset_px": (0, 0)}
        draw.update(wingbeat_phase=0.1, length_m=0.01, confuser_id=1)
        excess, t0 = [], time.perf_counter()
        for path in (None, lambda rr, up: eo_path_at(rr, up, light, sensor.wavelength_nm, horizon)):
            frame = np.full((sensor.n_v, sensor.n_h), horizon)
            eo_confusers(frame, [draw], math.radians(sensor.hfov_deg) / sensor.n_h, {**render, "object_path": path})
            excess.append(float(np.sum(frame - horizon)))
        expected = math.exp(-beta * r / 1000.0)
        checks.append(
            Check(
                f"imaging.weather.confuser_fog.{r:g}m",
                expected,
                excess[1] / excess[0],
                FLOAT64_RATIO * expected,
                "-",
                error_estimate=0.0,
                time_s=time.perf_counter() - t0,
                source=f"Koschmieder exp(-beta R), beta = {beta:.4g} /km (csuas range, fog V = {CONFUSER_FOG_M:g} m, "
                "physical)",
                tolerance_source=f"{FLOAT64_RATIO:g} relative (float64 sums; the same render with and without the "
                "path, so its Monte Carlo error cancels: estimate 0)",
                method="a gull confuser of csuas dataset pasted on the horizon sky with the frame's path at its own "
                f"range (path.eo_path_at), its summed contrast over that without, {quality} render",
                details={"contrast_sum_clear": excess[0], "contrast_sum_fog": excess[1]},
            )
        )
    return checks


def layered_fog_checks(seed: int = 0) -> list:
    """The EO render's path transmittance through a fog layer (scenario ``fog_top_m``) vs a Mitsuba fog slab."""
    checks = []
    for h_s, h_d in LAYER_CASES:
        sensors = {"eo": {"modality": "eo", "height_m": h_s}}
        sc = _scenario({"fog_visibility_m": LAYER_VISIBILITY_M, "fog_top_m": LAYER_TOP_M}, sensors, h_d - h_s)
        light = scenario_daylight(sc, sc.sensors["eo"])
        slant = math.hypot(LAYER_GROUND_M, h_d - h_s)
        view = View(slant, 0.0, math.degrees(math.asin((h_s - h_d) / slant)))  # the render's own geometry
        layer = fog_layer_at(light.fog_layer, view)
        path = eo_path(slant, light.visibility_km, 550.0, 1.0, 0.0, light.convention, layer)
        rendered = next(t["value"] for t in path.terms if t["name"] == "transmittance")
        fraction, clear_km = layer
        fog_beta, clear_beta = (
            float(evaluate(_scenario(env, sensors))["eo"].term("kruse_extinction").value)
            for env in ({"fog_visibility_m": LAYER_VISIBILITY_M}, {"visibility_km": clear_km})
        )
        slab = fog_slab_transmittance(h_s, h_d, LAYER_GROUND_M, LAYER_TOP_M, fog_beta, seed=seed)
        expected = slab["transmittance"] * math.exp(-clear_beta * (1.0 - fraction) * slant / 1000.0)
        checks.append(
            Check(
                f"imaging.weather.layered_fog.{h_s:g}m_to_{h_d:g}m",
                expected,
                rendered,
                N_SIGMA * slab["stderr"],
                "-",
                error_estimate=slab["stderr"],
                time_s=slab["time_s"],
                source=f"Mitsuba volpath through an absorbing slab (beta {fog_beta:.4g} /km to {LAYER_TOP_M:g} m) "
                f"times the clear air's exp(-beta L_clear), beta {clear_beta:.3g} /km",
                tolerance_source=f"{N_SIGMA:g} standard errors of the slab's batches",
                method=f"csuas render's EO path of a scenario with fog_top_m = {LAYER_TOP_M:g} m, sensor {h_s:g} m, "
                f"drone {h_d:g} m, {LAYER_GROUND_M:g} m apart (L_fog / R = {fraction:.4g})",
                details={"slab_transmittance": slab["transmittance"], "fog_path_fraction": fraction},
            )
        )
    return checks


#: Fog-layer airlight: (elevation toward the sensor [deg], drone height [m], fog top [m]) at 300 m in 500 m fog, the
#: path crossing the top upward (the sensor above) and downward (the sensor below); samples of the medium render.
AIRLIGHT_CASES, AIRLIGHT_QUALITY = ((20.0, 10.0, 50.0), (-15.0, 100.0, 60.0)), Quality("medium_check", 6, 8)


def layered_airlight_checks(seed: int = 0) -> list:
    """The render's airlight of a fog layer on a slant path vs a scattering Mitsuba slab lit by the uniform sky."""
    checks = []
    for elevation, height, top in AIRLIGHT_CASES:
        m = layered_medium_vs_analytic_airlight(
            plate(width_m=0.3, height_m=0.3, reflectance=PLATE_REFLECTANCE),
            View(300.0, 0.0, elevation),
            visibility_km=FOG_VISIBILITY_M / 1000.0,
            target_height_m=height,
            fog_top_m=top,
            settings=RenderSettings(quality=AIRLIGHT_QUALITY, seed=seed),
        )
        se = float(np.hypot(m["medium_stderr"], m["analytic_stderr"]))
        checks.append(
            Check(
                f"imaging.weather.layered_airlight.el{elevation:g}_{height:g}m_top{top:g}m",
                m["analytic_radiance"],
                m["medium_radiance"],
                N_SIGMA * se,
                "cd m^-2",
                error_estimate=se,
                time_s=m["time_s"],
                source=f"the render's layered path L0 tau + L_h (1 - tau), tau = exp(-beta L_fog), L_fog / R = "
                f"{m['fog_path_fraction']:.4g} (fog {FOG_VISIBILITY_M:g} m to {top:g} m, vacuum above)",
                tolerance_source=f"{N_SIGMA:g} combined standard errors (jackknife of the medium's batches)",
                method="Mitsuba volpath through a conservative scattering slab lit by the uniform sky (radiative "
                f"equilibrium), a 0.3 m plate at {height:g} m, 300 m away at {elevation:g} deg",
                details={"transmittance": m["transmittance"], "inherent_radiance": m["inherent_radiance"]},
            )
        )
    return checks


def weather_checks(quality="draft", seed: int = 0) -> tuple:
    """All weather checks (list of Check) and the Koschmieder rows (range, contrast, stderr, closed form)."""
    t0 = time.perf_counter()
    eo, rows = koschmieder_checks(quality, seed)
    checks = eo + thermal_path_checks(quality, seed) + thermal_fog_checks(quality, seed)
    checks += confuser_fog_checks(quality, seed) + layered_fog_checks(seed) + layered_airlight_checks(seed)
    checks += medium_checks("full" if quality == "reference" else "quick", seed)
    return checks, np.array(rows), time.perf_counter() - t0
