"""Calibration and coverage of physical optics' model-error bound (:mod:`csuas.render.rcs.model_error`).

* :func:`calibrated_coefficient` -- the largest relative amplitude error of PO against the exact Mie
  series of a PEC sphere, times k a, over a range of ka (1.469 at ka = 3.61 over ka 2-50): the
  coefficient C of ``e_model = C / (k a)``.
* :data:`EFIE_PLATE_RECORDS` -- the EFIE's square plates at normal incidence against PO's
  4 pi A^2 / lambda^2 (``fullwave_checks`` module docstring, bempp-cl on the same mesh).
* :func:`sphere_coverage` -- SBR-PO runs of a PEC sphere at random ka and aspects against the Mie
  series: how often the discretisation bound alone, and the total bound, cover the exact answer.

References: Ruck et al., *Radar Cross Section Handbook*, 1970, ch. 3 (Mie series); Knott, Shaeffer
and Tuley, *Radar Cross Section*, 2nd ed., 2004, ch. 5 (the PO sphere).
"""

from __future__ import annotations

import math
import time

import numpy as np

from csuas.core.units import frequency_ghz as frequency_ghz_of

from .fullwave_checks import mie_pec_over_pia2

#: EFIE minus PO [dB] of square PEC plates at normal incidence, by side [wavelengths]
#: (bempp-cl EFIE, 10 edges per wavelength; validation/rcs/fullwave_checks.py module docstring).
EFIE_PLATE_RECORDS = {1.0: -0.59, 1.5: 0.54}


def po_sphere_over_pia2(ka) -> np.ndarray:
    """PO monostatic RCS / (pi a^2) of a sphere: |(e^{-jx}(1 + jx) - 1) / x|^2 with x = 2 ka (Knott et al., ch. 5)."""
    x = 2.0 * np.asarray(ka, float)
    return np.abs((np.exp(-1j * x) * (1 + 1j * x) - 1) / x) ** 2


def sphere_po_relative_error(ka) -> np.ndarray:
    """|sqrt(sigma_Mie / sigma_PO) - 1| of a PEC sphere: PO's relative amplitude error at ka."""
    ka = np.atleast_1d(np.asarray(ka, float))
    mie = np.array([mie_pec_over_pia2(x) for x in ka])
    return np.abs(np.sqrt(mie / po_sphere_over_pia2(ka)) - 1.0)


def calibrated_coefficient(ka_min: float = 2.0, ka_max: float = 50.0, points: int = 20_000) -> tuple[float, float]:
    """(max of e k a, the ka where it occurs) over ``points`` ka evenly spaced in [ka_min, ka_max]."""
    ka = np.linspace(ka_min, ka_max, points)
    scaled = sphere_po_relative_error(ka) * ka
    i = int(np.argmax(scaled))
    return float(scaled[i]), float(ka[i])


def sphere_coverage(cases: int = 48, seed: int = 26, quality: str = "standard", subdivisions: int = 6) -> dict:
    """SBR-PO on a PEC sphere (radius 1 m) at ka log-uniform in 2-50 and random aspects, against Mie.

    One aspect per ka (the sphere has no preferred aspect; it samples the faceting); both
    co-polarisations. Returns per entry (case x polarisation) the ka, aspect, SBR and Mie RCS [dBsm],
    the error [dB] and the discretisation and total bounds [dB]; the fraction of entries each bound
    covers, and the time of the runs [s].
    """
    from csuas.render.rcs import canonical
    from csuas.render.rcs.solver import compute_rcs, get_engine

    rng = np.random.default_rng(seed)
    ka = np.exp(rng.uniform(math.log(2.0), math.log(50.0), cases))
    az = rng.uniform(-180.0, 180.0, cases)
    el = np.degrees(np.arcsin(rng.uniform(-1.0, 1.0, cases)))
    engine = get_engine(canonical.sphere(1.0, subdivisions), "pec")
    sbr, mie, disc, total = [], [], [], []
    start = time.perf_counter()
    for k in range(cases):  # one frequency per aspect: a run per case
        res = compute_rcs(engine, float(frequency_ghz_of(2 * math.pi / ka[k])), az[k], el[k], quality=quality)
        for pol in ("VV", "HH"):
            sbr.append(float(res.rcs_dbsm(pol).ravel()[0]))
            mie.append(10 * math.log10(math.pi * mie_pec_over_pia2(float(ka[k]))))
            disc.append(float(res.error_estimate_db(pol).ravel()[0]))
            total.append(float(res.bound_db(pol).ravel()[0]))
    errors, disc, total = np.abs(np.array(sbr) - np.array(mie)), np.array(disc), np.array(total)
    return {
        "ka": np.repeat(ka, 2),
        "azimuth_deg": np.repeat(az, 2),
        "elevation_deg": np.repeat(el, 2),
        "polarisation": ["VV", "HH"] * cases,
        "sbr_dbsm": np.array(sbr),
        "mie_dbsm": np.array(mie),
        "error_db": errors,
        "discretisation_db": disc,
        "bound_db": total,
        "coverage_discretisation": float(np.mean(errors <= disc)),
        "coverage_total": float(np.mean(errors <= total)),
        "time_s": time.perf_counter() - start,
    }
