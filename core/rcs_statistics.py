"""Statistics of a target's radar cross-section over aspects, and the Pd they imply.

A drone seen from random aspects has a distribution of RCS, not one value (the paper's Eq. 6
averages it away). This module summarises samples of that distribution and fits the two
classic models: log-normal (3GPP TR 38.901 gives the UAV RCS as a log-normal in dBsm) and
chi-square with 2k degrees of freedom (Swerling 1/2: k = 1, Swerling 3/4: k = 2), fitted by
maximum likelihood as a gamma distribution of shape k. :func:`pd_over_rcs_samples` gives the
exact Pd of a scan-to-scan target whose RCS is drawn from the samples themselves (each scan one
aspect): the average of the steady-target Pd over the samples.

References
----------
- P. Swerling, "Probability of detection for fluctuating targets", IRE Trans. IT-6, 1960.
- 3GPP TR 38.901 v17, Table 7.9.2.1-1 (UAV RCS: log-normal, mean -12.81 dBsm, sd 3.74 dB).
- M. A. Richards, Fundamentals of Radar Signal Processing, 2nd ed., 2014, ch. 7 (chi-square models).
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require
from csuas.core.radar_detection import pd_exact
from csuas.defaults import load_drone_rcs_statistics

#: Step of the dB grid of :func:`pd_chi_square_target` [dB] (Pd within 1e-6 of Swerling 1 and 3).
_DB_STEP = 0.1


def _samples(rcs_m2):
    s = require("rcs_m2", rcs_m2, gt=0)
    if s.ndim != 1 or s.size < 8:
        raise ParameterError("rcs_m2", f"{s.size} sample(s)", "a 1-D array of at least 8 RCS samples > 0 [m^2]")
    return s


def rcs_summary(rcs_m2) -> dict:
    """Mean, median, 10th and 90th percentiles of RCS samples [m^2 and dBsm], with the mean's standard error.

    Parameters
    ----------
    rcs_m2 : array_like
        RCS samples over aspects [m^2], > 0, at least 8.
    """
    s = _samples(rcs_m2)
    mean, stderr = float(np.mean(s)), float(np.std(s, ddof=1) / np.sqrt(s.size))
    p10, median, p90 = np.percentile(s, [10, 50, 90])
    return {
        "n": int(s.size),
        "mean_m2": mean,
        "mean_stderr_m2": stderr,
        "mean_dbsm": float(10 * np.log10(mean)),
        "median_dbsm": float(10 * np.log10(median)),
        "p10_dbsm": float(10 * np.log10(p10)),
        "p90_dbsm": float(10 * np.log10(p90)),
    }


def fit_lognormal(rcs_m2) -> dict:
    """Log-normal fit: mean and standard deviation of the RCS in dBsm (maximum likelihood)."""
    db = 10 * np.log10(_samples(rcs_m2))
    return {"mean_dbsm": float(np.mean(db)), "std_db": float(np.std(db))}


def fit_chi_square(rcs_m2) -> dict:
    """Chi-square fit of the normalised RCS: degrees of freedom 2k (maximum likelihood gamma shape k).

    The shape solves ln k - psi(k) = ln(mean) - mean(ln s) (the gamma likelihood equation), by
    Newton's method from Minka's starting value. The nearest Swerling family is 1/2 (k = 1) or
    3/4 (k = 2); k well below 1 means a heavier tail than any Swerling case (returned as is).

    Returns
    -------
    dict
        ``k``, ``dof`` (2k), ``nearest_swerling_scan`` (1 or 3) and ``log_likelihood_ratio``, the
        log-likelihood per sample of the fitted shape over the nearer of k = 1 and 2 (>= 0).
    """
    from scipy import special

    s = _samples(rcs_m2)
    x = s / np.mean(s)
    gap = -np.mean(np.log(x))  # ln(mean) - mean(ln s), >= 0, with mean 1
    if gap <= 1e-12:
        return {"k": np.inf, "dof": np.inf, "nearest_swerling_scan": 0, "log_likelihood_ratio": 0.0}
    k = (3 - gap + np.sqrt((gap - 3) ** 2 + 24 * gap)) / (12 * gap)
    for _ in range(50):
        step = (np.log(k) - special.digamma(k) - gap) / (1 / k - special.polygamma(1, k))
        k = max(k - step, k / 10)
        if abs(step) < 1e-12 * k:
            break

    def loglik(shape):
        return float(shape * np.log(shape) - special.gammaln(shape) + (shape - 1) * np.mean(np.log(x)) - shape)

    nearest = 1 if abs(np.log(k)) <= abs(np.log(k / 2)) else 2
    return {
        "k": float(k),
        "dof": float(2 * k),
        "nearest_swerling_scan": 1 if nearest == 1 else 3,
        "log_likelihood_ratio": loglik(k) - loglik(float(nearest)),
    }


def aspect_chi_square_dof(preset: str, frequency_ghz: float, polarisation: str = "VV") -> tuple[float, float]:
    """Chi-square degrees of freedom 2k of a drone preset's RCS over aspects, from the shipped table.

    The band of ``defaults/drone_rcs_statistics.csv`` nearest in log-frequency is used.

    Returns
    -------
    tuple of float
        ``(dof, band_ghz)``.

    Raises
    ------
    ParameterError
        A preset or polarisation the table does not hold.
    """
    rows = [r for r in load_drone_rcs_statistics() if r["preset"] == preset and r["polarisation"] == polarisation]
    if not rows:
        presets = sorted({r["preset"] for r in load_drone_rcs_statistics()})
        raise ParameterError(
            "target preset / polarisation", f"{preset} / {polarisation}", f"one of {', '.join(presets)} / VV, HH"
        )
    f = float(require("frequency_ghz", frequency_ghz, gt=0))
    nearest = min(rows, key=lambda r: abs(np.log(r["frequency_ghz"] / f)))
    return float(nearest["chi2_dof"]), float(nearest["frequency_ghz"])


def pd_chi_square_target(snr_db_at_mean, pfa, n_pulses, dof, integration="noncoherent"):
    """Pd of a scan-to-scan target whose RCS is chi-square with ``dof`` degrees of freedom (mean 1).

    Within a scan the target is steady (:func:`pd_exact` with Swerling 0); from scan to scan its RCS
    x is gamma-distributed with shape k = dof/2 and mean 1, so

        Pd(S) = integral Pd_steady(S + y) g(y) dy,    y = 10 log10 x,

    evaluated by the trapezoidal rule in y (step :data:`_DB_STEP`) between the 1e-10 and 1 - 1e-12
    quantiles of y; below them Pd = Pfa. dof = 2 is Swerling 1 and dof = 4 Swerling 3.

    Parameters
    ----------
    snr_db_at_mean : array_like
        Single-pulse SNR [dB] at the mean RCS.
    pfa, n_pulses, integration
        As in :func:`csuas.core.radar_detection.pd_exact`.
    dof : float
        Degrees of freedom 2k, 0.2 <= dof <= 200.

    Returns
    -------
    ndarray
        Pd, shaped like ``snr_db_at_mean``.
    """
    from scipy import stats

    k = float(require("dof", dof, ge=0.2, le=200.0)) / 2.0
    snr = require("snr_db_at_mean", snr_db_at_mean)
    shape = stats.gamma(k, scale=1.0 / k)
    lo, hi = (10.0 * np.log10(shape.ppf(q)) for q in (1e-10, 1.0 - 1e-12))
    y = np.linspace(lo, hi, int(np.ceil((hi - lo) / _DB_STEP)) + 1)
    x = 10.0 ** (y / 10.0)
    weight = shape.pdf(x) * x * (np.log(10.0) / 10.0) * (y[1] - y[0])  # g(y) dy
    weight[[0, -1]] *= 0.5
    pd = pd_exact(snr[..., None] + y, pfa, n_pulses, 0, integration) @ weight
    below = shape.cdf(x[0])
    return np.clip(pd + below * np.asarray(pfa, float), 0.0, 1.0)


def pd_over_rcs_samples(snr_db_at_mean, rcs_m2, pfa, n_pulses=1, integration="noncoherent"):
    """Exact Pd of a scan-to-scan target whose RCS per scan is one of the samples, equally likely.

    Parameters
    ----------
    snr_db_at_mean : array_like
        Single-pulse SNR [dB] for the samples' mean RCS.
    rcs_m2 : array_like
        RCS samples over aspects [m^2].
    pfa, n_pulses, integration
        As in :func:`csuas.core.radar_detection.pd_exact` (steady target within a scan).

    Returns
    -------
    ndarray
        Pd, shaped like ``snr_db_at_mean``.
    """
    s = _samples(rcs_m2)
    snr = require("snr_db_at_mean", snr_db_at_mean)
    offsets = 10 * np.log10(s / np.mean(s))
    pd = pd_exact(snr[..., None] + offsets, pfa, n_pulses, 0, integration)
    return np.mean(pd, axis=-1)
