"""Exact distribution of the first time M of the last N looks detect (M-of-N track confirmation).

A track is confirmed at the first look k at which at least M of the looks k-N+1..k detected (looks
before the first count as misses). With independent looks of known Pd_k the probability of that
event at every look follows from a dynamic program over the detection pattern of the last N-1
looks (2^(N-1) states, each a bit mask): at each look the probability mass of every unconfirmed
pattern moves to the pattern shifted by a hit (Pd_k) or a miss (1 - Pd_k); a hit that brings the
window's count to M confirms, and its mass leaves the chain. This is the sliding-window detector's
exact cumulative probability (Richards, *Fundamentals of Radar Signal Processing*, 2nd ed., Section
6.5 gives the stationary M-of-N probability; here the looks' Pd varies along an approach).
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require

#: Largest window N (the program holds 2^(N-1) states).
MAX_WINDOW = 16


def first_confirmation(pd_per_look, m: int, n: int) -> np.ndarray:
    """Probability that M-of-N confirmation happens first at each look.

    Parameters
    ----------
    pd_per_look : array_like
        Pd of each look in time order, 0..1 (independent looks).
    m, n : int
        Detections M needed in a window of N consecutive looks, 1 <= M <= N <= MAX_WINDOW.

    Returns
    -------
    ndarray
        P(first confirmation at look k), same length as ``pd_per_look``; 1 - its sum is the
        probability of no confirmation over the looks.
    """
    pd = require("pd_per_look", pd_per_look, ge=0, le=1).ravel()
    if not (isinstance(n, (int, np.integer)) and 1 <= n <= MAX_WINDOW):
        raise ParameterError("n", n, f"a whole number 1 to {MAX_WINDOW}")
    if not (isinstance(m, (int, np.integer)) and 1 <= m <= n):
        raise ParameterError("m", m, f"a whole number 1 to n = {n}")
    states = 1 << (n - 1)
    masks = np.arange(states)
    ones = np.array([bin(s).count("1") for s in masks])  # hits among the last N-1 looks
    keep = states - 1
    hit_to, miss_to = ((masks << 1) | 1) & keep, (masks << 1) & keep
    confirms = ones + 1 >= m  # a hit now completes M in the window of N
    mass = np.zeros(states)
    mass[0] = 1.0
    out = np.empty(pd.size)
    for k, p in enumerate(pd):
        out[k] = p * mass[confirms].sum()
        nxt = np.zeros(states)
        np.add.at(nxt, miss_to, (1.0 - p) * mass)
        np.add.at(nxt, hit_to[~confirms], p * mass[~confirms])
        mass = nxt
    return out
