"""Command line of csuas (SPEC 8).

Each command lives in ``csuas.commands.<name>`` and exposes

``add_arguments(parser)``
    declares its options (``--json`` is added for every command here);
``run(args) -> dict``
    does the work and returns the JSON object printed with ``--json``;
``render_text(result) -> str``
    the human-readable form printed otherwise.

Errors derived from :class:`csuas.base.errors.CsuasError` end the program with exit
code 2 and a single line on standard error, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from csuas.base.errors import CsuasError
from csuas.base.fileio import dumps

#: Command name -> one-line help. The module ``csuas.commands.<name>`` implements it.
COMMANDS = {
    "range": "predicted detection range of each sensor of a scenario",
    "defaults": "list the paper's default parameters, or check every derivable default",
    "sensitivity": "one-at-a-time sensitivity (tornado) analysis and platform comparison",
    "bench": "benchmarks: core models, exact solves vs the paper's loops, silhouettes, SBR, Sionna, lidar, render window",
    "drone": "drone model size, exact silhouette metrics (d_crit, projected area, LCS) and mesh export",
    "pathloss": "RF path gain drone -> RF sensor by Sionna RT, beside Friis and the two-ray model",
    "rcs": "radar cross-section of a mesh or drone preset by shooting and bouncing rays (SBR-PO)",
    "render": "EO, thermal and lidar renders of a scenario's drone at slant ranges: pixels on target, contrast, "
              "Delta T, lidar cross-section",
    "report": "validation report: every cross-check of the analytic core against the simulators, with a baseline",
}


class _Parser(argparse.ArgumentParser):
    """Argument parser whose usage errors are one line and exit code 2."""

    def error(self, message):  # noqa: D102 - argparse hook
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The top-level parser; only ``command``'s module is imported (fast start-up)."""
    parser = _Parser(prog="csuas", description="Counter-drone sensor detection-range models and their validation.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, help_text in COMMANDS.items():
        cmd = sub.add_parser(name, help=help_text, description=help_text)
        if name == command:
            module = importlib.import_module(f"csuas.commands.{name}")
            module.add_arguments(cmd)
            cmd.add_argument("--json", action="store_true", help="print one JSON object on stdout")
            cmd.set_defaults(_module=module)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``csuas`` console script; returns the exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    args = build_parser(command if command in COMMANDS else None).parse_args(argv)
    try:
        result = args._module.run(args)
    except CsuasError as exc:
        print(f"csuas {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"csuas {args.command}: interrupted", file=sys.stderr)
        return 130
    print(dumps(result) if args.json else args._module.render_text(result))
    return int(result.get("exit_code", 0)) if isinstance(result, dict) else 0


if __name__ == "__main__":
    sys.exit(main())
