"""``csuas render eo --atmosphere-method``: Mitsuba's participating medium instead of the analytic path
(render/imaging/medium_path.py) where the analytic path is an approximation."""

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
from csuas.render.imaging.medium_path import (
    BLUR_SHARE_LIMIT,
    FogMedium,
    MethodChoice,
    blur_share,
    choose_method,
    medium_samples,
    render_eo_medium,
    single_scatter_source,
)
from csuas.render.imaging.quality import Quality
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
from csuas.render.imaging.targets import plate

FOG = Daylight(visibility_km=0.5, convention="physical")
#: The same fog under a uniform sky and ground (no sun): Koschmieder's airlight source is exact.
UNIFORM_FOG = Daylight(illuminance_lx=1e4, diffuse_fraction=1.0, ground_reflectance=1.0, visibility_km=0.5)
#: The default EO sensor's IFOV [rad]: 10 deg over 1920 px.
IFOV = math.radians(10.0) / 1920


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


def test_auto_takes_the_medium_only_where_the_analytic_path_is_an_approximation():
    sensor = EoSensor()
    # no weather declared (clear air's 10 km path), or the paper convention: the analytic path, whatever the view
    clear = Daylight(visibility_km=10.0)
    for light, weather in ((clear, False), (replace(FOG, convention="paper"), True)):
        assert choose_method("auto", light, View(300.0, 0.0, 30.0), sensor, 40.0, weather).method == "analytic"
    # uniform fog under a uniform sky, horizontal path, optical depth 2.3: Koschmieder's uniform path holds
    uniform = choose_method("auto", UNIFORM_FOG, View(300.0), sensor, None, True)
    assert uniform.method == "analytic" and uniform.blur_share < BLUR_SHARE_LIMIT
    # under the default sun (85 % of 70 klx at 45 deg, behind the sensor), sky (0.15 E / pi) and ground (0.2 E / pi)
    # the fog scatters J1 = (L_sky + L_ground) / 2 + E_sun p(cos 135 deg) = 4271 cd/m^2 into a horizontal line of
    # sight, not L_h = 3342: 28 % of it, times 1 - tau = 0.90 over 300 m of 500 m fog
    e = 70000.0
    hg_135 = (1.0 - 0.85**2) / (4.0 * math.pi * (1.0 + 0.85**2 + 2.0 * 0.85 * math.cos(math.radians(45.0))) ** 1.5)
    j1 = 0.5 * (0.15 + 0.2) * e / math.pi + 0.85 * e / math.sin(math.radians(45.0)) * hg_135
    assert single_scatter_source(FOG, View(300.0)) == pytest.approx(j1, rel=1e-4)
    sunlit = choose_method("auto", FOG, View(300.0), sensor, None, True)
    assert sunlit.method == "medium" and "sky is not uniform" in sunlit.reasons[0]
    # a haze of 10 km over 150 m changes the airlight by 0.28 (1 - 0.94) = 1.6 % of the background: analytic
    assert choose_method("auto", replace(FOG, visibility_km=10.0), View(150.0), sensor, None, True).method == "analytic"
    # a fog top 40 m above the drone: crossed by a path to a sensor 102.6 m above it, not by one 13 m below it
    layer = replace(UNIFORM_FOG, fog_layer=(0.39, 10.0))
    crossing = choose_method("auto", layer, View(300.0, 0.0, 20.0), sensor, 40.0, True)
    assert crossing.method == "medium" and crossing.medium.top_above_target_m == 40.0
    assert "crosses the fog's top" in crossing.reasons[0]
    below = choose_method("auto", layer, View(300.0, 0.0, -2.5), sensor, 40.0, True)
    assert below.method == "analytic"
    # the sensor above the drone: the ground (0.2 E / pi) lies behind it, not the sky (0.15 E / pi)
    dim_ground = replace(UNIFORM_FOG, diffuse_fraction=0.5, ground_reflectance=0.45)
    looking_down = choose_method("auto", dim_ground, View(300.0, 0.0, 5.0), sensor, None, True)
    assert looking_down.method == "medium" and "ground" in looking_down.reasons[0]
    # forward scatter: the share passes 1 % at an optical depth of 0.01 / (alpha I(0.85)), I(0.85) = 6.513
    tau_limit = BLUR_SHARE_LIMIT / blur_share(1.0, IFOV)
    assert tau_limit == pytest.approx(16.89, abs=0.01)
    beta = 3.912023005 / 0.1  # 100 m fog at 550 nm [1/km] (Kruse/Kim, q = 0 below 0.5 km)
    thick = replace(UNIFORM_FOG, visibility_km=0.1)
    for range_m, method in (
        (0.99 * tau_limit / beta * 1000.0, "analytic"),
        (1.01 * tau_limit / beta * 1000.0, "medium"),
    ):
        assert choose_method("auto", thick, View(range_m), sensor, None, True).method == method
    # requested methods are kept; the medium needs a path under the physical convention
    assert choose_method("analytic", layer, View(300.0, 0.0, 20.0), sensor, 40.0, True).method == "analytic"
    assert choose_method("medium", FOG, View(300.0), sensor, None, True).method == "medium"
    for light in (replace(FOG, visibility_km=None), replace(FOG, convention="paper")):
        with pytest.raises(ParameterError, match="atmosphere_method"):
            choose_method("medium", light, View(300.0), sensor, None, True)
    with pytest.raises(ParameterError, match="atmosphere_method"):
        choose_method("volumetric", FOG, View(300.0), sensor, None, True)


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
    # the fog's top 54.6 m below the drone, the path crosses it
    code, out, _ = _render(capsys, str(scenario), "--range-m", "300", "--elevation-deg", "-20")
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
