"""Coverage of a site: where each sensor sees, detects and how likely, per flight level, and fused.

For a sensor on a mast at a DEM cell and a drone at ``altitude`` above the terrain of every cell:

* *visible*: line of sight over the terrain with the Earth's curvature and the modality's refraction
  (:func:`csuas.core.terrain.viewshed`; k = 4/3 for radio and radar, the optical value for EO,
  thermal and lidar, 1 for sound, whose refraction the model leaves out), traced only out to the
  sensor's mapped reach (:func:`mapped_reach_m`);
* *in its field of regard*: inside the azimuth sector around the sensor's boresight, between its
  elevation limits (the upper one leaves the overhead dead zone, the "cone of silence") and beyond
  its minimum slant range (the near-range dead zone);
* *detected*: visible, in the field of regard and within the sensor's predicted detection range
  (:mod:`csuas.core.ranges`) at the slant distance from its eye to the drone;
* *Pd*: the sensor's probability of detection at that slant distance (:mod:`csuas.core.pd_curves`),
  0 where hidden or outside the field of regard;
* except for an acoustic sensor of the physical convention, which hears a drone the terrain hides over
  the terrain's top edge (:mod:`csuas.core.barrier`, ISO 9613-2): hidden cells it reaches are detected
  where the budget margin covers the barrier attenuation, with the Pd at that margin (still not visible);
* per sensor, the *minimum detectable altitude* of each cell (the lowest flight level detected);
* fused: the number of sensors detecting each cell, their OR, the OR of their Pd and, given k, the
  cells detected by at least k sensors and the probability that at least k of the n independent
  sensors detect (the Poisson-binomial tail, :func:`csuas.core.fusion.fuse_k_of_n`).

Grid conventions: rows run from north to south and columns from west to east (a north-up raster),
so a bearing, clockwise from grid north, is atan2(east, north) = atan2(d_col, -d_row).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core import units
from csuas.core.barrier import barrier_frequency_hz, terrain_barrier_db
from csuas.core.checks import require_all
from csuas.core.fusion import fuse_k_of_n, fuse_or
from csuas.core.modality import RECORDS
from csuas.core.pd_curves import acoustic_pd_with_loss, margin_db, sensor_pd
from csuas.core.radar import radar_frequency_ghz
from csuas.core.ranges import evaluate, rf_frequency_ghz
from csuas.core.rf import free_space_path_loss_db
from csuas.core.scenario import Scenario
from csuas.core.terrain import (
    RayLimits,
    bearing_deg,
    cells_around,
    curvature_drop_m,
    fresnel_clearance,
    height_at,
    lowest_visible_height_m,
    off_boresight_deg,
    viewshed,
)

#: Effective Earth-radius factor of each modality's line of sight (its record's ``horizon``, csuas.core.modality).
K_FACTOR = {m.name: m.line_of_sight.k for m in RECORDS}
#: Pointing and dead-zone settings of a sited sensor: default and allowed domain (:func:`require` bounds).
POINTING = {
    "azimuth_deg": (0.0, {"ge": 0.0, "le": 360.0}),
    "sector_deg": (360.0, {"gt": 0.0, "le": 360.0}),
    "elevation_min_deg": (-90.0, {"ge": -90.0, "le": 90.0}),
    "elevation_max_deg": (90.0, {"ge": -90.0, "le": 90.0}),
    "min_range_m": (0.0, {"ge": 0.0}),
}
#: Pd below which a sensor's map ends (the mapped reach): farther cells are not traced and get Pd 0.
PD_NEGLIGIBLE = 1e-3
#: Share of the first Fresnel zone's radius a link keeps clear to count as free space (ITU-R P.530-18, 2.2.2).
FRESNEL_CLEAR = 0.6
#: Fused Pd from which a flight level counts as detected in the minimum detectable height.
PD_DETECTABLE = 0.5
#: Log-spaced slant distances on which the mapped reach is looked up.
REACH_GRID_POINTS = 512


@dataclass(frozen=True)
class SitedSensor:
    """A scenario sensor placed on the site: its cell position, mast height, pointing and dead zones.

    Attributes
    ----------
    name : str
        The sensor's key in the scenario.
    row, col : float
        Position in (fractional) cell coordinates of the DEM.
    mast_m : float
        Eye height above the terrain under it [m].
    azimuth_deg : float
        Boresight bearing [deg], clockwise from grid north, 0..360.
    sector_deg : float
        Full width of the azimuth sector centred on the boresight [deg], 0 < w <= 360 (360: all round).
    elevation_min_deg, elevation_max_deg : float
        Elevation limits of the line of sight from the eye to the drone [deg], -90..90, min < max; the
        upper limit leaves the overhead dead zone (cone of silence).
    min_range_m : float
        Minimum slant range [m], >= 0: the near-range dead zone.
    """

    name: str
    row: float
    col: float
    mast_m: float
    azimuth_deg: float = POINTING["azimuth_deg"][0]
    sector_deg: float = POINTING["sector_deg"][0]
    elevation_min_deg: float = POINTING["elevation_min_deg"][0]
    elevation_max_deg: float = POINTING["elevation_max_deg"][0]
    min_range_m: float = POINTING["min_range_m"][0]

    def __post_init__(self):
        """Every pointing value in its domain (all mistakes at once)."""
        require_all(
            *((f"sensors.{self.name}.{key}", getattr(self, key), bounds) for key, (_, bounds) in POINTING.items())
        )
        if not self.elevation_min_deg < self.elevation_max_deg:
            raise ParameterError(
                f"sensors.{self.name}.elevation_max_deg",
                self.elevation_max_deg,
                f"above elevation_min_deg = {self.elevation_min_deg:g}",
            )


def elevation_deg(ground_m, height_m, k_factor):
    """Elevation angle of the line of sight to a point [deg]: atan((dh - d^2 / (2 k R_E)) / d).

    Parameters
    ----------
    ground_m : array_like
        Ground distance d from the eye [m], >= 0.
    height_m : array_like
        Height dh of the point above the eye [m] (negative below it).
    k_factor : float
        Effective Earth-radius factor: the point sinks by the curvature drop
        (:func:`csuas.core.terrain.curvature_drop_m`, as in the viewshed).
    """
    drop = curvature_drop_m(ground_m, k_factor)
    return np.degrees(np.arctan2(np.asarray(height_m, dtype=float) - drop, ground_m))


def mapped_reach_m(scenario: Scenario, sensor_name: str, farthest_m: float) -> float:
    """Farthest slant distance the sensor's map needs [m]: its detection range or where Pd >= PD_NEGLIGIBLE.

    Since the slant distance is at least the ground distance, no cell beyond this ground distance is
    detected or has Pd >= PD_NEGLIGIBLE (Pd falling with range). Pd is read on REACH_GRID_POINTS
    log-spaced distances up to ``farthest_m``, and the grid point after the last one still at
    PD_NEGLIGIBLE is taken (never short of the crossing).

    Parameters
    ----------
    scenario : Scenario
    sensor_name : str
    farthest_m : float
        Farthest ground distance of the site from the sensor [m], > 0.

    Returns
    -------
    float
        The reach [m]; inf when the sensor still detects, or its Pd is still PD_NEGLIGIBLE, at ``farthest_m``.
    """
    detection = float(np.asarray(evaluate(scenario)[sensor_name].range_m))
    grid = np.geomspace(1e-3 * farthest_m, farthest_m, REACH_GRID_POINTS)
    above = np.flatnonzero(sensor_pd(scenario, sensor_name, grid).pd >= PD_NEGLIGIBLE)
    if detection >= farthest_m or (above.size and above[-1] == grid.size - 1):
        return float("inf")
    return max(detection, float(grid[above[-1] + 1 if above.size else 0]))


def farthest_ground_m(shape, sited: SitedSensor, cell_m: float) -> float:
    """The farthest ground distance [m] from the sensor to a cell of a grid of ``shape``: to a corner cell."""
    corners = [(r, c) for r in (0, shape[0] - 1) for c in (0, shape[1] - 1)]
    return max(float(np.hypot(r - sited.row, c - sited.col) * cell_m) for r, c in corners)


def reach_window(shape, sited: SitedSensor, reach_m: float, cell_m: float) -> tuple[slice, slice]:
    """The rows and columns of a grid of ``shape`` within the sensor's mapped reach each way (inf: all).

    Every cell a sensor's layers judge (within ``reach_m``), the terrain between it and the sensor and its
    bilinear neighbours lie inside (:func:`csuas.core.terrain.cells_around`). Each sensor's line of sight is
    computed on this window of the DEM, so a run by tiles (``csuas coverage --scheduler``), which reads the
    same window, gives the same answers cell for cell whatever the viewshed's method.
    """
    return cells_around(shape, sited.row, sited.col, reach_m / cell_m)


def in_window(sited: SitedSensor, window: tuple[slice, slice]) -> SitedSensor:
    """The sensor placed in the window's own cell coordinates (exact: the window starts at or before it)."""
    return replace(sited, row=sited.row - window[0].start, col=sited.col - window[1].start)


def sensor_layers(
    dem_m: np.ndarray, cell_m: float, scenario: Scenario, sited: SitedSensor, altitudes_m, reach_m=None
) -> dict:
    """Visible, detected and Pd grids (altitude, rows, cols) of one sensor, and its minimum detectable altitude.

    The line of sight is traced on the sensor's :func:`reach_window` of the DEM (cells beyond the reach are
    not traced, as before); the other grids are cell by cell.

    Parameters
    ----------
    dem_m : ndarray (rows, cols)
        Terrain heights [m] of a north-up grid of square cells.
    cell_m : float
        Cell size [m].
    scenario : Scenario
        Where the sensor's range and Pd models come from.
    sited : SitedSensor
        The sensor's place, mast, pointing and dead zones.
    altitudes_m : sequence of float
        Flight levels above the terrain of each cell [m].
    reach_m : float, optional
        The sensor's mapped reach [m] (:func:`mapped_reach_m`) when ``dem_m`` is a window of a larger DEM
        (its value over the whole DEM); None: found on ``dem_m``'s own extent.

    Returns
    -------
    dict
        ``visible`` and ``detected`` (bool), ``pd`` (float), each (A, rows, cols); ``min_altitude_m``
        (rows, cols; NaN where no flight level is detected); ``range_m`` (the sensor's predicted range);
        ``reach_m`` (:func:`mapped_reach_m`), ``altitudes_m`` (the flight levels, (A,)) and ``traced``
        (rows, cols: the cells within it and inside
        the azimuth sector, the only ones whose line of sight is traced; ``visible`` is False
        elsewhere); ``aimed`` (rows, cols: the cells inside the azimuth sector, at any range);
        ``regard`` (bool, (A, rows, cols): the cells in the sensor's sector, elevation limits and
        beyond its minimum range).
    """
    if reach_m is None:
        reach_m = mapped_reach_m(scenario, sited.name, farthest_ground_m(dem_m.shape, sited, cell_m))
    window = reach_window(dem_m.shape, sited, reach_m, cell_m)
    if (window[0].stop - window[0].start, window[1].stop - window[1].start) == dem_m.shape:
        return _window_layers(dem_m, cell_m, scenario, sited, altitudes_m, reach_m)
    inner = _window_layers(dem_m[window], cell_m, scenario, in_window(sited, window), altitudes_m, reach_m)
    whole = _window_layers(dem_m, cell_m, scenario, sited, altitudes_m, reach_m, trace=False)
    for key in ("visible", "detected", "pd"):
        whole[key][(slice(None), *window)] = inner[key]
    whole["min_altitude_m"][window] = inner["min_altitude_m"]
    return whole


def _window_layers(dem_m, cell_m, scenario: Scenario, sited: SitedSensor, altitudes_m, reach, trace=True) -> dict:
    """:func:`sensor_layers` on a grid holding the sensor's whole reach; ``trace`` False: nothing visible
    (the caller pastes the window's lines of sight), the geometry and field of regard alone."""
    spec = scenario.sensors[sited.name]
    k = K_FACTOR[spec.modality]
    detection = float(np.asarray(evaluate(scenario)[sited.name].range_m))
    rows, cols = np.indices(dem_m.shape)
    d_row, d_col = rows - sited.row, cols - sited.col
    ground = np.hypot(d_row, d_col) * cell_m
    eye = float(height_at(dem_m, np.array([sited.row]), np.array([sited.col]))[0]) + sited.mast_m  # as the viewshed
    # the sensor's own cell (the drone overhead) lies in every sector
    aimed = (np.abs(off_boresight_deg(bearing_deg(d_row, d_col), sited.azimuth_deg)) <= sited.sector_deg / 2) | (
        ground == 0.0
    )
    traced = (ground <= reach) & aimed
    barrier = trace and barrier_frequency_hz(scenario, sited.name) is not None
    visible, detected, pd, regards = [], [], [], []
    for altitude in altitudes_m:
        limits = _sensor_limits(sited, reach)
        seen = (
            viewshed(dem_m, cell_m, sited.row, sited.col, sited.mast_m, altitude, k, limits)
            if trace
            else np.zeros(dem_m.shape, dtype=bool)
        )
        rise = dem_m + altitude - eye
        slant = np.hypot(ground, rise)
        elevation = elevation_deg(ground, rise, k)
        regard = (
            aimed
            & (elevation >= sited.elevation_min_deg)
            & (elevation <= sited.elevation_max_deg)
            & (slant >= sited.min_range_m)
        )
        gate = seen & regard
        prob = np.zeros(dem_m.shape)
        prob[gate] = sensor_pd(scenario, sited.name, slant[gate]).pd
        heard = gate & (slant <= detection)
        if barrier:
            _hear_behind_terrain(scenario, sited, (dem_m, cell_m, eye), altitude, regard & ~seen & traced, prob, heard)
        visible.append(seen)
        detected.append(heard)
        pd.append(prob)
        regards.append(regard)
    detected_arr = np.array(detected)
    altitudes = np.asarray(altitudes_m, float)
    first = np.argmax(detected_arr, axis=0)
    min_altitude = np.where(detected_arr.any(axis=0), altitudes[first], np.nan)
    return {
        "visible": np.array(visible),
        "detected": detected_arr,
        "pd": np.array(pd),
        "min_altitude_m": min_altitude,
        "range_m": detection,
        "reach_m": reach,
        "altitudes_m": np.asarray(altitudes_m, float),
        "traced": traced,
        "aimed": aimed,
        "regard": np.array(regards),
    }


def fresnel_layers(dem_m: np.ndarray, cell_m: float, scenario: Scenario, sited: SitedSensor, layers: dict) -> dict:
    """First Fresnel zone clearance of an RF or radar sensor's link to the drone over each cell, per flight level.

    :func:`csuas.core.terrain.fresnel_clearance` at the sensor's carrier (:func:`link_frequency_ghz`) with
    k = 4/3, over the cells its :func:`sensor_layers` traced (its mapped reach and sector); a radar's two
    legs share the one path.

    Parameters
    ----------
    dem_m, cell_m, scenario, sited
        As :func:`sensor_layers`.
    layers : dict
        The sensor's :func:`sensor_layers` (its ``reach_m`` and ``visible`` grids; one per flight level).

    Returns
    -------
    dict
        ``clearance`` (A, rows, cols): the smallest clearance / r1 along each cell's path, NaN beyond the
        reach, outside the sector and where the path holds no terrain sample (cells closer than one cell);
        ``obstructed`` (A,): the share of the visible cells judged whose clearance is below
        :data:`FRESNEL_CLEAR` (NaN where none is visible).
    """
    wavelength = float(units.wavelength_m(link_frequency_ghz(scenario, sited.name)))
    k = K_FACTOR[scenario.sensors[sited.name].modality]
    limits = _sensor_limits(sited, layers["reach_m"])
    window = reach_window(dem_m.shape, sited, layers["reach_m"], cell_m)
    placed = in_window(sited, window)
    clearance, obstructed = [], []
    for visible, altitude in zip(layers["visible"], layers["altitudes_m"]):
        ratio = np.full(dem_m.shape, np.nan)
        ratio[window] = fresnel_clearance(
            dem_m[window], cell_m, (placed.row, placed.col, placed.mast_m), altitude, wavelength, k, limits
        )
        ratio[np.isinf(ratio)] = np.nan
        judged = visible & np.isfinite(ratio)
        obstructed.append(float((ratio[judged] < FRESNEL_CLEAR).mean()) if judged.any() else float("nan"))
        clearance.append(ratio)
    return {"clearance": np.array(clearance), "obstructed": np.array(obstructed)}


def _hear_behind_terrain(scenario: Scenario, sited: SitedSensor, site: tuple, altitude: float, hidden, prob, heard):
    """Pd and detection, in place, of the ``hidden`` cells an acoustic sensor hears over the terrain (ISO 9613-2)."""
    if not hidden.any():
        return
    dem_m, cell_m, eye = site
    rows, cols = np.nonzero(hidden)
    z = dem_m[rows, cols] + altitude
    slant = np.hypot(np.hypot(rows - sited.row, cols - sited.col) * cell_m, z - eye)
    targets = np.stack([rows.astype(float), cols.astype(float), z], axis=1)
    a_bar = terrain_barrier_db(scenario, sited.name, dem_m, cell_m, (sited.row, sited.col, eye), targets, slant)
    prob[rows, cols] = acoustic_pd_with_loss(scenario, sited.name, slant, a_bar)
    spec = scenario.sensors[sited.name]
    heard[rows, cols] = margin_db(scenario, spec, scenario.convention, slant) >= a_bar


def link_frequency_ghz(scenario: Scenario, sensor_name: str) -> float:
    """Carrier frequency [GHz] of an RF sensor (its own, or the drone's link, Table 33) or a radar (c / lambda)."""
    spec = scenario.sensors[sensor_name]
    if spec.modality == "rf":
        return rf_frequency_ghz(spec.params, scenario.target)
    if spec.modality == "radar":
        return radar_frequency_ghz(spec.params)
    raise ParameterError(f"sensors.{sensor_name}", spec.modality, "an RF or radar sensor")


def free_space_equivalent_range_m(path_gain_db, frequency_ghz):
    """The distance [m] whose free-space path gain (Eq. 54) equals ``path_gain_db``: 10^((-PG - FSPL(1 m)) / 20)."""
    return 10.0 ** ((-np.asarray(path_gain_db, dtype=float) - free_space_path_loss_db(frequency_ghz, 1.0)) / 20.0)


def multipath_detection(scenario: Scenario, sensor_name: str, path_gain_db, regard) -> tuple[np.ndarray, np.ndarray]:
    """Detected cells and Pd of an RF or radar sensor from a map of the path gain over the terrain.

    Every term of the sensor's link budget but the propagation stays the paper's, so the sensor detects
    a cell where the path gain is at least the free-space path gain at its detection range (for a
    monostatic radar the same one-way condition, both legs alike), and its Pd is that of the
    free-space equivalent range (:func:`free_space_equivalent_range_m`).

    Parameters
    ----------
    path_gain_db : ndarray (rows, cols)
        One-way path gain [dB] from the sensor to each cell at the flight level; -inf where no path.
    regard : ndarray bool (rows, cols)
        The cells in the sensor's field of regard (sector, elevation limits, minimum range).

    Returns
    -------
    tuple
        ``(detected, pd)``: bool and float grids; False and 0 outside the field of regard or where no path.
    """
    frequency = link_frequency_ghz(scenario, sensor_name)
    detection = float(np.asarray(evaluate(scenario)[sensor_name].range_m))
    gain = np.asarray(path_gain_db, dtype=float)
    gate = np.asarray(regard, dtype=bool) & np.isfinite(gain)
    threshold = -free_space_path_loss_db(frequency, detection) if detection > 0 else np.inf
    pd = np.zeros(gain.shape)
    if gate.any():
        pd[gate] = sensor_pd(scenario, sensor_name, free_space_equivalent_range_m(gain[gate], frequency)).pd
    return gate & (gain >= threshold), pd


def fused_layers(per_sensor: dict, k: int | None = None) -> dict:
    """Fused grids over sensors (altitude, rows, cols).

    Parameters
    ----------
    per_sensor : dict
        :func:`sensor_layers` of each sensor.
    k : int, optional
        Sensors that must detect for the k-of-n layers, 1 <= k <= n.

    Returns
    -------
    dict
        ``count`` detecting, ``detected`` (OR), ``pd`` (OR of independent Pd: 1 - prod(1 - Pd)); given
        ``k``, also ``k_of_n`` (count >= k) and ``pd_k_of_n`` (at least k of n detect: the exact
        Poisson-binomial tail).
    """
    detected = np.array([layers["detected"] for layers in per_sensor.values()])
    pd = np.array([layers["pd"] for layers in per_sensor.values()])
    count = detected.sum(axis=0)
    fused = {"count": count, "detected": detected.any(axis=0), "pd": fuse_or(pd)}
    if k is not None:
        fused["pd_k_of_n"] = fuse_k_of_n(pd, k)
        fused["k_of_n"] = count >= k
    return fused


def _sensor_limits(sited: SitedSensor, reach_m: float) -> RayLimits:
    """The rays a sited sensor's layers trace: out to its mapped reach (inf: all) and over its sector."""
    return RayLimits(
        None if np.isinf(reach_m) else reach_m,
        None if sited.sector_deg >= 360.0 else (sited.azimuth_deg, sited.sector_deg),
    )


def lowest_detected_level_m(pd, altitudes_m, threshold: float = PD_DETECTABLE) -> np.ndarray:
    """The lowest flight level [m] at which each cell's Pd reaches ``threshold`` (NaN where none does).

    Parameters
    ----------
    pd : ndarray (A, rows, cols)
        Pd at each flight level.
    altitudes_m : sequence of float
        The A flight levels [m], in any order.
    threshold : float
        Pd that counts as detected.
    """
    reached = np.asarray(pd, dtype=float) >= threshold
    lowest = np.where(reached, np.asarray(altitudes_m, dtype=float).reshape(-1, 1, 1), np.inf).min(axis=0)
    return np.where(np.isinf(lowest), np.nan, lowest)


def fused_visibility(dem_m: np.ndarray, cell_m: float, scenario: Scenario, sited: dict, per_sensor: dict) -> dict:
    """What all the sensors together see: per level how many see each cell, and the lowest heights seen and detected.

    Parameters
    ----------
    dem_m, cell_m, scenario
        As :func:`sensor_layers`.
    sited : dict
        Each sensor's :class:`SitedSensor`, by name.
    per_sensor : dict
        Each sensor's :func:`sensor_layers`, by name (the same flight levels).

    Returns
    -------
    dict
        ``visible_count`` (A, rows, cols): the sensors in whose line of sight the drone is (cumulative
        visibility); ``min_visible_height_m`` (rows, cols): the lowest height above the terrain at which
        any sensor has the drone in sight, the smallest of their
        :func:`csuas.core.terrain.lowest_visible_height_m` over the cells each traces (NaN where none
        does); ``min_detectable_height_m`` (rows, cols): the lowest of the site's flight levels at which
        the fused Pd (the OR of the sensors' Pd) reaches :data:`PD_DETECTABLE` (NaN where none does: a
        search over the declared levels only).
    """
    lowest = np.full(dem_m.shape, np.inf)
    for name, placed in sited.items():
        k = K_FACTOR[scenario.sensors[name].modality]
        reach = per_sensor[name]["reach_m"]
        window = reach_window(dem_m.shape, placed, reach, cell_m)
        local = in_window(placed, window)
        seen = lowest_visible_height_m(
            dem_m[window], cell_m, local.row, local.col, local.mast_m, k, _sensor_limits(placed, reach)
        )
        lowest[window] = np.minimum(lowest[window], seen)
    layers = list(per_sensor.values())
    return {
        "visible_count": np.sum([layer["visible"] for layer in layers], axis=0),
        "min_visible_height_m": np.where(np.isinf(lowest), np.nan, lowest),
        "min_detectable_height_m": lowest_detected_level_m(
            fuse_or(np.array([layer["pd"] for layer in layers])), layers[0]["altitudes_m"]
        ),
    }
