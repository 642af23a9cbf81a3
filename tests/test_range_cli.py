"""``csuas range`` shows everything it used and never a silent zero (issue 9, section 2)."""

import json
import math

import pytest

from csuas.cli import main

A = 6_371_000.0


def _range(capsys, tmp_path, text, *extra):
    path = tmp_path / "s.toml"
    path.write_text('name = "t"\n' + text)
    assert main(["range", str(path), "--json", *extra]) == 0
    return json.loads(capsys.readouterr().out)


def test_the_section_4_9_radar_is_a_preset_giving_445_3_m_and_the_default_radar_says_why_it_gives_47_m(
    capsys, tmp_path
):
    out = _range(
        capsys,
        tmp_path,
        '[sensors.paper]\nmodality = "radar"\npreset = "paper_section_4_9"\n[sensors.table39]\nmodality = "radar"\n',
    )
    assert out["sensors"]["paper"]["range_m"] == pytest.approx(445.3, abs=0.05)  # Section 4.9.3, Fig. 5
    default = out["sensors"]["table39"]
    assert default["range_m"] == pytest.approx(47.1, abs=0.05)
    assert any("13 dB" in n and "paper_section_4_9" in n for n in default["notes"])
    # Eq. 109 by hand: 100 W, G = 35 dB, lambda = 0.0125 m, sigma 0.01, SNR 10 dB, k_B 1.381e-23, 290 K, F 10 dB, 50 MHz
    eq_109 = (100 * 10**7 * 0.0125**2 * 0.01 / ((4 * math.pi) ** 3 * 10 * 1.381e-23 * 290 * 10 * 50e6)) ** 0.25
    assert out["sensors"]["paper"]["range_m"] == pytest.approx(eq_109, rel=1e-9)


def test_every_input_states_where_it_came_from(capsys, tmp_path):
    out = _range(
        capsys,
        tmp_path,
        '[sensors.r]\nmodality = "radar"\npreset = "echoshield"\nsnr_min_db = 13.0\n[environment]\nrain = "moderate"\n',
    )
    inputs = out["sensors"]["r"]["inputs"]
    assert inputs["frequency_ghz"] == {"value": 16.0, "unit": "GHz", "source": "preset echoshield"}
    assert inputs["snr_min_db"]["source"] == "scenario"
    assert inputs["p_tx_w"]["source"] == "default (Table 39)"
    assert inputs["wavelength_m"]["value"] == pytest.approx(3e8 / 16e9, rel=1e-12)
    assert out["environment_inputs"]["rain_rate_mm_h"]["source"].startswith("scenario (class 'moderate'")
    assert out["target_inputs"]["d_crit_m"]["source"] == "default (Table 8)"


def test_dense_fog_lidar_names_table_47s_fixed_path(capsys, tmp_path):
    out = _range(capsys, tmp_path, '[environment]\nfog = "dense"\n[sensors.l]\nmodality = "lidar"\n')
    lidar = out["sensors"]["l"]
    # Kruse at V = 0.1 km (Kim's q = 0 below 0.5 km): 3.912 / 0.1 per km, read as dB/km over 3 km
    eta = 10 ** (-3.912 / 0.1 * 3 / 10)
    assert lidar["range_m"] < 0.01
    assert f"{eta:.3g}" in lidar["reason"] and "3 km" in lidar["reason"]


def test_a_target_above_the_slant_range_has_no_horizontal_range_and_says_so(capsys, tmp_path):
    out = _range(
        capsys,
        tmp_path,
        '[target]\naltitude_m = 300.0\n[sensors.e]\nmodality = "eo"\n[sensors.r]\nmodality = "radar"\n',
    )
    eo, radar = out["sensors"]["e"], out["sensors"]["r"]
    assert eo["horizontal_range_m"] == pytest.approx(math.sqrt(eo["range_m"] ** 2 - 300.0**2), rel=1e-12)
    assert radar["horizontal_range_m"] is None
    assert "never within range at that altitude" in radar["reason"]


def test_a_sensor_height_caps_radio_ranges_at_the_4_3_earth_horizon(capsys, tmp_path):
    out = _range(
        capsys,
        tmp_path,
        '[target]\naltitude_m = 110.0\n[sensors.rf]\nmodality = "rf"\nheight_m = 10.0\n'
        '[sensors.eo]\nmodality = "eo"\nheight_m = 10.0\n',
    )
    limit = math.sqrt(2 * 4 / 3 * A * 10.0) + math.sqrt(2 * 4 / 3 * A * 120.0)
    rf = out["sensors"]["rf"]
    assert rf["range_m"] == pytest.approx(limit, rel=1e-12)
    assert rf["terms"]["horizon_m"]["value"] == pytest.approx(limit, rel=1e-12)
    assert "4/3-Earth" in rf["terms"]["horizon_m"]["source"] and "limited by" in rf["reason"]
    optical = math.sqrt(2 * A * 10.0 / 0.87) + math.sqrt(2 * A * 120.0 / 0.87)
    assert out["sensors"]["eo"]["terms"]["horizon_m"]["value"] == pytest.approx(optical, rel=1e-12)
    assert out["sensors"]["eo"]["range_m"] == pytest.approx(555.54, abs=0.01)  # far inside: unchanged


def test_without_heights_a_range_past_the_horizon_is_flagged(capsys, tmp_path):
    out = _range(capsys, tmp_path, '[sensors.rf]\nmodality = "rf"\n[sensors.eo]\nmodality = "eo"\n')
    limit = math.sqrt(2 * 4 / 3 * A * 2.0) + math.sqrt(2 * 4 / 3 * A * 120.0)
    assert out["sensors"]["rf"]["range_m"] > limit
    assert f"({limit / 1000:.1f} km)" in out["sensors"]["rf"]["reason"]
    assert "horizon" not in out["sensors"]["eo"].get("reason", "")


def test_night_is_named_as_an_effect_no_model_reads(capsys, tmp_path):
    out = _range(capsys, tmp_path, '[environment]\npreset = "night"\n[sensors.e]\nmodality = "eo"\n')
    assert "night" in out["effects"] and "illuminance_lx" in out["ignored_effects"]["night"]
    day = _range(capsys, tmp_path, '[sensors.e]\nmodality = "eo"\n')
    assert out["sensors"]["e"]["range_m"] == day["sensors"]["e"]["range_m"]


def test_the_text_output_shows_terms_inputs_and_horizontal_range(capsys, tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        '[target]\naltitude_m = 100.0\n[sensors.r]\nmodality = "radar"\npreset = "echoshield"\n'
        '[sensors.e]\nmodality = "eo"\n'
    )
    assert main(["range", str(path)]) == 0
    text = capsys.readouterr().out
    assert "term  l_total_db" in text and "Eqs. 84-86" in text
    assert "input frequency_ghz" in text and "preset echoshield" in text
    assert "horizontal n/a" in text and "horizontal 546.5 m" in text


def test_a_fov_in_radians_draws_one_warning_not_an_error(capsys, tmp_path):
    out = _range(capsys, tmp_path, '[sensors.e]\nmodality = "eo"\nhfov_deg = 0.17\nvfov_deg = 20.0\n')
    (warning,) = out["warnings"]  # one mistake, one warning: aspect ratio and the likely radian together
    aspect = math.tan(math.radians(0.17) / 2) / math.tan(math.radians(10.0))
    assert f"{aspect:.3g}" in warning and "1920 / 1080" in warning
    assert f"{math.degrees(0.17):.3g} deg" in warning and "hfov_deg = 0.17 looks like radians" in warning
    assert not _range(capsys, tmp_path, '[sensors.e]\nmodality = "eo"\n')["warnings"]
    path = tmp_path / "fov.toml"
    path.write_text('[sensors.e]\nmodality = "eo"\nhfov_deg = 0.17\nvfov_deg = 20.0\n')
    assert main(["range", str(path)]) == 0  # the text output: the warning once on stderr
    err = capsys.readouterr().err
    assert err.count("csuas range: warning:") == 1 and "looks like radians" in err


def test_a_near_zero_range_names_the_budget_that_is_spent(capsys, tmp_path):
    out = _range(
        capsys,
        tmp_path,
        '[target]\nsl_db = 20.0\n[environment]\nnoise_level_db = 90.0\n[sensors.a]\nmodality = "acoustic"\n',
    )
    a = out["sensors"]["a"]
    budget = 20.0 - 10.0 - 90.0 + 20.0  # Eq. 44: SL - SNR_req - NL + G_array (Table 8, Eq. 38, Eq. 42 defaults)
    assert a["range_m"] == pytest.approx(10 ** (budget / 20), rel=1e-12)  # Eq. 44 spherical spreading: 1 mm
    assert f"budget_db = {budget:g} dB" in a["reason"] and "below 1 m" in a["reason"]


def test_a_null_horizontal_range_carries_its_meaning(capsys, tmp_path):
    out = _range(capsys, tmp_path, '[target]\naltitude_m = 300.0\n[sensors.r]\nmodality = "radar"\n')
    radar = out["sensors"]["r"]
    assert radar["horizontal_range_m"] is None and "never within range" in radar["horizontal_range_m_note"]
    assert "horizontal_range_m_nonfinite" not in radar
    assert main(["range", str(tmp_path / "s.toml")]) == 0
    text = capsys.readouterr().out
    assert "horizontal_range_m                    n/a m" in text and "nan" not in text


def test_the_mavic_3_target_preset_has_the_side_view_height_of_its_mesh():
    from csuas.defaults import load_presets
    from csuas.drone_models.presets import build_drone
    from csuas.drone_models.silhouette import projected_metrics

    preset = load_presets()["target"]["dji_mavic_3"]
    side = projected_metrics(build_drone("dji_mavic_3"), 90.0, 0.0)  # Eq. 1, min(d_x, d_y) seen from the side
    assert preset["d_crit_m"] == pytest.approx(side["d_crit_min_m"], rel=1e-3)
    assert 0.1077 < preset["d_crit_m"] < 0.1077 + 0.02  # DJI: 107.7 mm high unfolded without propellers
    assert preset["mass_g"] == 895.0  # DJI take-off weight


def test_every_mistake_of_a_scenario_comes_at_once(capsys, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(
        'surprise = 1\n[target]\nd_crit_m = -1\n[environment]\nrain = "biblical"\n'
        '[sensors.r]\nmodality = "radar"\np_tx_w = -5\n[sensors.x]\nmodality = "sonar"\n'
    )
    assert main(["range", str(path)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 5
    for key in ("surprise", "target.d_crit_m", "environment.rain", "sensors.r.p_tx_w", "sensors.x.modality"):
        assert sum(key in line for line in lines) == 1, key


def test_every_drone_mesh_preset_is_a_target_preset(capsys):
    from csuas.drone_models import list_presets

    assert main(["defaults", "presets", "--json"]) == 0
    presets = json.loads(capsys.readouterr().out)["presets"]
    targets = {p["name"] for p in presets if p["kind"] == "target"}
    assert set(list_presets()) <= targets
    radar = {p["name"]: p for p in presets if p["kind"] == "sensor" and p["modality"] == "radar"}
    assert radar["paper_section_4_9"]["sets"]["p_tx_w"] == 100.0


def test_defaults_list_text_shows_the_valid_range_and_description(capsys):
    assert main(["defaults", "list"]) == 0
    text = capsys.readouterr().out
    line = next(row for row in text.splitlines() if row.startswith("eo.hfov_deg"))
    assert "0 .. 180" in line and "horizontal field of view" in line


def test_sensitivity_of_a_scenario_with_several_sensors_needs_the_sensor_named(capsys):
    assert main(["sensitivity", "--scenario", "default", "--vary", "sensor.hfov_deg=1:20"]) == 2
    err = capsys.readouterr().err
    assert "--sensor" in err and "eo, tir, acoustic, rf, radar, lidar" in err


def test_fog_top_is_a_term_with_its_source_in_physical_and_ignored_in_paper(capsys, tmp_path):
    text = (
        "[target]\naltitude_m = 100.0\n[environment]\nfog_visibility_m = 200.0\nfog_top_m = 50.0\n"
        '[sensors.e]\nmodality = "eo"\nheight_m = 2.0\n'
    )
    physical = _range(capsys, tmp_path, 'convention = "physical"\n' + text)
    terms = physical["sensors"]["e"]["terms"]
    assert terms["fog_path_fraction"]["value"] == pytest.approx(0.48, abs=1e-12)  # (50 - 2) / (102 - 2)
    assert "layered fog" in terms["fog_path_fraction"]["source"] and physical["ignored_effects"] == {}
    paper = _range(capsys, tmp_path, text)
    assert "fog_top_m" in paper["ignored_effects"]["fog_layer"]
