"""Detection by several sensors, and by many looks along an approach (the paper's Section 5 fusion item).

Sensors are taken as independent: a layered system detects when any sensor does (OR), or when
at least k of n do (k-of-n, the Poisson-binomial tail, exact by dynamic programming). Along an
approach the drone closes at a constant speed and each sensor looks at its frame or scan rate;
the cumulative probability of detection after the j-th look is 1 - prod_i<=j (1 - Pd_i) for
independent looks, or the running maximum of Pd_i for fully correlated looks (the same draw of
every random factor each time: only the rising Pd adds detections). The first-detection range is
distributed as the cumulative probability's increments, on the looks only: its median is a look.

References
----------
- D. K. Barton, Radar Equations for Modern Radar, Artech House, 2013, ch. 1 (cumulative
  probability of detection).
- Y. Bar-Shalom, P. K. Willett and X. Tian, Tracking and Data Fusion, YBS, 2011 (k-of-n logic).
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require, require_all

CORRELATIONS = ("independent", "correlated")
#: Most looks one approach may take (memory: 8 bytes a look and sensor).
MAX_LOOKS = 50_000_000


def _probabilities(name, value, axis):
    p = require(name, value, ge=0, le=1)
    if p.ndim == 0 or p.shape[axis] == 0:
        raise ParameterError(name, value, "an array with at least one sensor along the sensor axis")
    return np.moveaxis(p, axis, 0)


def fuse_or(pd_per_sensor, axis=0):
    """Probability that at least one of several independent sensors detects: 1 - prod(1 - Pd).

    Parameters
    ----------
    pd_per_sensor : array_like
        Pd of each sensor, sensors along ``axis``; each 0..1.
    axis : int
        The sensor axis.
    """
    p = _probabilities("pd_per_sensor", pd_per_sensor, axis)
    with np.errstate(divide="ignore"):  # a sensor with Pd = 1: log(0) = -inf, and the product is 0
        return -np.expm1(np.sum(np.log1p(-p), axis=0))  # exact for tiny Pd, where 1 - prod(1 - p) rounds


def fuse_k_of_n(pd_per_sensor, k, axis=0):
    """Probability that at least k of n independent sensors detect (exact Poisson-binomial tail).

    The distribution of the number of detecting sensors is built one sensor at a time
    (q_j <- q_j (1 - p) + q_(j-1) p), vectorised over every other axis.

    Parameters
    ----------
    pd_per_sensor : array_like
        Pd of each sensor, sensors along ``axis``; each 0..1.
    k : int
        Sensors that must detect, 1 <= k <= n.
    axis : int
        The sensor axis.
    """
    p = _probabilities("pd_per_sensor", pd_per_sensor, axis)
    n = p.shape[0]
    if not float(k).is_integer() or not 1 <= k <= n:
        raise ParameterError("k", k, f"a whole number 1..{n} (the number of sensors)")
    counts = np.zeros((n + 1, *p.shape[1:]))
    counts[0] = 1.0
    for sensor in p:
        counts[1:] = counts[1:] * (1.0 - sensor) + counts[:-1] * sensor
        counts[0] = counts[0] * (1.0 - sensor)
    return np.clip(np.sum(counts[int(k) :], axis=0), 0.0, 1.0)


def approach_looks(start_range_m, stop_range_m, speed_m_s, look_rate_hz):
    """Ranges of a sensor's looks at a drone closing at constant speed [m], far to near.

    Parameters
    ----------
    start_range_m, stop_range_m : float
        First and last range of the approach [m], start > stop >= 0.
    speed_m_s : float
        Closing speed [m/s], > 0.
    look_rate_hz : float
        Frames or scans per second [Hz], > 0.

    Returns
    -------
    ndarray
        Look ranges start, start - v / f, ... down to stop (inclusive when it falls on a look).
    """
    start, stop, v, f = (
        float(x)
        for x in require_all(
            ("start_range_m", start_range_m, {"gt": 0}),
            ("stop_range_m", stop_range_m, {"ge": 0}),
            ("speed_m_s", speed_m_s, {"gt": 0}),
            ("look_rate_hz", look_rate_hz, {"gt": 0}),
        )
    )
    if stop >= start:
        raise ParameterError("stop_range_m", stop, f"below start_range_m = {start:g}")
    step = v / f
    count = int(np.floor((start - stop) / step * (1 + 1e-12))) + 1
    if count > MAX_LOOKS:
        max_rate = MAX_LOOKS * v / (start - stop)
        raise ParameterError(
            "look_rate_hz",
            f,
            f"at most {max_rate:g} Hz for an approach of {start - stop:g} m at {v:g} m/s ({MAX_LOOKS:g} looks)",
        )
    return start - step * np.arange(count)


def cumulative_pd(pd_at_look, correlation="independent"):
    """Cumulative probability of detection after each look of an approach (looks along the last axis).

    Parameters
    ----------
    pd_at_look : array_like
        Pd of each look, in the order of the looks (far to near), each 0..1.
    correlation : {"independent", "correlated"}
        Looks independent (1 - prod(1 - Pd)) or fully correlated (running maximum).
    """
    if correlation not in CORRELATIONS:
        raise ParameterError("correlation", correlation, ", ".join(CORRELATIONS))
    p = require("pd_at_look", pd_at_look, ge=0, le=1)
    if correlation == "correlated":
        return np.maximum.accumulate(p, axis=-1)
    with np.errstate(divide="ignore"):
        return -np.expm1(np.cumsum(np.log1p(-p), axis=-1))


def first_detection(look_range_m, cumulative):
    """Distribution of the first-detection range, and its median, from a cumulative Pd.

    Parameters
    ----------
    look_range_m : array_like
        Range of each look [m], far to near (last axis).
    cumulative : array_like
        Cumulative Pd after each look (:func:`cumulative_pd`), non-decreasing.

    Returns
    -------
    dict
        ``probability``: the probability that the first detection happens at each look;
        ``never``: the probability of no detection over the approach; ``median_range_m``: the
        median of that discrete distribution, the range of the first look by which detection has
        happened with probability >= 0.5 (a look, never a point between two), None where the
        approach ends first (as a float array with NaN when ``cumulative`` has
        more than one row).
    """
    r = require("look_range_m", look_range_m, ge=0)
    c = require("cumulative", cumulative, ge=0, le=1)
    probability = np.diff(c, axis=-1, prepend=0.0)
    never = 1.0 - c[..., -1]
    c2, r2 = np.atleast_2d(c), np.broadcast_to(np.atleast_2d(r), np.atleast_2d(c).shape)
    median = np.full(c2.shape[0], np.nan)
    for row in range(c2.shape[0]):
        j = int(np.searchsorted(c2[row], 0.5))  # the first look by which detection has happened with P >= 0.5
        if j < c2.shape[1]:
            median[row] = r2[row, j]
    if c.ndim <= 1:
        median_out = None if np.isnan(median[0]) else float(median[0])
    else:
        median_out = median.reshape(c.shape[:-1])
    return {"probability": probability, "never": never, "median_range_m": median_out}
