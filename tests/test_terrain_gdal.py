"""Line of sight over terrain against independent implementations: GDAL's viewshed and the exact sight line.

GDAL's ``gdal_viewshed`` (Wang et al. 2000, a different algorithm from csuas's R2 rays) comes with
Debian's gdal-bin, which tools/setup.sh installs; without it these tests skip with that reason.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.core.horizon import EARTH_RADIUS_M, K_OPTICAL, K_RADIO
from csuas.core.terrain import gaussian_hills
from csuas.validation.terrain.viewshed_oracles import (
    ViewshedCase,
    compare_viewsheds,
    exact_line_of_sight,
    fractal_dem,
    gdal_available,
    gdal_viewshed,
)

needs_gdal = pytest.mark.skipif(not gdal_available(), reason="GDAL's gdal_viewshed is not installed (gdal-bin)")


@needs_gdal
@pytest.mark.parametrize("row, col", [(200, 200), (120, 300), (330, 80)])
@pytest.mark.parametrize("target_m", [2.0, 30.0, 120.0])
def test_viewshed_agrees_with_gdal_on_hills_but_for_grazing_cells(row, col, target_m):
    """The issue's criterion: >= 99 % of cells agree, and every disagreement grazes (measured 99.76-99.97 %)."""
    case = ViewshedCase(gaussian_hills(400, 25.0), 25.0, row, col, 10.0, target_m, K_RADIO)
    result = compare_viewsheds(case, exact_samples=300)
    assert result["agreement"] >= 0.99
    assert result["disagreeing_grazing"] == 1.0
    assert result["csuas_exact_grazing"] == 1.0


@needs_gdal
@pytest.mark.parametrize("row, col, target_m", [(150, 150, 2.0), (40, 260, 30.0), (150, 150, 120.0)])
def test_on_rough_terrain_the_rays_follow_the_sight_line_closer_than_gdal(row, col, target_m):
    """Slopes up to 46 degrees: csuas meets the exact sight line on >= 99 % of cells, GDAL on fewer.

    Measured (3000 random cells): csuas 99.2-99.8 %, GDAL 96.1-99.1 %; csuas and GDAL agree on
    96.3-98.9 % of all cells, so there the gap to the issue's 99 % is GDAL's own approximation.
    """
    dem = fractal_dem(300, 300.0, 1.6, seed=1)
    result = compare_viewsheds(
        ViewshedCase(dem, 30.0, row, col, 10.0, target_m, K_OPTICAL), exact_samples=1500, seed=row
    )
    assert result["csuas_exact"] >= 0.99
    assert result["csuas_exact_grazing"] == 1.0
    assert result["csuas_exact"] >= result["gdal_exact"]


@needs_gdal
def test_gdal_is_given_csuas_curvature():
    """GDAL on a flat DEM sees to the two radio horizons sqrt(2 k R h_s) + sqrt(2 k R h_t) (35.60 km)."""
    cell = 100.0
    visible = gdal_viewshed(np.zeros((801, 801)), cell, 400, 400, 10.0, 30.0, K_RADIO)
    rr, cc = np.indices(visible.shape)
    distance = np.hypot(rr - 400, cc - 400) * cell
    limit = math.sqrt(2 * K_RADIO * EARTH_RADIUS_M * 10.0) + math.sqrt(2 * K_RADIO * EARTH_RADIUS_M * 30.0)
    clear = np.abs(distance - limit) > 1.5 * cell
    assert np.array_equal(visible[clear], (distance <= limit)[clear])


def test_exact_sight_line_casts_a_walls_closed_form_shadow():
    """A 40 m wall 50 cells from a 5 m eye hides a 100 m target beyond 50 (100 - 5) / (40 - 5) = 135.7 cells."""
    dem = np.zeros((3, 301))
    dem[:, 50] = 40.0  # the bilinear surface's crest is the column itself
    cols = np.arange(51, 301)
    visible = exact_line_of_sight(dem, 10.0, 1, 0, 5.0, 100.0, 1e12, np.stack([np.ones_like(cols), cols], 1))
    assert np.array_equal(visible, cols <= 50 * 95 / 35)
