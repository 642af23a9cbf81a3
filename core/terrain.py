"""Line of sight over terrain: which cells of a DEM a sensor sees at a flight level above the ground.

The Earth's curvature with standard refraction drops a point at ground distance d below the
sensor's tangent plane by d^2 / (2 k R_E) (k = 4/3 for radio, 7/6 for light near the ground:
refraction coefficient 0.13 in :mod:`csuas.core.horizon`; ITU-R P.834-9 Eq. 1). A target at
height h above the terrain at distance d is seen when its elevation angle from the sensor is at
least the largest elevation angle of the terrain between them.

The viewshed is computed by rays (the "R2" method of Franklin & Ray, *Higher isn't necessarily
better: visibility algorithms and experiments*, 1994): rays leave the sensor toward every boundary
cell of the DEM, the terrain is sampled where each crosses a grid line (linear between the two cells
beside the crossing, as R2 does), and the running maximum of the terrain's elevation angle along the
ray is the horizon each cell must clear; a cell takes the horizon of the ray that crosses its grid
line nearest to it, from the samples before that line. A cell is thus judged against the terrain of
a path within half a cell of its own sight line: the method's error is confined to cells that graze
the horizon (tested against the exact sight line). A maximum distance stops the rays there: the
horizon being a running maximum from the sensor out, every cell within it is judged exactly as
without the limit.

The rays are swept, not traced one by one: the grid round the sensor is cut into four wedges (south
and north, where rays cross more rows than columns, east and west), and each wedge is swept line by
line outward from the sensor (rows for south and north, columns for east and west), every ray active
on a line advancing by one sample there, so that the terrain and the results are read and written a
line at a time (columns are first copied eight at a time into a strip, so that a column is
contiguous too; only the rows the wedge reads on those lines, within one cell of its diagonals). The
cost is the cells plus the samples (about two a cell: the rays are dense near the sensor), O(cells);
the memory, beyond the DEM and the result, is a few values per ray, a line's worth of scratch and the
strip (a few rows of the DEM). A line's samples are taken in three passes over its rays (where they
cross, the terrain there, the tangents), so that the first and the last vectorise; the indices are
unsigned (no wrap-around test), the distances multiply by reciprocals kept per ray and per line, and
the kernels use fast math without the no-NaN and no-infinity assumptions (the sector test needs NaN,
the horizons start at -inf). Measured at 8000^2 (CPU-s, best of 2-3, load 2-4; same cells bit for bit
at each step): 1.44 before, 1.39 fast math, 1.32 reciprocals and a branch-free max, 1.23 unsigned
indices, 1.05 the three passes, 1.00 the strip's rows (1.08-1.18 without, alternating runs), 0.87-0.89
the walk to each cell's nearest ray against midpoints between neighbouring rays kept per wedge (0.97
without): GDAL's 0.94-1.24 s in the same minutes (bench ratios 0.92-1.17 at 8000^2). Tried
and not taken: results written to a strip too and copied back a row at a time (slower: the strip must
first be read from the result, the east wedge 0.63 -> 0.72 s); the judging in two passes (nearest ray,
then the values: 1.05 -> 1.25 s); the lines' results and targets passed as 1-D views (1.15 s); the
tangent compared as a product, not a quotient (no change); a 16-column strip (within the noise).
Alternatives measured before that tuning on an 8000^2 DEM against GDAL's 1.0 CPU-s
(docs/performance.md): the rays traced one by one with the cells grouped by nearest ray (the
previous code, same method): 9.9 times GDAL's CPU, cost ~ cells^1.1, scattered in memory; the east
and west wedges swept on a transposed copy of the DEM: 1.9 s (the copy alone 0.6 s, 8 bytes a cell
more); their columns read in place eight at a time: 1.9-2.1 s; the strip: 1.5-1.6 s (all the same
answers, cell for cell); rays traced only once their neighbours part by a cell, taking the nearer
one's horizon there: 15 % less CPU, but 98.5 % of cells against the exact sight line on rough terrain
(below 99 %). GDAL's own algorithm (Wang, Robinson & White 2000, reference planes, one
interpolation a cell) is cheaper by design but judges a cell on horizons interpolated from its
neighbours: on rough terrain it meets the exact sight line on 96.8-99.3 % of cells where these rays
meet it on at least 99 % (tests/test_terrain_gdal.py), so it was not taken.
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
    h_target = np.broadcast_to(np.asarray(require("target_height_m", target_height_m, ge=0), dtype=float), dem.shape)
    sight = _sight(dem, cell_m, (sensor_row, sensor_col, sensor_height_m), k_factor, limits)
    visible = np.zeros(dem.shape, dtype=bool)
    _sweep(dem, sight, _VISIBLE, h_target, visible)
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
    sight = _sight(dem, cell_m, (sensor_row, sensor_col, sensor_height_m), k_factor, limits)
    lowest = np.full(dem.shape, np.inf)
    _sweep(dem, sight, _LOWEST, np.broadcast_to(0.0, dem.shape), lowest)
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
    sight = _sight(dem, cell_m, sensor, k_factor, limits)
    judged = np.zeros(dem.shape, dtype=bool)
    _sweep(dem, sight, _JUDGED, np.broadcast_to(0.0, dem.shape), judged)
    clearance = np.full(dem.shape, np.nan)
    _fresnel_ratios(dem, sight.record, height, wavelength, judged, clearance)
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


#: What the sweep writes for each judged cell (:func:`_sweep`): that it is judged, whether its target is
#: in sight, the lowest height above it in sight [m].
_JUDGED, _VISIBLE, _LOWEST = 0, 1, 2
#: Columns copied at once into a strip for the east and west wedges (:func:`_sweep_wedge`).
_STRIP_LINES = 8
_FAST_MATH = {"nsz", "arcp", "contract", "afn", "reassoc"}


@dataclass(frozen=True)
class _Sight:
    """Checked inputs of a sweep (:func:`_sight`).

    Attributes
    ----------
    record : tuple
        The sensor's (row, col) [cells], its eye height [m] (terrain + mast), the cell [m] and the
        curvature drop at 1 m [m].
    bounds : tuple
        The farthest distance judged [cells] (inf: all) and the sector's (azimuth, width) [deg] (NaN: all round).
    window : (slice, slice)
        The rows and columns within the farthest distance and two cells more (the whole grid without one).
    """

    record: tuple
    bounds: tuple
    window: tuple[slice, slice]


def _sight(dem: np.ndarray, cell_m, sensor, k_factor, limits: RayLimits) -> _Sight:
    """The checked DEM, sensor and limits of a sweep, all errors named."""
    sensor_row, sensor_col, sensor_height_m = sensor
    max_distance_m, sector_deg = limits.max_distance_m, limits.sector_deg
    # the extremes are finite only when every cell is (NaN propagates), with no temporary grid
    if dem.ndim != 2 or min(dem.shape) < 2 or not (np.isfinite(dem.min()) and np.isfinite(dem.max())):
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
    limit = np.inf if max_distance_m is None else float(require("max_distance_m", max_distance_m, gt=0)) / cell
    sector = (np.nan, np.nan)
    if sector_deg is not None:
        sector = (
            float(require("sector azimuth_deg", sector_deg[0], ge=0, le=360)),
            float(require("sector width_deg", sector_deg[1], gt=0, le=360)),
        )
    record = (float(sensor_row), float(sensor_col), eye, cell, float(curvature_drop_m(1.0, k_factor)))
    return _Sight(record, (limit, *sector), cells_around(dem.shape, sensor_row, sensor_col, limit + 2.0))


def _sweep(dem: np.ndarray, sight: _Sight, mode: int, target: np.ndarray, out: np.ndarray) -> None:
    """Sweeps the four wedges round the sensor (module docstring), writing ``mode``'s value for every judged cell.

    ``mode`` is :data:`_JUDGED` (``out`` bool: True), :data:`_VISIBLE` (``out`` bool: whether the
    target ``target`` [m] above the terrain is seen) or :data:`_LOWEST` (``out`` float: the lowest
    visible height [m]). The south and north wedges sweep the DEM's rows, the east and west ones its
    columns (:func:`_sweep_wedge`); cells not judged are left as they are.
    """
    row, col = sight.record[0], sight.record[1]
    rows, cols = sight.window
    view = dem[rows, cols]
    for transposed in (False, True):
        shape, origin = (dem.shape[::-1], (col, row)) if transposed else (dem.shape, (row, col))
        offset = (cols.start, rows.start) if transposed else (rows.start, cols.start)
        for step in (1, -1):
            slopes = _wedge_slopes(shape, origin, step, sight.bounds, transposed)
            frame = (float(origin[0]), float(origin[1]), step, transposed, *offset)
            _sweep_wedge(view, frame, sight.record, slopes, sight.bounds, mode, target[rows, cols], out[rows, cols])
    near_rows, near_cols = cells_around(dem.shape, row, col, 1.0)
    for r in range(near_rows.start, near_rows.stop):  # the sensor's own cell: always in sight
        for c in range(near_cols.start, near_cols.stop):
            if np.hypot(r - row, c - col) < 0.5:
                out[r, c] = 0.0 if mode == _LOWEST else True


def _wedge_slopes(shape, origin, step: int, bounds, transposed: bool) -> np.ndarray:
    """The rays of one wedge, as their cross offsets per line swept (sorted): toward every boundary cell of the
    grid within one cell of the wedge (cross offset at most the lines swept plus one), and with a sector
    only those within its half width and the widest gap between neighbouring rays (so that every cell in
    the sector keeps its nearest ray). ``shape`` and ``origin`` are the grid's and the sensor's in the
    wedge's frame (lines swept, cross)."""
    n_a, n_b = shape
    a0, b0 = origin
    lines = step * (np.arange(n_a, dtype=float) - a0)
    lines = lines[lines > 0]
    if lines.size == 0:
        return np.empty(0)
    cross = np.arange(n_b, dtype=float) - b0
    far = cross / lines.max()
    side = np.concatenate([(0.0 - b0) / lines, (n_b - 1.0 - b0) / lines])
    slopes = np.concatenate(
        [far[np.abs(cross) <= lines.max() + 1], side[np.abs(side) <= 1.0 + 1.0 / np.tile(lines, 2)]]
    )
    slopes = np.unique(slopes)
    azimuth, width = bounds[1], bounds[2]
    if np.isnan(azimuth):
        return slopes
    spacing = np.degrees(np.max(np.diff(np.arctan(slopes)), initial=0.0))
    d_row, d_col = (
        (slopes, np.full(slopes.size, float(step))) if transposed else (np.full(slopes.size, float(step)), slopes)
    )
    return slopes[np.abs(off_boresight_deg(bearing_deg(d_row, d_col), azimuth)) <= width / 2 + spacing]


@numba.njit(cache=True, nogil=True)
def _fill_strip(view, strip, first, step, reach):
    """The next columns ``first``, ``first + step``, ... of ``view`` (as many as ``strip`` holds and the window
    has) as rows of ``strip``: a column swept is then contiguous, and ``view`` is read a few cache lines
    per row at a time. Only the rows ``reach`` (first, last) are copied: those the wedge reads on these
    lines. Returns how many columns were copied."""
    count = min(strip.shape[0], view.shape[1] - first if step > 0 else first + 1)
    for r in range(max(reach[0], 0), min(reach[1], view.shape[0] - 1) + 1):
        for t in range(count):
            strip[t, r] = view[r, first + t * step]
    return count


@numba.njit(cache=True, nogil=True, error_model="numpy", fastmath=_FAST_MATH)
def _sweep_wedge(view, frame, sensor, slopes, bounds, mode, target, out):
    """One wedge of the sweep: its lines from the sensor outward, each judging its cells on the rays' horizons
    so far, then adding its own samples to them.

    ``view`` holds the terrain [m] of a window of the DEM; ``frame`` is the sensor's (line, cross)
    position on the whole DEM [cells], the direction swept (+1, -1), whether the lines are the DEM's
    columns (the east and west wedges: they are copied :data:`_STRIP_LINES` at a time into rows of a
    strip, so that every line swept is contiguous in memory) and the window's first line and cross
    index on the DEM (distances are taken on the DEM's own indices, so a window changes no bit of them).
    A ray is active on a line while it crosses the window there, within a cell: the active rays are one
    run of ``slopes``, shrinking outward.
    """
    a0, b0, step, transposed, a_off, b_off = frame
    n_lines, n_cross = (view.shape[1], view.shape[0]) if transposed else (view.shape[0], view.shape[1])
    if slopes.size == 0:
        return
    secants = np.sqrt(1.0 + slopes * slopes)
    horizon, scratch = np.full(slopes.size, -np.inf), np.empty((2, slopes.size))
    midpoints = np.append(0.5 * (slopes[:-1] + slopes[1:]), np.inf)  # between neighbouring rays
    rays = (slopes, secants, 1.0 / secants, horizon, scratch)  # slope, secant, cosine, horizon, scratch
    strip = np.empty((_STRIP_LINES if transposed else 0, n_cross))
    lo, hi, used, filled = 0, slopes.size - 1, 0, 0  # the active rays; the strip's lines swept and copied
    a = int(np.floor(a0)) + 1 if step > 0 else int(np.ceil(a0)) - 1
    while 0 <= a - a_off < n_lines and step * (a - a0) <= bounds[0]:
        da = step * (a - a0)
        while lo < hi and b0 + slopes[lo] * da < b_off - 1.0:
            lo += 1
        while hi > lo and b0 + slopes[hi] * da > b_off + n_cross:
            hi -= 1
        line = (a, da, b0, step, transposed, a_off, b_off)
        if transposed:
            if used == filled:
                # a ray crosses line da within da + 1 of the sensor (its cross offset is at most one more
                # than the lines swept, or it is clamped to the window's edge, nearer), the judged cells within da
                far = da + _STRIP_LINES + 2.0
                reach = (int(np.floor(b0 - far)) - b_off, int(np.ceil(b0 + far)) - b_off)
                used, filled = 0, _fill_strip(view, strip, a - a_off, step, reach)
            heights = strip[used]
            used += 1
            _judge_line(heights, line, sensor, (midpoints, rays[3], lo, hi), bounds, mode, target, out)
            _sample_line(heights, (da, b0, b_off), sensor, rays, (lo, hi))
        else:
            _judge_line(view[a - a_off], line, sensor, (midpoints, rays[3], lo, hi), bounds, mode, target, out)
            _sample_line(view[a - a_off], (da, b0, b_off), sensor, rays, (lo, hi))
        a += step


@numba.njit(cache=True, nogil=True, inline="always")
def _sample_line(heights, line, sensor, rays, active):
    """Each active ray's terrain where it crosses the line (linear between the two cells beside it, curvature
    dropped) raises its horizon (tangent of the elevation angle from the eye).

    In three passes over the active rays (where they cross, the terrain there, the tangents) through
    ``rays``' two scratch rows, so that the first and the last vectorise (the middle one gathers)."""
    da, b0, b_off = line
    eye, cell, drop_1m = sensor[2], sensor[3], sensor[4]
    slopes, secants, cosines, horizon, scratch = rays
    lo, count = active[0], active[1] + 1 - active[0]
    slope, secant, cosine, highest = slopes[lo:], secants[lo:], cosines[lo:], horizon[lo:]
    cells, fractions = scratch[0], scratch[1]
    last = float(heights.size - 1)
    for k in range(count):
        # the crossing in the line's own indices (exact: b_off is a whole number below it)
        y = min(max(b0 + slope[k] * da, b_off), b_off + last) - b_off
        cells[k] = np.floor(min(y, last - 1.0))
        fractions[k] = y - cells[k]
    for k in range(count):
        i = np.uint64(cells[k])  # never negative: indexes without wrap-around
        cells[k] = heights[i] + fractions[k] * (heights[i + np.uint64(1)] - heights[i])
    along = da * cell  # [m]
    per_along = 1.0 / along
    for k in range(count):
        tangent = (cells[k] - eye) * (per_along * cosine[k]) - drop_1m * along * secant[k]
        highest[k] = max(highest[k], tangent)


@numba.njit(cache=True, nogil=True, inline="always")
def _judge_line(heights, line, sensor, rays, bounds, mode, target, out):
    """Each cell of the line in the wedge (within the limit and the sector) takes the horizon so far of the
    ray that crosses the line nearest to it (a pointer walking up the sorted rays) and gets ``mode``'s value."""
    a, da, b0, step, transposed, a_off, b_off = line
    eye, cell, drop_1m = sensor[2], sensor[3], sensor[4]
    midpoints, horizon, lo, hi = rays
    limit, azimuth, width = bounds
    half = min(da, np.sqrt(max(limit * limit - da * da, 0.0)))
    first, last = max(int(np.ceil(b0 - half)), b_off), min(int(np.floor(b0 + half)), b_off + heights.size - 1)
    j = lo
    all_round = np.isnan(azimuth)
    for b in range(first, last + 1):
        db = b - b0
        reach = np.sqrt(da * da + db * db)
        if (not transposed and abs(db) >= da) or reach > limit:  # the diagonals belong to the east and west
            continue
        if not all_round:
            d_row, d_col = (db, step * da) if transposed else (step * da, db)
            if abs((np.degrees(np.arctan2(d_col, -d_row)) % 360.0 - azimuth + 180.0) % 360.0 - 180.0) > width / 2:
                continue
        while j < hi and midpoints[j] * da < db:
            j += 1
        w_a, w_b = a - a_off, b - b_off  # in the window
        r, c = (w_b, w_a) if transposed else (w_a, w_b)
        distance = reach * cell
        if mode == _JUDGED:
            out[r, c] = True
        elif mode == _VISIBLE:
            rise = heights[w_b] + target[r, c] - drop_1m * distance * distance - eye
            out[r, c] = rise / distance >= horizon[j]
        else:
            out[r, c] = max(horizon[j] * distance + eye + drop_1m * distance * distance - heights[w_b], 0.0)


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
