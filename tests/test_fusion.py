"""Fusion of sensors and cumulative detection along an approach (core.fusion).

References: brute-force enumeration of every detection outcome, the closed form 1 - (1 - p)^n
of n independent looks, and Monte Carlo simulation of an approach.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core.fusion import approach_looks, cumulative_pd, first_detection, fuse_k_of_n, fuse_or


def _enumerate_at_least(p, k):
    total = 0.0
    for outcome in itertools.product((0, 1), repeat=len(p)):
        if sum(outcome) >= k:
            total += np.prod([pi if o else 1 - pi for pi, o in zip(p, outcome)])
    return total


@pytest.mark.parametrize("n", [1, 2, 3, 5])
def test_k_of_n_and_or_against_enumeration(n):
    rng = np.random.default_rng(n)
    p = rng.random(n)
    for k in range(1, n + 1):
        assert fuse_k_of_n(p, k) == pytest.approx(_enumerate_at_least(p, k), abs=1e-14)
    assert fuse_or(p) == pytest.approx(_enumerate_at_least(p, 1), abs=1e-14)


def test_or_fusion_keeps_tiny_probabilities():
    assert fuse_or([1e-18, 2e-18]) == pytest.approx(3e-18, rel=1e-12)  # 1 - prod(1 - p) would give 0
    assert fuse_or([1.0, 0.3]) == 1.0


def test_fusion_vectorised_over_ranges():
    pd = np.array([[0.1, 0.5, 0.9], [0.2, 0.2, 0.2], [0.0, 1.0, 0.5]])  # sensors x ranges
    both = fuse_k_of_n(pd, 3)
    np.testing.assert_allclose(both, np.prod(pd, axis=0), atol=1e-15)
    np.testing.assert_allclose(fuse_or(pd.T, axis=1), fuse_or(pd), atol=1e-15)


def test_approach_looks_and_cumulative_closed_form():
    looks = approach_looks(1000.0, 0.0, 10.0, 2.0)  # 5 m a look
    assert looks[0] == 1000.0 and looks[-1] == pytest.approx(0.0, abs=1e-9) and len(looks) == 201
    p = 0.03
    cumulative = cumulative_pd(np.full(looks.size, p))
    np.testing.assert_allclose(cumulative, 1 - (1 - p) ** np.arange(1, looks.size + 1), rtol=1e-12)
    correlated = cumulative_pd([0.1, 0.4, 0.3, 0.6], "correlated")
    assert correlated.tolist() == [0.1, 0.4, 0.4, 0.6]


def test_first_detection_against_a_simulated_approach():
    looks = approach_looks(2000.0, 10.0, 15.0, 1.0)
    pd = np.clip(1.5 - looks / 1000.0, 0.0, 1.0) * 0.3  # rising as the drone closes
    result = first_detection(looks, cumulative_pd(pd))
    rng = np.random.default_rng(5)
    trials = 50_000
    detected = rng.random((trials, looks.size)) < pd
    first = np.where(detected.any(axis=1), detected.argmax(axis=1), -1)
    counts = np.bincount(first[first >= 0], minlength=looks.size) / trials
    sigma = np.sqrt(result["probability"] * (1 - result["probability"]) / trials)
    assert np.all(np.abs(counts - result["probability"]) <= 4 * sigma + 1e-4)
    assert np.mean(first < 0) == pytest.approx(result["never"], abs=4 * np.sqrt(result["never"] / trials) + 1e-4)
    ranges = np.where(first >= 0, looks[np.maximum(first, 0)], -np.inf)
    simulated_median = np.median(ranges)  # detections happen at or before (farther than) this range half the time
    assert result["median_range_m"] == pytest.approx(simulated_median, abs=15.0)  # one look of spacing


def test_median_is_none_when_the_approach_ends_first():
    looks = approach_looks(100.0, 0.0, 10.0, 1.0)
    assert first_detection(looks, cumulative_pd(np.full(looks.size, 0.01)))["median_range_m"] is None


def test_bad_input():
    with pytest.raises(ParameterError, match="k"):
        fuse_k_of_n([0.5, 0.5], 3)
    with pytest.raises(ParameterError, match="pd_per_sensor"):
        fuse_or([])
    with pytest.raises(ParameterError, match="pd_per_sensor"):
        fuse_or([0.5, 1.5])
    with pytest.raises(ParameterError, match="stop_range_m"):
        approach_looks(100.0, 200.0, 10.0, 1.0)
    with pytest.raises(ParameterError, match="look_rate_hz"):
        approach_looks(50_000.0, 0.0, 1.0, 1e6)
    with pytest.raises(ParameterError, match="correlation"):
        cumulative_pd([0.5], "partial")
