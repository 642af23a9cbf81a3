"""What a command's work will cost, estimated before it starts, and the limits it is checked against.

Every command that can run long builds one :class:`Estimate` (wall time and peak resident memory)
from the sizes the user asked for, before it builds any array, and passes it to
:func:`check_limits`. Above ``--max-seconds`` (default :data:`DEFAULT_MAX_SECONDS`) or
``--max-memory-gb`` (default half the machine's memory, :func:`machine_memory_bytes`) the command
stops with one line (exit 2) that states the estimate and the flag that lifts the limit.

The models' constants are measured on 2 CPU cores (docs/performance.md, "Cost models"); the
benchmark suite ``cost_models`` (``csuas bench --only cost_models``) compares each model with the
measured cost on three sizes.
"""

from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass
from pathlib import Path

from csuas.base.errors import ParameterError, raise_all

#: Default limit of ``--max-seconds`` [s].
DEFAULT_MAX_SECONDS = 600.0
#: Resident memory of a ``csuas`` process with NumPy, SciPy and the core imported, before any work [B]
#: (ru_maxrss of ``csuas range default``, 2 CPU cores, Python 3.12; ``cost_models`` benchmark).
BASE_PROCESS_BYTES = 150e6
#: Estimated times above this [s] are announced on standard error before the work starts.
ANNOUNCE_SECONDS = 10.0
#: cgroup v2 and v1 files holding a container's memory limit.
_CGROUP_LIMITS = ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes")

GB = 1e9


@dataclass(frozen=True)
class Estimate:
    """The predicted cost of one command's work.

    Attributes
    ----------
    what : str
        The work in words, with its sizes (``"sweep range of 1,000,000 points"``).
    seconds : float
        Wall time on 2 CPU cores [s].
    bytes : float
        Peak resident memory of the process, interpreter included [B].
    """

    what: str
    seconds: float
    bytes: float

    def __add__(self, other: Estimate) -> Estimate:
        """Two pieces of work run one after the other: times add, the peak is the larger one."""
        return Estimate(f"{self.what} and {other.what}", self.seconds + other.seconds, max(self.bytes, other.bytes))

    def as_dict(self) -> dict:
        """JSON form: ``what``, ``seconds_2_cpu_cores``, ``peak_memory_gb``."""
        return {"what": self.what, "seconds_2_cpu_cores": self.seconds, "peak_memory_gb": self.bytes / GB}


def machine_memory_bytes() -> float:
    """Physical memory available to this process [B]: the machine's, or its container's limit if lower."""
    total = float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    for name in _CGROUP_LIMITS:
        try:
            text = Path(name).read_text().strip()
        except OSError:
            continue
        if text.isdigit():
            total = min(total, float(text))
    return total


def default_max_memory_gb() -> float:
    """Default of ``--max-memory-gb``: half the machine's memory [GB]."""
    return machine_memory_bytes() / 2.0 / GB


def add_limit_arguments(parser, seconds: bool = True) -> None:
    """Declare ``--max-seconds`` (unless the command has its own) and ``--max-memory-gb``."""
    if seconds:
        parser.add_argument(
            "--max-seconds",
            type=float,
            default=DEFAULT_MAX_SECONDS,
            help=f"refuse work estimated to take longer on 2 CPU cores [s] (default {DEFAULT_MAX_SECONDS:g})",
        )
    parser.add_argument(
        "--max-memory-gb",
        type=float,
        default=None,
        help="refuse work estimated to need more memory at its peak [GB] (default half the machine's memory)",
    )


def limits_of(args) -> tuple[float, float]:
    """``(max_seconds, max_memory_gb)`` of parsed options, checked; the memory default filled in."""
    max_seconds = float(args.max_seconds)
    max_memory_gb = default_max_memory_gb() if args.max_memory_gb is None else float(args.max_memory_gb)
    errors = []
    if not (max_seconds > 0.0 and math.isfinite(max_seconds)):
        errors.append(ParameterError("max_seconds", max_seconds, "a finite number of seconds > 0"))
    if not (max_memory_gb > 0.0 and math.isfinite(max_memory_gb)):
        errors.append(ParameterError("max_memory_gb", max_memory_gb, "a finite number of GB > 0"))
    raise_all(errors)
    return max_seconds, max_memory_gb


def check_limits(estimate: Estimate, args, command: str, announce: bool = True) -> None:
    """Refuse ``estimate`` above the limits of ``args`` (one line naming the flag); announce long work.

    Parameters
    ----------
    estimate : Estimate
    args : argparse.Namespace
        With ``max_seconds`` and ``max_memory_gb`` (:func:`add_limit_arguments`).
    command : str
        The command's name, for the announcement on standard error.
    announce : bool
        Whether to announce work above :data:`ANNOUNCE_SECONDS` (False for a first, partial estimate).

    Raises
    ------
    ParameterError
        Named ``max_seconds`` or ``max_memory_gb`` (the time first), one line naming every flag to raise.
    """
    max_seconds, max_memory_gb = limits_of(args)
    size = f"{_duration(estimate.seconds)} on 2 CPU cores and {estimate.bytes / GB:.3g} GB at its peak"
    over = []
    if estimate.seconds > max_seconds:
        over.append(("max_seconds", max_seconds))
    if estimate.bytes > max_memory_gb * GB:
        over.append(("max_memory_gb", round(max_memory_gb, 3)))
    if over:
        flags = " and ".join("--" + name.replace("_", "-") for name, _ in over)
        machine = f" (this machine has {machine_memory_bytes() / GB:.3g} GB)" if over[-1][0] == "max_memory_gb" else ""
        raise ParameterError(
            *over[0], f"at least the estimated {size} for {estimate.what}; raise {flags} to run it{machine}"
        )
    if announce and estimate.seconds > ANNOUNCE_SECONDS:
        print(f"csuas {command}: {estimate.what}: about {size}", file=sys.stderr, flush=True)


def _duration(seconds: float) -> str:
    """A duration in the unit that reads best: ``42 s``, ``17 min``, ``3.2 h``, ``5.1e+04 days``."""
    if seconds < 120.0:
        return f"{seconds:.3g} s"
    if seconds < 7200.0:
        return f"{seconds / 60.0:.3g} min"
    if seconds < 172800.0:
        return f"{seconds / 3600.0:.3g} h"
    return f"{seconds / 86400.0:.3g} days"


@dataclass(frozen=True)
class Measured:
    """The measured cost of a child process (:func:`run_measured`).

    Attributes
    ----------
    code : int
        Exit code (negative: the signal that ended it).
    stderr : str
        Its standard error.
    seconds : float
        Wall time from start to end [s].
    bytes : float
        Its peak resident memory (ru_maxrss of that child alone) [B].
    cpu_seconds : float
        Its processor time, user and system, of all its threads [s] (wall time on an idle machine
        for single-threaded work: a check of timings on a loaded one).
    killed : bool
        Whether it was still running after the time limit and was killed.
    """

    code: int
    stderr: str
    seconds: float
    bytes: float
    cpu_seconds: float
    killed: bool


def run_measured(argv: list, cwd, kill_after_s: float) -> Measured:
    """Run ``argv`` in ``cwd``; its exit code, standard error, wall time and peak memory (``os.wait4``).

    A child still running after ``kill_after_s`` is killed (SIGKILL), so that runaway work cannot
    exhaust the machine; standard output is discarded.
    """
    import signal
    import subprocess
    import tempfile
    import time

    start = time.perf_counter()
    with tempfile.TemporaryFile("w+") as err:
        child = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.DEVNULL, stderr=err)
        killed = False
        while True:
            pid, status, usage = os.wait4(child.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() - start > kill_after_s:
                child.send_signal(signal.SIGKILL)
                pid, status, usage = os.wait4(child.pid, 0)
                killed = True
                break
            time.sleep(0.02)
        seconds = time.perf_counter() - start
        child.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        text = err.read()
    cpu = usage.ru_utime + usage.ru_stime
    return Measured(child.returncode, text, seconds, usage.ru_maxrss * 1024.0, cpu, killed)
