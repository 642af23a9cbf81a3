"""A layered fog's slant transmittance rendered through a Mitsuba fog slab against exp(-beta L_fog)."""

from __future__ import annotations

import math

import pytest

from csuas.render.imaging.fog_slab import fog_slab_transmittance

BETA_PER_KM, TOP_M, GROUND_M = 19.56, 50.0, 300.0  # 200 m visibility (Koschmieder), fog up to 50 m, 300 m apart


@pytest.mark.parametrize(
    "h_s, h_d, ground, fraction",
    [
        (2.0, 102.0, GROUND_M, 0.48),  # crossing the top upward
        (120.0, 10.0, GROUND_M, 40.0 / 110.0),  # crossing it downward
        (2.0, 30.0, 100.0, 1.0),  # fully inside (100 m apart: T = 0.13)
    ],
)
def test_rendered_slab_transmittance_is_the_closed_form(h_s, h_d, ground, fraction):
    """L_fog / R by hand ((h_top - h_low) / (h_high - h_low)); Monte Carlo agreement within 4 standard errors."""
    out = fog_slab_transmittance(h_s, h_d, ground, TOP_M, BETA_PER_KM, samples_per_pixel=512, seed=3)
    slant = math.hypot(ground, h_d - h_s)
    assert out["slant_range_m"] == pytest.approx(slant, rel=1e-12)
    closed = math.exp(-BETA_PER_KM * fraction * slant / 1000.0)
    assert 0 < out["stderr"] < 0.2 * closed
    assert abs(out["transmittance"] - closed) < 4 * out["stderr"], (out, closed)


def test_path_above_the_fog_renders_clear():
    out = fog_slab_transmittance(60.0, 100.0, GROUND_M, TOP_M, BETA_PER_KM, samples_per_pixel=64)
    assert out["transmittance"] == 1.0 and out["stderr"] == 0.0
