"""PO's model-error bound on PEC cylinders and the DJI Mini 4 Pro's arm with its motor, against the EFIE.

References: the dated EFIE records of validation/rcs/part_records.py (bempp-cl, Richardson-extrapolated
from two meshes; each value carries the extrapolation's correction as its own error), which the slow test
re-solves. SBR-PO runs live on the EFIE's fine mesh. Population: closed PEC cylinders of radius x length
0.25 x 2, 0.35 x 1.5 and 0.5 x 1 wavelengths at 10 GHz from broadside to end-on (8 elevations), and the
arm with its motor at 2.4, 5.8 and 10 GHz from 8 aspects, VV and HH; entries whose reference is uncertain by
more than 3 dB (a null the two meshes place apart) judge nothing and are counted. The floor coefficient K is calibrated
on the cylinder 0.35 x 1.5 and the arm at 5.8 GHz; the other four cases test it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.render.rcs.model_error import PO_FLOOR_COEFFICIENT, floor_error_db, floor_relative_error
from csuas.validation.rcs import model_error as me
from csuas.validation.rcs import part_references as pr
from csuas.validation.rcs.part_records import PART_RECORDS

C = 299_792_458.0


def test_floor_term_is_sqrt_k_lambda_squared_over_sigma():
    lam = C / 10e9
    sigma = 1e-3
    e = math.sqrt(PO_FLOOR_COEFFICIENT * lam**2 / sigma)
    assert float(floor_relative_error(10.0, sigma)) == pytest.approx(e, rel=1e-9)
    assert float(floor_error_db(10.0, sigma)) == pytest.approx(-20 * math.log10(1 - e), rel=1e-9)
    # no return: nothing to be relative to; a floor at or above the return: no bound
    assert np.isinf(floor_relative_error(10.0, 0.0)) and np.isinf(floor_error_db(10.0, PO_FLOOR_COEFFICIENT * lam**2))


def test_records_are_the_meshes_of_their_cases():
    """Every case is recorded; re-meshing gives the recorded element counts; the reference's error is stated."""
    assert set(PART_RECORDS) == set(me.PART_CALIBRATION) | set(me.PART_TEST) <= set(pr.PART_CASES)
    uncertain = total = 0
    for name, record in PART_RECORDS.items():
        h = pr.fine_edge_m(name)
        counts = (len(pr.case_mesh(name, h).faces), len(pr.case_mesh(name, pr.COARSE_RATIO * h).faces))
        assert counts == tuple(record["elements"]), name
        assert record["edges_per_wavelength"][0] >= 8.5  # cells of lambda/10 or finer (diagonals: mean 8.8)
        for pol in ("VV", "HH"):
            assert len(record["reference_dbsm"][pol]) == len(record["aspects_deg"]) == len(pr.aspects(name))
            errors = np.asarray(record["reference_error_db"][pol])
            assert (errors >= 0.0).all() and np.isfinite(record["reference_dbsm"][pol]).all()
            uncertain += int((errors > me.MAX_REFERENCE_ERROR_DB).sum())
            total += len(errors)
    # Richardson fails only in a few nulls that the two meshes place apart (they judge nothing)
    assert uncertain <= 0.05 * total


@pytest.fixture(scope="module")
def calibration():
    return me.part_entries(me.PART_CALIBRATION)


@pytest.fixture(scope="module")
def test_entries():
    return me.part_entries(me.PART_TEST)


def test_floor_coefficient_is_calibrated_on_the_calibration_cases(calibration):
    needed, _ = me.calibrated_floor(calibration)
    # K covers every calibration entry (reference's own error added): the calibrated value rounded up to two
    # significant digits, so no looser than 10 %
    assert 0.9 * PO_FLOOR_COEFFICIENT <= needed <= PO_FLOOR_COEFFICIENT
    assert me.part_coverage(calibration)["coverage_strict"] == 1.0


def test_bound_covers_95_percent_of_the_test_parts(test_entries):
    r = me.part_coverage(test_entries)
    assert r["entries"] + r["unjudged"] == 2 * sum(len(PART_RECORDS[n]["aspects_deg"]) for n in me.PART_TEST)
    assert r["coverage_total"] >= 0.95
    # before the floor (discretisation + 1.5/(k a), a the bounding radius) the same entries were not covered
    assert r["coverage_without_floor"] < 0.95


@pytest.mark.slow
def test_an_efie_record_is_reproduced_by_bempp():
    """The smallest cylinder's two meshes re-solved through the --full report's check (measured 311 s at load
    4-5 beside another EFIE run, 35 s of it numba's compilation): every aspect within 0.01 dB of the record."""
    from csuas.validation.report import checks_rcs

    checks = checks_rcs._reproduced_references(["cylinder_r0.25_l2"])
    assert [c.name for c in checks] == [f"rcs.bound_parts.cylinder_r0.25_l2.{p}.efie_reproduced" for p in ("VV", "HH")]
    for check in checks:
        assert check.ok and check.details["aspects"] == len(PART_RECORDS["cylinder_r0.25_l2"]["aspects_deg"]), check


def test_report_section_judges_the_test_parts_within_their_bounds():
    """The quick section (the --full one without re-solving the EFIE): K's check and the coverage check pass;
    each finite bound is a check of its own."""
    from csuas.validation.report import checks_rcs

    assert checks_rcs.BOUND_PARTS["quick"] == {"recalibrate": False} and checks_rcs.bound_parts(None).notes
    section = checks_rcs.bound_parts(checks_rcs.BOUND_PARTS["quick"])
    by_name = {c.name: c for c in section.outcomes}
    assert by_name["rcs.bound_parts.floor_coefficient"].ok
    assert by_name["rcs.bound_parts.coverage"].ok
    entries = [c for c in section.outcomes if c.unit == "dBsm"]
    assert entries and sum(c.ok for c in entries) >= 0.9 * len(entries)
    # a figure outside its bound is one the 95 % claim allows, stated as such, never a silent pass
    assert all((c.limitation is None) == (abs(c.measured - c.expected) <= c.tolerance) for c in entries)
