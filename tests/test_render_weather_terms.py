"""EO and thermal renders apply the path terms of ``csuas range``, for every environment preset and both conventions.

No Mitsuba: the render's path (:mod:`csuas.render.imaging.path`) is analytic; the render modes build it
from :func:`scenario_daylight` and :func:`scenario_thermal_scene`. Rain extinction is checked against
the Marshall-Palmer integral done numerically.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from test_thermal_fog import lwir_advection_ratio

from csuas.core import eo, tir
from csuas.core import ranges as ranges_module
from csuas.core.atmosphere import rain_extinction_per_km
from csuas.core.ranges import evaluate
from csuas.core.scenario import load_scenario, parse_scenario
from csuas.defaults import load_presets
from csuas.render.imaging.modes import atmosphere_on, scenario_daylight, scenario_thermal_scene
from csuas.render.imaging.path import NO_PATH, eo_path, fog_layer_at, thermal_fog_at, tir_path
from csuas.render.imaging.records import View

RANGE_M = 300.0
#: Terms of the atmosphere in the range models' outputs (EO and thermal).
PATH_TERMS = {
    "kruse_extinction",
    "fog_path_fraction",
    "rain_extinction_per_km",
    "extinction_db_km",
    "rain_extinction_db_km",
    "fog_extinction_db_km",
}
SENSORS = {
    "eo": {"modality": "eo", "height_m": 2.0},
    "mrtd": {"modality": "tir", "model": "mrtd"},
    "netd": {"modality": "tir", "model": "netd"},
    "johnson": {"modality": "tir"},
}
#: Environments: every preset, and a fog layer under a 100 m target (the physical convention's slant path).
ENVIRONMENTS = [{"preset": p} for p in sorted(load_presets()["environment"])] + [
    {"fog_visibility_m": 200.0, "fog_top_m": 50.0},
    {"preset": "rain_heavy", "fog_visibility_m": 200.0, "fog_top_m": 50.0},
]


def _terms(items) -> dict:
    return {t["name"]: t["value"] for t in items}


def _range_path_terms(result) -> dict:
    return {t.name: (float(np.asarray(t.value)), t.unit, t.source) for t in result.terms if t.name in PATH_TERMS}


def _scenario_view(sc, range_m: float = RANGE_M) -> View:
    """The view whose geometry is the scenario's: the target ``altitude_m`` above the sensor at ``range_m``."""
    return View(range_m, 0.0, -math.degrees(math.asin(sc.target["altitude_m"] / range_m)))


def _render_path(sc, name: str, view: View | None = None):
    """The path a render of ``name`` applies under ``csuas render``'s automatic atmosphere (no Mitsuba), seen from
    ``view`` (the scenario's geometry unless given)."""
    spec, view = sc.sensors[name], view or _scenario_view(sc)
    if not atmosphere_on(sc, "auto", spec):
        return NO_PATH
    if spec.modality == "eo":
        light = scenario_daylight(sc, spec)
        layer = fog_layer_at(light.fog_layer, view)
        return eo_path(
            view.range_m, light.visibility_km, 550.0, 1.0, light.rain_extinction_per_km, light.convention, layer
        )
    scene = scenario_thermal_scene(sc, spec)
    fog = thermal_fog_at(scene, view)
    total = scene.extinction_db_km + fog[0]
    return tir_path(view.range_m, total, scene.air_temperature_k, "lwir", scene.rain_db_km, sc.convention, fog)


@pytest.mark.parametrize("convention", ["paper", "physical"])
@pytest.mark.parametrize("environment", ENVIRONMENTS, ids=lambda e: "-".join(f"{k}={v}" for k, v in e.items()))
def test_render_and_range_apply_the_same_terms(environment, convention):
    sc = parse_scenario(
        {"convention": convention, "target": {"altitude_m": 100.0}, "environment": environment, "sensors": SENSORS}
    )
    ranges = evaluate(sc)
    for name in SENSORS:
        expected = _range_path_terms(ranges[name])
        path = _render_path(sc, name)
        rendered = {t["name"]: (t["value"], t["unit"], t["source"]) for t in path.terms if t["name"] in PATH_TERMS}
        assert rendered.keys() == expected.keys(), name
        for term, (value, unit, source) in expected.items():
            assert rendered[term][0] == pytest.approx(value, rel=1e-12), (name, term)
            assert rendered[term][1:] == (unit, source), (name, term)
        assert (path is NO_PATH) == (not expected), name  # no term in range: the render applies nothing
    layered = "fog_top_m" in environment and convention == "physical"
    assert ("fog_path_fraction" in _range_path_terms(ranges["eo"])) == layered
    rain = environment.get("preset", "").startswith("rain") or environment.get("preset") == "rf_standard"
    assert ("rain_extinction_per_km" in _range_path_terms(ranges["eo"])) == (rain and convention == "physical")


@pytest.mark.parametrize("convention", ["paper", "physical"])
def test_render_path_transmittance_is_the_range_models(convention):
    """The render's transmittance at R is the one the EO contrast range (Eq. 21) and the thermal model solve with."""
    sc = parse_scenario({"convention": convention, "environment": {"preset": "rain_moderate"}, "sensors": SENSORS})
    ranges = evaluate(sc)
    beta = sum(
        _range_path_terms(ranges["eo"])[k][0]
        for k in ("kruse_extinction", "rain_extinction_per_km")
        if k in _range_path_terms(ranges["eo"])
    )
    eo = _terms(_render_path(sc, "eo").terms)
    # Eq. 10 read in dB (paper) or Beer-Lambert (physical), computed here by hand
    expected = 10 ** (-beta * RANGE_M / 1e4) if convention == "paper" else math.exp(-beta * RANGE_M / 1e3)
    assert eo["transmittance"] == pytest.approx(expected, rel=1e-12)
    sigma = _range_path_terms(ranges["mrtd"])["extinction_db_km"][0]
    tir = _terms(_render_path(sc, "mrtd").terms)
    # Eq. 31 as printed, exp(-sigma R) (paper), or the dB reading 10^(-sigma R / 10) (physical)
    expected = math.exp(-sigma * RANGE_M / 1e3) if convention == "paper" else 10 ** (-sigma * RANGE_M / 1e4)
    assert tir["transmittance"] == pytest.approx(expected, rel=1e-12)


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


def test_path_extinction_adds_a_layered_fog_and_rain_by_hand():
    # at 550 nm Kruse's factor is 1 in both conventions: Koschmieder's 3.912 / V (Eq. 12)
    koschmieder = -math.log(0.02)
    rain = 0.365 * 30.0**0.63  # Marshall-Palmer, Q_ext = 2, to 0.2 %
    total, terms = eo.path_extinction(550.0, 0.2, "physical", rain, (0.25, 10.0))
    assert float(total) == pytest.approx(0.25 * koschmieder / 0.2 + 0.75 * koschmieder / 10.0 + rain, rel=1e-12)
    assert [t.name for t in terms] == ["kruse_extinction", "fog_path_fraction", "rain_extinction_per_km"]
    total, terms = eo.path_extinction(550.0, 0.2, "paper")
    assert float(total) == pytest.approx(koschmieder / 0.2, rel=1e-12) and [t.unit for t in terms] == ["dB/km"]


def test_path_inputs_follow_the_convention():
    sc = parse_scenario(
        {
            "convention": "physical",
            "target": {"altitude_m": 100.0},
            "environment": {"fog_visibility_m": 200.0, "fog_top_m": 50.0, "rain_rate_mm_h": 6.0},
            "sensors": SENSORS,
        }
    )
    physical = ranges_module.eo_path_inputs(sc, sc.sensors["eo"], "physical")
    assert physical["visibility_km"] == 0.2 and physical["rain_extinction_per_km"] > 0
    # a straight path from 2 m to 102 m spends (50 - 2) / 100 of its length below a 50 m top
    assert float(physical["fog_layer"][0]) == pytest.approx(0.48, rel=1e-12) and physical["fog_layer"][1] == 10.0
    paper = ranges_module.eo_path_inputs(sc, sc.sensors["eo"], "paper")
    assert paper == {"visibility_km": 0.2, "rain_extinction_per_km": 0.0, "fog_layer": None}
    table_27 = sc.sensors["mrtd"].params["extinction_db_km"]
    assert ranges_module.thermal_path(sc, sc.sensors["johnson"], "physical") == (None, 0.0, [])
    sigma, rain, terms = ranges_module.thermal_path(sc, sc.sensors["mrtd"], "paper")
    assert (float(sigma), rain, [t.name for t in terms]) == (table_27, 0.0, ["extinction_db_km"])
    sigma, rain, terms = ranges_module.thermal_path(sc, sc.sensors["mrtd"], "physical")
    assert float(rain) == pytest.approx(10 * math.log10(math.e) * 0.365 * 6.0**0.63, rel=2e-3)
    names = ["extinction_db_km", "rain_extinction_db_km", "fog_extinction_db_km", "fog_path_fraction"]
    assert [t.name for t in terms] == names
    fog = {t.name: float(t.value) for t in terms}
    # the fog's 200 m visibility fills 0.48 of the path: 3.912 / 0.2 km x LWIR band ratio, in dB, times 0.48
    assert fog["fog_extinction_db_km"] == pytest.approx(
        10 * math.log10(math.e) * -math.log(0.02) / 0.2 * lwir_advection_ratio() * 0.48, rel=1e-9
    )
    assert float(sigma) == pytest.approx(table_27 + fog["rain_extinction_db_km"] + fog["fog_extinction_db_km"], 1e-12)


def test_thermal_path_terms_list_only_what_is_applied():
    assert tir.path_terms(0.0, 0.0) == [] and tir.rain_terms(0.0) == []
    assert [t.name for t in tir.path_terms(0.2, 0.0)] == ["extinction_db_km"]
    (rain,) = tir.rain_terms(1.5)
    assert (rain.name, rain.value, rain.unit) == ("rain_extinction_db_km", 1.5, "dB/km")


def _dataset_exr(tmp_path, name: str, environment: str, sensor: str = "eo") -> np.ndarray:
    """The signal (electrons or kelvin) of a one-image dataset of the drone at 100 m, centred, quantised only (its
    EXR holds the signal before quantisation)."""
    import OpenEXR

    from csuas import cli

    scenario = tmp_path / f"{name}.toml"
    scenario.write_text(
        f'name = "{name}"\nconvention = "physical"\n[environment]\n{environment}\n'
        '[sensors.eo]\nmodality = "eo"\n[sensors.tir]\nmodality = "tir"\nmodel = "mrtd"\n'
    )
    spec = tmp_path / f"{name}_spec.toml"
    spec.write_text(
        f'seed = 1\ncount = 1\nscenario = "{scenario.as_posix()}"\nsensor = "{sensor}"\ndrones = ["dji_mini_4_pro"]\n'
        'range_m = [100.0]\nposition = "centre"\nchain = ["quantise"]\nexr = true\n'
    )
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / name)]) == 0
    with OpenEXR.File(str(tmp_path / name / "images" / "000000_dji_mini_4_pro.exr")) as exr:
        return np.asarray(exr.channels()["Y"].pixels, dtype=float)


@pytest.mark.slow
def test_dataset_frames_take_the_scenarios_fog(tmp_path):
    """A fog of 200 m visibility cuts the drone's excess over the sky by exp(-(3.912/0.2 - 3.912/10) 0.1 km).

    Same seed, same sky (the airlight of a sky background is the sky): the frames differ only by the path's
    transmittance on the drone's excess light (Koschmieder, physical convention, at the EO default 550 nm).
    """
    clear = _dataset_exr(tmp_path, "clear", "")
    fog = _dataset_exr(tmp_path, "fog", "fog_visibility_m = 200.0")
    sky = float(np.median(clear))
    assert float(np.median(fog)) == pytest.approx(sky, rel=1e-6)
    excess_clear, excess_fog = (float(np.sum(frame - sky)) for frame in (clear, fog))
    koschmieder = -math.log(0.02)
    expected = math.exp(-(koschmieder / 0.2 - koschmieder / 10.0) * 0.1)
    assert excess_fog / excess_clear == pytest.approx(expected, rel=1e-4)  # float32 EXR pixels


@pytest.mark.slow
def test_thermal_dataset_frames_take_the_scenarios_rain(tmp_path):
    """Heavy rain (30 mm/h) cuts the drone's excess band radiance over the background by 10^(-a R / 10), a the
    rain's Marshall-Palmer attenuation in dB/km: the path radiance adds alike to the drone and its background."""
    from csuas.core.radiometry import band_radiance

    dry = _dataset_exr(tmp_path, "dry", "", "tir")
    wet = _dataset_exr(tmp_path, "wet", "rain_rate_mm_h = 30.0", "tir")
    excess = []
    for frame in (dry, wet):
        radiance = np.asarray(band_radiance(frame, "lwir"), dtype=float)
        excess.append(float(np.sum(radiance - np.median(radiance))))
    rain_db_km = 10 * math.log10(math.e) * math.pi * 8000.0 / (4.1 * 30.0**-0.21) ** 3 * 1e-3  # Q_ext = 2
    assert excess[1] / excess[0] == pytest.approx(10 ** (-rain_db_km * 0.1 / 10), rel=1e-3)


@pytest.mark.slow
def test_a_render_keeps_todays_figures_where_range_applies_no_term(capsys, tmp_path):
    """Heavy rain on a Johnson thermal sensor: its range lists no path term (the model has no path), so the
    automatic atmosphere renders exactly what ``--atmosphere off`` (the render without any path) does."""
    import json

    from csuas import cli

    scenario = tmp_path / "wet.toml"
    scenario.write_text(
        'name = "wet"\nconvention = "physical"\n[environment]\npreset = "rain_heavy"\n[sensors.t]\nmodality = "tir"\n'
    )
    assert not {"extinction_db_km", "rain_extinction_db_km"} & {
        t.name for t in evaluate(load_scenario(str(scenario)))["t"].terms
    }
    rows = []
    for atmosphere in ("auto", "off"):
        argv = ["render", "tir", str(scenario), "--range-m", "150", "--quality", "draft", "--quiet", "--json"]
        assert cli.main([*argv, "--atmosphere", atmosphere]) == 0
        (row,) = json.loads(capsys.readouterr().out)["results"]
        rows.append({k: v for k, v in row.items() if k != "time_s"})
    assert rows[0]["terms"] == [] and rows[0] == rows[1]
