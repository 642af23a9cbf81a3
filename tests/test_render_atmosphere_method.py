"""``csuas render eo --atmosphere-method``: Mitsuba's participating medium instead of the analytic path
(render/imaging/medium_choice.py, render/imaging/medium_path.py) where the analytic path is an approximation."""

from __future__ import annotations

import json
import math
import time
from dataclasses import replace

import numpy as np
import pytest
from scipy import integrate

from csuas import cli
from csuas.base.errors import ParameterError
from csuas.render.imaging.medium_choice import (
    BLUR_SHARE_LIMIT,
    NOISE_BACKGROUND,
    NOISE_TARGET,
    FogMedium,
    MethodChoice,
    analytic_error,
    blur_share,
    choose_method,
    fog_medium,
    footprint,
    medium_samples,
    medium_stderr,
    single_scatter_source,
    sun_ratio,
)
from csuas.render.imaging.medium_path import render_eo_medium
from csuas.render.imaging.quality import Quality
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
from csuas.render.imaging.targets import plate

FOG = Daylight(visibility_km=0.5, convention="physical")
#: The same fog under a uniform sky and ground (no sun): Koschmieder's airlight source is exact.
UNIFORM_FOG = Daylight(illuminance_lx=1e4, diffuse_fraction=1.0, ground_reflectance=1.0, visibility_km=0.5)
#: The default EO sensor's IFOV [rad]: 10 deg over 1920 px.
IFOV = math.radians(10.0) / 1920
#: The fog's single-scattered source of the default light on a horizontal line of sight [cd/m^2]:
#: (L_sky + L_ground) / 2 + E_sun p(cos 135 deg), Henyey-Greenstein g 0.85.
_HG_135 = (1.0 - 0.85**2) / (4.0 * math.pi * (1.0 + 0.85**2 + 2.0 * 0.85 * math.cos(math.radians(45.0))) ** 1.5)
J1_DEFAULT = 0.5 * (0.15 + 0.2) * 70000.0 / math.pi + 0.85 * 70000.0 / math.sin(math.radians(45.0)) * _HG_135
#: A dark plate facing the sensor (render/imaging/targets.py).
PLATE = plate(width_m=0.3, height_m=0.3, reflectance=0.05)


def _hg(cos_theta, g):
    """Henyey-Greenstein phase function [1/sr] (Henyey & Greenstein 1941)."""
    return (1.0 - g * g) / (4.0 * math.pi * (1.0 + g * g - 2.0 * g * cos_theta) ** 1.5)


def _single_scatter_share(tau_s, alpha, g, range_m=1000.0):
    """Share of a point's light scattered once onto the pixel within alpha of its image (no small-cone shortcut):
    at distance x in front of the point, the cone theta < atan(alpha R / x) of the exact phase function."""

    def cone(x):
        theta = math.atan(alpha * range_m / x)
        value, _ = integrate.quad(lambda t: _hg(math.cos(t), g) * 2.0 * math.pi * math.sin(t), 0.0, theta)
        return value

    value, _ = integrate.quad(cone, 0.0, range_m, points=[alpha * range_m * 10.0**k for k in range(0, 4)], limit=400)
    return tau_s / range_m * value


@pytest.mark.parametrize("g", [0.0, 0.5, 0.85])
def test_blur_share_is_the_single_scatter_integral_of_the_phase_function(g):
    # the closed form (small angles, pixel much smaller than the forward lobe) against the exact cone integral
    tau_s = 3.0
    exact = _single_scatter_share(tau_s, IFOV, g)
    assert blur_share(tau_s, IFOV, g) == pytest.approx(exact, rel=1e-3)


def test_auto_lists_where_the_analytic_path_is_an_approximation():
    sensor = EoSensor()
    # no weather declared (clear air's 10 km path), or the paper convention: the analytic path, whatever the view
    clear = Daylight(visibility_km=10.0)
    for light, weather in ((clear, False), (replace(FOG, convention="paper"), True)):
        assert choose_method("auto", light, View(300.0, 0.0, 30.0), sensor, 40.0, weather).method == "analytic"
    # uniform fog under a uniform sky, horizontal path, optical depth 2.3: Koschmieder's uniform path holds
    uniform = choose_method("auto", UNIFORM_FOG, View(300.0), sensor, None, True)
    assert uniform.method == "analytic" and uniform.blur_share < BLUR_SHARE_LIMIT and uniform.comparison is None
    # under the default sun (85 % of 70 klx at 45 deg, behind the sensor), sky (0.15 E / pi) and ground (0.2 E / pi)
    # the fog scatters J1 = (L_sky + L_ground) / 2 + E_sun p(cos 135 deg) = 4271 cd/m^2 into a horizontal line of
    # sight, not L_h = 3342: 28 % of it, times 1 - tau = 0.90 over 300 m of 500 m fog
    assert single_scatter_source(FOG, View(300.0)) == pytest.approx(J1_DEFAULT, rel=1e-4)
    # the forced medium lists the approximations it removes (auto's comparison: the tests below)
    sunlit = choose_method("medium", FOG, View(300.0), sensor, None, True)
    assert sunlit.method == "medium" and "sky is not uniform" in sunlit.reasons[1]
    # a haze of 10 km over 150 m changes the airlight by 0.28 (1 - 0.94) = 1.6 % of the background: analytic
    assert choose_method("auto", replace(FOG, visibility_km=10.0), View(150.0), sensor, None, True).method == "analytic"
    # a fog top 40 m above the drone: crossed by a path to a sensor 102.6 m above it, not by one 13 m below it
    layer = replace(UNIFORM_FOG, fog_layer=(0.39, 10.0))
    crossing = choose_method("medium", layer, View(300.0, 0.0, 20.0), sensor, 40.0, True)
    assert crossing.medium.top_above_target_m == 40.0 and "crosses the fog's top" in crossing.reasons[1]
    below = choose_method("auto", layer, View(300.0, 0.0, -2.5), sensor, 40.0, True)
    assert below.method == "analytic" and below.comparison is None
    # the sensor above the drone: the ground (0.2 E / pi) lies behind it, not the sky (0.15 E / pi)
    dim_ground = replace(UNIFORM_FOG, diffuse_fraction=0.5, ground_reflectance=0.45)
    assert "ground" in choose_method("medium", dim_ground, View(300.0, 0.0, 5.0), sensor, None, True).reasons[1]
    # forward scatter: the share passes 1 % at an optical depth of 0.01 / (alpha I(0.85)), I(0.85) = 6.513
    tau_limit = BLUR_SHARE_LIMIT / blur_share(1.0, IFOV)
    assert tau_limit == pytest.approx(16.89, abs=0.01)
    beta = 3.912023005 / 0.1  # 100 m fog at 550 nm [1/km] (Kruse/Kim, q = 0 below 0.5 km)
    thick = replace(UNIFORM_FOG, visibility_km=0.1)
    for range_m, listed in ((0.99 * tau_limit / beta * 1000.0, False), (1.01 * tau_limit / beta * 1000.0, True)):
        reasons = choose_method("medium", thick, View(range_m), sensor, None, True).reasons
        assert any("forward-scattered" in r for r in reasons) == listed
    # requested methods are kept; the medium needs a path under the physical convention
    assert choose_method("analytic", layer, View(300.0, 0.0, 20.0), sensor, 40.0, True).method == "analytic"
    for light in (replace(FOG, visibility_km=None), replace(FOG, convention="paper")):
        with pytest.raises(ParameterError, match="atmosphere_method"):
            choose_method("medium", light, View(300.0), sensor, None, True)
    with pytest.raises(ParameterError, match="atmosphere_method"):
        choose_method("volumetric", FOG, View(300.0), sensor, None, True)
    # auto compares the two paths on the rendered target: without one it refuses, naming the key
    with pytest.raises(ParameterError, match="target"):
        choose_method("auto", FOG, View(300.0), sensor, None, True)


def test_the_analytic_error_estimate_by_hand():
    # a 0.3 m plate of reflectance 0.05 facing the sensor at 300 m in 500 m fog, default sun behind the sensor:
    # L_t = 0.05 (E_sun cos 45 + pi (L_sky + L_ground) / 2) / pi, background the sky L_h = 0.15 E / pi;
    # analytic: L tau + L_h (1 - tau) for both; estimate: J1 in place of L_h, the background behind
    # 4 more ranges of fog (the medium's box), tau_b = exp(-5 beta R)
    e, beta = 70000.0, math.log(50.0) / 0.5
    lt = 0.05 * (0.85 * e + math.pi * (0.15 + 0.2) * e / math.pi / 2.0) / math.pi
    lh = 0.15 * e / math.pi
    tau, tau_b = math.exp(-beta * 0.3), math.exp(-5.0 * beta * 0.3)

    def contrast(t, b):
        return (t - b) / (t + b)

    analytic = contrast(lt * tau + lh * (1 - tau), lh)
    estimate = contrast(lt * tau + J1_DEFAULT * (1 - tau), lh * tau_b + J1_DEFAULT * (1 - tau_b))
    medium = fog_medium(FOG, EoSensor(), None)
    share = 0.01
    error, terms, predicted = analytic_error(PLATE, FOG, View(300.0), medium, share)
    by_name = {t["name"]: t["value"] for t in terms}
    assert by_name["airlight_source"] == pytest.approx(abs(estimate - analytic), rel=1e-4)
    assert by_name["fog_layer_sun"] == 0.0 and predicted == pytest.approx(estimate, rel=1e-4)
    assert by_name["forward_scatter"] == pytest.approx(share * abs(estimate), rel=1e-4)
    assert error == pytest.approx(sum(by_name.values()), rel=1e-12)


def test_the_noise_model_by_hand():
    # s = a + b x per ray, x = E_sun / (pi J1); the contrast's error (1 - C^2) / 2 sqrt(s_t^2 / N_t + s_b^2 / N_b)
    x = 0.85 * 70000.0 / math.sin(math.radians(45.0)) / (math.pi * J1_DEFAULT)
    assert sun_ratio(FOG, View(300.0)) == pytest.approx(x, rel=1e-4)
    samples = medium_samples(1225, "standard")
    assert samples == 1225 * 16 * 8
    n_t = samples * 62.0 / 1225
    s_t, s_b = NOISE_TARGET[0] + NOISE_TARGET[1] * x, NOISE_BACKGROUND[0] + NOISE_BACKGROUND[1] * x
    expected = 0.5 * (1 - 0.02**2) * math.sqrt(s_t**2 / n_t + s_b**2 / (samples - n_t))
    assert medium_stderr(62.0, 1225, x, 0.02, "standard") == pytest.approx(expected, rel=1e-12)
    # reference traces 16 times the rays (16^2 x 8 against 4^2 x 8 per pixel): a quarter of the error
    ratio = medium_stderr(62.0, 1225, x, 0.02, "reference") / medium_stderr(62.0, 1225, x, 0.02, "standard")
    assert ratio == pytest.approx(0.25, rel=1e-9)


def test_auto_takes_the_more_accurate_path_at_the_requested_quality():
    sensor, fog = EoSensor(), Daylight(visibility_km=0.4, convention="physical")  # fog_moderate's visibility
    # the default drone at 150 m: the analytic path's error ~0.025 against the medium's ~0.017 at standard
    standard = choose_method("auto", fog, View(150.0), sensor, None, True, "dji_mini_4_pro", "standard")
    cmp = standard.comparison
    assert standard.method == "analytic" and standard.medium is None
    assert 2.0 * cmp.medium_stderr > cmp.analytic_error > 0.0 and cmp.suggested_quality == "reference"
    assert "--quality reference" in standard.reasons[-1] and f"{cmp.analytic_error:.3g}" in standard.reasons[-1]
    record = standard.as_dict()["comparison"]
    assert record["analytic_error"]["value"] == cmp.analytic_error and record["analytic_error"]["source"]
    assert {t["name"] for t in record["analytic_error"]["terms"]} == {
        "airlight_source",
        "fog_layer_sun",
        "forward_scatter",
    }
    # at reference (16 x the samples) the medium's error is a quarter: it wins and is traced
    reference = choose_method("auto", fog, View(150.0), sensor, None, True, "dji_mini_4_pro", "reference")
    assert reference.method == "medium" and reference.comparison.medium_stderr == pytest.approx(
        cmp.medium_stderr / 4.0, rel=1e-9
    )
    assert "the medium is the more accurate" in reference.reasons[-1]
    # a thinner fog (1 km) leaves more of the source's error (0.058) than the medium's noise at standard
    light_fog = choose_method("auto", replace(fog, visibility_km=1.0), View(150.0), sensor, None, True, PLATE)
    assert light_fog.method == "medium"
    # a uniform sky: fog in radiative equilibrium, Koschmieder exact even across a layer's top: analytic
    layer = replace(UNIFORM_FOG, fog_layer=(0.39, 10.0))
    crossing = choose_method("auto", layer, View(300.0, 0.0, 20.0), sensor, 40.0, True, "dji_mini_4_pro")
    assert crossing.method == "analytic" and crossing.comparison.analytic_error < 1e-3


#: Medium renders not used to calibrate the noise model: (visibility [km], range [m], diffuse share, elevation).
COVERAGE_RENDERS = ((0.5, 120.0, 0.3, -5.0), (0.25, 200.0, 0.45, 0.0))


@pytest.mark.slow
@pytest.mark.parametrize("visibility_km, range_m, diffuse, elevation_deg", COVERAGE_RENDERS)
def test_the_noise_model_predicts_the_medium_renders_standard_error(visibility_km, range_m, diffuse, elevation_deg):
    """Coverage: the predicted standard error of the contrast within 0.5-2.5 of the jackknife's (8 batches: that
    estimate's own relative error is about 1 / sqrt(14) = 27 %; the model errs toward more noise, 0.74-1.84 on
    the seven held-out renders of its fit)."""
    light = Daylight(visibility_km=visibility_km, convention="physical", diffuse_fraction=diffuse)
    view, sensor = View(range_m, 0.0, elevation_deg), EoSensor()
    medium = fog_medium(light, sensor, None)
    choice = MethodChoice("medium", ("test",), medium, 0.0)
    res, record = render_eo_medium(
        "dji_mini_4_pro", view, sensor, light, choice, RenderSettings(quality="draft", seed=3)
    )
    pixels, window = footprint("dji_mini_4_pro", view, sensor)
    assert window == res.window.n_pixels and pixels == pytest.approx(res.values["pixels_on_target"], rel=0.05)
    predicted = medium_stderr(pixels, window, sun_ratio(light, view), res.values["contrast"], "draft")
    assert 0.5 < predicted / record["stderr"]["contrast"] < 2.5


@pytest.mark.slow
def test_the_medium_follows_koschmieder_in_uniform_isotropic_fog_under_uniform_light():
    """Radiative equilibrium (uniform sky and ground, conservative isotropic fog): Koschmieder's law is the exact
    solution, C(R) = C0 exp(-beta R), with C0 the vacuum render's inherent contrast."""
    light = UNIFORM_FOG
    beta = math.log(50.0) / 0.5  # [1/km] Kruse/Kim at 550 nm, V < 0.5 km: q = 0
    choice = MethodChoice("medium", ("test",), FogMedium(beta, g=0.0), 0.0)
    quality = Quality("t", 3, 8)
    res, record = render_eo_medium(
        plate(width_m=0.3, height_m=0.3, reflectance=0.05),
        View(200.0),
        EoSensor(),
        light,
        choice,
        RenderSettings(quality=quality),
    )
    tau = math.exp(-beta * 0.2)
    expected = res.values["contrast_weber_inherent"] * tau
    se = record["stderr"]["contrast_weber"]
    assert 0.0 < se < 0.03 and abs(res.values["contrast_weber"] - expected) < 4.0 * se
    terms = {t["name"]: t for t in res.terms}
    assert abs(terms["transmittance"]["value"] - tau) < 4.0 * terms["transmittance"]["stderr"]
    # the uniform sky seen through the fog keeps its luminance E / pi (equilibrium)
    assert res.values["background_radiance_apparent"] == pytest.approx(1e4 / math.pi, rel=0.01)
    # the estimate counts the samples the trace takes
    assert record["samples"] == medium_samples(res.window.n_pixels, quality)


def _render(capsys, *argv, mode="eo"):
    try:
        code = cli.main(["render", mode, *argv, "--quality", "draft", "--quiet", "--json"])
    except SystemExit as exc:  # argparse's own refusals (a choice that is not one)
        code = exc.code
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.mark.slow
def test_a_render_without_weather_is_the_analytic_render_bit_for_bit(capsys):
    rows = []
    for method in ("auto", "analytic"):
        code, out, _ = _render(capsys, "default", "--range-m", "150", "--atmosphere-method", method)
        assert code == 0
        (row,) = json.loads(out)["results"]
        assert row["atmosphere_method"]["method"] == "analytic"
        rows.append({k: v for k, v in row.items() if k not in ("time_s", "atmosphere_method")})
    assert rows[0] == rows[1]
    assert [t["name"] for t in rows[0]["terms"]][-2:] == ["transmittance", "airlight"]


@pytest.mark.slow
def test_render_json_reports_the_medium_with_its_error_time_and_the_analytic_figures(capsys, tmp_path):
    scenario = tmp_path / "layer.toml"
    scenario.write_text(
        'name = "layer"\nconvention = "physical"\n[target]\naltitude_m = 100.0\n[environment]\n'
        'fog_visibility_m = 200.0\nfog_top_m = 50.0\n[sensors.eo]\nmodality = "eo"\n'
    )
    # the sensor 2 m up, the drone R sin 20 deg = 102.6 m above it (the render's own geometry, elevation -20 deg):
    # the fog's top 54.6 m below the drone, the path crosses it; auto at draft keeps the analytic path (the
    # medium's predicted noise there exceeds the analytic error), so the medium is requested
    code, out, _ = _render(
        capsys, str(scenario), "--range-m", "300", "--elevation-deg", "-20", "--atmosphere-method", "medium"
    )
    assert code == 0
    (row,) = json.loads(out)["results"]
    method = row["atmosphere_method"]
    top_above_drone = 50.0 - 2.0 - 300.0 * math.sin(math.radians(20.0))
    assert method["method"] == "medium" and method["medium"]["fog_top_above_target_m"] == pytest.approx(top_above_drone)
    assert method["medium"]["extinction_per_km"] == pytest.approx(math.log(50.0) / 0.2, rel=1e-9)
    assert method["time_s"] > 0 and method["samples"] > 0 and method["stderr"]["contrast"] > 0
    terms = {t["name"]: t for t in row["terms"]}
    assert "Mitsuba volpath" in terms["transmittance"]["source"] and terms["transmittance"]["stderr"] > 0
    assert row["contrast"] == pytest.approx(method["analytic"]["contrast"] + method["difference"]["contrast"]["value"])
    assert np.isfinite(row["stderr"]["contrast"])


@pytest.mark.slow
def test_the_default_fog_render_at_standard_takes_the_analytic_path_and_says_why(capsys, tmp_path):
    """fog_moderate (400 m), the default drone at 150 m, standard quality: the medium's predicted standard error
    (~0.019; 0.019 and 0.022 measured on two seeds) is not below half the analytic path's estimated error (~0.025),
    so the render is the analytic one, its record listing the approximation, both figures and the quality that
    would remove it."""
    scenario = tmp_path / "fog.toml"
    scenario.write_text(
        'name = "fog"\nconvention = "physical"\n[environment]\npreset = "fog_moderate"\n[sensors.eo]\nmodality = "eo"\n'
    )
    assert cli.main(["render", "eo", str(scenario), "--range-m", "150", "--quiet", "--json"]) == 0
    (row,) = json.loads(capsys.readouterr().out)["results"]
    method = row["atmosphere_method"]
    cmp = method["comparison"]
    assert method["method"] == "analytic" and "medium" not in method and cmp["quality"] == "standard"
    assert "sky is not uniform" in method["reasons"][0] and "--quality reference" in method["reasons"][-1]
    error, stderr = cmp["analytic_error"]["value"], cmp["medium_stderr"]["value"]
    assert 0.015 < error < 0.04 and 0.01 < stderr and cmp["confidence"] * stderr > error
    assert (
        cmp["analytic_error"]["source"] and cmp["medium_stderr"]["source"] and cmp["suggested_quality"] == "reference"
    )
    # the render is the analytic one: its contrast's Monte Carlo error is the vacuum render's, not the medium's
    assert row["stderr"]["contrast"] < 0.005 and all("Mitsuba volpath" not in t["source"] for t in row["terms"])


@pytest.mark.slow
def test_a_light_fog_render_at_standard_takes_the_medium(capsys, tmp_path):
    """fog_light (800 m), the default drone at 150 m, standard: the analytic error (~0.051) passes 2 x the
    medium's predicted standard error (~0.019): auto traces the medium, whose measured standard error the
    noise model predicted (within the coverage test's 0.5-2.5; 0.90 measured on seed 0)."""
    scenario = tmp_path / "fog.toml"
    scenario.write_text(
        'name = "fog"\nconvention = "physical"\n[environment]\npreset = "fog_light"\n[sensors.eo]\nmodality = "eo"\n'
    )
    assert cli.main(["render", "eo", str(scenario), "--range-m", "150", "--quiet", "--json"]) == 0
    (row,) = json.loads(capsys.readouterr().out)["results"]
    method = row["atmosphere_method"]
    cmp = method["comparison"]
    assert method["method"] == "medium" and "the medium is the more accurate" in method["reasons"][-1]
    assert cmp["confidence"] * cmp["medium_stderr"]["value"] < cmp["analytic_error"]["value"]
    assert 0.5 < cmp["medium_stderr"]["value"] / method["stderr"]["contrast"] < 2.5
    assert any("Mitsuba volpath" in t["source"] for t in row["terms"])


@pytest.mark.parametrize(
    "argv,fragment",
    [
        (["default", "--range-m", "100", "--atmosphere-method", "volumetric"], "--atmosphere-method"),
        # the default scenario's paper convention has no medium
        (["default", "--range-m", "100", "--atmosphere-method", "medium"], "atmosphere_method"),
        (
            [
                "adverse",
                "--range-m",
                "100",
                "--convention",
                "physical",
                "--atmosphere-method",
                "medium",
                "--max-seconds",
                "0.5",
            ],
            "max_seconds",
        ),
        (["default", "--range-m", "100", "--max-seconds", "-1"], "max_seconds"),
        (["tir", "default", "--range-m", "100", "--atmosphere-method", "medium"], "atmosphere_method"),
    ],
)
def test_bad_atmosphere_method_and_limits_exit_2_naming_the_key(capsys, argv, fragment):
    cpu = time.process_time()
    mode, argv = (argv[0], argv[1:]) if argv[0] == "tir" else ("eo", argv)
    code, out, err = _render(capsys, *argv, mode=mode)
    assert code == 2 and out == "" and fragment in err and "Traceback" not in err
    assert time.process_time() - cpu < 5.0  # refused before any render
