"""Swarms in sweeps, sensitivity analyses and coverage (issue 26, section 3): ``target.swarm.count`` and
``target.swarm.spacing_m`` as sweep axes and sensitivity bounds, each point equal to ``csuas range`` of the
same swarm, the radar's merged swarm at k^(1/4) times one drone's range (k sigma in the radar equation);
coverage maps refuse a swarm (one drone per cell)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from csuas.cli import main
from csuas.sweep import parse_spec, read_results, run_sweep

#: Section 4's default radar on one Mini 4 Pro (csuas range default): 47.1216879 m.
RADAR_ONE_M = 47.1216879
POINTS = [(2, 5.0), (8, 1.0)]  # (count, spacing_m): both merged into one radar cell at their first detection


def _range_json(tmp_path, capsys, count: int, spacing_m: float) -> dict:
    path = tmp_path / f"swarm_{count}_{spacing_m:g}.toml"
    text = _swarm_scenario_text().replace("count = 4, spacing_m = 5.0", f"count = {count}, spacing_m = {spacing_m}")
    path.write_text(text)
    assert main(["range", str(path), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _swarm_scenario_text() -> str:
    from csuas.defaults import scenario_path

    text = scenario_path("swarm").read_text()
    assert "count = 4, spacing_m = 5.0" in text
    return text


@pytest.mark.parametrize("job", ["range", "pd"])
def test_a_two_point_swarm_sweep_equals_two_range_calls(tmp_path, capsys, job):
    spec = parse_spec(
        {
            "job": job,
            "scenario": "swarm",
            "seed": 1,
            "combine": "zip",
            "axes": {"target.swarm.count": [c for c, _ in POINTS], "target.swarm.spacing_m": [s for _, s in POINTS]},
        }
    )
    table = read_results(run_sweep(spec, tmp_path / "sweep", "serial", progress=None)["results"])
    for i, (count, spacing) in enumerate(POINTS):
        expected = _range_json(tmp_path, capsys, count, spacing)["sensors"]
        for name, sensor in expected.items():
            swarm = sensor["swarm"]
            assert table[f"swarm_first_detection_m.{name}"][i] == pytest.approx(swarm["first_detection_m"], rel=1e-12)
            assert table[f"swarm_resolved_count.{name}"][i] == swarm["resolved_count"]
        # the radar merges them all (5 m and 1 m apart: under R theta_3 at 56-79 m): k sigma, R ~ k^(1/4)
        assert table["swarm_first_detection_m.radar"][i] == pytest.approx(RADAR_ONE_M * count**0.25, rel=1e-6)
    if job == "range":  # one drone's columns are unchanged by the swarm
        assert list(table["range_m.radar"]) == pytest.approx([RADAR_ONE_M] * 2, rel=1e-6)


def test_a_sweep_without_swarm_columns_when_the_scenario_has_no_swarm():
    spec = parse_spec({"job": "range", "scenario": "default", "seed": 1, "axes": {"target.d_crit_m": [0.1]}})
    assert not [c for c in spec.kind.columns(spec) if c.startswith("swarm_")]


@pytest.mark.parametrize(
    ("scenario", "axes", "fragment"),
    [
        ("default", '"target.swarm.count" = [2]', "axes.target.swarm.count.0 = 2 is invalid; allowed: a scenario"),
        ("swarm", '"target.swarm.count" = [3, 1]', "axes.target.swarm.count.1 = 1 is invalid; allowed: a whole number"),
        ("swarm", '"target.swarm.count" = [2.5]', "axes.target.swarm.count.0"),
        ("swarm", '"target.swarm.spacing_m" = [0.0]', "axes.target.swarm.spacing_m.0 = 0.0 is invalid"),
        ("swarm", '"target.swarm.offsets_m" = [1.0]', "axes.target.swarm.offsets_m"),
    ],
)
def test_bad_swarm_axes_exit_2_naming_the_key(tmp_path, capsys, scenario, axes, fragment):
    spec = tmp_path / "bad.toml"
    spec.write_text(f'job = "range"\nscenario = "{scenario}"\n[axes]\n{axes}\n')
    assert main(["sweep", str(spec), "--out", str(tmp_path / "out"), "--scheduler", "serial"]) == 2
    err = capsys.readouterr().err
    assert fragment in err and "Traceback" not in err


def test_the_rcs_job_takes_no_swarm_axis(tmp_path, capsys):
    spec = tmp_path / "bad.toml"
    spec.write_text('job = "rcs"\nscenario = "swarm"\n[axes]\nfrequency_ghz = [10.0]\n"target.swarm.count" = [2]\n')
    assert main(["sweep", str(spec), "--out", str(tmp_path / "out"), "--scheduler", "serial"]) == 2
    assert "axes.target.swarm.count" in capsys.readouterr().err


def test_sensitivity_of_a_swarm_varies_its_first_detection_and_its_count_and_spacing(tmp_path, capsys):
    args = ["sensitivity", "--scenario", "swarm", "--sensor", "radar", "--json", "--vary"]
    args += ["target.swarm.count=2:8", "target.swarm.spacing_m=1:20"]
    assert main(args) == 0
    entry = json.loads(capsys.readouterr().out)["analyses"]["swarm.radar"]
    assert entry["figure"].startswith("swarm first_detection_m")
    assert entry["baseline_m"] == pytest.approx(RADAR_ONE_M * 4**0.25, rel=1e-6)  # 4 merged at 5 m: 66.64 m
    bars = {b["parameter"]: b for b in entry["bars"]}
    assert bars["target.swarm.count"]["default"] == 4 and bars["target.swarm.spacing_m"]["default"] == 5.0
    assert bars["target.swarm.count"]["range_at_low_m"] == pytest.approx(RADAR_ONE_M * 2**0.25, rel=1e-6)
    assert bars["target.swarm.count"]["range_at_high_m"] == pytest.approx(RADAR_ONE_M * 8**0.25, rel=1e-6)
    # 20 m apart: resolved at any range a single drone reaches (theta_3 R = 20 m only at ~400 m): one drone's
    assert bars["target.swarm.spacing_m"]["range_at_high_m"] == pytest.approx(RADAR_ONE_M, rel=1e-6)
    two = _range_json(tmp_path, capsys, 2, 5.0)["sensors"]["radar"]["swarm"]["first_detection_m"]
    assert bars["target.swarm.count"]["range_at_low_m"] == pytest.approx(two, rel=1e-12)  # as csuas range


def test_sensitivity_refuses_swarm_keys_without_a_swarm(capsys):
    code = main(["sensitivity", "--scenario", "default", "--sensor", "radar", "--vary", "target.swarm.count=2:8"])
    assert code == 2
    assert "vary target.swarm.count" in capsys.readouterr().err


def test_coverage_refuses_a_swarm_scenario_naming_the_key_and_why(tmp_path, capsys):
    from csuas.defaults import site_path

    text = site_path("demo").read_text()
    assert 'scenario = "default"' in text
    site = tmp_path / "site.toml"
    site.write_text(text.replace('scenario = "default"', 'scenario = "swarm"'))
    assert main(["coverage", str(site), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "scenario = 'swarm' is invalid" in err and "target.swarm" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


def test_with_swarm_value_sets_a_line_formation_and_names_what_it_refuses():
    from csuas.base.errors import ParameterError
    from csuas.core.scenario import load_scenario, with_swarm_value
    from csuas.core.swarm_detection import swarm_first_detection_m

    swarm = load_scenario("swarm")
    three = with_swarm_value(swarm, "target.swarm.count", 3.0)
    np.testing.assert_array_equal(three.swarm.offsets_m[:, 1], [-5.0, 0.0, 5.0])  # 5 m kept, centred
    wide = with_swarm_value(swarm, "target.swarm.spacing_m", 2.0)
    np.testing.assert_array_equal(wide.swarm.offsets_m[:, 1], [-3.0, -1.0, 1.0, 3.0])
    assert swarm_first_detection_m(three, "radar") == pytest.approx(RADAR_ONE_M * 3**0.25, rel=1e-6)
    with pytest.raises(ParameterError) as info:
        with_swarm_value(swarm, "target.swarm.count", 101, "axes.target.swarm.count.0")
    assert info.value.name == "axes.target.swarm.count.0" and "2 to 100" in str(info.value)
    offsets = load_scenario("swarm")
    offsets.swarm = type(swarm.swarm)(swarm.swarm.offsets_m, "offsets")
    with pytest.raises(ParameterError, match="offsets_m"):
        with_swarm_value(offsets, "target.swarm.spacing_m", 1.0)


def test_the_rcs_job_of_a_swarm_scenario_names_its_one_drone(tmp_path, capsys):
    spec = tmp_path / "rcs.toml"
    spec.write_text('job = "rcs"\nscenario = "swarm"\n[axes]\nfrequency_ghz = [10.0]\n')
    assert main(["sweep", str(spec), "--out", str(tmp_path / "out"), "--scheduler", "serial"]) == 2
    assert "options.target" in capsys.readouterr().err
    parse_spec(
        {"job": "rcs", "scenario": "swarm", "axes": {"frequency_ghz": [10.0]}, "options": {"target": "dji_mini_4_pro"}}
    )


def test_the_render_job_takes_swarm_axes():
    spec = parse_spec(
        {
            "job": "render",
            "scenario": "swarm",
            "axes": {"target.swarm.spacing_m": [1.0, 2.0]},
            "options": {"range_m": 100.0},
        }
    )
    from csuas.sweep.jobs import with_values

    point = with_values(spec.scenario, {k: v[1] for k, v in spec.points(0, 2).items()})
    np.testing.assert_array_equal(point.swarm.offsets_m[:, 1], [-3.0, -1.0, 1.0, 3.0])


def test_a_swarm_sweep_estimate_counts_its_pairs_of_drones():
    from csuas.sweep.cost import largest_swarm, sweep_estimate
    from csuas.sweep.kinds import JOB_KINDS, SWARM_SECONDS_PER_PAIR_SENSOR

    data = {"job": "range", "scenario": "swarm", "axes": {"target.swarm.count": [2, 8]}}
    assert largest_swarm(data, 4) == 8 and largest_swarm({"axes": {"target.swarm.count": {"max": 12}}}, 4) == 12
    plain = sweep_estimate(data, {"target.swarm.count": 2}, 6, "serial", None)
    swarm = sweep_estimate(data, {"target.swarm.count": 2}, 6, "serial", None, swarm_count=8)
    # 2 points x 6 sensors x 28 pairs (8 drones) x 1.2 ms
    assert swarm.seconds - plain.seconds == pytest.approx(2 * 6 * 28 * SWARM_SECONDS_PER_PAIR_SENSOR, rel=1e-12)
    assert JOB_KINDS["range"].cost.point_seconds(6, 6) > 1e3 * JOB_KINDS["range"].cost.point_seconds(6)
