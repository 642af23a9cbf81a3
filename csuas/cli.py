"""Command line of csuas (docs/command-line.md).

Each command lives in ``csuas.commands.<name>`` and exposes

``add_arguments(parser)``
    declares its options (``--json`` is added for every command here);
``run(args) -> dict``
    does the work and returns the JSON object printed with ``--json``;
``render_text(result) -> str``
    the human-readable form printed otherwise.

Exit codes: 0 success; 1 a failed check (report, defaults check) or an internal failure of
csuas (one line with a hint to rerun with ``--debug`` for the traceback); 2 bad input: a
:class:`csuas.base.errors.CsuasError`, or an operating-system error about a file the user named
(missing, a directory, unreadable, already a file), one line on standard error, never a traceback;
130 interrupted by SIGINT, 143 by SIGTERM (both end the same way: temporary files removed).
"""

from __future__ import annotations

import argparse
import os
import sys

from csuas.base.errors import CsuasError
from csuas.base.interrupts import Terminated, handling_interrupts, pending, raise_if_interrupted
from csuas.base.registry import resolve

#: Command name -> one-line help. The module ``csuas.commands.<name>`` implements it.
COMMANDS = {
    "range": "predicted detection range of each sensor of a scenario",
    "defaults": "list the paper's default parameters, or check every derivable default",
    "sensitivity": "one-at-a-time sensitivity (tornado) analysis and platform comparison",
    "bench": "benchmarks: core models, exact solves vs the paper's loops, silhouettes, SBR, Sionna, lidar, "
    "render window",
    "drone": "drone model size, exact silhouette metrics (d_crit, projected area, LCS) and mesh export",
    "pathloss": "RF path gain drone -> RF sensor by Sionna RT, beside Friis and the two-ray model",
    "rcs": "radar cross-section of a mesh or drone preset by shooting and bouncing rays (SBR-PO)",
    "rcs-statistics": "the drone presets' RCS over aspects per band and polarisation (mean, percentiles, "
    "log-normal and chi-square fits), the table the radar's aspect-fluctuation model reads",
    "rcs-table": "per-aspect RCS table of a drone preset or mesh (azimuth x elevation x frequency x "
    "polarisation, each cell's bound) as MATLAB rcsSignature .mat, OSI-style .csv or NetCDF .nc",
    "micro-doppler": "Doppler spectrum of a drone's spinning rotor blades (physical optics): lines at multiples of "
    "blades x rotation rate, blade-flash period, time-averaged RCS spinning vs at rest (JSON and a PNG)",
    "render": "EO, thermal and lidar renders of a scenario's drone at slant ranges: pixels on target, contrast, "
    "Delta T, lidar cross-section",
    "report": "validation report: every cross-check of the analytic core against the simulators, with a baseline",
    "pd": "probability of detection against range for every sensor of a scenario, fused, and along an approach",
    "pd-radar": "probability of detection of a radar detector (Swerling 0-4), or the SNR a Pd needs",
    "sweep": "a sweep over scenario parameters or simulator settings, in one process or on a Dask cluster",
    "coverage": "where each sensor of a site sees and detects a drone over terrain, per flight level and fused "
    "(GeoTIFF, PNG, coverage.json)",
    "engage": "tracks and false alarms of a site over time: Monte Carlo runs of a drone among birds, noise and "
    "clutter into a Stone Soup tracker (warning time, false tracks per hour by cause)",
    "dataset": "labelled EO frames (16-bit PNG, COCO and YOLO) of drones at drawn ranges and aspects, through the "
    "sensor chain",
}


#: Exit code when standard output's reader went away (128 + SIGPIPE), as the shell reports it.
BROKEN_PIPE = 141


class _Parser(argparse.ArgumentParser):
    """Argument parser whose usage errors are one line and exit code 2."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The top-level parser; only ``command``'s module is imported (fast start-up)."""
    parser = _Parser(
        prog="csuas",
        description="Counter-drone sensor detection-range models and their validation.",
        epilog="--debug (anywhere on the line): show the traceback of an unexpected error",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, help_text in COMMANDS.items():
        cmd = sub.add_parser(name, help=help_text, description=help_text)
        if name == command:
            module = resolve(f"csuas.commands.{name.replace('-', '_')}")
            module.add_arguments(cmd)
            cmd.add_argument("--json", action="store_true", help="print one JSON object on stdout")
            cmd.set_defaults(_module=module)
    return parser


def _describe_os_error(exc: OSError) -> str:
    """One line for an operating-system error: what happened and to which path."""
    what = exc.strerror or type(exc).__name__
    where = f": {exc.filename}" if exc.filename else ""
    return f"{what}{where}"


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``csuas`` console script; returns the exit code.

    SIGINT and SIGTERM are handled from the first line (:func:`csuas.base.interrupts.handling_interrupts`):
    an interrupt while the command's modules load or its arguments are parsed ends the run with
    exit code 130 or 143 and one line, like one during the work.
    """
    command = "csuas"
    with handling_interrupts():
        try:
            argv = sys.argv[1:] if argv is None else list(argv)
            command = next((a for a in argv if not a.startswith("-")), command)
            return _main(argv)
        except KeyboardInterrupt as exc:  # while the command's module loads, during parsing, or printing
            return _interrupted(command, exc)


def _interrupted(command: str, exc: KeyboardInterrupt) -> int:
    """Report an interrupt in one line; its exit code (130 SIGINT, 143 SIGTERM)."""
    terminated = isinstance(exc, Terminated)
    print(f"csuas {command}: {'terminated' if terminated else 'interrupted'}", file=sys.stderr)
    return 143 if terminated else 130


def _main(argv: list[str]) -> int:
    """Parse ``argv``, run the command and print its result; the exit code (module docstring)."""
    from csuas.base.fileio import dumps  # NumPy: imported after the interrupt handlers are in place

    debug = "--debug" in argv
    argv = [a for a in argv if a != "--debug"]
    command = next((a for a in argv if not a.startswith("-")), None)
    args = build_parser(command if command in COMMANDS else None).parse_args(argv)
    try:
        try:
            result = args._module.run(args)
            text = dumps(result) if args.json else args._module.render_text(result)
        except Exception:
            if pending() is None:
                raise
            raise pending() from None
        raise_if_interrupted()
    except CsuasError as exc:
        for line in str(exc).splitlines() or [type(exc).__name__]:
            print(f"csuas {args.command}: error: {line}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        return _interrupted(args.command, exc)
    except (OSError, RecursionError, MemoryError) as exc:
        if debug:
            raise
        detail = _describe_os_error(exc) if isinstance(exc, OSError) else type(exc).__name__
        print(f"csuas {args.command}: error: {detail}", file=sys.stderr)
        return 2
    except Exception as exc:
        if debug:
            raise
        print(
            f"csuas {args.command}: internal error: {type(exc).__name__}: {exc} (rerun with --debug for the traceback)",
            file=sys.stderr,
        )
        return 1
    try:
        print(text, flush=True)
    except BrokenPipeError:  # the reader left (csuas ... | head): end quietly, as SIGPIPE would
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return BROKEN_PIPE
    return int(result.get("exit_code", 0)) if isinstance(result, dict) else 0


#: Exit codes of an interrupted run (SIGINT, SIGTERM).
INTERRUPTED = (130, 143)


def entry() -> None:
    """The ``csuas`` console script: :func:`main`, then exit.

    An interrupt that arrives while Dr.Jit, Mitsuba or Sionna load can leave their C extensions
    half initialised, and the interpreter's own shutdown then aborts (a fatal GIL error, exit -6)
    after csuas has already cleaned up and reported. An interrupted run with those modules loaded
    therefore ends at once, with its exit code, once its output is flushed.
    """
    code = main()
    if code in INTERRUPTED and any(m.split(".")[0] in ("drjit", "mitsuba", "sionna") for m in list(sys.modules)):
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)


if __name__ == "__main__":
    entry()
