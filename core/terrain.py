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
cells that graze the horizon. A maximum distance stops the rays there: the horizon being a running
maximum from the sensor out, every cell within it is judged exactly as without the limit, and only
the samples beyond it are saved.

The rays are traced in compiled code (Numba): the cells are grouped by their nearest ray (found from
where their bearing leaves the grid, between two boundary cells), and each ray is sampled only as far
as its farthest cell, keeping its horizon in one buffer. Memory is a few integers per cell (12-19 bytes
beyond the DEM, measured at 2000^2 and 4000^2 cells) where the NumPy version held every ray's samples
(690 bytes per cell); the answers are the NumPy version's, cell for cell (tested).
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require
from csuas.core.horizon import EARTH_RADIUS_M, fresnel_radius


def curvature_drop_m(distance_m, k_factor):
    """Drop of the Earth's surface below the tangent plane at ground distance d: d^2 / (2 k R_E) [m]."""
    d = require("distance_m", distance_m, ge=0)
    k = require("k_factor", k_factor, gt=0)
    return d * d / (2.0 * k * EARTH_RADIUS_M)


@numba.njit(cache=True, nogil=True, inline="always")
def _bilinear(dem, row, col):
    """Bilinear height [m] of ``dem`` at one fractional (row, col), clamped to the grid (``dem`` at least 2 x 2)."""
    n_r, n_c = dem.shape
    r = min(max(row, 0.0), n_r - 1.0)
    c = min(max(col, 0.0), n_c - 1.0)
    r0, c0 = min(int(np.floor(r)), n_r - 2), min(int(np.floor(c)), n_c - 2)
    fr, fc = r - r0, c - c0
    return (
        dem[r0, c0] * (1 - fr) * (1 - fc)
        + dem[r0, c0 + 1] * (1 - fr) * fc
        + dem[r0 + 1, c0] * fr * (1 - fc)
        + dem[r0 + 1, c0 + 1] * fr * fc
    )


@numba.njit(cache=True, nogil=True)
def _bilinear_many(dem, rows, cols, out):
    for i in range(rows.size):
        out[i] = _bilinear(dem, rows[i], cols[i])


def height_at(dem: np.ndarray, rows, cols) -> np.ndarray:
    """DEM heights [m] at fractional (row, col) cell positions, bilinear, clamped to the grid."""
    grid = np.asarray(dem, dtype=float)
    if min(grid.shape) < 2:  # one row or column: the grid's own line, repeated
        grid = np.repeat(np.repeat(grid, 2 if grid.shape[0] < 2 else 1, 0), 2 if grid.shape[1] < 2 else 1, 1)
    r, c = np.broadcast_arrays(np.asarray(rows, dtype=float), np.asarray(cols, dtype=float))
    out = np.empty(r.shape)
    _bilinear_many(grid, np.ascontiguousarray(r).ravel(), np.ascontiguousarray(c).ravel(), out.reshape(-1))
    return out


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


@dataclass(frozen=True)
class RayLimits:
    """How far and in which directions the viewshed's rays are traced.

    Attributes
    ----------
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
    """

    max_distance_m: float | None = None
    sector_deg: tuple[float, float] | None = None


def viewshed(
    dem_m: np.ndarray,
    cell_m: float,
    sensor_row: float,
    sensor_col: float,
    sensor_height_m: float,
    target_height_m,
    k_factor: float = 4.0 / 3.0,
    limits: RayLimits = RayLimits(),
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
    limits : RayLimits
        The farthest distance and the azimuth sector traced (default: the whole grid, all round).

    Returns
    -------
    ndarray bool (rows, cols)
        True where the target is visible (the sensor's own cell always).
    """
    dem = np.asarray(dem_m, dtype=float)
    h_target = np.broadcast_to(require("target_height_m", target_height_m, ge=0), dem.shape)
    horizon, sensor = _horizons(dem, cell_m, (sensor_row, sensor_col, sensor_height_m), k_factor, limits)
    visible = np.zeros(dem.shape, dtype=bool)
    _judge_visible(dem, h_target, sensor, horizon, visible)
    return visible


def lowest_visible_height_m(
    dem_m: np.ndarray,
    cell_m: float,
    sensor_row: float,
    sensor_col: float,
    sensor_height_m: float,
    k_factor: float = 4.0 / 3.0,
    limits: RayLimits = RayLimits(),
) -> np.ndarray:
    """The lowest height above the terrain [m] at which a target over each cell is in the sensor's line of sight.

    The same rays and horizons as :func:`viewshed` (its arguments, less the target's height): a target
    at least this high over a cell is visible there, one lower is not (GDAL's "DEM mode", a minimum
    visible height per cell). 0 where the ground itself is in sight (the sensor's own cell always);
    +inf beyond the limits' ``max_distance_m`` or outside their ``sector_deg``.
    """
    dem = np.asarray(dem_m, dtype=float)
    horizon, sensor = _horizons(dem, cell_m, (sensor_row, sensor_col, sensor_height_m), k_factor, limits)
    lowest = np.empty(dem.shape)
    _lowest_heights(dem, sensor, horizon, lowest)
    return lowest


def fresnel_clearance(
    dem_m: np.ndarray,
    cell_m: float,
    sensor: tuple[float, float, float],
    target_height_m: float,
    wavelength_m: float,
    k_factor: float = 4.0 / 3.0,
    limits: RayLimits = RayLimits(),
) -> np.ndarray:
    """The first Fresnel zone's clearance of the sight line from the sensor to a target over each cell [-].

    Along the straight ground path from the eye to the target over a cell, the terrain is sampled every
    half cell from half a cell out to half a cell short of the cell (bilinear, as :func:`line_of_sight`)
    and lowered by the curvature drop d^2 / (2 k R_E), as the viewshed's; at each sample the clearance
    of the sight line above the terrain is divided by the first Fresnel zone's radius there,
    r1 = sqrt(lambda d1 d2 / (d1 + d2)) (:func:`csuas.core.horizon.first_fresnel_radius_m`), and the
    cell takes the smallest ratio. Below 0 the terrain cuts the sight line (the target is hidden);
    from 0.6 up the path is free space in the usual criterion (ITU-R P.530-18, Section 2.2.2: 60 % of
    r1 clear; ITU-R P.526-15, Section 4.1, knife-edge loss about 0 dB from there). Unlike the viewshed,
    which judges a cell on its nearest ray's horizon, each cell's own path is traced: the cost is the
    cells times their path length (cells^1.5 over a whole DEM).

    Parameters
    ----------
    dem_m : ndarray (rows, cols)
        Terrain heights [m], finite, on square cells.
    cell_m : float
        Cell size [m].
    sensor : (float, float, float)
        The sensor's (row, col) in fractional cell coordinates, inside the grid, and its mast [m], >= 0.
    target_height_m : float
        The target's height above the terrain of each cell (the flight level) [m], >= 0.
    wavelength_m : float
        The link's wavelength [m], > 0.
    k_factor : float
        Effective Earth-radius factor (4/3 for radio, :data:`csuas.core.horizon.K_RADIO`).
    limits : RayLimits
        The farthest distance and the azimuth sector, as :func:`viewshed`'s: NaN beyond or outside.

    Returns
    -------
    ndarray float (rows, cols)
        The smallest clearance ratio along each cell's path; +inf where the path holds no sample (the
        sensor's own cell and any closer than a cell); NaN beyond the limits.
    """
    dem = np.asarray(dem_m, dtype=float)
    height = float(require("target_height_m", target_height_m, ge=0))
    wavelength = float(require("wavelength_m", wavelength_m, gt=0))
    horizon, record = _horizons(dem, cell_m, sensor, k_factor, limits)
    clearance = np.full(dem.shape, np.nan)
    _fresnel_ratios(dem, record, height, wavelength, ~np.isnan(horizon), clearance)
    return clearance


@numba.njit(cache=True, nogil=True)
def _fresnel_ratios(dem, sensor, height, wavelength, judged, clearance):
    """Each judged cell's smallest ratio of the sight line's clearance to r1 along its own path (the
    samples of :func:`fresnel_clearance`); +inf where its path holds no sample."""
    row, col, eye, cell, drop_1m = sensor
    for r in range(dem.shape[0]):
        for c in range(dem.shape[1]):
            if not judged[r, c]:
                continue
            reach = np.hypot(r - row, c - col)  # [cells]
            length = reach * cell
            rise = dem[r, c] + height - drop_1m * length * length - eye  # the target above the eye [m]
            smallest = np.inf
            s = 1
            while s * 0.5 <= reach - 0.5:
                step = s * 0.5
                d1 = step * cell
                terrain = _bilinear(dem, row + (r - row) * step / reach, col + (c - col) * step / reach)
                gap = eye + rise * step / reach - (terrain - drop_1m * d1 * d1)
                smallest = min(smallest, gap / fresnel_radius(wavelength, d1, length - d1))
                s += 1
            clearance[r, c] = smallest


def _horizons(dem: np.ndarray, cell_m, sensor, k_factor, limits: RayLimits) -> tuple[np.ndarray, tuple]:
    """Checked inputs, then the horizon each cell's target must clear (tangent of an elevation angle).

    Returns the horizon grid (-inf at the sensor's own cell, NaN where not judged: beyond the limit or
    outside the sector) and the sensor record (row, col, eye height [m], cell [m], drop at 1 m [m]).
    """
    sensor_row, sensor_col, sensor_height_m = sensor
    max_distance_m, sector_deg = limits.max_distance_m, limits.sector_deg
    if dem.ndim != 2 or min(dem.shape) < 2 or not np.isfinite(dem).all():
        raise ParameterError("dem_m", f"array of shape {dem.shape}", "a finite 2-D grid of at least 2 x 2 cells")
    cell = float(require("cell_m", cell_m, gt=0))
    n_r, n_c = dem.shape
    if not (0.0 <= sensor_row <= n_r - 1 and 0.0 <= sensor_col <= n_c - 1):
        raise ParameterError(
            "sensor position", (sensor_row, sensor_col), f"inside the grid 0..{n_r - 1} x 0..{n_c - 1}"
        )
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
    sector = (np.nan, np.nan)
    if sector_deg is not None:
        sector = (
            float(require("sector azimuth_deg", sector_deg[0], ge=0, le=360)),
            float(require("sector width_deg", sector_deg[1], gt=0, le=360)),
        )
        spacing = np.degrees(np.max(np.diff(angle)))  # the widest gap between neighbouring rays
        aside = np.abs(off_boresight_deg(bearing_deg(np.sin(angle), np.cos(angle)), sector[0]))
        angle = angle[aside <= sector[1] / 2 + spacing]
    window = cells_around(dem.shape, sensor_row, sensor_col, span)
    record = (float(sensor_row), float(sensor_col), eye, cell, float(curvature_drop_m(1.0, k_factor)))
    horizon = np.full(dem.shape, np.nan)
    _trace_horizons(
        dem,
        record,
        (
            _perimeter_rays(angle, dem.shape, sensor_row, sensor_col),
            np.stack([np.sin(angle), np.cos(angle)], 1),
            dem.shape,
        ),
        int(np.ceil(2 * span)),
        (float(limit), *sector),
        (window[0].start, window[0].stop, window[1].start, window[1].stop),
        horizon,
    )
    return horizon, record


@numba.njit(cache=True, nogil=True)
def _judge_visible(dem, h_target, sensor, horizon, visible):
    """A cell is visible where its target's elevation tangent reaches the horizon (never where that is NaN)."""
    row, col, eye, cell, drop_1m = sensor
    for r in range(dem.shape[0]):
        for c in range(dem.shape[1]):
            distance = max(np.hypot(r - row, c - col), 1e-9) * cell
            visible[r, c] = (dem[r, c] + h_target[r, c] - drop_1m * distance * distance - eye) / distance >= horizon[
                r, c
            ]


@numba.njit(cache=True, nogil=True)
def _lowest_heights(dem, sensor, horizon, lowest):
    """The height above each cell whose elevation tangent equals the horizon, at least 0 (+inf where NaN)."""
    row, col, eye, cell, drop_1m = sensor
    for r in range(dem.shape[0]):
        for c in range(dem.shape[1]):
            distance = max(np.hypot(r - row, c - col), 1e-9) * cell
            needed = horizon[r, c] * distance + eye + drop_1m * distance * distance - dem[r, c]
            lowest[r, c] = np.inf if np.isnan(needed) else max(needed, 0.0)


def _perimeter_rays(angles, shape, row: float, col: float) -> np.ndarray:
    """Index in ``angles`` of the ray toward each boundary cell, (4, max(rows, cols)): the top and bottom
    rows (per column), the left and right columns (per row); -1 where that cell's ray was left out
    (outside a sector) and past the edge's end."""
    n_r, n_c = shape
    cols, rows = np.arange(n_c, dtype=float), np.arange(n_r, dtype=float)
    edges = (
        np.arctan2(0.0 - row, cols - col),
        np.arctan2(n_r - 1.0 - row, cols - col),
        np.arctan2(rows - row, 0.0 - col),
        np.arctan2(rows - row, n_c - 1.0 - col),
    )
    found = np.full((4, max(n_r, n_c)), -1, dtype=np.int64)
    for k, edge in enumerate(edges):
        index = np.minimum(np.searchsorted(angles, edge), len(angles) - 1)
        found[k, : len(edge)] = np.where(angles[index] == edge, index, -1)
    return found


@numba.njit(cache=True, nogil=True, inline="always")
def _nearest_ray(perimeter, directions, shape, row, col, d_row, d_col):
    """The ray nearest in bearing to the offset (d_row, d_col) from the sensor: of the two boundary cells
    beside the point where that bearing leaves the grid (bearings run monotonically round the boundary),
    the one whose ray makes the larger cosine with it. -1 when neither ray was traced."""
    n_r, n_c = shape
    exit_t = np.inf
    if d_row < 0:
        exit_t = min(exit_t, -row / d_row)
    elif d_row > 0:
        exit_t = min(exit_t, (n_r - 1.0 - row) / d_row)
    if d_col < 0:
        exit_t = min(exit_t, -col / d_col)
    elif d_col > 0:
        exit_t = min(exit_t, (n_c - 1.0 - col) / d_col)
    exit_row = min(max(row + exit_t * d_row, 0.0), n_r - 1.0)
    exit_col = min(max(col + exit_t * d_col, 0.0), n_c - 1.0)
    if d_row != 0 and exit_t == (-row / d_row if d_row < 0 else (n_r - 1.0 - row) / d_row):
        edge, along = (0 if d_row < 0 else 1), exit_col
    else:
        edge, along = (2 if d_col < 0 else 3), exit_row
    first, second = perimeter[edge, int(np.floor(along))], perimeter[edge, int(np.ceil(along))]
    if first < 0:
        return second
    if second < 0:
        return first
    closer = d_row * directions[second, 0] + d_col * directions[second, 1]
    return second if closer > d_row * directions[first, 0] + d_col * directions[first, 1] else first


@numba.njit(cache=True, nogil=True)
def _cells_by_ray(sensor, rays, n_samples, bounds, window):
    """Each cell of ``window`` that is judged: its ray and sample, grouped by ray (counting sort).

    Returns (start, order, sample, slot): the cells of ray j are ``order[start[j]:start[j + 1]]``
    (flat window indices), ``sample`` their nearest sample; ``slot`` is -1 for the sensor's own cell
    (always visible) and -2 for a cell outside the limit or the sector (never).
    """
    row, col = sensor[0], sensor[1]
    perimeter, directions, shape = rays
    limit, azimuth, width = bounds
    r0, r1, c0, c1 = window
    n_cols = c1 - c0
    slot = np.empty((r1 - r0) * n_cols, np.int32)
    sample = np.empty(slot.size, np.int32)
    count = np.zeros(len(directions) + 1, np.int64)
    for k in range(slot.size):
        d_row, d_col = r0 + k // n_cols - row, c0 + k % n_cols - col
        reach = np.hypot(d_row, d_col)
        outside = reach > limit
        if not np.isnan(azimuth):
            bearing = np.degrees(np.arctan2(d_col, -d_row)) % 360.0
            outside |= abs((bearing - azimuth + 180.0) % 360.0 - 180.0) > width / 2
        ray = -2 if outside or reach < 0.5 else _nearest_ray(perimeter, directions, shape, row, col, d_row, d_col)
        if reach < 0.5:
            slot[k] = -1
        elif ray < 0:
            slot[k] = -2
        else:
            slot[k] = ray
            sample[k] = min(max(int(np.rint(reach / 0.5)) - 1, 0), n_samples - 1)
            count[ray + 1] += 1
    start = np.cumsum(count)
    filled = start[:-1].copy()
    order = np.empty(start[-1], np.int64)
    for k in range(slot.size):
        if slot[k] >= 0:
            order[filled[slot[k]]] = k
            filled[slot[k]] += 1
    return start, order, sample, slot


@numba.njit(cache=True, nogil=True)
def _trace_horizons(dem, sensor, rays, n_samples, bounds, window, horizon):
    """The viewshed's rays (module docstring), ray by ray, each giving the cells nearest to it their horizon.

    ``sensor`` is (row, col, eye height [m], cell [m], curvature drop at 1 m [m]); ``rays`` the rays'
    indices round the boundary (:func:`_perimeter_rays`), their directions (sin, cos) and the grid's
    shape. A ray's horizon is sampled every half cell only as far as its farthest cell. Writes -inf at
    the sensor's own cell and leaves cells not judged as they are. Memory: a few integers per cell.
    """
    row, col, eye, cell, drop_1m = sensor
    directions = rays[1]
    start, order, sample, slot = _cells_by_ray(sensor, rays, n_samples, bounds, window)
    r0, c0, n_cols = window[0], window[2], window[3] - window[2]
    for k in range(slot.size):
        if slot[k] == -1:
            horizon[r0 + k // n_cols, c0 + k % n_cols] = -np.inf
    before = np.empty(n_samples)
    for ray in range(len(directions)):
        if start[ray + 1] == start[ray]:
            continue
        farthest = 0
        for i in range(start[ray], start[ray + 1]):
            farthest = max(farthest, sample[order[i]])
        sin_a, cos_a = directions[ray, 0], directions[ray, 1]
        running = -np.inf
        for s in range(farthest + 1):
            before[s] = running  # what sample s must clear: the terrain before it
            step = (s + 1) * 0.5
            distance = step * cell
            terrain = _bilinear(dem, row + sin_a * step, col + cos_a * step) - drop_1m * distance * distance
            running = max(running, (terrain - eye) / distance)
        for i in range(start[ray], start[ray + 1]):
            k = order[i]
            horizon[r0 + k // n_cols, c0 + k % n_cols] = before[sample[k]]


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
    eye_z = float(eye[2])
    seen = np.ones(len(points), dtype=bool)
    for part, reach, steps, ground in _profiles(dem, cell, eye, points, k_factor, chunk):
        slope = (ground - eye_z) / (steps * cell)
        slope = np.where(steps[None, :] <= reach[:, None] - 0.5, slope, -np.inf)
        own = np.maximum(reach, 1e-9) * cell
        own_slope = (points[part, 2] - curvature_drop_m(own, k_factor) - eye_z) / own
        seen[part] = (own_slope >= slope.max(axis=1)) | (reach < 0.5)
    return seen


def _profiles(dem, cell, eye, points, k_factor, chunk):
    """Terrain profiles from the eye toward points, ``chunk`` points at a time, sampled every half cell.

    Yields (slice of the points, their ground reach [cells], sample distances [cells], terrain heights at
    the samples lowered by the curvature drop [m] (points x samples)); chunks of zero reach are skipped.
    """
    eye_row, eye_col = float(eye[0]), float(eye[1])
    d_row, d_col = points[:, 0] - eye_row, points[:, 1] - eye_col
    reach = np.hypot(d_row, d_col)  # [cells]
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
        yield part, reach[part], steps, height_at(dem, rows, cols) - curvature_drop_m(steps * cell, k_factor)


def diffraction_path_difference_m(dem_m, cell_m, eye, targets, k_factor: float = 4.0 / 3.0, chunk: int = 4096):
    """Path-length difference over the terrain's top edges between an eye and each target (ISO 9613-2, Eqs. 16, 17).

    The diffracted path is the taut string over the terrain profile (sampled as :func:`line_of_sight`
    samples it, curvature drop included) from the eye to the target: its first edge is the profile's
    horizon seen from the eye (the sample of largest elevation angle), its last the horizon seen from the
    target. One edge (both the same sample): single diffraction, z = d_ss + d_sr - d (Eq. 16 with a = 0:
    the edge lies across the vertical plane of the path). Two: double diffraction, z = d_ss + e + d_sr - d
    (Eq. 17, a = 0) with e the straight distance between the edges (terrain poking above that segment is
    not followed: z errs short, the barrier weak). Where no sample rises above the straight eye-target
    line the path is clear: z = 0 and every distance is 0.

    Parameters
    ----------
    dem_m, cell_m, eye, targets, k_factor, chunk
        As :func:`line_of_sight`: heights [m], cell [m], the eye's (row, col, height [m]), targets
        (n, 3) of (row, col, height [m]), effective Earth-radius factor, targets traced at once.

    Returns
    -------
    tuple of ndarray (n,)
        z [m], the target-to-edge distance d_ss [m], the edge-to-eye distance d_sr [m] (the target is the
        source, the eye the receiver) and the edge separation e [m] (0 for single diffraction).
    """
    dem = np.asarray(dem_m, dtype=float)
    cell = float(require("cell_m", cell_m, gt=0))
    points = np.atleast_2d(np.asarray(targets, dtype=float))
    eye_z = float(eye[2])
    z, to_edge, from_edge, between = (np.zeros(len(points)) for _ in range(4))
    for part, reach, steps, ground in _profiles(dem, cell, eye, points, k_factor, chunk):
        distance = steps * cell
        span = np.maximum(reach, 1e-9) * cell  # [m]
        rise = points[part, 2] - curvature_drop_m(span, k_factor) - eye_z
        height = ground - eye_z
        inside = distance[None, :] < span[:, None]
        from_eye = np.where(inside, height / distance[None, :], -np.inf)
        back = np.maximum(span[:, None] - distance[None, :], 1e-12)
        from_target = np.where(inside, (height - rise[:, None]) / back, -np.inf)
        first, last = np.argmax(from_eye, axis=1), np.argmax(from_target, axis=1)
        rows = np.arange(first.size)
        blocked = from_eye[rows, first] > rise / span
        x1, y1 = distance[first], height[rows, first]
        x2, y2 = distance[last], height[rows, last]
        near, far, e = np.hypot(x1, y1), np.hypot(span - x2, rise - y2), np.hypot(x2 - x1, y2 - y1)
        z[part] = np.where(blocked, np.maximum(near + e + far - np.hypot(span, rise), 0.0), 0.0)
        to_edge[part], from_edge[part] = np.where(blocked, far, 0.0), np.where(blocked, near, 0.0)
        between[part] = np.where(blocked, e, 0.0)
    return z, to_edge, from_edge, between


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
