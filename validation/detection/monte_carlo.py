"""Monte Carlo simulation of radar detectors: the independent reference of core.radar_detection.

Complex Gaussian noise of unit power per sample plus a target whose RCS is drawn per the Swerling
case (docs/detection.md): one draw per dwell for Swerling 0, 1 and 3, one per pulse for 2 and 4,
whatever the integration (coherent integration of pulse-to-pulse echoes sums independent phasors).
The detector either sums the squared magnitudes of the N pulses (noncoherent) or takes the
squared magnitude of their sum over N (coherent), and compares with the threshold that gives Pfa
under noise alone (gamma quantile, independent of the code under test).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special


def simulate_detector(snr_db, pfa, n_pulses, swerling, integration, trials, rng) -> tuple[float, float]:
    """Fraction of simulated dwells that cross the threshold, and its binomial standard error.

    Parameters
    ----------
    snr_db : float
        Mean single-pulse SNR [dB].
    pfa : float
        Probability of false alarm.
    n_pulses : int
    swerling : int
        0-4.
    integration : {"noncoherent", "coherent"}
    trials : int
        Simulated dwells.
    rng : numpy.random.Generator
    """
    snr = 10 ** (snr_db / 10)
    n = int(n_pulses)
    draws = n if swerling in (2, 4) else 1
    if swerling == 0:
        rcs = np.ones((trials, n))
    else:
        shape = 1.0 if swerling in (1, 2) else 2.0
        rcs = np.repeat(rng.gamma(shape, 1 / shape, size=(trials, draws)), n // draws, axis=1)
    signal = np.sqrt(snr * rcs) * np.exp(2j * np.pi * rng.random((trials, draws)))
    return _detected_fraction(signal, n, pfa, integration, trials, rng)


def _detected_fraction(signal, n: int, pfa: float, integration: str, trials: int, rng) -> tuple[float, float]:
    """Add unit-power complex noise to ``signal`` (trials, N or 1), detect, and count threshold crossings."""
    noise = (rng.standard_normal((trials, n)) + 1j * rng.standard_normal((trials, n))) / math.sqrt(2)
    if integration == "coherent":
        statistic = np.abs(np.sum(signal + noise, axis=1)) ** 2 / n
        threshold = -math.log(pfa)
    else:
        statistic = np.sum(np.abs(signal + noise) ** 2, axis=1)
        threshold = special.gammainccinv(n, pfa)
    fraction = float(np.mean(statistic > threshold))
    return fraction, math.sqrt(max(fraction * (1 - fraction), 1.0 / trials) / trials)


def simulate_over_rcs_samples(snr_db_at_mean, rcs_m2, pfa, n_pulses, trials, rng) -> tuple[float, float]:
    """Detections of a scan-to-scan target whose RCS per dwell is drawn from samples (noncoherent)."""
    s = np.asarray(rcs_m2, dtype=float)
    draw = rng.choice(s / s.mean(), size=(trials, 1)) * 10 ** (snr_db_at_mean / 10)
    n = int(n_pulses)
    signal = np.sqrt(draw) * np.exp(2j * np.pi * rng.random((trials, 1)))
    return _detected_fraction(signal, n, pfa, "noncoherent", trials, rng)
