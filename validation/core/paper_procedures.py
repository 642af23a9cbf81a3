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


def tir_step_reduction(
    mrtd, d_crit_m: float, lp_task: float, n_ttpf: float, delta_t0_k: float, sigma_db_km: float, step_m: float = 0.01
) -> float:
    """TIR MRTD range by the procedure of Section 4.4.3 (paper convention, Eq. 31).

    Start from the unattenuated MRTD range (Eq. 29) as R_hyp; attenuate Delta T
    over R_hyp (Eq. 31), read the sensor frequency from the MRTD curve (Eq. 27)
    and recompute R_MRTD (Eq. 29); reduce R_hyp by ``step_m`` until
    R_MRTD(R_hyp) >= R_hyp. (Iterating R_hyp = R_MRTD(R_hyp) directly, the
    other reading of step 5, can fall into a two-cycle: the map decreases
    with R and its slope may exceed 1 in magnitude.)
    """

    def r_mrtd(r_hyp):
        delta_t = abs(delta_t0_k) * math.exp(-sigma_db_km * r_hyp / 1000.0)
        return d_crit_m * float(mrtd.max_frequency(delta_t)) / (lp_task * n_ttpf)

    r_hyp = r_mrtd(0.0)
    while r_hyp > 0 and r_mrtd(r_hyp) < r_hyp:
        r_hyp -= step_m
    return max(r_hyp, 0.0)
