"""Thermal IR: band radiometry (docs/validation.md), Eq. 26, MRTD curves and the MRTD range with attenuation."""

import math

import numpy as np
import pytest
from scipy import integrate

from csuas.base.errors import ParameterError
from csuas.core import radiometry, tir
from csuas.core.mrtd import LLOYD_K, ParametricMrtd, TabulatedMrtd, diffraction_mtf
from csuas.validation.core.paper_procedures import tir_step_reduction

H, C, KB = 6.62607015e-34, 299792458.0, 1.380649e-23


def _planck_quad(t, lo_um, hi_um):
    f = lambda lam: 2 * H * C**2 / lam**5 / math.expm1(H * C / (lam * KB * t))
    return integrate.quad(f, lo_um * 1e-6, hi_um * 1e-6, epsabs=0, epsrel=1e-12)[0]


@pytest.mark.parametrize(
    "t, band, ref",
    [(288.15, "mwir", 1.19403), (298.15, "mwir", 1.74415), (288.15, "lwir", 31.4780), (298.15, "lwir", 37.3463)],
)
def test_band_radiance_oracles(t, band, ref):
    value = radiometry.band_radiance(t, band)
    assert value == pytest.approx(ref, abs=1e-4)  # docs/validation.md, 6 digits
    lo, hi = radiometry.BANDS_UM[band]
    assert value == pytest.approx(_planck_quad(t, lo, hi), rel=1e-10)  # adaptive quadrature


def test_radiance_temperature_inverts_band_radiance():
    t = np.linspace(160.0, 900.0, 1001)
    for band in ("lwir", "mwir", (3.5, 4.2)):
        back = radiometry.radiance_temperature(radiometry.band_radiance(t, band), band)
        np.testing.assert_allclose(back, t, atol=2e-5)


@pytest.mark.parametrize("band, t_s, t_b, diff", [("lwir", 267.78, 283.11, 15.33), ("mwir", 278.60, 291.19, 12.59)])
def test_graybody_apparent_temperatures(band, t_s, t_b, diff):
    # docs/validation.md: e = 0.68 at 288.15 K and e = 0.77 at 298.15 K, no reflected surroundings
    a = radiometry.graybody_apparent_temperature(0.68, 288.15, band)
    b = radiometry.graybody_apparent_temperature(0.77, 298.15, band)
    assert (a, b) == (pytest.approx(t_s, abs=0.01), pytest.approx(t_b, abs=0.01))  # docs/validation.md: 2 decimals
    assert abs(float(tir.delta_t_radiometric(0.68, 288.15, 0.77, 298.15, band))) == pytest.approx(diff, abs=0.01)


@pytest.mark.parametrize("band, diff", [("lwir", 7.79), ("mwir", 7.96)])
def test_reflected_surroundings(band, diff):
    dt = tir.delta_t_radiometric(0.68, 288.15, 0.77, 298.15, band, surroundings_k=288.15)
    assert abs(float(dt)) == pytest.approx(diff, abs=0.01)


def test_linear_delta_t_eq_26():
    assert float(tir.delta_t_linear(0.68, 288.15, 0.77, 298.15)) == pytest.approx(-33.6335, abs=1e-4)


def test_blackbody_apparent_temperature_is_physical_temperature():
    assert radiometry.graybody_apparent_temperature(1.0, 300.0) == pytest.approx(300.0, abs=1e-5)


def test_radiance_out_of_table_is_an_error():
    with pytest.raises(ParameterError, match="radiance"):
        radiometry.radiance_temperature(1e-30)
    with pytest.raises(ParameterError, match="band"):
        radiometry.band_radiance(300.0, "swir")


def _mrtd():
    return ParametricMrtd(netd_k=0.05, ifov_rad=5e-4, f_number=1.0, pitch_m=10e-6, wavelength_m=10e-6)


def test_parametric_mrtd_formula_and_nyquist():
    m = _mrtd()
    f_n = 1.0 / (2 * 5e-4)
    assert m.nyquist_cy_rad == pytest.approx(f_n)
    f = 0.3 * f_n
    # MTF: circular-pupil diffraction at f/(D/lambda) times detector |sinc(f IFOV)|
    cutoff = (20e-3 / 1.0) / 10e-6  # D / lambda with D = focal / F, focal = pitch / IFOV
    mtf = diffraction_mtf(f / cutoff) * abs(math.sin(math.pi * f * 5e-4) / (math.pi * f * 5e-4))
    assert m(f) == pytest.approx(LLOYD_K * 0.05 * 0.3 / mtf, rel=1e-12)
    assert m(1.0001 * f_n) == np.inf
    freqs = np.linspace(1.0, f_n, 500)
    assert np.all(np.diff(m(freqs)) > 0)
    # inverse: MRTD(max_frequency(dT)) = dT below the Nyquist cap
    dt = np.array([0.002, 0.01, 0.05, 0.1])
    np.testing.assert_allclose(m(m.max_frequency(dt)), dt, rtol=1e-9)
    assert m.max_frequency(100.0) == pytest.approx(f_n)


def test_tabulated_mrtd_interpolates_log_linearly():
    t = TabulatedMrtd((0.1, 0.5, 1.0), (0.05, 0.2, 1.0))
    assert t(300.0) == pytest.approx(math.exp(0.5 * (math.log(0.05) + math.log(0.2))))
    assert t(1200.0) == np.inf
    assert t.max_frequency(0.1) == pytest.approx(300.0)
    assert t.max_frequency(0.01) == 0.0
    with pytest.raises(ParameterError, match="mrtd_k"):
        TabulatedMrtd((0.1, 0.5), (0.2, 0.1))
    with pytest.raises(ParameterError, match="mrtd_frequency"):
        TabulatedMrtd((0.5, 0.1), (0.1, 0.2))


def test_hot_target_mrtd_range_equals_johnson_at_nyquist():
    # With Delta T far above the MRTD, the Nyquist limit gives Eq. 29 = Eq. 23: d / (2 lp IFOV) = 101 m
    r = tir.tir_mrtd_range(
        mrtd=_mrtd(), d_crit_m=0.101, lp_task=1.0, n_ttpf=1.0, delta_t0_k=-33.63, extinction_db_km=0.0
    )
    assert float(r.range_m) == pytest.approx(0.101 / (2 * 5e-4), rel=1e-12)


@pytest.mark.parametrize("convention", ["paper", "physical"])
def test_attenuated_range_solves_the_balance(convention):
    m = _mrtd()
    dt0, sigma = np.array([-0.08, 0.3, -1.0]), np.array([5.0, 40.0, 400.0])
    kw = dict(t_bg_app_k=283.11, air_temperature_k=293.15) if convention == "physical" else {}
    r = tir.tir_mrtd_range(
        mrtd=m,
        d_crit_m=0.101,
        lp_task=1.0,
        n_ttpf=1.0,
        delta_t0_k=dt0,
        extinction_db_km=sigma,
        convention=convention,
        **kw,
    ).range_m
    assert np.all((r > 0) & (r < 101.0))
    dt_r = np.abs(tir.attenuated_delta_t(dt0, r, sigma, convention, **kw))
    np.testing.assert_allclose(dt_r, m(r / 0.101), rtol=1e-8)  # Eq. 27 at the predicted range


def test_exact_solve_agrees_with_paper_iteration():
    m = _mrtd()
    for dt0, sigma in [(0.1, 10.0), (0.5, 60.0), (2.0, 300.0)]:
        exact = float(
            tir.tir_mrtd_range(
                mrtd=m, d_crit_m=0.101, lp_task=1.0, n_ttpf=1.0, delta_t0_k=dt0, extinction_db_km=sigma
            ).range_m
        )
        # the paper's loop stops within one step below the exact range
        loop = tir_step_reduction(m, 0.101, 1.0, 1.0, dt0, sigma, step_m=0.1)
        assert exact - 0.1 <= loop <= exact + 1e-9


def test_paper_attenuation_reads_db_as_nepers():
    # Eq. 31 as printed: exp(-sigma z) with sigma in dB/km; physical: 10^(-sigma z / 10)
    assert tir.attenuated_delta_t(10.0, 1000.0, 0.2, "paper") == pytest.approx(10 * math.exp(-0.2))
    phys = tir.attenuated_delta_t(10.0, 1000.0, 0.2, "physical", t_bg_app_k=283.0, air_temperature_k=283.0)
    assert phys == pytest.approx(10 * 10 ** (-0.02), rel=0.02)  # radiance-linear to 2 % for 10 K


def test_zero_delta_t_is_never_detectable():
    r = tir.tir_mrtd_range(mrtd=_mrtd(), d_crit_m=0.101, lp_task=1.0, n_ttpf=1.0, delta_t0_k=0.0, extinction_db_km=0.2)
    assert float(r.range_m) == 0.0 and "never detectable" in str(r.reason)
