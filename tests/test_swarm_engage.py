"""A swarm in an engagement (issue 26, section 3): N truths in formation, the groups each sensor resolves at
each look and their Pd, the first detection of any drone and the drones the tracker holds at once."""

from __future__ import annotations

import numpy as np
import pytest
import tomllib

from csuas.core.pd_curves import sensor_pd
from csuas.core.swarm import Formation
from csuas.defaults import engagement_path
from csuas.render.engagement.build import build
from csuas.render.engagement.metrics import looks_table, summarise
from csuas.render.engagement.simulate import DronePath, run_once
from csuas.render.engagement.spec import parse_spec
from csuas.render.engagement.swarm import member_positions


def test_the_formation_flies_behind_and_left_of_the_lead():
    path = DronePath(np.array([[0.0, 0.0, 30.0], [1000.0, 0.0, 30.0], [1000.0, 1000.0, 30.0]]), 10.0)
    formation = Formation(np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 5.0, 2.0]]), "offsets")
    x, y, h = member_positions(path, formation, [0.0, 150.0])
    # heading +x: behind is -x, left +y; on the second leg (heading +y, 50 s along it) behind is -y, left -x
    np.testing.assert_allclose(x, [[0, -10, 0], [1000, 1000, 995]], atol=1e-9)
    np.testing.assert_allclose(y, [[0, 0, 5], [500, 490, 500]], atol=1e-9)
    np.testing.assert_allclose(h, [[30, 30, 32], [30, 30, 32]], atol=1e-12)


@pytest.fixture(scope="module")
def swarm_engagement():
    data = tomllib.loads(engagement_path("example").read_text(encoding="utf-8"))
    data["runs"], data["confusers"]["birds_per_km2"] = 1, 0.0
    data["scenario"]["target"]["swarm"] = {"count": 3, "spacing_m": 20.0}
    return build(parse_spec(data), None)


@pytest.mark.slow
def test_a_radar_sees_three_sigma_where_the_swarm_merges_and_each_drone_where_it_resolves(swarm_engagement):
    engagement = swarm_engagement
    sensor, swarm = engagement.sensors["radar"], engagement.swarm_looks["radar"]
    counts = swarm.resolved_count
    assert set(counts.tolist()) == {1, 3}  # 20 m apart: one beam far out, three near the radar
    checked = 0
    for k in np.flatnonzero(counts == 1):
        if swarm.pd[k][0] > 0.01:  # 3 sigma at R: the range equation's Pd of sigma at R / 3^(1/4) (Eq. 109)
            x, y = swarm.centres[k][0]
            slant = float(sensor.geometry(x, y, engagement.looks["radar"].z[k]).slant_m[0])
            single = sensor_pd(sensor.scenario, "radar", [slant / 3**0.25]).pd[0]
            assert swarm.pd[k][0] == pytest.approx(single, rel=0.02)  # the centroid's height: a metre off the lead's
            checked += 1
    assert checked > 3
    for k in np.flatnonzero(counts == 3)[:5]:  # each drone alone: one drone's Pd where it flies
        z = engagement.terrain.height(swarm.x[k], swarm.y[k]) + engagement.path.waypoints[0, 2]
        alone = sensor.drone_pd(sensor.geometry(swarm.x[k], swarm.y[k], z))
        np.testing.assert_allclose(sorted(swarm.pd[k]), sorted(alone), rtol=1e-9, atol=1e-12)
    table = looks_table(engagement)["radar"]
    np.testing.assert_allclose(table["pd_any"], [1 - np.prod(1 - p) for p in swarm.pd], rtol=1e-12)


@pytest.mark.slow
def test_a_run_reports_the_first_detection_of_any_drone_and_the_tracks_it_holds(swarm_engagement):
    record = run_once(swarm_engagement, 0)
    assert record["first_detection_time_s"] is not None
    assert record["first_track_time_s"] is None or record["first_detection_time_s"] <= record["first_track_time_s"]
    assert record["drone_tracks_max"] >= 1
    metrics = summarise(swarm_engagement, [record])
    assert metrics["swarm"]["count"] == 3
    assert metrics["swarm"]["drone_tracks_max"]["median"] == record["drone_tracks_max"]
