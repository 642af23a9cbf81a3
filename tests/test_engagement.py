"""Engagements: false alarms, M-of-N first tracks, GOSPA, clutter and the spec, against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from csuas.base.errors import InputErrors
from csuas.core import clutter, false_alarms
from csuas.core.coverage import SitedSensor
from csuas.core.horizon import EARTH_RADIUS_M
from csuas.core.m_of_n import first_confirmation
from csuas.core.scenario import parse_scenario
from csuas.core.terrain import gaussian_hills, height_at, line_of_sight, viewshed
from csuas.defaults import load_birds
from csuas.render.engagement.sensors import LookSettings, SensorModel, Terrain
from csuas.render.engagement.simulate import BirdSettings, DronePath, Engagement, gospa_distance, run_once
from csuas.render.engagement.spec import parse_spec

CELL = 25.0


def _scenario():
    return parse_scenario(
        {
            "name": "engage_test",
            "convention": "paper",
            "target": {"preset": "dji_mini_4_pro"},
            "environment": {"preset": "clear_day"},
            "sensors": {"radar": {"modality": "radar", "preset": "paper_section_4_9"}},
        }
    )


def _radar(dem, settings, gamma_db=None, row=40.0, col=40.0):
    terrain = Terrain(dem, CELL, 0.0, dem.shape[0] * CELL)
    return terrain, SensorModel(_scenario(), SitedSensor("radar", row, col, 10.0), terrain, settings, gamma_db)


def test_false_alarms_per_look_match_pfa_times_cells():
    """No target: noise false alarms per look against Pfa x cells within 3 standard errors, all inside the regard."""
    _, sensor = _radar(np.zeros((80, 80)), LookSettings(pfa=1e-4, clutter=False))
    dr = false_alarms.range_resolution_m(50.0)
    beam = false_alarms.beamwidth_deg(35.0)
    cells = np.ceil(sensor.reach_m / dr) * np.ceil(360.0 / beam)
    assert sensor.cells == cells
    rng = np.random.default_rng(11)
    looks = 400
    counts = np.array([len(sensor.false_alarm_xy(rng)) for _ in range(looks)])
    expected = 1e-4 * cells
    stderr = np.sqrt(cells * 1e-4 * (1 - 1e-4) / looks)
    assert abs(counts.mean() - expected) < 3 * stderr
    points = sensor.false_alarm_xy(rng)
    assert np.all(np.hypot(points[:, 0] - sensor.x, points[:, 1] - sensor.y) <= sensor.reach_m)
    per_hour = false_alarms.per_hour(expected, 0.5)
    assert per_hour == pytest.approx(expected * 7200)


def _approach(dem, sensor, runs_seed=3, birds=0.0):
    """A straight approach to the radar from 900 m at 15 m/s, 30 m above the terrain."""
    path = DronePath(np.array([[sensor.x - 900.0, sensor.y, 30.0], [sensor.x - 20.0, sensor.y, 30.0]]), 15.0)
    terrain = sensor.terrain
    return Engagement(
        terrain, {"radar": sensor}, path, BirdSettings(birds, ("pigeon",)), (3, 5), 5, runs_seed, load_birds()
    )


def test_first_track_time_matches_exact_m_of_n():
    """One sensor, independent looks, no false alarms: the tracker's first-track CDF against the DP at every look."""
    dem = np.zeros((80, 80))
    _, sensor = _radar(dem, LookSettings(pfa=0.0, clutter=False, decorrelation="independent", sigma_bearing_deg=0.5))
    engagement = _approach(dem, sensor)
    looks = engagement.looks["radar"]
    runs = 80
    first = np.array([run_once(engagement, i)["first_track_time_s"] for i in range(runs)], dtype=float)
    exact = np.cumsum(first_confirmation(looks.pd, 3, 5))
    measured = np.array([np.mean(first <= t + 1e-9) for t in looks.t_s])
    stderr = np.sqrt(exact * (1 - exact) / runs)
    assert np.all(np.abs(measured - exact) <= 3 * stderr + 0.5 / runs), np.max(np.abs(measured - exact) - 3 * stderr)
    assert 0.05 < exact[len(exact) // 2] or exact[-1] > 0.9  # the approach crosses the radar's reach


def test_gospa_hand_computed():
    """GOSPA (p = 2, c = 100 m, alpha = 2): one track 5 m off the truth, one false: sqrt(5^2 + c^2 / 2)."""
    assert gospa_distance([[3.0, 4.0], [500.0, 0.0]], [[0.0, 0.0]]) == pytest.approx(np.sqrt(25 + 100**2 / 2))
    assert gospa_distance([], [[0.0, 0.0]]) == pytest.approx(np.sqrt(100**2 / 2))
    assert gospa_distance([[0.0, 200.0]], [[0.0, 0.0]]) == pytest.approx(np.sqrt(2 * 100**2 / 2))


def test_clutter_on_flat_ground_matches_constant_gamma():
    """Flat ground: each seen cell's clutter false alarms per look against the constant-gamma closed form."""
    dem = np.zeros((80, 80))
    terrain, sensor = _radar(dem, LookSettings(clutter_rejection_db=50.0), gamma_db=-15.0)
    ground = np.hypot(sensor.clutter_xy[:, 0] - sensor.x, sensor.clutter_xy[:, 1] - sensor.y)
    slant = np.hypot(ground, sensor.eye_z)
    psi = np.arctan2(sensor.eye_z + ground**2 / (2 * 4 / 3 * EARTH_RADIUS_M), ground)  # curvature drop, k = 4/3
    dr, beam = 299792458.0 / (2 * 50e6), np.radians(false_alarms.beamwidth_deg(35.0))
    sigma_c = 10 ** (-1.5) * np.sin(psi) * slant * beam * dr / np.cos(psi)
    snr_db = 10.0 + 40 * np.log10(445.30460703828703 / slant)  # the radar's SNR on 0.01 m^2: 10 dB at 445.3 m
    cnr = 10 ** (snr_db / 10) * sigma_c / 0.01
    rate = CELL**2 / (slant * beam * dr / np.cos(psi)) * (1e-6 ** (1 / (1 + cnr * 1e-5)) - 1e-6)
    assert np.allclose(sensor.clutter_rate, rate, rtol=1e-9, atol=0.0)
    assert sensor.clutter_rate.size > 100


def test_no_clutter_from_hidden_cells():
    """A ridge between the radar and the far ground: every clutter cell is seen, none lies behind the ridge."""
    dem = np.zeros((80, 80))
    dem[:, 50:52] = 60.0  # a north-south ridge 250 m east of the radar
    terrain, sensor = _radar(dem, LookSettings(clutter_rejection_db=0.0), gamma_db=-10.0)
    rows, cols = terrain.rowcol(sensor.clutter_xy[:, 0], sensor.clutter_xy[:, 1])
    assert cols.max() < 52  # nothing east of the ridge
    seen = viewshed(dem, CELL, 40.0, 40.0, 10.0, 0.0, 4 / 3)
    assert seen[np.rint(rows).astype(int), np.rint(cols).astype(int)].all()
    assert (~seen[:, 53:]).all()


def test_line_of_sight_agrees_with_viewshed():
    """Point-to-point line of sight against the viewshed's cells on hills: all but grazing cells agree."""
    dem = gaussian_hills(120, CELL)
    seen = viewshed(dem, CELL, 60.3, 50.7, 10.0, 30.0, 4 / 3)
    rows, cols = np.indices(dem.shape)
    eye = float(height_at(dem, np.array([60.3]), np.array([50.7]))[0]) + 10.0
    points = np.stack([rows.ravel(), cols.ravel(), (dem + 30.0).ravel()], axis=1)
    los = line_of_sight(dem, CELL, (60.3, 50.7, eye), points, 4 / 3)
    assert np.mean(los == seen.ravel()) > 0.995
    assert 0.2 < los.mean() < 0.95


def test_spec_names_every_mistake():
    with pytest.raises(InputErrors) as error:
        parse_spec(
            {
                "site": "demo",
                "runs": 0,
                "drone": {"waypoints": [[1.0, 2.0, 3.0]], "speed_m_s": -1.0},
                "tracker": {"confirm": [5, 3]},
                "confusers": {"bird_classes": ["crow"]},
                "colour": "red",
            }
        )
    text = str(error.value)
    for key in ("runs", "drone.waypoints", "drone.speed_m_s", "tracker.confirm", "confusers.bird_classes", "colour"):
        assert key in text


def test_clutter_exceedance_is_its_closed_form_monte_carlo():
    """Exponential clutter plus noise over the noise threshold: Monte Carlo against Pfa^(1/(1+CNR)) within 3 s.e."""
    rng = np.random.default_rng(2)
    pfa, cnr, n = 1e-2, 3.0, 200_000
    crossings = np.mean(rng.exponential(1 + cnr, n) > -np.log(pfa))
    p = clutter.exceedance(pfa, cnr)
    assert abs(crossings - p) < 3 * np.sqrt(p * (1 - p) / n)


def test_gospa_reproduces_stone_soups_own_example():
    """Stone Soup's GOSPA test case (c = 10, p = 1): five tracks 0.5 then 1 off five truths give 2.5 then 5."""
    truths = [[float(i), 0.0] for i in range(5)]
    half_off = [[i + 0.5, 0.0] for i in range(5)]
    one_off = [[i + 1.0, 0.0] for i in range(5)]
    assert gospa_distance(half_off, truths, c_m=10.0, p=1) == pytest.approx(5 * 0.5)
    assert gospa_distance(one_off, truths, c_m=10.0, p=1) == pytest.approx(5 * 1.0)


def test_siap_scores_of_a_hand_built_picture():
    """The report's hand-built picture (a drone held by track A for 0-4 s, then by track B 3 m off and 2 m/s
    fast for 5-9 s, track C 14 km away): each SIAP score by hand."""
    from csuas.render.engagement.siap import siap_scores
    from csuas.validation.report.checks_engage import siap_picture

    scores = siap_scores(*siap_picture(), 100.0)
    assert scores["completeness"] == pytest.approx(10 / 10)  # a track on the drone at every look
    assert scores["ambiguity"] == pytest.approx(10 / 10)  # one track at a time
    assert scores["spuriousness"] == pytest.approx(10 / 20)  # C's 10 track-looks of 20
    assert scores["position_accuracy_m"] == pytest.approx((5 * 0 + 5 * 3) / 10)
    assert scores["velocity_accuracy_m_s"] == pytest.approx((5 * 0 + 5 * 2) / 10)
    assert scores["track_number_changes_per_s"] == pytest.approx((2 - 1) / 8.0)  # held 0-4 s and 5-9 s
    assert scores["longest_track_segment"] == pytest.approx(4 / 9)  # 4 s of a 9 s flight


def test_a_radar_look_without_false_alarms_sees_no_bird_and_does_not_fail():
    """Pfa 0 puts the look's threshold at infinity: Pd 0 for a gull in plain view (it raised); Pfa 1e-6 sees it."""
    gull = load_birds()["gull"]
    _, quiet = _radar(np.zeros((80, 80)), LookSettings(pfa=0.0, clutter=False))
    _, noisy = _radar(np.zeros((80, 80)), LookSettings(pfa=1e-6, clutter=False))
    for sensor, seen in ((quiet, False), (noisy, True)):
        geometry = sensor.geometry(np.array([sensor.x + 30.0]), np.array([sensor.y]), np.array([20.0]))
        assert geometry.visible.all() and geometry.in_regard.all()
        pd = sensor.bird_pd(geometry, gull, np.zeros(1))
        assert (pd[0] > 0.5) if seen else (pd[0] == 0.0)
