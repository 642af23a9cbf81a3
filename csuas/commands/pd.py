"""``csuas pd SCENARIO``: probability of detection against range for every sensor, and fused (docs/detection.md).

JSON (``--json``): top-level ``range_m`` (the grid) and, aligned with it, ``sensors.<name>.pd``;
per sensor also ``range_at_pd`` (keys ``"0.5"`` and ``"0.9"``: metres, solved on the model rather
than read off the grid, or null when never reached), ``deterministic_range_m`` and
``pd_at_deterministic_range`` (the paper's range and the Pd its threshold implies),
``assumptions``, ``looks`` and ``look_rate_hz``; ``fused.pd``,
``fused.rule`` and ``fused.range_at_pd``. With ``--approach-speed-m-s`` also ``cumulative_pd``
(aligned with ``range_m``: detected by the time the drone, closing from the grid's far end,
reaches that range) and ``median_first_detection_range_m`` (the median of the discrete
first-detection distribution: a look) per sensor and fused, the fused ones by ``--fusion``'s rule
(k-of-n: at least K sensors have each detected by then); per sensor with independent looks and a
Pfa, ``false_alarm_cumulative_pd``, what noise crossings alone put in its ``cumulative_pd``.
With ``target.swarm`` also a top-level ``swarm`` (the formation) and per sensor ``swarm``: ``csuas range``'s
swarm keys and, aligned with ``range_m``, ``pd_any`` (any resolved group detected) and
``resolved_count_at_range``; the other keys stay one drone's. With a swarm and ``--approach-speed-m-s``, each
sensor's ``swarm`` also holds ``cumulative_pd_any`` (aligned with ``range_m``: any drone detected by then),
``median_first_detection_range_m`` and ``median_first_detection_time_s`` (of any drone, the time from the approach's
start), ``resolved_count_changes`` (``time_s``, ``range_m``,
``resolved_count`` where the groups change along the approach) and ``approach_assumption``; ``fused.swarm``
the fused ``cumulative_pd_any`` and ``median_first_detection_range_m`` by ``--fusion``'s rule.
Every radio and optical sensor's Pd is 0 beyond its line-of-sight horizon: that of its
``height_m``, or without one that of the reference heights ``csuas range`` flags (2 m, 120 m).
With ``--micro-doppler`` each radar also reports ``micro_doppler`` (:mod:`csuas.render.rcs.drone_or_bird`):
the drone as a Doppler-spread target, its blade lines' SNR and the probability that its blade lines
declare it a drone (aligned with ``range_m``), against the probability that a bird is declared one.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from csuas.base.errors import ParameterError, raise_all
from csuas.base.paths import output_file
from csuas.base.plots import pd_plot
from csuas.core import radar
from csuas.core.pd_curves import (
    FALSE_ALARM_NOTE,
    GRID_BEYOND,
    GRID_POINTS,
    REPORTED_PD,
    approach,
    default_range_grid,
    fuse,
    fused_cumulative,
    fused_first_detection_m,
    fused_pd_of_range,
    margin_db,
    range_at_pd,
    sensor_pd,
)
from csuas.core.scenario import load_scenario
from csuas.core.swarm_detection import formation_json, swarm_approach, swarm_pd, swarm_range
from csuas.render.rcs.drone_or_bird import ClassifierSettings, drone_or_bird


def add_arguments(parser):
    """Declare the options of ``csuas pd``."""
    parser.add_argument("scenario", help="scenario TOML file, or an embedded scenario name")
    parser.add_argument(
        "--range-m",
        type=float,
        nargs="+",
        default=None,
        metavar="R",
        help=f"slant ranges [m] (default: {GRID_POINTS} log-spaced from 1 m to {GRID_BEYOND:g}x the longest range)",
    )
    parser.add_argument("--fusion", default="or", help="or (default), or k-of-n:K (at least K sensors detect)")
    parser.add_argument(
        "--approach-speed-m-s",
        type=float,
        default=None,
        metavar="V",
        help="closing speed of a drone flying in from the grid's far end: cumulative Pd and median first detection",
    )
    parser.add_argument("--plot", default=None, metavar="FILE.png", help="write Pd against range (and the approach)")
    parser.add_argument(
        "--convention", choices=("paper", "physical"), default=None, help="override the scenario's convention"
    )
    defaults = ClassifierSettings()
    parser.add_argument(
        "--micro-doppler",
        action="store_true",
        help="radars also report the drone's blade lines and the drone-or-bird decision (docs/detection.md)",
    )
    parser.add_argument(
        "--micro-doppler-prf-hz", type=float, default=defaults.prf_hz, help="PRF of the Doppler dwell [Hz]"
    )
    parser.add_argument(
        "--micro-doppler-dwell-s", type=float, default=defaults.dwell_s, help="Doppler dwell [s] (default 0.05)"
    )
    parser.add_argument(
        "--micro-doppler-elevation-deg",
        type=float,
        default=defaults.elevation_deg,
        help="radar elevation in the drone's frame, above a multirotor's rotor plane [deg] (default 10)",
    )
    parser.add_argument(
        "--micro-doppler-azimuth-deg",
        type=float,
        default=defaults.azimuth_deg,
        help="radar azimuth from the drone's nose [deg] (default 0: approaching; sets a pusher's aspect)",
    )


def _grid(scenario, args) -> np.ndarray:
    if args.range_m is not None:
        return np.asarray(sorted(args.range_m), dtype=float)
    return default_range_grid(scenario, args.convention)


def _check(args) -> None:
    errors = []
    if args.range_m is not None:
        bad = [r for r in args.range_m if not (np.isfinite(r) and r >= 0)]
        if bad or not args.range_m:
            errors.append(ParameterError("range_m", bad[0] if bad else args.range_m, "ranges >= 0 [m], finite"))
    if args.approach_speed_m_s is not None and not (
        np.isfinite(args.approach_speed_m_s) and args.approach_speed_m_s > 0
    ):
        errors.append(ParameterError("approach_speed_m_s", args.approach_speed_m_s, "> 0 [m/s], finite"))
    kind, _, k = args.fusion.partition(":")
    if args.fusion != "or" and not (kind == "k-of-n" and k.isdigit() and int(k) >= 1):
        errors.append(ParameterError("fusion", args.fusion, "or, or k-of-n:K with K a whole number >= 1"))
    if args.plot is not None and not args.plot.lower().endswith(".png"):
        errors.append(ParameterError("plot", args.plot, "a file name ending in .png"))
    elif args.plot is not None:
        try:
            output_file(args.plot, "plot")
        except ParameterError as exc:
            errors.append(exc)
    raise_all(errors)


def _at_pd(pd_of_range, search_m) -> dict:
    return dict(zip((f"{p:g}" for p in REPORTED_PD), range_at_pd(pd_of_range, search_m, REPORTED_PD)))


def _approaches(scenario, args, grid, out) -> None:
    """Each sensor's approach from the grid's far end, fused by the same rule as the Pd per look."""
    approaches = []
    for name, sensor in out["sensors"].items():
        a = approach(scenario, name, args.approach_speed_m_s, float(grid[-1]), float(grid[0]), args.convention)
        approaches.append(a)
        sensor["cumulative_pd"] = fused_cumulative([a], grid)
        sensor["median_first_detection_range_m"] = a["median_range_m"]
        sensor["approach_notes"] = a["notes"]
        if a["false_alarm_cumulative"] is not None:
            sensor["false_alarm_cumulative_pd"] = fused_cumulative(
                [{"look_range_m": a["look_range_m"], "cumulative_pd": a["false_alarm_cumulative"]}], grid
            )
    out["approach_speed_m_s"] = args.approach_speed_m_s
    out["fused"]["cumulative_pd"] = fused_cumulative(approaches, grid, args.fusion)
    out["fused"]["median_first_detection_range_m"] = fused_first_detection_m(approaches, args.fusion)
    if scenario.swarm is not None:
        _swarm_approaches(scenario, args, grid, out)


def _swarm_approaches(scenario, args, grid, out) -> None:
    """The swarm along the same approach: each sensor's and the fused first detection of any drone and the
    groups resolved over time (:func:`swarm_approach`), beside one drone's keys."""
    approaches = []
    for name, sensor in out["sensors"].items():
        a = swarm_approach(scenario, name, args.approach_speed_m_s, float(grid[-1]), float(grid[0]), args.convention)
        approaches.append(a)
        sensor["swarm"].update(
            cumulative_pd_any=fused_cumulative([a], grid),
            median_first_detection_range_m=a["median_range_m"],
            median_first_detection_time_s=a["median_time_s"],
            resolved_count_changes=a["resolved_count_changes"],
            approach_assumption=a["assumption"],
        )
    out["fused"]["swarm"] = {
        "cumulative_pd_any": fused_cumulative(approaches, grid, args.fusion),
        "median_first_detection_range_m": fused_first_detection_m(approaches, args.fusion),
    }


def _plot(args, scenario, grid, curves, out) -> str:

    cumulative, false_alarms = None, None
    if "approach_speed_m_s" in out:
        cumulative = {name: s["cumulative_pd"] for name, s in out["sensors"].items()}
        cumulative[f"fused ({args.fusion})"] = out["fused"]["cumulative_pd"]
        false_alarms = {
            name: s["false_alarm_cumulative_pd"]
            for name, s in out["sensors"].items()
            if "false_alarm_cumulative_pd" in s and s["false_alarm_cumulative_pd"][0] > FALSE_ALARM_NOTE
        }
    return str(
        pd_plot(
            Path(args.plot),
            f"Pd against range, scenario {scenario.name} ({out['convention']} convention)",
            grid,
            {c.sensor: c.pd for c in curves},
            fused=(f"fused ({args.fusion})", out["fused"]["pd"]),
            markers={c.sensor: (c.deterministic_range_m, c.pd_at_deterministic_range) for c in curves},
            cumulative=cumulative,
            false_alarms=false_alarms,
        )
    )


def _classifier(args) -> ClassifierSettings:
    settings = ClassifierSettings(
        args.micro_doppler_prf_hz,
        args.micro_doppler_dwell_s,
        args.micro_doppler_elevation_deg,
        args.micro_doppler_azimuth_deg,
    )
    return settings.check("micro_doppler")


def _micro_doppler(scenario, args, grid, out) -> None:
    """``sensors.<radar>.micro_doppler``: the drone-or-bird decision on the grid (:func:`drone_or_bird`)."""
    convention = args.convention or scenario.convention
    for name, sensor in scenario.sensors.items():
        if sensor.modality != "radar":
            continue
        p = sensor.params
        gain_db = 10 * np.log10(float(radar.integration_gain(int(p["n_pulses"]), p["integration"], convention)))
        snr1_db = p["snr_min_db"] - gain_db + margin_db(scenario, sensor, convention, grid)
        result = drone_or_bird(scenario, p, snr1_db, _classifier(args))
        result["pd_detected_and_classified"] = out["sensors"][name]["pd"] * result["pd_classified_drone"]
        out["sensors"][name]["micro_doppler"] = result


def run(args) -> dict:
    """Pd of every sensor of the scenario on the grid, fused, and along an approach."""
    _check(args)
    if args.micro_doppler:
        _classifier(args)
    scenario = load_scenario(args.scenario)
    grid = _grid(scenario, args)
    curves = [sensor_pd(scenario, name, grid, args.convention) for name in scenario.sensors]
    if args.fusion != "or" and int(args.fusion.partition(":")[2]) > len(curves):
        raise ParameterError("fusion", args.fusion, f"K at most {len(curves)}, the scenario's sensors")
    # ranges at Pd are solved on the model; the grid and the default grid only bracket them
    search = np.union1d(grid[grid > 0], default_range_grid(scenario, args.convention))
    fused = fuse(curves, args.fusion)
    out = {
        "scenario": scenario.name,
        "convention": args.convention or scenario.convention,
        "range_m": grid,
        "sensors": {},
        "fused": {
            "pd": fused,
            "rule": args.fusion,
            "range_at_pd": _at_pd(fused_pd_of_range(scenario, args.fusion, args.convention), search),
        },
    }
    for c in curves:
        out["sensors"][c.sensor] = {
            "modality": c.modality,
            "pd": c.pd,
            "range_at_pd": _at_pd(lambda r, name=c.sensor: sensor_pd(scenario, name, r, args.convention).pd, search),
            "deterministic_range_m": c.deterministic_range_m,
            "pd_at_deterministic_range": c.pd_at_deterministic_range,
            "assumptions": c.assumptions,
            "looks": c.looks,
            "look_rate_hz": c.look_rate_hz,
        }
    if scenario.swarm is not None:
        out["swarm"] = formation_json(scenario)
        for name, sensor in out["sensors"].items():
            sensor["swarm"] = {
                **swarm_range(scenario, name, out["convention"]),
                **swarm_pd(scenario, name, grid, args.convention),
            }
    if args.micro_doppler:
        _micro_doppler(scenario, args, grid, out)
    if args.approach_speed_m_s is not None:
        _approaches(scenario, args, grid, out)
    if args.plot is not None:
        out["plot"] = _plot(args, scenario, grid, curves, out)
    return out


def _metres(value) -> str:
    return "never" if value is None else f"{value:,.1f} m"


def render_text(result: dict) -> str:
    """One row per sensor: the paper's range and its Pd, the ranges of Pd 0.5 and 0.9, the assumptions."""
    lines = [f"scenario {result['scenario']} ({result['convention']} convention), Pd per look"]
    approach_on = "approach_speed_m_s" in result
    header = f"  {'sensor':<14}{'R* (paper)':>14}{'Pd(R*)':>8}{'R(Pd=0.5)':>14}{'R(Pd=0.9)':>14}"
    lines.append(header + (f"{'median first':>16}" if approach_on else ""))
    for name, s in result["sensors"].items():
        pd_star = "-" if s["pd_at_deterministic_range"] is None else f"{s['pd_at_deterministic_range']:.3f}"
        row = (
            f"  {name:<14}{_metres(s['deterministic_range_m']):>14}{pd_star:>8}"
            f"{_metres(s['range_at_pd']['0.5']):>14}{_metres(s['range_at_pd']['0.9']):>14}"
        )
        lines.append(row + (f"{_metres(s['median_first_detection_range_m']):>16}" if approach_on else ""))
    f = result["fused"]
    at = f["range_at_pd"]
    row = f"  {'fused ' + f['rule']:<14}{'':>14}{'':>8}{_metres(at['0.5']):>14}{_metres(at['0.9']):>14}"
    lines.append(row + (f"{_metres(f['median_first_detection_range_m']):>16}" if approach_on else ""))
    if approach_on:
        lines.append(f"approach at {result['approach_speed_m_s']:g} m/s from {result['range_m'][-1]:,.0f} m")
    for name, s in result["sensors"].items():
        if "swarm" in s:
            w = s["swarm"]
            lines.append(
                f"  {name}: swarm of {w['count']}, first detection of any {_metres(w['first_detection_m'])} "
                f"({w['resolved_count']} resolved there); Pd of any: sensors.{name}.swarm.pd_any (--json)"
            )
            if approach_on:
                median = _metres(w["median_first_detection_range_m"])
                lines.append(f"    approach: median first detection of any {median}")
    lines.append("assumptions:")
    for name, s in result["sensors"].items():
        lines.append(f"  {name}: " + "; ".join(s["assumptions"] + s.get("approach_notes", [])))
    if "plot" in result:
        lines.append(f"plot: {result['plot']}")
    return "\n".join(lines)
