"""The ``engage`` sweep job: runs of ``csuas engage`` as chunks, the same whatever the chunking, resumed by chunk.

A short approach (640 m, 43 looks a sensor, no birds) keeps a run under a second; the reference for each
row is the engagement simulator called directly for the same run index (``run_once``), not the sweep.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.cli import main
from csuas.defaults import engagement_path
from csuas.render.engagement.build import load_engagement
from csuas.render.engagement.simulate import CAUSES, run_once
from csuas.sweep import parse_spec, read_results, run_sweep

LONG_APPROACH = "waypoints = [[504000.0, 5002700.0, 30.0], [506600.0, 5003150.0, 30.0], [505000.0, 5005000.0, 30.0]]"
SHORT_APPROACH = "waypoints = [[505400.0, 5004500.0, 30.0], [505000.0, 5005000.0, 30.0]]"
RUNS = 3


@pytest.fixture(scope="module")
def engagement_file(tmp_path_factory):
    text = engagement_path("example").read_text(encoding="utf-8")
    assert LONG_APPROACH in text and "birds_per_km2 = 2.0" in text
    text = text.replace(LONG_APPROACH, SHORT_APPROACH).replace("birds_per_km2 = 2.0", "birds_per_km2 = 0.0")
    path = tmp_path_factory.mktemp("engage") / "short.toml"
    path.write_text(text.replace("runs = 50", f"runs = {RUNS}"), encoding="utf-8")
    return path


def _sweep(engagement_file, chunk_points: int) -> dict:
    return {"job": "engage", "chunk_points": chunk_points, "options": {"engagement": str(engagement_file)}}


def _run(spec_data: dict, out) -> dict:
    return run_sweep(parse_spec(spec_data), out, scheduler="serial", progress=None)


def test_two_chunks_equal_one_chunk_and_the_simulator_run_by_run(engagement_file, tmp_path):
    two = _run(_sweep(engagement_file, 2), tmp_path / "two")
    one = _run(_sweep(engagement_file, RUNS), tmp_path / "one")
    assert (two["chunks"], one["chunks"], two["points"]) == (2, 1, RUNS)
    a, b = read_results(two["results"]), read_results(one["results"])
    assert list(a) == list(b)
    for column in a:
        if column != "time_s":
            np.testing.assert_array_equal(a[column], b[column], err_msg=column)
    _, engagement = load_engagement(str(engagement_file))
    for i in range(RUNS):  # the simulator itself, run i seeded by the spec's seed and i
        record = run_once(engagement, i)
        assert a["point"][i] == i
        for key in ("first_track_time_s", "first_track_range_m", "warning_time_s", "gospa_mean"):
            expected = math.nan if record[key] is None else record[key]
            np.testing.assert_equal(a[key][i], expected, err_msg=key)
        for cause in CAUSES:
            found = sum(track["cause"] == cause for track in record["false_tracks"])
            assert a[f"false_tracks.{cause}"][i] == found
        for sensor, counts in record["false_alarms"].items():
            assert a[f"false_alarms.{sensor}.noise"][i] == counts["noise"]
            assert a[f"false_alarms.{sensor}.clutter"][i] == counts["clutter"]
    assert len(set(a["false_alarms.eo.noise"])) > 1  # the runs differ: each has its own draws


def test_resume_recomputes_only_the_deleted_chunk(engagement_file, tmp_path):
    out = tmp_path / "out"
    first = _run(_sweep(engagement_file, 2), out)
    kept = out / "chunks" / "chunk-000000.parquet"
    kept_mtime = kept.stat().st_mtime_ns
    before = read_results(first["results"])
    (out / "chunks" / "chunk-000001.parquet").unlink()
    again = _run(_sweep(engagement_file, 2), out)
    assert (again["chunks_run"], again["chunks_resumed"]) == (1, 1)
    assert kept.stat().st_mtime_ns == kept_mtime
    after = read_results(again["results"])
    for column in before:
        if column != "time_s":
            np.testing.assert_array_equal(before[column], after[column], err_msg=column)
    assert json.loads((out / "sweep.json").read_text())["chunks_run"] == 1


def test_engage_takes_no_axes_and_an_unknown_job_names_the_jobs(engagement_file):
    data = _sweep(engagement_file, 2) | {"axes": {"target.d_crit_m": [0.1]}}
    with pytest.raises(ParameterError, match="job engage takes no axes"):
        parse_spec(data)
    with pytest.raises(ParameterError) as unknown:
        parse_spec({"job": "engagement"})
    assert unknown.value.name == "job"
    assert "range, pd, render, rcs, engage" in str(unknown.value)


def test_the_cost_estimate_counts_the_runs_before_any_run(engagement_file, tmp_path, capsys):
    spec = tmp_path / "many.toml"
    spec.write_text(f'job = "engage"\n[options]\nengagement = "{engagement_file}"\nruns = 1000\n', encoding="utf-8")
    out = tmp_path / "out"
    assert main(["sweep", str(spec), "--out", str(out), "--scheduler", "serial", "--max-seconds", "600"]) == 2
    err = capsys.readouterr().err
    assert "an engage sweep of 1,000 runs" in err and "--max-seconds" in err, err
    assert not out.exists()
