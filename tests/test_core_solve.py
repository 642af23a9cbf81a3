"""Exact solvers: Lambert-W closed form and the bracketed array root solve."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.special import lambertw

from csuas.core.solve import bracketed_root, lambertw_exp, solve_log_linear


def test_lambertw_exp_matches_scipy_where_representable():
    log_x = np.linspace(-30, 600, 500)
    np.testing.assert_allclose(lambertw_exp(log_x), lambertw(np.exp(log_x)).real, rtol=1e-12)


def test_lambertw_exp_far_beyond_float_range():
    log_x = np.array([1e3, 1e5, 1e8])
    w = lambertw_exp(log_x)
    np.testing.assert_allclose(w + np.log(w), log_x, rtol=1e-14)  # W e^W = x  <=>  W + ln W = ln x


@given(st.floats(-200, 5000), st.floats(0, 1.0), st.sampled_from([2.0, 4.0]))
def test_solve_log_linear_satisfies_its_equation(k, a, n):
    r = float(solve_log_linear(k, a, n))
    assert np.isfinite(r) and r > 0
    assert 10 * n * math.log10(r) + a * r == pytest.approx(k, abs=1e-9 * max(1.0, abs(k)))


def test_solve_log_linear_limits():
    r = solve_log_linear([-np.inf, np.inf, 60.0], [1e-3, 1e-3, 0.0], 2.0)
    assert r[0] == 0.0 and r[1] == np.inf and r[2] == pytest.approx(1000.0)


def test_bracketed_root_on_arrays():
    targets = np.array([0.5, 2.0, 10.0, 1e5])
    root, found = bracketed_root(lambda x: x**3 - targets, np.zeros(4), np.full(4, 1e3))
    assert found.all()
    np.testing.assert_allclose(root, np.cbrt(targets), rtol=1e-11)


def test_bracketed_root_reports_missing_roots():
    root, found = bracketed_root(lambda x: x + 1.0, np.zeros(3), np.ones(3))
    assert not found.any()


def test_bracketed_root_flat_and_steep_residuals():
    # a residual that is flat over most of the bracket, then steep (a bisection safeguard is needed)
    f = lambda x: np.tanh(50 * (x - np.array([0.9, 0.1])))
    root, found = bracketed_root(f, np.zeros(2), np.ones(2))
    assert found.all()
    np.testing.assert_allclose(root, [0.9, 0.1], atol=1e-10)
