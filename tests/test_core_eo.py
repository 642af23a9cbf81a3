"""EO range: Johnson/TTPF (Eqs. 15-18) limited by contrast (Eq. 21)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from csuas.base.errors import ParameterError
from csuas.core import eo, johnson


def test_johnson_default_is_555_5_m():
    # Section 4.9.1: d_crit 0.101 m, N_H 1920, HFOV 10 deg, lp 1, n_TTPF 1 -> 555.5 m
    r = johnson.johnson_range_m(0.101, johnson.ifov_rad(10.0, 1920), 1.0, 1.0)
    assert r == pytest.approx(0.101 / 2 * 1920 / math.radians(10.0), rel=1e-12)
    assert round(float(r), 1) == 555.5


@pytest.mark.parametrize(
    "p, n",
    list(zip([1.00, 0.95, 0.80, 0.50, 0.30, 0.10, 0.02, 0.00], [3.00, 2.00, 1.50, 1.00, 0.75, 0.50, 0.25, 0.00])),
)
def test_ttpf_table_21(p, n):
    assert johnson.n_ttpf(p) == pytest.approx(n)


def test_ttpf_interpolation_is_monotone():
    p = np.linspace(0, 1, 1001)
    assert np.all(np.diff(johnson.n_ttpf(p)) >= 0)


def test_line_pairs_table_20():
    assert [johnson.line_pairs(t) for t in ("detection", "recognition", "identification")] == [1, 4, 8]
    with pytest.raises(ParameterError, match="task"):
        johnson.line_pairs("classification")


def test_tir_ifov_from_pitch():
    # Eq. 22: 10 um / 20 mm = 0.5 mrad
    assert johnson.ifov_from_pitch_rad(10.0, 20.0) == pytest.approx(5e-4)


def test_n_ttpf_zero_is_unbounded_not_nan():
    r = johnson.johnson_range_m([0.101, 0.0], 1e-4, 1.0, 0.0)
    assert r[0] == np.inf and r[1] == 0.0


@given(st.floats(0.01, 1.0), st.floats(0.5, 60.0), st.integers(100, 8000), st.floats(1.1, 4.0))
def test_johnson_scaling_with_pixels_and_fov(d, hfov, n_h, k):
    # R is proportional to N_H / HFOV (Eq. 17) and to d_crit
    base = johnson.johnson_range_m(d, johnson.ifov_rad(hfov, n_h))
    assert johnson.johnson_range_m(d, johnson.ifov_rad(hfov, n_h * k)) == pytest.approx(k * base, rel=1e-9)
    assert johnson.johnson_range_m(d, johnson.ifov_rad(hfov / k, n_h)) == pytest.approx(k * base, rel=1e-9)
    assert johnson.johnson_range_m(k * d, johnson.ifov_rad(hfov, n_h)) == pytest.approx(k * base, rel=1e-9)


def _eo(**kw):
    args = dict(
        d_crit_m=0.101,
        hfov_deg=10.0,
        n_h=1920,
        lp_task=1.0,
        n_ttpf=1.0,
        c_eo=0.5,
        c_min=0.05,
        wavelength_nm=550.0,
        visibility_km=10.0,
        convention="paper",
    )
    args.update(kw)
    return eo.eo_range(**args)


def test_contrast_limit_closed_forms():
    # paper: C0 10^(-sigma R/10) = c_min -> R = 10 log10(C0/c_min)/sigma km (sigma read as dB/km)
    sigma = 3.912 / 0.4
    assert eo.contrast_limited_range_m(0.5, 0.05, sigma, "paper") == pytest.approx(10.0 / sigma * 1000.0, rel=1e-12)
    # physical: C0 exp(-beta R) = c_min -> R = ln(C0/c_min)/beta km
    assert eo.contrast_limited_range_m(0.5, 0.05, sigma, "physical") == pytest.approx(
        math.log(10.0) / sigma * 1000.0, rel=1e-12
    )


def test_clear_day_is_resolution_limited_and_fog_contrast_limited():
    clear = _eo()
    assert float(clear.range_m) == pytest.approx(555.54, abs=0.01)
    assert str(clear.reason) == "resolution-limited (Eq. 18)"
    fog = _eo(visibility_km=0.1, convention="physical")
    sigma = -math.log(0.02) / 0.1  # Kruse at q = 0 (V < 0.5 km)
    assert float(fog.range_m) == pytest.approx(math.log(10.0) / sigma * 1000.0, rel=1e-9)
    assert str(fog.reason) == "contrast-limited (Eq. 21)"
    # the attenuated contrast at the predicted range equals c_min exactly
    assert 0.5 * math.exp(-sigma * float(fog.range_m) / 1000.0) == pytest.approx(0.05, rel=1e-9)


@pytest.mark.parametrize("c0", [0.05, 0.049, 0.0, -0.04])
def test_contrast_at_or_below_c_min_is_never_detectable(c0):
    r = _eo(c_eo=c0)
    assert float(r.range_m) == 0.0
    assert "never detectable" in str(r.reason)


def test_negative_contrast_uses_its_magnitude():
    assert float(_eo(c_eo=-0.5, visibility_km=0.2).range_m) == float(_eo(c_eo=0.5, visibility_km=0.2).range_m)


@pytest.mark.parametrize("v_km", [0.5, 1.0, 6.0, 50.0])
def test_every_kruse_breakpoint_gives_finite_ranges(v_km):
    r = _eo(visibility_km=np.array([v_km * (1 - 1e-9), v_km, v_km * (1 + 1e-9)]), wavelength_nm=850.0)
    assert np.all(np.isfinite(r.range_m)) and np.all(r.range_m > 0)


def test_broadcasting_over_a_sweep():
    r = _eo(visibility_km=np.logspace(-1, 2, 7)[:, None], d_crit_m=np.array([0.05, 0.1, 0.3]))
    assert r.range_m.shape == (7, 3)
    assert np.all(np.diff(r.range_m, axis=0) >= 0)  # clearer air never shortens the range


def test_bad_contrast_threshold():
    with pytest.raises(ParameterError, match="c_min"):
        _eo(c_min=0.0)
