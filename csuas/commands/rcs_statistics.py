"""``csuas rcs-statistics``: the drone presets' RCS over aspects per band and polarisation, as a table.

Prints the table (:mod:`csuas.validation.rcs.statistics_table`) or writes it as CSV; with
``--write-defaults`` it replaces the shipped ``defaults/drone_rcs_statistics.csv`` that the radar's
aspect-fluctuation model (``radar.fluctuation``) reads.
"""

from __future__ import annotations

import datetime
import sys
from importlib import resources

from csuas.base.cost import add_limit_arguments, check_limits
from csuas.base.errors import ParameterError, raise_all
from csuas.base.paths import output_file
from csuas.drone_models.presets import list_presets
from csuas.render.quality import RCS

#: The shipped table, inside the installed package.
DEFAULTS_FILE = "drone_rcs_statistics.csv"


def add_arguments(parser):
    """Declare the options of ``csuas rcs-statistics``."""
    from csuas.validation.rcs.statistics_table import BANDS_GHZ

    parser.add_argument("--presets", nargs="+", choices=sorted(list_presets()), default=None, help="default all")
    parser.add_argument(
        "--bands-ghz", nargs="+", type=float, default=list(BANDS_GHZ), help="frequencies [GHz] (default the table's)"
    )
    parser.add_argument(
        "--quality",
        choices=RCS.names,
        default="standard",
        help=f"SBR {RCS.help_text()} (default standard)",
    )
    parser.add_argument(
        "--accuracy-db", type=float, default=0.5, help="95 %% bound of each Eq. 6 mean [dB] (default 0.5)"
    )
    parser.add_argument("--max-aspects", type=int, default=8192, help="aspect budget per band (default 8192)")
    add_limit_arguments(parser)
    target = parser.add_mutually_exclusive_group()
    target.add_argument("--out", metavar="CSV", default=None, help="write the table to this file")
    target.add_argument("--write-defaults", action="store_true", help=f"replace the shipped defaults/{DEFAULTS_FILE}")


def _validate(args) -> None:
    errors = []
    for f in args.bands_ghz:
        if not (0.1 <= f <= 300.0):
            errors.append(ParameterError("bands_ghz", f, "0.1 <= f <= 300 [GHz]"))
    if not (0.0 < args.accuracy_db <= 10.0):
        errors.append(ParameterError("accuracy_db", args.accuracy_db, "0 < x <= 10 [dB]"))
    if args.max_aspects < 256:
        errors.append(ParameterError("max_aspects", args.max_aspects, "integer >= 256 (one batch)"))
    if args.out is not None:
        try:
            output_file(args.out, "out")
        except ParameterError as exc:
            errors.append(exc)
    raise_all(errors)


def _progress(done: int, total: int, seconds: float) -> None:
    eta = seconds / done * (total - done)
    print(f"csuas rcs-statistics: {done}/{total} bands, {seconds:.0f} s, about {eta:.0f} s left", file=sys.stderr)


def run(args) -> dict:
    """The rows, and where they were written."""
    from csuas.validation.rcs.statistics_cost import statistics_estimate
    from csuas.validation.rcs.statistics_table import drone_statistics, write_table

    _validate(args)
    presets = sorted(list_presets()) if args.presets is None else args.presets
    check_limits(statistics_estimate(presets, args.bands_ghz, args.quality, args.max_aspects), args, "rcs-statistics")
    rows = drone_statistics(
        args.presets,
        args.bands_ghz,
        quality=args.quality,
        accuracy_db=args.accuracy_db,
        max_aspects=args.max_aspects,
        progress=_progress,
    )
    out = {"rows": rows, "settings": {"quality": args.quality, "accuracy_db": args.accuracy_db}}
    path = args.out
    if args.write_defaults:
        path = resources.files("csuas.defaults").joinpath(DEFAULTS_FILE)
    if path is not None:
        header = (
            "RCS of the drone presets over aspects (csuas rcs-statistics"
            f" --quality {args.quality} --accuracy-db {args.accuracy_db:g} --max-aspects {args.max_aspects}),"
            f" {datetime.date.today().isoformat()}\n"
            "mean: Eq. 6 linear mean over the sphere and its 95 % bound; percentiles and fits over uniformly"
            " drawn aspects\n"
            f"total time {sum(r['time_s'] for r in rows) / 2:.0f} s (each band's time is on both of its rows)"
        )
        write_table(rows, path, header)
        out["written"] = str(path)
    return out


def render_text(result: dict) -> str:
    """The table, one line per preset, band and polarisation."""
    lines = [
        f"{'preset':<16} {'GHz':>5} pol {'mean':>7} {'+-dB':>5} {'median':>7} {'p10':>7} {'p90':>7}"
        f" {'2k':>5} {'aspects':>7}"
    ]
    for r in result["rows"]:
        lines.append(
            f"{r['preset']:<16} {r['frequency_ghz']:>5g} {r['polarisation']:<3} {r['mean_dbsm']:>7.2f}"
            f" {r['mean_error_db']:>5.2f} {r['median_dbsm']:>7.2f} {r['p10_dbsm']:>7.2f} {r['p90_dbsm']:>7.2f}"
            f" {r['chi2_dof']:>5.2f} {r['aspects']:>7d}"
        )
    if "written" in result:
        lines.append(f"written: {result['written']}")
    return "\n".join(lines)
