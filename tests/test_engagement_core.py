"""Core math of engagements: false alarms per look, M-of-N confirmation, bird RCS, constant-gamma clutter."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from csuas.base.errors import ParameterError
from csuas.core import birds, clutter, false_alarms, itu, m_of_n
from csuas.defaults import load_birds, load_clutter, load_drone_rcs_statistics
from csuas.validation.report.checks_engage import enumerated_first_confirmation


def test_radar_cells_closed_form():
    dr = false_alarms.range_resolution_m(50.0)
    assert dr == pytest.approx(299792458.0 / 1e8)
    beam = false_alarms.beamwidth_deg(10 * np.log10(4 * np.pi / np.radians(3.0) ** 2))
    assert beam == pytest.approx(3.0)
    cells = false_alarms.radar_cells(1000.0, 100.0, 3.0, 120.0, 3.0, doppler_bins=16, elevation_beams=2)
    assert cells == 300 * 16 * 40 * 2
    per_look = false_alarms.false_alarms_per_look(1e-6, cells)
    assert false_alarms.per_hour(per_look, 0.5) == pytest.approx(1e-6 * cells * 7200.0)
    assert false_alarms.imaging_cells(1920, 1080, 12) == 1920 * 1080 * 12


def test_radar_cells_name_bad_input():
    with pytest.raises(ParameterError, match="reach_m"):
        false_alarms.radar_cells(10.0, 20.0, 3.0, 120.0, 3.0)
    with pytest.raises(ParameterError, match="sector_deg"):
        false_alarms.radar_cells(100.0, 0.0, 3.0, 400.0, 3.0)


@pytest.mark.parametrize(("m", "n"), [(1, 1), (2, 3), (3, 5), (4, 4)])
def test_m_of_n_matches_enumeration(m, n):
    pd = np.random.default_rng(3).uniform(0, 1, 11)
    assert np.allclose(m_of_n.first_confirmation(pd, m, n), enumerated_first_confirmation(pd, m, n), atol=1e-14)


def test_m_of_n_closed_forms():
    p = 0.3
    first = m_of_n.first_confirmation(np.full(6, p), 1, 1)
    assert np.allclose(first, p * (1 - p) ** np.arange(6))
    first = m_of_n.first_confirmation(np.full(6, p), 3, 3)
    assert first[:2].sum() == 0.0 and first[2] == pytest.approx(p**3)
    with pytest.raises(ParameterError, match="m"):
        m_of_n.first_confirmation([0.5], 4, 3)


def test_bird_water_permittivity_and_reflectivity():
    # static permittivity of pure water at 20 C: 80.1 (CRC Handbook); lossless eps = 4: |(1-2)/(1+2)|^2 = 1/9
    eps_real, eps_imag = itu.water_permittivity(1e-3, 293.15)  # the model the bird's body uses (P.840)
    assert eps_real == pytest.approx(80.1, abs=0.1) and eps_imag == pytest.approx(0.0, abs=0.01)
    assert birds.normal_reflectivity(4.0) == pytest.approx(1 / 9)
    # broadside, near-static water: pi a^2 |(1 - sqrt(80.1)) / (1 + sqrt(80.1))|^2
    gamma2 = ((math.sqrt(80.1) - 1) / (math.sqrt(80.1) + 1)) ** 2
    assert birds.bird_rcs_m2(np.pi / 2, 0.3, 0.06, 1e-3, 20.0) == pytest.approx(np.pi * 0.15**2 * gamma2, rel=1e-3)
    with pytest.raises(ParameterError, match="temperature_c"):
        birds.bird_rcs_m2(np.pi / 2, 0.3, 0.06, 24.0, 60.0)


def test_spheroid_rcs_limits():
    a, b = 0.2, 0.05
    assert birds.spheroid_rcs_m2(0.7, 0.1, 0.1) == pytest.approx(np.pi * 0.01)  # a sphere: pi r^2
    assert birds.spheroid_rcs_m2(np.pi / 2, a, b) == pytest.approx(np.pi * a**2)  # broadside
    assert birds.spheroid_rcs_m2(0.0, a, b) == pytest.approx(np.pi * b**4 / a**2)  # nose-on: pi (b^2/a)^2


def test_bird_and_drone_rcs_overlap_at_24_ghz():
    """Rahman & Robertson 2019: birds and small drones overlap in RCS at 24 GHz."""
    drone = next(
        r for r in load_drone_rcs_statistics() if r["preset"] == "dji_mini_4_pro" and r["frequency_ghz"] == 24.0
    )
    rng = np.random.default_rng(5)
    for name, bird in load_birds().items():
        rcs = birds.bird_rcs_m2(
            birds.random_aspects_rad(rng, 4000), bird["body_length_m"], bird["body_diameter_m"], 24.0
        )
        median = 10 * np.log10(np.median(rcs))
        assert drone["p10_dbsm"] < median < drone["p90_dbsm"], name
        p10, p90 = 10 * np.log10(np.percentile(rcs, [10, 90]))
        assert p10 < drone["median_dbsm"] < p90, name


def test_clutter_closed_forms():
    gamma = load_clutter()["gamma_db"]["farmland"]
    psi = np.radians(5.0)
    assert clutter.sigma0(gamma, psi) == pytest.approx(10 ** (-1.5) * np.sin(psi))
    rcs = clutter.cell_rcs_m2(gamma, psi, 300.0, 3.0, 0.05)
    assert rcs == pytest.approx(10 ** (-1.5) * np.sin(psi) * 300.0 * 0.05 * 3.0 / np.cos(psi))
    assert clutter.sigma0(gamma, 0.0) == 0.0
    # exponential clutter-plus-noise power of mean 1 + CNR over the noise threshold -ln(Pfa)
    pfa, cnr = 1e-6, np.array([0.0, 1.0, 10.0, 1000.0])
    expected = stats.expon(scale=1 + cnr).sf(-np.log(pfa))
    assert np.allclose(clutter.exceedance(pfa, cnr), expected, rtol=1e-12)
    assert clutter.exceedance(pfa, 1000.0, 30.0) == pytest.approx(stats.expon(scale=2.0).sf(-np.log(pfa)))
