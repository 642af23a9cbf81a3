"""Scenario files (docs/scenarios.md): parsing, presets, class names, validation errors and effects."""

import numpy as np
import pytest

from csuas.base.errors import ScenarioError
from csuas.core import itu
from csuas.core.ranges import evaluate
from csuas.core.scenario import load_scenario, parse_scenario


def _scenario(**sections):
    data = {"sensors": {"eo": {"modality": "eo"}}}
    data.update(sections)
    return parse_scenario(data)


def test_embedded_default_has_every_modality_at_table_defaults():
    sc = load_scenario("default")
    assert {s.modality for s in sc.sensors.values()} == {"eo", "tir", "acoustic", "rf", "radar", "lidar"}
    assert sc.target["d_crit_m"] == 0.101 and sc.environment["illuminance_lx"] == 70000.0
    assert sc.sensors["eo"].params["n_ttpf"] == 1.0 and sc.sensors["eo"].params["lp_task"] == 1.0
    assert sc.effects == frozenset()


@pytest.mark.parametrize(
    "section, expected",
    [
        ({"rain": "moderate"}, {"rain_rate_mm_h": 6.0}),
        ({"rain_rate_mm_h": "heavy"}, {"rain_rate_mm_h": 30.0}),
        ({"rain": 12.5}, {"rain_rate_mm_h": 12.5}),
        ({"fog": "dense"}, {"fog_visibility_m": 100.0, "lwc_g_m3": 0.5}),
        ({"fog": "light", "lwc_g_m3": 0.1}, {"fog_visibility_m": 800.0, "lwc_g_m3": 0.1}),
        ({"wind": "strong_breeze"}, {"wind_speed_m_s": 12.3}),
        ({"illumination": "night"}, {"illuminance_lx": 0.01}),
        ({"noise": "city"}, {"noise_level_db": 70.0}),
        ({"preset": "rain_heavy"}, {"rain_rate_mm_h": 30.0}),
    ],
)
def test_environment_classes_and_numbers(section, expected):
    env = _scenario(environment=section).environment
    assert {k: env[k] for k in expected} == expected


def test_presets_and_overrides():
    sc = parse_scenario(
        {
            "target": {"preset": "black_hornet_3", "sl_db": 60},
            "sensors": {
                "r": {"modality": "radar", "preset": "netrad"},
                "e": {"modality": "eo", "preset": "mx_10", "task": "identification", "p_desired": 0.95},
            },
        }
    )
    assert sc.target["d_crit_m"] == 0.025 and sc.target["sl_db"] == 60.0
    assert sc.sensors["r"].params["frequency_ghz"] == 2.4 and sc.sensors["r"].params["p_tx_w"] == 0.199
    assert sc.sensors["e"].params["lp_task"] == 8.0 and sc.sensors["e"].params["n_ttpf"] == 2.0


@pytest.mark.parametrize(
    "data, fragment",
    [
        ({"target": {"dcrit": 0.1}}, "target.dcrit"),
        ({"target": {"d_crit_m": "big"}}, "target.d_crit_m = 'big'"),
        ({"target": {"d_crit_m": -1.0}}, "target.d_crit_m = -1.0"),
        ({"target": {"d_crit_m": True}}, "target.d_crit_m = True"),
        ({"environment": {"rain": "torrential"}}, "slight, moderate, heavy"),
        ({"convention": "exact"}, "paper or physical"),
        ({"colour": 1}, "a known key"),
        ({"sensors": {"x": {"modality": "sonar"}}}, "sensors.x.modality = 'sonar'"),
        ({"sensors": {"x": {"modality": "eo", "n_h": 1920.5}}}, "a whole number"),
        ({"sensors": {"x": {"modality": "eo", "task": "find"}}}, "detection, recognition, identification"),
        ({"sensors": {"x": {"modality": "radar", "frequency_ghz": 24.0, "wavelength_m": 0.0125}}}, "not both"),
        ({"sensors": {"x": {"modality": "radar", "model": "range_equation"}}}, "p_rx_min_w"),
        ({"sensors": {"x": {"modality": "eo", "preset": "hubble"}}}, "sensors.x.preset = 'hubble'"),
        ({"sensors": {}}, "at least one"),
        ({"environment": {"fog_top_m": 50.0}}, "environment.fog_top_m = 50.0 is invalid; allowed: given with"),
    ],
)
def test_bad_input_names_key_value_and_what_is_allowed(data, fragment):
    data = {"sensors": {"eo": {"modality": "eo"}}, **data}
    with pytest.raises(ScenarioError) as err:
        parse_scenario(data)
    assert fragment in str(err.value) and "\n" not in str(err.value)


def test_malformed_and_missing_files(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("name = [unclosed\n")
    with pytest.raises(ScenarioError, match="not valid TOML"):
        load_scenario(bad)
    with pytest.raises(ScenarioError, match="no such file"):
        load_scenario(tmp_path / "missing.toml")


def test_effects_follow_the_declared_conditions():
    sc = _scenario(environment={"rain": "slight", "fog": "light", "wind": 6.7, "visibility_km": 5.0})
    assert sc.effects == {"rain", "fog", "wind", "haze"}
    assert sc.optical_visibility_km == 0.8


def test_disabled_effects_contribute_nothing_and_cost_nothing(monkeypatch):
    # no rain or fog: the ITU models must not even be called, and no term appears
    def forbidden(*args, **kwargs):
        raise AssertionError("an effect the scenario does not have was computed")

    for name in ("rain_specific_attenuation_db_km", "fog_specific_attenuation_db_km"):
        monkeypatch.setattr(itu, name, forbidden)
    import csuas.core.radar as radar_mod
    import csuas.core.rf as rf_mod

    monkeypatch.setattr(rf_mod, "rain_specific_attenuation_db_km", forbidden)
    monkeypatch.setattr(rf_mod, "fog_specific_attenuation_db_km", forbidden)
    monkeypatch.setattr(radar_mod, "rain_specific_attenuation_db_km", forbidden)
    monkeypatch.setattr(radar_mod, "fog_specific_attenuation_db_km", forbidden)
    for convention in ("paper", "physical"):
        results = evaluate(load_scenario("default"), convention)
        for result in results.values():
            names = {t.name for t in result.terms}
            assert not names & {"gamma_rain_db_km", "gamma_fog_db_km", "rain_loss_db", "wind_noise_db"}


def test_fog_top_layers_the_physical_eo_path_by_its_closed_form():
    """Sensor 2 m, drone 100 m above it, fog (200 m visibility) up to 50 m: 48 % of the path in fog, Eq. 21's
    contrast range 1000 ln(C0 / C_min) / (0.48 beta_fog + 0.52 beta_clear); the paper convention ignores the top."""
    fog = {"fog_visibility_m": 200.0, "fog_top_m": 50.0}
    data = {"target": {"altitude_m": 100.0}, "sensors": {"eo": {"modality": "eo", "height_m": 2.0}}}
    layered = evaluate(parse_scenario({**data, "convention": "physical", "environment": fog}))["eo"]
    full = evaluate(parse_scenario({**data, "convention": "physical", "environment": {"fog_visibility_m": 200.0}}))
    clear = evaluate(parse_scenario({**data, "convention": "physical"}))["eo"]
    assert float(layered.term("fog_path_fraction").value) == pytest.approx(0.48, abs=1e-12)
    beta_fog = float(full["eo"].term("kruse_extinction").value)
    beta_clear = float(clear.term("kruse_extinction").value)
    beta = 0.48 * beta_fog + 0.52 * beta_clear
    assert float(layered.term("kruse_extinction").value) == pytest.approx(beta, rel=1e-12)
    sc = parse_scenario({**data, "convention": "physical", "environment": fog})
    c0, c_min = abs(sc.target["c_eo"]), sc.sensors["eo"].params["c_min"]
    expected = 1000.0 * np.log(c0 / c_min) / beta
    assert float(layered.term("contrast_limited_range_m").value) == pytest.approx(expected, rel=1e-12)
    assert "fog_path_fraction" not in {t.name for t in full["eo"].terms}
    paper = evaluate(parse_scenario({**data, "environment": fog}))["eo"]
    paper_full = evaluate(parse_scenario({**data, "environment": {"fog_visibility_m": 200.0}}))["eo"]
    assert float(paper.range_m) == float(paper_full.range_m) and sc.effects >= {"fog", "fog_layer"}


def test_rain_adds_its_term_where_it_acts():
    results = evaluate(
        parse_scenario(
            {"environment": {"rain": "heavy"}, "sensors": {"rf": {"modality": "rf"}, "eo": {"modality": "eo"}}}
        )
    )
    assert results["rf"].term("gamma_rain_db_km").value > 0
    assert "gamma_rain_db_km" not in {t.name for t in results["eo"].terms}  # the paper's EO model has no rain term


def test_p_desired_zero_without_a_limit_is_an_explicit_error():
    sc = parse_scenario({"sensors": {"t": {"modality": "tir", "p_desired": 0.0}}})
    with pytest.raises(Exception, match="p_desired"):
        evaluate(sc)
    # with an atmosphere the EO contrast limit bounds the range
    sc = parse_scenario({"sensors": {"e": {"modality": "eo", "p_desired": 0.0}}})
    assert 0 < float(evaluate(sc)["e"].range_m) < 1e6


@pytest.mark.parametrize("convention", ["paper", "physical"])
def test_every_embedded_scenario_is_finite(convention):
    import numpy as np

    from csuas.core.scenario import embedded_scenarios

    names = embedded_scenarios()
    assert {"default", "adverse", "black_hornet"} <= set(names)
    for name in names:
        for result in evaluate(load_scenario(name), convention).values():
            assert np.all(np.isfinite(result.range_m)) and np.all(result.range_m >= 0)


def test_paper_lidar_eta_follows_declared_visibility():
    from csuas.core.ranges import paper_eta_tl

    sc = parse_scenario({"environment": {"visibility_km": 3.0}, "sensors": {"l": {"modality": "lidar"}}})
    assert paper_eta_tl(sc, sc.sensors["l"]) == pytest.approx(0.6803, abs=1e-4)  # Table 47's derivation
    sc = parse_scenario({"sensors": {"l": {"modality": "lidar"}}})
    assert paper_eta_tl(sc, sc.sensors["l"]) == 0.681


def test_table_9_contrast_classes():
    sc = parse_scenario(
        {"target": {"c_eo": "low_contrast_clutter"}, "sensors": {"e": {"modality": "eo", "c_min": "general"}}}
    )
    assert sc.target["c_eo"] == 0.2 and sc.sensors["e"].params["c_min"] == 0.01


def test_altitude_adds_the_horizontal_range_of_eq_13():
    from csuas.core.ranges import horizontal_range_m

    assert horizontal_range_m(500.0, 300.0) == pytest.approx(400.0)  # 3-4-5 triangle
    assert np.isnan(horizontal_range_m(100.0, 120.0))  # higher than the range: never within range
    sc = parse_scenario({"target": {"altitude_m": 120.0}, "sensors": {"e": {"modality": "eo"}}})
    result = evaluate(sc)["e"]
    slant = float(result.range_m)
    assert result.term("horizontal_range_m").value == pytest.approx((slant**2 - 120.0**2) ** 0.5)
    assert "horizontal_range_m" not in {t.name for t in evaluate(_scenario())["eo"].terms}
    high = evaluate(parse_scenario({"target": {"altitude_m": 5000.0}, "sensors": {"e": {"modality": "eo"}}}))["e"]
    assert np.isnan(high.term("horizontal_range_m").value)
    assert "never within range at that altitude" in str(high.reason)
