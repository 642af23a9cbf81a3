"""``csuas bench``: benchmarks with their figures and ratios (docs/performance.md)."""

from __future__ import annotations

import inspect
import sys
from pathlib import Path

from csuas.base.errors import ParameterError
from csuas.base.registry import resolve

#: Benchmark suites: name -> "module:function" (csuas.base.registry); each returns a list of row dicts or a dict.
SUITES = {
    "core_models": "csuas.validation.core.bench:bench_models",
    "core_iterative": "csuas.validation.core.bench:bench_iterative",
    "terrain_viewshed": "csuas.validation.core.bench:bench_viewshed",
    "drone_silhouette": "csuas.validation.drone.bench:bench_silhouette",
    "rcs_sbr": "csuas.validation.rcs.bench:bench_sbr",
    "rcs_memory": "csuas.validation.rcs.bench:bench_memory",
    "rcs_po_accuracy": "csuas.validation.rcs.bench:bench_po_accuracy",
    "rcs_micro_doppler": "csuas.validation.rcs.micro_doppler_bench:bench_micro_doppler",
    "sionna_links": "csuas.validation.links.bench:bench_links",
    "lidar_lcs": "csuas.validation.lidar.bench:bench",
    "render_window": "csuas.validation.imaging.bench:bench_window_vs_full_frame",
    "dataset_frames": "csuas.validation.imaging.bench:bench_frames",
    "dataset_rates": "csuas.validation.imaging.bench:bench_dataset_rates",
    "detection_pd": "csuas.validation.detection.bench:bench_pd",
    "sweep_dask": "csuas.validation.sweep.bench:bench_sweep",
    "cost_models": "csuas.validation.cost.bench:bench_cost_models",
    "engage_runs": "csuas.commands.engage:bench_runs",
    "sweep_engage": "csuas.validation.sweep.bench:bench_engage_sweep",
    "sweep_scaling": "csuas.validation.sweep.scaling:bench_sweep_scaling",
    "detector_loop": "csuas.validation.detector.detector_loop:bench_detector_loop",
    "coverage_tiles": "csuas.validation.terrain.tiles_bench:bench_coverage_tiles",
}


def add_arguments(parser):
    """Declare the options of ``csuas bench``."""
    parser.add_argument("--only", nargs="+", choices=sorted(SUITES), default=None, help="run only these suites")
    parser.add_argument(
        "--engage-runs",
        type=int,
        default=None,
        metavar="N",
        help="runs of the sweep_engage suite (default 16, minutes on 2 cores; issue 24's figure is 10000, hours)",
    )
    parser.add_argument(
        "--coverage-cells",
        type=int,
        default=None,
        metavar="N",
        help="cells a side of the coverage_tiles DEM (default 20000, issue 25's figure: tens of minutes on 2 cores)",
    )
    parser.add_argument(
        "--out",
        default="csuas-bench",
        help="folder of the suites that write files, one sub-folder each (default: ./csuas-bench)",
    )
    parser.add_argument(
        "--device", default=None, help="torch device of detector_loop (default: cuda when present, else cpu)"
    )


def run(args) -> dict:
    """``{suite: figures}`` for every suite run."""

    if args.engage_runs is not None and args.engage_runs < 1:
        raise ParameterError("--engage-runs", args.engage_runs, "a whole number >= 1")
    cells = getattr(args, "coverage_cells", None)
    if cells is not None and cells < 64:
        raise ParameterError("--coverage-cells", cells, "a whole number >= 64")
    sizes = {
        "sweep_engage": {"runs": args.engage_runs} if args.engage_runs else {},
        "coverage_tiles": {"cells": cells} if cells else {},
    }
    out = {}
    for name in args.only or SUITES:
        print(f"bench: {name} ...", file=sys.stderr, flush=True)
        suite = resolve(SUITES[name])
        # a suite that writes files takes out_dir (its own sub-folder of --out), one that trains takes device
        options = {
            "out_dir": str(Path(getattr(args, "out", "csuas-bench")) / name),
            "device": getattr(args, "device", None),
            **sizes.get(name, {}),
        }
        accepted = inspect.signature(suite).parameters
        out[name] = suite(**{k: v for k, v in options.items() if k in accepted})
    return {"benchmarks": out}


def _fmt(value):
    return f"{value:.4g}" if isinstance(value, float) else str(value)


def render_text(result: dict) -> str:
    """One line per benchmark row."""
    lines = []
    for name, rows in result["benchmarks"].items():
        lines.append(f"[{name}]")
        for row in rows if isinstance(rows, list) else [rows]:
            lines.append("  " + ", ".join(f"{k}={_fmt(v)}" for k, v in row.items()))
    return "\n".join(lines)
