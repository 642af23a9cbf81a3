"""Line of sight over terrain (core/terrain.py) against closed-form horizons and shadows.

* A smooth Earth: the farthest visible cell from a sensor on a mast against the sum of the two
  horizons, sqrt(2 k R h_s) + sqrt(2 k R h_t) (ITU-R P.834-9 Eq. 1), for radio (k = 4/3) and light.
* A straight wall: the end of its shadow on a target behind it against the straight line through the
  crest, x = D (h_t - h_s) / (H - h_s).
"""

from __future__ import annotations

import math

import numpy as np

from csuas.base.checks import Check
from csuas.core.horizon import EARTH_RADIUS_M, K_OPTICAL, K_RADIO
from csuas.validation.report.registry import CheckSpec, Section, timed

#: Grid cell of the smooth-Earth check [m] and the tolerance: the method judges cells within 1.5 cells of
#: the horizon on a path up to half a cell off their own line.
SMOOTH_CELL_M = 100.0
WALL_CELL_M = 10.0


def _farthest_visible_m(visible: np.ndarray, row: float, col: float, cell: float) -> float:
    rr, cc = np.indices(visible.shape)
    return float(np.hypot(rr - row, cc - col)[visible].max() * cell)


def terrain(_knob=None) -> Section:
    """The viewshed's horizons and shadows against their closed forms."""
    from csuas.core.terrain import viewshed

    s = Section()
    flat = np.zeros((901, 901))
    for name, k in (("radio", K_RADIO), ("optical", K_OPTICAL)):
        visible, elapsed = timed(viewshed, flat, SMOOTH_CELL_M, 450.0, 450.0, 10.0, 30.0, k)
        horizon = math.sqrt(2 * k * EARTH_RADIUS_M * 10.0) + math.sqrt(2 * k * EARTH_RADIUS_M * 30.0)
        s.outcomes.append(
            Check(
                f"terrain.smooth_earth.{name}.farthest_visible_m",
                horizon,
                _farthest_visible_m(visible, 450.0, 450.0, SMOOTH_CELL_M),
                1.5 * SMOOTH_CELL_M,
                "m",
                time_s=elapsed,
                source="sum of the two horizons sqrt(2 k R h) (ITU-R P.834-9 Eq. 1), k = "
                f"{k:.4g}, 10 m mast, 30 m flight level",
                method=f"R2 viewshed of a flat 90 km square in {SMOOTH_CELL_M:g} m cells",
                tolerance_source="1.5 cells: cells graze the horizon on a path within half a cell of their line",
            )
        )
    wall = np.zeros((101, 401))
    wall[:, 50] = 40.0
    visible, elapsed = timed(viewshed, wall, WALL_CELL_M, 50.0, 0.0, 5.0, 100.0, 1e12)
    behind = np.flatnonzero(~visible[50, 51:]) + 51
    shadow_start = float(behind.min() * WALL_CELL_M) if behind.size else float("inf")
    expected = 50 * WALL_CELL_M * (100.0 - 5.0) / (40.0 - 5.0)
    s.outcomes.append(
        Check(
            "terrain.wall.shadow_start_m",
            expected,
            shadow_start,
            2 * WALL_CELL_M,
            "m",
            time_s=elapsed,
            source="the straight line through the crest: D (h_t - h_s) / (H - h_s)",
            method="a 40 m wall 500 m from a 5 m eye, a 100 m flight level behind it, no curvature",
            tolerance_source="2 cells: the sample nearest the crest and the cell's own half-cell path",
        )
    )
    return s


SPECS = [
    CheckSpec(
        "terrain.line_of_sight",
        "Line of sight over terrain vs closed-form horizons and shadows",
        "terrain",
        "the R2 viewshed's farthest visible cell and a wall's shadow vs their closed forms",
        "1.5 cells (horizon), 2 cells (shadow)",
        terrain,
        None,
        {},
        False,
    ),
]
