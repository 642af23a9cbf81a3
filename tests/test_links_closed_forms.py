"""NumPy parts of the Sionna RT links: Fresnel, two-ray, four-path radar, RCS tables, budgets.

References: Fresnel's equations (Born & Wolf, Principles of Optics, 7th ed., Sec. 1.5.2), the PEC and
Brewster limits, the two-ray d^-4 law (Rappaport, Wireless Communications, 2nd ed., Eq. 4.52) and the
radar equation (the paper's Eq. 68), all written inline.
"""

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core.dielectric import complex_permittivity
from csuas.render.links.budget import PRESETS, SIONNA_DEFAULT, LinkBudget, resolve_budget
from csuas.render.links.rcs_table import RCSTable, as_rcs_function, bisector_aspect
from csuas.render.links.two_ray import (
    fresnel_coefficients,
    radar_four_paths,
    two_ray_path_gain_db,
    two_ray_paths,
)

C = 299_792_458.0


def test_fresnel_limits():
    # Perfect conductor: r_te = -1, r_tm = +1 at every angle (image of a vertical dipole is upright).
    cos = np.array([1.0, 0.5, 0.01])
    r_te, r_tm = fresnel_coefficients(cos, -1e15j)
    np.testing.assert_allclose(r_te, -1, atol=1e-5)
    np.testing.assert_allclose(r_tm, 1, atol=1e-5)
    # Lossless dielectric eps = 4: normal incidence (1 - 2)/(1 + 2) = -1/3 for TE and +1/3 for TM;
    # Brewster angle tan(theta_B) = 2 cancels TM; grazing gives -1 for both.
    r_te, r_tm = fresnel_coefficients([1.0, np.cos(np.arctan(2.0)), 1e-9], 4.0)
    np.testing.assert_allclose(r_te[0], -1 / 3, atol=1e-12)
    np.testing.assert_allclose(r_tm[0], 1 / 3, atol=1e-12)
    assert abs(r_tm[1]) < 1e-12
    np.testing.assert_allclose([r_te[2], r_tm[2]], [-1, -1], atol=1e-6)


def test_complex_permittivity_itu_definition():
    # eta = eps_r - j sigma / (2 pi f eps0): concrete at 10 GHz, sigma = 0.0462 * 10^0.7822 S/m.
    sigma = 0.0462 * 10**0.7822
    eta = complex_permittivity(5.24, sigma, 10.0)
    assert eta.real == 5.24
    np.testing.assert_allclose(-eta.imag, sigma / (2 * np.pi * 10e9 * 8.8541878128e-12), rtol=1e-12)


def test_two_ray_free_space_is_friis():
    d = np.array([1.0, 10.0, 5e4])
    gain = two_ray_path_gain_db(2.4, d, 7.0, 7.0, None)
    np.testing.assert_allclose(gain, -20 * np.log10(4 * np.pi * d / (C / 2.4e9)), atol=1e-9)


@pytest.mark.parametrize("polarization", ["V", "H"])
def test_two_ray_far_field_d4_law_over_pec(polarization):
    # Far beyond the last lobe over a PEC: H (r_te = -1) gives |h|^2 -> (h_t h_r / d^2)^2 (the d^-4 law);
    # V (r_tm = +1, upright image) makes the two rays add: 4x Friis.
    d = np.array([2e5, 1e6])  # k * path difference <= 0.03 rad: small-angle limit
    h_t, h_r, f = 30.0, 2.0, 2.4
    gain = two_ray_path_gain_db(f, d, h_t, h_r, -1e15j, polarization)
    if polarization == "H":
        np.testing.assert_allclose(gain, 20 * np.log10(h_t * h_r / d**2), atol=0.01)
    else:
        np.testing.assert_allclose(gain, -20 * np.log10(4 * np.pi * d / (C / (f * 1e9))) + 20 * np.log10(2), atol=0.01)


def test_two_ray_scalar_form_in_the_vertical_plane():
    # Independent scalar form for V polarisation: h = lambda/(4 pi) [e^{-jkR1}/R1 + r_tm e^{-jkR2}/R2].
    f, h_t, h_r = 5.0, 40.0, 3.0
    d = np.geomspace(5.0, 2e4, 37)
    eta = complex_permittivity(15 * f**-0.1, 0.035 * f**1.63, f)
    lam = C / (f * 1e9)
    r1, r2 = np.hypot(d, h_t - h_r), np.hypot(d, h_t + h_r)
    cos_i = (h_t + h_r) / r2
    root = np.sqrt(eta - (1 - cos_i**2))
    r_tm = (eta * cos_i - root) / (eta * cos_i + root)
    expected = lam / (4 * np.pi) * (np.exp(-2j * np.pi * r1 / lam) / r1 + r_tm * np.exp(-2j * np.pi * r2 / lam) / r2)
    tx = np.stack([0 * d, 0 * d, h_t + 0 * d], -1)
    rx = np.stack([d * np.cos(0.7), d * np.sin(0.7), h_r + 0 * d], -1)  # any azimuth: same physics
    np.testing.assert_allclose(two_ray_paths(f, tx, rx, eta).sum(-1), expected, rtol=1e-8, atol=0)


def test_radar_four_paths_free_space_is_radar_equation_and_pec_lobes_reach_12_db():
    f, sigma = 24.0, 0.01
    lam = C / (f * 1e9)
    radar = np.array([[500.0, 0.0, 5.0]])
    target = np.array([0.0, 0.0, 5.0])
    free = np.abs(radar_four_paths(f, radar, target, sigma, None).sum(-1)) ** 2
    np.testing.assert_allclose(free, lam**2 * sigma / ((4 * np.pi) ** 3 * 500.0**4), rtol=1e-12)
    # Over a PEC with V polarisation, the one-way field is at most doubled, the two-way power 16x (+12.04 dB).
    ranges = np.linspace(100.0, 3000.0, 4000)
    radars = np.stack([ranges, 0 * ranges, 5 + 0 * ranges], -1)
    over = np.abs(radar_four_paths(f, radars, np.array([0.0, 0.0, 20.0]), sigma, -1e15j).sum(-1)) ** 2
    slant = np.hypot(ranges, 15.0)
    gain = 10 * np.log10(over / (lam**2 * sigma / ((4 * np.pi) ** 3 * slant**4)))
    assert 11.9 < gain.max() <= 12.05
    assert gain.min() < -30


def test_rcs_table_interpolation_wrap_and_clamp():
    az = np.arange(0.0, 360.0, 30.0)
    el = np.array([-30.0, 0.0, 30.0])
    sigma = np.outer(1.0 + az / 100.0, [1.0, 2.0, 3.0])
    table = RCSTable(az, el, sigma)
    assert table.periodic
    np.testing.assert_allclose(table(60.0, 0.0), 1.6 * 2.0)  # node
    np.testing.assert_allclose(table(45.0, 15.0), (1.3 + 1.6) / 2 * 2.5)  # bilinear
    np.testing.assert_allclose(table(345.0, 0.0), (4.3 + 1.0) / 2 * 2.0)  # wraps 330 -> 360 = 0
    np.testing.assert_allclose(table(-15.0, 0.0), table(345.0, 0.0))
    np.testing.assert_allclose(table(0.0, 80.0), 3.0)  # clamped elevation
    assert table(np.zeros((2, 3)), 0.0).shape == (2, 3)
    closed = RCSTable(np.linspace(-180, 180, 13), el, np.ones((13, 3)))  # closing column accepted
    assert closed.periodic and closed(179.0, 0.0) == 1.0


@pytest.mark.parametrize(
    "az, el, sigma",
    [
        ([0.0, 0.0], [0.0], [[1.0], [1.0]]),  # not increasing
        ([0.0, 400.0], [0.0], [[1.0], [1.0]]),  # spans more than 360 deg
        ([0.0, 90.0], [-100.0, 0.0], np.ones((2, 2))),  # elevation below -90
        ([0.0, 90.0], [0.0], [[1.0], [-1.0]]),  # negative sigma
        ([0.0, 90.0], [0.0], [[1.0], [np.nan]]),  # NaN
        ([0.0, 90.0], [0.0], [[1.0, 1.0]]),  # wrong shape
    ],
)
def test_rcs_table_bad_input(az, el, sigma):
    with pytest.raises(ParameterError):
        RCSTable(az, el, sigma)


def test_rcs_functions_and_bisector():
    assert as_rcs_function(None)(0.0, 0.0) == 0.01  # Table 8 default
    assert np.all(as_rcs_function(2.0)(np.zeros(3), 0.0) == 2.0)
    for bad in (-1.0, np.inf, "big"):
        with pytest.raises(ParameterError):
            as_rcs_function(bad)
    # Monostatic: the bisector of -k_i and k_s is the direction toward the radar.
    to_radar = np.array(
        [
            np.cos(np.radians(40)) * np.cos(np.radians(10)),
            np.sin(np.radians(40)) * np.cos(np.radians(10)),
            np.sin(np.radians(10)),
        ]
    )
    az, el = bisector_aspect(-to_radar, to_radar)
    np.testing.assert_allclose([az, el], [40.0, 10.0], atol=1e-12)


def test_budgets():
    assert resolve_budget("standard") == PRESETS["standard"]
    assert resolve_budget("sionna_default") == SIONNA_DEFAULT
    custom = resolve_budget("draft", samples=7, max_depth=2)
    assert (custom.samples, custom.max_depth, custom.name) == (7, 2, "custom")
    for kwargs in ({"budget": "fast"}, {"samples": 0}, {"samples": 2.5}, {"max_depth": -1}, {"max_depth": 11}):
        with pytest.raises(ParameterError):
            resolve_budget(**kwargs)
    for budget, name in ((LinkBudget("custom", 0, 1), "samples"), (LinkBudget("custom", 4, 11), "max_depth")):
        with pytest.raises(ParameterError, match=name):
            resolve_budget(budget)


def test_a_perfect_conductor_has_a_finite_real_and_minus_infinite_imaginary_permittivity():
    eta = complex_permittivity(1.0, np.inf, 10.0)
    assert eta.real == 1.0 and eta.imag == -np.inf
    lossy = complex_permittivity(4.0 - 0.1j, 0.01, 1.0)  # a complex eps_r keeps its own loss
    assert lossy == pytest.approx(4.0 - 1j * (0.1 + 0.01 / (2 * np.pi * 1e9 * 8.8541878128e-12)), rel=1e-12)
