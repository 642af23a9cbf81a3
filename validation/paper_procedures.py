"""The paper's iterative procedures as written, one scenario at a time (reference for benchmarks).

These scalar loops are what the paper prescribes (Sections 4.3.3 and 4.4.3);
csuas replaces them by the exact vectorised solutions of ``csuas.core``. They
are kept to measure that replacement: accuracy (the loops stop within one
step of the answer) and speed (``csuas bench``).
"""

from __future__ import annotations

import math


def eo_step_reduction(r_johnson_m: float, c0: float, c_min: float, sigma_db_km: float, step_m: float = 1.0) -> float:
    """EO range by the procedure of Section 4.3.3 (paper convention, Eq. 10).

    Start from the Johnson range and reduce it by ``step_m`` until the
    attenuated contrast C0 10^(-sigma R/10) reaches C_min (Eq. 21).
    """
    r = r_johnson_m
    while r > 0 and c0 * 10.0 ** (-sigma_db_km * r / 1000.0 / 10.0) < c_min:
        r -= step_m
    return max(r, 0.0)


def tir_fixed_point(mrtd, d_crit_m: float, lp_task: float, n_ttpf: float, delta_t0_k: float,
                    sigma_db_km: float, tol_m: float = 1e-3, max_iter: int = 10_000) -> float:
    """TIR MRTD range by the iteration of Section 4.4.3 (paper convention, Eq. 31).

    Guess R_hyp, attenuate Delta T (Eq. 31), read the sensor frequency from
    the MRTD curve (Eq. 27) and recompute R (Eq. 29); repeat until R_hyp = R.
    """
    r_hyp = 0.0
    for _ in range(max_iter):
        delta_t = abs(delta_t0_k) * math.exp(-sigma_db_km * r_hyp / 1000.0)
        r_new = d_crit_m * float(mrtd.max_frequency(delta_t)) / (lp_task * n_ttpf)
        if abs(r_new - r_hyp) < tol_m:
            return r_new
        r_hyp = r_new
    return r_hyp
