"""Exact radar probability of detection of a square-law detector, Swerling 0-4, and its inverse.

The detector sums N pulses' square-law outputs |s_k + n_k|^2 (complex Gaussian noise of power 1 per
pulse) and compares the sum with a threshold T (noncoherent integration), or adds the N complex
samples first and compares |sum|^2 / N with T (coherent integration; see :func:`pd_exact` for
what that means for each target model). ``snr_db`` is always the single-pulse SNR: the target's
mean echo power over the noise power of one pulse.

Target models (Swerling 1960): 0 steady; 1 and 3 scan-to-scan fluctuation (one radar cross-section
draw for all N pulses), 2 and 4 pulse-to-pulse fluctuation (an independent draw per pulse); 1 and 2
exponential power (chi-square, 2 degrees of freedom), 3 and 4 chi-square with 4 degrees of freedom.

Every case is evaluated in closed form or as a finite sum of incomplete gamma functions over whole
arrays, no quadrature:

* Swerling 0: Marcum's generalised Q function, P[chi'^2(2N, 2N snr) > 2T] (Marcum 1960).
* Swerling 1: Z = beta E + G_(N-1) with E exponential, G gamma and beta = 1 + N snr (rotate the N
  pulses so that one axis carries the common echo), which gives DiFranco and Rubin's closed form
  Q(N-1, T) + e^(-T/beta) (1 - 1/beta)^(-(N-1)) P(N-1, T (1 - 1/beta)).
* Swerling 2: Z is gamma(N, 1 + snr): Q(N, T/(1 + snr)).
* Swerling 3: the moment generating function (1 + s)^-(N-2) (1 + beta s)^-2, beta = 1 + N snr/2,
  makes Z = gamma(2, beta) + G_(N-2); N = 1 is the two-term mixture of its partial fractions.
  Its tail is a sum of positive Kummer series (no cancellation at low SNR).
* Swerling 4: each pulse is gamma(1, beta) or gamma(2, beta) with probabilities 1/beta and
  1 - 1/beta (beta = 1 + snr/2), so Z is gamma(N + J, beta) with J binomial(N, 1 - 1/beta): a sum
  of N + 1 positive terms.

P and Q are the regularised lower and upper incomplete gamma functions. Products such as
(1 + 1/(N snr))^(N-1) P(N-1, x) that overflow and underflow at low SNR are evaluated as
T^m e^-T / m! M(1, m+1, x) (Kummer's function M), exactly and without cancellation.

References
----------
Marcum, J. I. (1960). A statistical theory of target detection by pulsed radar. IRE Trans.
    Information Theory 6(2), 59-267.
Swerling, P. (1960). Probability of detection for fluctuating targets. IRE Trans. Information
    Theory 6(2), 269-308.
DiFranco, J. V. and Rubin, W. L. (1968). Radar Detection. Prentice-Hall.
Meyer, D. P. and Mayer, H. A. (1973). Radar Target Detection. Academic Press.
Albersheim, W. J. (1981). A closed-form approximation to Robertson's detection characteristics.
    Proc. IEEE 69(7), 839.
Shnidman, D. A. (2002). Determination of required SNR values. IEEE Trans. Aerospace and
    Electronic Systems 38(3), 1059-1064.
Richards, M. A. (2014). Fundamentals of Radar Signal Processing, 2nd ed. McGraw-Hill, ch. 6.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError, raise_all
from csuas.core.checks import require
from csuas.core.solve import bracketed_root

SWERLING_CASES = (0, 1, 2, 3, 4)
INTEGRATIONS = ("coherent", "noncoherent")
METHODS = ("exact", "albersheim", "shnidman")
#: Largest pulse count: Swerling 4's exact sum costs O(N); it covers Albersheim's 8096.
N_PULSES_MAX = 10_000
#: Smallest Pfa: below it Poisson weights of the exact sums leave the normal double range.
PFA_MIN = 1e-300
PFA_WHY = "Pfa < 1e-300 leaves double precision's normal range"
#: SNRs beyond this [dB] give Pd = Pfa or 1 to double precision and are evaluated there.
SNR_DB_CLIP = 1000.0
#: The inverse's search limits [dB]: Pd(-400 dB) = Pfa and Pd(+400 dB) = 1 in double precision.
SNR_DB_SEARCH = 400.0
#: Non-centrality beyond which Marcum's Q is 1 in double precision for any threshold of N <= 1e4
#: pulses (the threshold stays below 3e4 for Pfa >= 1e-300, five hundred standard deviations away).
_NC_MAX = 1e12
#: Below this the incomplete gamma P(m, x) is replaced by its Kummer series (no underflow).
_P_TINY = 1e-250


def _check(errors, name, value, **bounds):
    """``require`` that records its ParameterError in ``errors`` instead of raising; NaN-free float array."""
    try:
        return require(name, value, **bounds)
    except ParameterError as exc:
        errors.append(exc)
        return None


def _check_pulses(errors, n_pulses):
    n = _check(errors, "n_pulses", n_pulses, ge=1, le=N_PULSES_MAX)
    if n is not None and np.any(n != np.floor(n)):
        errors.append(ParameterError("n_pulses", float(n[n != np.floor(n)].flat[0]), f"an integer 1..{N_PULSES_MAX}"))
        return None
    return n


def _check_swerling(errors, swerling):
    arr = np.asarray(swerling)
    allowed = "0, 1, 2, 3 or 4 (Swerling cases)"
    if arr.dtype.kind not in "iuf":
        errors.append(ParameterError("swerling", swerling, allowed))
        return None
    bad = ~np.isin(arr, SWERLING_CASES)
    if np.any(bad):
        errors.append(ParameterError("swerling", arr[bad].flat[0] if arr.ndim else arr, allowed))
        return None
    return arr.astype(int)


def _check_integration(errors, integration):
    arr = np.asarray(integration)
    if arr.dtype.kind not in "US" or np.any(~np.isin(arr, INTEGRATIONS)):
        bad = arr[~np.isin(arr, INTEGRATIONS)].flat[0] if arr.ndim and arr.size else integration
        errors.append(ParameterError("integration", bad, " or ".join(INTEGRATIONS)))
        return None
    return arr == "coherent"


def _check_pd(errors, pd, pfa):
    p = _check(errors, "pd", pd, gt=0, lt=1, why="Pd = 0 asks for no detection and Pd = 1 for an infinite SNR")
    if p is None or pfa is None:
        return p
    low = p <= pfa
    if np.any(low):
        first = np.broadcast_to(p, np.broadcast(p, pfa).shape)[np.broadcast_to(low, np.broadcast(p, pfa).shape)]
        errors.append(
            ParameterError(
                "pd",
                float(first.flat[0]),
                "> pfa: a Pd at or below Pfa needs no signal (noise alone crosses the threshold with probability Pfa)",
            )
        )
        return None
    return p


def _coherent_swerling4(errors, coherent, swerling, n):
    """Coherent integration of several pulses of a Swerling 4 target has no closed form: an error."""
    if coherent is None or swerling is None or n is None:
        return
    bad = np.broadcast_to(coherent & (swerling == 4) & (n > 1), np.broadcast(coherent, swerling, n).shape)
    if np.any(bad):
        errors.append(
            ParameterError(
                "swerling",
                4,
                "0-3 with coherent integration of more than one pulse: the coherent sum of independent "
                "chi-square-4 echoes has no closed form (use swerling = 2 for Gaussian echoes, or noncoherent)",
            )
        )


def threshold(pfa, n_pulses=1):
    """Normalised threshold T of a square-law detector summing N pulses (noise power 1 per pulse).

    Pfa = Q(N, T), the regularised upper incomplete gamma function (the sum of N unit exponentials
    is gamma(N, 1)); T = Q^-1(N, Pfa).

    Parameters
    ----------
    pfa : array_like
        Probability of false alarm, 1e-300 <= Pfa < 1.
    n_pulses : array_like
        Pulses integrated noncoherently, an integer 1..10000.

    Returns
    -------
    ndarray
        T [noise powers of one pulse] (T = -ln Pfa for N = 1).

    Raises
    ------
    ParameterError
        Pfa outside [1e-300, 1), a non-integer or out-of-range N (all mistakes together).
    """
    errors = []
    p = _check(errors, "pfa", pfa, ge=PFA_MIN, lt=1, why=PFA_WHY)
    n = _check_pulses(errors, n_pulses)
    raise_all(errors)
    return _threshold(p, n)[()]


def _threshold(pfa, n):
    from scipy.special import gammainccinv

    return np.where(n == 1, -np.log(pfa), gammainccinv(n, pfa))


def _log_kernel(m, t, c, log_c, inv_beta):
    """log K, K = e^(-T/beta) c^-m P(m, T c) with c = 1 - 1/beta: one term of Swerling 1 and 3 (flat arrays).

    Where P underflows K = T^m e^-T / m! M(1, m+1, T c) (Kummer series of P, exact for every c).
    """
    from scipy.special import gammainc, gammaln, hyp1f1

    out = -t * inv_beta  # m = 0: P(0, x) = 1
    pos = m > 0
    if np.any(pos):
        mm, tt, cc, lc, ib = m[pos], t[pos], c[pos], log_c[pos], inv_beta[pos]
        x = tt * cc
        p = gammainc(mm, x)
        big = p > _P_TINY
        val = np.empty_like(x)
        val[big] = -tt[big] * ib[big] - mm[big] * lc[big] + np.log(p[big])
        small = ~big
        if np.any(small):
            ms, ts = mm[small], tt[small]
            val[small] = ms * np.log(ts) - ts - gammaln(ms + 1) + np.log(hyp1f1(1.0, ms + 1, x[small]))
        out[pos] = val
    return out


def _q_upper(m, t):
    """Q(m, T), with Q(0, T) = 0 (flat arrays)."""
    from scipy.special import gammaincc

    return np.where(m > 0, gammaincc(np.maximum(m, 1), t), 0.0)


def _pd_swerling0(snr, t, n):
    from scipy.stats import ncx2

    return ncx2.sf(2 * t, 2 * n, np.minimum(2 * n * snr, _NC_MAX))


def _pd_swerling1(snr, t, n):
    x = n * snr
    inv_beta, c, log_c = 1.0 / (1.0 + x), x / (1.0 + x), -np.log1p(1.0 / x)
    m = n - 1
    return _q_upper(m, t) + np.exp(_log_kernel(m, t, c, log_c, inv_beta))


def _pd_swerling2(snr, t, n):
    from scipy.special import gammaincc

    return gammaincc(n, t / (1.0 + snr))


def _pd_swerling3(snr, t, n):
    """Q(m, T) + K_m + (T/(beta (m+1))) A M(2, m+2, x), m = N - 2, A = T^m e^-T / m!, x = T (1 - 1/beta).

    The gamma(2, beta) tail e^(-u/beta)(1 + u/beta) integrated against the gamma(m) density gives two
    positive series, A M(1, m+1, x) = K_m and the M(2, m+2, x) term; the textbook form
    (1 + T/beta) K_m - (m/beta) K_(m+1) cancels up to a factor T at low SNR. For x > m the contiguous
    relation M(2, m+2, x) = m+1 + (x-m) M(1, m+2, x) (both terms positive) keeps e^x out of range.
    """
    from scipy.special import gammaln, hyp1f1

    x = n * snr / 2
    inv_beta, c, log_c = 1.0 / (1.0 + x), x / (1.0 + x), -np.log1p(1.0 / x)
    out = np.exp(-t * inv_beta) * (1.0 + c * t * inv_beta)  # N = 1: the two-term mixture
    many = n > 1
    if np.any(many):
        m, tt, cc, lc, ib = n[many] - 2, t[many], c[many], log_c[many], inv_beta[many]
        xx = tt * cc
        log_a = m * np.log(tt) - tt - gammaln(m + 1)
        third = np.empty_like(xx)
        up = xx > m
        if np.any(up):
            k1 = np.exp(_log_kernel(m[up] + 1, tt[up], cc[up], lc[up], ib[up]))
            third[up] = ib[up] * (tt[up] * np.exp(log_a[up]) + (xx[up] - m[up]) * k1)
        low = ~up
        if np.any(low):
            scale = tt[low] * ib[low] / (m[low] + 1)
            third[low] = scale * np.exp(log_a[low] + np.log(hyp1f1(2.0, m[low] + 2, xx[low])))
        out[many] = _q_upper(m, tt) + np.exp(_log_kernel(m, tt, cc, lc, ib)) + third
    return out


def _pd_swerling4(snr, t, n):
    """Sum over j of binomial(j; N, p) Q(N + j, T/beta), upward in j with all terms positive.

    Points are sorted by N (largest first) so that those still summing at step j are a prefix. Each
    binomial weight is formed afresh, ln C(N, j) + j ln p + (N - j) ln(1 - p), whose terms stay small
    where the weight matters (a running product would accumulate N roundings of ln values of order
    N ln beta), and the sum is divided by the weights' own sum.
    """
    from scipy.special import gammaincc, gammaln

    order = np.argsort(-n, kind="stable")
    ns, ss, ts = n[order], snr[order], t[order]
    ni = ns.astype(np.int64)
    n_max = int(ni[0])
    active = np.searchsorted(-ni, -np.arange(n_max + 2), side="right")  # points with N >= j
    log_fact = gammaln(np.arange(n_max + 1) + 1.0)  # ln k!
    half = ss / 2
    y = ts / (1.0 + half)  # T / beta
    log_y = np.log(y)
    log_p, log_q = -np.log1p(1.0 / half), -np.log1p(half)  # ln p, ln(1 - p); p = 1 - 1/beta
    log_fact_n = log_fact[ni]
    # the Poisson(y) weight at N: >= Pfa/N where it grows with j (y > N), so no underflow for Pfa >= 1e-300
    pois = np.exp(ns * log_y - y - log_fact_n)
    q = gammaincc(ns, y)  # Q(N + j, y), raised by one Poisson weight per step
    acc, weights = np.zeros_like(y), np.zeros_like(y)
    for j in range(n_max + 1):
        k = active[j]
        b = np.exp(log_fact_n[:k] - log_fact[j] - log_fact[ni[:k] - j] + j * log_p[:k] + (ns[:k] - j) * log_q[:k])
        acc[:k] += b * q[:k]
        weights[:k] += b
        k = active[j + 1]  # points with N > j go on to j + 1
        if k:
            q[:k] += pois[:k]
            pois[:k] *= y[:k] / (ns[:k] + (j + 1))
    out = np.empty_like(acc)
    out[order] = acc / weights
    return out


_PD_CASES = (_pd_swerling0, _pd_swerling1, _pd_swerling2, _pd_swerling3, _pd_swerling4)
#: Coherent integration of N pulses is one sample of this single-pulse case (SNR N snr; snr for Swerling 2).
_COHERENT_CASE = np.array([0, 1, 1, 3, 3])


def _pd_flat(snr, t, n, case):
    """Pd on flat arrays: linear single-sample SNR, threshold, pulse count (float), Swerling case."""
    out = np.empty(snr.shape)
    for sw in SWERLING_CASES:
        idx = np.flatnonzero(case == sw)
        if idx.size:
            out[idx] = _PD_CASES[sw](snr[idx], t[idx], n[idx])
    return np.clip(out, 0.0, 1.0)


def _prepare(pfa, n, swerling, coherent, *others):
    """Broadcast and flatten; fold coherent integration into one sample of N-fold SNR.

    Returns the shape, the flat threshold, effective pulse count, case, SNR factor and ``others``.
    """
    shape = np.broadcast(pfa, n, swerling, coherent, *others).shape
    flat = [np.broadcast_to(v, shape).ravel() for v in (pfa, n, swerling, coherent, *others)]
    pfa_f, n_f, sw_f, coh_f = flat[:4]
    n_eff = np.where(coh_f, 1.0, n_f)
    case = np.where(coh_f, _COHERENT_CASE[sw_f], sw_f)
    # coherent: an echo that keeps its phase adds in amplitude, N snr; Swerling 2's independent echoes
    # add in power like the noise, so the single-sample SNR stays snr
    gain = np.where(coh_f & (sw_f != 2), n_f, 1.0)
    # the threshold depends on (pfa, N, integration) only: computed on their own broadcast
    small = np.broadcast(pfa, n, coherent).shape
    n_small = np.where(np.broadcast_to(coherent, small), 1.0, np.broadcast_to(n, small))
    n_max = int(np.max(n_small))
    if np.size(pfa) == 1 and n_small.size > n_max:  # one Pfa: a table over N = 1..max
        t_small = _threshold(np.ravel(pfa)[0], np.arange(1.0, n_max + 1))[n_small.astype(np.int64) - 1]
    else:
        t_small = _threshold(np.broadcast_to(pfa, small), n_small)
    t = np.broadcast_to(t_small, shape).ravel()
    return shape, t, n_eff, case, gain, flat[4:]


def _validate_common(errors, pfa, n_pulses, swerling, integration):
    p = _check(errors, "pfa", pfa, ge=PFA_MIN, lt=1, why=PFA_WHY)
    n = _check_pulses(errors, n_pulses)
    sw = _check_swerling(errors, swerling)
    coh = _check_integration(errors, integration)
    _coherent_swerling4(errors, coh, sw, n)
    return p, n, sw, coh


def pd_exact(snr_db, pfa, n_pulses=1, swerling=0, integration="noncoherent"):
    """Exact probability of detection of a square-law detector (Marcum 1960; Swerling 1960).

    Parameters
    ----------
    snr_db : array_like
        Single-pulse SNR [dB]: mean echo power over the noise power of one pulse; any finite value
        (beyond +-1000 dB Pd equals Pfa or 1 to double precision and is evaluated there).
    pfa : array_like
        Probability of false alarm, 1e-300 <= Pfa < 1.
    n_pulses : array_like
        Pulses integrated, an integer 1..10000.
    swerling : array_like of int
        Target model 0-4 (module docstring).
    integration : {"noncoherent", "coherent"} or array_like of str
        Noncoherent: the detector sums N square-law outputs against T = Q^-1(N, Pfa). Coherent: the
        N complex samples are added before detection and |sum|^2 / N is compared with T = -ln Pfa.
        For steady and scan-to-scan targets (0, 1, 3) the echo adds in phase: the single-pulse case
        at N snr. Swerling 2's pulse-to-pulse echoes are independent complex Gaussians whose sum is
        complex Gaussian of power N snr against noise of power N: exactly Swerling 1 at the
        single-pulse snr, with no integration gain (decorrelated echoes add in power, like noise).
        Swerling 4's independent chi-square-4 echoes add as random phasors whose sum has no closed
        form: coherent integration of several Swerling 4 pulses raises ParameterError (N = 1 is the
        single-pulse case).

    Returns
    -------
    ndarray
        Pd in [Pfa, 1], the arguments' broadcast shape (a scalar for scalar arguments). Pd -> Pfa
        as the SNR -> 0 and -> 1 as it grows.

    Raises
    ------
    ParameterError
        A NaN or infinite SNR, Pfa outside [1e-300, 1), N not an integer 1..10000, a Swerling case
        outside 0-4, an unknown integration, coherent Swerling 4 with N > 1; several at once raise
        :class:`csuas.base.errors.InputErrors`.

    Notes
    -----
    Equations (T threshold, snr linear, P and Q regularised incomplete gamma functions):
    Swerling 0, P[chi'^2(2N, 2N snr) > 2T]; Swerling 1, Q(N-1, T) + K_(N-1) with beta = 1 + N snr;
    Swerling 2, Q(N, T/(1 + snr)); Swerling 3, Q(N-2, T) + (1 + T/beta) K_(N-2) - ((N-2)/beta)
    K_(N-1) with beta = 1 + N snr/2, evaluated as positive series (:func:`_pd_swerling3`) (N = 1:
    e^(-T/beta) (1 + (1 - 1/beta) T/beta)); Swerling 4,
    sum_j C(N, j) p^j (1-p)^(N-j) Q(N + j, T/beta) with beta = 1 + snr/2, p = 1 - 1/beta; where
    K_m = e^(-T/beta) (1 - 1/beta)^-m P(m, T (1 - 1/beta)).
    """
    errors = []
    s = _check(errors, "snr_db", snr_db)
    p, n, sw, coh = _validate_common(errors, pfa, n_pulses, swerling, integration)
    raise_all(errors)
    shape, t, n_eff, case, gain, (s_flat,) = _prepare(p, n, sw, coh, s)
    snr = gain * np.power(10.0, np.clip(s_flat, -SNR_DB_CLIP, SNR_DB_CLIP) / 10.0)
    return _pd_flat(snr, t, n_eff, case).reshape(shape)[()]


def _shnidman_db(pd, pfa, n, swerling):
    """Shnidman's equation (2002) [dB], no domain checks (flat or broadcastable arrays)."""
    k = np.choose(np.asarray(swerling), [np.inf, 1.0, n, 2.0, 2.0 * n])
    alpha = np.where(n < 40, 0.0, 0.25)
    with np.errstate(invalid="ignore", divide="ignore"):
        eta = np.sqrt(-0.8 * np.log(4 * pfa * (1 - pfa))) + np.sign(pd - 0.5) * np.sqrt(
            -0.8 * np.log(4 * pd * (1 - pd))
        )
        x_inf = eta * (eta + 2 * np.sqrt(n / 2 + (alpha - 0.25)))
        c1 = (((17.7006 * pd - 18.4496) * pd + 14.5339) * pd - 3.525) / k
        c2 = (np.exp(27.31 * pd - 25.14) + (pd - 0.8) * (0.7 * np.log(1e-5 / pfa) + (2 * n - 20) / 80)) / k
        c_db = np.where(pd <= 0.872, c1, c1 + c2)
        return c_db + 10 * np.log10(x_inf / n)


def _albersheim_db(pd, pfa, n):
    a = np.log(0.62 / pfa)
    b = np.log(pd / (1 - pd))
    return -5 * np.log10(n) + (6.2 + 4.54 / np.sqrt(n + 0.44)) * np.log10(a + 0.12 * a * b + 1.7 * b)


def _check_fitted_domain(errors, name, pd, pd_range, pfa, pfa_range, n_pulses, n_max):
    """Pd, Pfa and N checked against an approximation's fitted domain (errors collected)."""
    why = (
        f"{name} equation is fitted for {pd_range[0]:g} <= Pd <= {pd_range[1]:g}, "
        f"{pfa_range[0]:g} <= Pfa <= {pfa_range[1]:g}, 1 <= N <= {n_max}"
    )
    p = _check(errors, "pd", pd, ge=pd_range[0], le=pd_range[1], why=why)
    f = _check(errors, "pfa", pfa, ge=pfa_range[0], le=pfa_range[1], why=why)
    n = _check(errors, "n_pulses", n_pulses, ge=1, le=n_max, why=why)
    if n is not None and np.any(n != np.floor(n)):
        errors.append(ParameterError("n_pulses", float(n[n != np.floor(n)].flat[0]), f"an integer 1..{n_max}"))
    return p, f, n


def albersheim_snr_db(pd, pfa, n_pulses=1):
    """Albersheim's approximation (1981) of the single-pulse SNR [dB] a steady target needs.

    SNR = -5 log10 N + (6.2 + 4.54/sqrt(N + 0.44)) log10(A + 0.12 A B + 1.7 B), A = ln(0.62/Pfa),
    B = ln(Pd/(1 - Pd)), for N pulses integrated noncoherently by a linear (envelope) detector.

    Parameters
    ----------
    pd : array_like
        Probability of detection, 0.1 <= Pd <= 0.9.
    pfa : array_like
        Probability of false alarm, 1e-7 <= Pfa <= 1e-3.
    n_pulses : array_like
        Pulses integrated, an integer 1..8096.

    Returns
    -------
    ndarray
        Single-pulse SNR [dB]. Albersheim (1981) states an error within 0.2 dB of the exact linear
        detector over the validity range above; the square-law detector of :func:`pd_exact`
        differs from the linear one by up to about 0.2 dB more at large N. Measured against
        :func:`pd_exact` (tests/test_radar_detection.py): within 0.33 dB for Pd >= 0.3, but the
        claim fails at low Pd: -4.08 dB at Pd 0.1, Pfa 1e-3, N 1 and -0.75 dB at Pfa 1e-7, where
        linear and square law coincide (N = 1); the argument of its logarithm nears zero there.

    Raises
    ------
    ParameterError
        Arguments outside the validity range (use ``required_snr_db(..., method="exact")`` there).
    """
    errors = []
    p, f, n = _check_fitted_domain(errors, "Albersheim's", pd, (0.1, 0.9), pfa, (1e-7, 1e-3), n_pulses, 8096)
    raise_all(errors)
    return _albersheim_db(p, f, n)[()]


def shnidman_snr_db(pd, pfa, n_pulses=1, swerling=0):
    """Shnidman's approximation (2002) of the single-pulse SNR [dB] for Swerling 0-4, noncoherent.

    X_inf = eta (eta + 2 sqrt(N/2 + alpha - 1/4)) with eta = sqrt(-0.8 ln(4 Pfa (1-Pfa))) +
    sign(Pd - 0.5) sqrt(-0.8 ln(4 Pd (1-Pd))), alpha = 0 for N < 40 and 1/4 otherwise; the
    fluctuation correction C [dB] = C1 (Pd <= 0.872) or C1 + C2 with
    C1 = (((17.7006 Pd - 18.4496) Pd + 14.5339) Pd - 3.525)/K,
    C2 = (exp(27.31 Pd - 25.14) + (Pd - 0.8)(0.7 ln(1e-5/Pfa) + (2N - 20)/80))/K,
    K = inf, 1, N, 2, 2N for Swerling 0-4; SNR = C + 10 log10(X_inf / N).

    Parameters
    ----------
    pd : array_like
        Probability of detection, 0.1 <= Pd <= 0.99.
    pfa : array_like
        Probability of false alarm, 1e-9 <= Pfa <= 1e-3.
    n_pulses : array_like
        Pulses integrated noncoherently (square-law detector), an integer 1..100.
    swerling : array_like of int
        Target model 0-4.

    Returns
    -------
    ndarray
        Single-pulse SNR [dB], within about 1 dB of the exact square-law value over the validity
        range above (Shnidman 2002); measured against :func:`pd_exact`: at most 1.045 dB (Pd 0.1,
        Pfa 1e-3, N 1, Swerling 1 and 2), within 1 dB for Pd >= 0.2.

    Raises
    ------
    ParameterError
        Arguments outside the validity range (use ``required_snr_db(..., method="exact")`` there).
    """
    errors = []
    p, f, n = _check_fitted_domain(errors, "Shnidman's", pd, (0.1, 0.99), pfa, (1e-9, 1e-3), n_pulses, 100)
    sw = _check_swerling(errors, swerling)
    raise_all(errors)
    p, f, n, sw = np.broadcast_arrays(p, f, n, sw)
    return _shnidman_db(p, f, n, sw)[()]


def required_snr_db(pd, pfa, n_pulses=1, swerling=0, integration="noncoherent", method="exact"):
    """Single-pulse SNR [dB] at which the detection probability equals ``pd``: the inverse of :func:`pd_exact`.

    Parameters
    ----------
    pd : array_like
        Probability of detection, Pfa < Pd < 1: a Pd at or below Pfa needs no signal (Pd = Pfa at
        zero SNR), Pd = 1 an infinite one.
    pfa, n_pulses, swerling, integration : array_like
        As in :func:`pd_exact`.
    method : {"exact", "albersheim", "shnidman"}
        ``exact``: the root of the exact Pd in SNR, by a bracketed Illinois iteration on all points
        at once to 1e-7 dB (:func:`csuas.core.solve.bracketed_root`), started from Shnidman's
        estimate. ``albersheim`` (Swerling 0 only) and ``shnidman``: the approximations within
        their validity ranges (:func:`albersheim_snr_db`, :func:`shnidman_snr_db`); coherent
        integration uses their single-pulse value less 10 log10 N (less nothing for Swerling 2).

    Returns
    -------
    ndarray
        Single-pulse SNR [dB], the arguments' broadcast shape.

    Raises
    ------
    ParameterError
        Invalid arguments as in :func:`pd_exact`; Pd outside (Pfa, 1); a Pd so close to Pfa or 1
        that double precision cannot resolve it; an approximation outside its range or case.
    """
    if method not in METHODS:
        raise ParameterError("method", method, ", ".join(METHODS))
    errors = []
    p, n, sw, coh = _validate_common(errors, pfa, n_pulses, swerling, integration)
    d = _check_pd(errors, pd, p)
    if method == "albersheim" and sw is not None and np.any(sw != 0):
        errors.append(ParameterError("swerling", int(sw[sw != 0].flat[0]) if sw.ndim else int(sw), "0 (Albersheim)"))
    raise_all(errors)
    if method != "exact":
        shape, _, n_eff, case, gain, (d_flat,) = _prepare(p, n, sw, coh, d)
        pfa_flat = np.broadcast_to(p, shape).ravel()
        if method == "albersheim":
            single = albersheim_snr_db(d_flat, pfa_flat, n_eff)
        else:
            single = shnidman_snr_db(d_flat, pfa_flat, n_eff, case)
        return (np.asarray(single) - 10 * np.log10(gain)).reshape(shape)[()]
    shape, t, n_eff, case, gain, (d_flat, pfa_flat) = _prepare(p, n, sw, coh, d, p)

    def residual(x_db, idx=slice(None)):
        snr = np.power(10.0, x_db / 10.0)
        return _pd_flat(snr, t[idx], n_eff[idx], case[idx]) - d_flat[idx]

    guess = _shnidman_db(np.clip(d_flat, 0.1, 0.99), pfa_flat, n_eff, case)
    guess = np.clip(np.where(np.isfinite(guess), guess, 10.0), -SNR_DB_SEARCH + 1, SNR_DB_SEARCH - 1)
    lo, hi = guess - 1.0, guess + 1.0
    f_lo, f_hi = residual(lo), residual(hi)
    step = 2.0
    for _ in range(20):  # widen the brackets outward, doubling the step, until they hold the root
        down = np.flatnonzero((f_lo > 0) & (lo > -SNR_DB_SEARCH))
        up = np.flatnonzero((f_hi < 0) & (hi < SNR_DB_SEARCH))
        if not (down.size or up.size):
            break
        hi[down], f_hi[down] = lo[down], f_lo[down]
        lo[down] = np.maximum(lo[down] - step, -SNR_DB_SEARCH)
        f_lo[down] = residual(lo[down], down)
        lo[up], f_lo[up] = hi[up], f_hi[up]
        hi[up] = np.minimum(hi[up] + step, SNR_DB_SEARCH)
        f_hi[up] = residual(hi[up], up)
        step *= 2.0
    unresolved = (f_lo > 0) | (f_hi < 0)
    if np.any(unresolved):
        raise ParameterError(
            "pd",
            float(d_flat[unresolved][0]),
            "a Pd that double precision separates from Pfa and 1 (this one is too close to one of them)",
        )
    root, _ = bracketed_root(residual, lo, hi, xtol=1e-7, rtol=0.0)
    return (root - 10 * np.log10(gain)).reshape(shape)[()]
