"""Cost of ``csuas coverage`` (time and peak memory), from the DEM's size, the sensors and the flight levels.

Each sensor traces one viewshed per flight level (:func:`csuas.core.terrain.viewshed`, in
proportion to the cells), each RF or radar sensor also one Fresnel clearance layer per level
(:func:`csuas.core.terrain.fresnel_clearance`, each cell's own path: cells^1.5), every layer is
written as a GeoTIFF (and a detected layer as GeoJSON) by the main process and as a PNG map by one of
the map workers (``csuas.commands.coverage_files.MapWriter``: a fixed part and a part in proportion
to the cells, shared among the workers), and a radio map costs one Sionna RT run per sensor and level.
The process holds the DEM, every sensor's grids per level, the fused grids and, at its peak,
one map's images (a viewshed adds only its result, 1 byte a cell: docs/performance.md).

Times are for 2 idle CPU cores: the demo site took 27.6 s wall (37.7 CPU-s) before its PNG maps were
drawn once in two workers and its radio maps' replicas stopped rebuilding the scene (README), 47 maps
at 0.34 s each of it; a map now costs 0.16-0.25 CPU-s from 200^2 to 800^2 cells (measured with the
process's CPU time at a load average of 13, which counts what the map itself uses), and a radio map of
the demo at 2^20 rays :data:`RADIO_MAP_SECONDS`. The viewshed and Fresnel shares were split between a
fixed and a per-cell part as measured under load (synthetic DEMs of 200^2, 400^2 and 800^2 cells with 3
sensors and 2 or 6 levels took 14.9, 18.0, 41.2 and 48.5 s on 2 CPU cores at a load average of 10-20,
about 7 times the idle figures). Memory does not depend on the load: 425, 476 and 703 MB (ru_maxrss)
for 200^2, 400^2 and 800^2 cells with 3 sensors and 2 levels (two Fresnel links) since the viewshed's
rays are swept (2026-11-27; 201, 289 and 757 MB before, when they held 690 bytes a cell): about 470
bytes a cell and 400 MB before the grids. The ``cost_models`` benchmark compares the model with
measurements on three sizes.
"""

from __future__ import annotations

from csuas.base.cost import Estimate

#: Start: imports (rasterio, matplotlib), the scenario and the DEM [s].
START_SECONDS = 1.0
#: One viewshed and Pd map of one sensor and level: fixed part [s] and per cell [s].
TRACE_SECONDS = 0.02
TRACE_CELL_SECONDS = 0.6e-6
#: One layer written by the main process (GeoTIFF, GeoJSON): fixed part [s] and per cell [s] (0.48 CPU-s for
#: the demo's 47 layers of 400^2 cells, measured).
LAYER_SECONDS = 0.004
LAYER_CELL_SECONDS = 0.04e-6
#: One PNG map drawn and written by a map worker: fixed part [s] and per cell [s] (0.16 CPU-s at 200^2 cells,
#: 0.25 at 800^2, measured), and the workers sharing them (MapWriter's on 2 CPU cores).
MAP_SECONDS = 0.16
MAP_CELL_SECONDS = 0.15e-6
MAP_WORKERS = 2
#: The map workers' start: each imports matplotlib (0.73 CPU-s, measured) beside the main process's work.
MAP_WORKERS_START_SECONDS = 0.7
#: One Sionna RT radio map of one sensor and level at :data:`RADIO_MAP_SAMPLES` rays per replica [s]; other
#: ray counts in proportion (assumed: tracing dominates). 4.8 s idle while every replica rotated the scene;
#: turning the rays instead took 0.31 times the wall and 0.30 times the CPU of that for the demo's two maps,
#: side by side at a load average of 11-15 (20.8 s against 66.9 s, 7.0 against 22.9 CPU-s).
RADIO_MAP_SECONDS = 1.5
RADIO_MAP_SAMPLES = 2**20
#: One Fresnel clearance layer of one RF or radar link and level, per cell and terrain sample of its own
#: path (about sqrt(cells) samples a cell over a whole DEM) [s]: 1.7 s a level for the demo's RF sensor
#: (400^2 cells all round) at a load average of 6 on 2 CPU cores, taken as half that idle.
FRESNEL_CELL_SAMPLE_SECONDS = 1.3e-8
#: Memory per cell and level of each Fresnel clearance grid kept (float64) [B].
FRESNEL_LEVEL_CELL_BYTES = 8.0
#: Resident memory before the grids (interpreter, rasterio, matplotlib) [B]: the intercept of the three
#: measured peaks (module docstring); with a radio map, Sionna's 210 MB more (measured as 350 MB against
#: 140 MB when the process was smaller) [B].
PROCESS_BYTES = 400e6
RADIO_PROCESS_BYTES = PROCESS_BYTES + 210e6
#: Memory per cell at the peak (the DEM, hillshade, one map's images; a viewshed's result) [B]: the measured
#: 470 bytes a cell (module docstring) less the grids kept for 3 sensors, 2 levels and 2 Fresnel links.
CELL_BYTES = 330.0
#: Memory per cell and level of each sensor's kept grids (visible, detected, Pd, regard) [B], and of
#: the fused grids per level [B].
SENSOR_LEVEL_CELL_BYTES = 11.0
FUSED_LEVEL_CELL_BYTES = 24.0
#: Layers per sensor and level (visible, detected, Pd); per level of the fused grids (count, detected,
#: Pd, visible count, and with a k-of-n rule two more); per radio map (path gain, its bound, detected, Pd);
#: fused over all levels (the lowest visible and detectable heights).
SENSOR_LAYERS, FUSED_LAYERS, FUSED_K_LAYERS, RADIO_LAYERS, FUSED_HEIGHT_LAYERS = 3, 4, 2, 4, 2


def coverage_estimate(
    cells: tuple[int, int],
    sensors: int,
    levels: int,
    k_of_n: bool,
    radio_maps: int = 0,
    radio_samples: int = 2**20,
    fresnel_links: int = 0,
) -> Estimate:
    """Time and peak memory of a coverage run.

    Parameters
    ----------
    cells : (int, int)
        The DEM's rows and columns.
    sensors : int
        Sited sensors.
    levels : int
        Flight levels (``altitudes_agl_m``).
    k_of_n : bool
        Whether the fused k-of-n layers are written (``fusion_k``).
    radio_maps : int
        Sensors with a radio map (each mapped at every level).
    radio_samples : int
        Rays per replica of each radio map.
    fresnel_links : int
        RF and radar sensors, each with a Fresnel clearance layer per level (traced over the whole DEM:
        an upper bound where the sensor's reach is shorter).
    """
    n = float(cells[0]) * float(cells[1])
    layers = sensors * (SENSOR_LAYERS * levels + 1) + (FUSED_LAYERS + (FUSED_K_LAYERS if k_of_n else 0)) * levels
    layers += (RADIO_LAYERS * radio_maps + fresnel_links) * levels + FUSED_HEIGHT_LAYERS
    seconds = START_SECONDS + MAP_WORKERS_START_SECONDS + sensors * levels * (TRACE_SECONDS + TRACE_CELL_SECONDS * n)
    seconds += (
        layers * (LAYER_SECONDS + LAYER_CELL_SECONDS * n)
        + layers * (MAP_SECONDS + MAP_CELL_SECONDS * n) / MAP_WORKERS
        + radio_maps * levels * RADIO_MAP_SECONDS * radio_samples / RADIO_MAP_SAMPLES
    )
    seconds += fresnel_links * levels * FRESNEL_CELL_SAMPLE_SECONDS * n * n**0.5
    kept = levels * (
        SENSOR_LEVEL_CELL_BYTES * (sensors + radio_maps)
        + FUSED_LEVEL_CELL_BYTES
        + FRESNEL_LEVEL_CELL_BYTES * fresnel_links
    )
    peak = (RADIO_PROCESS_BYTES if radio_maps else PROCESS_BYTES) + n * (CELL_BYTES + kept)
    what = (
        f"coverage of {cells[0]:,} x {cells[1]:,} cells, {sensors} sensor(s), {levels} flight level(s)"
        + (f", {radio_maps} radio map(s) a level" if radio_maps else "")
        + f" ({layers:,} layers)"
    )
    return Estimate(what, seconds, peak)


#: Bytes per cell of a tile a worker holds: its layers (float32) and each sensor's grids cut to it (float64, bool).
TILE_LAYER_CELL_BYTES = 4.0
#: Bytes per cell of the reach window a worker traces (the DEM's float64 heights, one viewshed's horizons,
#: the sensor's grids over the window): 480 MiB peak per worker measured with a 1363^2 window and 500^2 tiles
#: (csuas bench --only coverage_tiles --coverage-cells 2000), less the process and the tile: about 170 B.
WINDOW_CELL_BYTES = 200.0
#: Start of a Dask cluster of local workers, each importing csuas [s].
CLUSTER_START_SECONDS = 5.0


def coverage_tiles_estimate(cells: tuple[int, int], windows: list, tiling: tuple, levels: int, layers: int) -> Estimate:
    """Time and peak memory per worker of a coverage run by tiles (``csuas coverage --scheduler``).

    Each tile traces, for every sensor whose reach window touches it, that whole window
    (:func:`csuas.core.coverage.reach_window`), so a window is traced once per tile it touches; every layer is
    written once by tiles and once as a COG (the per-cell part of :data:`LAYER_CELL_SECONDS`). The tiles share the
    workers; a worker holds one tile's layers and one sensor's window at its peak.

    Parameters
    ----------
    cells : (int, int)
        The DEM's rows and columns.
    windows : list of (int, int, bool)
        Per sensor: the cells of its reach window, the tiles it touches, and whether it has a Fresnel layer.
    tiling : (int, int)
        Cells of a tile, and the workers (1 for ``serial``).
    levels, layers : int
        Flight levels, and layers written.
    """
    n = float(cells[0]) * float(cells[1])
    tile_cells, workers = tiling
    traced = sum(float(w) * touched for w, touched, _ in windows)
    fresnel = sum(float(w) ** 1.5 * touched for w, touched, has in windows if has)
    work = levels * (TRACE_CELL_SECONDS * traced + FRESNEL_CELL_SAMPLE_SECONDS * fresnel)
    work += 2.0 * layers * LAYER_CELL_SECONDS * n
    seconds = START_SECONDS + (CLUSTER_START_SECONDS if workers > 1 else 0.0) + work / workers
    largest = max((float(w) for w, _, _ in windows), default=0.0)
    kept = layers * TILE_LAYER_CELL_BYTES + levels * len(windows) * (SENSOR_LEVEL_CELL_BYTES + FRESNEL_LEVEL_CELL_BYTES)
    peak = PROCESS_BYTES + tile_cells * kept + largest * WINDOW_CELL_BYTES
    what = (
        f"coverage by tiles of {cells[0]:,} x {cells[1]:,} cells, {len(windows)} sensor(s), {levels} flight "
        f"level(s) ({layers:,} layers), memory per worker"
    )
    return Estimate(what, seconds, peak)
