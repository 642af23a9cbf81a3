"""A swarm along ``csuas pd --approach-speed-m-s`` (issue 26, section 3): the first detection of any drone and
the groups resolved over time, consistent with ``csuas pd``'s Pd of any group on the same ranges."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas.cli import main

#: Four Mini 4 Pro 5 m apart across the line of sight, the default radar (1 scan/s, independent looks) and
#: EO camera (30 frames/s, correlated looks).
SCENARIO = (
    '[target]\npreset = "dji_mini_4_pro"\nswarm = {count = 4, spacing_m = 5.0}\n'
    '[sensors.radar]\nmodality = "radar"\n[sensors.eo]\nmodality = "eo"\n'
)
SPEED_M_S = 10.0
LOOKS_M = np.arange(10.0, 201.0, 10.0)  # the radar's looks: 200 m down to 10 m, one a second at 10 m/s


def _pd(tmp_path, capsys, ranges, approach: bool) -> dict:
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO)
    args = ["pd", str(path), "--json", "--range-m", *(repr(float(r)) for r in ranges)]
    assert main(args + (["--approach-speed-m-s", f"{SPEED_M_S:g}"] if approach else [])) == 0
    return json.loads(capsys.readouterr().out)


def test_independent_looks_accumulate_pd_of_any_group_look_by_look(tmp_path, capsys):
    approach = _pd(tmp_path, capsys, LOOKS_M, approach=True)["sensors"]["radar"]["swarm"]
    pd_any = np.asarray(_pd(tmp_path, capsys, LOOKS_M, approach=False)["sensors"]["radar"]["swarm"]["pd_any"])
    # far to near: 1 - prod over the looks so far of (1 - Pd_any); on the grid (near to far) reversed back
    expected = 1.0 - np.cumprod(1.0 - pd_any[::-1])
    np.testing.assert_allclose(approach["cumulative_pd_any"], expected[::-1], rtol=1e-12, atol=1e-15)
    median = LOOKS_M[::-1][np.searchsorted(expected, 0.5)]
    assert approach["median_first_detection_range_m"] == median
    assert approach["median_first_detection_time_s"] == pytest.approx((200.0 - median) / SPEED_M_S, rel=1e-12)


def test_the_radar_resolves_the_drones_when_its_beam_narrows_below_their_spacing(tmp_path, capsys):
    swarm = _pd(tmp_path, capsys, LOOKS_M, approach=True)["sensors"]["radar"]["swarm"]
    # cross-range cell R theta_3, theta_3 = sqrt(4 pi / G), G = 25 dB: 5 m apart resolve below 25.08 m
    resolve_m = 5.0 / math.sqrt(4.0 * math.pi / 10**2.5)
    assert resolve_m == pytest.approx(25.083, abs=1e-3)
    first_resolved = LOOKS_M[LOOKS_M <= resolve_m].max()  # 20 m, (200 - 20) / 10 m/s = 18 s in
    assert swarm["resolved_count_changes"] == [
        {"time_s": 0.0, "range_m": 200.0, "resolved_count": 1},
        {"time_s": (200.0 - first_resolved) / SPEED_M_S, "range_m": first_resolved, "resolved_count": 4},
    ]
    assert swarm["approach_assumption"].startswith("each look draws every resolved group afresh")


def test_correlated_looks_keep_the_running_maximum_of_pd_of_any(tmp_path, capsys):
    out = _pd(tmp_path, capsys, LOOKS_M, approach=True)
    swarm = out["sensors"]["eo"]["swarm"]
    looks = 200.0 - SPEED_M_S / 30.0 * np.arange(571)  # 30 frames a second from 200 m to 10 m
    pd_any = np.asarray(_pd(tmp_path, capsys, looks, approach=False)["sensors"]["eo"]["swarm"]["pd_any"])[::-1]
    running = np.maximum.accumulate(pd_any)  # far to near
    median = looks[np.searchsorted(running, 0.5)] if running[-1] >= 0.5 else None
    assert swarm["median_first_detection_range_m"] == pytest.approx(median, rel=1e-12)
    at_grid = [running[looks >= r][-1] for r in LOOKS_M]  # the last look at or beyond each grid range
    np.testing.assert_allclose(swarm["cumulative_pd_any"], at_grid, rtol=1e-12)
    # the fused OR of two sensors whose "has detected by R" events are independent
    radar = np.asarray(out["sensors"]["radar"]["swarm"]["cumulative_pd_any"])
    fused = 1.0 - (1.0 - radar) * (1.0 - np.asarray(swarm["cumulative_pd_any"]))
    np.testing.assert_allclose(out["fused"]["swarm"]["cumulative_pd_any"], fused, rtol=1e-12)
    # one drone's keys stay one drone's: its own approach is no better than the swarm's
    assert out["sensors"]["eo"]["median_first_detection_range_m"] <= swarm["median_first_detection_range_m"]


def test_swarm_approach_looks_at_the_sensor_rate_from_start_to_stop():
    from csuas.core.scenario import parse_scenario
    from csuas.core.swarm_detection import swarm_approach, swarm_pd

    scenario = parse_scenario(
        {"target": {"swarm": {"count": 4, "spacing_m": 5.0}}, "sensors": {"radar": {"modality": "radar"}}}, "s"
    )
    a = swarm_approach(scenario, "radar", SPEED_M_S, 200.0, 10.0)
    np.testing.assert_allclose(a["look_range_m"], LOOKS_M[::-1], rtol=1e-12)  # 1 scan/s at 10 m/s
    pd_any = swarm_pd(scenario, "radar", a["look_range_m"])["pd_any"]
    np.testing.assert_allclose(a["cumulative_pd"], 1.0 - np.cumprod(1.0 - pd_any), rtol=1e-12)
    assert a["never"] == pytest.approx(float(np.prod(1.0 - pd_any)), rel=1e-12)
