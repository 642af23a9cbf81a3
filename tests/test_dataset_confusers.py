"""Confusers of csuas dataset frames (render/imaging/confusers.py): birds, a light aircraft, insects near the lens."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas import cli
from csuas.base.errors import InputErrors
from csuas.render.imaging.dataset import class_names, draws, parse_dataset_spec


def test_the_light_aircraft_has_the_cessna_172s_published_dimensions():
    from csuas.drone_models.aircraft import build_light_aircraft

    # Cessna 172S POH Section 1: length 8.28 m, span 11.0 m, height 2.72 m
    assert build_light_aircraft().extents() == pytest.approx([8.28, 11.0, 2.72], abs=1e-9)


def test_an_insect_blurs_as_a_thin_lens_focused_at_infinity_images_it():
    from csuas.render.imaging.confusers import defocus_blur_px

    # thin lens 1/f = 1/d + 1/v: the image of a point at d lies at v = f d / (d - f) behind the lens; on the film at f
    # the cone of the aperture A = f / N has the diameter A (v - f) / v
    pitch, ifov, n, d = 2.9e-6, math.radians(10.0) / 1920, 2.0, 0.5
    f = pitch / ifov
    v = f * d / (d - f)
    assert defocus_blur_px(d, n, pitch * 1e6, ifov) == pytest.approx((f / n) * (v - f) / v / pitch, rel=1e-12)


def test_confuser_counts_and_classes_are_checked_with_their_key_paths():
    with pytest.raises(InputErrors) as caught:
        parse_dataset_spec(
            {"confusers": {"birds": -1, "insects": {"min": 3, "max": 1}, "bird_classes": ["crow"], "planes": 1}}
        )
    text = str(caught.value)
    for key in ("confusers.birds", "confusers.insects.max", "confusers.bird_classes", "confusers.planes"):
        assert key in text


def test_confuser_classes_follow_the_drones_and_each_frame_draws_them_from_its_own_stream():
    plain = {"seed": 4, "count": 3, "drones": ["dji_mini_4_pro", "black_hornet_3"]}
    spec = parse_dataset_spec(
        {**plain, "confusers": {"birds": {"min": 1, "max": 2}, "bird_classes": ["gull"], "insects": 1}}
    )
    assert class_names(spec) == ["dji_mini_4_pro", "black_hornet_3", "gull", "insect"]
    items = draws(spec, (1920, 1080))
    without = draws(parse_dataset_spec(plain), (1920, 1080))
    assert [{k: v for k, v in i.items() if k != "confusers"} for i in items] == without  # the drones' draws unchanged
    for item in items:
        kinds = [c["class"] for c in item["confusers"]]
        assert kinds.count("insect") == 1 and 1 <= kinds.count("gull") <= 2
        assert all(0.5 <= c["range_m"] <= 3.0 for c in item["confusers"] if c["class"] == "insect")


def _uniform_frame_with(draw: dict, n_h: int = 320, n_v: int = 240) -> tuple:
    from csuas.render.imaging.confusers import eo_confusers, eo_render_settings
    from csuas.render.imaging.records import Daylight, EoSensor

    sensor = EoSensor(hfov_deg=4.0, n_h=n_h, n_v=n_v)
    params = {"f_number": 2.0, "pixel_pitch_um": 2.9}
    render = eo_render_settings(sensor, Daylight(), "draft", 1, params, 288.15)
    ifov = math.radians(sensor.hfov_deg) / n_h
    frame = np.full((n_v, n_h), 3000.0)
    return frame, eo_confusers(frame, [draw], ifov, render)[0], sensor, ifov


def test_a_birds_box_is_its_projected_mesh_within_a_pixel():
    from csuas.drone_models.birds import build_bird
    from csuas.render.imaging.camera import SensorGeometry
    from csuas.render.imaging.common import silhouette_box_px

    draw = {"class": "gull", "range_m": 60.0, "azimuth_deg": 70.0, "elevation_deg": -15.0}
    draw.update(target_offset_px=(23.4, -11.7), wingbeat_phase=0.1, length_m=0.01, confuser_id=1)
    frame, lab, sensor, ifov = _uniform_frame_with(draw)
    geometry = SensorGeometry(ifov, sensor.n_h, sensor.n_v)
    cx, cy = geometry.default_target_px()
    bird = build_bird("gull", 0.1, 288.15)
    x_lo, x_hi, y_lo, y_hi = silhouette_box_px(bird, 60.0, 70.0, -15.0, geometry, (cx + 23.4, cy - 11.7))
    x, y, w, h = lab["bbox"]
    assert abs(x - x_lo) < 1 and abs(x + w - x_hi) < 1 and abs(y - y_lo) < 1 and abs(y + h - y_hi) < 1
    assert not lab["clipped"] and lab["visibility"] == 1.0
    assert (frame != 3000.0).sum() == pytest.approx(lab["area"], abs=0)  # pasted exactly where it is labelled


def test_an_insect_near_the_lens_is_a_faint_disk_as_wide_as_its_silhouette_plus_the_blur():
    from csuas.render.imaging.confusers import INSECT_REFLECTANCE, defocus_blur_px

    draw = {"class": "insect", "range_m": 1.0, "azimuth_deg": 0.0, "elevation_deg": 0.0, "target_offset_px": (0, 0)}
    draw.update(wingbeat_phase=0.0, length_m=0.01, confuser_id=1)
    frame, lab, sensor, ifov = _uniform_frame_with(draw)
    blur = defocus_blur_px(1.0, 2.0, 2.9, ifov)
    size = 0.01 / 1.0 / ifov  # the body's length [px]
    assert lab["bbox"][2] == pytest.approx(size + blur, abs=3.0)  # the support of silhouette (x) disk
    # the frame blends to the insect by its coverage, pixel by pixel: the light it blocks sums to its coverage
    from csuas.render.imaging.records import Daylight

    insect = INSECT_REFLECTANCE * Daylight().illuminance_lx / math.pi
    blocked = float(np.sum((3000.0 - frame) / (3000.0 - insect)))
    assert blocked == pytest.approx(lab["pixels_on_target"], rel=1e-6)


@pytest.mark.slow
def test_a_dataset_labels_confusers_as_their_own_classes_in_coco_yolo_and_mot(tmp_path, capsys):
    spec = tmp_path / "c.toml"
    spec.write_text(
        'seed = 2\ndrones = ["dji_mini_4_pro"]\nchain = ["psf", "quantise"]\n'
        "[sequence]\nframes = 2\nwaypoints_m = [[-1.0, 60.0, 0.0], [1.0, 60.0, 0.0]]\nspeed_m_s = 10.0\n"
        '[confusers]\nbirds = 1\nbird_classes = ["pigeon"]\nbird_range_m = {min = 40.0, max = 40.0}\n'
    )
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / "c")]) == 0
    capsys.readouterr()
    coco = json.loads((tmp_path / "c" / "annotations.json").read_text())
    assert coco["categories"][1] == {"id": 2, "name": "pigeon", "supercategory": "confuser"}
    birds = [a for a in coco["annotations"] if a["category_id"] == 2]
    assert [a["track_id"] for a in birds] == [1001, 1001]
    # pigeon wingbeat 5.5 Hz: the phase advances by 5.5 / 30 of a cycle a frame
    phases = [a["csuas"]["wingbeat_phase"] for a in birds]
    assert (phases[1] - phases[0]) % 1.0 == pytest.approx(5.5 / 30.0, abs=1e-9)
    gt = (tmp_path / "c" / "mot" / "001_dji_mini_4_pro" / "gt" / "gt.txt").read_text().splitlines()
    assert sorted(int(line.split(",")[1]) for line in gt) == [1, 1, 1001, 1001]
    assert "1: pigeon" in (tmp_path / "c" / "data.yaml").read_text()
    yolo = (tmp_path / "c" / "labels" / "000000_dji_mini_4_pro.txt").read_text().splitlines()
    assert sorted(line.split()[0] for line in yolo) == ["0", "1"]
    rows = (tmp_path / "c" / "difficulty.csv").read_text().splitlines()
    assert rows[0].startswith("file_name,category,track_id,x,y,w,h,background_class,local_contrast")
    assert sorted(row.split(",")[1] for row in rows[1:]) == ["dji_mini_4_pro", "dji_mini_4_pro", "pigeon", "pigeon"]
    assert all(a["csuas"]["background_class"] == "sky" for a in coco["annotations"])  # the render's uniform sky


def test_a_layer_beyond_the_drone_changes_only_the_background_its_uncovered_share_shows():
    from csuas.render.imaging.compose import DroneWindow, blend

    # a 1 x 3 drone window: covered fully, half, not at all; its own light 7 where it covers, uniform U = 2
    u, own, uniform, background = np.array([[0.0, 0.5, 1.0]]), 7.0, 2.0, 5.0
    rendered = (1.0 - u) * own + u * uniform
    frame = np.full((2, 5), background)
    frame[0, 1:4] = rendered + u * (background - uniform)
    drone = DroneWindow(1, 0, rendered, u, uniform, 100.0)
    alpha, light = np.full((2, 5), 0.4), np.full((2, 5), 0.4 * 11.0)  # a layer of light 11 at 40 % opacity
    under = frame.copy()
    blend(under, (0, 0), alpha, light, drone)
    behind = 0.6 * background + 0.4 * 11.0
    assert under[0, 1:4] == pytest.approx(rendered[0] + u[0] * (behind - uniform), rel=1e-12)
    assert under[1] == pytest.approx(np.full(5, behind), rel=1e-12) and under[0, 0] == pytest.approx(behind)
    over = frame.copy()
    blend(over, (0, 0), alpha, light, None)
    assert over == pytest.approx(0.6 * frame + 0.4 * 11.0, rel=1e-12)


def test_the_cost_estimate_adds_a_window_render_per_mesh_confuser_and_clutter_per_pixel(tmp_path):
    from csuas.render.imaging import dataset_cost as cost

    plain = parse_dataset_spec({"count": 10})
    layered = parse_dataset_spec(
        {"count": 10, "confusers": {"birds": {"min": 1, "max": 3}, "aircraft": 1, "insects": 2}, "clutter": {}}
    )
    pixels = 1920 * 1080
    a, b = (cost.dataset_estimate(s, (1920, 1080), tmp_path / "none") for s in (plain, layered))
    # a mean of 2 birds and 1 aircraft rendered in their windows, 2 insects blurred, the clutter over every pixel
    extra = 3 * cost.WINDOW_SECONDS["draft"] + 2 * cost.INSECT_SECONDS + cost.CLUTTER_PIXEL_SECONDS * pixels
    assert b.seconds - a.seconds == pytest.approx(10 * extra, rel=1e-12)
    assert b.bytes - a.bytes == pytest.approx(cost.CLUTTER_PIXEL_BYTES * pixels, rel=1e-12)


@pytest.mark.slow
def test_thermal_clutter_puts_clouds_between_the_cold_sky_and_the_air_and_warm_land_below_the_horizon(tmp_path):
    import OpenEXR

    from csuas.core.scenario import load_scenario

    air = load_scenario("default").environment["temperature_k"]
    spec = tmp_path / "t.toml"
    spec.write_text(
        'sensor = "tir"\nsky_temperature_k = 230.0\ndrones = ["dji_mini_4_pro"]\nrange_m = [150.0]\n'
        'elevation_deg = [-1.0]\nposition = "centre"\nchain = ["quantise"]\nexr = true\n'
        "[clutter]\nterrain = true\nclouds = 0.5\n"
    )
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / "t")]) == 0
    with OpenEXR.File(str(tmp_path / "t" / "images" / "000000_dji_mini_4_pro.exr")) as exr:
        kelvin = exr.channels()["Y"].pixels
    sky, ground = kelvin[:100], kelvin[-100:]
    # clear sky at 230 K, clouds up to 12 K below the air (opaque where thick), nothing warmer than the clouds
    assert sky.min() == pytest.approx(230.0, abs=0.01) and sky.max() == pytest.approx(air - 12.0, abs=0.05)
    # land cover: emissivity 0.92-0.98 at 1-15 K above the air, the rest the air's reflection
    assert air + 0.9 < ground.min() and ground.max() < air + 15.0
    coco = json.loads((tmp_path / "t" / "annotations.json").read_text())
    assert coco["annotations"][0]["csuas"]["background_class"] in ("sky", "cloud", "skyline")
