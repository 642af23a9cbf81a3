"""Every failure clean: one line and a meaningful exit code, interrupts that leave nothing behind."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from waiting import PATIENCE_S, wait_until

from csuas import cli
from csuas.base.errors import InputErrors, ParameterError, plain, raise_all
from csuas.base.fileio import TEMP_MARKER, atomic_path, remove_stale_temps, write_text_atomic
from csuas.base.interrupts import Terminated, deferred_interrupts, handling_interrupts, pending

CSUAS = [sys.executable, "-m", "csuas.cli"]


def _fail_with(monkeypatch, exc):
    from csuas.commands import range as range_command

    def boom(args):
        raise exc

    monkeypatch.setattr(range_command, "run", boom)


@pytest.mark.parametrize(
    "exc",
    [
        FileExistsError(17, "File exists", "out/x.exr"),
        IsADirectoryError(21, "Is a directory", "b.json"),
        PermissionError(13, "Permission denied", "s.toml"),
        NotADirectoryError(20, "Not a directory", "f/report.json"),
        RecursionError("maximum recursion depth exceeded"),
    ],
)
def test_an_operating_system_error_is_one_line_and_exit_code_2(monkeypatch, capsys, exc):
    _fail_with(monkeypatch, exc)
    assert cli.main(["range", "default"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    if isinstance(exc, OSError):
        assert exc.filename in err and exc.strerror in err


def test_an_internal_failure_is_exit_code_1_with_the_debug_hint(monkeypatch, capsys):
    _fail_with(monkeypatch, ZeroDivisionError("float division by zero"))
    assert cli.main(["range", "default"]) == 1
    err = capsys.readouterr().err
    assert "ZeroDivisionError" in err and "--debug" in err and len(err.strip().splitlines()) == 1


def test_debug_shows_the_traceback(monkeypatch):
    _fail_with(monkeypatch, ZeroDivisionError("float division by zero"))
    with pytest.raises(ZeroDivisionError):
        cli.main(["range", "default", "--debug"])


def test_several_mistakes_come_together_one_line_each(capsys):
    code = cli.main(["render", "eo", "default", "--range-m", "-1", "nan", "--seed", "-1", "--elevation-deg", "95"])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(lines) == 4 and all(line.startswith("csuas render: error: ") for line in lines)
    for option in ("range_m = -1.0", "range_m = nan", "seed = -1", "elevation_deg = 95.0"):
        assert any(option in line for line in lines), option


def test_numbers_in_messages_are_plain():
    assert plain(np.float64(95.0)) == "95.0"
    assert plain(np.int64(3)) == "3"
    assert plain(np.array([1.0, 2.0])) == "[1.0, 2.0]"
    assert "np.float64" not in str(ParameterError("x", np.float64(95.0), "x < 90"))


def test_raise_all_raises_one_or_all():
    raise_all([])
    with pytest.raises(ParameterError):
        raise_all([ParameterError("a", 1, "b")])
    with pytest.raises(InputErrors) as info:
        raise_all([ParameterError("a", 1, "b"), ParameterError("c", 2, "d")])
    assert str(info.value).splitlines() == ["a = 1 is invalid; allowed: b", "c = 2 is invalid; allowed: d"]


def test_a_stale_temporary_file_of_a_dead_process_is_removed_by_the_next_write(tmp_path):
    dead = tmp_path / f".report{TEMP_MARKER}99999999-abc.json"
    alive = tmp_path / f".report{TEMP_MARKER}{os.getpid()}-def.json"
    foreign = tmp_path / ".report.keep.json"
    for path in (dead, alive, foreign):
        path.write_text("{}")
    write_text_atomic(tmp_path / "report.json", "{}")
    assert not dead.exists() and alive.exists() and foreign.exists()
    assert remove_stale_temps(tmp_path) == []


def test_sigkill_mid_write_leaves_a_temp_that_the_next_write_removes(tmp_path):
    code = (
        "import sys, time; from csuas.base.fileio import atomic_path\n"
        f"with atomic_path({str(tmp_path / 'a.exr')!r}) as tmp:\n"
        "    tmp.write_bytes(b'half'); print('ready', flush=True); time.sleep(60)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "ready"
    proc.kill()
    proc.wait()
    left = [p for p in tmp_path.iterdir() if TEMP_MARKER in p.name]
    assert len(left) == 1 and not (tmp_path / "a.exr").exists()
    with atomic_path(tmp_path / "b.exr") as tmp:
        tmp.write_bytes(b"whole")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.exr"]


def test_an_interrupt_inside_an_atomic_write_leaves_nothing(tmp_path):
    with pytest.raises(KeyboardInterrupt), atomic_path(tmp_path / "x.json") as tmp:
        tmp.write_text("half")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def _drjit_loaded(proc) -> bool:
    """Dr.Jit's library is mapped into ``proc`` (Linux): csuas is inside its command, loading the simulator.

    Commands import Dr.Jit only inside ``run``, where csuas's own interrupt handlers are in force.
    """
    try:
        return "drjit" in open(f"/proc/{proc.pid}/maps").read()
    except OSError:
        return False


def _interrupt(argv, ready, what: str, sig, cwd):
    """Start ``csuas argv``, send ``sig`` as soon as ``ready(proc)`` holds, and return (exit code, out, err)."""
    proc = subprocess.Popen([*CSUAS, *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=cwd)
    wait_until(lambda: ready(proc), what, proc)
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=PATIENCE_S)
    return proc.returncode, out, err


@pytest.mark.slow
def test_sigint_while_the_renderer_loads_is_never_lost(tmp_path):
    """Ctrl-C while Dr.Jit and Mitsuba load (sent once Dr.Jit's library is mapped) used to be swallowed (exit 0,
    files)."""
    out_dir = tmp_path / "out"
    code, _, err = _interrupt(
        ["render", "eo", "default", "--range-m", "100", "--quality", "draft", "--quiet", "--out", str(out_dir)],
        _drjit_loaded,
        "Dr.Jit loading",
        signal.SIGINT,
        tmp_path,
    )
    # 130: csuas reported the interrupt; -2: the interrupt ended the process while Dr.Jit held the signal.
    # Never -6: an interpreter shutdown with half-loaded C extensions used to abort (fatal GIL error).
    assert code in (130, -signal.SIGINT), err
    assert "Fatal Python error" not in err
    assert "Traceback" not in err
    assert not out_dir.exists() or not [p for p in out_dir.iterdir() if p.suffix == ".png"]


@pytest.mark.slow
def test_sigterm_ends_a_running_command_like_sigint(tmp_path):
    code, _, err = _interrupt(
        # standard quality runs 13 s on 2 idle cores after Dr.Jit loads: the signal lands mid-run
        ["rcs", "dji_mini_4_pro", "--frequency-ghz", "24", "--sphere-average", "--quality", "standard"],
        _drjit_loaded,
        "Dr.Jit loading",
        signal.SIGTERM,
        tmp_path,
    )
    assert code == 143, err
    assert err.strip().splitlines()[-1] == "csuas rcs: terminated" and "Traceback" not in err


@pytest.mark.slow
def test_an_rcs_far_below_the_optical_region_is_flagged_not_floored(capsys):
    """ka = 0.05: the grid barely covers the target, but fully lit facets are integrated exactly."""
    assert cli.main(["rcs", "black_hornet_3", "--frequency-ghz", "0.03", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["rays"] < 100
    assert -200 < out["rcs_dbsm"] < -60  # PO of a 0.17 m target at 10 m wavelength, far above the floor
    text = " ".join(out["warnings"])
    assert "ka = " in text and "indicative only" in text and "tubes" in text


@pytest.mark.slow
def test_the_tube_estimate_bounds_the_tubes_traced(capsys):
    assert cli.main(["rcs", "dji_mini_4_pro", "--frequency-ghz", "10", "--quality", "draft", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["rays"] <= out["cost_estimate"]["tubes_per_aspect"]
    # the bounding disc's square grid exceeds the hull's by at most (4/pi) x the hull-to-disc area ratio
    assert out["cost_estimate"]["tubes_per_aspect"] < 20 * out["rays"]


def test_work_beyond_the_tube_budget_is_refused_before_tracing(capsys):
    start = time.process_time()  # this process's CPU time: tracing would spend minutes of it, load adds none
    code = cli.main(["rcs", "dji_mini_4_pro", "--frequency-ghz", "35", "--rays-per-wavelength", "1000"])
    err = capsys.readouterr().err
    assert code == 2 and "max_tubes" in err and "min on 2 CPU cores" in err
    assert time.process_time() - start < 30.0


def test_a_reader_that_leaves_early_gets_no_traceback(tmp_path):
    """``csuas range default --json | head -1`` used to end in a BrokenPipeError traceback."""
    proc = subprocess.Popen([*CSUAS, "range", "default", "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # the reader is gone before csuas writes
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=PATIENCE_S) == 141
    assert "Traceback" not in err and "BrokenPipe" not in err


def _signal_this_thread(sig) -> None:
    """Send ``sig`` to the calling (main) thread: POSIX delivers it before this returns, whatever the load.

    ``os.kill`` lets the kernel pick any thread, Dr.Jit's pool once an earlier test loaded it, and on a
    loaded machine that thread may run its handler only after the block under test has ended.
    """
    signal.pthread_kill(threading.get_ident(), sig)


@pytest.fixture
def python_sigint():
    """SIGINT raises KeyboardInterrupt, as in a terminal, even where pytest was started with SIGINT ignored
    (a background job of a non-interactive shell: ``make test &``, a CI step), which Python then keeps."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_a_signal_during_an_extension_import_is_delivered_after_it(python_sigint):
    """SIGINT inside a nanobind import aborted the process (exit -6); it is held and raised after the block."""
    reached_end_of_block = False
    with pytest.raises(KeyboardInterrupt):
        with deferred_interrupts():
            _signal_this_thread(signal.SIGINT)  # the handler runs in this block: it must only hold the signal
            reached_end_of_block = True
    assert reached_end_of_block
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_signal_held_during_an_import_is_recorded_by_the_command_handler():
    with handling_interrupts():
        with pytest.raises(KeyboardInterrupt), deferred_interrupts():
            _signal_this_thread(signal.SIGTERM)
        assert isinstance(pending(), Terminated)


@pytest.mark.slow
def test_an_interrupted_dataset_keeps_only_whole_images_and_resumes(tmp_path):
    """Ctrl-C while frames render and the previous one is written: every record has its image and label,
    no temporary file is left, and the next run renders only what is missing."""
    out_dir = tmp_path / "set"

    def first_record_written(_proc) -> bool:
        records = out_dir / "records"
        return records.is_dir() and any(not p.name.startswith(".") for p in records.iterdir())

    code, _, err = _interrupt(
        ["dataset", "example", "--out", str(out_dir)], first_record_written, "first record", signal.SIGINT, tmp_path
    )
    assert code in (130, -signal.SIGINT), err
    assert "Traceback" not in err
    records = sorted(p.stem for p in (out_dir / "records").iterdir())
    assert 0 < len(records) < 20  # the interrupt landed mid-set
    assert {p.stem for p in (out_dir / "images").iterdir()} >= set(records)
    assert {p.stem for p in (out_dir / "labels").iterdir()} >= set(records)
    assert not [p for p in out_dir.rglob("*") if TEMP_MARKER in p.name]  # temporaries (the folder's lock stays)
    assert cli.main(["dataset", "example", "--out", str(out_dir), "--json"]) == 0
    assert len(list((out_dir / "records").iterdir())) == 20
