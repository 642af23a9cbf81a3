"""Line-of-sight horizons (core/horizon.py) against their closed forms and textbook numbers."""

import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core import horizon

A = 6_371_000.0


def test_radio_horizon_of_a_2_m_antenna_is_5_83_km():
    """4/3 Earth: d = sqrt(2 k a h) = 5.83 km for h = 2 m (radar handbooks: 4.12 sqrt(h) km, h in m)."""
    d = horizon.horizon_distance_m(2.0)
    assert d == pytest.approx(math.sqrt(2 * (4 / 3) * A * 2.0), rel=1e-12)
    assert d / 1000 == pytest.approx(4.12 * math.sqrt(2.0), rel=2e-3)


def test_optical_horizon_uses_refraction_coefficient_0_13():
    d = horizon.horizon_distance_m(120.0, k=horizon.K_OPTICAL)
    assert d == pytest.approx(math.sqrt(2 * A * 120.0 / (1 - 0.13)), rel=1e-12)
    assert horizon.horizon_distance_m(120.0, k=1.0) < d < horizon.horizon_distance_m(120.0)


def test_line_of_sight_limit_is_the_sum_of_both_horizons_and_broadcasts():
    h1, h2 = np.array([[2.0], [10.0]]), np.array([0.0, 30.0, 120.0])
    limit = horizon.line_of_sight_limit_m(h1, h2)
    assert limit.shape == (2, 3)
    expected = np.sqrt(2 * 4 / 3 * A * h1) + np.sqrt(2 * 4 / 3 * A * h2)
    np.testing.assert_allclose(limit, expected, rtol=1e-12)
    assert horizon.line_of_sight_limit_m(0.0, 0.0) == 0.0


@pytest.mark.parametrize("bad", [-1.0, float("nan")])
def test_a_negative_or_nan_height_is_refused(bad):
    with pytest.raises(ParameterError, match="height_m"):
        horizon.horizon_distance_m(bad)
