"""Benchmarks of the probability-of-detection core (docs/performance.md).

* exact Pd of ``core.radar_detection.pd_exact`` over random (SNR, N, Pfa, Swerling) points, per
  Swerling case and mixed; the inputs are drawn before the timer;
* the required-SNR inverse against a scalar loop: SciPy's ``brentq`` on a Pd computed by
  ``quad`` from the defining integral (the way a direct implementation would do it), on a few
  points, per point; with the largest difference between the two [dB].
"""

from __future__ import annotations

import time

import numpy as np
from scipy import integrate, optimize, special, stats

from csuas.core.radar_detection import pd_exact, required_snr_db

#: Points of the scalar reference loop (its per-point time is what counts).
LOOP_POINTS = 12


def _best_of(fn, repeat=3):
    best, out = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


def _quadrature_pd_swerling_1(snr_db, pfa, n):
    """Swerling 1 Pd as the steady Pd averaged over an exponential RCS, by adaptive quadrature."""
    t, snr = special.gammainccinv(n, pfa), 10 ** (snr_db / 10)
    integrand = lambda x: stats.ncx2.sf(2 * t, 2 * n, 2 * n * snr * x) * np.exp(-x)
    return integrate.quad(integrand, 0, np.inf, limit=200)[0]


def bench_pd(n: int = 1_000_000, seed: int = 0) -> list[dict]:
    """Exact Pd evaluations per second, and the inverse against a scalar root-finding loop."""
    rng = np.random.default_rng(seed)
    snr = rng.uniform(-10.0, 30.0, n)
    pulses = rng.integers(1, 65, n)
    pfa = 10 ** rng.uniform(-10.0, -3.0, n)
    swerling = rng.integers(0, 5, n)
    rows = []
    elapsed, _ = _best_of(lambda: pd_exact(snr, pfa, pulses, swerling), repeat=1)
    rows.append({"what": "pd_exact, Swerling 0-4 mixed", "points": n, "per_s": n / elapsed, "time_s": elapsed})
    for case in range(5):
        m = swerling == case
        elapsed, _ = _best_of(lambda m=m, case=case: pd_exact(snr[m], pfa[m], pulses[m], case), repeat=1)
        rows.append({"what": f"pd_exact, Swerling {case}", "points": int(m.sum()), "per_s": m.sum() / elapsed})
    # the inverse: Swerling 1, N 1..16, Pd 0.1..0.99, Pfa 1e-8..1e-4
    k = 10_000
    pd = rng.uniform(0.1, 0.99, k)
    n_inv = rng.integers(1, 17, k)
    pfa_inv = 10 ** rng.uniform(-8.0, -4.0, k)
    vector_time, snr_inv = _best_of(lambda: required_snr_db(pd, pfa_inv, n_inv, 1))
    loop = []
    start = time.perf_counter()
    for i in range(LOOP_POINTS):
        f = lambda x, i=i: _quadrature_pd_swerling_1(x, pfa_inv[i], n_inv[i]) - pd[i]
        loop.append(optimize.brentq(f, -40.0, 60.0, xtol=1e-6))
    loop_time = (time.perf_counter() - start) / LOOP_POINTS
    rows.append(
        {
            "what": "required_snr_db (Swerling 1) vs brentq over quad",
            "points": k,
            "vector_per_point_s": vector_time / k,
            "loop_per_point_s": loop_time,
            "speedup": loop_time / (vector_time / k),
            "max_difference_db": float(np.max(np.abs(np.asarray(loop) - snr_inv[:LOOP_POINTS]))),
        }
    )
    return rows
