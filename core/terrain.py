"""Line of sight over terrain: which cells of a DEM a sensor sees at a flight level above the ground.

The Earth's curvature with standard refraction drops a point at ground distance d below the
sensor's tangent plane by d^2 / (2 k R_E) (k = 4/3 for radio, 7/6 for light near the ground:
refraction coefficient 0.13 in :mod:`csuas.core.horizon`; ITU-R P.834-9 Eq. 1). A target at
height h above the terrain at distance d is seen when its elevation angle from the sensor is at
least the largest elevation angle of the terrain between them.

The viewshed is computed by rays (the "R2" method of Franklin & Ray, *Higher isn't necessarily
better: visibility algorithms and experiments*, 1994): rays leave the sensor toward every boundary
cell of the DEM, the terrain is sampled along each at half-cell steps (bilinear interpolation),
and the running maximum of the terrain's elevation angle along the ray is the horizon each sample
must clear. Every cell takes the horizon of the ray sample nearest to it, so a cell is judged
against the terrain of a path within half a cell of its own line: the method's error is confined to
cells that graze the horizon. Vectorised over rays and samples with NumPy. A maximum distance stops the
rays there: the horizon being a running maximum from the sensor out, every cell within it is judged
exactly as without the limit, and only the samples beyond it are saved.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require
from csuas.core.horizon import EARTH_RADIUS_M


def curvature_drop_m(distance_m, k_factor):
    """Drop of the Earth's surface below the tangent plane at ground distance d: d^2 / (2 k R_E) [m]."""
    d = require("distance_m", distance_m, ge=0)
    k = require("k_factor", k_factor, gt=0)
    return d * d / (2.0 * k * EARTH_RADIUS_M)


def height_at(dem: np.ndarray, rows, cols) -> np.ndarray:
    """DEM heights [m] at fractional (row, col) cell positions, bilinear, clamped to the grid."""
    n_r, n_c = dem.shape
    r = np.clip(rows, 0.0, n_r - 1.0)
    c = np.clip(cols, 0.0, n_c - 1.0)
    r0 = np.minimum(np.floor(r).astype(int), n_r - 2) if n_r > 1 else np.zeros_like(r, dtype=int)
    c0 = np.minimum(np.floor(c).astype(int), n_c - 2) if n_c > 1 else np.zeros_like(c, dtype=int)
    fr, fc = r - r0, c - c0
    r1, c1 = np.minimum(r0 + 1, n_r - 1), np.minimum(c0 + 1, n_c - 1)
    return (
        dem[r0, c0] * (1 - fr) * (1 - fc)
        + dem[r0, c1] * (1 - fr) * fc
        + dem[r1, c0] * fr * (1 - fc)
        + dem[r1, c1] * fr * fc
    )


def bearing_deg(d_row, d_col):
    """Bearing of a grid offset, clockwise from grid north (rows run south, columns east) [deg], 0..360."""
    return np.degrees(np.arctan2(d_col, -np.asarray(d_row, dtype=float))) % 360.0


def off_boresight_deg(bearing, azimuth_deg):
    """Signed azimuth of a bearing from the boresight [deg], wrapped to -180..180 (clockwise positive)."""
    return (np.asarray(bearing, dtype=float) - azimuth_deg + 180.0) % 360.0 - 180.0


def cells_around(shape, row: float, col: float, radius_cells: float) -> tuple[slice, slice]:
    """Rows and columns of a grid of ``shape`` within ``radius_cells`` of (row, col) each way (inf: all)."""
    if not np.isfinite(radius_cells):
        return slice(0, shape[0]), slice(0, shape[1])
    rows = slice(max(int(np.floor(row - radius_cells)), 0), min(int(np.ceil(row + radius_cells)) + 1, shape[0]))
    cols = slice(max(int(np.floor(col - radius_cells)), 0), min(int(np.ceil(col + radius_cells)) + 1, shape[1]))
    return rows, cols


def viewshed(
    dem_m: np.ndarray,
    cell_m: float,
    sensor_row: float,
    sensor_col: float,
    sensor_height_m: float,
    target_height_m,
    k_factor: float = 4.0 / 3.0,
    max_distance_m: float | None = None,
    sector_deg: tuple[float, float] | None = None,
) -> np.ndarray:
    """Cells of the DEM where a target ``target_height_m`` above the terrain is in the sensor's line of sight.

    Parameters
    ----------
    dem_m : ndarray (rows, cols)
        Terrain heights [m], finite, on square cells.
    cell_m : float
        Cell size [m].
    sensor_row, sensor_col : float
        The sensor's position in (fractional) cell coordinates, inside the grid.
    sensor_height_m : float
        The sensor's height above the terrain under it (its mast) [m], >= 0.
    target_height_m : float or ndarray (rows, cols)
        The target's height above the terrain of each cell (the flight level) [m], >= 0.
    k_factor : float
        Effective Earth-radius factor (4/3 radio; 1 / (1 - 0.13) for light).
    max_distance_m : float, optional
        Farthest ground distance from the sensor traced [m], > 0: the rays stop there (no sample beyond
        it is computed) and cells farther away come out not visible. Inside it the result is the
        untruncated viewshed's, cell for cell (the horizon is a running maximum from the sensor out).
        None: the whole grid.
    sector_deg : (float, float), optional
        ``(azimuth, width)`` [deg]: only the rays whose bearing (:func:`bearing_deg`) lies within
        ``width / 2`` of ``azimuth``, and one ray spacing beyond, are traced, and cells outside the
        sector come out not visible (the sensor's own cell excepted). Inside it the result is the
        all-round viewshed's, cell for cell (each cell keeps its nearest ray). None: all round.

    Returns
    -------
    ndarray bool (rows, cols)
        True where the target is visible (the sensor's own cell always).
    """
    dem = np.asarray(dem_m, dtype=float)
    if dem.ndim != 2 or min(dem.shape) < 2 or not np.isfinite(dem).all():
        raise ParameterError("dem_m", f"array of shape {dem.shape}", "a finite 2-D grid of at least 2 x 2 cells")
    cell = float(require("cell_m", cell_m, gt=0))
    n_r, n_c = dem.shape
    if not (0.0 <= sensor_row <= n_r - 1 and 0.0 <= sensor_col <= n_c - 1):
        raise ParameterError(
            "sensor position", (sensor_row, sensor_col), f"inside the grid 0..{n_r - 1} x 0..{n_c - 1}"
        )
    h_target = np.broadcast_to(require("target_height_m", target_height_m, ge=0), dem.shape)
    eye = float(height_at(dem, np.array([sensor_row]), np.array([sensor_col]))[0]) + float(
        require("sensor_height_m", sensor_height_m, ge=0)
    )
    farthest = np.hypot(max(sensor_row, n_r - 1 - sensor_row), max(sensor_col, n_c - 1 - sensor_col))  # [cells]
    limit = np.inf if max_distance_m is None else float(require("max_distance_m", max_distance_m, gt=0)) / cell
    span = min(farthest, limit)  # [cells]
    # rays toward every boundary cell, sampled every half cell out to the farthest corner or the limit
    boundary = np.concatenate(
        [
            np.stack([np.zeros(n_c), np.arange(n_c)], 1),
            np.stack([np.full(n_c, n_r - 1.0), np.arange(n_c)], 1),
            np.stack([np.arange(n_r), np.zeros(n_r)], 1),
            np.stack([np.arange(n_r), np.full(n_r, n_c - 1.0)], 1),
        ]
    )
    angle = np.unique(np.arctan2(boundary[:, 0] - sensor_row, boundary[:, 1] - sensor_col))
    if sector_deg is not None:
        azimuth = float(require("sector azimuth_deg", sector_deg[0], ge=0, le=360))
        width = float(require("sector width_deg", sector_deg[1], gt=0, le=360))
        spacing = np.degrees(np.max(np.diff(angle)))  # the widest gap between neighbouring rays
        aside = np.abs(off_boresight_deg(bearing_deg(np.sin(angle), np.cos(angle)), azimuth))
        angle = angle[aside <= width / 2 + spacing]
    steps = np.arange(1, int(np.ceil(2 * span)) + 1) * 0.5  # [cells]
    rows = sensor_row + np.sin(angle)[:, None] * steps[None, :]
    cols = sensor_col + np.cos(angle)[:, None] * steps[None, :]
    distance = steps * cell
    drop = curvature_drop_m(distance, k_factor)
    terrain = height_at(dem, rows, cols) - drop[None, :]
    slope = (terrain - eye) / distance[None, :]  # tangent of the terrain's elevation angle
    horizon = np.maximum.accumulate(slope, axis=1)
    before = np.concatenate([np.full((len(angle), 1), -np.inf), horizon[:, :-1]], axis=1)  # what a sample must clear
    # every cell within the limit looks up the ray nearest to its bearing and the sample nearest to its distance
    window = cells_around(dem.shape, sensor_row, sensor_col, span)
    rr, cc = np.meshgrid(
        np.arange(window[0].start, window[0].stop), np.arange(window[1].start, window[1].stop), indexing="ij"
    )
    dr, dc = rr - sensor_row, cc - sensor_col
    bearing = np.arctan2(dr, dc)
    ray = np.searchsorted(angle, bearing)
    ray = np.where(
        (ray == len(angle))
        | (
            (ray > 0)
            & (
                np.abs(bearing - angle[np.maximum(ray - 1, 0)])
                < np.abs(angle[np.minimum(ray, len(angle) - 1)] - bearing)
            )
        ),
        ray - 1,
        ray,
    )
    ray = np.clip(ray, 0, len(angle) - 1)
    reach_cells = np.hypot(dr, dc)
    sample = np.clip(np.rint(reach_cells / 0.5).astype(int) - 1, 0, len(steps) - 1)
    own_distance = np.maximum(reach_cells, 1e-9) * cell
    own_slope = (dem[window] + h_target[window] - curvature_drop_m(own_distance, k_factor) - eye) / own_distance
    visible = np.zeros(dem.shape, dtype=bool)
    inside = reach_cells <= limit
    if sector_deg is not None:
        inside &= np.abs(off_boresight_deg(bearing_deg(dr, dc), azimuth)) <= width / 2
    visible[window] = ((own_slope >= before[ray, sample]) & inside) | (reach_cells < 0.5)
    return visible


def line_of_sight(dem_m, cell_m, eye, targets, k_factor: float = 4.0 / 3.0, chunk: int = 4096) -> np.ndarray:
    """Whether each target point is in the line of sight of one eye, over the terrain.

    The terrain is sampled every half cell along the ground line from the eye to each target (bilinear,
    :func:`height_at`), lowered by the curvature drop; the target is seen when the tangent of its
    elevation angle from the eye is at least the largest of the samples up to half a cell short of it,
    the rule of :func:`viewshed` for one cell.

    Parameters
    ----------
    dem_m : ndarray (rows, cols)
        Terrain heights [m].
    cell_m : float
        Cell size [m].
    eye : (float, float, float)
        The eye's (row, col) in fractional cell coordinates and its height [m] (terrain + mast).
    targets : ndarray (n, 3)
        Each target's (row, col, height [m]), heights on the DEM's datum.
    k_factor : float
        Effective Earth-radius factor.
    chunk : int
        Targets traced at once (bounds the memory).

    Returns
    -------
    ndarray bool (n,)
        True where the target is seen (always within half a cell of the eye).
    """
    dem = np.asarray(dem_m, dtype=float)
    cell = float(require("cell_m", cell_m, gt=0))
    points = np.atleast_2d(np.asarray(targets, dtype=float))
    eye_row, eye_col, eye_z = (float(v) for v in eye)
    d_row, d_col = points[:, 0] - eye_row, points[:, 1] - eye_col
    reach = np.hypot(d_row, d_col)  # [cells]
    seen = np.ones(len(points), dtype=bool)
    for start in range(0, len(points), chunk):
        part = slice(start, start + chunk)
        longest = float(reach[part].max(initial=0.0))
        steps = np.arange(1, int(np.ceil(2 * longest)) + 1) * 0.5  # [cells]
        if steps.size == 0:
            continue
        unit_r = np.where(reach[part] > 0, d_row[part] / np.maximum(reach[part], 1e-12), 0.0)
        unit_c = np.where(reach[part] > 0, d_col[part] / np.maximum(reach[part], 1e-12), 0.0)
        rows = eye_row + unit_r[:, None] * steps[None, :]
        cols = eye_col + unit_c[:, None] * steps[None, :]
        distance = steps * cell
        slope = (height_at(dem, rows, cols) - curvature_drop_m(distance, k_factor) - eye_z) / distance
        slope = np.where(steps[None, :] <= reach[part, None] - 0.5, slope, -np.inf)
        own = np.maximum(reach[part], 1e-9) * cell
        own_slope = (points[part, 2] - curvature_drop_m(own, k_factor) - eye_z) / own
        seen[part] = (own_slope >= slope.max(axis=1)) | (reach[part] < 0.5)
    return seen


def gaussian_hills(cells: int, cell_m: float, hills: int = 12, seed: int = 7) -> np.ndarray:
    """Seeded synthetic terrain [m]: ``hills`` Gaussian hills 20-120 m high and 400-1500 m wide on a square grid.

    The embedded demo site's terrain (400 cells of 25 m) and a test terrain of the viewshed's checks.
    """
    n, cell = int(require("cells", cells, ge=2)), float(require("cell_m", cell_m, gt=0))
    rng = np.random.default_rng(seed)
    north, east = np.indices((n, n)) * cell
    dem = np.zeros((n, n))
    for cx, cy, height, width in zip(
        rng.uniform(0, n * cell, hills),
        rng.uniform(0, n * cell, hills),
        rng.uniform(20, 120, hills),
        rng.uniform(400, 1500, hills),
    ):
        dem += height * np.exp(-((east - cx) ** 2 + (north - cy) ** 2) / (2 * width**2))
    return dem
