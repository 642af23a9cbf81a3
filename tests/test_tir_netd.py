"""NETD-limited thermal detection (core.tir.tir_netd_range; core.detection.target_pixels and blob_snr; core.detection's
Gaussian threshold), against closed forms written here and the standard normal's published quantiles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core.detection import blob_snr, gaussian_pd, gaussian_required_snr, target_pixels
from csuas.core.tir import tir_netd_range


def test_gaussian_threshold_matches_the_normal_quantiles():
    # Q^-1(1e-6) = 4.753424 (Abramowitz & Stegun Table 26.5); Pd = 0.5 where the amplitude equals it
    assert gaussian_required_snr(0.5, 1e-6) == pytest.approx(4.753424, abs=1e-6)
    assert gaussian_pd(4.753424, 1e-6) == pytest.approx(0.5, abs=1e-6)
    # Q^-1(0.1) = 1.281552: Pd 0.9 needs 4.753424 + 1.281552
    assert gaussian_required_snr(0.9, 1e-6) == pytest.approx(6.034976, abs=1e-6)
    assert gaussian_pd(gaussian_required_snr(0.9, 1e-6), 1e-6) == pytest.approx(0.9, abs=1e-12)
    assert gaussian_pd(0.0, 1e-3) == pytest.approx(1e-3)  # no signal: the false-alarm rate
    with pytest.raises(ParameterError, match="amplitude_snr"):
        gaussian_pd(-1.0, 1e-6)


def test_pixels_and_blob_snr_in_both_regimes():
    # 0.06 m^2 at 0.5 mrad: 240 m gives 0.06 / 0.12^2 = 4.1667 px
    assert target_pixels(0.06, 0.5e-3, 240.0) == pytest.approx(0.06 / 0.12**2)
    assert np.isinf(target_pixels(0.06, 0.5e-3, 0.0))
    assert blob_snr(2.0, 0.05, 4.0) == pytest.approx(2.0 * 2.0 / 0.05)  # sqrt(4) pixels
    assert blob_snr(-2.0, 0.05, 0.25) == pytest.approx(2.0 * 0.25 / 0.05)  # a quarter pixel: diluted
    assert blob_snr(1.0, 0.1, 1.0 - 1e-12) == pytest.approx(blob_snr(1.0, 0.1, 1.0 + 1e-12))  # continuous


def test_unattenuated_range_has_the_closed_form_of_each_regime():
    # resolved: a 1 m^2 target, 1 K, 50 mK NETD, 1 mrad, SNR 5: R = 1 * 1 / (0.05 * 1e-3 * 5) = 4000 m,
    # where it covers 1 / 4^2 = 0.0625 px -- not resolved, so the sub-pixel form applies:
    # R = sqrt(1 * 1 / (0.05 * 5)) / 1e-3 = 2000 m (0.25 px, SNR = 1 * 0.25 / 0.05 = 5)
    r = tir_netd_range(
        projected_area_m2=1.0, ifov_rad_=1e-3, netd_mk=50.0, required_snr=5.0, delta_t0_k=1.0, extinction_db_km=0.0
    )
    assert float(r.range_m) == pytest.approx(2000.0, rel=1e-12)
    # a hot large target: 100 K, 100 m^2, 10 mrad, SNR 5: resolved form 100 * 10 / (0.05 * 0.01 * 5) = 4e5 m covers
    # 100 / 4000^2 px: sub-pixel again; at 1 mrad IFOV and 0.01 K: R = 0.01 * 10 / (0.05 * 1e-3 * 5) = 400 m
    # covers 100 / 0.4^2 = 625 px -- resolved, and SNR there = 0.01 * 25 / 0.05 = 5
    r = tir_netd_range(
        projected_area_m2=100.0, ifov_rad_=1e-3, netd_mk=50.0, required_snr=5.0, delta_t0_k=-0.01, extinction_db_km=0.0
    )
    assert float(r.range_m) == pytest.approx(400.0, rel=1e-12)


def test_attenuated_range_is_where_the_blob_snr_meets_the_requirement():
    sigma, dt0, area, ifov, netd, snr = 0.7, -33.6, 0.06, 0.5e-3, 50.0, 4.753424
    r = float(
        tir_netd_range(
            projected_area_m2=area,
            ifov_rad_=ifov,
            netd_mk=netd,
            required_snr=snr,
            delta_t0_k=dt0,
            extinction_db_km=sigma,
        ).range_m
    )
    # paper convention: Delta T(R) = Delta T0 exp(-sigma R[km]) (Eq. 31 as printed); sub-pixel at these ranges
    dt = abs(dt0) * math.exp(-sigma * r / 1000.0)
    pixels = area / (ifov * r) ** 2
    assert pixels < 1.0
    assert dt * pixels / (netd / 1000.0) == pytest.approx(snr, rel=1e-9)


def test_no_contrast_or_area_is_never_detectable_and_bad_noise_is_refused():
    r = tir_netd_range(
        projected_area_m2=0.06, ifov_rad_=0.5e-3, netd_mk=50.0, required_snr=5.0, delta_t0_k=0.0, extinction_db_km=0.2
    )
    assert float(r.range_m) == 0.0 and "never" in str(r.reason)
    with pytest.raises(ParameterError, match="netd_mk"):
        tir_netd_range(
            projected_area_m2=0.06, ifov_rad_=0.5e-3, netd_mk=0.0, required_snr=5.0, delta_t0_k=1.0, extinction_db_km=0
        )


def test_pd_at_the_netd_range_is_p_desired(tmp_path):
    from csuas.core.pd_curves import sensor_pd
    from csuas.core.scenario import load_scenario

    path = tmp_path / "s.toml"
    path.write_text(
        'name = "n"\n[target]\n[environment]\n[sensors.tir]\nmodality = "tir"\nmodel = "netd"\np_desired = 0.9\n'
    )
    curve = sensor_pd(load_scenario(path), "tir", [100.0, 1000.0])
    assert curve.pd_at_deterministic_range == pytest.approx(0.9, abs=1e-9)
    assert curve.pd[0] > 0.999 and "NETD" in " ".join(curve.assumptions)
