"""Exact, vectorised solvers for the paper's iterative range procedures.

The paper finds several ranges by stepping a trial range down until a
condition holds (EO contrast limit, Section 4.3.3; TIR MRTD with attenuation,
Section 4.4.3; lidar transmission loss, Eq. 101). csuas solves them exactly:

* :func:`solve_log_linear` -- closed form (Lambert W) of
  ``10 n log10(R) + a R = K``, the shape of every spreading-plus-attenuation
  budget (RF, radar, lidar, acoustic with absorption);
* :func:`bracketed_root` -- a bracketed root solve over whole arrays
  (bisection safeguarded regula falsi, no per-point Python loop) for monotone
  residuals without a closed form, with an explicit "no root" mask.
"""

from __future__ import annotations

import numpy as np

LN10 = np.log(10.0)


def lambertw_exp(log_x):
    """Principal Lambert W of ``exp(log_x)``, stable for any real ``log_x``.

    Parameters
    ----------
    log_x : array_like
        Natural logarithm of the argument (may be far beyond float range, e.g. 1e5).

    Returns
    -------
    ndarray
        W(e^log_x) >= 0.
    """
    log_x = np.asarray(log_x, dtype=float)
    small = log_x < 1.0
    out = np.empty_like(log_x)
    if np.any(small):
        from scipy.special import lambertw  # imported on first use: 0.17 s of every command's start-up

        out[small] = lambertw(np.exp(log_x[small])).real
    big = ~small
    if np.any(big):
        lx = log_x[big]
        w = lx - np.log(lx)  # asymptotic start; Newton on w + ln w = lx
        for _ in range(8):
            w = w - (w + np.log(w) - lx) / (1.0 + 1.0 / w)
        out[big] = w
    return out


def solve_log_linear(budget_db, slope_db_per_m, n=2.0):
    """Solve ``10 n log10(R) + a R = K`` for the range R [m].

    Parameters
    ----------
    budget_db : array_like
        K [dB]: the link budget available for spreading and attenuation.
        May be -inf (R = 0) or +inf (R = inf).
    slope_db_per_m : array_like
        a [dB/m] >= 0: attenuation per metre of path (two-way paths pass twice
        the one-way coefficient).
    n : float
        Spreading exponent: 2 for one-way (Friis, acoustic), 4 for two-way
        (radar, lidar).

    Returns
    -------
    ndarray
        R [m] >= 0. With a = 0 this is ``10**(K/(10 n))``; otherwise
        ``(10 n/(a ln10)) W((a ln10/(10 n)) 10**(K/(10 n)))``, evaluated in the
        log domain so that extreme budgets do not overflow.
    """
    k = np.asarray(budget_db, dtype=float)
    a = np.asarray(slope_db_per_m, dtype=float)
    k, a = np.broadcast_arrays(k, a)
    scale = 10.0 * n
    out = np.zeros(k.shape)
    finite = np.isfinite(k)
    out[k == np.inf] = np.inf
    c_all = a * LN10 / scale
    free = finite & (c_all == 0)  # no attenuation, or a slope so small it underflows
    with np.errstate(over="ignore"):
        out[free] = np.power(10.0, k[free] / scale)
    att = finite & (c_all > 0)
    if np.any(att):
        c = c_all[att]
        log_x = np.log(c) + k[att] * LN10 / scale
        out[att] = lambertw_exp(log_x) / c
    return out


def bracketed_root(residual, lo, hi, *, xtol=1e-12, rtol=1e-12, max_iter=200):
    """Root of a monotone residual over arrays, by safeguarded regula falsi.

    Parameters
    ----------
    residual : callable
        ``residual(x) -> ndarray`` evaluated elementwise on an array of trial
        points (same shape as ``lo``).
    lo, hi : array_like
        Brackets (broadcast together). A root exists where the residual
        changes sign between them.
    xtol, rtol : float
        Absolute and relative tolerances on x.
    max_iter : int
        Iteration cap (the Illinois modification converges superlinearly;
        bisection steps guarantee at most ~60 halvings in double precision).

    Returns
    -------
    root : ndarray
        The root where bracketed, NaN elsewhere (never returned to users: see ``found``).
    found : ndarray of bool
        Whether the residual changed sign in [lo, hi].
    """
    lo, hi = (np.array(v, dtype=float) for v in np.broadcast_arrays(lo, hi))
    f_lo, f_hi = residual(lo), residual(hi)
    found = np.sign(f_lo) * np.sign(f_hi) <= 0
    a, b, fa, fb = lo.copy(), hi.copy(), f_lo.copy(), f_hi.copy()
    root = np.where(f_lo == 0, lo, np.where(f_hi == 0, hi, np.nan))
    active = found & np.isnan(root)
    side = np.zeros(a.shape, dtype=int)
    for iteration in range(max_iter):
        if not np.any(active):
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            x = b - fb * (b - a) / (fb - fa)
        bisect = ~np.isfinite(x) | (x <= np.minimum(a, b)) | (x >= np.maximum(a, b)) | (iteration % 4 == 3)
        x = np.where(bisect, 0.5 * (a + b), x)
        fx = np.where(active, residual(np.where(active, x, a)), 0.0)
        left = np.sign(fx) == np.sign(fa)
        # Illinois: halve the retained end's value when the same side is kept twice.
        a_new = np.where(left, x, a)
        fa_new = np.where(left, fx, np.where(side == -1, fa * 0.5, fa))
        b_new = np.where(left, b, x)
        fb_new = np.where(left, np.where(side == 1, fb * 0.5, fb), fx)
        side = np.where(left, 1, -1)
        a = np.where(active, a_new, a)
        b = np.where(active, b_new, b)
        fa = np.where(active, fa_new, fa)
        fb = np.where(active, fb_new, fb)
        converged = active & ((fx == 0) | (np.abs(b - a) <= xtol + rtol * np.abs(x)))
        root = np.where(converged, x, root)
        active &= ~converged
    root = np.where(active, 0.5 * (a + b), root)
    return root, found
