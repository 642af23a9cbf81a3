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
from pathlib import Path

import numpy as np

from csuas.base.errors import ParameterError, raise_all

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
    from csuas.defaults import engagement_path

    return engagement_path(name)


def _scenario(spec, site: dict, base: Path | None):
    """The scenario of the engagement: the spec's (name, file beside the spec or inline table) or the site's."""
    from csuas.core.scenario import load_scenario, parse_scenario
    from csuas.defaults import scenario_path

    source = spec.scenario if spec.scenario is not None else site.get("scenario", "default")
    if isinstance(source, dict):
        data = dict(source)
    else:
        import tomllib

        path = Path(source)
        if base is not None and not path.is_absolute() and (base / path).is_file():
            path = base / path
        if not path.is_file():
            path = Path(str(scenario_path(str(source))))
        if not path.is_file():
            return load_scenario(source)  # its own error, naming the scenario
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    data["target"] = {**data.get("target", {}), "preset": spec.drone.target}
    return parse_scenario(data, str(data.get("name", "scenario")))


def build(spec, spec_dir: Path | None):
    """The :class:`csuas.render.engagement.simulate.Engagement` of a validated spec (site, scenario, sensors)."""
    from csuas.base.fileio import read_spec
    from csuas.commands.coverage import load_dem, validated_site
    from csuas.core.coverage import POINTING, SitedSensor
    from csuas.defaults import load_birds, load_clutter, site_path
    from csuas.render.engagement.sensors import (
        ENGAGED_MODALITIES,
        LOOK_DEFAULTS,
        LookSettings,
        SensorModel,
        Terrain,
    )
    from csuas.render.engagement.simulate import BirdSettings, DronePath, Engagement

    site_source = spec.site
    if spec_dir is not None and (spec_dir / site_source).is_file():
        site_source = str(spec_dir / site_source)
    site = read_spec(site_source, site_path, "site")
    scenario = _scenario(spec, site, spec_dir)
    chosen = spec.sensors or list(site.get("sensors", {}))
    missing = [
        ParameterError("sensors", n, "sensors of the site: " + ", ".join(site.get("sensors", {})))
        for n in chosen
        if n not in site.get("sensors", {})
    ]
    raise_all(missing)
    site = {**site, "sensors": {n: site["sensors"][n] for n in chosen}}
    site.pop("radio_map", None)
    site.pop("fusion_k", None)
    checked = validated_site(site, scenario)
    errors = [
        ParameterError(
            f"sensors.{n}",
            scenario.sensors[n].modality,
            "a modality engage simulates: " + ", ".join(ENGAGED_MODALITIES),
        )
        for n in chosen
        if scenario.sensors[n].modality not in ENGAGED_MODALITIES
    ]
    errors += [
        ParameterError(f"looks.{n}", n, "a sensor taking part: " + ", ".join(chosen))
        for n in spec.looks
        if n not in chosen
    ]
    raise_all(errors)
    site_file = Path(site_source)
    dem, transform, _, cell = load_dem(checked.dem, site_file if site_file.is_file() else None)
    terrain = Terrain(dem, cell, float(transform.c), float(transform.f))
    waypoints = np.array(spec.drone.waypoints, float)
    rows, cols = terrain.rowcol(waypoints[:, 0], waypoints[:, 1])
    outside = ~((rows >= 0) & (rows <= dem.shape[0] - 1) & (cols >= 0) & (cols <= dem.shape[1] - 1))
    raise_all(
        [
            ParameterError(f"drone.waypoints[{i}]", spec.drone.waypoints[i], "a point inside the DEM")
            for i in np.flatnonzero(outside)
        ]
    )
    gamma = load_clutter()["gamma_db"]
    sensors = {}
    for name in chosen:
        table = checked.sensors[name]
        row, col = terrain.rowcol(float(table.x), float(table.y))
        pointing = {key: float(getattr(table, key)) for key in POINTING}
        sited = SitedSensor(name, float(row), float(col), float(table.mast_m), **pointing)
        modality = scenario.sensors[name].modality
        given = spec.looks[name].model_dump(exclude_none=True) if name in spec.looks else {}
        settings = LookSettings(**{**LOOK_DEFAULTS[modality], **given})
        sensors[name] = SensorModel(scenario, sited, terrain, settings, gamma[settings.land_cover])
    birds = BirdSettings(spec.confusers.birds_per_km2, tuple(spec.confusers.bird_classes), spec.confusers.radius_m)
    path = DronePath(waypoints, spec.drone.speed_m_s)
    return Engagement(
        terrain,
        sensors,
        path,
        birds,
        tuple(spec.tracker.confirm),
        spec.tracker.delete_after_misses,
        spec.seed,
        load_birds(),
    )


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
    from csuas.base.fileio import prepare_output_dir, read_spec, write_text_atomic
    from csuas.base.paths import inside
    from csuas.render.engagement.metrics import curves, looks_table, summarise
    from csuas.render.engagement.spec import parse_spec

    if args.print_example:
        return {"example": _spec_source("example").read_text(encoding="utf-8")}
    if args.spec is None or args.out is None:
        raise ParameterError("spec / --out", args.spec, "a spec (or example) and --out DIR, or --print-example")
    if not args.max_seconds > 0:
        raise ParameterError("--max-seconds", args.max_seconds, "a time > 0 [s]")
    if not 1 <= args.workers <= 256:
        raise ParameterError("--workers", args.workers, "1 to 256 processes")
    spec = parse_spec(read_spec(args.spec, _spec_source, "engagement spec"))
    source = Path(args.spec)
    engagement = build(spec, source.parent if source.is_file() else None)
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
    map_png, curve_png, summary = (inside(out, name) for name in ("engage_map.png", "engage_curve.png", "engage.json"))
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
    from csuas.commands.engage_plots import curve_plot, map_plot

    result["map_png"] = str(map_plot(map_png, engagement, records, result["metrics"]))
    result["curve_png"] = str(curve_plot(curve_png, engagement, result["curves"], result["metrics"]))
    write_text_atomic(summary, json.dumps(result, indent=1, allow_nan=False))
    result["out"] = str(out)
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

    Lives beside the command because the example's site is read by the command line's site loader. Each
    figure times only the runs (the engagement is built before the timer).
    """
    from csuas.base.fileio import read_spec
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
