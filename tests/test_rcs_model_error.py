"""PO's model-error bound (render/rcs/model_error.py) against exact answers: Mie spheres, plates, the EFIE.

Population of the coverage claim: PEC spheres (radius 1 m, icosphere of 81 920 faces) at ka drawn
log-uniformly in 2-50 and random aspects, VV and HH, SBR-PO at standard quality against the Mie
series; square PEC plates of side 1-10 wavelengths at normal incidence against 4 pi A^2 / lambda^2
(PO is the exact answer's large-plate limit there); the EFIE's plates of side 1 and 1.5 wavelengths.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.core.units import wavelength_m
from csuas.render.rcs import canonical
from csuas.render.rcs.model_error import (
    MIN_KA,
    PO_MODEL_COEFFICIENT,
    db_from_relative,
    model_error_db,
    relative_from_db,
    total_bound_db,
)
from csuas.render.rcs.solver import compute_rcs
from csuas.validation.rcs.model_error import EFIE_PLATE_RECORDS, calibrated_coefficient, sphere_coverage


def test_coefficient_is_the_mie_envelope_of_po_on_spheres_ka_2_to_50():
    largest, at_ka = calibrated_coefficient(points=4000)
    # C bounds PO's relative amplitude error times ka everywhere on the grid, and is no looser than 5 %
    assert largest <= PO_MODEL_COEFFICIENT <= 1.05 * largest
    assert 3.0 < at_ka < 4.5  # the resonance region, where the creeping wave is strongest


def test_total_bound_adds_relative_amplitudes():
    # 1 dB and 2 dB larger-side bounds: e = 1 - 10^(-1/20) = 0.10875, 1 - 10^(-2/20) = 0.20567
    assert relative_from_db(1.0) == pytest.approx(0.108749, abs=1e-6)
    assert float(total_bound_db(1.0, 2.0)) == pytest.approx(-20 * math.log10(1 - 0.108749 - 0.205672), abs=1e-4)
    assert float(total_bound_db(0.5, 0.0)) == pytest.approx(0.5)
    assert np.isinf(db_from_relative(1.0)) and np.isinf(total_bound_db(6.0, 6.1))


def test_model_bound_is_infinite_below_the_calibrated_ka():
    lam = wavelength_m(10.0)
    small = 0.99 * MIN_KA * lam / (2 * math.pi)
    assert np.isinf(model_error_db(10.0, small))
    assert float(model_error_db(10.0, 20.0 * lam / (2 * math.pi))) == pytest.approx(
        -20 * math.log10(1 - PO_MODEL_COEFFICIENT / 20.0)
    )


def test_total_bound_covers_mie_on_95_percent_of_random_spheres():
    result = sphere_coverage(cases=32, seed=2026)
    # before: the discretisation bound alone (against PO) covers the exact answer almost never
    assert result["coverage_discretisation"] < 0.2
    assert result["coverage_total"] >= 0.95


def test_bound_covers_plates_at_normal_incidence_and_the_efie_records():
    f = 10.0
    lam = wavelength_m(f)
    for side in (1.0, 2.0, 4.0, 10.0):
        res = compute_rcs(canonical.plate(side * lam), f, 0.0, 90.0, material="pec", quality="standard")
        exact = 4 * math.pi * (side * lam) ** 4 / lam**2
        for pol in ("VV", "HH"):
            error = abs(10 * math.log10(float(res.rcs_m2(pol).ravel()[0]) / exact))
            assert error <= float(res.bound_db(pol).ravel()[0])
    for side, efie_minus_po_db in EFIE_PLATE_RECORDS.items():
        half_diagonal = side * lam / math.sqrt(2.0)
        assert abs(efie_minus_po_db) <= float(model_error_db(f, half_diagonal))


def test_truncation_term_sees_the_bounces_the_limit_cuts_off():
    """Square trihedral on its axis: the return needs three bounces (12 pi a^4 / lambda^2, Knott et al. ch. 5)."""
    a, f = 0.1, 10.0
    exact_dbsm = 10 * math.log10(12 * math.pi * a**4 / wavelength_m(f) ** 2)
    mesh = canonical.trihedral(a)
    el = math.degrees(math.asin(1 / math.sqrt(3)))
    cut = compute_rcs(mesh, f, 45.0, el, material="pec", quality="standard", max_bounces=2)
    # two bounces miss the triple reflection: the live tubes outweigh the result, no bound
    assert np.isinf(cut.truncation_db("VV")).all() and np.isinf(cut.bound_db("VV")).all()
    full = compute_rcs(mesh, f, 45.0, el, material="pec", quality="standard", max_bounces=3)
    # after three bounces every tube on the axis leaves: nothing is truncated
    assert float(full.truncation_db("VV").ravel()[0]) == 0.0
    assert abs(float(full.rcs_dbsm("VV").ravel()[0]) - exact_dbsm) <= float(full.bound_db("VV").ravel()[0])
    plate = compute_rcs(canonical.plate(0.1), f, 0.0, 90.0, material="pec", quality="draft", max_bounces=1)
    assert float(plate.truncation_db("HH").ravel()[0]) == 0.0
