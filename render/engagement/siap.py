"""SIAP scores of one engagement run: its confirmed tracks against the drone's truth (Stone Soup).

The Single Integrated Air Picture attribute measures (Votruba et al. 2001), computed by Stone Soup's
``SIAPMetrics`` on the tracks the tracker confirmed, with the drone as the only truth (birds are
confusers: a track on a bird counts as spurious). Each track is first sampled at every look time
within its life (:func:`held_track`: its latest state extrapolated at constant velocity), the picture
the operator holds between the track's own updates. A track is associated with the drone at a time when
the drone is the truth closest to it and within ``association_m`` (Stone Soup's ``TrackToTruth``: two
consecutive looks in range start an association, from the first of them, and one look out of range
ends it, so the scores follow the tracks look by look; a single pair cannot start one, since Stone
Soup's time ranges need an end after their start).

References
----------
Votruba, P., Nisley, R., Rothrock, R. and Zombro, B. (2001), *Single Integrated Air Picture (SIAP)
Metrics Implementation*, SIAP System Engineering Task Force, Technical Report 2001-003.
Stone Soup, ``stonesoup.metricgenerator.tracktotruthmetrics.SIAPMetrics`` (MIT licence).
"""

from __future__ import annotations

import bisect

import numpy as np
from stonesoup.dataassociator.tracktotrack import TrackToTruth
from stonesoup.measures import Euclidean
from stonesoup.metricgenerator.manager import MultiManager
from stonesoup.metricgenerator.tracktotruthmetrics import SIAPMetrics
from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState
from stonesoup.types.state import State
from stonesoup.types.track import Track

from csuas.render.engagement.tracker import extrapolated_xy, timestamp

#: The scores kept, by Stone Soup's metric title: name in engage.json -> title.
SCORES = {
    "completeness": "SIAP Completeness",
    "ambiguity": "SIAP Ambiguity",
    "spuriousness": "SIAP Spuriousness",
    "position_accuracy_m": "SIAP Position Accuracy",
    "velocity_accuracy_m_s": "SIAP Velocity Accuracy",
    "track_number_changes_per_s": "SIAP Rate of Track Number Change",
    "longest_track_segment": "SIAP Longest Track Segment",
}


def truth_path(t_s, x_m, y_m, vx_m_s, vy_m_s) -> GroundTruthPath:
    """The drone's truth as a Stone Soup path of states (x, vx, y, vy) at times ``t_s`` [s]."""
    return GroundTruthPath(
        [
            GroundTruthState(np.array([[x], [vx], [y], [vy]]), timestamp=timestamp(float(t)))
            for t, x, y, vx, vy in zip(t_s, x_m, y_m, vx_m_s, vy_m_s)
        ]
    )


def held_track(track: Track, times) -> Track:
    """``track`` at each of ``times`` (datetimes, sorted) from its first state to its last: the latest state
    at or before each time, extrapolated at constant velocity (state x, vx, y, vy)."""
    states = sorted(track.states, key=lambda state: state.timestamp)
    stamps = [state.timestamp for state in states]
    held = []
    for when in times:
        if when < stamps[0] or when > stamps[-1]:
            continue
        latest = states[bisect.bisect_right(stamps, when) - 1]
        x, y = extrapolated_xy(latest, when)
        vx, vy = float(latest.state_vector[1]), float(latest.state_vector[3])
        held.append(State(np.array([[x], [vx], [y], [vy]]), timestamp=when))
    return Track(held)


def siap_scores(tracks, truth: GroundTruthPath, association_m: float) -> dict:
    """SIAP scores (``SCORES``) of ``tracks`` (Stone Soup tracks with states x, vx, y, vy) against ``truth``.

    Parameters
    ----------
    tracks : iterable of stonesoup.types.track.Track
        The confirmed tracks of the run, sampled at the truth's times by :func:`held_track`.
    truth : GroundTruthPath
        The drone's states at the times of the looks (:func:`truth_path`).
    association_m : float
        Largest distance at which a track is associated with the drone [m].

    Returns
    -------
    dict
        completeness and longest track segment [0-1], ambiguity [tracks per tracked truth],
        spuriousness [0-1], position accuracy [m], velocity accuracy [m/s], rate of track number
        changes [1/s]. A run with no track scores completeness 0 and spuriousness 0.
    """
    generator = SIAPMetrics(position_measure=Euclidean((0, 2)), velocity_measure=Euclidean((1, 3)))
    associator = TrackToTruth(association_threshold=association_m, consec_pairs_confirm=2, consec_misses_end=1)
    manager = MultiManager([generator], associator=associator)
    times = sorted(state.timestamp for state in truth.states)
    held = [held_track(track, times) for track in tracks]
    manager.add_data({"groundtruth_paths": {truth}, "tracks": {track for track in held if track.states}})
    manager.associate_tracks(generator)
    titles = {metric.title: metric.value for metric in generator.compute_metric(manager)}
    return {name: float(titles[title]) for name, title in SCORES.items()}
