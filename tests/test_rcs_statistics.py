"""RCS statistics over aspects (core.rcs_statistics) against samples of known distributions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core.radar_detection import pd_exact
from csuas.core.rcs_statistics import fit_chi_square, fit_lognormal, pd_over_rcs_samples, rcs_summary


@pytest.mark.parametrize("k", [0.5, 1.0, 2.0, 5.0])
def test_chi_square_fit_recovers_the_gamma_shape(k):
    rng = np.random.default_rng(int(10 * k))
    samples = rng.gamma(k, 0.01 / k, 40_000)
    fit = fit_chi_square(samples)
    # the MLE's relative standard deviation is at most sqrt(2 / n) (large k) and below it for k <= 5
    assert fit["k"] == pytest.approx(k, rel=4 * math.sqrt(2.0 / 40_000))
    assert fit["dof"] == pytest.approx(2 * fit["k"])
    assert fit["nearest_swerling_scan"] == (1 if k <= 1.0 else 3)
    assert fit["log_likelihood_ratio"] >= 0.0


def test_lognormal_fit_and_summary():
    rng = np.random.default_rng(1)
    db = rng.normal(-12.81, 3.74, 50_000)  # 3GPP TR 38.901 small UAV
    fit = fit_lognormal(10 ** (db / 10))
    assert fit["mean_dbsm"] == pytest.approx(-12.81, abs=4 * 3.74 / math.sqrt(50_000))
    assert fit["std_db"] == pytest.approx(3.74, rel=0.02)
    summary = rcs_summary(10 ** (db / 10))
    assert summary["median_dbsm"] == pytest.approx(-12.81, abs=0.1)
    assert summary["p10_dbsm"] == pytest.approx(-12.81 - 1.2816 * 3.74, abs=0.15)
    sigma_ln = 3.74 * math.log(10) / 10  # mean of a log-normal: exp(mu + s^2 / 2)
    assert summary["mean_dbsm"] == pytest.approx(-12.81 + 10 * math.log10(math.exp(sigma_ln**2 / 2)), abs=0.1)


def test_pd_over_exponential_samples_is_swerling_1():
    """Samples of an exponential RCS give, in the limit, the Swerling 1 Pd with the same mean."""
    n = 20_000
    samples = -np.log(1 - (np.arange(n) + 0.5) / n)  # exponential quantiles: a low-noise sample
    snr = np.array([5.0, 13.0, 21.0])
    np.testing.assert_allclose(pd_over_rcs_samples(snr, samples, 1e-6), pd_exact(snr, 1e-6, 1, 1), atol=2e-3)


def test_pd_over_constant_samples_is_the_steady_pd():
    samples = np.full(16, 0.01)
    np.testing.assert_allclose(pd_over_rcs_samples([3.0, 10.0], samples, 1e-4, 8), pd_exact([3.0, 10.0], 1e-4, 8, 0))
    assert fit_chi_square(samples)["k"] == np.inf


def test_bad_samples():
    with pytest.raises(ParameterError, match="rcs_m2"):
        rcs_summary([0.01, 0.02])
    with pytest.raises(ParameterError, match="rcs_m2"):
        fit_lognormal(np.r_[np.ones(10), -1.0])
