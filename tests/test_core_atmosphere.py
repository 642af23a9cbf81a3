"""Atmospheric optics: Koschmieder (Eq. 12), Kruse/Kim (Eqs. 19-20), Beer-Lambert (Eq. 10)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from csuas.base.errors import ParameterError
from csuas.core import atmosphere


def test_koschmieder_reproduces_table_16():
    sigma = atmosphere.koschmieder_extinction_per_km([0.8, 0.4, 0.1])
    np.testing.assert_allclose(sigma, [4.89, 9.78, 39.12], atol=0.005)  # Table 16, printed to 2 decimals


def test_koschmieder_wmo_threshold():
    # WMO's 5 % threshold: sigma = 2.996 / V (docs/validation.md)
    assert atmosphere.koschmieder_extinction_per_km(1.0, 0.05) == pytest.approx(2.9957, abs=1e-4)


@pytest.mark.parametrize(
    "v_km, q",
    [
        (0.3, 0.0),
        (0.5, 0.0),
        (0.5 + 1e-9, 0.0),
        (0.75, 0.25),
        (1.0, 0.5),
        (1.0 + 1e-9, 0.5),
        (3.0, 0.82),
        (6.0, 1.3),
        (6.0 + 1e-9, 1.3),
        (10.0, 1.3),
        (50.0, 1.3),
        (50.0 + 1e-9, 1.6),
        (100.0, 1.6),
    ],
)
def test_kruse_q_at_every_breakpoint(v_km, q):
    # Eq. 20: continuous at 0.5, 1 and 6 km; jumps to 1.6 above 50 km
    assert atmosphere.kruse_q(v_km) == pytest.approx(q, abs=1e-8)


def test_kruse_at_550nm_is_koschmieder():
    # At the reference wavelength the size term vanishes: sigma = 3.912 / V for any q
    v = np.array([0.2, 0.7, 3.0, 20.0, 80.0])
    np.testing.assert_allclose(atmosphere.kruse_extinction_per_km(550.0, v), -math.log(0.02) / v, rtol=1e-12)


def test_table_47_transmission_factor():
    # Table 47 text: sigma(1550 nm, V = 3 km) = 0.557, eta_TL = 10^(-0.557*3/10) = 0.681
    q = 0.16 * 3 + 0.34
    sigma_ref = 3.912 / 3.0 * (1550 / 550) ** (-q)
    sigma = atmosphere.kruse_extinction_per_km(1550.0, 3.0)
    assert sigma == pytest.approx(sigma_ref, rel=1e-4)
    assert sigma == pytest.approx(0.557, abs=0.001)
    assert atmosphere.transmittance(0.557, 3000.0, "paper") == pytest.approx(0.681, abs=5e-4)


def test_paper_and_physical_beer_lambert():
    # 1 km^-1 equals 4.343 dB/km: physical exp(-beta z) = paper 10^(-(4.343 beta) z/10)
    beta, z = 0.7, 2500.0
    phys = atmosphere.transmittance(beta, z, "physical")
    assert phys == pytest.approx(math.exp(-beta * 2.5), rel=1e-12)
    assert atmosphere.transmittance(beta * 10 / math.log(10), z, "paper") == pytest.approx(phys, rel=1e-12)


def test_zero_extinction_and_infinite_range():
    assert atmosphere.transmittance(0.0, np.inf, "paper") == 1.0
    assert atmosphere.transmittance(0.43, np.inf, "physical") == 0.0
    assert atmosphere.range_for_transmittance(0.0, 0.1) == np.inf


@given(st.floats(1e-3, 100.0), st.floats(1e-6, 0.999), st.sampled_from(["paper", "physical"]))
def test_range_for_transmittance_inverts_transmittance(k, tau, convention):
    r = atmosphere.range_for_transmittance(k, tau, convention)
    assert atmosphere.transmittance(k, r, convention) == pytest.approx(tau, rel=1e-9)


def test_far_ranges_stay_finite():
    r = np.logspace(0, np.log10(50_000), 50)  # 1 m to 50 km
    tau = atmosphere.transmittance(39.12, r, "physical")
    assert np.all(np.isfinite(tau)) and np.all((tau >= 0) & (tau <= 1))
    assert np.all(np.diff(tau) <= 0)


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: atmosphere.kruse_extinction_per_km(550, 0.0), "visibility_km"),
        (lambda: atmosphere.kruse_extinction_per_km(-1, 10), "wavelength_nm"),
        (lambda: atmosphere.transmittance(-0.1, 10), "extinction"),
        (lambda: atmosphere.transmittance(0.1, np.nan), "range_m"),
        (lambda: atmosphere.transmittance(0.1, 10, "exact"), "convention"),
    ],
)
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ParameterError, match=name):
        call()
