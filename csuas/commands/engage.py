"""``csuas engage SPEC --out DIR``: tracks and false alarms of a site over time, with birds and clutter.

Monte Carlo runs of a drone flying waypoints over a coverage site (docs/coverage.md) past its sensors,
among birds, noise false alarms and ground clutter, into one Stone Soup tracker
(:mod:`csuas.render.engagement`). Writes ``DIR/engage.json`` (``runs``, ``seed``, ``metrics``,
``looks``, ``curves``, ``runs_detail``), ``DIR/engage_map.png`` (truth, tracks and false tracks over
the hillshade) and ``DIR/engage_curve.png`` (the cumulative probability of a confirmed track against
the distance to the protected point, beside each sensor's cumulative Pd). ``csuas engage example``
runs the embedded example; ``--print-example`` prints its spec. The cost (runs x looks) is estimated
first, and a spec above ``--max-seconds`` is refused. Keys: docs/engagements.md.
"""

from __future__ import annotations

import json
import sys
import time

from csuas.base.errors import ParameterError
from csuas.base.fileio import exclusive_lock, prepare_output_dir, read_spec, write_text_atomic
from csuas.base.paths import inside
from csuas.defaults import engagement_path
from csuas.render.engagement.build import build, load_engagement

#: Looks of each sensor in the pilot run that measures the cost per look (:func:`estimate_seconds`), and
#: the most time it may take [s] (it then counts the looks it took).
PILOT_LOOKS, PILOT_BUDGET_S = 10, 20.0


def add_arguments(parser):
    """Declare the options of ``csuas engage``."""
    parser.add_argument("spec", nargs="?", help="engagement spec TOML file, or an embedded spec (example)")
    parser.add_argument("--out", help="output folder (engage.json, engage_map.png, engage_curve.png)")
    parser.add_argument("--print-example", action="store_true", help="print the embedded example's spec and exit")
    parser.add_argument("--workers", type=int, default=1, help="processes that share the runs (default 1)")
    parser.add_argument(
        "--max-seconds",
        type=float,
        default=600.0,
        help="refuse a spec whose estimated run time exceeds this [s] (default 600)",
    )


def _spec_source(name: str):

    return engagement_path(name)


def estimate_seconds(engagement, runs: int) -> float:
    """Estimated run time [s] on one process: runs x the looks of a run x the measured seconds per look.

    The seconds per look come from a pilot run over the first PILOT_LOOKS looks of every sensor (a
    tentative track lives at most N looks, so the tracker's load has settled by then; the run's own
    draws, seeded apart from the real runs; stopped after PILOT_BUDGET_S). The cost grows with false
    alarms, birds and the tentative tracks they start (their pairs grow as the square of the detections
    per look), which a fixed cost per look would miss.
    """
    from csuas.render.engagement.simulate import run_once

    revisit = max(sensor.settings.revisit_s for sensor in engagement.sensors.values())
    until = (PILOT_LOOKS - 1) * revisit
    looks = sum(len(seen.t_s) for seen in engagement.looks.values())
    started = time.process_time()  # CPU time: the estimate of a machine that others do not share
    pilot = run_once(engagement, runs, until_s=until, budget_s=PILOT_BUDGET_S)
    setup = time.process_time() - started - pilot["tracking_cpu_s"]  # the run's draws, all its looks
    return runs * (setup + pilot["tracking_cpu_s"] * looks / max(pilot["looks_tracked"], 1))


def run_all(engagement, runs: int, workers: int) -> list:
    """Every run's record, in run order, over ``workers`` processes (each run seeded by its index alone)."""
    from csuas.render.engagement.simulate import run_once

    indices = range(runs)
    if workers <= 1 or runs <= 1:
        records = []
        for index in indices:
            records.append(run_once(engagement, index, keep_paths=index < 3))
            if (index + 1) % max(runs // 10, 1) == 0:
                print(f"csuas engage: {index + 1}/{runs} runs", file=sys.stderr, flush=True)
        return records
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(max_workers=workers) as pool:
        return list(
            pool.map(
                run_once,
                [engagement] * runs,
                indices,
                [i < 3 for i in indices],
                chunksize=max(runs // (4 * workers), 1),
            )
        )


def run(args) -> dict:
    """Validate, estimate, run every Monte Carlo run, and write engage.json and the plots."""

    if args.print_example:
        return {"example": _spec_source("example").read_text(encoding="utf-8")}
    if args.spec is None or args.out is None:
        raise ParameterError("spec / --out", args.spec, "a spec (or example) and --out DIR, or --print-example")
    if not args.max_seconds > 0:
        raise ParameterError("--max-seconds", args.max_seconds, "a time > 0 [s]")
    if not 1 <= args.workers <= 256:
        raise ParameterError("--workers", args.workers, "1 to 256 processes")
    spec, engagement = load_engagement(args.spec)
    estimate = estimate_seconds(engagement, spec.runs) / min(args.workers, spec.runs)
    if estimate > args.max_seconds:
        most = max(int(spec.runs * args.max_seconds / estimate), 0)
        raise ParameterError(
            "runs",
            spec.runs,
            f"at most {most} runs within --max-seconds {args.max_seconds:g} (estimated {estimate:.0f} s)",
        )
    out = prepare_output_dir(args.out)
    # every file is checked before the runs: inside --out, never a device or a FIFO (base/paths.py)
    files = tuple(inside(out, name) for name in ("engage_map.png", "engage_curve.png", "engage.json"))
    with exclusive_lock(out / LOCK_NAME, "--out"):
        return _run_locked(args, spec, engagement, estimate, files)


#: Lock file inside the output folder: one engagement writes into a folder at a time (as sweep, dataset,
#: coverage and report do).
LOCK_NAME = ".csuas-engage.lock"


def _run_locked(args, spec, engagement, estimate: float, files: tuple) -> dict:
    """The runs, engage.json and the plots, holding the output folder's lock."""
    from csuas.commands.engage_plots import curve_plot, map_plot
    from csuas.render.engagement.metrics import curves, looks_table, summarise

    map_png, curve_png, summary = files
    started = time.perf_counter()
    records = run_all(engagement, spec.runs, args.workers)
    elapsed = time.perf_counter() - started
    result = {
        "spec": str(args.spec),
        "runs": spec.runs,
        "seed": spec.seed,
        "metrics": summarise(engagement, records),
        "looks": looks_table(engagement),
        "curves": curves(engagement, records),
        "protected_point": engagement.protected_xy.tolist(),
        "arrival_s": engagement.path.duration_s,
        "estimated_s": estimate,
        "time_s": elapsed,
        "runs_per_second": spec.runs / elapsed,
        "runs_detail": records,
    }
    result["map_png"] = str(map_plot(map_png, engagement, records, result["metrics"]))
    result["curve_png"] = str(curve_plot(curve_png, engagement, result["curves"], result["metrics"]))
    write_text_atomic(summary, json.dumps(result, indent=1, allow_nan=False))
    result["out"] = str(summary.parent)
    return result


def render_text(result: dict) -> str:
    """The buyer's answer: warning time, false tracks per hour by cause, false alarms, and where the files are."""
    if "example" in result:
        return result["example"].rstrip("\n")
    m = result["metrics"]
    w, f = m["warning_time_s"], m["first_track_range_m"]

    def fmt(v, unit):
        return "never" if v is None else f"{v:.0f} {unit}"

    lines = [
        f"engage: {result['runs']} runs in {result['time_s']:.1f} s ({result['runs_per_second']:.2f} runs/s)",
        f"warning time: median {fmt(w['median'], 's')} (p10 {fmt(w['p10'], 's')}, p90 {fmt(w['p90'], 's')})",
        f"first track {fmt(f['median'], 'm')} before the protected point (median); "
        f"never in {100 * f['never_fraction']:.0f} % of runs",
        "false tracks per hour: {:.1f} ({})".format(
            m["false_tracks_per_hour"]["total"],
            ", ".join(f"{c} {v:.1f}" for c, v in m["false_tracks_per_hour"]["by_cause"].items()),
        ),
    ]
    for name, a in m["false_alarms_per_hour"].items():
        lines.append(
            f"false alarms per hour, {name}: {a['total']:.0f} (noise {a['noise']:.0f}, expected "
            f"{a['noise_expected']:.0f}; clutter {a['clutter']:.0f})"
        )
    lines.append(f"track continuity {m['track_continuity']}, mean GOSPA {m['gospa_mean']}")
    siap = m["siap"]
    lines.append(
        f"SIAP: completeness {siap['completeness']:.2f}, spuriousness {siap['spuriousness']:.2f}, "
        f"position accuracy {siap['position_accuracy_m']:.1f} m, longest segment {siap['longest_track_segment']:.2f}"
    )
    lines.append(f"files: {result['out']}/engage.json, {result['map_png']}, {result['curve_png']}")
    return "\n".join(lines)


def bench_runs(runs: int = 4) -> list[dict]:
    """Runs per second of the embedded example, on one process and on two, and without birds (``csuas bench``).

    Lives beside the command because it times the command's own process pool (:func:`run_all`). Each
    figure times only the runs (the engagement is built before the timer).
    """
    from csuas.render.engagement.spec import parse_spec

    data = read_spec("example", _spec_source, "engagement spec")
    out = []
    for label, birds, workers in (("example", None, 1), ("example", None, 2), ("example without birds", 0.0, 1)):
        spec_data = dict(data)
        if birds is not None:
            spec_data["confusers"] = {**data["confusers"], "birds_per_km2": birds}
        engagement = build(parse_spec(spec_data), None)
        started = time.perf_counter()
        run_all(engagement, runs, workers)
        elapsed = time.perf_counter() - started
        out.append(
            {
                "case": label,
                "workers": workers,
                "runs": runs,
                "time_s": elapsed,
                "runs_per_second": runs / elapsed,
                "estimated_s": estimate_seconds(engagement, runs) / workers,
            }
        )
    return out
