"""Acoustic range (Eqs. 32-49, 106-108), Table 31 and ISO 9613-1 absorption."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from csuas.base.errors import ParameterError
from csuas.core import acoustic
from csuas.core.solve import LN10


def test_wind_noise_table_31_interpolation():
    assert acoustic.wind_noise_db(6.7) == pytest.approx(79.25)  # Table 32
    np.testing.assert_allclose(
        acoustic.wind_noise_db(np.arange(1, 13)), [72, 72, 73, 74, 75, 77.5, 80, 82.5, 85, 87.5, 88.5, 89]
    )


def test_wind_outside_table_31():
    # Strong breeze (12.3 m/s) holds the last measured value; calm (0.3 m/s) adds no wind term
    assert acoustic.wind_noise_db(12.3) == 89.0
    assert acoustic.wind_noise_extrapolated(np.array([0.3, 6.7, 12.3])).tolist() == [True, False, True]
    calm = acoustic.acoustic_range(sl_db=70, snr_req_db=10, noise_level_db=30, g_array_db=0, wind_speed_m_s=0.3)
    assert "wind_noise_db" not in {t.name for t in calm.terms}
    assert float(calm.range_m) == pytest.approx(10**1.5)
    strong = acoustic.acoustic_range(sl_db=70, snr_req_db=10, noise_level_db=30, g_array_db=0, wind_speed_m_s=12.3)
    n_total = 10 * math.log10(10**3 + 10 ** ((89 - 20 * math.log10(50)) / 10))
    assert float(strong.range_m) == pytest.approx(10 ** ((60 - n_total) / 20), rel=1e-12)


def test_array_gain_eq_42():
    assert acoustic.array_gain_db(128) == pytest.approx(21.0721, abs=1e-4)
    assert acoustic.array_gain_db(128, 3.0) == pytest.approx(24.0721, abs=1e-4)


def test_default_loss_model_of_table_32():
    # SL 80, SNR 10, N_lvl 35, G 20, moderate breeze at 50 m (Eqs. 44, 46, 108)
    r = acoustic.acoustic_range(
        sl_db=80, snr_req_db=10, noise_level_db=35, g_array_db=20, wind_speed_m_s=6.7, wind_distance_m=50
    )
    n_total = 10 * math.log10(10**3.5 + 10 ** ((79.25 - 20 * math.log10(50)) / 10))
    assert float(r.range_m) == pytest.approx(10 ** ((80 - 10 - n_total + 20) / 20), rel=1e-12)


def test_silence_without_wind_is_an_explained_unbounded_range():
    r = acoustic.acoustic_range(sl_db=80, snr_req_db=10, noise_level_db=np.array([-np.inf, 35.0]), g_array_db=0)
    assert np.isinf(r.range_m[0]) and r.reason[0].startswith("unbounded")
    assert r.range_m[1] == pytest.approx(10 ** ((80 - 10 - 35) / 20), rel=1e-12) and r.reason[1] == ""


def test_minus_infinity_ambient_with_wind_is_finite():
    r = acoustic.acoustic_range(sl_db=80, snr_req_db=10, noise_level_db=-np.inf, g_array_db=0, wind_speed_m_s=6.7)
    assert float(r.range_m) == pytest.approx(10 ** ((70 - (79.25 - 20 * math.log10(50))) / 20), rel=1e-12)


# ISO 9613-2:1996 Table 2 (pure-tone attenuation, dB/km, at exact mid-band frequencies 63 Hz ... 8 kHz)
ISO_TABLE_2 = {
    (20.0, 70.0): [0.1, 0.3, 1.1, 2.8, 5.0, 9.0, 22.9, 76.6],
    (10.0, 70.0): [0.1, 0.4, 1.0, 1.9, 3.7, 9.7, 32.8, 117.0],
    (30.0, 70.0): [0.1, 0.3, 1.0, 3.1, 7.4, 12.7, 23.1, 59.3],
    (15.0, 20.0): [0.3, 0.6, 1.2, 2.7, 8.2, 28.2, 88.8, 202.0],
    (15.0, 50.0): [0.1, 0.5, 1.2, 2.2, 4.2, 10.8, 36.2, 129.0],
}


@pytest.mark.parametrize("t_c, rh", list(ISO_TABLE_2))
def test_iso_9613_absorption_against_published_table(t_c, rh):
    f = 1000.0 * 10 ** (np.array([-12, -9, -6, -3, 0, 3, 6, 9]) / 10)
    alpha = acoustic.iso9613_absorption_db_m(f, t_c + 273.15, rh) * 1000.0
    ref = np.array(ISO_TABLE_2[(t_c, rh)])
    tolerance = np.where(ref >= 100, 0.5, 0.05)  # half a unit of the printed digit
    assert np.all(np.abs(alpha - ref) <= tolerance), (alpha, ref)


def test_iso_9613_oracle_value():
    assert acoustic.iso9613_absorption_db_m(1000.0) * 1000 == pytest.approx(4.98, abs=0.005)  # docs/validation.md


@settings(deadline=None)  # the first example loads the parameter registry (its upper bounds), once
@given(st.floats(30, 120), st.floats(1e-5, 0.05))
def test_absorption_range_solves_the_budget(budget, alpha):
    r = float(
        acoustic.acoustic_range(
            sl_db=budget + 10, snr_req_db=10, noise_level_db=0.0, g_array_db=0, absorption_db_m=alpha
        ).range_m
    )
    assert 20 * math.log10(r) + alpha * r == pytest.approx(budget, abs=1e-7 * max(budget, 1))


def test_extreme_source_levels_stay_finite():
    r = acoustic.acoustic_range(
        sl_db=np.array([-50.0, 100.0, 200.0]), snr_req_db=10, noise_level_db=30, g_array_db=0, absorption_db_m=5e-3
    ).range_m  # the registry's extremes of sl_db (defaults/parameters.toml: -50 to 200 dB)
    assert np.all(np.isfinite(r)) and r[0] < 1e-3 and r[2] > r[1]
    assert 20 * math.log10(r[2]) + 5e-3 * r[2] == pytest.approx(200.0 - 40, rel=1e-12)


def test_log_linear_closed_form_constant():
    assert LN10 == pytest.approx(math.log(10))


def test_wind_beyond_table_31_is_flagged_in_the_term():
    gale = acoustic.acoustic_range(sl_db=80, snr_req_db=10, noise_level_db=35, g_array_db=20, wind_speed_m_s=50.0)
    breeze = acoustic.acoustic_range(sl_db=80, snr_req_db=10, noise_level_db=35, g_array_db=20, wind_speed_m_s=6.7)
    assert "beyond its 1-12 m/s" in gale.term("wind_noise_db").source
    assert float(gale.term("wind_noise_db").value) == 89.0  # Table 31's last row, held
    assert breeze.term("wind_noise_db").source == "Table 31"


def test_barrier_dz_against_iso9613_2_eq_14_by_hand():
    """D_z = 10 lg(3 + 20 z f / 340): 1 kHz, z 0.5 m -> 10 lg 32.412 = 15.107 dB; 250 Hz, z 0.1 m -> 6.504 dB."""
    assert acoustic.iso9613_barrier_db(1000.0, 0.5) == pytest.approx(10 * math.log10(3 + 20 / 0.34 * 0.5), abs=1e-12)
    assert acoustic.iso9613_barrier_db(1000.0, 0.5) == pytest.approx(15.107, abs=5e-4)
    assert acoustic.iso9613_barrier_db(250.0, 0.1) == pytest.approx(6.5035, abs=5e-4)
    # grazing edge (z = 0): 10 lg 3 = 4.771 dB; K_met scales z (Eq. 14)
    assert acoustic.iso9613_barrier_db(500.0, 0.0) == pytest.approx(4.7712, abs=5e-5)
    assert acoustic.iso9613_barrier_db(1000.0, 1.0, met_factor=0.5) == pytest.approx(15.107, abs=5e-4)


def test_barrier_capped_at_20_db_and_less_the_ground_effect():
    """Single diffraction caps D_z at 20 dB (Section 7.4); A_bar = D_z - A_gr, not below 0 (Eq. 12)."""
    # 4 kHz, z 5 m: 10 lg(3 + 20 x 5 / 0.085) = 30.72 dB uncapped
    assert acoustic.iso9613_barrier_db(4000.0, 5.0) == 20.0
    assert acoustic.iso9613_barrier_db(1000.0, 0.5, ground_db=3.0) == pytest.approx(12.107, abs=5e-4)
    assert acoustic.iso9613_barrier_db(1000.0, 0.5, ground_db=20.0) == 0.0
    with pytest.raises(ParameterError, match="path_difference_m"):
        acoustic.iso9613_barrier_db(1000.0, -0.1)


def test_barrier_c3_and_double_diffraction_against_iso9613_2_eq_15_by_hand():
    """C3 = (1 + (5 lambda/e)^2) / (1/3 + (5 lambda/e)^2): 1 kHz, e 1 m -> 3.89 / 3.2233 = 1.206825; cap 25 dB."""
    assert acoustic.iso9613_barrier_c3(1000.0, 1.0) == pytest.approx(3.89 / (1 / 3 + 2.89), abs=1e-12)
    assert acoustic.iso9613_barrier_c3(1000.0, 1.0) == pytest.approx(1.206825, abs=5e-7)
    assert acoustic.iso9613_barrier_c3(1000.0, 0.0) == 1.0  # one edge
    assert acoustic.iso9613_barrier_c3(1000.0, 1e6) == pytest.approx(3.0, abs=1e-9)  # edges far apart
    # D_z with e = 1 m at 1 kHz, z 0.5 m: 10 lg(3 + 20 / 0.34 x 1.206825 x 0.5) = 15.8540 dB
    assert acoustic.iso9613_barrier_db(1000.0, 0.5, edge_separation_m=1.0) == pytest.approx(
        10 * math.log10(3 + 20 / 0.34 * (3.89 / (1 / 3 + 2.89)) * 0.5), abs=1e-12
    )
    # double diffraction caps at 25 dB, single at 20 (Section 7.4)
    assert acoustic.iso9613_barrier_db(4000.0, 5.0, edge_separation_m=10.0) == 25.0
    assert acoustic.iso9613_barrier_db(4000.0, 5.0) == 20.0
    with pytest.raises(ParameterError, match="edge_separation_m"):
        acoustic.iso9613_barrier_db(1000.0, 0.5, edge_separation_m=-1.0)


def test_barrier_met_factor_eq_18_by_hand():
    """K_met = exp(-sqrt(d_ss d_sr d / 2z) / 2000): 100, 200, 290 m, z 10 m -> exp(-538.52 / 2000) = 0.763946."""
    assert acoustic.iso9613_barrier_met_factor(10.0, 100.0, 200.0, 290.0) == pytest.approx(0.763946, abs=5e-7)
    assert acoustic.iso9613_barrier_met_factor(0.0, 100.0, 200.0, 290.0) == 1.0
