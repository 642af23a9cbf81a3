"""Difficulty annotations of csuas dataset objects (render/imaging/difficulty.py): local contrast, background class."""

from __future__ import annotations

import numpy as np
import pytest

from csuas.render.imaging.difficulty import RING_PX, annotation_difficulty, background_class, local_contrast


def test_the_local_contrast_of_a_box_on_a_checkerboard_ring_is_its_closed_form():
    # background b +- s in a checkerboard: the ring's mean is b and its standard deviation exactly s (ddof 0) when
    # the ring holds as many + as - pixels; the object a over its mask
    a, b, s = 900.0, 1000.0, 12.5
    rows, cols = np.indices((200, 300))
    dn = b + s * np.where((rows + cols) % 2 == 0, 1.0, -1.0)
    x, y, w, h = 100, 80, 20, 10  # the ring: (20 + 16) x (10 + 16) - 20 x 10 = 736 px, an even count on both colours
    mask = np.zeros(dn.shape, bool)
    mask[y + 2 : y + 8, x + 3 : x + 17] = True
    dn[mask] = a
    out = local_contrast(dn, mask, [x, y, w, h])
    assert out["ring_px"] == (w + 2 * RING_PX) * (h + 2 * RING_PX) - w * h
    assert out["ring_mean_dn"] == pytest.approx(b, abs=1e-12) and out["ring_sigma_dn"] == pytest.approx(s, rel=1e-12)
    assert out["local_contrast"] == pytest.approx((a - b) / s, rel=1e-12)


def test_a_ring_cut_by_the_frame_edge_keeps_its_pixels_inside_and_a_flat_ring_has_no_finite_contrast():
    dn = np.full((50, 60), 100.0)
    mask = np.zeros(dn.shape, bool)
    mask[0:4, 0:5] = True
    dn[mask] = 140.0
    out = annotation_difficulty(dn, mask, [0, 0, 5, 4], None)
    assert out["ring_px"] == (5 + RING_PX) * (4 + RING_PX) - 20  # only the right and lower sides lie in the frame
    assert out["local_contrast"] is None and out["background_class"] == "uniform"


def test_the_background_class_follows_the_horizon_of_a_level_view():
    # looking level (elevation 0) at a target in the frame's centre: the rays of rows above the centre row
    # (n_v // 2 + 0.5 = 540.5) point up (sky), those at or below it down (terrain)
    horizon = {"kind": "horizon", "frame": (1920, 1080), "ifov_rad": 1e-4, "azimuth_deg": 30.0}
    horizon.update(elevation_deg=0.0, target_offset_px=(0.0, 0.0), clouds=None)
    assert background_class([900, 500, 40, 40], horizon) == "sky"  # rows 500-539
    assert background_class([900, 530, 40, 20], horizon) == "skyline"
    assert background_class([900, 541, 40, 20], horizon) == "terrain"
    clouds = np.zeros((1080, 1920))
    clouds[490:545, 890:950] = 1.0
    assert background_class([900, 500, 40, 40], {**horizon, "clouds": clouds}) == "cloud"
    assert background_class([900, 500, 40, 40], {"kind": "sky"}) == "sky"


def _level_rays(n_h: int = 200, n_v: int = 400, ifov: float = 1e-3, elevation_deg: float = 0.0):
    from csuas.render.imaging.clutter import frame_rays

    item = {"azimuth_deg": 0.0, "elevation_deg": elevation_deg, "target_offset_px": (0.0, 0.0)}
    return frame_rays(n_h, n_v, ifov, item), ifov


def test_a_power_line_covers_each_column_by_its_angular_width_at_its_catenarys_height():
    from csuas.render.imaging.clutter import CONDUCTOR_DIAMETER_M, SURFACES, _power_line

    rays, ifov = _level_rays(elevation_deg=-3.0)  # the view 3 deg up: the wires are in the frame
    context = {"band": "eo", "illuminance_lx": 1e4, "ambient_k": 290.0, "ifov_rad": ifov, "camera_height_m": 10.0}
    forward = np.array([rays[200, 100, 0], rays[200, 100, 1]]) / np.hypot(*rays[200, 100, :2])
    coverage, light, _ = _power_line(rays, forward, 100.0, 150.0, context)  # mid-span at the frame's centre column
    assert light == pytest.approx(SURFACES["power_line"][0] * 1e4 / np.pi)
    column = rays[:, 100]
    along = 100.0 / float(column[0] @ [forward[0], forward[1], 0.0])  # slant distance factor of the centre column
    ground = along * float(np.hypot(column[0, 0], column[0, 1]))
    # mid-span the wire hangs a (cosh(150 / a) - 1) = 11.3 m below the 25 m towers: 25 - 10 - 11.27 m above the camera
    sag = 1000.0 * (np.cosh(0.15) - 1.0)
    height = 15.0 - sag
    assert coverage[:, 100].sum() == pytest.approx(CONDUCTOR_DIAMETER_M / np.hypot(ground, height) / ifov, rel=1e-3)
    row = float(np.sum(np.arange(400) * coverage[:, 100]) / coverage[:, 100].sum())
    elevation = np.degrees(np.arcsin(rays[:, 100, 2]))
    assert np.interp(row, np.arange(400), elevation) == pytest.approx(np.degrees(np.arctan2(height, ground)), abs=0.06)


def test_clutter_builds_only_the_layers_a_spec_declares_and_maps_their_classes():
    from csuas.render.imaging.clutter import CLASSES, clutter_layers
    from csuas.render.imaging.dataset_schema import ClutterSchema

    rays, ifov = _level_rays()
    context = {"band": "eo", "illuminance_lx": 1e4, "ambient_k": 290.0, "ifov_rad": ifov}
    layers, codes = clutter_layers(rays, ClutterSchema(), context, 1)
    assert layers == [] and set(np.unique(codes)) == {CLASSES.index("sky"), CLASSES.index("terrain")}
    layers, codes = clutter_layers(rays, ClutterSchema(terrain=True), context, 1)
    assert len(layers) == 1
    below = rays[..., 2] < -1e-6
    assert set(np.unique(codes[below])) <= {CLASSES.index(n) for n in ("grass", "forest", "road", "buildings")}
    assert (codes[rays[..., 2] > 0] == CLASSES.index("sky")).all() and (layers[0][0] == below).all()


def test_the_suns_ghosts_lie_on_the_line_through_the_frames_centre_and_the_sun_is_where_the_spec_puts_it():
    from csuas.drone_models.geometry import direction_vector
    from csuas.render.imaging.background import view_rays
    from csuas.render.imaging.clutter import GHOSTS, ghost_centres, sun_direction, sun_pixel

    size, ifov = (1920, 1080), np.radians(10.0) / 1920
    sun = sun_pixel(size, ifov, (2.5, 1.0))
    assert sun == pytest.approx((960 + np.tan(np.radians(2.5)) / ifov, 540 - np.tan(np.radians(1.0)) / ifov))
    for (g, _), (x, y) in zip(GHOSTS, ghost_centres(sun, size)):
        # on the line: (x - cx, y - cy) = g (sx - cx, sy - cy)
        assert (x - 960, y - 540) == pytest.approx((g * (sun[0] - 960), g * (sun[1] - 540)), abs=1e-9)
    item = {"azimuth_deg": 40.0, "elevation_deg": -12.0, "target_offset_px": (30.0, -20.0)}
    azimuth, elevation = sun_direction(size, ifov, item, (2.5, 1.0))
    rays = view_rays(*size, ifov, 40.0, -12.0, (30.0, -20.0))
    col, row = int(sun[0]), int(sun[1])  # the pixel holding the sun's image; its centre within half a pixel
    assert np.degrees(np.arccos(rays[row, col] @ direction_vector(azimuth, elevation))) < np.degrees(ifov)


def test_a_lens_flare_needs_a_sun():
    from csuas.base.errors import InputErrors
    from csuas.render.imaging.dataset import parse_dataset_spec

    with pytest.raises(InputErrors) as caught:
        parse_dataset_spec({"clutter": {"lens_flare": True}})
    assert "clutter.lens_flare" in str(caught.value)


def test_a_relief_terrains_rays_end_on_the_fractal_dem():
    from csuas.render.imaging.clutter import RELIEF_CELL_M, _relief_hits, frame_rays, value_noise
    from csuas.render.imaging.dataset_schema import ClutterSchema

    ifov = np.radians(10.0) / 640
    rays = frame_rays(640, 360, ifov, {"azimuth_deg": 30.0, "elevation_deg": 1.0, "target_offset_px": (0.0, 0.0)})
    ground, x, y, distance = _relief_hits(rays, ClutterSchema(terrain=True, relief_m=60.0), ifov, 7)
    assert 0.5 < ground.mean() < 0.9  # looking 1 deg down from 10 m: ground below, sky above the skyline
    # the DEM 60 m x noise (seed + 7) relative to the ground under the camera; the ray from 10 m above it
    origin = value_noise(np.zeros(1), np.zeros(1), 14, RELIEF_CELL_M, 5)[0]
    dem = 60.0 * (value_noise(x, y, 14, RELIEF_CELL_M, 5, distance * ifov) - origin)
    ray = 10.0 + distance * np.tan(np.arcsin(rays[..., 2][ground]))
    # profile samples 2.4 % of the distance apart, interpolated: within centimetres but at ridges' occlusion edges
    assert np.median(np.abs(ray - dem)) < 0.01 and np.percentile(np.abs(ray - dem), 99) < 0.05
