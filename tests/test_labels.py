"""Object labels from coverage (render/imaging/labels.py) against boxes, masks and encodings worked by hand."""

from __future__ import annotations

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.render.imaging.labels import decode_run_length, frame_mask, label, run_length, yolo_line


def test_run_length_is_cocos_column_major_encoding():
    # [[0, 1], [1, 1]] read down the columns: 0, 1, 1, 1 -> one 0, three 1
    assert run_length(np.array([[0, 1], [1, 1]], bool)) == {"size": [2, 2], "counts": [1, 3]}
    # a first pixel set starts with an empty run of zeros
    assert run_length(np.array([[1, 0], [0, 0]], bool))["counts"] == [0, 1, 3]
    rng = np.random.default_rng(3)
    for _ in range(20):
        mask = rng.random((7, 11)) < 0.3
        encoded = run_length(mask)
        assert sum(encoded["counts"]) == mask.size
        assert np.array_equal(decode_run_length(encoded), mask)


def test_box_area_and_flags_of_a_window_in_the_frame():
    coverage = np.zeros((3, 4))
    coverage[1, 1:3] = 1.0
    coverage[2, 2] = 0.5
    out = label(coverage, x0=10, y0=20, frame_width=100, frame_height=50)
    assert out["bbox"] == [11, 21, 2, 2] and out["area"] == 3
    assert out["pixels_on_target"] == pytest.approx(2.5) and not out["clipped"] and not out["subpixel"]
    assert np.array_equal(decode_run_length(out["segmentation"]), frame_mask(coverage, 10, 20, 100, 50))
    # half outside the left edge: the box is clipped to the frame and flagged
    clipped = label(coverage, x0=-2, y0=20, frame_width=100, frame_height=50)
    assert clipped["bbox"] == [0, 21, 1, 2] and clipped["clipped"] and clipped["pixels_on_target"] == pytest.approx(1.5)
    # a target smaller than a pixel keeps a one-pixel box
    tiny = label(np.array([[0.0, 0.3]]), x0=5, y0=5, frame_width=10, frame_height=10)
    assert tiny["bbox"] == [6, 5, 1, 1] and tiny["subpixel"]
    gone = label(coverage, x0=500, y0=20, frame_width=100, frame_height=50)
    assert gone["bbox"] is None and not gone["in_frame"] and gone["clipped"]


def test_yolo_line_normalises_the_box_centre_and_size():
    assert yolo_line([10, 20, 4, 6], 100, 50) == "0 0.120000 0.460000 0.040000 0.120000"
    assert yolo_line([0, 0, 100, 50], 100, 50, class_id=2) == "2 0.500000 0.500000 1.000000 1.000000"


def test_bad_coverage_and_frame_are_refused():
    with pytest.raises(ParameterError, match="coverage"):
        label(np.full((2, 2), np.nan), 0, 0, 10, 10)
    with pytest.raises(ParameterError, match="frame size"):
        label(np.zeros((2, 2)), 0, 0, 0, 10)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("range_m", "azimuth_deg", "elevation_deg", "offset_px"),
    [(150.0, 30.0, 10.0, (100.0, -50.0)), (60.0, 200.0, -20.0, (0.0, 0.0)), (400.0, 90.0, 45.0, (-300.0, 200.0))],
)
def test_rendered_box_matches_the_exact_projection_of_the_mesh(range_m, azimuth_deg, elevation_deg, offset_px):
    """The label's box against the pinhole projection of every mesh vertex (bbox of a projected polyhedron
    is the bbox of its projected vertices): camera at range_m along the view direction, image axes h
    (right) and v (up) of drone_models.geometry.view_basis, principal point at the frame's centre pixel."""
    import math

    from csuas.drone_models import build_drone
    from csuas.drone_models.geometry import direction_vector, view_basis
    from csuas.render.imaging.eo import render_eo
    from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View

    sensor = EoSensor()
    res = render_eo(
        "dji_mini_4_pro",
        View(range_m, azimuth_deg, elevation_deg, offset_px),
        sensor,
        Daylight(),
        settings=RenderSettings("draft", 0),
    )
    box = label(res.coverage, res.window.x0, res.window.y0, sensor.n_h, sensor.n_v)["bbox"]
    vertices = np.vstack([np.asarray(p.mesh.vertices) for p in build_drone("dji_mini_4_pro").parts])
    d = direction_vector(azimuth_deg, elevation_deg)
    h, v = view_basis(d, azimuth_deg)
    depth = range_m - vertices @ d
    ifov = math.radians(sensor.hfov_deg) / sensor.n_h
    x = sensor.n_h // 2 + 0.5 + offset_px[0] + (vertices @ h) / (depth * ifov)
    y = sensor.n_v // 2 + 0.5 + offset_px[1] - (vertices @ v) / (depth * ifov)
    left, top, right, bottom = (math.floor(value) for value in (x.min(), y.min(), x.max(), y.max()))
    assert abs(box[0] - left) <= 1 and abs(box[1] - top) <= 1
    assert abs(box[0] + box[2] - 1 - right) <= 1 and abs(box[1] + box[3] - 1 - bottom) <= 1
