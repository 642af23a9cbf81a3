"""Scores of a learned detector on held-out csuas frames, by pixels on target and by background, beside
the physics Pd of the same frames (docs/datasets.md, "A detector in the loop").

Per group of frames (a bin of the drone's ``pixels_on_target``, a background class, or all):

* ``ap50`` and ``ap`` (COCO, :mod:`csuas.validation.detector.average_precision`) over the group's frames,
  its false positives included, with a bootstrap standard error over frames;
* ``pd_learned``: the share of the group's drones the detector finds (IoU >= 0.5) at the score threshold
  where its false alarms over all held-out frames are those the physics threshold allows, Pfa per pixel
  times the frame's pixels (0.08 a frame at Pfa 1e-6 on 320 x 256 px), with its binomial standard error;
* the mean physics Pd of the group's drones (:mod:`csuas.validation.detector.physics`) and its standard error.

A frame belongs to the bin of its drone (a csuas frame holds at most one); frames whose drone left the
frame count in ``all`` (their detections are false alarms) and in no bin.
"""

from __future__ import annotations

import math

import numpy as np

from csuas.validation.detector import average_precision as ap
from csuas.validation.detector.physics import COLUMNS, frame_pd

#: Bin edges of the drone's pixels on target.
PIXEL_EDGES = (0.0, 1.0, 4.0, 16.0, 64.0, 256.0, math.inf)
#: Bootstrap resamples of the AP's standard error.
RESAMPLES = 200


def _mean_and_stderr(values: np.ndarray) -> tuple[float | None, float | None]:
    if len(values) == 0:
        return None, None
    stderr = float(np.std(values, ddof=1) / math.sqrt(len(values))) if len(values) > 1 else None
    return float(np.mean(values)), stderr


def _group(matches, physics: dict, indices, threshold: float) -> dict:
    """The scores of the frames ``indices`` (module docstring)."""
    chosen = [matches[i] for i in indices]
    values = ap.average_precision(chosen)
    row: dict = {"frames": len(chosen), "targets": int(sum(m.target_scores.shape[1] for m in chosen))}
    row["ap50"] = None if values is None else float(values[0])
    row["ap"] = None if values is None else float(values.mean())
    first = lambda frames: None if (v := ap.average_precision(frames)) is None else float(v[0])
    row["ap50_stderr"] = ap.bootstrap_stderr(chosen, first, RESAMPLES) if chosen else None
    rate = ap.detection_rate(chosen, threshold)
    row["pd_learned"] = None if rate is None else rate[0]
    row["pd_learned_stderr"] = None if rate is None else math.sqrt(rate[0] * (1 - rate[0]) / rate[1])
    with_target = [i for i in indices if not math.isnan(physics["pixels_on_target"][i])]
    row["pixels_on_target_mean"] = _mean_and_stderr(physics["pixels_on_target"][with_target])[0]
    for column in COLUMNS:
        row[column], row[f"{column}_stderr"] = _mean_and_stderr(physics[column][with_target])
    return row


def _found(match) -> float | None:
    """Score of the detection matched to the frame's drone at IoU 0.5; None when none or no drone."""
    scores = match.target_scores[0]
    return float(scores[0]) if len(scores) and np.isfinite(scores[0]) else None


def frame_physics(frames, pfa: float) -> dict[str, np.ndarray]:
    """Per frame: its drone's ``pixels_on_target`` and physics Pd (NaN for a frame without a drone)."""
    first = [f.labels[0] if f.labels else None for f in frames]
    pixels = np.array([np.nan if b is None else b["pixels_on_target"] for b in first])
    cycles = np.array([0.0 if b is None else b["johnson_cycles"] for b in first])
    snr = np.array([0.0 if b is None else b["snr"] for b in first])
    columns = frame_pd(cycles, snr, pfa)
    out = {"pixels_on_target": pixels}
    out.update({k: np.where(np.isnan(pixels), np.nan, v) for k, v in columns.items()})
    return out


def evaluate(frames, detections, pfa: float, edges=PIXEL_EDGES) -> dict:
    """Score ``detections`` (one ``(boxes, scores)`` per frame) on ``frames`` (module docstring).

    Returns
    -------
    dict
        ``all``, ``by_pixels_on_target`` (rows with ``pixels_min``, ``pixels_max``, None for the last),
        ``by_background`` (rows with ``background``), ``score_threshold``, ``false_alarms_per_frame``, ``pfa``;
        per frame ``frames`` (``pixels_on_target``, ``background``, ``found_score`` at IoU 0.5 or None, and the
        physics columns).
    """
    matches = [ap.match_frame(f.boxes, boxes, scores) for f, (boxes, scores) in zip(frames, detections)]
    physics = frame_physics(frames, pfa)
    pixels_per_frame = frames[0].size_px[0] * frames[0].size_px[1]
    allowed = pfa * pixels_per_frame
    # scores are probabilities: -inf (every detection counts) is 0, inf (none does) just above 1
    threshold = float(np.clip(ap.false_alarm_threshold(matches, allowed), 0.0, np.nextafter(1.0, 2.0)))
    out: dict = {"pfa": pfa, "false_alarms_per_frame": allowed, "score_threshold": threshold}
    out["all"] = _group(matches, physics, list(range(len(frames))), threshold)
    bins = ap.bin_index(np.nan_to_num(physics["pixels_on_target"], nan=-1.0), edges)
    out["by_pixels_on_target"] = [
        {
            "pixels_min": lo,
            "pixels_max": None if math.isinf(hi) else hi,  # None: no upper edge (strict JSON)
            **_group(matches, physics, list(np.flatnonzero(bins == i)), threshold),
        }
        for i, (lo, hi) in enumerate(zip(edges[:-1], edges[1:]))
    ]
    classes = sorted({f.background for f in frames})
    out["by_background"] = [
        {"background": c, **_group(matches, physics, [i for i, f in enumerate(frames) if f.background == c], threshold)}
        for c in classes
    ]
    out["frames"] = [
        {
            "image": str(f.path),
            "background": f.background,
            "pixels_on_target": None if math.isnan(physics["pixels_on_target"][i]) else physics["pixels_on_target"][i],
            "found_score": _found(m),
            **{c: None if math.isnan(physics[c][i]) else float(physics[c][i]) for c in COLUMNS},
        }
        for i, (f, m) in enumerate(zip(frames, matches))
    ]
    return out
