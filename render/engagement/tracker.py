"""Multi-sensor tracking of an engagement with Stone Soup: Kalman filter, GNN association, M-of-N initiation.

The state is the target's ground position and velocity (x, vx, y, vy) in the DEM's CRS [m, m/s], a
nearly-constant-velocity model (Stone Soup's ``ConstantVelocity`` on each axis); every sensor reports
(bearing, ground range) from its own position (``CartesianToBearingRange`` with the sensor's offset and
each detection's own noise), so one tracker takes every sensor's detections through the extended
Kalman updater. Each look of a sensor is one scan, in time order.

* Association: Stone Soup's global-nearest-neighbour ``GNNWith2DAssignment`` over a
  ``DistanceHypothesiser`` with the Mahalanobis distance, gated at ``GATE_SIGMAS``. A cheap Euclidean
  pre-gate (:class:`PrefilteredHypothesiser`) hands it only the detections that could pass that gate.
* Initiation, M of N (:class:`MOfNInitiator`; Stone Soup's ``MultiMeasurementInitiator`` counts M
  updates with no window, so the window is written here on top of its components): every
  detection no track takes starts a tentative track (position from the measurement, velocity 0 with
  a standard deviation of ``PRIOR_SPEED_M_S``); at each look of a sensor that covers it, a tentative
  track is a hit when GNN gives it a detection, a miss otherwise; it is confirmed when M of its last N
  looks are hits, and dropped when none of its last N-1 looks is (no later window can use them). For
  a single target this is exactly "M of N consecutive looks detect" (:mod:`csuas.core.m_of_n`).
* Deletion: Stone Soup's ``UpdateTimeStepsDeleter``: a confirmed track with no update in its last
  ``delete_after_misses`` looks by sensors that cover it.

Only the looks of a sensor whose sector and reach hold the track's predicted position count as the
track's looks (hits or misses).

References
----------
Stone Soup (https://stonesoup.readthedocs.io), D. Last et al., "Stone Soup: announcement of beta
release of an open-source framework for tracking and state estimation", Proc. SPIE 11018, 2019.
S. Blackman and R. Popoli, *Design and Analysis of Modern Tracking Systems*, Artech House, 1999,
Section 11.2 (M-of-N track confirmation).
"""

from __future__ import annotations

from collections import Counter
from datetime import datetime, timedelta

import numpy as np
from stonesoup.base import Property
from stonesoup.dataassociator.neighbour import GNNWith2DAssignment
from stonesoup.deleter.time import UpdateTimeStepsDeleter
from stonesoup.hypothesiser import Hypothesiser
from stonesoup.hypothesiser.distance import DistanceHypothesiser
from stonesoup.measures import Mahalanobis
from stonesoup.models.measurement.nonlinear import CartesianToBearingRange
from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
from stonesoup.predictor.kalman import KalmanPredictor
from stonesoup.types.angle import Bearing
from stonesoup.types.array import CovarianceMatrix, StateVector
from stonesoup.types.detection import Detection
from stonesoup.types.state import GaussianState
from stonesoup.types.track import Track
from stonesoup.updater.kalman import ExtendedKalmanUpdater

#: Mahalanobis gate of association [-] (chi-square with 2 degrees of freedom: 99.97 % of true pairs inside).
GATE_SIGMAS = 4.0
#: The Cartesian pre-gate's width relative to the gate (room for the linearisation).
PREGATE_FACTOR = 1.5
#: Standard deviation of a new track's velocity [m/s] (drones and birds fly below it).
PRIOR_SPEED_M_S = 25.0
#: Process noise of the constant-velocity model [m^2/s^3] (manoeuvres and wandering birds).
PROCESS_NOISE = 2.0
#: The engagement's time zero (Stone Soup needs datetimes).
EPOCH = datetime(2026, 1, 1)


def timestamp(t_s: float) -> datetime:
    """The datetime of a time [s] after the engagement starts."""
    return EPOCH + timedelta(seconds=float(t_s))


def seconds(when: datetime) -> float:
    """Seconds since the engagement started."""
    return (when - EPOCH).total_seconds()


def make_detection(sensor_xy, bearing_rad, range_m, sigma_bearing_rad, sigma_range_m, t_s, metadata) -> Detection:
    """A Stone Soup detection of (bearing, ground range) from a sensor at ``sensor_xy`` with its own noise."""
    model = BearingRangeModel(
        ndim_state=4,
        mapping=(0, 2),
        noise_covar=CovarianceMatrix(np.diag([sigma_bearing_rad**2, sigma_range_m**2])),
        translation_offset=StateVector([sensor_xy[0], sensor_xy[1]]),
    )
    x = sensor_xy[0] + range_m * np.cos(bearing_rad)
    y = sensor_xy[1] + range_m * np.sin(bearing_rad)
    jac = np.array(
        [[-range_m * np.sin(bearing_rad), np.cos(bearing_rad)], [range_m * np.cos(bearing_rad), np.sin(bearing_rad)]]
    )
    cartesian = jac @ np.diag([sigma_bearing_rad**2, sigma_range_m**2]) @ jac.T
    meta = {**metadata, "xy": (x, y), "cartesian_covar": cartesian}
    return Detection(
        StateVector([Bearing(bearing_rad), range_m]), timestamp=timestamp(t_s), measurement_model=model, metadata=meta
    )


class BearingRangeModel(CartesianToBearingRange):
    """Stone Soup's (bearing, range) measurement of a 2-D position, with its Jacobian in closed form.

    d(phi)/d(x, y) = (-dy, dx) / r^2 and d(rho)/d(x, y) = (dx, dy) / r (no rotation offset), instead of
    Stone Soup's numerical differences (the same matrix, several times faster).
    """

    def jacobian(self, state, **kwargs):
        """The 2 x 4 Jacobian of (bearing, range) at ``state``."""
        v = np.asarray(state.state_vector, float).ravel()
        dx = v[self.mapping[0]] - float(self.translation_offset[0, 0])
        dy = v[self.mapping[1]] - float(self.translation_offset[1, 0])
        r2 = max(dx * dx + dy * dy, 1e-12)
        r = np.sqrt(r2)
        jac = np.zeros((2, self.ndim_state))
        jac[0, self.mapping[0]], jac[0, self.mapping[1]] = -dy / r2, dx / r2
        jac[1, self.mapping[0]], jac[1, self.mapping[1]] = dx / r, dy / r
        return jac


def extrapolated_xy(state, when: datetime) -> np.ndarray:
    """A state's position (x, y) [m] (state x, vx, y, vy) extrapolated to ``when`` at constant velocity."""
    dt = (when - state.timestamp).total_seconds()
    v = state.state_vector
    return np.array([float(v[0]) + float(v[1]) * dt, float(v[2]) + float(v[3]) * dt])


def predicted_xy(track: Track, when: datetime) -> np.ndarray:
    """A track's position (x, y) [m] extrapolated to ``when`` at constant velocity."""
    return extrapolated_xy(track.state, when)


def predicted_position(track: Track, when: datetime) -> tuple[np.ndarray, np.ndarray]:
    """A track's position (x, y) [m] at ``when`` (constant velocity) and its 2 x 2 covariance, F P F' + Q."""
    state = track.state
    dt = (when - state.timestamp).total_seconds()
    p = np.asarray(state.covar, float)
    q = PROCESS_NOISE * abs(dt) ** 3 / 3
    cov = np.array(
        [
            [p[0, 0] + 2 * dt * p[0, 1] + dt * dt * p[1, 1] + q, 0.0],
            [0.0, p[2, 2] + 2 * dt * p[2, 3] + dt * dt * p[3, 3] + q],
        ]
    )
    cov[0, 1] = cov[1, 0] = p[0, 2] + dt * (p[0, 3] + p[1, 2]) + dt * dt * p[1, 3]
    return predicted_xy(track, when), cov


class NearlyConstantVelocity(CombinedLinearGaussianTransitionModel):
    """Stone Soup's two ``ConstantVelocity`` models (x and y), with their matrices cached by time step.

    The same F and Q as the combined model (Stone Soup rebuilds them with a block-diagonal on every
    call, the tracker's main cost); cached per time interval.
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._cache: dict = {}

    def _cached(self, what: str, time_interval, **kwargs):
        key = (what, time_interval)
        if key not in self._cache:
            method = super().matrix if what == "matrix" else super().covar
            self._cache[key] = method(time_interval=time_interval, **kwargs)
        return self._cache[key]

    def matrix(self, time_interval, **kwargs):
        """The transition matrix F over ``time_interval``."""
        return self._cached("matrix", time_interval, **kwargs)

    def covar(self, time_interval, **kwargs):
        """The process-noise covariance Q over ``time_interval``."""
        return self._cached("covar", time_interval, **kwargs)


class PrefilteredHypothesiser(Hypothesiser):
    """Hands a Stone Soup hypothesiser only the detections that could pass its gate (a Cartesian pre-gate).

    The pre-gate is the Mahalanobis distance of the detection's position from the track's predicted
    position, with the prediction's covariance plus the detection's own (its measurement noise through
    the polar-to-Cartesian Jacobian), at PREGATE_FACTOR times the gate: the same linearised test as the
    hypothesiser's in measurement space, with room for the linearisation's difference.
    """

    hypothesiser: Hypothesiser = Property(doc="the hypothesiser that scores the pairs left")

    def hypothesise(self, track, detections, timestamp, **kwargs):
        """Hypotheses of ``track`` over the detections inside the pre-gate."""
        return self.hypothesiser.hypothesise(track, candidates(track, detections, timestamp), timestamp, **kwargs)


def candidates(track: Track, detections, when: datetime) -> set:
    """The detections inside a track's Cartesian pre-gate at ``when`` (:class:`PrefilteredHypothesiser`)."""
    if not detections:
        return set()
    centre, cov = predicted_position(track, when)
    listed = list(detections)
    e = np.array([d.metadata["xy"] for d in listed]) - centre
    s = cov + np.array([d.metadata["cartesian_covar"] for d in listed])
    det = s[:, 0, 0] * s[:, 1, 1] - s[:, 0, 1] * s[:, 1, 0]
    # e' S^-1 e of each 2 x 2 S in closed form
    distance2 = (s[:, 1, 1] * e[:, 0] ** 2 - 2 * s[:, 0, 1] * e[:, 0] * e[:, 1] + s[:, 0, 0] * e[:, 1] ** 2) / det
    return {d for d, inside in zip(listed, distance2 <= (PREGATE_FACTOR * GATE_SIGMAS) ** 2) if inside}


def build_components():
    """Stone Soup's predictor, updater and GNN associator of an engagement."""
    transition = NearlyConstantVelocity([ConstantVelocity(PROCESS_NOISE), ConstantVelocity(PROCESS_NOISE)])
    predictor, updater = KalmanPredictor(transition), ExtendedKalmanUpdater(measurement_model=None)
    inner = DistanceHypothesiser(predictor, updater, Mahalanobis(), missed_distance=GATE_SIGMAS)
    return predictor, updater, GNNWith2DAssignment(PrefilteredHypothesiser(inner))


def initial_state(detection: Detection) -> GaussianState:
    """A new track's state from one detection: its position, velocity 0 +- PRIOR_SPEED_M_S."""
    covar = np.zeros((4, 4))
    covar[np.ix_([0, 2], [0, 2])] = detection.metadata["cartesian_covar"]
    covar[1, 1] = covar[3, 3] = PRIOR_SPEED_M_S**2
    x, y = detection.metadata["xy"]
    return GaussianState(StateVector([x, 0.0, y, 0.0]), CovarianceMatrix(covar), timestamp=detection.timestamp)


class MOfNInitiator:
    """M-of-N track confirmation on Stone Soup's Kalman components and GNN associator (module docstring).

    Parameters
    ----------
    m, n : int
        Hits M needed among a tentative track's last N looks.
    updater, associator
        Stone Soup's updater and data associator (:func:`build_components`).
    """

    def __init__(self, m: int, n: int, updater, associator):
        self.m, self.n, self.updater, self.associator = m, n, updater, associator
        self.tentative: dict[Track, list] = {}
        self.sources: dict[Track, Counter] = {}

    def initiate(self, detections: set, when: datetime, covered) -> set:
        """Take one look's unassociated detections; return the tracks confirmed now.

        ``covered(tracks)`` gives the tentative tracks the look covers.
        """
        looking = covered(list(self.tentative))
        contested = {t for t in looking if candidates(t, detections, when)}  # the others miss without scoring
        hypotheses = self.associator.associate(contested, detections, when) if contested else {}
        used, confirmed = set(), set()
        for track in looking:
            hypothesis = hypotheses.get(track)
            hit = bool(hypothesis) and hypothesis.measurement in detections
            if hit:
                track.append(self.updater.update(hypothesis))
                used.add(hypothesis.measurement)
                self.sources[track] += tally(hypothesis.measurement)
            history = self.tentative[track]
            history.append(hit)
            if sum(history[-self.n :]) >= self.m:
                confirmed.add(track)
            elif not any(history[max(len(history) - self.n + 1, 0) :]):  # no hit any later window could hold
                self._drop(track)
        for detection in detections - used:
            track = Track([initial_state(detection)])
            self.tentative[track] = [True]
            self.sources[track] = tally(detection)
            if self.m <= 1:
                confirmed.add(track)
        for track in confirmed:
            self.tentative.pop(track, None)
        return confirmed

    def _drop(self, track: Track) -> None:
        self.tentative.pop(track, None)
        self.sources.pop(track, None)


class EngagementTracker:
    """Confirmed tracks of an engagement, one sensor look at a time (module docstring).

    Parameters
    ----------
    m, n : int
        M-of-N confirmation.
    delete_after_misses : int
        Looks without an update (by sensors covering the track) after which a confirmed track ends.
    """

    def __init__(self, m: int, n: int, delete_after_misses: int):
        self.predictor, self.updater, self.associator = build_components()
        self.initiator = MOfNInitiator(m, n, self.updater, self.associator)
        self.deleter = UpdateTimeStepsDeleter(time_steps_since_update=delete_after_misses)
        self.tracks: set = set()
        self.records: dict[Track, dict] = {}

    def step(self, t_s: float, detections: list, covers) -> list:
        """Process one look: ``covers(x, y)`` says which ground points the looking sensor covers.

        Returns the tracks confirmed at this look.
        """
        when = timestamp(t_s)

        def covered(tracks):
            if not tracks:
                return []
            where = np.array([predicted_xy(track, when) for track in tracks])
            keep = covers(where[:, 0], where[:, 1])
            return [track for track, k in zip(tracks, keep) if k]

        looking = covered(list(self.tracks))
        pending = set(detections)
        contested = {t for t in looking if candidates(t, pending, when)}  # the others miss without scoring
        hypotheses = self.associator.associate(contested, pending, when) if contested else {}
        for track in looking:
            hypothesis = hypotheses.get(track)
            if hypothesis and hypothesis.measurement in pending:
                track.append(self.updater.update(hypothesis))
                pending.discard(hypothesis.measurement)
                self.records[track]["sources"] += tally(hypothesis.measurement)
            else:
                track.append(
                    hypothesis.prediction if hypothesis else self.predictor.predict(track.state, timestamp=when)
                )
        self.tracks -= self.deleter.delete_tracks(set(looking))
        confirmed = self.initiator.initiate(pending, when, covered)
        for track in confirmed:
            sources = self.initiator.sources.pop(track)
            self.records[track] = {"confirmed_s": t_s, "cause": cause_of(sources), "sources": sources}
        self.tracks |= confirmed
        return list(confirmed)


def tally(detection) -> Counter:
    """What one detection adds to its track's counts: its source, and with a drone-or-bird decision
    (metadata ``blade_lines`` True or False; None without one) ``classified`` and ``blade_lines``."""
    flag = detection.metadata.get("blade_lines")
    counts = Counter({detection.metadata["source"]: 1})
    if flag is not None:
        counts.update({"classified": 1, "blade_lines": int(flag)})
    return counts


def declared_not_drone(sources: Counter) -> bool:
    """Whether a track's drone-or-bird decisions reject it: some detections were classified, none showed blade lines."""
    return sources.get("classified", 0) > 0 and sources.get("blade_lines", 0) == 0


def cause_of(sources: Counter) -> str:
    """The cause of a track from the sources of its detections at confirmation: the most frequent one.

    Ties go to the drone first, then birds, clutter, noise (a track the drone helped confirm is the drone's).
    """
    order = ("drone", "birds", "clutter", "noise")
    return max(order, key=lambda s: (sources.get(s, 0), -order.index(s)))
