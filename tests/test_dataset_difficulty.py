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
