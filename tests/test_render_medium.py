"""Fog as a homogeneous participating medium (volumetric path tracing) against the analytic Koschmieder airlight."""

from __future__ import annotations

import math

import pytest

from csuas.render.imaging import Quality
from csuas.render.imaging.records import RenderSettings, View
from csuas.render.imaging.targets import plate
from csuas.validation.imaging.medium import medium_vs_analytic_airlight

pytestmark = pytest.mark.slow


@pytest.mark.parametrize("range_m,visibility_km,n_side", [(300.0, 0.5, 6), (1500.0, 5.0, 24)])
def test_medium_agrees_with_analytic_airlight(range_m, visibility_km, n_side):
    out = medium_vs_analytic_airlight(
        plate(width_m=0.3, height_m=0.3, reflectance=0.05),
        View(range_m),
        visibility_km=visibility_km,
        settings=RenderSettings(quality=Quality("t", n_side, 8)),
    )
    beta = math.log(50.0) / visibility_km  # [1/km], Kruse factor 1 at 550 nm
    assert out["transmittance"] == pytest.approx(math.exp(-beta * range_m / 1000.0), rel=1e-12)
    assert 0.05 < out["transmittance"] < 0.5  # the path matters: airlight dominates or competes
    assert out["difference_sigma"] < 4.0
    assert out["medium_stderr"] < 0.01 * out["medium_radiance"]
    assert out["medium_radiance"] == pytest.approx(out["analytic_radiance"], rel=0.025)
