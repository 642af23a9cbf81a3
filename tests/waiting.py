"""Waiting for a state, never for a time: the tests' one way to wait on another process.

A test that sleeps a fixed time and then expects a file or a line is a test of the machine's load,
not of csuas: on 2 cores at a load average of 8-30 a process reaches the same state 5-15 times later.
:func:`wait_until` polls for the state itself, with a timeout generous enough that load only makes
a test slower; the timeout is there to end a hung test with a clear line, not to judge speed
(speed targets live in ``csuas bench``).
"""

from __future__ import annotations

import subprocess
import time

import pytest

#: How long a test waits for a state before it gives up [s]: 20x the longest idle wait of any test.
PATIENCE_S = 600.0


def wait_until(ready, what: str, proc: subprocess.Popen | None = None, timeout_s: float = PATIENCE_S) -> None:
    """Poll ``ready()`` every 10 ms until it is true.

    Parameters
    ----------
    ready : callable
        ``ready() -> bool``, the state the test needs (a file written, a worker started).
    what : str
        That state in words, for the failure message.
    proc : subprocess.Popen, optional
        The process expected to reach it: the test fails at once, with its standard error when
        piped, if the process ends first (and kills it on timeout).
    timeout_s : float
        Give up after this long [s] and fail the test, naming ``what``.
    """
    deadline = time.monotonic() + timeout_s
    while not ready():
        if proc is not None and proc.poll() is not None:
            err = proc.stderr.read()[-2000:] if proc.stderr else ""
            pytest.fail(f"the process ended (exit {proc.returncode}) before {what}: {err}")
        if time.monotonic() > deadline:
            if proc is not None:
                proc.kill()
            pytest.fail(f"{what}: not reached after {timeout_s:.0f} s")
        time.sleep(0.01)
