"""Engagements with RF, acoustic and lidar sensors: cells, false alarms per hour, Pd per look and birds.

References: false alarms per hour Pfa x cells x 3600 / T (Richards 2014, Section 6.2); cells of a receiver
frequency bins x ceil(sector / theta), theta = sqrt(4 pi / G) (Skolnik Eq. 9.2); lidar range gates x beam
positions; the lidar range of the paper's convention R ~ sigma^(1/4) (Eq. 104).
"""

from __future__ import annotations

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core.coverage import K_FACTOR, SitedSensor
from csuas.core.horizon import EARTH_RADIUS_M
from csuas.core.pd_curves import acoustic_pd_with_loss, sensor_pd
from csuas.core.ranges import evaluate
from csuas.core.scenario import parse_scenario
from csuas.defaults import load_birds
from csuas.render.engagement.sensors import LookSettings, SensorModel, Terrain, bird_critical_dimension_m
from csuas.render.engagement.simulate import BirdSettings, DronePath, Engagement, drone_looks, run_once
from csuas.render.engagement.spec import parse_spec

CELL = 25.0
SIZE = 200  # DEM cells a side: 5 km
CENTRE = 100.0


def _scenario(convention="paper"):
    return parse_scenario(
        {
            "name": "engage_modalities",
            "convention": convention,
            "target": {"preset": "dji_mini_4_pro"},
            "environment": {"preset": "clear_day"},
            "sensors": {name: {"modality": name} for name in ("rf", "acoustic", "lidar")},
        }
    )


def _sensor(name, settings, scenario=None):
    dem = np.zeros((SIZE, SIZE))
    terrain = Terrain(dem, CELL, 0.0, SIZE * CELL)
    sited = SitedSensor(name, CENTRE, CENTRE, 10.0)
    return SensorModel(scenario or _scenario(), sited, terrain, settings)


def _beam_deg(gain_db):
    return np.degrees(np.sqrt(4 * np.pi / 10 ** (gain_db / 10)))


def test_cells_of_each_modality_by_their_rules():
    """RF: 1024 bins x 360 deg / beam of 14 dB; acoustic: one band (paper) or 24 (physical) x beams of 20 dB; lidar."""
    rf = _sensor("rf", LookSettings())
    assert rf.cells == 1024 * np.ceil(360.0 / _beam_deg(14.0)) == 1024 * 9
    acoustic = _sensor("acoustic", LookSettings())
    assert acoustic.cells == np.ceil(360.0 / _beam_deg(20.0)) == 18
    physical = _sensor("acoustic", LookSettings(), _scenario("physical"))
    assert physical.cells == 24 * 18
    given = _sensor("rf", LookSettings(frequency_bins=256, bearing_cells=36))
    assert given.cells == 256 * 36
    lidar = _sensor("lidar", LookSettings(instrumented_range_m=300.0, range_gate_m=1.5, beam_positions=400))
    assert lidar.cells == np.ceil(300.0 / 1.5) * 400


def _engagement(sensors, runs_seed=5):
    """A drone 1-1.9 km west of the sensors, beyond their 500 m reach: no target, only noise."""
    any_sensor = next(iter(sensors.values()))
    x, y = any_sensor.x, any_sensor.y
    path = DronePath(np.array([[x - 1900.0, y, 30.0], [x - 1000.0, y, 30.0]]), 15.0)
    return Engagement(any_sensor.terrain, sensors, path, BirdSettings(0.0, ()), (3, 5), 5, runs_seed, load_birds())


def test_false_alarms_per_hour_of_rf_and_acoustic_match_closed_form():
    """No target: each sensor's noise false alarms per hour over the runs against Pfa x cells x 3600 / T, 3 s.e."""
    sensors = {
        "rf": _sensor("rf", LookSettings(pfa=1e-4, instrumented_range_m=500.0, revisit_s=1.0)),
        "acoustic": _sensor("acoustic", LookSettings(pfa=2e-2, instrumented_range_m=500.0, revisit_s=0.5)),
    }
    engagement = _engagement(sensors)
    runs = 6
    records = [run_once(engagement, i) for i in range(runs)]
    for name, sensor in sensors.items():
        assert not engagement.looks[name].visible[engagement.looks[name].in_regard].any()
        looks = runs * len(engagement.looks[name].t_s)
        hours = looks * sensor.settings.revisit_s / 3600.0
        measured = sum(r["false_alarms"][name]["noise"] for r in records) / hours
        pfa, cells = sensor.settings.pfa, sensor.cells
        expected = pfa * cells * 3600.0 / sensor.settings.revisit_s
        stderr = np.sqrt(looks * cells * pfa * (1 - pfa)) / hours
        assert abs(measured - expected) < 3 * stderr, (name, measured, expected, stderr)


@pytest.mark.parametrize("name", ["rf", "acoustic", "lidar"])
def test_look_pd_is_the_modalitys_pd_curve_at_the_slant_range(name):
    """A look's Pd equals csuas pd's curve of the modality at that slant range exactly (0 outside the regard)."""
    sensor = _sensor(name, LookSettings(instrumented_range_m=2400.0))
    path = DronePath(np.array([[sensor.x - 2000.0, sensor.y + 40.0, 30.0], [sensor.x, sensor.y + 40.0, 30.0]]), 15.0)
    looks = drone_looks(sensor.terrain, sensor, path)
    seen = looks.visible & looks.in_regard
    assert seen.sum() > 100
    curve = sensor_pd(sensor.scenario, name, looks.slant_range_m[seen]).pd
    np.testing.assert_array_equal(looks.pd[seen], curve)
    assert np.all(looks.pd[~seen] == 0.0)
    assert curve.max() > 0.5  # the approach reaches where the sensor detects


def test_birds_rf_and_acoustic_none_lidar_from_size():
    """RF and acoustic see no bird; lidar: a bird as the drone at R (d_drone / d_bird)^(1/2) (paper: R ~ sigma^1/4)."""
    gull = load_birds()["gull"]
    for name in ("rf", "acoustic"):
        sensor = _sensor(name, LookSettings())
        geometry = sensor.geometry(np.array([sensor.x + 100.0]), np.array([sensor.y]), np.array([40.0]))
        assert geometry.visible.all()
        assert sensor.bird_pd(geometry, gull, np.zeros(1))[0] == 0.0
    lidar = _sensor("lidar", LookSettings(instrumented_range_m=1000.0))
    ground = np.linspace(20.0, 400.0, 60)
    geometry = lidar.geometry(lidar.x + ground, np.full(ground.shape, lidar.y), np.full(ground.shape, 10.0))
    assert geometry.visible.all()
    bird = lidar.bird_pd(geometry, gull, np.zeros(ground.shape))
    shrink = np.sqrt(lidar.scenario.target["d_crit_m"] / bird_critical_dimension_m(gull))
    drone_equivalent = sensor_pd(lidar.scenario, "lidar", geometry.slant_m * shrink).pd
    np.testing.assert_allclose(bird, drone_equivalent, rtol=1e-9, atol=1e-12)
    assert bird.max() > 0.9 and bird.min() < 0.1


def test_spec_takes_the_new_look_keys_and_names_bad_ones():
    """frequency_bins, bearing_cells, range_gate_m, beam_positions parse; a bad value is named with its key."""
    base = {"site": "demo", "drone": {"waypoints": [[0, 0, 30], [1, 1, 30]], "speed_m_s": 10}}
    spec = parse_spec({**base, "looks": {"rf": {"frequency_bins": 512, "bearing_cells": 8}}})
    assert spec.looks["rf"].frequency_bins == 512
    with pytest.raises(Exception) as caught:
        parse_spec({**base, "looks": {"lidar": {"range_gate_m": -1.0, "beam_positions": 0}}})
    text = str(caught.value)
    assert "looks.lidar.range_gate_m" in text and "looks.lidar.beam_positions" in text


def test_rf_alone_confirms_at_the_third_look_with_its_coarse_range():
    """Pd 1 from the first look (125 km paper range), Pfa 1e-15: 3 of 5 confirms at t = 2 s in every run.

    The exact M-of-N program gives P(first track at look 3) = 1 at Pd = 1; the RF's 50 % range from the
    received level (defaults) must not break the association of its own successive detections.
    """
    sensor = _sensor("rf", LookSettings(pfa=1e-15, sigma_range_fraction=0.5, sigma_bearing_deg=3.0))
    path = DronePath(np.array([[sensor.x - 2000.0, sensor.y, 30.0], [sensor.x - 200.0, sensor.y, 30.0]]), 15.0)
    engagement = Engagement(sensor.terrain, {"rf": sensor}, path, BirdSettings(0.0, ()), (3, 5), 5, 2, load_birds())
    assert np.all(engagement.looks["rf"].pd == 1.0)
    times = [run_once(engagement, i)["first_track_time_s"] for i in range(10)]
    assert times == [2.0] * 10


def test_aspect_decorrelation_is_refused_for_a_sensor_without_a_wavelength_rule():
    """The aspect rule needs a radar's wavelength: an RF sensor asking for it is named with its key."""
    with pytest.raises(ParameterError) as caught:
        _sensor("rf", LookSettings(decorrelation="aspect"))
    assert "looks.rf.decorrelation" in str(caught.value)


def _behind_ridge(convention):
    """An acoustic array (2 m mast) 500 m east of a 25 m ridge (DEM column 80), the drone 10 m up west of it."""
    dem = np.zeros((SIZE, SIZE))
    dem[:, 80] = 25.0
    terrain = Terrain(dem, CELL, 0.0, SIZE * CELL)
    sensor = SensorModel(
        _scenario(convention), SitedSensor("acoustic", CENTRE, CENTRE, 2.0), terrain, LookSettings(revisit_s=2.0)
    )
    path = DronePath(np.array([[sensor.x - 2000.0, sensor.y, 10.0], [sensor.x - 600.0, sensor.y, 10.0]]), 15.0)
    return sensor, drone_looks(terrain, sensor, path)


def test_acoustic_look_behind_a_ridge_hears_through_the_iso9613_barrier():
    """Physical convention: Pd with A_bar = D_z(z, K_met) (ISO 9613-2 Eqs. 14, 16, 18) of the ridge's exact geometry."""
    sensor, looks = _behind_ridge("physical")
    assert looks.in_regard.all() and not looks.visible.any()
    drop = lambda d: d**2 / (2 * K_FACTOR["acoustic"] * EARTH_RADIUS_M)  # curvature drop d^2 / (2 k R_E)
    ground = np.hypot(looks.x - sensor.x, looks.y - sensor.y)
    edge_rise, drone_rise = 25.0 - drop(500.0) - 2.0, looks.z - drop(ground) - 2.0
    d_sr, d_ss = np.hypot(500.0, edge_rise), np.hypot(ground - 500.0, drone_rise - edge_rise)
    z = d_sr + d_ss - np.hypot(ground, drone_rise)
    k_met = np.exp(-np.sqrt(d_ss * d_sr * looks.slant_range_m / (2 * z)) / 2000.0)
    f = float(evaluate(sensor.scenario)["acoustic"].term("detector_band_hz").value)
    a_bar = np.minimum(10 * np.log10(3 + 20 * f / 340.0 * z * k_met), 20.0)  # no ground term: no height_m
    expected = acoustic_pd_with_loss(sensor.scenario, "acoustic", looks.slant_range_m, a_bar)
    np.testing.assert_allclose(looks.pd, expected, rtol=1e-9, atol=1e-12)
    free = sensor_pd(sensor.scenario, "acoustic", looks.slant_range_m).pd
    assert looks.pd.max() > 0.2 and np.all(looks.pd < free)  # audible behind the ridge, less than in the open
    # from 10 lg 3 = 4.77 dB far off (K_met -> 0: downwind refraction over the edge) to 8.6 dB 100 m behind it
    assert np.all(a_bar >= 10 * np.log10(3.0)) and 8.0 < a_bar.max() < 9.0


def test_acoustic_look_behind_a_ridge_is_deaf_in_the_paper_convention():
    _, looks = _behind_ridge("paper")
    assert not looks.visible.any() and np.all(looks.pd == 0.0)
