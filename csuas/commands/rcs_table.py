"""``csuas rcs-table PRESET --out FILE``: per-aspect RCS table with each cell's bound, as a file.

The table (:mod:`csuas.render.rcs.signature`) covers azimuth x elevation x frequency x
polarisation; the format follows the suffix of ``--out`` (:mod:`csuas.render.rcs.signature_files`:
``.mat`` MATLAB ``rcsSignature``, ``.csv`` the OSI per-degree layout, ``.nc`` NetCDF 3). The cost is
estimated before tracing and the run refused above ``--max-seconds``.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from csuas.base.errors import ParameterError, raise_all
from csuas.render.quality import RCS

#: Default elevations [deg]: the whole sphere in 5-degree steps.
DEFAULT_ELEVATIONS_DEG = tuple(float(e) for e in np.arange(-90.0, 90.1, 5.0))

#: Default band [GHz]: X band, one of the rcs-statistics table's bands.
DEFAULT_FREQUENCY_GHZ = 9.4


def add_arguments(parser) -> None:
    """Options of ``csuas rcs-table``."""
    parser.add_argument(
        "mesh_or_preset", metavar="PRESET", help="drone preset name (e.g. dji_mini_4_pro) or a mesh file (metres)"
    )
    parser.add_argument(
        "--out", required=True, metavar="FILE", help="output file: .mat (MATLAB rcsSignature), .csv (OSI) or .nc"
    )
    parser.add_argument(
        "--azimuth-step-deg", type=float, default=5.0, help="azimuth step, -180 to 180 deg (default 5; divides 360)"
    )
    parser.add_argument(
        "--elevation-deg",
        type=float,
        nargs="+",
        default=list(DEFAULT_ELEVATIONS_DEG),
        help="elevations [deg] (default -90 to 90 in 5-degree steps)",
    )
    parser.add_argument(
        "--frequency-ghz",
        type=float,
        nargs="+",
        default=[DEFAULT_FREQUENCY_GHZ],
        help=f"frequencies [GHz] (default {DEFAULT_FREQUENCY_GHZ:g})",
    )
    parser.add_argument(
        "--polarisations",
        nargs="+",
        choices=("VV", "HH", "HV", "VH"),
        default=["VV", "HH", "HV", "VH"],
        help="receive-transmit polarisations (default all four; the first is the .mat's pattern)",
    )
    parser.add_argument(
        "--quality", choices=RCS.names, default="standard", help=f"SBR {RCS.help_text()} (default standard)"
    )
    bounces = ", ".join(str(RCS.values(rung)["max_bounces"]) for rung in RCS.names)
    parser.add_argument(
        "--max-bounces",
        type=int,
        default=None,
        help=f"reflections per tube (default the quality's: {bounces}); raise it where the truncation term leaves "
        "cells without a bound (csuas rcs --truncation-fraction finds the limit at one aspect)",
    )
    parser.add_argument(
        "--material", default=None, help="one material for all faces (default: a preset's parts, PEC for a mesh)"
    )
    parser.add_argument(
        "--max-seconds",
        type=float,
        default=600.0,
        help="refuse a table estimated to take longer on 2 CPU cores [s] (default 600)",
    )


def _validate(args) -> None:
    """Every option checked before the mesh is loaded; all mistakes at once."""
    from csuas.render.rcs.signature import azimuth_axis
    from csuas.render.rcs.signature_files import check_suffix
    from csuas.render.rcs.solver import MAX_BOUNCES

    errors = []
    for check in (lambda: check_suffix(args.out), lambda: azimuth_axis(args.azimuth_step_deg)):
        try:
            check()
        except ParameterError as err:
            errors.append(err)
    for el in args.elevation_deg:
        if not (-90.0 <= el <= 90.0):
            errors.append(ParameterError("elevation_deg", el, "-90 to 90 [deg]"))
    if list(args.elevation_deg) != sorted(set(args.elevation_deg)):
        errors.append(ParameterError("elevation_deg", args.elevation_deg, "increasing, without repeats"))
    for f in args.frequency_ghz:
        if not (0.0 < f <= 3000.0):
            errors.append(ParameterError("frequency_ghz", f, "0 < f <= 3000 [GHz]"))
    if list(args.frequency_ghz) != sorted(set(args.frequency_ghz)):
        errors.append(ParameterError("frequency_ghz", args.frequency_ghz, "increasing, without repeats"))
    if len(set(args.polarisations)) != len(args.polarisations):
        errors.append(ParameterError("polarisations", args.polarisations, "each of VV, HH, HV, VH at most once"))
    if args.max_bounces is not None and not (1 <= args.max_bounces <= MAX_BOUNCES):
        errors.append(ParameterError("max_bounces", args.max_bounces, f"an integer from 1 to {MAX_BOUNCES}"))
    if not (math.isfinite(args.max_seconds) and args.max_seconds > 0.0):
        errors.append(ParameterError("max_seconds", args.max_seconds, "a finite number > 0 [s]"))
    raise_all(errors)


def run(args) -> dict:
    """Estimate, trace, write; returns the ``--json`` object (the file, the grid, the cost, bound ranges)."""
    from csuas.render.rcs.signature import azimuth_axis, estimate_cost, signature_table
    from csuas.render.rcs.signature_files import write_signature
    from csuas.render.rcs.solver import get_engine, resolve_quality

    start = time.perf_counter()
    _validate(args)
    azimuth = azimuth_axis(args.azimuth_step_deg)
    n, bounces = resolve_quality(args.quality, None, args.max_bounces)
    engine = get_engine(args.mesh_or_preset, args.material)
    aspects = (len(azimuth) - 1) * len(args.elevation_deg)
    cost = estimate_cost(engine.target, args.frequency_ghz, aspects, n, bounces)
    if cost["seconds_2_cpu_cores"] > args.max_seconds:
        raise ParameterError(
            "max_seconds",
            args.max_seconds,
            f"at least the estimated {cost['seconds_2_cpu_cores']:.0f} s on 2 CPU cores ({cost['tubes']:.3g} tubes, "
            f"{aspects} aspects); raise --max-seconds, or coarsen the grid or --quality",
        )
    if cost["seconds_2_cpu_cores"] > 10.0:
        print(f"csuas rcs-table: roughly {cost['seconds_2_cpu_cores']:.0f} s on 2 CPU cores", file=sys.stderr)
    table = signature_table(
        engine,
        azimuth,
        args.elevation_deg,
        args.frequency_ghz,
        polarisations=args.polarisations,
        quality=args.quality,
        max_bounces=bounces,
    )
    write_signature(table, args.out)
    finite = table.bound_db[np.isfinite(table.bound_db)]
    return {
        "target": args.mesh_or_preset,
        "written": str(args.out),
        "azimuth_deg": [float(azimuth[0]), float(azimuth[-1]), float(args.azimuth_step_deg)],
        "elevation_deg": [float(e) for e in args.elevation_deg],
        "frequency_ghz": [float(f) for f in args.frequency_ghz],
        "polarisations": list(args.polarisations),
        "cells": int(table.rcs_dbsm.size),
        "cost_estimate": cost,
        "rays": table.tubes,
        "quality": args.quality,
        "max_bounces": table.max_bounces,
        "model_db": table.model_db.tolist(),
        "bound_db_median": float(np.median(finite)) if finite.size else None,
        "cells_without_bound": int(table.bound_db.size - finite.size),
        "sbr_time_s": table.time_s,
        "time_s": time.perf_counter() - start,
    }


def render_text(result: dict) -> str:
    """Summary of ``csuas rcs-table``."""
    az0, az1, step = result["azimuth_deg"]
    median = result["bound_db_median"]
    return "\n".join(
        [
            f"RCS table of {result['target']}: {result['cells']} cells (azimuth {az0:g} to {az1:g} deg in {step:g}, "
            f"{len(result['elevation_deg'])} elevations, {len(result['frequency_ghz'])} frequencies, "
            f"{' '.join(result['polarisations'])})",
            f"  bound against the exact answer: median {'-' if median is None else f'{median:.2f}'} dB, "
            f"{result['cells_without_bound']} cells without one; PO model term "
            + ", ".join(f"{m:.2f}" for m in result["model_db"])
            + " dB",
            f"  {result['rays']} tubes, {result['sbr_time_s']:.1f} s tracing, {result['time_s']:.1f} s in all",
            f"  written: {result['written']}",
        ]
    )
