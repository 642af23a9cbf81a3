"""Sequence datasets (render/imaging/sequence.py): trajectory, attitude, image motion against closed forms; a
small video with COCO video keys, MOTChallenge ground truth and a rolling-shutter label that follows the drone."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas import cli
from csuas.base.errors import InputErrors, ParameterError
from csuas.render.imaging.dataset import parse_dataset_spec
from csuas.render.imaging.labels import decode_run_length
from csuas.render.imaging.sequence import (
    SequenceSpec,
    approach_waypoints,
    body_view,
    flight,
    parse_sequence,
    sequence_frames,
)

IFOV = math.radians(10.0) / 1920


def test_the_drone_flies_its_waypoints_at_its_speed_and_hovers_at_the_end():
    spec = SequenceSpec(
        frames=1, waypoints_m=((0.0, 100.0, 10.0), (30.0, 100.0, 10.0), (30.0, 140.0, 10.0)), speed_m_s=10.0
    )
    position, velocity = flight(spec, 2.0)
    assert np.allclose(position, [20.0, 100.0, 10.0]) and np.allclose(velocity, [10.0, 0.0, 0.0])
    position, velocity = flight(spec, 5.0)  # 50 m: 30 east, then 20 north
    assert np.allclose(position, [30.0, 120.0, 10.0]) and np.allclose(velocity, [0.0, 10.0, 0.0])
    position, velocity = flight(spec, 60.0)
    assert np.allclose(position, [30.0, 140.0, 10.0]) and np.allclose(velocity, 0.0)
    start, end = approach_waypoints(bearing_deg=90.0, range_m=500.0, elevation_deg=30.0)
    assert np.allclose(start, [500 * math.cos(math.radians(30)), 0.0, 250.0], atol=1e-9)
    assert np.allclose(end, [0.0, 0.0, 250.0])


def test_a_level_drone_flying_east_north_of_the_camera_shows_its_right_side_from_above():
    # the camera lies south (-y in a body frame whose nose is east: its right) and below
    azimuth, elevation = body_view([0.0, 100.0, 20.0], heading_rad=0.0)
    assert azimuth == pytest.approx(-90.0) and elevation == pytest.approx(-math.degrees(math.atan2(20.0, 100.0)))
    azimuth, _ = body_view([0.0, 100.0, 0.0], heading_rad=math.pi / 2)  # flying north, away: the tail
    assert abs(azimuth) == pytest.approx(180.0)


def test_a_crossing_drone_moves_across_the_focal_plane_at_speed_over_distance():
    # boresight north (the mean direction of a symmetric crossing); on the pinhole's focal plane x = e / n
    spec = SequenceSpec(frames=31, waypoints_m=((-10.0, 200.0, 0.0), (10.0, 200.0, 0.0)), speed_m_s=20.0)
    frames = sequence_frames(spec, IFOV, (1920, 1080), 30.0, seed=0)
    for frame in frames:
        east = -10.0 + 20.0 * frame["time_s"]
        assert frame["target_offset_px"][0] == pytest.approx(east / 200.0 / IFOV, abs=1e-6)
        assert frame["velocity_px_s"][0] == pytest.approx(20.0 / 200.0 / IFOV, rel=1e-6)
        assert frame["velocity_px_s"][1] == pytest.approx(0.0, abs=1e-6)
        assert frame["range_m"] == pytest.approx(math.hypot(east, 200.0))
    assert [f["frame_id"] for f in frames] == list(range(31))


def test_a_pan_tilt_unit_keeps_the_drone_centred_within_its_jitter():
    spec = SequenceSpec(
        frames=400, waypoints_m=((-300.0, 200.0, 30.0), (300.0, 200.0, 30.0)), speed_m_s=20.0, pointing="track"
    )
    still = sequence_frames(spec, IFOV, (1920, 1080), 30.0, seed=0)
    assert max(abs(v) for f in still for v in (*f["target_offset_px"], *f["velocity_px_s"])) < 1e-6
    jittery = sequence_frames(SequenceSpec(**{**spec.__dict__, "jitter_urad": 200.0}), IFOV, (1920, 1080), 30.0, 1)
    offsets = np.array([f["target_offset_px"] for f in jittery])
    # 200 urad rms over an IFOV of 90.9 urad: 2.2 px rms in each axis; standard error of an rms over 400: 3.5 %
    assert np.sqrt(np.mean(offsets**2, axis=0)) == pytest.approx(200e-6 / IFOV, rel=0.12)
    with pytest.raises(ParameterError, match="field of view"):
        sequence_frames(SequenceSpec(**{**spec.__dict__, "pointing": "fixed"}), IFOV, (1920, 1080), 30.0, 0)


def test_every_sequence_mistake_is_named_with_its_key_path():
    with pytest.raises(InputErrors) as caught:
        parse_dataset_spec(
            {
                "range_m": [100.0],
                "sequence": {"frames": 0, "approach": {"bearing_deg": 10.0, "range_m": -5.0}, "pointing": "x", "y": 1},
            }
        )
    text = str(caught.value)
    for key in ("range_m", "sequence.frames", "sequence.approach.range_m", "sequence.approach.speed_m_s"):
        assert key in text
    assert "sequence.pointing" in text and "sequence.y" in text
    _, errors = parse_sequence({"frames": 3, "waypoints_m": [[0, 1, 2]], "speed_m_s": 5.0})
    assert [e.name for e in errors] == ["sequence.waypoints_m"]
    spec, errors = parse_sequence({"frames": 3, "approach": {"bearing_deg": 0.0, "range_m": 300.0, "speed_m_s": 9.0}})
    assert not errors and spec.waypoints_m[0] == pytest.approx(
        (0.0, 300 * math.cos(math.radians(5.0)), 300 * math.sin(math.radians(5.0)))
    )


def _dark_box(path, background_dn: float, noise_dn: float) -> tuple:
    """Columns and rows of the pixels darker than the sky by 6 sigma: the drone as the image shows it."""
    from csuas.render.imaging.dataset_files import read_dn_png

    dn = read_dn_png(path).astype(float)
    rows, cols = np.nonzero(dn < background_dn - 6 * noise_dn)
    return cols.min(), cols.max(), rows.min(), rows.max()


@pytest.mark.slow
def test_a_sequence_writes_video_keys_mot_ground_truth_and_a_label_that_follows_the_rolling_shutter(tmp_path, capsys):
    # 30 m/s at 60 m: 5500 px/s; a slow readout of 200 us per row shears the drone by 1.1 px per row
    base = (
        'seed = 2\ndrones = ["dji_mini_4_pro"]\nchain = [CHAIN"psf", "shot_noise", "read_noise", "quantise"]\n'
        "[sequence]\nframes = 2\nwaypoints_m = [[-1.0, 60.0, 0.0], [1.0, 60.0, 0.0]]\nspeed_m_s = 30.0\n"
        "line_time_us = 200.0\n"
    )
    masks = {}
    for name, chain in (("global", ""), ("rolling", '"rolling_shutter", ')):
        spec = tmp_path / f"{name}.toml"
        spec.write_text(base.replace("CHAIN", chain))
        assert cli.main(["dataset", str(spec), "--out", str(tmp_path / name)]) == 0
        coco = json.loads((tmp_path / name / "annotations.json").read_text())
        masks[name] = decode_run_length(coco["annotations"][0]["segmentation"])
        assert coco["videos"] == [{"id": 1, "name": "001_dji_mini_4_pro", "frame_rate_hz": 30.0, "frames": 2}]
        assert [(i["video_id"], i["frame_id"]) for i in coco["images"]] == [(1, 0), (1, 1)]
        assert [a["track_id"] for a in coco["annotations"]] == [1, 1]
        gt = (tmp_path / name / "mot" / "001_dji_mini_4_pro" / "gt" / "gt.txt").read_text().splitlines()
        for line, annotation in zip(gt, coco["annotations"]):
            fields = line.split(",")
            assert [int(v) for v in fields[:6]] == [annotation["image_id"], 1, *annotation["bbox"]]
        x, y, w, h = coco["annotations"][0]["bbox"]
        image = tmp_path / name / coco["images"][0]["file_name"]
        from csuas.render.imaging.dataset_files import read_dn_png

        frame = read_dn_png(image).astype(float)
        sky = frame[: y - 10]
        left, right, top, bottom = _dark_box(image, float(np.median(sky)), float(np.std(sky)))
        # the label's box is the drone's image to within the blur of its partly covered edge pixels
        assert max(abs(left - x), abs(right - (x + w - 1)), abs(top - y), abs(bottom - (y + h - 1))) <= 2
    capsys.readouterr()
    # each row of the drone moves by v t_line (r - r_mid): 5500 px/s x 200 us = 1.1 px per row from row 539.5
    velocity = 30.0 / 60.0 / IFOV
    rows = [r for r in range(1080) if masks["global"][r].any() and masks["rolling"][r].any()]
    assert len(rows) > 10
    for r in rows:
        centres = [np.flatnonzero(masks[name][r]).mean() for name in ("global", "rolling")]
        assert centres[1] - centres[0] == pytest.approx(velocity * 200e-6 * (r - 539.5), abs=1.0)


def test_the_embedded_sequence_spec_keeps_the_drone_in_view_for_all_its_frames():
    from csuas.core.scenario import load_scenario
    from csuas.render.imaging.dataset import load_dataset_spec
    from csuas.render.imaging.sequence import sequence_items

    spec = load_dataset_spec("sequence")
    params = load_scenario(spec.scenario).sensors["eo"].params
    items = sequence_items(spec.sequence, spec.axes["drones"], spec.count, spec.seed, params)
    assert len(items) == 30 and items[-1]["time_s"] == pytest.approx(29 / 30)
    assert all(abs(i["target_offset_px"][0]) < 960 for i in items)
    assert items[0]["line_time_s"] == pytest.approx(1 / (30 * 1080))  # one frame period over the rows


def test_rotor_blades_turn_at_their_rpm_and_are_built_at_each_frames_phase():
    from csuas.render.imaging.sequence import blade_phase_deg, sequence_target

    assert blade_phase_deg(6000.0, 0.0025) == pytest.approx(90.0)  # 100 rev/s: a quarter turn in 2.5 ms
    assert blade_phase_deg(6000.0, 0.01) == pytest.approx(0.0, abs=1e-9)  # a whole turn
    assert sequence_target({"drone": "dji_mini_4_pro"}) == "dji_mini_4_pro"  # swept discs without rotor_rpm
    quarter = sequence_target({"drone": "dji_mini_4_pro", "blade_phase_deg": 90.0})
    straight = sequence_target({"drone": "dji_mini_4_pro", "blade_phase_deg": 0.0})
    assert quarter.propellers == "blades"
    blades = [p for p in quarter.parts if "prop" in p.name or "blade" in p.name]
    turned = [p for p in straight.parts if "prop" in p.name or "blade" in p.name]
    assert blades and not np.allclose(blades[0].mesh.vertices, turned[0].mesh.vertices)
    spec, errors = parse_sequence(
        {"frames": 2, "waypoints_m": [[0, 50, 5], [5, 50, 5]], "speed_m_s": 5, "rotor_rpm": -1}
    )
    assert [e.name for e in errors] == ["sequence.rotor_rpm"]


def test_the_sun_stays_put_in_the_world_while_the_drone_turns_under_it():
    # east along y = 200 m, then north: the heading turns by 90 deg, the sun's body azimuth by -90 deg
    spec = SequenceSpec(
        frames=60, waypoints_m=((-20.0, 200.0, 10.0), (0.0, 200.0, 10.0), (0.0, 220.0, 10.0)), speed_m_s=20.0
    )
    frames = sequence_frames(spec, IFOV, (1920, 1080), 30.0, seed=0)
    first, last = frames[0], frames[-1]
    assert (first["sun_azimuth_deg"] - last["sun_azimuth_deg"]) % 360.0 == pytest.approx(90.0)
    # the sun behind a camera looking about north: from the drone flying east it lies to the right, about -90 deg
    assert first["sun_azimuth_deg"] == pytest.approx(-90.0, abs=5.0)


def test_each_drone_and_draw_is_its_own_video_and_track_with_its_own_jitter():
    from csuas.render.imaging.sequence import sequence_items

    spec = SequenceSpec(
        frames=3,
        waypoints_m=((-5.0, 100.0, 5.0), (5.0, 100.0, 5.0)),
        speed_m_s=10.0,
        pointing="track",
        jitter_urad=50.0,
    )
    params = {"look_rate_hz": 25.0, "n_h": 1920, "n_v": 1080, "hfov_deg": 10.0}
    items = sequence_items(spec, ["dji_mini_4_pro", "black_hornet_3", "dji_mini_4_pro"], 2, 7, params)
    assert [(i["video_id"], i["drone"]) for i in items[::3]] == [
        (1, "dji_mini_4_pro"),
        (2, "dji_mini_4_pro"),
        (3, "black_hornet_3"),
        (4, "black_hornet_3"),
    ]
    assert [i["track_id"] for i in items] == [i["video_id"] for i in items] and len({i["name"] for i in items}) == 12
    assert items[1]["time_s"] == pytest.approx(1 / 25.0)  # the sensor's look rate
    assert items[0]["target_offset_px"] != items[3]["target_offset_px"]  # each video draws its own jitter


def test_a_thermal_sequence_refuses_the_exposure_smear_it_does_not_have(tmp_path, capsys):
    spec = tmp_path / "tir.toml"
    spec.write_text(
        'sensor = "tir"\nchain = ["psf", "motion", "netd", "quantise"]\n[sequence]\nframes = 2\n'
        "approach = {bearing_deg = 0.0, range_m = 100.0, speed_m_s = 10.0}\n"
    )
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / "t")]) == 2
    assert "chain" in capsys.readouterr().err
