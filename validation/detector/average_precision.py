"""Average precision of one class, COCO's way, over all frames or the frames of one bin (NumPy only).

The rules are those of pycocotools' ``COCOeval`` for boxes (one category, ``maxDets`` 100, area
``all``): each frame's detections are sorted by score (stable) and matched greedily, highest score
first, to the unmatched ground-truth box of highest IoU at or above the threshold (IoU of [x, y, w, h]
boxes without COCO's old +1); over the frames, in frame order, all detections are sorted by score
(stable merge sort), precision is made non-increasing from the right and read at the 101 recall
points 0, 0.01, ..., 1 (the first detection that reaches each), and averaged. AP50 is that at IoU
0.5; AP the mean over IoU 0.50:0.05:0.95.

Written here rather than called from pycocotools because the evaluation must run where only
torch, torchvision and NumPy are (the GPU machine of docs/datasets.md, "A detector in the loop"),
on frame subsets (bins) and on bootstrap resamples that repeat frames, which ``COCOeval``'s image ids
cannot express; tests/test_detector_loop.py checks it against pycocotools on hand-made detections.

Because greedy matching takes detections in score order, the detections above any score threshold
match exactly as they do in the full list: a target is found at threshold s iff the score of the
detection matched to it is at least s. :func:`match_frame` keeps those scores, from which both the
AP and the detection rate at a false-alarm rate follow.

References
----------
- T.-Y. Lin et al., "Microsoft COCO: Common Objects in Context", ECCV 2014; pycocotools'
  ``cocoeval.py`` (``evaluateImg``, ``accumulate``), the rules reproduced here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError

#: COCO's IoU thresholds 0.50:0.05:0.95 (as pycocotools builds them).
IOU_THRESHOLDS = np.linspace(0.5, 0.95, int(np.round((0.95 - 0.5) / 0.05)) + 1)
#: COCO's recall points 0:0.01:1.
RECALL_POINTS = np.linspace(0.0, 1.0, int(np.round((1.0 - 0.0) / 0.01)) + 1)
#: Detections kept per frame, highest scores first (COCO's maxDets).
MAX_DETECTIONS = 100


@dataclass(frozen=True)
class FrameMatch:
    """One frame's detections matched to its targets at each IoU threshold.

    Attributes
    ----------
    scores : ndarray, shape (d,)
        The frame's kept detection scores, highest first.
    matched : ndarray of bool, shape (t, d)
        Whether each detection matched a target at each IoU threshold.
    target_scores : ndarray, shape (t, g)
        The score of the detection matched to each target at each threshold; -inf when none.
    """

    scores: np.ndarray
    matched: np.ndarray
    target_scores: np.ndarray


def box_iou(detections, targets) -> np.ndarray:
    """IoU of every detection with every target, boxes [x, y, w, h] in pixels (COCO's ``bbox`` IoU).

    Returns
    -------
    ndarray, shape (len(detections), len(targets))
    """
    d = np.asarray(detections, dtype=float).reshape(-1, 4)
    g = np.asarray(targets, dtype=float).reshape(-1, 4)
    left = np.maximum(d[:, None, 0], g[None, :, 0])
    top = np.maximum(d[:, None, 1], g[None, :, 1])
    right = np.minimum(d[:, None, 0] + d[:, None, 2], g[None, :, 0] + g[None, :, 2])
    bottom = np.minimum(d[:, None, 1] + d[:, None, 3], g[None, :, 1] + g[None, :, 3])
    inter = np.clip(right - left, 0.0, None) * np.clip(bottom - top, 0.0, None)
    union = d[:, None, 2] * d[:, None, 3] + g[None, :, 2] * g[None, :, 3] - inter
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(union > 0, inter / np.where(union > 0, union, 1.0), 0.0)


def match_frame(targets, boxes, scores, iou_thresholds=IOU_THRESHOLDS) -> FrameMatch:
    """Greedy COCO matching of one frame's detections to its targets (module docstring).

    Parameters
    ----------
    targets : array_like, shape (g, 4)
        Ground-truth boxes [x, y, w, h] [px].
    boxes : array_like, shape (d, 4)
        Detected boxes [x, y, w, h] [px].
    scores : array_like, shape (d,)
        Their scores.
    iou_thresholds : array_like
        IoU at or above which a detection may match a target.
    """
    scores = np.asarray(scores, dtype=float).reshape(-1)
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    if len(scores) != len(boxes):
        raise ParameterError("scores", len(scores), f"one score per box ({len(boxes)} boxes)")
    order = np.argsort(-scores, kind="mergesort")[:MAX_DETECTIONS]
    scores, boxes = scores[order], boxes[order]
    targets = np.asarray(targets, dtype=float).reshape(-1, 4)
    ious = box_iou(boxes, targets)
    thresholds = np.asarray(iou_thresholds, dtype=float)
    matched = np.zeros((len(thresholds), len(scores)), dtype=bool)
    target_scores = np.full((len(thresholds), len(targets)), -np.inf)
    for t, threshold in enumerate(thresholds):
        taken = np.zeros(len(targets), dtype=bool)
        for d in range(len(scores)):
            best, best_iou = -1, min(threshold, 1 - 1e-10)
            for g in range(len(targets)):  # the last target of the highest IoU, as COCOeval's loop
                if not taken[g] and ious[d, g] >= best_iou:
                    best, best_iou = g, ious[d, g]
            if best >= 0:
                taken[best], matched[t, d], target_scores[t, best] = True, True, scores[d]
    return FrameMatch(scores, matched, target_scores)


def average_precision(frames: list[FrameMatch]) -> np.ndarray | None:
    """COCO AP at each IoU threshold over a list of matched frames (in that order; repeats allowed).

    Returns
    -------
    ndarray or None
        AP per threshold; None when the frames hold no target (COCO's -1).
    """
    if not frames:
        return None
    targets = sum(f.target_scores.shape[1] for f in frames)
    if targets == 0:
        return None
    scores = np.concatenate([f.scores for f in frames])
    order = np.argsort(-scores, kind="mergesort")
    matched = np.concatenate([f.matched for f in frames], axis=1)[:, order]
    out = np.zeros(matched.shape[0])
    if matched.shape[1] == 0:
        return out  # targets but no detection: precision 0 at every recall
    for t, hits in enumerate(matched):
        tp = np.cumsum(hits).astype(float)
        fp = np.cumsum(~hits).astype(float)
        recall = tp / targets
        precision = tp / (tp + fp + np.spacing(1))
        precision = np.maximum.accumulate(precision[::-1])[::-1]  # non-increasing from the right
        at = np.searchsorted(recall, RECALL_POINTS, side="left")
        out[t] = np.where(at < len(precision), precision[np.minimum(at, len(precision) - 1)], 0.0).mean()
    return out


def false_alarm_threshold(frames: list[FrameMatch], false_alarms_per_frame: float, level: int = 0) -> float:
    """The lowest score threshold at which unmatched detections (IoU threshold ``level``) number at most
    ``false_alarms_per_frame`` per frame over ``frames``.

    Returns
    -------
    float
        A detection counts when its score is at least this; inf when even the top score is too many.
    """
    if false_alarms_per_frame < 0:
        raise ParameterError("false_alarms_per_frame", false_alarms_per_frame, ">= 0")
    false = np.sort(np.concatenate([f.scores[~f.matched[level]] for f in frames] or [np.empty(0)]))[::-1]
    allowed = int(np.floor(false_alarms_per_frame * len(frames)))
    if allowed >= len(false):
        return -np.inf
    return float(np.nextafter(false[allowed], np.inf))  # just above the first false alarm too many


def detection_rate(frames: list[FrameMatch], threshold: float, level: int = 0) -> tuple[float, int] | None:
    """Share of the frames' targets matched (IoU threshold ``level``) by a detection scoring at least
    ``threshold``, and the number of targets; None without targets."""
    found = np.concatenate([f.target_scores[level] for f in frames] or [np.empty(0)])
    if len(found) == 0:
        return None
    return float(np.mean(found >= threshold)), len(found)


def bootstrap_stderr(frames: list[FrameMatch], statistic, resamples: int = 200, seed: int = 0) -> float | None:
    """Standard error of ``statistic(frames)`` by resampling the frames with replacement (Efron 1979).

    Resamples whose statistic is None (no target drawn) are left out; None when fewer than two remain.
    """
    rng = np.random.default_rng(seed)
    values = []
    for _ in range(resamples):
        value = statistic([frames[i] for i in rng.integers(len(frames), size=len(frames))])
        if value is not None:
            values.append(value)
    return float(np.std(values, ddof=1)) if len(values) > 1 else None


def bin_index(values, edges) -> np.ndarray:
    """Bin of each value: i where edges[i] <= value < edges[i + 1]; -1 outside [edges[0], edges[-1]).

    Parameters
    ----------
    values : array_like
    edges : array_like
        Increasing bin edges (the last may be inf).
    """
    e = np.asarray(edges, dtype=float)
    if e.ndim != 1 or len(e) < 2 or np.any(np.diff(e) <= 0):
        raise ParameterError("edges", list(e), "at least two increasing edges")
    v = np.asarray(values, dtype=float)
    i = np.searchsorted(e, v, side="right") - 1
    return np.where((v >= e[0]) & (v < e[-1]), i, -1)
