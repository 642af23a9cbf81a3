"""Monte Carlo runs of an engagement: a drone, birds and false alarms through a site's sensors into one tracker.

One run: the drone flies its waypoints at constant speed and height above the terrain; birds
(:func:`draw_birds`) fly straight with a wandering heading at their class's airspeed and height; at
every look of every sensor (``revisit_s`` apart from t = 0) the drone is detected with the sensor's Pd
at that look (:class:`csuas.render.engagement.sensors.SensorModel`), each bird with its own Pd, and the
noise and clutter false alarms are drawn; the detections go, look by look in time order, into the
Stone Soup tracker (:mod:`csuas.render.engagement.tracker`). The drone's detection draws of one
sensor are correlated from look to look through a Gaussian copula, z_k = rho_k z_(k-1) +
sqrt(1 - rho_k^2) e_k, detected when Phi(z_k) < Pd_k: each look keeps its Pd exactly while successive
draws share the RCS fluctuation as the sensor's rule dictates (:meth:`SensorModel.look_correlation`).

Per run: the first confirmed track of the drone (its time, and the distance the drone still had to
fly to the protected point, the last waypoint: the straight-line distance on a straight approach), the
warning time (arrival at the protected point minus that time; 0 when never confirmed), every false
track (a confirmed track whose detections at confirmation came mostly from noise, clutter or birds)
with its cause, the false alarms of each sensor, GOSPA
(Stone Soup's metric; the drone is the only truth, birds are confusers) averaged over the looks, and
the track continuity (the share of looks from the first track to arrival at which a confirmed track
lies within GOSPA_C_M of the drone).

With a drone-or-bird decision (``Engagement.classifier``, spec ``[classification] micro_doppler``) every
radar detection carries ``blade_lines``: drawn true with the drone's probability of showing its blade
lines at that look's range (:func:`csuas.render.rcs.drone_or_bird.drone_or_bird`) for the drone, and
with the probability that noise alone crosses a tested Doppler bin for birds, noise and clutter (their
power stays inside the guard band). The draws come from a generator of their own, so the tracks are
those of the same run without the decision; a confirmed track whose radar detections were classified
and none showed blade lines is declared not a drone (:func:`csuas.render.engagement.tracker.declared_not_drone`):
its record says ``rejected``, and the false tracks are counted with and without the rejected ones.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from scipy.special import ndtr
from stonesoup.measures import Euclidean
from stonesoup.metricgenerator.ospametric import GOSPAMetric
from stonesoup.types.array import StateVector
from stonesoup.types.state import State

from csuas.core import radar
from csuas.core.swarm import Formation
from csuas.render.engagement.sensors import SensorModel, Terrain
from csuas.render.engagement.siap import siap_scores, truth_path
from csuas.render.engagement.swarm import member_positions, swarm_looks
from csuas.render.engagement.tracker import (
    EngagementTracker,
    declared_not_drone,
    make_detection,
    predicted_xy,
    timestamp,
)
from csuas.render.rcs.drone_or_bird import ClassifierSettings, drone_or_bird

#: GOSPA's cut-off distance c [m], order p and alpha = 2 (Rahmathullah et al. 2017).
GOSPA_C_M, GOSPA_P = 100.0, 2
#: Random-walk rate of a bird's heading [deg / sqrt(s)] (wandering flight).
BIRD_HEADING_WALK_DEG = 10.0
#: Slowest bird airspeed drawn [m/s].
BIRD_MIN_SPEED_M_S = 3.0
#: Causes of false tracks (and of detections besides the drone).
CAUSES = ("noise", "clutter", "birds")


@dataclass(frozen=True)
class DronePath:
    """Waypoints (x, y [m] in the DEM's CRS, height above the terrain [m]) flown at constant speed [m/s]."""

    waypoints: np.ndarray
    speed_m_s: float

    @property
    def legs_m(self) -> np.ndarray:
        """Ground length of each leg [m]."""
        return np.hypot(*np.diff(self.waypoints[:, :2], axis=0).T)

    @property
    def duration_s(self) -> float:
        """Time from the first waypoint to the protected point (the last) [s]."""
        return float(self.legs_m.sum() / self.speed_m_s)

    def to_go_m(self, t_s) -> float:
        """Distance the drone still has to fly to the protected point at time ``t_s`` [m] (its path's length to go)."""
        return float(self.speed_m_s * (self.duration_s - np.clip(t_s, 0.0, self.duration_s)))

    def at(self, t_s) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(x, y, height above terrain, heading [rad, from +x toward +y]) at times [s]."""
        along = np.clip(np.asarray(t_s, float), 0.0, self.duration_s) * self.speed_m_s
        ends = np.concatenate([[0.0], np.cumsum(self.legs_m)])
        leg = np.clip(np.searchsorted(ends, along, side="right") - 1, 0, len(self.legs_m) - 1)
        frac = (along - ends[leg]) / np.maximum(self.legs_m[leg], 1e-12)
        start, stop = self.waypoints[leg], self.waypoints[leg + 1]
        point = start + frac[:, None] * (stop - start)
        heading = np.arctan2(stop[:, 1] - start[:, 1], stop[:, 0] - start[:, 0])
        return point[:, 0], point[:, 1], point[:, 2], heading


@dataclass(frozen=True)
class BirdSettings:
    """Confusers: mean density [1/km^2] over the square within ``radius_m`` of the sensors, and the classes drawn."""

    density_per_km2: float
    classes: tuple
    radius_m: float = 2000.0


@dataclass
class Looks:
    """The drone as one sensor sees it at each look (the same in every run)."""

    t_s: np.ndarray
    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    slant_range_m: np.ndarray
    visible: np.ndarray
    in_regard: np.ndarray
    pd: np.ndarray
    correlation: np.ndarray


@dataclass
class Engagement:
    """A site's sensors, the drone's path, the confusers and the tracker's rule: everything a run needs."""

    terrain: Terrain
    sensors: dict
    path: DronePath
    birds: BirdSettings
    confirm: tuple
    delete_after_misses: int
    seed: int
    bird_table: dict = field(default_factory=dict)
    swarm: Formation | None = None
    classifier: ClassifierSettings | None = None
    looks: dict = field(init=False)
    swarm_looks: dict = field(init=False)
    blade_lines: dict = field(init=False)

    def __post_init__(self):
        self.looks = {name: drone_looks(self.terrain, sensor, self.path) for name, sensor in self.sensors.items()}
        self.blade_lines = {
            name: blade_line_chances(sensor, self.looks[name], self.classifier)
            for name, sensor in self.sensors.items()
            if self.classifier is not None and sensor.modality == "radar"
        }
        self.swarm_looks = {}
        if self.swarm is not None:
            self.swarm_looks = {
                name: swarm_looks(self.terrain, sensor, self.path, self.swarm, self.looks[name].t_s)
                for name, sensor in self.sensors.items()
            }

    def truth_xy(self, t_s: float) -> list:
        """The truths' (x, y) at ``t_s`` [m]: the drone, or each drone of the swarm."""
        if self.swarm is None:
            x, y, _, _ = self.path.at(np.array([t_s]))
            return [(x[0], y[0])]
        x, y, _ = member_positions(self.path, self.swarm, np.array([t_s]))
        return list(zip(x[0], y[0]))

    @property
    def protected_xy(self) -> np.ndarray:
        """The protected point: the last waypoint (x, y) [m]."""
        return self.path.waypoints[-1, :2]

    def bird_box(self) -> tuple[float, float, float, float]:
        """(west, east, south, north) [m] of the square within the birds' radius of every sensor, inside the DEM."""
        xs = [s.x for s in self.sensors.values()]
        ys = [s.y for s in self.sensors.values()]
        r, t = self.birds.radius_m, self.terrain
        south = t.north_m - t.dem_m.shape[0] * t.cell_m
        east = t.west_m + t.dem_m.shape[1] * t.cell_m
        return (
            max(min(xs) - r, t.west_m),
            min(max(xs) + r, east),
            max(min(ys) - r, south),
            min(max(ys) + r, t.north_m),
        )


def drone_looks(terrain: Terrain, sensor: SensorModel, path: DronePath) -> Looks:
    """The drone at every look of a sensor: position, slant range, line of sight, field of regard, Pd, correlation."""
    t = np.arange(0.0, path.duration_s + 1e-9, sensor.settings.revisit_s)
    x, y, h, heading = path.at(t)
    z = terrain.height(x, y) + h
    geometry = sensor.geometry(x, y, z)
    # aspect: the angle between the drone's heading and its line of sight to the sensor
    los = np.stack([sensor.x - x, sensor.y - y, sensor.eye_z - z])
    los /= np.maximum(np.linalg.norm(los, axis=0), 1e-9)
    aspect = np.arccos(np.clip(np.cos(heading) * los[0] + np.sin(heading) * los[1], -1.0, 1.0))
    change = np.abs(np.diff(aspect, prepend=aspect[:1]))
    correlation = sensor.look_correlation(change)
    correlation[0] = 0.0
    return Looks(
        t, x, y, z, geometry.slant_m, geometry.visible, geometry.in_regard, sensor.drone_pd(geometry), correlation
    )


def blade_line_chances(sensor: SensorModel, looks: Looks, classifier: ClassifierSettings) -> tuple[np.ndarray, float]:
    """Chance that a radar detection shows blade lines: the drone's at each look, and anything else's (a scalar)."""
    p = sensor.spec.params
    gain_db = 10 * np.log10(
        float(radar.integration_gain(int(p["n_pulses"]), p["integration"], sensor.scenario.convention))
    )
    snr1_db = sensor.radar_snr_db(looks.slant_range_m, sensor.scenario.target["sigma_radar_m2"]) - gain_db
    decision = drone_or_bird(
        sensor.scenario, p, snr1_db, classifier, "classification"
    )  # the scenario's Pfa, per Doppler bin
    return np.asarray(decision["pd_classified_drone"], float), float(decision["p_bird_classified_drone"])


def _classify(rng, detections: list, chances: tuple | None, k: int) -> None:
    """Mark each detection of look ``k`` with ``blade_lines`` (module docstring); nothing without a decision."""
    if chances is None:
        return
    for detection in detections:
        chance = chances[0][k] if detection.metadata["source"] == "drone" else chances[1]
        detection.metadata["blade_lines"] = bool(rng.uniform() < chance)


def correlated_draws(rng: np.random.Generator, pd, correlation) -> np.ndarray:
    """Detections of successive looks: marginal Pd, Gaussian copula of lag-one correlation rho (module docstring)."""
    noise = rng.standard_normal(len(pd))
    z = np.empty(len(pd))
    previous = 0.0
    for k, (rho, e) in enumerate(zip(correlation, noise)):
        previous = rho * previous + np.sqrt(max(1.0 - rho * rho, 0.0)) * e if k else e
        z[k] = previous
    return ndtr(z) < pd


def draw_birds(rng: np.random.Generator, engagement: Engagement, times) -> list:
    """Birds of one run, each a dict with its class and its (x, y, z, heading) at ``times``.

    Count Poisson with mean density x area of :meth:`Engagement.bird_box`; class uniform over the
    spec's classes; start uniform in the box; height above the terrain uniform in the class's flight
    heights; airspeed normal with the class's mean and s.d. (``defaults/birds.toml``); heading uniform,
    then a random walk of BIRD_HEADING_WALK_DEG per sqrt(s).
    """
    west, east, south, north = engagement.bird_box()
    area_km2 = max(east - west, 0.0) * max(north - south, 0.0) / 1e6
    count = rng.poisson(engagement.birds.density_per_km2 * area_km2) if engagement.birds.classes else 0
    dt = np.diff(times, prepend=times[0])
    out = []
    for _ in range(count):
        name = engagement.birds.classes[rng.integers(len(engagement.birds.classes))]
        bird = engagement.bird_table[name]
        low, high = bird["flight_height_m"]
        speed = max(rng.normal(bird["airspeed_m_s"], bird["airspeed_sd_m_s"]), BIRD_MIN_SPEED_M_S)
        heading = rng.uniform(0, 2 * np.pi) + np.cumsum(
            np.radians(BIRD_HEADING_WALK_DEG) * np.sqrt(dt) * rng.standard_normal(len(times))
        )
        x = rng.uniform(west, east) + np.cumsum(speed * dt * np.cos(heading))
        y = rng.uniform(south, north) + np.cumsum(speed * dt * np.sin(heading))
        z = engagement.terrain.height(x, y) + rng.uniform(low, high)
        out.append({"class": name, "table": bird, "x": x, "y": y, "z": z, "heading": heading})
    return out


def _bird_detections(rng, sensor: SensorModel, birds: list, index) -> list:
    """(bird number, look index) of every bird detection by one sensor at its looks (``index`` into the run's times)."""
    hits = []
    for number, bird in enumerate(birds):
        x, y, z, heading = (bird[k][index] for k in ("x", "y", "z", "heading"))
        geometry = sensor.geometry(x, y, z)
        los = np.stack([sensor.x - x, sensor.y - y, sensor.eye_z - z])
        los /= np.maximum(np.linalg.norm(los, axis=0), 1e-9)
        aspect = np.arccos(np.clip(np.cos(heading) * los[0] + np.sin(heading) * los[1], -1.0, 1.0))
        pd = sensor.bird_pd(geometry, bird["table"], aspect)
        hits += [(number, k) for k in np.flatnonzero(rng.uniform(size=pd.size) < pd)]
    return hits


def _drone_truths(rng, engagement: Engagement, name: str) -> list:
    """The drone's detections by one sensor at each look, (x, y, object) lists: the drone (correlated draws), or
    each resolved group of a swarm at its centroid, the group's first drone as its object (independent draws)."""
    if engagement.swarm is None:
        looks = engagement.looks[name]
        hits = correlated_draws(rng, looks.pd, looks.correlation)
        return [[(looks.x[k], looks.y[k], 0)] if hit else [] for k, hit in enumerate(hits)]
    swarm = engagement.swarm_looks[name]
    out = []
    for groups, centres, pd in zip(swarm.groups, swarm.centres, swarm.pd):
        hits = rng.uniform(size=len(pd)) < pd
        out.append([(centres[j, 0], centres[j, 1], groups[j][0]) for j in np.flatnonzero(hits)])
    return out


def _look_detections(rng, sensor: SensorModel, t_s: float, truth: dict) -> tuple[list, dict]:
    """Detections of one look: ``truth`` maps sources to (x, y, object) lists; plus noise and clutter false alarms."""
    noise, clutter = sensor.false_alarm_xy(rng), sensor.clutter_alarm_xy(rng)
    points = [(x, y, source, obj) for source, items in truth.items() for x, y, obj in items]
    points += [(x, y, "noise", None) for x, y in noise] + [(x, y, "clutter", None) for x, y in clutter]
    if not points:
        return [], {"noise": 0, "clutter": 0}
    xs, ys = np.array([p[0] for p in points]), np.array([p[1] for p in points])
    bearing, ground, sigma_r = sensor.measure(rng, xs, ys)
    false_alarm = np.array([p[2] in ("noise", "clutter") for p in points])
    # a false alarm is a point of the field of regard as such: reported where it fell
    bearing = np.where(false_alarm, np.arctan2(ys - sensor.y, xs - sensor.x), bearing)
    ground = np.where(false_alarm, np.hypot(xs - sensor.x, ys - sensor.y), ground)
    sigma_b = np.radians(sensor.settings.sigma_bearing_deg)
    detections = [
        make_detection(
            (sensor.x, sensor.y),
            b,
            max(r, 1e-3),
            sigma_b,
            s,
            t_s,
            {"source": p[2], "object": p[3], "sensor": sensor.name},
        )
        for b, r, s, p in zip(bearing, ground, sigma_r, points)
    ]
    return detections, {"noise": len(noise), "clutter": len(clutter)}


def run_once(
    engagement: Engagement, index: int, keep_paths: bool = False, until_s: float | None = None, budget_s=None
) -> dict:
    """One Monte Carlo run (seeded by the engagement's seed and ``index``): its metrics (module docstring).

    ``until_s`` stops the tracker after that time and ``budget_s`` once it has run that long [s] (a pilot
    run that times the looks); the record's ``looks_tracked`` says how many looks it took and
    ``tracking_cpu_s`` the CPU time they took.
    """
    started = time.perf_counter()
    rng = np.random.default_rng([engagement.seed, index])
    classifying = np.random.default_rng([engagement.seed, index, 1])  # apart: the same tracks with or without it
    times = np.unique(np.concatenate([looks.t_s for looks in engagement.looks.values()]))
    birds = draw_birds(rng, engagement, times)
    scans = []  # (t, sensor order, sensor name, detections)
    alarms = {name: {"noise": 0, "clutter": 0} for name in engagement.sensors}
    for order, (name, sensor) in enumerate(engagement.sensors.items()):
        looks = engagement.looks[name]
        index_in_run = np.searchsorted(times, looks.t_s)
        drones = _drone_truths(rng, engagement, name)
        bird_hits = _bird_detections(rng, sensor, birds, index_in_run)
        for k, t in enumerate(looks.t_s):
            truth = {"drone": drones[k]}
            truth["birds"] = [
                (birds[b]["x"][index_in_run[k]], birds[b]["y"][index_in_run[k]], b) for b, kk in bird_hits if kk == k
            ]
            detections, counts = _look_detections(rng, sensor, float(t), truth)
            _classify(classifying, detections, engagement.blade_lines.get(name), k)
            alarms[name]["noise"] += counts["noise"]
            alarms[name]["clutter"] += counts["clutter"]
            scans.append((float(t), order, name, detections))
    scans.sort(key=lambda s: (s[0], s[1]))
    first_detection = next((t for t, _, _, ds in scans if any(d.metadata["source"] == "drone" for d in ds)), None)
    if until_s is not None:
        scans = [scan for scan in scans if scan[0] <= until_s]
    tracker = EngagementTracker(*engagement.confirm, engagement.delete_after_misses)
    gospa_values, held, drone_tracks = [], [], [0]
    tracked, setup_cpu, tracking = 0, time.process_time(), time.perf_counter()
    for i, (t, _, name, detections) in enumerate(scans):
        if budget_s is not None and time.perf_counter() - tracking > budget_s:
            break
        tracker.step(t, detections, engagement.sensors[name].covers)
        tracked += 1
        if i + 1 == len(scans) or scans[i + 1][0] != t:
            value, near = _score(tracker, engagement, t)
            gospa_values.append(value)
            held.append((t, near))
            drone_tracks.append(sum(1 for track in tracker.tracks if tracker.records[track]["cause"] == "drone"))
    record = _run_summary(engagement, tracker, alarms, gospa_values, held, keep_paths, time.perf_counter() - started)
    record["siap"] = _siap(tracker, engagement.path, [t for t, _ in held])
    record["looks_tracked"], record["tracking_cpu_s"] = tracked, time.process_time() - setup_cpu
    if engagement.swarm is not None:  # the drones the tracker resolved at once, and the first detection of any
        record.update(first_detection_time_s=first_detection, drone_tracks_max=max(drone_tracks))
    return record


def gospa_distance(track_xy, truth_xy, c_m: float = GOSPA_C_M, p: float = GOSPA_P) -> float:
    """GOSPA (Stone Soup's ``GOSPAMetric``, cut-off ``c_m`` [m], order ``p``, alpha = 2) between positions [m]."""
    metric = GOSPAMetric(c=c_m, p=p, measure=Euclidean(mapping=(0, 1)))
    when = timestamp(0.0)
    tracks = [State(StateVector([x, y]), timestamp=when) for x, y in track_xy]
    truths = [State(StateVector([x, y]), timestamp=when) for x, y in truth_xy]
    value, _ = metric.compute_gospa_metric(tracks, truths)
    return float(value.value["distance"])


def _score(tracker: EngagementTracker, engagement: Engagement, t_s: float) -> tuple[float, bool]:
    """GOSPA of the confirmed tracks against the truths at ``t_s`` (the drone, or each drone of a swarm), and
    whether a track lies within GOSPA_C_M of the lead."""
    truths = engagement.truth_xy(t_s)
    when = timestamp(t_s)
    positions = [predicted_xy(track, when) for track in tracker.tracks]
    near = any(np.hypot(p[0] - truths[0][0], p[1] - truths[0][1]) < GOSPA_C_M for p in positions)
    return gospa_distance(positions, truths), near


def _siap(tracker: EngagementTracker, path: DronePath, times_s: list) -> dict:
    """SIAP scores of the run's confirmed tracks against the drone at the look times ``times_s`` [s]."""
    x, y, _, heading = path.at(np.asarray(times_s, float))
    vx, vy = path.speed_m_s * np.cos(heading), path.speed_m_s * np.sin(heading)
    return siap_scores(tracker.records.keys(), truth_path(times_s, x, y, vx, vy), GOSPA_C_M)


def _run_summary(engagement, tracker, alarms, gospa_values, held, keep_paths, elapsed) -> dict:
    """One run's record for ``runs_detail``."""
    records = tracker.records
    drone_times = [r["confirmed_s"] for r in records.values() if r["cause"] == "drone"]
    drone_rejected = sum(declared_not_drone(r["sources"]) for r in records.values() if r["cause"] == "drone")
    first = min(drone_times) if drone_times else None
    arrival = engagement.path.duration_s
    out = {
        "first_track_time_s": first,
        "first_track_range_m": None,
        "warning_time_s": 0.0,
        "track_continuity": None,
        "gospa_mean": float(np.mean(gospa_values)) if gospa_values else None,
        "false_alarms": alarms,
        "false_tracks": [],
        "drone_tracks": len(drone_times),
        "drone_tracks_rejected": drone_rejected,
        "time_s": elapsed,
    }
    if first is not None:
        x, y, _, _ = engagement.path.at(np.array([first]))
        out["first_track_range_m"] = float(
            np.hypot(x[0] - engagement.protected_xy[0], y[0] - engagement.protected_xy[1])
        )
        out["warning_time_s"] = float(arrival - first)
        after = [near for t, near in held if t >= first]
        out["track_continuity"] = float(np.mean(after)) if after else None
    for track, record in records.items():
        if record["cause"] != "drone":
            state = next(
                s
                for s in track.states
                if (s.timestamp - timestamp(0.0)).total_seconds() >= record["confirmed_s"] - 1e-9
            )
            v = np.asarray(state.state_vector, float).ravel()
            out["false_tracks"].append(
                {
                    "cause": record["cause"],
                    "t_s": record["confirmed_s"],
                    "x": float(v[0]),
                    "y": float(v[2]),
                    "rejected": declared_not_drone(record["sources"]),
                }
            )
    if engagement.swarm is not None:  # every track of the swarm confirmed in the run, broken ones counted again
        out["drone_tracks_confirmed"] = sum(1 for r in records.values() if r["cause"] == "drone")
    if keep_paths:
        out["tracks"] = [
            {
                "cause": record["cause"],
                "xy": [[float(s.state_vector[0]), float(s.state_vector[2])] for s in track.states],
            }
            for track, record in records.items()
        ]
    return out
