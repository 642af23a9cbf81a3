"""Radar probability of detection (core.radar_detection) against closed forms, published values,
numerical integration of the defining integrals and Monte Carlo simulation of the detector.

References: Richards, Fundamentals of Radar Signal Processing (2014), ch. 6 (Albersheim's example,
13.1 dB at Pd 0.9, Pfa 1e-6, N 1); Meyer & Mayer (1973) / DiFranco & Rubin (1968) single-pulse
values at Pd 0.9, Pfa 1e-6 (steady 13.2 dB, Swerling 1 21.1 dB); the Swerling 1 single-pulse
closed form Pd = Pfa^(1 / (1 + SNR)).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate, optimize, special, stats

from csuas.base.errors import InputErrors, ParameterError
from csuas.core.radar_detection import (
    albersheim_snr_db,
    pd_exact,
    required_snr_db,
    shnidman_snr_db,
    threshold,
)
from csuas.validation.detection.monte_carlo import simulate_detector


def test_swerling_1_single_pulse_closed_form():
    snr_db = np.linspace(-5.0, 35.0, 41)
    for pfa in (1e-3, 1e-6, 1e-9):
        snr = 10 ** (snr_db / 10)
        np.testing.assert_allclose(pd_exact(snr_db, pfa, 1, 1), pfa ** (1 / (1 + snr)), rtol=1e-10)


def test_threshold_is_the_noise_only_tail():
    for n, pfa in ((1, 1e-6), (10, 1e-4), (500, 1e-10)):
        t = threshold(pfa, n)
        assert stats.gamma.sf(t, n) == pytest.approx(pfa, rel=1e-9)
    assert threshold(1e-6, 1) == pytest.approx(-math.log(1e-6), rel=1e-12)  # exponential noise, N = 1


@pytest.mark.parametrize(
    "swerling, snr_db_printed, tolerance_db",
    [(0, 13.2, 0.05), (1, 21.1, 0.05), (2, 21.1, 0.05)],  # Meyer & Mayer / DiFranco & Rubin, Pd 0.9, Pfa 1e-6, N 1
)
def test_published_single_pulse_requirements(swerling, snr_db_printed, tolerance_db):
    assert required_snr_db(0.9, 1e-6, 1, swerling) == pytest.approx(snr_db_printed, abs=tolerance_db)


def test_albersheim_reproduces_richards_example():
    assert albersheim_snr_db(0.9, 1e-6, 1) == pytest.approx(13.1, abs=0.05)


def _steady_quadrature(snr, pfa, n):
    """Pd of a steady target: the integral of the noncentral chi-square density above the threshold."""
    t = special.gammainccinv(n, pfa)
    dist = stats.ncx2(2 * n, 2 * n * snr)
    mean, sd = dist.mean(), dist.std()
    upper = max(2 * t, mean) + 60 * sd  # the density is negligible beyond
    points = [mean] if 2 * t < mean < upper else None
    return integrate.quad(dist.pdf, 2 * t, upper, points=points, limit=400, epsabs=1e-13)[0]


def _scan_to_scan_quadrature(snr, pfa, n, dof):
    """Pd of Swerling 1 (dof 2) or 3 (dof 4): the steady Pd averaged over the chi-square RCS."""
    t = special.gammainccinv(n, pfa)
    k = dof / 2
    weight = stats.gamma(k, scale=1 / k).pdf
    integrand = lambda x: stats.ncx2.sf(2 * t, 2 * n, 2 * n * snr * x) * weight(x)
    return integrate.quad(integrand, 0, np.inf, limit=400, epsabs=1e-12)[0]


@pytest.mark.parametrize("n", [1, 2, 5, 30])
@pytest.mark.parametrize("snr_db", [-3.0, 5.0, 12.0, 20.0])
def test_steady_and_scan_to_scan_against_their_defining_integrals(n, snr_db):
    snr, pfa = 10 ** (snr_db / 10), 1e-6
    assert pd_exact(snr_db, pfa, n, 0) == pytest.approx(_steady_quadrature(snr, pfa, n), abs=1e-9)
    assert pd_exact(snr_db, pfa, n, 1) == pytest.approx(_scan_to_scan_quadrature(snr, pfa, n, 2), abs=1e-8)
    assert pd_exact(snr_db, pfa, n, 3) == pytest.approx(_scan_to_scan_quadrature(snr, pfa, n, 4), abs=1e-8)


@pytest.mark.parametrize("integration", ["noncoherent", "coherent"])
@pytest.mark.parametrize("swerling", [0, 1, 2, 3, 4])
@pytest.mark.parametrize("n", [1, 4, 16])
def test_monte_carlo_detector_reproduces_the_exact_pd(swerling, n, integration):
    rng = np.random.default_rng(1000 * swerling + 10 * n + (integration == "coherent"))
    trials, pfa = 100_000, 1e-3
    for snr_db in (0.0, 6.0):
        exact = float(pd_exact(snr_db, pfa, n, swerling, integration))
        simulated, _ = simulate_detector(snr_db, pfa, n, swerling, integration, trials, rng)
        sigma = math.sqrt(exact * (1 - exact) / trials)
        assert abs(simulated - exact) <= 4 * sigma + 1e-4, (snr_db, exact, simulated)


def test_the_inverse_returns_the_requested_pd_and_matches_a_scalar_root_search():
    pd = np.array([0.1, 0.5, 0.9, 0.99, 0.999])
    for swerling in range(5):
        for n in (1, 7, 100):
            snr = required_snr_db(pd, 1e-6, n, swerling)
            np.testing.assert_allclose(pd_exact(snr, 1e-6, n, swerling), pd, atol=1e-9)
    root = optimize.brentq(lambda x: _steady_quadrature(10 ** (x / 10), 1e-6, 4) - 0.9, -20, 40, xtol=1e-10)
    assert required_snr_db(0.9, 1e-6, 4, 0) == pytest.approx(root, abs=1e-4)


def test_shnidman_within_its_stated_accuracy_of_the_exact_curves():
    pd, pfa = np.array([0.1, 0.2, 0.5, 0.8, 0.95, 0.99]), np.array([1e-9, 1e-6, 1e-3])
    worst = 0.0
    for swerling in range(5):
        for n in (1, 10, 100):
            exact = required_snr_db(pd[:, None], pfa[None, :], n, swerling)
            approx = shnidman_snr_db(pd[:, None], pfa[None, :], n, swerling)
            worst = max(worst, float(np.max(np.abs(approx - exact))))
    assert worst < 1.1  # Shnidman (2002): "about 1 dB"; measured worst 1.04 dB (Swerling 1 and 2, N = 1)


def test_albersheim_accuracy_for_a_steady_target():
    """Within 0.3 dB of the exact square law for 0.3 <= Pd <= 0.9; at Pd = 0.1 it is far off (documented)."""
    pd, pfa = np.array([0.3, 0.5, 0.7, 0.9]), np.array([1e-7, 1e-5, 1e-3])
    for n in (1, 2, 10, 100, 1000):
        exact = required_snr_db(pd[:, None], pfa[None, :], n, 0)
        assert np.max(np.abs(albersheim_snr_db(pd[:, None], pfa[None, :], n) - exact)) < 0.3
    low = albersheim_snr_db(0.1, 1e-3, 1) - required_snr_db(0.1, 1e-3, 1, 0)
    assert -4.2 < low < -4.0  # the docstring's measured worst case


def test_the_approximations_are_selectable_from_the_inverse():
    assert required_snr_db(0.9, 1e-6, 10, 0, method="albersheim") == albersheim_snr_db(0.9, 1e-6, 10)
    assert required_snr_db(0.9, 1e-6, 10, 3, method="shnidman") == shnidman_snr_db(0.9, 1e-6, 10, 3)
    with pytest.raises(ParameterError, match="albersheim"):
        required_snr_db(0.9, 1e-6, 10, 1, method="albersheim")


def test_hard_cases_never_nan():
    snr = np.array([-300.0, -100.0, 0.0, 100.0, 300.0])
    for swerling in range(5):
        for n in (1, 1000):
            for integration in ("noncoherent", "coherent"):
                pd = pd_exact(snr, 1e-12, n, swerling, integration)
                assert np.all(np.isfinite(pd))
                assert pd[0] == pytest.approx(1e-12, rel=1e-9) and pd[-1] == 1.0
                assert np.all(np.diff(pd) >= 0)


def test_broadcasting_zero_d_and_float32():
    snr = np.array([[0.0, 5.0, 10.0], [15.0, 20.0, 25.0]])
    pd = pd_exact(snr, 1e-6, np.array([[1], [8]]), 1)
    assert pd.shape == (2, 3)
    for i in range(2):
        for j in range(3):
            assert pd[i, j] == pd_exact(snr[i, j], 1e-6, [1, 8][i], 1)
    assert np.ndim(pd_exact(10.0, 1e-6)) == 0
    assert pd_exact(np.float32(10.0), np.float32(1e-6)) == pytest.approx(pd_exact(10.0, 1e-6), rel=1e-6)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"pfa": 0.0}, "pfa"),
        ({"pfa": 1.0}, "pfa"),
        ({"n_pulses": 0}, "n_pulses"),
        ({"n_pulses": 2.5}, "n_pulses"),
        ({"swerling": 5}, "swerling"),
        ({"integration": "magic"}, "integration"),
        ({"snr_db": float("nan")}, "snr_db"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, name):
    args = {"snr_db": 10.0, "pfa": 1e-6, "n_pulses": 1, "swerling": 0} | kwargs
    with pytest.raises((ParameterError, InputErrors), match=name):
        pd_exact(**args)


def test_several_bad_inputs_are_reported_together():
    with pytest.raises(InputErrors) as info:
        pd_exact(10.0, 2.0, 0, 7)
    text = str(info.value)
    assert "pfa" in text and "n_pulses" in text and "swerling" in text


@pytest.mark.parametrize("pd, why", [(0.0, "pd"), (1.0, "infinite"), (1e-7, "no signal")])
def test_an_unreachable_pd_is_a_clear_error(pd, why):
    with pytest.raises(ParameterError, match=why):
        required_snr_db(pd, 1e-6, 1, 0)
