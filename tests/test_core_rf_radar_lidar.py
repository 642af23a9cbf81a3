"""RF Friis (Eqs. 50-61), radar (Eqs. 62-86) and lidar (Eqs. 87-104)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from csuas.base.errors import ParameterError
from csuas.core import itu, lidar, radar, rf
from csuas.core.units import C_LIGHT, db_to_linear, wavelength_m


def _rf(**kw):
    args = dict(p_tx_w=0.1, g_tx_dbi=8.0, g_rx_db=14.0, frequency_ghz=2.4, s_rx_dbm=-100.0)
    args.update(kw)
    return rf.rf_range(**args)


def test_friis_range_eq_57():
    lam = C_LIGHT / 2.4e9
    expected = lam / (4 * math.pi) * 10 ** ((20.0 + 8 + 14 + 100) / 20)
    assert float(_rf().range_m) == pytest.approx(expected, rel=1e-12)
    # received power at that range equals the sensitivity (Eq. 56 margin = 0)
    p = rf.received_power_dbm(0.1, 8.0, 14.0, 2.4, float(_rf().range_m))
    assert p == pytest.approx(-100.0, abs=1e-9)


def test_fspl_closed_form():
    assert rf.free_space_path_loss_db(2.4, 1000.0) == pytest.approx(
        20 * math.log10(4 * math.pi * 1000 * 2.4e9 / C_LIGHT)
    )


def test_paper_rf_losses_over_a_fixed_kilometre():
    r = _rf(rain_rate_mm_h=6.0, lwc_g_m3=0.2)
    loss = float(itu.rain_specific_attenuation_db_km(2.4, 6.0) + itu.fog_specific_attenuation_db_km(2.4, 0.2))
    assert float(r.range_m) == pytest.approx(float(_rf().range_m) * 10 ** (-loss / 20), rel=1e-12)
    assert r.term("rain_loss_db").value == pytest.approx(8.17e-4, rel=0.01)  # Table 37


def test_physical_rf_losses_over_the_range():
    r = float(_rf(rain_rate_mm_h=30.0, frequency_ghz=5.8, convention="physical").range_m)
    gamma = float(itu.rain_specific_attenuation_db_km(5.8, 30.0))
    budget = 20 + 8 + 14 + 100
    assert rf.free_space_path_loss_db(5.8, r) + gamma * r / 1000 == pytest.approx(budget, abs=1e-8)


def test_no_weather_means_no_weather_terms():
    names = {t.name for t in _rf().terms}
    assert not names & {"gamma_rain_db_km", "gamma_fog_db_km", "rain_loss_db", "fog_loss_db", "weather_loss_db"}


@pytest.mark.parametrize("p", [0.0, -1.0])
def test_zero_or_negative_power_is_an_error(p):
    with pytest.raises(ParameterError, match="rf_power_w"):
        _rf(p_tx_w=p)
    with pytest.raises(ParameterError, match="p_tx_w"):
        radar.radar_range(p_tx_w=p, g_tx_db=25, g_rx_db=25, wavelength_m=0.0125, sigma_m2=0.01)


def test_radar_equation_received_power_eq_68():
    p = radar.received_power_w(10.0, 25.0, 25.0, 0.0125, 0.01, 500.0)
    expected = 10 * 10**2.5 * 10**2.5 * 0.0125**2 * 0.01 / ((4 * math.pi) ** 3 * 500.0**4)
    assert p == pytest.approx(expected, rel=1e-12)


def test_range_equation_model_inverts_eq_68():
    r = radar.radar_range(
        p_tx_w=10, g_tx_db=25, g_rx_db=25, wavelength_m=0.0125, sigma_m2=0.01, model="range_equation", p_rx_min_w=1e-13
    )
    assert radar.received_power_w(10, 25, 25, 0.0125, 0.01, float(r.range_m)) == pytest.approx(1e-13, rel=1e-12)


def test_snr_model_eq_75_and_integration():
    kw = dict(
        p_tx_w=10,
        g_tx_db=25,
        g_rx_db=25,
        wavelength_m=0.0125,
        sigma_m2=0.01,
        snr_min_db=10,
        t0_k=290,
        noise_figure_db=10,
        bandwidth_mhz=200,
        k_b=1.38e-23,
    )
    single = float(radar.radar_range(**kw).range_m)
    noise = 1.38e-23 * 290 * 10 * 200e6
    expected = (10 * 10**5 * 0.0125**2 * 0.01 / ((4 * math.pi) ** 3 * 10 * noise)) ** 0.25
    assert single == pytest.approx(expected, rel=1e-12)
    coh = float(radar.radar_range(**kw, n_pulses=10, integration="coherent").range_m)
    assert coh == pytest.approx(single * 10**0.25, rel=1e-12)  # Eq. 80
    nc_paper = float(radar.radar_range(**kw, n_pulses=10, integration="noncoherent").range_m)
    assert nc_paper == pytest.approx(single * (10 ** (1 / 10)) ** 0.25, rel=1e-12)  # Eq. 82 as printed
    nc_phys = float(radar.radar_range(**kw, n_pulses=10, integration="noncoherent", convention="physical").range_m)
    assert nc_phys == pytest.approx(single * math.sqrt(10) ** 0.25, rel=1e-12)


def test_eq_85_total_loss():
    # from the paper's rounded gammas: 13 + 3 x 0.183 + 3 x 0.0154 = 13.595 dB
    assert radar.total_loss_db(10, 3, 0.183, 0.0154, 3, 3) == pytest.approx(13.595, abs=5e-4)
    g_rain = itu.rain_specific_attenuation_db_km(12.0, 6.0)
    g_fog = itu.fog_specific_attenuation_db_km(12.0, 0.2)
    assert radar.total_loss_db(10, 3, g_rain, g_fog, 3, 3) == pytest.approx(13.595, abs=1e-3)
    assert g_rain + g_fog == pytest.approx(0.198, abs=1e-3)  # Table 44 L_propagation


def test_loss_budget_scales_range_by_l_over_40():
    kw = dict(p_tx_w=10, g_tx_db=25, g_rx_db=25, wavelength_m=0.0125, sigma_m2=0.01)
    base = float(radar.radar_range(**kw).range_m)
    lossy = radar.radar_range(**kw, l_hardware_db=10, l_processing_db=3, rain_rate_mm_h=6, lwc_g_m3=0.2)
    total = lossy.term("l_total_db").value
    assert float(lossy.range_m) == pytest.approx(base * 10 ** (-total / 40), rel=1e-12)  # Eq. 86
    assert total == pytest.approx(13.1985, abs=1e-3)


def test_physical_radar_losses_at_own_frequency_two_way():
    kw = dict(
        p_tx_w=10,
        g_tx_db=25,
        g_rx_db=25,
        wavelength_m=C_LIGHT / 35e9,
        sigma_m2=0.01,
        rain_rate_mm_h=30.0,
        convention="physical",
        model="range_equation",
        p_rx_min_w=1e-15,
    )
    r = float(radar.radar_range(**kw).range_m)
    gamma = float(itu.rain_specific_attenuation_db_km(35.0, 30.0))
    p = radar.received_power_w(10, 25, 25, C_LIGHT / 35e9, 0.01, r) * 10 ** (-2 * gamma * r / 1000 / 10)
    assert p == pytest.approx(1e-15, rel=1e-9)


@settings(max_examples=50)
@given(st.floats(0.01, 1e4), st.floats(1e-4, 10.0), st.floats(1.5, 16.0))
def test_radar_fourth_root_scaling(p_tx, sigma, k):
    kw = dict(g_tx_db=25, g_rx_db=25, wavelength_m=0.0125, l_hardware_db=10, l_processing_db=3)
    base = float(radar.radar_range(p_tx_w=p_tx, sigma_m2=sigma, **kw).range_m)
    assert float(radar.radar_range(p_tx_w=k * p_tx, sigma_m2=sigma, **kw).range_m) == pytest.approx(
        base * k**0.25, rel=1e-10
    )
    assert float(radar.radar_range(p_tx_w=p_tx, sigma_m2=k * sigma, **kw).range_m) == pytest.approx(
        base * k**0.25, rel=1e-10
    )


def test_extreme_db_values_do_not_overflow():
    r = radar.radar_range(
        p_tx_w=10,
        g_tx_db=np.array([-50.0, 80.0]),
        g_rx_db=80.0,
        wavelength_m=0.0125,
        sigma_m2=1e6,
        l_hardware_db=0.0,
        l_processing_db=0.0,
        rain_rate_mm_h=30.0,
        convention="physical",
    ).range_m
    assert np.all(np.isfinite(r)) and r[1] > r[0] > 0


def test_lidar_eq_99_and_104():
    d, lam = 3e-3, 1550e-9
    r99 = (1 / 1e-10 * 0.006 / (1.22**2 * math.pi) * d**4 / lam**2) ** 0.25
    assert lidar.lidar_range_no_loss_m(1.0, 1e-10, 0.006, 3.0, 1550.0) == pytest.approx(r99, rel=1e-12)
    # Eq. 98 at the Eq. 99 range equals the minimum power
    assert lidar.received_power_w(1.0, 0.006, 3.0, 1550.0, r99) == pytest.approx(1e-10, rel=1e-12)
    r = lidar.lidar_range(
        p_tx_w=1, p_rx_min_w=1e-10, sigma_lidar_m2=0.006, aperture_mm=3, wavelength_nm=1550, eta_sys=0.5, eta_tl=0.681
    )
    assert float(r.range_m) == pytest.approx(r99 * (0.681**2 * 0.5) ** 0.25, rel=1e-12)  # Eq. 104
    assert float(r.range_m) == pytest.approx(r99 * math.sqrt(0.681) * 0.5**0.25, rel=1e-12)  # Eqs. 101, 103


def test_physical_lidar_bounds_the_interaction_by_the_target_area():
    kw = dict(p_tx_w=1, p_rx_min_w=1e-10, sigma_lidar_m2=0.006, aperture_mm=3, wavelength_nm=1550, eta_sys=0.5)
    r = float(lidar.lidar_range(**kw, projected_area_m2=0.06, convention="physical").range_m)
    # at this range the 0.63 mrad beam is smaller than the target: P = P_tx (sigma/A_p) d^2/(4 R^2) eta
    assert r == pytest.approx(math.sqrt(1 * (0.006 / 0.06) * 3e-3**2 / 4 * 0.5 / 1e-10), rel=1e-9)
    unbounded = float(lidar.lidar_range(**kw, convention="physical").range_m)
    assert unbounded == pytest.approx(lidar.lidar_range_no_loss_m(1, 1e-10, 0.006, 3, 1550) * 0.5**0.25, rel=1e-9)


def test_physical_lidar_with_fog_balances_the_budget():
    kw = dict(p_tx_w=1, p_rx_min_w=1e-10, sigma_lidar_m2=0.006, aperture_mm=3, wavelength_nm=1550, eta_sys=0.5)
    r = float(lidar.lidar_range(**kw, visibility_km=0.2, convention="physical").range_m)
    beta = -math.log(0.02) / 0.2
    p = lidar.received_power_w(1, 0.006, 3, 1550, r, None, math.exp(-2 * beta * r / 1000), 0.5)
    assert p == pytest.approx(1e-10, rel=1e-8)


def test_wavelength_conversion():
    assert wavelength_m(24.0) == pytest.approx(0.012491, abs=1e-6)
    assert db_to_linear(-np.inf) == 0.0
