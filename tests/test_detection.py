"""Detection probability of the EO, thermal, RF, acoustic and lidar sensors (core.detection).

References: the paper's Table 21 (P_desired against n_TTPF = N / N50), the TTPF formula written
out here, Monte Carlo simulation of each detector, numerical integration of the fading average,
and exact Poisson sums.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate, special, stats

from csuas.base.errors import InputErrors, ParameterError
from csuas.core import johnson
from csuas.core.checks import require_all
from csuas.core.detection import (
    energy_detector_pd,
    energy_detector_threshold,
    imaging_pd,
    lidar_pd_gaussian,
    lidar_pd_poisson,
    photon_counting_threshold,
    ttpf_cycles_ratio,
    ttpf_probability,
)

#: Table 21 of the paper: (P_desired, n_TTPF), every column.
TABLE_21 = [
    (1.00, 3.00),
    (0.95, 2.00),
    (0.80, 1.50),
    (0.50, 1.00),
    (0.30, 0.75),
    (0.10, 0.50),
    (0.02, 0.25),
    (0.0, 0.0),
]


@pytest.mark.parametrize("p_desired, n_ttpf", TABLE_21)
def test_ttpf_reproduces_every_column_of_table_21(p_desired, n_ttpf):
    assert ttpf_probability(n_ttpf) == pytest.approx(p_desired, abs=0.021)  # worst: 0.8206 at n_TTPF 1.5


def test_ttpf_closed_form_both_exponents():
    x = np.array([0.3, 1.0, 2.5, 7.0])
    for name, (e0, e1) in {"johnson": (2.7, 0.7), "ttp": (1.51, 0.24)}.items():
        e = e0 + e1 * x
        np.testing.assert_allclose(ttpf_probability(x, name), x**e / (1 + x**e), rtol=1e-12)
    assert ttpf_probability(1.0, "ttp") == 0.5


@pytest.mark.parametrize("p_desired, n_ttpf", [row for row in TABLE_21 if 0 < row[0] < 1])
def test_ttpf_inverse_gives_table_21_multipliers(p_desired, n_ttpf):
    x = float(ttpf_cycles_ratio(p_desired))
    assert ttpf_probability(x) == pytest.approx(p_desired, abs=1e-12)
    assert x == pytest.approx(n_ttpf, rel=0.037)


def test_ttpf_extremes_are_finite():
    assert ttpf_probability([0.0, 1e-300, 1e300, np.inf]).tolist() == [0.0, 0.0, 1.0, 1.0]


@pytest.mark.parametrize("p_desired, n_ttpf", [row for row in TABLE_21 if 0 < row[1]])
def test_pd_at_the_table_21_range_is_the_desired_probability(p_desired, n_ttpf):
    """P(R_TTPF(P)) = P within Table 21's own agreement with the TTPF (Eq. 18 range, independent module)."""
    ifov = johnson.ifov_rad(10.0, 1920)
    r50 = float(johnson.johnson_range_m(0.101, ifov, 1.0, 1.0))
    r_p = float(johnson.johnson_range_m(0.101, ifov, 1.0, n_ttpf))
    assert imaging_pd(r_p, r50) == pytest.approx(p_desired, abs=0.021)
    assert imaging_pd(r50, r50) == 0.5


def test_imaging_pd_cutoff_zero_range_and_monotone():
    r = np.array([0.0, 100.0, 555.5, 1000.0, 5000.0])
    pd = imaging_pd(r, 555.5, cutoff_range_m=2000.0)
    assert pd[0] == 1.0 and pd[2] == 0.5 and pd[-1] == 0.0
    assert np.all(np.diff(pd) <= 0)
    assert imaging_pd(100.0, 0.0) == 0.0  # no resolvable cycles at all


def _energy_monte_carlo(snr_db, pfa, m, fading, k_lin, trials, rng):
    snr = 10 ** (snr_db / 10)
    if fading == "none":
        gain = np.ones(trials)
    elif fading == "rayleigh":
        gain = rng.exponential(1.0, trials)
    else:  # Rician power: |sqrt(K/(K+1)) + sqrt(1/(K+1)) CN(0,1)|^2, mean 1
        diffuse = (rng.standard_normal(trials) + 1j * rng.standard_normal(trials)) / math.sqrt(2)
        gain = np.abs(math.sqrt(k_lin / (k_lin + 1)) + diffuse / math.sqrt(k_lin + 1)) ** 2
    amplitude = np.sqrt(snr * gain)[:, None] * np.exp(2j * np.pi * rng.random((trials, m)))
    noise = (rng.standard_normal((trials, m)) + 1j * rng.standard_normal((trials, m))) / math.sqrt(2)
    energy = np.sum(np.abs(amplitude + noise) ** 2, axis=1)
    return np.mean(energy > special.gammainccinv(m, pfa))


@pytest.mark.parametrize("fading, k_db", [("none", 0.0), ("rayleigh", 0.0), ("rician", 6.0)])
@pytest.mark.parametrize("m", [1, 8])
def test_energy_detector_against_monte_carlo(fading, k_db, m):
    rng = np.random.default_rng(7 * m + len(fading))
    trials, pfa = 100_000, 1e-2
    for snr_db in (0.0, 8.0):
        exact = float(energy_detector_pd(snr_db, pfa, m, fading, k_db))
        simulated = _energy_monte_carlo(snr_db, pfa, m, fading, 10 ** (k_db / 10), trials, rng)
        sigma = math.sqrt(exact * (1 - exact) / trials)
        assert abs(simulated - exact) <= 4 * sigma + 1e-4, (snr_db, exact, simulated)


def test_energy_detector_m1_closed_form_and_threshold():
    """M = 1 is the single-sample square-law detector: Rayleigh fading gives Pfa^(1/(1+snr))."""
    snr = 10 ** (np.array([-5.0, 3.0, 12.0]) / 10)
    np.testing.assert_allclose(
        energy_detector_pd(10 * np.log10(snr), 1e-4, 1, "rayleigh"), 1e-4 ** (1 / (1 + snr)), rtol=1e-6
    )
    assert energy_detector_threshold(1e-4, 1) == pytest.approx(-math.log(1e-4), rel=1e-12)
    assert stats.gamma.sf(energy_detector_threshold(1e-6, 40), 40) == pytest.approx(1e-6, rel=1e-9)


@pytest.mark.parametrize("m", [1, 4, 100, 1000])
@pytest.mark.parametrize("k_db", [None, 0.0, 8.0, 20.0])
def test_fading_average_against_adaptive_quadrature(m, k_db):
    """The composite rule against scipy's adaptive integral of the steady Pd over the fading density."""
    k = 0.0 if k_db is None else 10 ** (k_db / 10)
    dist = stats.expon() if k_db is None else stats.ncx2(2, 2 * k, scale=1 / (2 * (1 + k)))
    lo, hi = dist.ppf(1e-16), dist.isf(1e-16)
    worst = 0.0
    for snr_db in (-10.0, 0.0, 12.0, 30.0):
        for pfa in (1e-4, 1e-9):
            snr, t = 10 ** (snr_db / 10), special.gammainccinv(m, pfa)
            step = max(t - m, 0) / (m * snr)  # where the steady Pd rises
            points = [x for x in (0.5 * step, step, 2 * step, 1.0) if lo < x < hi]
            integrand = lambda g, t=t, snr=snr: stats.ncx2.sf(2 * t, 2 * m, 2 * m * snr * g) * dist.pdf(g)
            reference = integrate.quad(integrand, lo, hi, points=points, limit=1000, epsabs=1e-14, epsrel=1e-13)[0]
            fading = "rayleigh" if k_db is None else "rician"
            computed = float(energy_detector_pd(snr_db, pfa, m, fading, 0.0 if k_db is None else k_db))
            worst = max(worst, abs(computed - reference))
    assert worst < 1e-6


@pytest.mark.parametrize("m", [1, 4, 32, 500])
def test_rayleigh_fading_is_swerling_1_of_the_radar_detector(m):
    """Slow Rayleigh fading over M samples is a scan-to-scan exponential target: the Swerling 1 closed form."""
    from csuas.core.radar_detection import pd_exact

    snr = np.array([-8.0, 0.0, 6.0, 15.0, 30.0])
    for pfa in (1e-3, 1e-8):
        np.testing.assert_allclose(
            energy_detector_pd(snr, pfa, m, "rayleigh"), pd_exact(snr, pfa, m, 1), atol=1e-6, rtol=0
        )


def test_rician_limits_are_rayleigh_and_steady():
    snr = np.array([0.0, 6.0, 12.0])
    np.testing.assert_allclose(
        energy_detector_pd(snr, 1e-3, 4, "rician", -np.inf), energy_detector_pd(snr, 1e-3, 4, "rayleigh"), atol=1e-12
    )
    np.testing.assert_allclose(
        energy_detector_pd(snr, 1e-3, 4, "rician", 40.0), energy_detector_pd(snr, 1e-3, 4), atol=2e-3
    )


def test_lidar_gaussian_against_monte_carlo_and_closed_form():
    rng = np.random.default_rng(3)
    pfa, trials = 1e-3, 200_000
    for snr_db in (6.0, 12.0):
        amplitude = 10 ** (snr_db / 20)
        detected = np.mean(amplitude + rng.standard_normal(trials) > stats.norm.isf(pfa))
        exact = float(lidar_pd_gaussian(snr_db, pfa))
        assert abs(detected - exact) <= 4 * math.sqrt(exact * (1 - exact) / trials) + 1e-4
    assert lidar_pd_gaussian(-300.0, 1e-6) == pytest.approx(1e-6, rel=1e-9)
    assert lidar_pd_gaussian(300.0, 1e-12) == 1.0


def test_photon_counting_against_exact_poisson_sums():
    for noise, pfa in ((0.1, 1e-6), (5.0, 1e-3), (0.0, 1e-9)):
        k = int(photon_counting_threshold(noise, pfa))
        tail = lambda kk, mean: 1.0 - sum(math.exp(-mean) * mean**i / math.factorial(i) for i in range(kk))
        assert tail(k, noise) <= pfa * (1 + 1e-9)
        assert k == 1 or tail(k - 1, noise) > pfa
        for signal in (1.0, 4.0, 20.0):
            assert lidar_pd_poisson(signal, noise, pfa) == pytest.approx(tail(k, signal + noise), rel=1e-9, abs=1e-15)
    assert lidar_pd_poisson(0.0, 0.0, 1e-6) == 0.0  # no photons, no detection, no false alarm


def test_photon_counting_against_monte_carlo():
    rng = np.random.default_rng(11)
    k = photon_counting_threshold(2.0, 1e-3)
    counts = rng.poisson(6.0 + 2.0, 200_000)
    exact = float(lidar_pd_poisson(6.0, 2.0, 1e-3))
    assert abs(np.mean(counts >= k) - exact) <= 4 * math.sqrt(exact * (1 - exact) / 200_000)


def test_hard_cases_never_nan():
    for fading in ("none", "rayleigh", "rician"):
        pd = energy_detector_pd(np.array([-300.0, 0.0, 300.0]), 1e-12, 1000, fading, 3.0)
        assert np.all(np.isfinite(pd)) and pd[0] == pytest.approx(1e-12) and pd[-1] == 1.0
    assert np.all(np.isfinite(lidar_pd_gaussian(np.array([-300.0, 300.0]), 1e-12)))


def test_broadcasting_zero_d_and_float32():
    snr = np.array([[0.0, 5.0, 10.0], [15.0, 20.0, 25.0]])
    pd = energy_detector_pd(snr, 1e-3, np.array([[1], [8]]), "rayleigh")
    assert pd.shape == (2, 3) and pd[1, 2] == energy_detector_pd(25.0, 1e-3, 8, "rayleigh")
    assert np.ndim(energy_detector_pd(3.0, 1e-3)) == 0
    assert energy_detector_pd(np.float32(3.0), np.float32(1e-3)) == pytest.approx(energy_detector_pd(3.0, 1e-3))
    assert imaging_pd(np.float32(300.0), np.float32(555.5)) == pytest.approx(imaging_pd(300.0, 555.5), rel=1e-6)


def test_bad_inputs_name_their_parameters_together():
    with pytest.raises(InputErrors) as info:
        energy_detector_pd(float("nan"), 1.5, 0.5)
    assert all(name in str(info.value) for name in ("snr_db", "pfa", "time_bandwidth"))
    with pytest.raises(ParameterError, match="fading"):
        energy_detector_pd(3.0, 1e-3, 1, "nakagami")
    with pytest.raises(ParameterError, match="exponent"):
        ttpf_probability(1.0, "holst")
    with pytest.raises(ParameterError, match="cycles_ratio"):
        ttpf_probability(-1.0)
    with pytest.raises(ParameterError, match="noise_photons"):
        lidar_pd_poisson(1.0, -1.0, 1e-3)
    assert [float(a) for a in require_all(("a", 1.0, {"gt": 0}), ("b", 2.0, {}))] == [1.0, 2.0]
