"""``csuas report [--quick|--full] [--out DIR] [--baseline FILE]``: the validation report.

References: docs/validation.md; JSON keys: docs/command-line.md.

Runs every registered cross-check between the analytic core and the
simulators on the embedded defaults, writes ``DIR/report.html``
(self-contained), ``DIR/report.json`` (every figure; ``checks[]`` with
``name``, ``expected``, ``measured``, ``tolerance``, ``ok``,
``known_deviation``, ``time_s``) and ``DIR/report.md``, with progress on
standard error. Exit code 0 when every check passes or is a known, explained
deviation of the paper; 1 when a check fails or, with ``--baseline``, a
figure regressed beyond its tolerance.
"""

from __future__ import annotations

import sys


def add_arguments(parser):
    """Declare the options of ``csuas report``."""
    level = parser.add_mutually_exclusive_group()
    level.add_argument(
        "--quick",
        dest="quality",
        action="store_const",
        const="quick",
        help="quick accuracy knobs, a few minutes on 2 CPU cores (default)",
    )
    level.add_argument(
        "--full", dest="quality", action="store_const", const="full", help="higher accuracy knobs (longer)"
    )
    parser.set_defaults(quality="quick")
    parser.add_argument("--out", default="csuas-report", help="output folder (default: ./csuas-report)")
    parser.add_argument("--baseline", default=None, help="an older report.json: exit 1 on any regression")


def run(args) -> dict:
    """Run the report; the returned object holds ``checks[]``, ``summary``, ``files``, ``exit_code``."""
    from csuas.validation.report.baseline import load_baseline
    from csuas.validation.report.runner import run_report

    if args.baseline is not None:
        load_baseline(args.baseline)  # refused now, not after the checks
    report = run_report(args.quality, args.out, args.baseline, progress=sys.stderr)
    return {
        "quality": report["quality"],
        "time_s": report["time_s"],
        "summary": report["summary"],
        "checks": report["checks"],
        "baseline": report["baseline"],
        "files": report["files"],
        "exit_code": report["exit_code"],
    }


def render_text(result: dict) -> str:
    """Summary lines: counts, failures, regressions and the files written."""
    s = result["summary"]
    lines = [
        f"{s['total']} checks: {s['ok']} ok, {s['known_deviation']} known deviations of the paper, "
        f"{s.get('limitation', 0)} limits of csuas's models, {s['failed']} failed "
        f"({result['quality']}, {result['time_s']:.1f} s)"
    ]
    lines += [
        f"FAIL {c['name']}: expected {c['expected']}, measured {c['measured']}, tolerance {c['tolerance']}"
        + (f" ({c['details']['error']})" if c["details"].get("error") else "")
        for c in result["checks"]
        if c["verdict"] == "FAIL"
    ]
    if result["baseline"]:
        regs = result["baseline"]["regressions"]
        lines.append(f"baseline {result['baseline']['file']}: {len(regs)} regression(s)")
        lines += [f"REGRESSION {r['name']}: {r['what']}" for r in regs]
        lines += [f"improvement {r['name']}: {r['what']}" for r in result["baseline"].get("improvements", [])]
        lines += [f"new check {n}" for n in result["baseline"].get("new_checks", [])]
        lines += [f"missing check {n}" for n in result["baseline"].get("missing_checks", [])]
    lines += [f"{kind}: {path}" for kind, path in result["files"].items()]
    return "\n".join(lines)
