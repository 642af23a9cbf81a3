"""Accuracy against samples per pixel, quality presets, bounded launches and the window benchmark.

References: docs/validation.md, docs/performance.md.
"""

from __future__ import annotations

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.drone_models import build_drone
from csuas.drone_models.silhouette import projected_metrics
from csuas.render.imaging import QUALITY_PRESETS, Quality, render_eo, resolve_quality
from csuas.render.imaging.records import RenderSettings, View
from csuas.validation.imaging.accuracy import accuracy_sweep
from csuas.validation.imaging.bench import bench_window_vs_full_frame

pytestmark = pytest.mark.slow


def test_presets_and_validation():
    assert {k: q.spp for k, q in QUALITY_PRESETS.items()} == {"draft": 32, "standard": 128, "reference": 2048}
    assert resolve_quality("standard") is QUALITY_PRESETS["standard"]
    with pytest.raises(ParameterError, match="quality"):
        resolve_quality(Quality("x", 2, 1))  # one batch gives no standard error
    with pytest.raises(ParameterError, match="quality"):
        resolve_quality("best")


def test_accuracy_sweep_error_falls_with_samples_and_stays_within_stderr():
    drone = build_drone("dji_mini_4_pro")
    r, az, el = 400.0, 30.0, 20.0
    ifov = np.radians(10.0) / 1920
    exact = projected_metrics(drone.mesh(), az, el)["projected_area_m2"] / (r * ifov) ** 2
    rows = accuracy_sweep(
        lambda q: render_eo(
            drone, View(range_m=r, azimuth_deg=az, elevation_deg=el), settings=RenderSettings(quality=q)
        ),
        n_sides=(1, 2, 4, 8),
        reference=exact,
        n_batches=4,
    )
    assert [row["spp"] for row in rows] == [4, 16, 64, 256]
    for row in rows:
        assert abs(row["error"]) <= 4 * row["stderr"] + 1e-3 * exact
        assert row["time_s"] > 0
    stderr = [row["stderr"] for row in rows]
    assert stderr[-1] < stderr[0] / 4  # jittered sampling: faster than 1/sqrt(spp)
    assert max(abs(rows[-1]["relative_error"]), rows[-1]["stderr"] / exact) < 0.01


def test_launch_size_bounds_memory_without_changing_samples():
    """Coverage depends only on the sample positions, not on how launches are packed."""
    from csuas.render.backend import use_variant
    from csuas.render.imaging.camera import Framing, SensorGeometry, target_bounds, target_window
    from csuas.render.imaging.scene import build_tir_scene, normalise_target, path_integrator
    from csuas.render.imaging.trace import Sampling, trace_window

    use_variant("ad_mono")
    sensor = SensorGeometry.from_fov(10.0, 1920, 1080)
    nt = normalise_target("dji_mini_4_pro", 0.0, 0.0)
    scene = build_tir_scene(nt, band="lwir", surroundings_radiance=0.0)
    tp = sensor.default_target_px()
    w = target_window(sensor, 300.0, nt.radius_m, tp)
    b = target_bounds(sensor, 300.0, nt.radius_m, tp)
    args = (scene, path_integrator(2), Framing(sensor, w, tp, 300.0 / nt.radius_m, b))
    small = trace_window(*args, Sampling(n_side=4, n_batches=4, channels=1, max_launch=4096))
    large = trace_window(*args, Sampling(n_side=4, n_batches=4, channels=1))
    assert w.n_pixels * 16 * 4 > 4096 * 4  # many launches in the small case
    np.testing.assert_array_equal(small.coverage, large.coverage)
    np.testing.assert_array_equal(small.extent, large.extent)


def test_window_and_full_frame_agree():
    out = bench_window_vs_full_frame(range_m=800.0, hfov_deg=2.0, n_h=320, n_v=180, quality="draft")
    assert out["difference_sigma"] < 4.0
    assert out["window_px"] < out["full_frame_px"] / 100
    assert 0 < out["time_ratio"]
