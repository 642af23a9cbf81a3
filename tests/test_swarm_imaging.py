"""Swarms in the EO renders and datasets (issue 26, section 3): N meshes placed at the formation's offsets,
each drone's box and pixels against the exact projection of its mesh, blobs merging under a one-pixel gap."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas.cli import main
from csuas.core.swarm import line_formation
from csuas.render.imaging.eo import render_eo
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
from csuas.render.imaging.swarm import blobs, formation_members, member_coverage, member_labels
from csuas.render.imaging.targets import plate

SENSOR = EoSensor()
IFOV = math.radians(SENSOR.hfov_deg) / SENSOR.n_h
SCENARIO = '[target]\nswarm = {count = 3, spacing_m = 2.0}\n[sensors.e]\nmodality = "eo"\n'


def _exact_box(parts, range_m: float) -> list:
    """Left, top, right, bottom pixel of a mesh's pinhole projection, seen from +x (azimuth 0):
    image right is body +y, up body +z, principal point at the frame's centre pixel (tests/test_labels.py)."""
    v = np.vstack([np.asarray(p.mesh.vertices) for p in parts])
    depth = range_m - v[:, 0]
    x = SENSOR.n_h // 2 + 0.5 + v[:, 1] / (depth * IFOV)
    y = SENSOR.n_v // 2 + 0.5 - v[:, 2] / (depth * IFOV)
    return [math.floor(value) for value in (x.min(), y.min(), x.max(), y.max())]


def _edges(bbox) -> list:
    """A COCO box's first and last pixel columns and rows: left, top, right, bottom."""
    x, y, w, h = bbox
    return [x, y, x + w - 1, y + h - 1]


def test_member_coverage_keeps_the_pixels_a_box_overlaps():
    cov = np.ones((3, 4))
    kept = member_coverage(cov, 10, 20, (11.5, 12.2, 20.0, 21.0))  # columns 11, 12; row 20
    assert kept.tolist() == [[0, 1, 1, 0], [0, 0, 0, 0], [0, 0, 0, 0]]
    assert blobs(np.array([[1, 0, 0], [0, 1, 0], [0, 0, 0.5]])) == [3]  # diagonal neighbours: one blob
    assert blobs(np.array([[1, 0, 1]])) == [1, 1]


@pytest.mark.slow
@pytest.mark.parametrize(("gap_px", "blob_count"), [(3.0, 2), (0.4, 1)])
def test_two_plates_get_their_exact_boxes_and_merge_under_a_one_pixel_gap(gap_px, blob_count):
    range_m, side_m = 500.0, 0.5
    pixel_m = range_m * IFOV
    members = formation_members(plate(side_m, side_m), line_formation(2, side_m + gap_px * pixel_m), 0.0, 0.0)
    view = View(range_m, 0.0, 0.0)
    res = render_eo([p for m in members for p in m], view, SENSOR, Daylight(), settings=RenderSettings("draft", 0))
    labels = member_labels(members, view, res, SENSOR.n_h, SENSOR.n_v)
    area_px = (side_m / pixel_m) ** 2  # 11.0 px a side
    for parts, lab in zip(members, labels):
        exact = _exact_box(parts, range_m)
        # a sliver of a pixel may hold no sample: each edge within one pixel (tests/test_labels.py)
        assert all(abs(a - b) <= 1 for a, b in zip(_edges(lab["bbox"]), exact)), (lab["bbox"], exact)
        if blob_count == 2:  # alone in its box: its own covered area, within the render's sampling (< 1 %)
            assert lab["pixels_on_target"] == pytest.approx(area_px, rel=0.01)
    assert len(blobs(res.coverage)) == blob_count
    assert float(res.coverage.sum()) == pytest.approx(2 * area_px, rel=0.01)


@pytest.mark.slow
def test_render_eo_reports_each_drone_of_a_swarm(tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO)
    assert main(["render", "eo", str(path), "--range-m", "300", "--quality", "draft", "--json"]) == 0
    swarm = json.loads(capsys.readouterr().out)["results"][0]["swarm"]
    assert swarm["count"] == 3 and len(swarm["blobs_px"]) == 3
    centres = [d["bbox"][0] + d["bbox"][2] / 2 for d in swarm["drones"]]
    # 2 m apart at 300 m: 2 / (300 IFOV) = 73.3 px, left to right (y of the line is image right)
    np.testing.assert_allclose(np.diff(centres), 2.0 / (300.0 * IFOV), atol=1.0)


@pytest.mark.slow
def test_a_swarm_dataset_labels_every_drone(tmp_path, capsys):
    from pycocotools.coco import COCO

    scenario = tmp_path / "s.toml"
    scenario.write_text(SCENARIO)
    spec = tmp_path / "spec.toml"
    spec.write_text(
        f'seed = 1\ncount = 1\nscenario = {json.dumps(str(scenario))}\ndrones = ["dji_mini_4_pro"]\n'
        'range_m = [150.0]\nazimuth_deg = [0.0]\nelevation_deg = [0.0]\nposition = "centre"\n'
    )
    assert main(["dataset", str(spec), "--out", str(tmp_path / "d"), "--json"]) == 0
    capsys.readouterr()
    coco = COCO(str(tmp_path / "d" / "annotations.json"))
    annotations = coco.loadAnns(coco.getAnnIds())
    assert [a["csuas"]["swarm_member"] for a in annotations] == [0, 1, 2]
    from csuas.drone_models import build_drone

    drone = build_drone("dji_mini_4_pro").parts
    for a, parts in zip(annotations, formation_members(drone, line_formation(3, 2.0), 0.0, 0.0)):
        exact = _exact_box(parts, 150.0)
        assert all(abs(u - v) <= 1 for u, v in zip(_edges(a["bbox"]), exact)), (a["bbox"], exact)
        assert coco.annToMask(a).sum() == a["area"]
    yolo = (tmp_path / "d" / "labels" / "000000_dji_mini_4_pro.txt").read_text().splitlines()
    assert len(yolo) == 3


@pytest.mark.slow
def test_a_swarm_sequence_has_one_mot_track_per_drone_at_its_exact_box(tmp_path, capsys):
    # flying straight at the camera along the boresight: each frame sees the formation from the nose (azimuth 0)
    scenario = tmp_path / "s.toml"
    scenario.write_text(SCENARIO)
    spec = tmp_path / "spec.toml"
    spec.write_text(
        f'seed = 1\nscenario = {json.dumps(str(scenario))}\ndrones = ["dji_mini_4_pro"]\n'
        "[sequence]\nframes = 2\nwaypoints_m = [[0.0, 150.0, 0.0], [0.0, 140.0, 0.0]]\nspeed_m_s = 15.0\n"
    )
    assert main(["dataset", str(spec), "--out", str(tmp_path / "d")]) == 0
    capsys.readouterr()
    from csuas.drone_models import build_drone
    from csuas.render.imaging.swarm import member_track_id

    members = formation_members(build_drone("dji_mini_4_pro").parts, line_formation(3, 2.0), 0.0, 0.0)
    gt = (tmp_path / "d" / "mot" / "001_dji_mini_4_pro" / "gt" / "gt.txt").read_text().splitlines()
    rows = [[int(v) for v in line.split(",")[:6]] for line in gt]
    assert len(rows) == 2 * 3  # 2 frames x 3 drones (before: drone 0 only)
    tracks = [1, member_track_id(1, 1), member_track_id(1, 2)]
    assert tracks == [1, 1101, 1102]
    for frame, range_m in ((1, 150.0), (2, 150.0 - 15.0 / 30.0)):  # one frame at 30 Hz: 0.5 m nearer
        in_frame = {track: box for f, track, *box in rows if f == frame}
        assert sorted(in_frame) == tracks
        for track, parts in zip(tracks, members):
            exact = _exact_box(parts, range_m)
            assert all(abs(u - v) <= 1 for u, v in zip(_edges(in_frame[track]), exact)), (frame, track, exact)
    coco = json.loads((tmp_path / "d" / "annotations.json").read_text())
    assert [(a["image_id"], a["track_id"]) for a in coco["annotations"]] == [(f, t) for f in (1, 2) for t in tracks]
    assert [[a["image_id"], a["track_id"], *a["bbox"]] for a in coco["annotations"]] == rows
