"""The edge term of the RCS bound (render/rcs/edge_residual.py) against hand geometry and the EFIE.

References, independent of the code under test:

* hand geometry of a square plate's rim at normal incidence: four straight edges broadside to the
  wave (each radiates a unit line current's ``L / (4 pi)``), V's magnetic field along the two
  edges parallel to y (hard), its electric field along the two parallel to x (soft), four corners;
* the bempp-cl EFIE of PEC plates recorded in ``validation/rcs/edge_residual_cases.py`` (dated,
  with their mesh density and refinement error), and one of them solved again here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.render.rcs import canonical
from csuas.render.rcs import edge_residual as er
from csuas.render.rcs.model_error import total_bound_db
from csuas.render.rcs.solver import compute_rcs, get_engine
from csuas.validation.rcs import edge_residual_cases as cases
from csuas.validation.rcs import fullwave as fw
from csuas.validation.rcs.model_error import BOUND_COVERAGE

C = 299_792_458.0


def test_plate_rim_has_four_lines_and_four_corners_and_a_disc_none():
    engine = get_engine(fw.plate_mesh(0.06, 0.003), "pec")  # 20 x 20 cells: 80 rim segments
    edges = engine.edges
    assert len(edges) == 80
    assert len(np.unique(er.edge_lines(edges))) == 4
    assert er.edge_corners(edges).shape[1] == 4
    disc = get_engine(canonical.disk(0.05, 64), "pec").edges  # turns 5.6 deg at each rim vertex
    assert len(disc) == 64 and er.edge_corners(disc).shape[1] == 0


def test_residual_of_a_square_plate_at_normal_incidence_by_hand():
    side, f = 0.06, 10.0
    engine = get_engine(fw.plate_mesh(side, 0.003), "pec")
    k = 2 * math.pi * f * 1e9 / C
    r = er.residual_amplitude(engine.edges, [0.0], [90.0], [f], [[0.0]], [[90.0]])[0, 0]
    lines = 2 * side / (4 * math.pi)  # two edges of each kind, broadside, in phase at the origin's plane
    corners = 4 / (4 * math.pi * k)
    expected = (er.C_HARD + er.C_SOFT) * lines + er.C_CORNER * corners
    assert r[0, 0] == pytest.approx(expected, rel=1e-9)  # VV: y-edges hard, x-edges soft
    assert r[1, 1] == pytest.approx(expected, rel=1e-9)  # HH: the roles swap, the same sum
    assert r[0, 1] == pytest.approx(er.C_CORNER * corners, rel=1e-9)  # cross: no edge is both


def test_bound_carries_the_edge_term_only_with_edge_diffraction():
    mesh = fw.plate_mesh(0.06, 0.003)
    on = compute_rcs(mesh, 10.0, [0.0], [60.0], material="pec", quality="draft", edge_diffraction=True)
    off = compute_rcs(mesh, 10.0, [0.0], [60.0], material="pec", quality="draft")
    assert off.edge_residual_m is None and off.edge_residual_db("VV") is None
    for pol in ("VV", "HH"):
        terms = (on.error_estimate_db(pol), on.model_error_db[:, None, None], on.model_floor_db(pol))
        terms += (on.truncation_db(pol),)
        edge = on.edge_residual_db(pol)
        assert edge[0, 0, 0] > 0.0
        np.testing.assert_allclose(on.bound_db(pol), total_bound_db(*terms, edge), rtol=1e-12)


def test_bound_covers_the_efie_on_held_out_plates_in_the_report_check():
    """Test plates (not the calibration's): 1.5, 2.5 and 3 wavelengths square, 1 x 1.5, 1 x 2, 2 x 1.5 and
    1.5 x 2.5 rectangles, azimuths other than the calibration's, 0-80 deg from the normal; through the report's
    spec. Measured: VV 158/162 (97.5 %), HH 160/162 (98.8 %); without the edge term 40.7 % and 49.4 %."""
    from csuas.validation.report.checks_rcs import EDGE_RESIDUAL, SPECS, edge_residual

    assert "rcs.edge_residual" in [spec.name for spec in SPECS]
    outcomes = edge_residual(EDGE_RESIDUAL["quick"]).outcomes
    assert [c.name for c in outcomes] == ["rcs.edge_residual.VV.coverage", "rcs.edge_residual.HH.coverage"]
    names = cases.cases("test")
    for check in outcomes:
        c = check.details
        assert check.ok and c["covered"] >= BOUND_COVERAGE
        assert c["covered_without_edge"] < BOUND_COVERAGE  # the term is needed: without it far less is covered
        assert len(names) >= 4 and c["n"] == sum(9 * len(cases.EFIE_PLATES[n]["azimuth_deg"]) for n in names)


def test_shipped_coefficients_cover_every_calibration_figure():
    rows = cases.figures(cases.cases("calibration"))
    assert cases.coverage(rows)["covered"] == 1.0
    needed = cases.calibrate(rows)
    shipped = np.array([er.C_HARD, er.C_SOFT, er.C_CORNER])
    assert np.all(shipped >= needed) and np.all(shipped <= needed + 0.011)  # rounded up to 0.01


@pytest.mark.slow
def test_efie_of_a_recorded_plate_is_reproduced():
    """The side-wavelength plate at normal incidence and 40 deg off it, solved again; most of the time is numba
    compiling bempp-cl's kernels (measured on the 2 shared cores: 140 s at load 4-5, 546 s at load 13-14)."""
    name = cases.cases("calibration")[0]
    mesh = cases.plate(name)
    az, el = cases.aspects(name)
    pick = np.isin(el, (90.0, 50.0)) & (az == 0.0)
    res = fw.monostatic_rcs_efie(
        mesh.vertices, mesh.faces, cases.FREQUENCY_GHZ, az[pick], el[pick], "VV", fw.EfieSettings(solver="lu")
    )
    for pol in ("VV", "HH"):
        recorded = np.asarray(cases.EFIE_PLATES[name][f"{pol.lower()}_dbsm"])[pick]
        np.testing.assert_allclose(res.rcs_dbsm(pol), recorded, atol=0.01)


def test_what_the_hard_polarisation_misses_is_double_diffraction():
    """VV in the principal plane (H along the two edges across it): adding Ross's doubly diffracted wave
    (tests/test_rcs_edges.py's independent GTD) to PO + PTD brings 10-60 deg from the normal close to the
    recorded EFIE; near grazing (70-80 deg) that first-order double diffraction overshoots instead.

    Measured (median |error| 10-60 deg, PTD -> PTD + Ross's double diffraction): side 1 wavelength 4.0 ->
    1.9 dB, 1.5: 3.9 -> 0.9 dB, 2: 3.2 -> 1.1 dB; at 70-80 deg 0.8-15 -> 2.2-25 dB.
    """
    from test_rcs_edges import db, po_plate, ross  # the independent closed forms (Ross 1966, PO)

    from csuas.render.rcs.edges import edge_amplitude

    theta = np.arange(10.0, 61.0, 10.0)
    for name in ("square_1", "square_1.5", "square_2"):
        side = cases.EFIE_PLATES[name]["side_wavelengths"][0] * C / (cases.FREQUENCY_GHZ * 1e9)
        edges = get_engine(canonical.plate(side), "pec").edges
        ptd = (
            po_plate(side, side, theta)
            + edge_amplitude(edges, 0.0 * theta, 90.0 - theta, cases.FREQUENCY_GHZ)[:, 0, 0, 0]
        )
        double = ross(side, side, theta, True, True) - ross(side, side, theta, True, False)
        az, el = cases.aspects(name)
        efie = np.asarray(cases.EFIE_PLATES[name]["vv_dbsm"])
        efie = np.array([efie[(az == 0.0) & (el == 90.0 - t)][0] for t in theta])
        before, after = np.median(np.abs(db(ptd) - efie)), np.median(np.abs(db(ptd + double) - efie))
        assert before > 3.0 and after < 2.0 and after < before / 2.0
