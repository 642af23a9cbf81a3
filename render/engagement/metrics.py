"""The metrics of an engagement over its Monte Carlo runs (``engage.json``'s ``metrics``, ``looks`` and ``curves``).

Percentiles (10th, 50th, 90th) run over every run: a run whose drone is never confirmed counts as
an infinitely late first track and a first-track range of -inf, so a percentile that falls among them
is null, and ``never_fraction`` says how many; its warning time is 0 (no warning). Rates per hour
divide counts by the simulated flight time, runs x the drone's flight to the protected point. The
cumulative probability of a confirmed track at a distance d from the protected point is the share of
runs whose first track came at a distance of at least d, with its binomial standard error.
"""

from __future__ import annotations

import numpy as np

from csuas.core import false_alarms
from csuas.core.fusion import cumulative_pd
from csuas.core.m_of_n import first_confirmation
from csuas.render.engagement.siap import SCORES
from csuas.render.engagement.simulate import CAUSES, Engagement

#: Points of the distance grid of the curves.
CURVE_POINTS = 200


def _percentiles(values) -> dict:
    """10th, 50th and 90th percentiles (inclusive, 'lower') of values with +-inf for the runs that never confirm."""
    data = np.sort(np.asarray(values, float))
    out = {}
    for key, q in (("p10", 10), ("median", 50), ("p90", 90)):
        v = float(np.percentile(data, q, method="lower")) if data.size else float("nan")
        out[key] = v if np.isfinite(v) else None
    return out


def _classified(runs: list, kept: dict) -> dict:
    """``classified``: false tracks per hour by cause once the drone-or-bird decision rejects tracks, and the
    share of the drone's tracks it rejected (null without drone tracks)."""
    drone = sum(r["drone_tracks"] for r in runs)
    rejected = sum(r["drone_tracks_rejected"] for r in runs)
    return {
        "classified": {
            "false_tracks_per_hour": {"total": float(sum(kept.values())), "by_cause": kept},
            "drone_tracks_rejected_fraction": rejected / drone if drone else None,
        }
    }


def summarise(engagement: Engagement, runs: list) -> dict:
    """``metrics`` of engage.json from the runs' records (:func:`csuas.render.engagement.simulate.run_once`)."""
    hours = len(runs) * engagement.path.duration_s / 3600.0
    never = np.array([r["first_track_time_s"] is None for r in runs])
    times = [np.inf if r["first_track_time_s"] is None else r["first_track_time_s"] for r in runs]
    ranges = [-np.inf if r["first_track_range_m"] is None else r["first_track_range_m"] for r in runs]
    by_cause = {c: sum(1 for r in runs for f in r["false_tracks"] if f["cause"] == c) / hours for c in CAUSES}
    kept = {
        c: sum(1 for r in runs for f in r["false_tracks"] if f["cause"] == c and not f["rejected"]) / hours
        for c in CAUSES
    }
    alarms = {}
    for name, sensor in engagement.sensors.items():
        noise = sum(r["false_alarms"][name]["noise"] for r in runs) / hours
        clutter = sum(r["false_alarms"][name]["clutter"] for r in runs) / hours
        expected_count = sensor.false_alarms_per_look * len(engagement.looks[name].t_s) * len(runs)
        alarms[name] = {
            "total": noise + clutter,
            "noise": noise,
            "clutter": clutter,
            "noise_expected": expected_count / hours,
            "noise_stderr": float(np.sqrt(expected_count)) / hours,
            "noise_expected_steady": float(
                false_alarms.per_hour(sensor.false_alarms_per_look, sensor.settings.revisit_s)
            ),
            "cells_per_look": sensor.cells,
            "pfa": sensor.pfa,
        }
    continuity = [r["track_continuity"] for r in runs if r["track_continuity"] is not None]
    gospa = [r["gospa_mean"] for r in runs if r["gospa_mean"] is not None]
    out = {
        "first_track_time_s": {**_percentiles(times), "never_fraction": float(never.mean())},
        "first_track_range_m": {**_percentiles(ranges), "never_fraction": float(never.mean())},
        "warning_time_s": _percentiles([r["warning_time_s"] for r in runs]),
        "false_tracks_per_hour": {"total": float(sum(by_cause.values())), "by_cause": by_cause},
        **(_classified(runs, kept) if engagement.classifier is not None else {}),
        "false_alarms_per_hour": alarms,
        "track_continuity": float(np.mean(continuity)) if continuity else None,
        "gospa_mean": float(np.mean(gospa)) if gospa else None,
        "siap": {name: float(np.mean([r["siap"][name] for r in runs])) for name in SCORES},
        "simulated_hours": hours,
    }
    if engagement.swarm is not None:
        first = [np.inf if r["first_detection_time_s"] is None else r["first_detection_time_s"] for r in runs]
        out["swarm"] = {
            "count": engagement.swarm.count,
            "first_detection_time_s": _percentiles(first),
            "drone_tracks_max": _percentiles([r["drone_tracks_max"] for r in runs]),
            "drone_tracks_confirmed": _percentiles([r["drone_tracks_confirmed"] for r in runs]),
        }
    return out


def looks_table(engagement: Engagement) -> dict:
    """``looks.<sensor>``: the drone at each look (t, x, y, slant range, line of sight and field of regard, Pd);
    with a swarm also ``resolved_count`` (groups the sensor resolves) and ``pd_any`` (any group detected)."""
    table = {
        name: {
            "t_s": looks.t_s.tolist(),
            "x": looks.x.tolist(),
            "y": looks.y.tolist(),
            "slant_range_m": looks.slant_range_m.tolist(),
            "visible": (looks.visible & looks.in_regard).tolist(),
            "pd": looks.pd.tolist(),
        }
        for name, looks in engagement.looks.items()
    }
    for name, swarm in engagement.swarm_looks.items():
        table[name].update(resolved_count=swarm.resolved_count.tolist(), pd_any=swarm.pd_any.tolist())
    return table


def curves(engagement: Engagement, runs: list) -> dict:
    """Cumulative probabilities against the drone's ground distance to the protected point [m].

    The distance is the one the drone still has to fly (``DronePath.to_go_m``). ``confirmed_track``:
    share of runs with a confirmed drone track by then (and its standard error); per sensor,
    ``cumulative_pd`` (at least one detection; independent looks, or the running maximum for a sensor
    whose looks are fully correlated) and ``m_of_n`` (that sensor alone confirming M of N with
    independent looks, :func:`csuas.core.m_of_n.first_confirmation`; null for correlated looks), at
    the sensor's looks.
    """
    grid = np.linspace(0.0, engagement.path.to_go_m(0.0), CURVE_POINTS)
    ranges = np.array([np.nan if r["first_track_range_m"] is None else r["first_track_range_m"] for r in runs])
    share = np.array([np.mean(np.nan_to_num(ranges, nan=-1.0) >= d) for d in grid])
    out = {
        "distance_m": grid.tolist(),
        "confirmed_track": share.tolist(),
        "confirmed_track_stderr": np.sqrt(share * (1 - share) / len(runs)).tolist(),
        "sensors": {},
    }
    m, n = engagement.confirm
    for name, looks in engagement.looks.items():
        correlated = bool(np.all(looks.correlation[1:] == 1.0))
        out["sensors"][name] = {
            "distance_m": [engagement.path.to_go_m(t) for t in looks.t_s],
            "cumulative_pd": cumulative_pd(looks.pd, "correlated" if correlated else "independent").tolist(),
            "m_of_n": None if correlated else np.cumsum(first_confirmation(looks.pd, m, n)).tolist(),
        }
    return out
