"""Sweeps that scale (issue 25, section 4): chunks sized from points and workers, each worker warmed once a job,
and the ``reason`` and ``notes`` of every point as ``csuas range`` reports them."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from waiting import wait_until

from csuas.cli import main
from csuas.core.range_notes import DEFAULT_RADAR_NOTE, sensor_notes
from csuas.sweep import parse_spec, read_results, run_sweep
from csuas.sweep.chunking import (
    OVERHEAD_SHARE,
    TASK_OVERHEAD_S,
    TASKS_PER_WORKER,
    chunk_points_for,
    lowest_chunk_points,
)
from csuas.sweep.warm import plugin_name, wait_warm

DEFAULT_SCENARIO = Path(__file__).resolve().parents[1] / "defaults" / "scenarios" / "default.toml"


@pytest.mark.parametrize(
    "n, workers, lowest, highest, chunk",
    [
        (5, 1, 1, 2, 2),  # 4 tasks of ceil(5/4) = 2, capped at 2: 3 chunks
        (12, 2, 9, 32, 6),  # too few points for 9 a task: one task a worker, 6 each
        (1000, 2, 1, 16, 16),  # 4 tasks a worker would be 125 points: capped at the job's 16
        (1000, 2, 1, 500, 125),  # 8 tasks of 125
        (360, 2, 95_239, 1_000_000, 180),  # a small range sweep: one task a worker
        (3, 4, 1, 10, 1),  # fewer points than workers: one point a task
        (100, 2, 10, 100, 13),  # floor(100 / 20) = 5 tasks a worker, at most 4: 8 tasks of ceil(12.5)
        (10**6, 2, 95_239, 10**6, 125_000),  # floor(10^6 / 190478) = 5 -> 4 a worker: 8 tasks of 125000
    ],
)
def test_chunk_points_follow_the_closed_form(n, workers, lowest, highest, chunk):
    assert TASKS_PER_WORKER == 4  # the cases above are worked for 4 tasks a worker
    assert chunk_points_for(n, workers, lowest, highest) == chunk


def test_the_lowest_chunk_hides_the_task_overhead_behind_the_cost_model():
    pd = parse_spec({"job": "pd", "axes": {"target.d_crit_m": [0.1, 0.2]}})
    # pd: 46 ms a point and sensor, 6 sensors of the default scenario: 0.28 s a point
    assert lowest_chunk_points(pd) == math.ceil(TASK_OVERHEAD_S / (OVERHEAD_SHARE * 46e-3 * 6))
    rcs = parse_spec({"job": "rcs", "axes": {"frequency_ghz": [9.4]}})
    assert lowest_chunk_points(rcs) == 1  # cost known only once traced: one point


def test_a_sweep_without_chunk_points_records_its_chunks_and_a_resumed_one_keeps_them(tmp_path):
    data = {"job": "range", "axes": {"target.d_crit_m": [0.05, 0.1, 0.15, 0.2, 0.25]}}
    first = run_sweep(parse_spec(data), tmp_path / "new", "serial", progress=None)
    # range: lowest ~10^5 points, so 5 points on one worker are one task
    assert (first["chunk_points"], first["chunks"]) == (5, 1)
    state = json.loads((tmp_path / "new" / "sweep-state.json").read_text())
    assert state["chunk_points"] == 5
    old = tmp_path / "old"
    old.mkdir()
    spec = parse_spec(data)
    (old / "sweep-state.json").write_text(json.dumps({"digest": spec.digest, "chunk_points": 2}))
    resumed = run_sweep(spec, old, "serial", progress=None)
    assert (resumed["chunk_points"], resumed["chunks"]) == (2, 3)
    np.testing.assert_array_equal(read_results(resumed["results"])["point"], np.arange(5))
    explicit = run_sweep(parse_spec({**data, "chunk_points": 1}), tmp_path / "explicit", "serial", progress=None)
    assert explicit["chunks"] == 5  # a spec's own chunk_points is kept as it is


def test_the_warm_up_plugin_runs_once_per_worker_across_sweeps(tmp_path):
    from distributed import Client, LocalCluster

    data = {"job": "range", "chunk_points": 1, "axes": {"target.d_crit_m": [0.05, 0.1, 0.15, 0.2]}}
    with (
        LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                     silence_logs=40) as cluster,
        Client(cluster.scheduler_address) as client,
    ):  # fmt: skip
        wait_until(lambda: len(client.scheduler_info()["workers"]) == 2, "two workers")
        assert sorted(client.run(wait_warm, "range").values()) == [0, 0]
        for name in ("one", "two"):
            out = run_sweep(parse_spec(data), tmp_path / name, cluster.scheduler_address, progress=None)
            assert out["workers"] == 2
            assert sorted(client.run(wait_warm, "range").values()) == [1, 1]  # each worker once, not once a sweep
        plugins = client.run(lambda dask_worker: sorted(dask_worker.plugins))
    assert not any(plugin_name("range") in names for names in plugins.values())  # unregistered once all are warm


def _scenario_file(folder: Path, values: dict) -> Path:
    """The default scenario with ``values`` (``section.key`` or ``sensors.NAME.key``) written into it."""
    text = DEFAULT_SCENARIO.read_text()
    for key, value in values.items():
        section, _, name = key.rpartition(".")
        text = text.replace(f"[{section}]\n", f"[{section}]\n{name} = {value!r}\n", 1)
    path = folder / f"scenario-{len(list(folder.glob('scenario-*')))}.toml"
    path.write_text(text)
    return path


def _range_json(scenario: Path, capsys) -> dict:
    capsys.readouterr()
    assert main(["range", str(scenario), "--json"]) == 0
    return json.loads(capsys.readouterr().out)["sensors"]


@pytest.mark.parametrize("job", ["range", "pd"])
def test_reason_and_notes_columns_match_csuas_range(job, tmp_path, capsys):
    axes = {
        "target.altitude_m": [0.0, 500.0, 0.0, 30.0],  # 500 m: above some slant ranges (never within range)
        "environment.rain_rate_mm_h": [0.0, 4.0, 50.0, 0.0],
        "sensors.lidar.p_tx_w": [1e-9, 1.0, 10.0, 1e-12],  # a lidar that runs out of budget before 1 m
    }
    spec = parse_spec({"job": job, "combine": "zip", "chunk_points": 3, "axes": axes})
    table = read_results(run_sweep(spec, tmp_path / "out", "serial", progress=None)["results"])
    reasons_seen = set()
    for i in range(4):
        point = {key: values[i] for key, values in axes.items()}
        sensors = _range_json(_scenario_file(tmp_path, point), capsys)
        for name, entry in sensors.items():
            assert table[f"reason.{name}"][i] == (entry.get("reason") or ""), (i, name)
            assert table[f"notes.{name}"][i] == "\n".join(entry["notes"]), (i, name)
            reasons_seen.add(table[f"reason.{name}"][i])
    assert any("range below 1 m" in r for r in reasons_seen) and any("never within range" in r for r in reasons_seen)
    assert set(table["notes.radar"]) == {DEFAULT_RADAR_NOTE}  # the radar's budget is the preset's at every point


def test_the_default_radar_note_goes_once_its_budget_is_set():
    assert sensor_notes("radar", "default", set()) == [DEFAULT_RADAR_NOTE]
    assert sensor_notes("radar", "default", {"p_tx_w"}) == []
    assert sensor_notes("radar", "paper_section_4_9", set()) == []
    assert sensor_notes("eo", "default", set()) == []
