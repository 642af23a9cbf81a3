"""Faults that used to lose time or hang (issue 22, section 4): unreadable resume files, a second run
into the same folder, a cluster whose workers all died, an interrupt at start-up, a TLS scheduler."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from waiting import wait_until

from csuas import cli
from csuas.base.fileio import exclusive_lock

CSUAS = [sys.executable, "-m", "csuas.cli"]


def _run(argv, capsys) -> tuple[int, list[str], str]:
    code = cli.main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.err.strip().splitlines(), captured.out


def _dataset_spec(tmp_path: Path, count: int = 2) -> Path:
    scenario = tmp_path / "small.toml"
    scenario.write_text(
        'name = "small"\n[target]\npreset = "dji_mini_4_pro"\n[sensors.eo]\nmodality = "eo"\nn_h = 64\nn_v = 48\n',
        encoding="utf-8",
    )
    spec = tmp_path / "spec.toml"
    spec.write_text(
        f'seed = 1\ncount = {count}\nscenario = "{scenario}"\ndrones = ["dji_mini_4_pro"]\nrange_m = [150.0]\n',
        encoding="utf-8",
    )
    return spec


def _sweep_spec(tmp_path: Path) -> Path:
    spec = tmp_path / "sweep.toml"
    spec.write_text(
        'job = "range"\nscenario = "default"\nchunk_points = 1\n[axes]\n"target.d_crit_m" = [0.1, 0.2, 0.3]\n',
        encoding="utf-8",
    )
    return spec


def _without_times(table):
    """A results table without its ``time_s`` column (wall time differs between runs; nothing else may)."""
    return table.drop_columns(["time_s"])


def _site(tmp_path: Path) -> Path:
    site = tmp_path / "site.toml"
    site.write_text("altitudes_agl_m = [30.0]\n[sensors.eo]\nx = 505000.0\ny = 5005000.0\n", encoding="utf-8")
    return site


# --- two runs into one folder -------------------------------------------------------------------------

#: Command -> (argv builder, its lock file in the output folder).
LOCKED = {
    "dataset": (lambda t, out: ["dataset", _dataset_spec(t), "--out", out], ".csuas-dataset.lock"),
    "sweep": (lambda t, out: ["sweep", _sweep_spec(t), "--scheduler", "serial", "--out", out], ".csuas-sweep.lock"),
    "coverage": (lambda t, out: ["coverage", _site(t), "--out", out], ".csuas-coverage.lock"),
}


@pytest.mark.parametrize("command", sorted(LOCKED))
def test_a_second_run_into_the_same_folder_is_refused(command, tmp_path, capsys):
    make_argv, lock = LOCKED[command]
    out = tmp_path / "out"
    out.mkdir()
    with exclusive_lock(out / lock, "--out"):  # the first run, still writing
        code, err, _ = _run(make_argv(tmp_path, out), capsys)
    assert code == 2, err
    assert len(err) == 1 and "no other csuas run is writing into" in err[0], err
    made = sorted(p.name for p in out.iterdir() if p.name != lock)
    assert made in ([], ["chunks"], ["images", "labels", "records"], ["images", "labels", "previews", "records"])


# --- resume over damaged files ------------------------------------------------------------------------


@pytest.mark.parametrize("damage", [b"garbage{", b"", b'{"image": 3}', b"\xff\xfe not utf-8"])
def test_a_dataset_resumes_over_an_unreadable_record_by_redoing_its_image(damage, tmp_path, capsys):
    spec, out = _dataset_spec(tmp_path), tmp_path / "out"
    code, err, _ = _run(["dataset", spec, "--out", out, "--json"], capsys)
    assert code == 0, err
    first = {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file() and "lock" not in p.name}
    records = sorted((out / "records").iterdir())
    records[0].write_bytes(damage)
    code, err, text = _run(["dataset", spec, "--out", out, "--json"], capsys)
    assert code == 0, err
    summary = json.loads(text)
    assert summary["redone"] == [records[0].stem] and summary["rendered"] == 1 and summary["resumed"] == 1
    assert any("warning" in line and records[0].name in line and "redone" in line for line in err)
    again = {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file() and "lock" not in p.name}
    assert again == first  # the redone image is the same bytes: image i draws from [seed, i]


def test_a_dataset_record_whose_image_is_gone_is_redone(tmp_path, capsys):
    spec, out = _dataset_spec(tmp_path, count=1), tmp_path / "out"
    assert _run(["dataset", spec, "--out", out], capsys)[0] == 0
    image = next((out / "images").iterdir())
    first = image.read_bytes()
    image.unlink()
    code, err, text = _run(["dataset", spec, "--out", out, "--json"], capsys)
    assert code == 0, err
    assert json.loads(text)["redone"] == [image.stem] and image.read_bytes() == first


@pytest.mark.parametrize("damage", [b"garbage", b"", b"PAR1" + b"\0" * 64 + b"PAR1"])
def test_a_sweep_resumes_over_an_unreadable_chunk_by_running_it_again(damage, tmp_path, capsys):
    import pyarrow.parquet as pq

    spec, out = _sweep_spec(tmp_path), tmp_path / "out"
    argv = ["sweep", spec, "--scheduler", "serial", "--out", out, "--json"]
    code, err, _ = _run(argv, capsys)
    assert code == 0, err
    first = pq.read_table(out / "results.parquet")
    (out / "chunks" / "chunk-000001.parquet").write_bytes(damage)
    code, err, text = _run(argv, capsys)
    assert code == 0, err
    provenance = json.loads(text)
    assert provenance["chunks_redone"] == [1] and provenance["chunks_run"] == 1 and provenance["chunks_resumed"] == 2
    assert any("warning" in line and "chunk-000001.parquet" in line for line in err)
    assert _without_times(pq.read_table(out / "results.parquet")).equals(_without_times(first))


def test_a_chunk_with_the_wrong_number_of_rows_is_run_again(tmp_path, capsys):
    import pyarrow as pa
    import pyarrow.parquet as pq

    spec, out = _sweep_spec(tmp_path), tmp_path / "out"
    argv = ["sweep", spec, "--scheduler", "serial", "--out", out, "--json"]
    assert _run(argv, capsys)[0] == 0
    first = pq.read_table(out / "results.parquet")
    one = pq.read_table(out / "chunks" / "chunk-000000.parquet")  # a file from elsewhere, copied in by hand
    pq.write_table(pa.concat_tables([one, one, one]), out / "chunks" / "chunk-000002.parquet")
    code, err, text = _run(argv, capsys)
    assert code == 0, err
    assert json.loads(text)["chunks_redone"] == [2]
    assert _without_times(pq.read_table(out / "results.parquet")).equals(_without_times(first))


# --- an interrupt at start-up -------------------------------------------------------------------------


def test_an_interrupt_while_the_command_loads_ends_the_run_with_130(monkeypatch, capsys, tmp_path):
    """SIGINT before the command runs (its module loading, its arguments parsed) is an interrupt, not a traceback."""
    real = cli.build_parser

    def interrupted_while_loading(command=None):
        os.kill(os.getpid(), signal.SIGINT)
        return real(command)

    monkeypatch.setattr(cli, "build_parser", interrupted_while_loading)
    out = tmp_path / "out"
    code = cli.main(["render", "eo", "default", "--range-m", "100", "--quality", "draft", "--out", str(out)])
    assert code == 130
    assert capsys.readouterr().err.strip().splitlines() == ["csuas render: interrupted"]
    assert not out.exists()


def _swallowed(sig: int) -> None:
    """An interrupt that a C extension swallowed: recorded by csuas's handler, its exception gone."""
    with pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), sig)
        time.sleep(5.0)  # the handler raises at the next bytecode; this never completes
    # (here a C extension would have dropped the exception; csuas still holds the signal)


def test_a_swallowed_interrupt_ends_the_run_at_the_next_module_load_and_is_then_forgotten():
    from csuas.base.interrupts import handling_interrupts, raise_if_interrupted
    from csuas.base.registry import resolve

    with handling_interrupts():
        _swallowed(signal.SIGTERM)
        with pytest.raises(KeyboardInterrupt):
            resolve("csuas.base.paths:inside")  # a checkpoint: every registry import
    raise_if_interrupted()  # outside the block: nothing left to raise in later library calls


def _handlers_installed(pid: int) -> bool:
    """True once the process catches SIGTERM: csuas's interrupt handlers are in place (Python's own never catch it)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except FileNotFoundError:
        return True  # already ended: the caller's wait() tells how
    caught = int(next(line.split()[1] for line in status.splitlines() if line.startswith("SigCgt:")), 16)
    return bool(caught & (1 << (signal.SIGTERM - 1)))


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads the process's signal mask from /proc")
def test_sigint_as_soon_as_a_render_starts_is_never_lost(tmp_path):
    out = tmp_path / "out"
    argv = ["render", "eo", "default", "--range-m", "100", "--quality", "draft", "--out", str(out), "--quiet"]
    proc = subprocess.Popen(CSUAS + argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120.0
    while not _handlers_installed(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.001)  # polling /proc for the handlers: the signal goes at the first moment csuas can take it
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 130, err.decode()
    assert err.decode().strip().splitlines()[-1] == "csuas render: interrupted"
    assert not out.exists() or not any(out.iterdir())


# --- a cluster whose workers all died -----------------------------------------------------------------

VENV_BIN = Path(sys.executable).parent


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _worker(address: str, cwd: Path) -> subprocess.Popen:
    """One Dask worker process without a nanny: killed, nothing replaces it."""
    return subprocess.Popen(
        [VENV_BIN / "dask", "worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=cwd,
    )  # fmt: skip


@pytest.mark.slow
def test_a_sweep_whose_workers_all_died_stops_after_the_timeout_and_resumes(tmp_path):
    from distributed import Client

    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    scheduler = subprocess.Popen(
        [VENV_BIN / "dask", "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=tmp_path,
    )  # fmt: skip
    workers = [_worker(address, tmp_path)]
    try:
        with Client(address, timeout=60) as client:
            client.wait_for_workers(1, timeout=120)
        spec = tmp_path / "many.toml"
        spec.write_text(
            'job = "range"\nscenario = "default"\nchunk_points = 1\n[axes]\n'
            '"target.d_crit_m" = {min = 0.05, max = 0.5, samples = 200}\n',
            encoding="utf-8",
        )
        out = tmp_path / "out"
        argv = CSUAS + ["sweep", str(spec), "--scheduler", address, "--no-worker-timeout-s", "2", "--out", str(out)]
        chunks = lambda: list((out / "chunks").glob("chunk-*.parquet"))
        sweep = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        wait_until(lambda: len(chunks()) >= 2, "two chunks written", sweep, timeout_s=120.0)
        workers[0].kill()  # every worker of the cluster is gone, mid-sweep
        workers[0].wait()
        _, err = sweep.communicate(timeout=120)  # used to wait forever
        lines = err.decode().strip().splitlines()
        assert sweep.returncode == 2, lines
        # Dask may log its client's shutdown ("distributed.client.AllExit") after csuas's line
        assert any("no Dask worker for 2 s" in line and "run the same command again" in line for line in lines), lines
        written = len(chunks())
        assert 2 <= written < 200 and not (out / "results.parquet").exists()
        workers.append(_worker(address, tmp_path))
        resumed = subprocess.run(argv + ["--json"], capture_output=True, timeout=600)
        assert resumed.returncode == 0, resumed.stderr.decode()
        provenance = json.loads(resumed.stdout)
        assert provenance["chunks_resumed"] == written and provenance["chunks_run"] == 200 - written
        import pyarrow.parquet as pq

        assert pq.read_table(out / "results.parquet").num_rows == 200
    finally:
        for p in (*workers, scheduler):
            p.kill()
            p.wait()


def test_the_no_worker_timeout_is_checked_before_any_work(tmp_path, capsys):
    argv = ["sweep", "range_rain", "--scheduler", "serial", "--no-worker-timeout-s", "0", "--out", tmp_path / "o"]
    code, err, _ = _run(argv, capsys)
    assert code == 2 and len(err) == 1 and "no_worker_timeout_s = 0.0" in err[0]
    assert not (tmp_path / "o").exists()


# --- a TLS scheduler ----------------------------------------------------------------------------------


@pytest.fixture
def tls_files(tmp_path):
    """A throwaway self-signed certificate for 127.0.0.1 (openssl; no network), as CA, server and client."""
    import shutil

    if shutil.which("openssl") is None:
        pytest.skip("needs the openssl command to make a throwaway certificate")
    cert, key = tmp_path / "cert.pem", tmp_path / "key.pem"
    subprocess.run(
        ["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-subj", "/CN=127.0.0.1",
         "-addext", "subjectAltName=IP:127.0.0.1", "-keyout", str(key), "-out", str(cert)],
        check=True, capture_output=True, timeout=60,
    )  # fmt: skip
    return cert, key


def test_a_sweep_runs_on_a_tls_scheduler_with_dasks_security_settings(tmp_path, capsys, tls_files):
    import dask
    from distributed import LocalCluster
    from distributed.security import Security

    cert, key = (str(p) for p in tls_files)
    security = Security(
        tls_ca_file=cert, tls_scheduler_cert=cert, tls_scheduler_key=key, tls_worker_cert=cert, tls_worker_key=key,
        tls_client_cert=cert, tls_client_key=key, require_encryption=True,
    )  # fmt: skip
    settings = {
        "distributed.comm.tls.ca-file": cert,
        "distributed.comm.tls.client.cert": cert,
        "distributed.comm.tls.client.key": key,
        "distributed.comm.require-encryption": True,
    }
    spec = _sweep_spec(tmp_path)
    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, protocol="tls://", host="127.0.0.1",
        security=security, dashboard_address=None,
    ) as cluster:  # fmt: skip
        address = cluster.scheduler_address
        assert address.startswith("tls://127.0.0.1:")
        code, err, _ = _run(["sweep", spec, "--scheduler", address, "--out", tmp_path / "bare"], capsys)
        assert code == 2 and len(err) == 1 and "distributed.comm.tls.ca-file" in err[0], err  # no settings: refused
        plain = address.replace("tls://", "tcp://")
        code, err, _ = _run(["sweep", spec, "--scheduler", plain, "--out", tmp_path / "plain"], capsys)
        assert code == 2 and len(err) == 1 and "reachable Dask scheduler" in err[0], err  # no TLS: no connection
        with dask.config.set(settings):
            code, err, text = _run(["sweep", spec, "--scheduler", address, "--out", tmp_path / "tls", "--json"], capsys)
    assert code == 0, err
    provenance = json.loads(text)
    assert provenance["scheduler"] == address and provenance["workers"] == 1 and provenance["chunks_run"] == 3
    serial = tmp_path / "serial"
    assert _run(["sweep", spec, "--scheduler", "serial", "--out", serial], capsys)[0] == 0
    import pyarrow.parquet as pq

    tls_table = pq.read_table(tmp_path / "tls" / "results.parquet")
    assert _without_times(tls_table).equals(_without_times(pq.read_table(serial / "results.parquet")))
