"""What each sensor of a scenario reports for a swarm (``target.swarm``): the first detection of any member,
the groups it resolves there and their Pd against range (docs/scenarios.md "Swarms").

Each sensor sees the groups of :func:`csuas.core.swarm.groups_at` at a range; a group is the scenario's
target with the merged signature of its members (:func:`group_target`), evaluated by the same model as
one drone (:func:`csuas.core.ranges.evaluate`, horizon caps included). The modality's resolution:

- radar: a cell c / (2 B) deep and R theta_3 wide (:mod:`csuas.core.swarm`); a group's RCS is k sigma
  (the mean of k random-phase returns); its fluctuation keeps the sensor's Swerling case (the sum of k
  random phasors tends to a Rayleigh amplitude, Swerling 1/2, as k grows).
- eo, tir: blobs merge when the gap is under one pixel; a group's critical dimension is that of its
  bounding box, its projected area k A_p.
- acoustic: one receiver hears one source of level SL + 10 log10 N (the drones' sources incoherent).
- rf: each drone's link is a separate emitter (its own hopping channels or time slots, so emissions do not
  overlap): every drone is detected alone, at the range of one.
- lidar: a beam of milliradians and nanosecond range gates resolve drones metres apart: each drone alone.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from csuas.core import false_alarms
from csuas.core.fusion import approach_looks, cumulative_pd, first_detection
from csuas.core.pd_curves import sensor_pd
from csuas.core.ranges import evaluate
from csuas.core.result import Term
from csuas.core.scenario import Scenario, SensorSpec
from csuas.core.swarm import blob_critical_m, first_detection_m, groups_at, incoherent_sum_db, link_range_m

#: How each modality treats the swarm (the JSON's ``swarm.assumption``).
ASSUMPTIONS = {
    "radar": "drones within one range cell (c/2B) and one beamwidth merge; a merged group's RCS is k sigma "
    "(mean of the coherent sum of k random-phase returns), fluctuating by the sensor's Swerling case",
    "eo": "blobs merge when the gap between drones is under one pixel; a merged blob's d_crit is its bounding box's",
    "tir": "blobs merge when the gap between drones is under one pixel; a merged blob's d_crit is its bounding box's",
    "acoustic": "one source of level SL + 10 log10 N (N incoherent sources of equal level)",
    "rf": "N separate emitters (each link on its own channels or time slots): each drone detected alone",
    "lidar": "a beam of milliradians and nanosecond range gates resolve drones metres apart: each drone alone",
}
#: A modality without a swarm rule of its own sees each drone alone.
EACH_ALONE = "no swarm rule for this modality: each drone alone"


@dataclass(frozen=True)
class Cells:
    """A sensor's resolution cell: depth along the line of sight [m], width across at 0 m [m] and its growth
    with range [m/m] (:func:`csuas.core.swarm.link_range_m`), with the terms that set it."""

    along_m: float
    across_m: float
    across_per_m: float
    terms: tuple


def sensor_cells(scenario: Scenario, sensor: SensorSpec) -> Cells:
    """The resolution cell of one sensor for ``scenario``'s swarm (the module's list)."""
    p, modality = sensor.params, sensor.modality
    if modality == "radar":
        depth = float(false_alarms.range_resolution_m(p["bandwidth_mhz"]))
        beam = float(false_alarms.beamwidth_deg(p["g_rx_db"]))
        return Cells(
            depth,
            0.0,
            float(np.radians(beam)),
            (
                Term("range_resolution_m", depth, "m", "c / (2 B)"),
                Term("beamwidth_deg", beam, "deg", "sqrt(4 pi / G_rx), Skolnik Eq. 9.2"),
            ),
        )
    if modality in ("eo", "tir"):
        ifov = float(np.radians(p["hfov_deg"]) / p["n_h"])
        return Cells(np.inf, scenario.target["d_crit_m"], ifov, (Term("ifov_mrad", ifov * 1e3, "mrad", "HFOV / N_H"),))
    if modality == "acoustic":
        return Cells(np.inf, np.inf, 0.0, ())
    return Cells(0.0, 0.0, 0.0, ())  # rf, lidar: each drone alone


def group_target(scenario: Scenario, modality: str, members) -> dict:
    """The target of one merged group of drones (indices ``members`` of the formation): the module's list."""
    t, k = dict(scenario.target), len(members)
    if modality == "radar":
        t["sigma_radar_m2"] = k * t["sigma_radar_m2"]
    elif modality in ("eo", "tir"):
        t["d_crit_m"] = blob_critical_m(scenario.swarm.offsets_m[members], t["d_crit_m"])
        t["projected_area_m2"] = k * t["projected_area_m2"]
    elif modality == "acoustic":
        t["sl_db"] = t["sl_db"] + incoherent_sum_db(k)
    return t


def _one_sensor(scenario: Scenario, name: str) -> Scenario:
    return replace(scenario, sensors={name: scenario.sensors[name]})


def _scalar_range(scenario: Scenario, name: str, convention: str) -> float:
    """One sensor's range [m] (a scenario's parameters are single values: one range)."""
    return float(np.asarray(evaluate(scenario, convention)[name].range_m))


def formation_json(scenario: Scenario) -> dict:
    """The declared formation (``csuas range --json``'s and ``pd --json``'s top-level ``swarm``)."""
    return {
        "count": scenario.swarm.count,
        "formation": scenario.swarm.kind,
        "offsets_m": scenario.swarm.offsets_m.tolist(),
    }


def swarm_range(scenario: Scenario, name: str, convention: str) -> dict:
    """The swarm's figures for one sensor (``csuas range --json``'s ``sensors.NAME.swarm``).

    Returns
    -------
    dict
        ``count``, ``single_drone_range_m``, ``first_detection_m`` (longest range at which any resolved
        group is detected [m]), ``resolved_count`` and ``largest_group`` there, ``terms`` and ``assumption``.
    """
    sensor = scenario.sensors[name]
    one = _one_sensor(scenario, name)
    cells = sensor_cells(scenario, sensor)
    link = link_range_m(scenario.swarm.offsets_m, cells.along_m, cells.across_m, cells.across_per_m)

    def group_range(members) -> float:
        return _scalar_range(replace(one, target=group_target(scenario, sensor.modality, members)), name, convention)

    first = first_detection_m(link, group_range)
    groups = groups_at(link, first) if first > 0 else groups_at(link, np.inf)
    terms = list(cells.terms)
    if sensor.modality == "radar":
        cross = float(first * cells.across_per_m)
        terms.append(Term("cross_range_resolution_m", cross, "m", "R theta_3 at first_detection_m"))
    if sensor.modality in ("eo", "tir") and first > 0:
        pixel_m = float(first * cells.across_per_m)
        terms.append(Term("drone_pixels", scenario.target["d_crit_m"] / pixel_m, "px", "d_crit / (R IFOV)"))
        largest = max(groups, key=len)
        span = np.ptp(scenario.swarm.offsets_m[largest], axis=0) + scenario.target["d_crit_m"]
        terms.append(Term("largest_blob_width_px", float(span[1] / pixel_m), "px", "(span_y + d_crit) / (R IFOV)"))
        terms.append(Term("largest_blob_height_px", float(span[2] / pixel_m), "px", "(span_z + d_crit) / (R IFOV)"))
    if sensor.modality == "acoustic":
        terms.append(Term("swarm_level_db", incoherent_sum_db(scenario.swarm.count), "dB", "10 log10 N"))
    return {
        "count": scenario.swarm.count,
        "single_drone_range_m": _scalar_range(one, name, convention),
        "first_detection_m": first,
        "resolved_count": len(groups),
        "largest_group": max(len(g) for g in groups),
        "terms": {t.name: t.as_dict() for t in terms},
        "assumption": ASSUMPTIONS.get(sensor.modality, EACH_ALONE),
    }


def swarm_first_detection_m(scenario: Scenario, name: str, convention: str | None = None) -> float:
    """The longest range at which any resolved group of the swarm is detected by sensor ``name`` [m]
    (:func:`swarm_range`'s ``first_detection_m``; the figure ``csuas sensitivity`` varies for a swarm)."""
    return float(swarm_range(scenario, name, convention or scenario.convention)["first_detection_m"])


def _pd_any_and_counts(scenario: Scenario, name: str, range_m, convention: str | None) -> tuple:
    """Pd that any group is detected, and the groups resolved, at each of ``range_m``.

    The groups at R depend only on which link ranges lie below R (:func:`csuas.core.swarm.groups_at`), so the
    ranges are binned by that count and each bin's groups found once: an approach's 10^5 looks cost a few
    bins, not 10^5 graph searches. Pd_any = 1 - prod_g (1 - Pd_g(R)), the groups' fluctuations independent.
    """
    sensor = scenario.sensors[name]
    r = np.asarray(range_m, dtype=float)
    cells = sensor_cells(scenario, sensor)
    link = link_range_m(scenario.swarm.offsets_m, cells.along_m, cells.across_m, cells.across_per_m)
    below = np.searchsorted(np.unique(link[np.isfinite(link)]), r, side="left")  # link ranges under each R
    miss, counts = np.ones_like(r), np.zeros(r.shape, dtype=int)
    for b in np.unique(below):
        idx = np.flatnonzero(below == b)
        groups = groups_at(link, r[idx[0]])
        counts[idx] = len(groups)
        for g in groups:
            variant = replace(scenario, target=group_target(scenario, sensor.modality, g))
            miss[idx] *= 1.0 - sensor_pd(variant, name, r[idx], convention).pd
    return 1.0 - miss, counts


def swarm_pd(scenario: Scenario, name: str, range_m, convention: str | None = None) -> dict:
    """Pd that any group of the swarm is detected, and the groups resolved, on ``range_m``
    (``csuas pd --json``'s ``sensors.NAME.swarm``, beside :func:`swarm_range`'s keys): ``pd_any`` =
    1 - prod_g (1 - Pd_g(R)), the groups' fluctuations independent; ``resolved_count_at_range``.
    """
    pd_any, counts = _pd_any_and_counts(scenario, name, range_m, convention)
    return {"pd_any": pd_any, "resolved_count_at_range": counts}


#: How an approach's looks at a swarm combine (``csuas pd --approach-speed-m-s``'s swarm ``assumption``).
APPROACH_LOOKS = {
    "independent": "each look draws every resolved group afresh: 1 - prod over looks of (1 - Pd_any)",
    "correlated": "one draw for the whole approach: the running maximum of Pd_any (a lower bound where "
    "separately resolved groups fluctuate independently)",
}


def swarm_approach(
    scenario: Scenario, name: str, speed_m_s: float, start_range_m: float, stop_range_m: float, convention=None
) -> dict:
    """The swarm closing at constant speed from ``start_range_m``, seen at sensor ``name``'s look rate: the
    cumulative Pd that any drone has been detected and the groups resolved over time
    (``csuas pd --approach-speed-m-s``'s ``sensors.NAME.swarm``), the swarm's counterpart of
    :func:`csuas.core.pd_curves.approach`.

    Returns
    -------
    dict
        ``look_range_m`` (far to near) and ``cumulative_pd`` after each look (:func:`cumulative_pd` of
        Pd_any by the sensor's ``looks``), ``median_range_m`` of the first detection of any drone (a look;
        None when the approach ends first) and ``median_time_s`` its time from the start, ``never``,
        ``resolved_count_changes`` (``time_s`` from the start, ``range_m`` and ``resolved_count`` at the first
        look and at every look where the count changes) and ``assumption`` (:data:`APPROACH_LOOKS`).
    """
    correlation = scenario.sensors[name].params["looks"]
    looks = approach_looks(start_range_m, stop_range_m, speed_m_s, scenario.sensors[name].params["look_rate_hz"])
    pd_any, counts = _pd_any_and_counts(scenario, name, looks, convention)
    cumulative = cumulative_pd(pd_any, correlation)
    first = first_detection(looks, cumulative)
    changes = np.flatnonzero(np.diff(counts, prepend=-1))
    return {
        "look_range_m": looks,
        "cumulative_pd": cumulative,
        "median_range_m": first["median_range_m"],
        "median_time_s": None
        if first["median_range_m"] is None
        else (start_range_m - first["median_range_m"]) / speed_m_s,
        "never": float(first["never"]),
        "resolved_count_changes": [
            {
                "time_s": float((start_range_m - looks[i]) / speed_m_s),
                "range_m": float(looks[i]),
                "resolved_count": int(counts[i]),
            }
            for i in changes
        ],
        "assumption": APPROACH_LOOKS[correlation],
    }
