"""``csuas sweep``: the same results on every scheduler, after a killed worker and after a killed client.

References: each point evaluated on its own through the scenario loader (independent of the
sweep's vectorised grouping); the serial run as the reference of the distributed ones.
"""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest
from waiting import PATIENCE_S, wait_until

from csuas.cli import main
from csuas.core.ranges import evaluate
from csuas.core.scenario import parse_scenario
from csuas.sweep import parse_spec, read_results, run_sweep
from csuas.sweep.jobs import point_seed

VENV_BIN = Path(sys.executable).parent

RANGE_SPEC = {
    "job": "range",
    "scenario": "default",
    "seed": 7,
    "axes": {
        "target.d_crit_m": [0.05, 0.101],
        "environment.rain_rate_mm_h": {"min": 0.0, "max": 50.0, "samples": 5},
        "environment.lwc_g_m3": [0.0, 0.3],
        "environment.wind_speed_m_s": [0.5, 8.0],
        "sensors.radar.p_tx_w": [1.0, 100.0],
        "sensors.eo.p_desired": [0.5, 0.8],
        "sensors.acoustic.n_micro": [16, 128],
    },
}
PD_SPEC = {
    "job": "pd",
    "scenario": "default",
    "seed": 3,
    "chunk_points": 1,
    "axes": {"sensors.radar.p_tx_w": [1.0, 3.0, 10.0, 30.0, 100.0, 300.0], "sensors.radar.swerling": [0, 1, 3]},
}


def _same(a: dict, b: dict) -> bool:
    """Equal results, floats to 1e-12 relative: a process's BLAS threads change the order of the sums of a
    linear solve (the thin-wire method of moments of a drone's wiring) by a few ulps, nothing more."""
    keys = [k for k in a if k != "time_s"]
    return keys == [k for k in b if k != "time_s"] and all(
        np.allclose(a[k], b[k], rtol=1e-12, atol=0.0, equal_nan=True)
        if a[k].dtype.kind == "f"
        else np.array_equal(a[k], b[k])
        for k in keys
    )


def _scenario_toml_data():
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib

    from csuas.defaults import scenario_path

    return tomllib.loads(scenario_path("default").read_text())


def test_vectorised_range_equals_each_point_through_the_scenario_loader(tmp_path):
    spec = parse_spec(RANGE_SPEC)
    results = read_results(run_sweep(spec, tmp_path, "serial", progress=None)["results"])
    assert len(results["point"]) == spec.n_points == 2 * 5 * 2 * 2 * 2 * 2 * 2
    base = _scenario_toml_data()
    rng = np.random.default_rng(11)
    for i in rng.choice(spec.n_points, 40, replace=False):
        data = {k: (dict(v) if isinstance(v, dict) else v) for k, v in base.items()}
        data["target"], data["environment"] = dict(base["target"]), dict(base["environment"])
        data["sensors"] = {k: dict(v) for k, v in base["sensors"].items()}
        for key in RANGE_SPEC["axes"]:
            parts, value = key.split("."), results[key][i]
            value = int(value) if key.endswith("n_micro") else float(value)
            if parts[0] == "sensors":
                data["sensors"][parts[1]][parts[2]] = value
            else:
                data[parts[0]][parts[1]] = value
        expected = evaluate(parse_scenario(data, "point"))
        for name, result in expected.items():
            assert results[f"range_m.{name}"][i] == pytest.approx(float(result.range_m), rel=1e-12), (name, i)


def test_serial_and_local_cluster_give_identical_tables(tmp_path):
    spec = parse_spec({**RANGE_SPEC, "chunk_points": 50})
    serial = read_results(run_sweep(spec, tmp_path / "serial", "serial", progress=None)["results"])
    out = run_sweep(spec, tmp_path / "local", "local", workers=2, progress=None)
    assert out["workers"] == 2 and out["chunks"] == 7
    assert _same(serial, read_results(out["results"]))


def _chunks(out_dir) -> int:
    """Chunks a sweep has written so far."""
    return len(list((out_dir / "chunks").glob("chunk-*.parquet")))


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def dask_cluster(tmp_path):
    """README's recipe: a scheduler and two one-thread workers started from the shell."""
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    scheduler = subprocess.Popen(
        [VENV_BIN / "dask", "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, cwd=tmp_path,
    )  # fmt: skip
    workers = subprocess.Popen(
        [VENV_BIN / "dask", "worker", address, "--nworkers", "2", "--nthreads", "1", "--no-dashboard"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, cwd=tmp_path,
    )  # fmt: skip
    from distributed import Client

    with Client(address, timeout=PATIENCE_S) as client:
        client.wait_for_workers(2, timeout=PATIENCE_S)
    yield address
    for p in (workers, scheduler):  # workers first: with their scheduler gone they wait for it before leaving
        p.terminate()
        try:
            p.wait(timeout=20)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()


@pytest.mark.slow
def test_a_tcp_cluster_gives_the_serial_table_even_when_a_worker_is_killed(tmp_path, dask_cluster):
    from distributed import Client

    address = dask_cluster
    with Client(address, timeout=PATIENCE_S) as client:
        worker_pids = sorted(client.run(os.getpid).values())
    spec = parse_spec(PD_SPEC)
    serial = read_results(run_sweep(spec, tmp_path / "serial", "serial", progress=None)["results"])
    out_dir = tmp_path / "tcp"
    holder = {}
    thread = threading.Thread(target=lambda: holder.update(out=run_sweep(spec, out_dir, address, progress=None)))
    thread.start()
    wait_until(lambda: _chunks(out_dir) >= 3 or not thread.is_alive(), "3 chunks written")
    assert thread.is_alive(), "the sweep ended before a worker could be killed mid-sweep"
    os.kill(worker_pids[0], signal.SIGKILL)  # a worker process dies mid-sweep; its nanny starts another
    thread.join(timeout=PATIENCE_S)
    assert "out" in holder and holder["out"]["scheduler"] == address
    assert _same(serial, read_results(holder["out"]["results"]))


@pytest.mark.slow
def test_a_killed_client_resumes_without_redoing_chunks(tmp_path):
    spec_file = tmp_path / "pd.toml"
    spec_file.write_text(
        'job = "pd"\nscenario = "default"\nseed = 3\nchunk_points = 1\n[axes]\n'
        '"sensors.radar.p_tx_w" = [1.0, 3.0, 10.0, 30.0, 100.0, 300.0]\n"sensors.radar.swerling" = [0, 1, 3]\n'
    )
    out_dir = tmp_path / "out"
    command = [VENV_BIN / "csuas", "sweep", str(spec_file), "--out", str(out_dir), "--scheduler", "serial"]
    proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wait_until(lambda: _chunks(out_dir) >= 4, "4 chunks written", proc)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    done_before = _chunks(out_dir)
    assert 4 <= done_before < 18 and not (out_dir / "results.parquet").exists()
    resumed = run_sweep(parse_spec(PD_SPEC), out_dir, "serial", progress=None)
    assert resumed["chunks_resumed"] == done_before and resumed["chunks_run"] == 18 - done_before
    reference = run_sweep(parse_spec(PD_SPEC), tmp_path / "clean", "serial", progress=None)
    assert _same(read_results(reference["results"]), read_results(resumed["results"]))


@pytest.mark.slow
def test_simulator_workers_are_recycled_after_their_tasks(tmp_path):
    spec = parse_spec(
        {"job": "rcs", "seed": 1, "chunk_points": 2, "recycle_after": 1, "options": {"quality": "draft"},
         "axes": {"frequency_ghz": [9.4], "azimuth_deg": [0.0, 30.0, 60.0, 90.0, 120.0, 150.0]}}
    )  # fmt: skip
    serial = read_results(run_sweep(spec, tmp_path / "serial", "serial", progress=None)["results"])
    out = run_sweep(spec, tmp_path / "local", "local", workers=1, progress=None)
    assert out["chunks"] == 3 and out["worker_processes"] == 3  # a fresh process after every task
    assert _same(serial, read_results(out["results"]))


def test_point_seeds_depend_on_the_seed_and_index_only():
    a, b = point_seed(7, [0, 1, 2]), point_seed(7, [2, 1, 0])
    assert a.tolist() == b[::-1].tolist() and len(set(a.tolist())) == 3
    assert point_seed(8, [0])[0] != a[0]


@pytest.mark.parametrize(
    "toml, fragment",
    [
        ('job = "range"\n[axes]\n"target.size_m" = [1.0]\n', "axes"),
        ('job = "range"\n[axes]\n"target.d_crit_m" = []\n', "axes.target.d_crit_m"),
        ('job = "rcs"\n[axes]\nfrequency_ghz = [10.0]\n"target.d_crit_m" = [0.1]\n', "job rcs takes only"),
        ('job = "range"\n[axes]\nrange_m = [100.0]\n', "axes"),
        ('job = "range"\n[axes]\n"target.d_crit_m" = {min = 1.0, max = 0.5, samples = 3}\n', "axes.target.d_crit_m"),
        ('job = "teleport"\n', "job"),
        ('job = "range"\ncombine = "zip"\n[axes]\n"target.d_crit_m" = [0.1, 0.2]\n"target.sl_db" = [70.0]\n', "zip"),
    ],
)
def test_bad_spec_exits_2_with_one_line(tmp_path, capsys, toml, fragment):
    spec = tmp_path / "bad.toml"
    spec.write_text(toml)
    assert main(["sweep", str(spec), "--out", str(tmp_path / "out"), "--scheduler", "serial"]) == 2
    err = capsys.readouterr().err
    assert fragment in err and "Traceback" not in err


def test_an_unreachable_scheduler_exits_2(tmp_path, capsys):
    port = _free_port()
    code = main(["sweep", "range_rain", "--out", str(tmp_path / "o"), "--scheduler", f"tcp://127.0.0.1:{port}"])
    assert code == 2 and "scheduler" in capsys.readouterr().err


def test_a_folder_of_another_sweep_is_refused(tmp_path, capsys):
    assert main(["sweep", "range_rain", "--out", str(tmp_path), "--scheduler", "serial"]) == 0
    assert main(["sweep", "pd_radar_power", "--out", str(tmp_path), "--scheduler", "serial"]) == 2
    assert "another sweep" in capsys.readouterr().err


@pytest.mark.parametrize("name", ["range_rain", "pd_radar_power", "rcs_bands", "render_ranges"])
def test_every_embedded_spec_parses(name):
    from csuas.sweep import load_spec

    spec = load_spec(name)
    assert spec.n_points >= 9 and spec.digest
