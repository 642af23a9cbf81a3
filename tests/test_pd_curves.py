"""Pd against range for a scenario's sensors (core.pd_curves), against closed forms of each budget.

References: the R^-4 (radar) and R^-2 (RF, acoustic) laws of the paper's equations, written out
here, with the physical convention's attenuation over the path; the detectors' own closed forms
at the deterministic range; the 4/3-Earth horizon; exact fusion of independent sensors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core import detection, radar_detection
from csuas.core.horizon import K_RADIO, line_of_sight_limit_m
from csuas.core.pd_curves import (
    acoustic_pd_with_loss,
    approach,
    fuse,
    fused_cumulative,
    fused_first_detection_m,
    fused_pd_of_range,
    margin_db,
    range_at_pd,
    sensor_pd,
)
from csuas.core.ranges import evaluate
from csuas.core.scenario import load_scenario, parse_scenario

R = np.geomspace(1.0, 3e5, 600)
#: The 4/3-Earth radio horizon of a 2 m sensor and a 120 m target, sqrt(2 k a h1) + sqrt(2 k a h2) [m].
RADIO_HORIZON_2_120_M = math.sqrt(2 * 4 / 3 * 6_371_000.0 * 2.0) + math.sqrt(2 * 4 / 3 * 6_371_000.0 * 120.0)


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
    inside = R <= RADIO_HORIZON_2_120_M
    assert curve.pd[0] > 0.999 and curve.pd[inside][-1] == pytest.approx(1e-5, rel=1e-6)
    assert np.all(curve.pd[~inside] == 0.0)  # beyond the reference horizon (no height given)


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


def test_acoustic_pd_with_a_loss_is_the_energy_detector_at_the_r2_margin_less_the_loss():
    """Paper convention (R^-2): Pd(R, L) = Pd_energy(snr_req + 20 lg(R* / R) - L); L = 0 is the free-field curve."""
    sc = _one("acoustic", {"time_bandwidth": 16.0, "pfa": 1e-4})
    r_star = float(evaluate(sc)["s"].range_m)
    r = np.array([0.2, 0.5, 1.0, 1.5]) * r_star
    loss = np.array([0.0, 6.0, 4.771, 12.5])
    snr = sc.sensors["s"].params["snr_req_db"] + 20 * np.log10(r_star / r) - loss
    expected = detection.energy_detector_pd(snr, 1e-4, 16.0)
    np.testing.assert_allclose(acoustic_pd_with_loss(sc, "s", r, loss), expected, atol=1e-3)
    assert acoustic_pd_with_loss(sc, "s", r[:1], 0.0) == pytest.approx(sensor_pd(sc, "s", r[:1]).pd, abs=1e-12)
    with pytest.raises(ParameterError, match="sensor"):
        acoustic_pd_with_loss(_one("rf"), "s", r, loss)


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


def test_range_at_pd_is_solved_on_the_model_between_two_search_points():
    """Pd = exp(-(R/100)^2): R(P) = 100 sqrt(-ln P) exactly, with only the ends of the search given."""
    gaussian = lambda r: np.exp(-((np.asarray(r) / 100.0) ** 2))
    r50, r90, never = range_at_pd(gaussian, [1.0, 1000.0], (0.5, 0.9, 0.9999999))
    assert r50 == pytest.approx(100.0 * math.sqrt(math.log(2.0)), rel=1e-9)
    assert r90 == pytest.approx(100.0 * math.sqrt(-math.log(0.9)), rel=1e-9)
    assert never is None  # above Pd at every search point
    step = lambda r: np.where(np.asarray(r) < 437.0, 1.0, 0.0)  # a horizon: the jump is the range
    assert range_at_pd(step, [1.0, 1000.0], (0.5,))[0] == pytest.approx(437.0, rel=1e-9)
    assert range_at_pd(step, [1.0, 100.0], (0.5,))[0] == 100.0  # still reached at the search's end


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


def _approach_of(looks, pd):
    return {"look_range_m": np.asarray(looks, float), "cumulative_pd": 1.0 - np.cumprod(1.0 - np.asarray(pd))}


def test_k_of_n_fuses_the_approach_by_its_rule_and_its_median_is_a_look():
    """Two sensors with different look ranges: 2-of-2 is C1 C2, 1-of-2 is 1 - (1 - C1)(1 - C2) (exact)."""
    a = _approach_of([100.0, 80.0, 60.0, 40.0], [0.3, 0.4, 0.5, 0.9])
    b = _approach_of([90.0, 50.0], [0.6, 0.7])
    r = np.array([95.0, 85.0, 70.0, 55.0, 45.0, 30.0])
    c1 = np.array([0.3, 0.3, 1 - 0.7 * 0.6, 1 - 0.7 * 0.6 * 0.5, 1 - 0.7 * 0.6 * 0.5, 1 - 0.7 * 0.6 * 0.5 * 0.1])
    c2 = np.array([0.0, 0.6, 0.6, 0.6, 1 - 0.4 * 0.3, 1 - 0.4 * 0.3])  # each the last look at or beyond r
    np.testing.assert_allclose(fused_cumulative([a, b], r, "k-of-n:2"), c1 * c2, atol=1e-15)
    np.testing.assert_allclose(fused_cumulative([a, b], r, "or"), 1 - (1 - c1) * (1 - c2), atol=1e-15)
    # 2-of-2 by 80 m: 0.58 * 0.6 = 0.348; by 60 m: 0.79 * 0.6 = 0.474; by 50 m: 0.79 * 0.88 = 0.695
    assert fused_first_detection_m([a, b], "k-of-n:2") == 50.0
    assert fused_first_detection_m([a, b], "or") == 90.0  # 1 - 0.7 * 0.4 = 0.72 at b's first look
    assert fused_first_detection_m([_approach_of([10.0], [0.1])], "or") is None


@pytest.mark.parametrize("rule", ["or", "k-of-n:2", "k-of-n:3"])
def test_fused_median_is_the_first_look_of_any_sensor_where_the_fused_pd_reaches_half(rule):
    """Against a scan of every look of every sensor (the union, far to near), three sensors at different rates."""
    rng = np.random.default_rng(4)
    approaches = [
        _approach_of(np.arange(3000.0, 0.0, -step), rng.uniform(0.0, 0.01, int(3000 / step)))
        for step in (1.5, 4.0, 15.0)
    ]
    union = np.unique(np.concatenate([a["look_range_m"] for a in approaches]))[::-1]
    reached = np.nonzero(fused_cumulative(approaches, union, rule) >= 0.5)[0]
    assert reached.size and 0 < reached[0]  # reached, and not at the first look
    assert fused_first_detection_m(approaches, rule) == union[reached[0]]


def test_fused_pd_of_range_is_the_rule_applied_to_each_sensors_pd():
    """OR fusion: 1 - prod(1 - Pd_i); every sensor at every range."""
    scenario = load_scenario("default")
    ranges = np.array([10.0, 300.0, 5000.0])
    each = np.array([sensor_pd(scenario, name, ranges).pd for name in scenario.sensors])
    fused = np.asarray(fused_pd_of_range(scenario, "or")(ranges))
    assert np.allclose(fused, 1.0 - np.prod(1.0 - each, axis=0), rtol=1e-12, atol=1e-15)
