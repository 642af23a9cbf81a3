"""Swarms (issue 26, section 3): resolution cells, merged signatures, first detection of any member and the
unchanged output of single drones, against closed forms and exact geometry."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import tomllib

from csuas.cli import main
from csuas.core.scenario import parse_scenario, swarm_formation
from csuas.core.swarm import (
    blob_critical_m,
    first_detection_m,
    groups_at,
    incoherent_sum_db,
    line_formation,
    link_range_m,
)
from csuas.core.swarm_detection import formation_json, group_target, sensor_cells, swarm_pd, swarm_range
from csuas.defaults.scenario_schema import SwarmTable

C = 299_792_458.0


def _json(capsys, tmp_path, command, text):
    path = tmp_path / "s.toml"
    path.write_text('name = "t"\n' + text)
    assert main([command, str(path), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _scenario(swarm: str, *modalities):
    text = f"[target]\nswarm = {swarm}\n" + "".join(f'[sensors.{m}]\nmodality = "{m}"\n' for m in modalities)
    return parse_scenario(tomllib.loads(text))


def test_the_default_formation_is_a_centred_line_across_the_line_of_sight():
    f = line_formation(4, 5.0)
    np.testing.assert_array_equal(f.offsets_m, [[0, -7.5, 0], [0, -2.5, 0], [0, 2.5, 0], [0, 7.5, 0]])
    assert f.kind == "line" and f.count == 4
    assert swarm_formation(None) is None
    table = SwarmTable(count=3, spacing_m=2.0)
    np.testing.assert_array_equal(swarm_formation(table).offsets_m, [[0, -2, 0], [0, 0, 0], [0, 2, 0]])
    sc = _scenario("{offsets_m = [[1, 2, 3], [4, 5, 6]]}", "radar")
    assert formation_json(sc) == {"count": 2, "formation": "offsets", "offsets_m": [[1, 2, 3], [4, 5, 6]]}


def test_radar_cell_is_c_over_2b_deep_and_a_beamwidth_wide():
    sc = _scenario("{count = 2, spacing_m = 5.0}", "radar")
    cells = sensor_cells(sc, sc.sensors["radar"])
    assert cells.along_m == pytest.approx(C / (2 * 200e6), rel=1e-12)  # Table 39: 200 MHz -> 0.7495 m
    theta = math.sqrt(4 * math.pi / 10**2.5)  # G_rx 25 dB, Skolnik Eq. 9.2
    assert cells.across_per_m == pytest.approx(theta, rel=1e-12)
    # two drones 5 m apart across the beam share it beyond 5 / theta; 1 m apart along it never (1 > 0.75 m)
    link = link_range_m([[0, 0, 0], [0, 5, 0], [1.0, 0, 0]], cells.along_m, 0.0, theta)
    assert link[0, 1] == pytest.approx(5 / theta, rel=1e-12)
    assert np.isinf(link[0, 2]) and np.isinf(link[1, 2])
    assert len(groups_at(link, 0.99 * 5 / theta)) == 3 and len(groups_at(link, 1.01 * 5 / theta)) == 2


def test_first_detection_takes_the_best_group_over_each_interval_of_constant_groups():
    # two drones merge beyond 100 m; one alone reaches 80 m, the pair 120 m: first detection 120 m
    link = np.array([[0.0, 100.0], [100.0, 0.0]])
    assert first_detection_m(link, lambda g: 80.0 if len(g) == 1 else 120.0) == 120.0
    # the pair would reach only 90 m, but it exists beyond 100 m only: each alone, 80 m
    assert first_detection_m(link, lambda g: 80.0 if len(g) == 1 else 90.0) == 80.0
    # each alone would reach 110 m but exists only inside 100 m; beyond it the pair reaches 105 m
    assert first_detection_m(link, lambda g: 110.0 if len(g) == 1 else 105.0) == 105.0


def test_an_unresolved_radar_swarm_is_seen_at_n_sigma_and_a_resolved_one_drone_by_drone(capsys, tmp_path):
    radar = '[sensors.r]\nmodality = "radar"\n'
    out = _json(capsys, tmp_path, "range", "[target]\nswarm = {count = 4, spacing_m = 5.0}\n" + radar)
    w = out["sensors"]["r"]["swarm"]
    single = out["sensors"]["r"]["range_m"]
    assert w["single_drone_range_m"] == single
    # free-space range equation: R proportional to sigma^(1/4); 4 sigma merged, as 5 m < R theta there
    assert w["first_detection_m"] == pytest.approx(single * 4**0.25, rel=1e-9)
    assert w["resolved_count"] == 1 and w["largest_group"] == 4
    theta = math.sqrt(4 * math.pi / 10**2.5)
    assert w["terms"]["cross_range_resolution_m"]["value"] == pytest.approx(w["first_detection_m"] * theta, rel=1e-9)
    assert out["swarm"] == {
        "count": 4,
        "formation": "line",
        "offsets_m": [[0.0, -7.5, 0.0], [0.0, -2.5, 0.0], [0.0, 2.5, 0.0], [0.0, 7.5, 0.0]],
    }
    # 100 m apart: beyond the beam at 47 m (100 / theta = 502 m), each drone alone
    wide = _json(capsys, tmp_path, "range", "[target]\nswarm = {count = 4, spacing_m = 100.0}\n" + radar)
    w = wide["sensors"]["r"]["swarm"]
    assert w["first_detection_m"] == wide["sensors"]["r"]["range_m"]
    assert w["resolved_count"] == 4 and w["largest_group"] == 1


def test_camera_blobs_merge_under_a_one_pixel_gap_with_the_bounding_box_s_d_crit(capsys, tmp_path):
    sensors = '[sensors.e]\nmodality = "eo"\n'
    single = _json(capsys, tmp_path, "range", sensors)["sensors"]["e"]["range_m"]
    ifov = math.radians(10.0) / 1920  # Table 22: 10 deg over 1920 pixels
    d = 0.101  # Table 8
    # a pair side by side, centres d + half a pixel at the single drone's range apart: gap 0.5 px there
    s = d + 0.5 * single * ifov
    out = _json(capsys, tmp_path, "range", f"[target]\nswarm = {{offsets_m = [[0, 0, 0], [0, {s!r}, 0]]}}\n" + sensors)
    w = out["sensors"]["e"]["swarm"]
    blob = math.sqrt((s + d) * d)  # bounding box (s + d) x d
    # the paper's EO range is Johnson-limited, proportional to d_crit (Eq. 18)
    assert w["first_detection_m"] == pytest.approx(single * blob / d, rel=1e-9)
    assert w["resolved_count"] == 1
    pixel = w["first_detection_m"] * ifov
    assert w["terms"]["drone_pixels"]["value"] == pytest.approx(d / pixel, rel=1e-9)
    assert w["terms"]["largest_blob_width_px"]["value"] == pytest.approx((s + d) / pixel, rel=1e-9)
    assert w["terms"]["largest_blob_height_px"]["value"] == pytest.approx(d / pixel, rel=1e-9)
    # 5 m apart: 5 m is 99 pixels at the single range, resolved, each alone
    line = _json(capsys, tmp_path, "range", "[target]\nswarm = {count = 3, spacing_m = 5.0}\n" + sensors)
    assert line["sensors"]["e"]["swarm"]["first_detection_m"] == single
    assert line["sensors"]["e"]["swarm"]["resolved_count"] == 3


def test_blob_critical_dimension_is_the_root_of_its_bounding_box():
    assert blob_critical_m([[0, 0, 0], [3, 1.0, 2.0]], 0.5) == pytest.approx(math.sqrt(1.5 * 2.5), rel=1e-15)


def test_n_incoherent_acoustic_sources_add_10_log_n(capsys, tmp_path):
    text = '[target]\nswarm = {count = 5, spacing_m = 2.0}\n[sensors.a]\nmodality = "acoustic"\n'
    w = _json(capsys, tmp_path, "range", text)["sensors"]["a"]["swarm"]
    assert w["terms"]["swarm_level_db"]["value"] == pytest.approx(6.98970004336, abs=1e-9)
    assert incoherent_sum_db(2) == pytest.approx(3.01029995664, abs=1e-9)
    sc = _scenario("{count = 5, spacing_m = 2.0}", "acoustic")
    assert group_target(sc, "acoustic", np.arange(5))["sl_db"] == pytest.approx(80.0 + 6.98970004336, abs=1e-9)
    # the paper's acoustic range: spherical spreading only, 20 log10 R: +10 log10 5 dB -> range x sqrt(5)
    assert w["first_detection_m"] == pytest.approx(w["single_drone_range_m"] * math.sqrt(5), rel=1e-9)
    assert w["resolved_count"] == 1


def test_rf_and_lidar_see_each_drone_alone():
    sc = _scenario("{count = 3, spacing_m = 1.0}", "rf", "lidar")
    for name in ("rf", "lidar"):
        w = swarm_range(sc, name, "paper")
        assert w["first_detection_m"] == w["single_drone_range_m"] and w["resolved_count"] == 3


def test_pd_of_any_of_n_resolved_drones_is_one_minus_the_product_of_misses(capsys, tmp_path):
    text = '[target]\nswarm = {count = 3, spacing_m = 200.0}\n[sensors.r]\nmodality = "radar"\n'
    out = _json(capsys, tmp_path, "pd", text)
    s = out["sensors"]["r"]
    assert s["swarm"]["resolved_count_at_range"] == [3] * len(out["range_m"])  # 200 m > R theta below 1 km
    np.testing.assert_allclose(s["swarm"]["pd_any"], 1 - (1 - np.asarray(s["pd"])) ** 3, rtol=1e-9, atol=1e-15)
    # merged (5 m apart) beyond 5 / theta: one target of 3 sigma
    sc = _scenario("{count = 3, spacing_m = 5.0}", "radar")
    theta = math.sqrt(4 * math.pi / 10**2.5)
    r = np.array([0.9, 1.1]) * 5.0 / theta
    got = swarm_pd(sc, "radar", r)
    assert got["resolved_count_at_range"].tolist() == [3, 1]


def test_bad_swarm_tables_name_the_key(capsys, tmp_path):
    for swarm, fragment in (
        ("{count = 4}", "target.swarm = {'count': 4} is invalid; allowed: count and spacing_m together"),
        ("{count = 1, spacing_m = 2.0}", "target.swarm.count = 1"),
        ("{offsets_m = [[0, 0]]}", "target.swarm.offsets_m"),
        ("{count = 2, spacing_m = 0.0}", "target.swarm.spacing_m = 0"),
    ):
        path = tmp_path / "bad.toml"
        path.write_text(f'[target]\nswarm = {swarm}\n[sensors.r]\nmodality = "radar"\n')
        assert main(["range", str(path), "--json"]) == 2
        assert fragment in capsys.readouterr().err


@pytest.mark.parametrize("command", ["range", "pd"])
def test_a_scenario_without_a_swarm_reports_exactly_what_one_drone_of_a_swarm_reports(capsys, tmp_path, command):
    sensors = '[sensors.r]\nmodality = "radar"\n[sensors.e]\nmodality = "eo"\n[sensors.a]\nmodality = "acoustic"\n'
    plain = _json(capsys, tmp_path, command, sensors)
    swarm = _json(capsys, tmp_path, command, "[target]\nswarm = {count = 4, spacing_m = 5.0}\n" + sensors)
    assert "swarm" not in json.dumps(plain)  # no key of the swarm appears without one
    swarm.pop("swarm")
    for s in swarm["sensors"].values():
        s.pop("swarm")
    assert swarm == plain
