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
    assert sorted(p.name for p in out.iterdir() if p.name != lock) in ([], ["chunks"], ["images", "labels", "records"])


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
