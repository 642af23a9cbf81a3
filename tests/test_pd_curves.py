"""Pd against range for a scenario's sensors (core.pd_curves), against closed forms of each budget.

References: the R^-4 (radar) and R^-2 (RF, acoustic) laws of the paper's equations, written out
here, with the physical convention's attenuation over the path; the detectors' own closed forms
at the deterministic range; the 4/3-Earth horizon; exact fusion of independent sensors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.core import detection, radar_detection
from csuas.core.horizon import K_RADIO, line_of_sight_limit_m
from csuas.core.pd_curves import (
    approach,
    fuse,
    fused_cumulative,
    margin_db,
    range_at_pd,
    sensor_pd,
)
from csuas.core.ranges import evaluate
from csuas.core.scenario import load_scenario, parse_scenario

R = np.geomspace(1.0, 3e5, 600)


def _one(modality, sensor=None, environment=None, convention="paper", target=None):
    return parse_scenario(
        {
            "convention": convention,
            "target": target or {"preset": "dji_mini_4_pro"},
            "environment": environment or {"preset": "clear_day"},
            "sensors": {"s": {"modality": modality, **(sensor or {})}},
        }
    )


@pytest.mark.parametrize("modality, exponent", [("radar", 4.0), ("rf", 2.0), ("acoustic", 2.0)])
def test_margin_follows_the_spreading_law_of_the_paper_convention(modality, exponent):
    sc = _one(modality)
    r_star = float(evaluate(sc)["s"].range_m)
    r = np.array([0.1, 0.5, 1.0, 2.0, 5.0]) * r_star
    np.testing.assert_allclose(
        margin_db(sc, sc.sensors["s"], "paper", r), 10 * exponent * np.log10(r_star / r), atol=2e-3
    )


def test_margin_includes_the_physical_two_way_rain_attenuation():
    sc = _one("radar", environment={"preset": "clear_day", "rain_rate_mm_h": 25.0}, convention="physical")
    result = evaluate(sc)["s"]
    r_star, gamma = float(result.range_m), float(result.term("gamma_rain_db_km").value)
    gas = float(result.term("gamma_gas_db_km").value)  # P.676 at 24 GHz, kept where 2 gamma R > 0.01 dB
    r = np.array([0.3, 1.0, 3.0]) * r_star
    gas_path = np.where(2 * gas * r / 1000.0 > 0.01, r, 0.0)
    expected = 40 * np.log10(r_star / r) - 2 * gamma * (r - r_star) / 1000.0 - 2 * gas * (gas_path - r_star) / 1000.0
    np.testing.assert_allclose(margin_db(sc, sc.sensors["s"], "physical", r), expected, atol=2e-3)


@pytest.mark.parametrize("integration", ["coherent", "noncoherent", "none"])
@pytest.mark.parametrize("swerling", [0, 1, 3])
def test_radar_pd_at_the_deterministic_range_is_the_pd_snr_min_implies(integration, swerling):
    sc = _one("radar", {"integration": integration, "swerling": swerling, "pfa": 1e-5})
    curve = sensor_pd(sc, "s", R)
    p = sc.sensors["s"].params
    n = p["n_pulses"] if integration != "none" else 1
    gain = {"coherent": n, "noncoherent": n ** (1 / n), "none": 1}[integration]  # paper convention, Eqs. 77-78
    implied = radar_detection.pd_exact(
        p["snr_min_db"] - 10 * math.log10(gain),
        1e-5,
        n,
        swerling,
        "coherent" if integration == "coherent" else "noncoherent",
    )
    assert curve.pd_at_deterministic_range == pytest.approx(float(implied), abs=1e-9)
    assert np.all(np.diff(curve.pd) <= 1e-12)  # Pd falls with range
    assert curve.pd[0] > 0.999 and curve.pd[-1] == pytest.approx(1e-5, rel=1e-6)


def test_energy_detector_sensors_at_their_threshold():
    sc = _one("acoustic", {"time_bandwidth": 16.0, "pfa": 1e-4})
    curve = sensor_pd(sc, "s", R)
    implied = detection.energy_detector_pd(sc.sensors["s"].params["snr_req_db"], 1e-4, 16.0)
    assert curve.pd_at_deterministic_range == pytest.approx(float(implied), abs=1e-9)
    sc = _one("rf", {"fading": "rayleigh", "snr_at_sensitivity_db": 13.0})
    curve = sensor_pd(sc, "s", R)
    assert curve.pd_at_deterministic_range == pytest.approx(
        float(detection.energy_detector_pd(13.0, 1e-6, 1.0, "rayleigh")), abs=1e-9
    )
    assert any("rayleigh" in a for a in curve.assumptions)


@pytest.mark.parametrize("p_desired", [0.3, 0.5, 0.8, 0.95])
def test_imaging_pd_at_the_johnson_range_follows_table_21(p_desired):
    """At the paper's R_TTPF(P) the TTPF gives P within Table 21's own agreement (0.021)."""
    for modality in ("eo", "tir"):
        sc = _one(modality, {"p_desired": p_desired})
        curve = sensor_pd(sc, "s", R)
        assert curve.pd_at_deterministic_range == pytest.approx(p_desired, abs=0.021)


def test_thermal_mrtd_model_meets_its_deterministic_range():
    """Resolvable cycles at the MRTD range equal lp n_TTPF: Pd there is the TTPF of n_TTPF."""
    for convention in ("paper", "physical"):
        sc = _one("tir", {"model": "mrtd", "p_desired": 0.8}, convention=convention)
        curve = sensor_pd(sc, "s", R)
        n_ttpf = sc.sensors["s"].params["n_ttpf"]
        assert curve.pd_at_deterministic_range == pytest.approx(float(detection.ttpf_probability(n_ttpf)), abs=1e-6)


def test_lidar_detectors():
    sc = _one("lidar", {"snr_at_threshold_db": 10.0})
    curve = sensor_pd(sc, "s", R)
    assert curve.pd_at_deterministic_range == pytest.approx(float(detection.lidar_pd_gaussian(10.0, 1e-6)), abs=1e-9)
    sc = _one("lidar", {"detector": "poisson", "photons_at_threshold": 8.0, "noise_photons": 0.5})
    curve = sensor_pd(sc, "s", R)
    assert curve.pd_at_deterministic_range == pytest.approx(float(detection.lidar_pd_poisson(8.0, 0.5, 1e-6)), abs=1e-9)


def test_horizon_ends_detection():
    sc = _one("rf", {"height_m": 10.0}, target={"preset": "dji_mini_4_pro", "altitude_m": 50.0})  # R* 125 km
    horizon = float(line_of_sight_limit_m(10.0, 60.0, K_RADIO))
    curve = sensor_pd(sc, "s", np.array([0.5 * horizon, 0.999 * horizon, 1.001 * horizon]))
    assert curve.pd[0] > 0.99 and curve.pd[2] == 0.0
    assert any("horizon" in a for a in curve.assumptions)


def test_every_embedded_scenario_gives_finite_monotone_curves():
    from csuas.core.scenario import embedded_scenarios

    for name in embedded_scenarios():
        sc = load_scenario(name)
        for sensor in sc.sensors:
            curve = sensor_pd(sc, sensor, R)
            assert np.all(np.isfinite(curve.pd)) and np.all((curve.pd >= 0) & (curve.pd <= 1))
            assert np.all(np.diff(curve.pd) <= 1e-12)


def test_range_at_pd_interpolates_and_says_never():
    r = np.array([10.0, 100.0, 1000.0])
    assert range_at_pd(r, np.array([1.0, 0.6, 0.4]), 0.5) == pytest.approx(10**2.5)
    assert range_at_pd(r, np.array([0.3, 0.2, 0.1]), 0.5) is None


def test_fusion_of_curves():
    sc = load_scenario("default")
    curves = [sensor_pd(sc, s, R) for s in sc.sensors]
    fused = fuse(curves, "or")
    assert np.all(fused >= np.max([c.pd for c in curves], axis=0) - 1e-15)
    all_six = fuse(curves, f"k-of-n:{len(curves)}")
    np.testing.assert_allclose(all_six, np.prod([c.pd for c in curves], axis=0), atol=1e-14)


def test_approach_of_a_steady_independent_sensor():
    """A radar far inside its range detects with Pd ~ 1 at the first look; the median is the start."""
    sc = _one("radar", {"p_tx_w": 1e5, "look_rate_hz": 2.0})
    result = approach(sc, "s", speed_m_s=20.0, start_range_m=200.0, stop_range_m=0.0)
    assert result["median_range_m"] == pytest.approx(200.0) and result["never"] < 1e-9
    fused = fused_cumulative([result], np.array([250.0, 200.0, 100.0]))
    assert fused[0] == 0.0 and fused[1] == pytest.approx(result["cumulative_pd"][0])
