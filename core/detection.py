"""Probability of detection of the EO, thermal, RF, acoustic and lidar sensors.

The paper's models (Sections 3.2-3.7) give one range per sensor: where a resolution or an SNR
meets its threshold. Its first stated limitation is that they "do not generate statistical
detection curves" (Section 5). This module gives the probability behind each threshold, with
the detector each modality is assumed to use stated as a parameter:

* EO and thermal IR: the target transfer probability function (TTPF) of the Johnson criteria,
  P = x^E / (1 + x^E) with x = N / N50 the cycles across d_crit over those of a 50 % task
  (Holst; Vollmerhausen & Driggers). The classic exponent E = 2.7 + 0.7 x reproduces the
  paper's Table 21 (N / N50 = n_TTPF) within 0.021; the targeting-task-performance (TTP) exponent
  E = 1.51 + 0.24 x is the later alternative. Since N is proportional to 1 / R,
  x = R_50 / R with R_50 the paper's Johnson range (Eq. 17-18 with n_TTPF = 1).
* RF (passive emission) and acoustics: an energy detector over a time-bandwidth product M
  (Urkowitz 1967): 2 M complex-sample degrees of freedom, Pfa from the central chi-square,
  Pd from the noncentral one; optionally Rayleigh or Rician fading of the received power,
  averaged by composite Gauss-Legendre quadrature in probability (error below 1e-6).
* Lidar: threshold detection of a return pulse in Gaussian noise (a linear-mode receiver),
  or photon counting with Poisson statistics (a Geiger-mode or photon-counting receiver).

References
----------
- G. C. Holst, Electro-Optical Imaging System Performance, 5th ed., SPIE, 2008, ch. 21 (TTPF).
- R. H. Vollmerhausen, E. Jacobs and R. G. Driggers, "New metric for predicting target
  acquisition performance", Opt. Eng. 43(11), 2004 (TTP exponent).
- H. Urkowitz, "Energy detection of unknown deterministic signals", Proc. IEEE 55(4), 1967.
- F. F. Digham, M.-S. Alouini and M. K. Simon, "On the energy detection of unknown signals
  over fading channels", IEEE Trans. Commun. 55(1), 2007.
- J. W. Goodman, Statistical Optics, Wiley, 1985, ch. 9 (photon counting).
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require, require_all
from csuas.core.solve import bracketed_root

#: TTPF exponents E(x) = E0 + E1 x: "johnson" (reproduces Table 21), "ttp" (Vollmerhausen et al. 2004).
TTPF_EXPONENTS = {"johnson": (2.7, 0.7), "ttp": (1.51, 0.24)}
FADING = ("none", "rayleigh", "rician")
#: Composite quadrature of the fading average: panel edges in probability and nodes per panel. Its
#: error against adaptive integration is below 1e-6 in Pd for SNR -10..30 dB, M 1..1000, Pfa 1e-9..1e-4,
#: K 0..20 dB (measured 3e-7; tests/test_detection.py).
FADING_PANEL_EDGES = np.array(
    [0, 1e-8, 1e-6, 1e-4, 1e-3, 1e-2, 0.05, 0.2, 0.5, 0.8, 0.95, 0.99, 0.999, 1 - 1e-4, 1 - 1e-6, 1 - 1e-8, 1]
)
FADING_NODES_PER_PANEL = 16


def _special():
    from scipy import special, stats

    return special, stats


def ttpf_probability(cycles_ratio, exponent="johnson"):
    """Target transfer probability function P(x) = x^E / (1 + x^E), E = E0 + E1 x (Table 21).

    Parameters
    ----------
    cycles_ratio : array_like
        x = N / N50, the cycles across d_crit over those of a 50 % task [-], >= 0.
    exponent : {"johnson", "ttp"}
        E = 2.7 + 0.7 x (classic; reproduces every column of Table 21 within 0.021, the largest
        gap at n_TTPF = 1.5: 0.8206 against 0.80) or E = 1.51 + 0.24 x (TTP era).

    Returns
    -------
    ndarray
        Probability of task success, 0 at x = 0, 0.5 at x = 1, -> 1 as x grows.
    """
    if exponent not in TTPF_EXPONENTS:
        raise ParameterError("exponent", exponent, ", ".join(TTPF_EXPONENTS))
    x = require("cycles_ratio", cycles_ratio, ge=0, allow_inf=True)
    e0, e1 = TTPF_EXPONENTS[exponent]
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        log_term = (e0 + e1 * x) * np.log(x)  # P = 1 / (1 + exp(-E ln x)), stable for any x
        p = 1.0 / (1.0 + np.exp(-log_term))
    return np.where(x == 0, 0.0, np.where(np.isinf(x), 1.0, p))


def ttpf_cycles_ratio(probability, exponent="johnson"):
    """Inverse of the TTPF: the cycles ratio x = N / N50 at which the task succeeds with a probability.

    The counterpart of Table 21's n_TTPF; the Johnson-era exponent gives each printed multiplier
    within 3.7 % (0.95: 2.04 for 2.00; 0.02: 0.259 for 0.25).

    Parameters
    ----------
    probability : array_like
        Probability of task success, 0 < P < 1 (P = 1 needs infinitely many cycles).
    exponent : {"johnson", "ttp"}
    """
    p = require("probability", probability, gt=0, lt=1)
    log_x, _ = bracketed_root(
        lambda u: ttpf_probability(np.exp(u), exponent) - p, np.full(p.shape, -40.0), np.full(p.shape, 40.0), xtol=1e-13
    )
    return np.exp(log_x)


def imaging_pd(range_m, range_50_m, exponent="johnson", cutoff_range_m=np.inf):
    """Probability of an EO or thermal task against range: the TTPF at x = R_50 / R.

    Parameters
    ----------
    range_m : array_like
        Slant range [m], >= 0.
    range_50_m : array_like
        Range of 50 % task success [m]: Eq. 17-18 with n_TTPF = 1, i.e.
        d_crit / (2 lp IFOV) (:func:`csuas.core.johnson.johnson_range_m`).
    exponent : {"johnson", "ttp"}
        TTPF exponent (:func:`ttpf_probability`).
    cutoff_range_m : array_like
        Range beyond which the target is not seen at all [m]: the EO contrast-limited range
        (Eq. 21) or the thermal range where the apparent Delta T falls below the MRTD; inf: none.

    Returns
    -------
    ndarray
        P(R), 1 at R = 0, 0 beyond the cutoff.
    """
    r = require("range_m", range_m, ge=0)
    r50 = require("range_50_m", range_50_m, ge=0, allow_inf=True)
    cutoff = require("cutoff_range_m", cutoff_range_m, ge=0, allow_inf=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(r == 0, np.inf, r50 / np.where(r == 0, 1.0, r))
    x = np.where(np.isnan(x), 0.0, x)  # R_50 = 0 and R = 0 cannot both hold a task: no cycles
    return np.where(r > cutoff, 0.0, ttpf_probability(x, exponent))


def energy_detector_threshold(pfa, time_bandwidth):
    """Threshold of an energy detector over M complex samples, in units of the noise power [-].

    Under noise alone the sum of M unit-power complex samples is Gamma(M, 1): Q(M, T) = Pfa.

    Parameters
    ----------
    pfa : array_like
        Probability of false alarm, 0 < Pfa < 1.
    time_bandwidth : array_like
        Time-bandwidth product M (integration time x bandwidth), >= 1.
    """
    p, m = require_all(("pfa", pfa, {"gt": 0, "lt": 1}), ("time_bandwidth", time_bandwidth, {"ge": 1}))
    special, _ = _special()
    return special.gammainccinv(m, p)


def _steady_energy_pd(snr, m, t):
    """Pd of the energy detector for a steady signal: noncentral chi-square, 2M dof, noncentrality 2 M snr."""
    _, stats = _special()
    return stats.ncx2.sf(2.0 * t, 2.0 * m, 2.0 * m * snr)


def energy_detector_pd(snr_db, pfa, time_bandwidth=1.0, fading="none", rician_k_db=0.0):
    """Probability of detection of an energy detector (RF emission, acoustics).

    The detector sums M = T B unit-noise complex samples of a signal of per-sample SNR snr
    (received signal power over noise power in the detector's bandwidth, the paper's SNR);
    Pfa sets the threshold (:func:`energy_detector_threshold`). A steady signal gives a
    noncentral chi-square with 2M degrees of freedom and noncentrality 2 M snr (Urkowitz 1967).
    With fading the received power is exponential (Rayleigh) or noncentral chi-square with 2
    degrees of freedom (Rician, K = specular / diffuse power) around its mean snr, constant over
    the integration (slow fading), and Pd is averaged over it (Digham et al. 2007) by
    composite Gauss-Legendre quadrature in probability (256 nodes; error below 1e-6).

    Parameters
    ----------
    snr_db : array_like
        Mean per-sample SNR [dB]; any finite value.
    pfa : array_like
        Probability of false alarm, 0 < Pfa < 1.
    time_bandwidth : array_like
        Time-bandwidth product M, >= 1.
    fading : {"none", "rayleigh", "rician"}
        Fading of the received power.
    rician_k_db : array_like
        Rician K factor [dB] (with ``fading="rician"``); -inf dB is Rayleigh, +inf dB steady.

    Returns
    -------
    ndarray
        Pd, between Pfa and 1.
    """
    if fading not in FADING:
        raise ParameterError("fading", fading, ", ".join(FADING))
    snr_db_arr, p, m, k_db = require_all(
        ("snr_db", snr_db, {}),
        ("pfa", pfa, {"gt": 0, "lt": 1}),
        ("time_bandwidth", time_bandwidth, {"ge": 1}),
        ("rician_k_db", rician_k_db, {"allow_inf": True}),
    )
    special, _ = _special()
    t = special.gammainccinv(m, p)
    snr = 10.0 ** (np.clip(snr_db_arr, -150.0, 150.0) / 10.0)
    if fading == "none":
        pd = _steady_energy_pd(snr, m, t)
    else:
        k = np.zeros_like(k_db) if fading == "rayleigh" else 10.0 ** (np.clip(k_db, -150.0, 60.0) / 10.0)
        pd = _faded_energy_pd(snr, m, t, k)
    pd = np.clip(pd, p, 1.0)
    pd = np.where(snr_db_arr <= -150.0, p, np.where(snr_db_arr >= 150.0, 1.0, pd))
    return pd[()] if np.ndim(pd) == 0 else pd


def _fading_nodes():
    """Composite Gauss-Legendre nodes and weights on (0, 1), panels refined toward both ends."""
    x, w = np.polynomial.legendre.leggauss(FADING_NODES_PER_PANEL)
    lo, hi = FADING_PANEL_EDGES[:-1, None], FADING_PANEL_EDGES[1:, None]
    return (lo + (hi - lo) * 0.5 * (x + 1.0)).ravel(), ((hi - lo) * 0.5 * w).ravel()


def _faded_energy_pd(snr, m, t, k):
    """Steady Pd averaged over a Rician power (K = 0: Rayleigh) of mean snr, by quadrature in probability.

    The power ratio g = P / mean is a noncentral chi-square with 2 dof and noncentrality 2K,
    scaled by 1 / (2 (1 + K)). With G its distribution function, E[Pd(snr g)] is the integral of
    Pd(snr G^-1(q)) over q in (0, 1): bounded for any K. The steady Pd is a steep step in g when
    M is large, anywhere in (0, 1), so the rule is composite: Gauss-Legendre panels refined
    geometrically toward q = 0 and q = 1 (nodes computed once per distinct K).
    """
    _, stats = _special()
    q, w = _fading_nodes()
    shape = np.broadcast_shapes(np.shape(snr), np.shape(m), np.shape(t), np.shape(k))
    values, index = np.unique(np.broadcast_to(k, shape), return_inverse=True)
    nodes = np.stack(
        [stats.ncx2.ppf(q, 2.0, 2.0 * kv) / (2.0 * (1.0 + kv)) if kv > 0 else -np.log1p(-q) for kv in values]
    )
    g = nodes[index.reshape(shape)]
    snr, m, t = (np.broadcast_to(x, shape)[..., None] for x in (snr, m, t))
    return np.sum(w * _steady_energy_pd(snr * g, m, t), axis=-1)


def lidar_pd_gaussian(snr_db, pfa):
    """Probability of detecting a lidar return in Gaussian noise (linear-mode receiver).

    The sampled photocurrent is the return's amplitude plus zero-mean Gaussian noise; the
    threshold is set for Pfa: Pd = Q(Q^-1(Pfa) - sqrt(SNR)), Q the standard normal survival
    function and SNR the power ratio (signal current squared over noise variance), so that
    sqrt(SNR) is the return's amplitude in noise standard deviations.

    Parameters
    ----------
    snr_db : array_like
        Power SNR of the return [dB].
    pfa : array_like
        Probability of false alarm per range cell, 0 < Pfa < 1.
    """
    snr_db_arr = require("snr_db", snr_db)
    return gaussian_pd(10.0 ** (np.clip(snr_db_arr, -300.0, 300.0) / 20.0), pfa)


def gaussian_pd(amplitude_snr, pfa):
    """Pd of a threshold on a signal amplitude in zero-mean Gaussian noise: Q(Q^-1(Pfa) - a).

    Parameters
    ----------
    amplitude_snr : array_like
        Signal amplitude in noise standard deviations, a >= 0 (the square root of the power SNR); inf
        (a target at zero range) gives Pd = 1.
    pfa : array_like
        Probability of false alarm, 0 < Pfa < 1.

    Returns
    -------
    ndarray
        Pd in [Pfa, 1] (Richards, *Fundamentals of Radar Signal Processing*, 2014, Eq. 6.23).
    """
    a, p = require_all(("amplitude_snr", amplitude_snr, {"ge": 0, "allow_inf": True}), ("pfa", pfa, {"gt": 0, "lt": 1}))
    _, stats = _special()
    return np.maximum(stats.norm.sf(stats.norm.isf(p) - a), p)


def target_pixels(projected_area_m2, ifov_rad_, range_m):
    """Pixels the target covers at a range: A / (IFOV R)^2 [px] (inf at R = 0).

    Parameters
    ----------
    projected_area_m2 : array_like
        Projected area of the target [m^2].
    ifov_rad_ : array_like
        Instantaneous field of view of one pixel [rad].
    range_m : array_like
        Slant range [m].
    """
    a = require("projected_area_m2", projected_area_m2, ge=0)
    w = require("ifov_rad", ifov_rad_, gt=0)
    r = require("range_m", range_m, ge=0)
    with np.errstate(divide="ignore"):
        return np.where(r > 0, a / np.square(w * np.where(r > 0, r, 1.0)), np.inf)


def blob_snr(signal, noise_sd, pixels):
    """SNR of a uniform blob summed over its pixels in white noise: |s| sqrt(n) / sigma, |s| n / sigma below a pixel.

    A matched sum of n pixels each carrying the excess ``signal`` over noise of standard deviation
    ``noise_sd`` (Holst 2008, ch. 21); a target smaller than a pixel puts the fraction n of its excess
    into one pixel. Continuous at n = 1; infinite pixels (zero range) give an infinite SNR for any
    signal.

    Parameters
    ----------
    signal : array_like
        Excess of the target over the background per fully covered pixel (any unit).
    noise_sd : array_like
        Temporal noise of one pixel, same unit, > 0.
    pixels : array_like
        Pixels covered, n >= 0 (may be inf).
    """
    s = np.abs(require("signal", signal))
    sigma = require("noise_sd", noise_sd, gt=0)
    n = require("pixels", pixels, ge=0, allow_inf=True)
    gain = np.where(n >= 1.0, np.sqrt(n), n)
    with np.errstate(invalid="ignore"):
        return np.where(np.isinf(n), np.where(s > 0, np.inf, 0.0), s * gain / sigma)


def gaussian_required_snr(pd, pfa):
    """Amplitude SNR a Gaussian threshold detector needs for ``pd`` at ``pfa``: Q^-1(Pfa) - Q^-1(Pd).

    The inverse of :func:`gaussian_pd`: 0 where Pd <= Pfa needs no signal, +inf for Pd = 1 (never
    certain in Gaussian noise).
    """
    d, p = require_all(("pd", pd, {"ge": 0, "le": 1}), ("pfa", pfa, {"gt": 0, "lt": 1}))
    _, stats = _special()
    return np.maximum(stats.norm.isf(p) - stats.norm.isf(d), 0.0)


def photon_counting_threshold(noise_photons, pfa):
    """Smallest count k with P(Poisson(noise) >= k) <= Pfa: the photon-counting threshold [-].

    Parameters
    ----------
    noise_photons : array_like
        Mean background and dark counts in the range gate, >= 0.
    pfa : array_like
        Probability of false alarm per gate, 0 < Pfa < 1.
    """
    noise, p = require_all(("noise_photons", noise_photons, {"ge": 0}), ("pfa", pfa, {"gt": 0, "lt": 1}))
    _, stats = _special()
    # P(X >= k) = sf(k - 1): the first k whose tail is within Pfa
    return stats.poisson.isf(p, noise) + 1.0


def lidar_pd_poisson(signal_photons, noise_photons, pfa):
    """Probability of detecting a lidar return by photon counting (Poisson statistics).

    Pd = P(Poisson(signal + noise) >= k), k from :func:`photon_counting_threshold`. Counts are
    whole, so the false-alarm probability actually met is at most Pfa.

    Parameters
    ----------
    signal_photons : array_like
        Mean signal photoelectrons per pulse in the gate, >= 0.
    noise_photons : array_like
        Mean noise counts in the gate, >= 0.
    pfa : array_like
        Probability of false alarm per gate, 0 < Pfa < 1.
    """
    (signal,) = require_all(("signal_photons", signal_photons, {"ge": 0}))
    k = photon_counting_threshold(noise_photons, pfa)
    _, stats = _special()
    return stats.poisson.sf(k - 1.0, signal + np.asarray(noise_photons, dtype=float))
