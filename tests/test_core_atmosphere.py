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


@pytest.mark.parametrize("wavelength_nm", [400.0, 550.0, 850.0, 1550.0])
@pytest.mark.parametrize("breakpoint_km", [0.5, 1.0, 6.0, 50.0])
def test_physical_extinction_is_continuous_at_every_kim_breakpoint(wavelength_nm, breakpoint_km):
    below, above = atmosphere.extinction_per_km(
        wavelength_nm, np.array([breakpoint_km, breakpoint_km * (1 + 1e-9)]), "physical"
    )
    assert abs(above - below) / below < 1e-6


@pytest.mark.parametrize("visibility_km", [0.1, 2.0, 10.0, 100.0, 300.0])
def test_physical_extinction_at_550_nm_is_koschmieder(visibility_km):
    assert atmosphere.extinction_per_km(550.0, visibility_km, "physical") == pytest.approx(
        3.912 / visibility_km, rel=1e-3
    )


def test_physical_extinction_adds_rayleigh_scattering_below_550_nm():
    """At 100 km: 0.0116/km molecular (Bucholtz 1995) x (400/550)^-4.05, the rest aerosol x (400/550)^-1.3."""
    molecular, total = 0.0116, -math.log(0.02) / 100.0
    expected = molecular * (400 / 550) ** -4.05 + (total - molecular) * (400 / 550) ** -1.3
    assert atmosphere.extinction_per_km(400.0, 100.0, "physical") == pytest.approx(expected, rel=1e-12)


def test_the_paper_convention_keeps_kims_step_at_50_km():
    """Issue reproduction: the EO contrast range at 400 nm drops from 84.5 to 76.8 km as V passes 50 km."""
    from csuas.core import eo

    def contrast_range_km(v, q):  # paper: C0 10^(-sigma R / 10) = c_min, sigma = 3.912/V (400/550)^-q
        return 10.0 * math.log10(0.5 / 0.05) / (-math.log(0.02) / v * (400 / 550) ** -q)

    ranges = [
        float(
            eo.eo_range(
                d_crit_m=0.101,
                hfov_deg=0.001,
                n_h=1920,
                lp_task=1.0,
                n_ttpf=1.0,
                c_eo=0.5,
                c_min=0.05,
                wavelength_nm=400.0,
                visibility_km=v,
                convention="paper",
            ).range_m
        )
        for v in (50.0, 50.01)
    ]
    assert ranges[0] / 1000 == pytest.approx(contrast_range_km(50.0, 1.3), rel=1e-9)
    assert ranges[1] / 1000 == pytest.approx(contrast_range_km(50.01, 1.6), rel=1e-9)
    assert round(ranges[0] / 1000, 1) == 84.5 and round(ranges[1] / 1000, 1) == 76.8
    term = eo.eo_range(
        d_crit_m=0.101,
        hfov_deg=10.0,
        n_h=1920,
        lp_task=1.0,
        n_ttpf=1.0,
        c_eo=0.5,
        c_min=0.05,
        wavelength_nm=400.0,
        visibility_km=50.0,
    ).term("kruse_extinction")
    assert "steps from 1.3 to 1.6 at 50 km" in term.source


def test_db_transmittance_is_the_decibel_beer_lambert_law():
    np.testing.assert_allclose(
        atmosphere.db_transmittance([0.0, 1.0, 3.0], 1000.0), [1.0, 10**-0.1, 10**-0.3], rtol=1e-15
    )
    assert atmosphere.db_transmittance(0.0, np.inf) == 1.0
    with pytest.raises(ParameterError, match="attenuation_db_km"):
        atmosphere.db_transmittance(-1.0, 10.0)


def _fog_length_by_geometry(h_s, h_t, top, n=200_001):
    """Length fraction of a straight path from h_s to h_t below ``top``, by counting midpoints (exact geometry)."""
    s = (np.arange(n) + 0.5) / n
    return float(np.mean(h_s + (h_t - h_s) * s < top))


@pytest.mark.parametrize(
    "h_s, h_t, top, expected",
    [
        (2.0, 30.0, 50.0, 1.0),  # fully inside the fog
        (2.0, 102.0, 50.0, 0.48),  # crossing the top: (50 - 2) / (102 - 2)
        (120.0, 10.0, 50.0, 40.0 / 110.0),  # descending path, the same rule
        (60.0, 100.0, 50.0, 0.0),  # fully above: T = 1
        (20.0, 20.0, 50.0, 1.0),  # level path in the fog
        (80.0, 80.0, 50.0, 0.0),  # level path above it
    ],
)
def test_layered_fog_path_fraction_is_the_closed_form(h_s, h_t, top, expected):
    """L_fog / R of a straight slant path through a fog of top h_top; T = exp(-beta L_fog) (Beer-Lambert)."""
    fraction = float(atmosphere.fog_path_fraction(h_s, h_t, top))
    assert fraction == pytest.approx(expected, abs=1e-12)
    if h_s != h_t:
        assert fraction == pytest.approx(_fog_length_by_geometry(h_s, h_t, top), abs=1e-5)
    beta, r_m = 19.56, 300.0  # 200 m fog visibility, Koschmieder [1/km]
    tau = atmosphere.transmittance(beta * fraction, r_m)
    assert tau == pytest.approx(math.exp(-beta * expected * r_m / 1000.0), rel=1e-12)
    if expected == 0.0:
        assert tau == 1.0


def test_layered_fog_top_must_not_be_negative():
    with pytest.raises(ParameterError, match="fog_top_m"):
        atmosphere.fog_path_fraction(2.0, 30.0, -1.0)
