"""EO and thermal renders apply the path extinctions of ``csuas range`` (physical), for every environment preset.

No Mitsuba: the render's path (:mod:`csuas.render.imaging.path`) is analytic; the render modes build it
from :func:`scenario_daylight` and :func:`scenario_thermal_scene`. Rain extinction is checked against
the Marshall-Palmer integral done numerically.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from csuas.core.atmosphere import rain_extinction_per_km
from csuas.core.ranges import evaluate
from csuas.core.scenario import parse_scenario
from csuas.defaults import load_presets
from csuas.render.imaging.modes import _atmosphere_on, scenario_daylight, scenario_thermal_scene
from csuas.render.imaging.path import eo_path, tir_path

RANGE_M = 300.0


def _terms(items):
    return {t["name"]: t["value"] for t in items}


@pytest.mark.parametrize("preset", sorted(load_presets()["environment"]))
def test_render_and_range_apply_the_same_extinction(preset):
    sensors = {"eo": {"modality": "eo"}, "tir": {"modality": "tir", "model": "mrtd"}}
    sc = parse_scenario({"convention": "physical", "environment": {"preset": preset}, "sensors": sensors})
    ranges = evaluate(sc)
    eo_terms = {t.name: float(np.asarray(t.value)) for t in ranges["eo"].terms}
    tir_terms = {t.name: float(np.asarray(t.value)) for t in ranges["tir"].terms}
    light = scenario_daylight(sc)
    rendered_eo = _terms(eo_path(RANGE_M, light.visibility_km, 550.0, 1.0, light.rain_extinction_per_km).terms)
    expected_beta = eo_terms["kruse_extinction"] + eo_terms.get("rain_extinction_per_km", 0.0)
    assert rendered_eo["extinction_per_km"] == pytest.approx(expected_beta, rel=1e-12)
    assert rendered_eo.get("rain_extinction_per_km", 0.0) == eo_terms.get("rain_extinction_per_km", 0.0)
    scene = scenario_thermal_scene(sc, sc.sensors["tir"])
    rendered_tir = _terms(
        tir_path(RANGE_M, scene.extinction_db_km, scene.air_temperature_k, "lwir", scene.rain_db_km).terms
    )
    assert rendered_tir["extinction_db_km"] == pytest.approx(tir_terms["extinction_db_km"], rel=1e-12)
    assert rendered_tir.get("rain_extinction_db_km", 0.0) == pytest.approx(tir_terms.get("rain_extinction_db_km", 0.0))
    # the render's automatic atmosphere is on wherever range applies a path: EO always, thermal MRTD always
    assert _atmosphere_on(sc, "auto", sc.sensors["eo"]) and _atmosphere_on(sc, "auto", sc.sensors["tir"])
    johnson = parse_scenario({"environment": {"preset": preset}, "sensors": {"t": {"modality": "tir"}}})
    assert _atmosphere_on(johnson, "auto", johnson.sensors["t"]) == bool({"rain", "fog", "haze"} & johnson.effects)


def test_no_rain_adds_no_term_and_leaves_the_paper_unchanged():
    sensors = {"eo": {"modality": "eo"}, "tir": {"modality": "tir", "model": "mrtd"}}
    for convention in ("paper", "physical"):
        sc = parse_scenario({"convention": convention, "sensors": sensors})
        for result in evaluate(sc).values():
            assert not {"rain_extinction_per_km", "rain_extinction_db_km"} & {t.name for t in result.terms}
    heavy = parse_scenario({"convention": "paper", "environment": {"preset": "rain_heavy"}, "sensors": sensors})
    clear = parse_scenario({"convention": "paper", "sensors": sensors})
    for name in sensors:
        assert float(evaluate(heavy)[name].range_m) == float(evaluate(clear)[name].range_m)


@pytest.mark.parametrize("rate", [1.0, 6.0, 30.0])
def test_rain_extinction_is_the_marshall_palmer_integral(rate):
    slope = 4.1 * rate**-0.21  # 1/mm

    def integrand(d_mm):
        return 2.0 * math.pi * d_mm**2 / 4.0 * 8000.0 * math.exp(-slope * d_mm)  # mm^2 m^-3 mm^-1

    per_m = quad(integrand, 0.0, 50.0)[0] * 1e-6
    assert float(rain_extinction_per_km(rate)) == pytest.approx(per_m * 1000.0, rel=1e-9)
    assert float(rain_extinction_per_km(rate)) == pytest.approx(0.365 * rate**0.63, rel=2e-3)


def test_rain_shortens_the_physical_eo_contrast_range_by_beer_lambert():
    sensors = {"eo": {"modality": "eo"}}
    dry = evaluate(parse_scenario({"convention": "physical", "sensors": sensors}))["eo"]
    wet = evaluate(
        parse_scenario({"convention": "physical", "environment": {"rain_rate_mm_h": 30.0}, "sensors": sensors})
    )["eo"]
    beta = float(wet.term("kruse_extinction").value) + float(rain_extinction_per_km(30.0))
    c = 0.5 / 0.05  # Table 24: c_eo / c_min
    assert float(wet.term("contrast_limited_range_m").value) == pytest.approx(1000.0 * math.log(c) / beta, rel=1e-12)
    assert float(wet.term("contrast_limited_range_m").value) < float(dry.term("contrast_limited_range_m").value)
