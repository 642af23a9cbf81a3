"""``csuas coverage SITE --out DIR --scheduler ...``: the coverage by tiles on Dask, one Cloud Optimised GeoTIFF
a layer.

The DEM is cut into square tiles of output cells (``--tile`` cells a side). A tile's task reads, for each
sensor whose mapped reach touches it, the sensor's reach window of the DEM
(:func:`csuas.core.coverage.reach_window`, read by window from the GeoTIFF: no process holds the whole DEM),
computes that sensor's layers on it exactly as the single-process run does (which traces every sensor on
the same window), keeps the tile's cells, fuses the sensors cell by cell and writes the tile's layers,
one band each, to ``DIR/tiles/tile-R-C.tif`` with its covered-cell counts in ``tile-R-C.json`` (both
atomically; the JSON last). A tile whose JSON is there is skipped when the command is run again on the
same folder with the same inputs (``DIR/coverage-tiles-state.json`` holds their digest: the site, the
scenario, the DEM's bytes and the tile size). When every tile is done, each layer's tiles are mosaicked
(a GDAL VRT) into ``DIR/<layer>.tif``: a Cloud Optimised GeoTIFF (GDAL's COG driver: 256-cell blocks,
DEFLATE with the floating-point predictor, overviews by nearest neighbour, NaN as nodata, the band's
description and unit), and ``DIR/coverage.json`` lists the layers and areas as the single-process run does.

Every layer's cells are those of the single-process run (tested); that run's PNG maps, GeoJSON,
GeoPackage and KML, which hold a whole map, are not written by tiles, nor is a Sionna radio map (it
traces the whole scene). Memory per worker: one tile's layers and one sensor's reach window at a time;
a sensor whose reach covers the whole DEM (it still detects at its farthest corner) needs the whole DEM.
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
import time
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from csuas.base.errors import ParameterError
from csuas.base.fileio import atomic_path, write_text_atomic
from csuas.base.paths import inside, sub_folder
from csuas.core.coverage import (
    FRESNEL_CLEAR,
    fresnel_layers,
    fused_layers,
    fused_visibility,
    in_window,
    lowest_detected_level_m,
    reach_window,
    sensor_layers,
)
from csuas.core.fusion import fuse_or
from csuas.render.site import dem_path, load_dem
from csuas.sweep.cluster import open_client, show_progress

#: Cells a side of a tile by default (a tile's 40-odd float32 layers: about 170 MB).
TILE_CELLS = 1024
#: The smallest tile a side [cells].
MIN_TILE_CELLS = 16
#: The folder of the tiles inside --out, and the file holding the inputs' digest.
TILES_DIR, STATE_NAME = "tiles", "coverage-tiles-state.json"
#: GTiff creation options of a tile's bands.
TILE_OPTIONS = {"compress": "deflate", "predictor": 3, "tiled": True, "blockxsize": 256, "blockysize": 256}


@dataclass(frozen=True)
class TiledSite:
    """What a tile's task needs: the DEM (path, or None for the demo), its grid, the sited sensors and layers.

    ``layers`` holds, in coverage.json's order, each layer's ``(sensor, altitude or None, kind)``; the layers of
    ``value_kinds`` count every finite cell as covered (the others: the cells above 0);
    ``reach_m`` each sensor's mapped reach over the whole DEM [m]; ``fill_m`` the height nodata cells take
    (the lowest valid one, as the single-process run's) or None.
    """

    dem: str | None
    shape: tuple[int, int]
    cell_m: float
    fill_m: float | None
    scenario: object
    sited: dict
    reach_m: dict
    altitudes: tuple
    fusion_k: int | None
    fresnel: tuple
    layers: tuple
    value_kinds: tuple
    tile: int


def tile_bounds(shape: tuple[int, int], tile: int) -> list[tuple[int, int, int, int]]:
    """The tiles of a grid, row-major: ``(row0, row1, col0, col1)`` (the last ones may be smaller)."""
    return [
        (r, min(r + tile, shape[0]), c, min(c + tile, shape[1]))
        for r in range(0, shape[0], tile)
        for c in range(0, shape[1], tile)
    ]


def dem_header(dem: str | None, site_path):
    """``(rows, cols), transform, crs, cell`` of a DEM the tiles can read by window: north-up, projected, square
    cells (a ParameterError naming ``dem`` otherwise); the demo terrain's without one."""
    if dem is None:
        heights, transform, crs, cell = load_dem(None, None)
        return heights.shape, transform, crs, cell
    import rasterio

    path = dem_path(dem, site_path)
    with rasterio.open(path) as src:
        transform, crs, shape = src.transform, src.crs, (src.height, src.width)
    north_up = transform.a > 0 and transform.e < 0 and not (transform.b or transform.d)
    if crs is None or not crs.is_projected or not north_up or abs(transform.a + transform.e) > 1e-6 * transform.a:
        raise ParameterError(
            "dem",
            dem,
            "for --scheduler, a north-up GeoTIFF in a projected CRS with square cells (reproject it first, e.g. "
            "gdalwarp -t_srs EPSG:326zz; without --scheduler the command reprojects it)",
        )
    if min(shape) < 2:
        raise ParameterError("dem", dem, f"a grid of at least 2 x 2 cells (this one: {shape[0]} x {shape[1]})")
    return shape, transform, str(crs), float(transform.a)


def nodata_fill_m(path: str | None) -> float | None:
    """The lowest valid height of the DEM [m] when it has nodata cells (they take it), read block by block."""
    if path is None:
        return None
    import rasterio

    lowest, holes = math.inf, False
    with rasterio.open(path) as src:
        if src.nodata is None:
            return None
        for _, window in src.block_windows(1):
            block = src.read(1, window=window, masked=True).astype(float)
            holes |= bool(np.ma.is_masked(block))
            if block.count():
                lowest = min(lowest, float(block.min()))
    return lowest if holes else None


@lru_cache(maxsize=1)
def _demo_heights() -> np.ndarray:
    return load_dem(None, None)[0]


def read_window(site: TiledSite, window: tuple[slice, slice]) -> np.ndarray:
    """The DEM's heights [m] (float64) over ``window``, nodata filled as :func:`csuas.render.site.load_dem` does."""
    if site.dem is None:
        return _demo_heights()[window]
    import rasterio
    from rasterio.windows import Window

    rows, cols = window
    with rasterio.open(site.dem) as src:
        block = src.read(
            1, window=Window(cols.start, rows.start, cols.stop - cols.start, rows.stop - rows.start), masked=True
        ).astype(float)
    if np.ma.is_masked(block):
        block = block.filled(site.fill_m)
    heights = np.asarray(block)
    if not np.isfinite(heights).all():
        raise ParameterError("dem", site.dem, "finite heights [m] (nodata cells marked as the GeoTIFF's nodata)")
    return heights


def _empty_grids(levels: int, shape: tuple[int, int]) -> dict:
    """A sensor's grids over cells beyond its reach: nothing visible, traced or detected."""
    return {
        "visible": np.zeros((levels, *shape), bool),
        "detected": np.zeros((levels, *shape), bool),
        "pd": np.zeros((levels, *shape)),
        "traced": np.zeros(shape, bool),
        "min_altitude_m": np.full(shape, np.nan),
        "min_visible_height_m": np.full(shape, np.nan),
        "clearance": np.full((levels, *shape), np.nan),
    }


def _overlap(site: TiledSite, name: str, bounds: tuple) -> tuple | None:
    """The cells ``(row0, row1, col0, col1)`` of ``bounds`` inside the sensor's reach window (None: none)."""
    rows, cols = reach_window(site.shape, site.sited[name], site.reach_m[name], site.cell_m)
    r0, r1, c0, c1 = bounds
    top, bottom, left, right = max(r0, rows.start), min(r1, rows.stop), max(c0, cols.start), min(c1, cols.stop)
    return (top, bottom, left, right) if top < bottom and left < right else None


def _sensor_tile(site: TiledSite, name: str, bounds: tuple) -> dict:
    """One sensor's grids over ``bounds``: computed on its reach window, cropped; empty beyond it."""
    r0, r1, c0, c1 = bounds
    grids = _empty_grids(len(site.altitudes), (r1 - r0, c1 - c0))
    overlap = _overlap(site, name, bounds)
    if overlap is None:
        return grids
    top, bottom, left, right = overlap
    placed, reach = site.sited[name], site.reach_m[name]
    rows, cols = reach_window(site.shape, placed, reach, site.cell_m)
    dem = read_window(site, (rows, cols))
    local = in_window(placed, (rows, cols))
    layers = sensor_layers(dem, site.cell_m, site.scenario, local, site.altitudes, reach_m=reach)
    found = {key: layers[key] for key in ("visible", "detected", "pd", "traced", "min_altitude_m")}
    found["min_visible_height_m"] = fused_visibility(dem, site.cell_m, site.scenario, {name: local}, {name: layers})[
        "min_visible_height_m"
    ]
    if name in site.fresnel:
        found["clearance"] = fresnel_layers(dem, site.cell_m, site.scenario, local, layers)["clearance"]
    inner = (slice(top - rows.start, bottom - rows.start), slice(left - cols.start, right - cols.start))
    outer = (slice(top - r0, bottom - r0), slice(left - c0, right - c0))
    for key, grid in found.items():
        grids[key][(Ellipsis, *outer)] = grid[(Ellipsis, *inner)]
    return grids


def tile_layers(site: TiledSite, bounds: tuple) -> dict:
    """Every layer's float32 grid over one tile, by ``(sensor, altitude, kind)``, as the single-process run
    writes it; and the Fresnel counts ``(sensor, altitude) -> (obstructed, judged)``.

    Only the box of the tile's cells within some sensor's reach is computed; the cells outside every reach
    take the values the same functions give a cell that no sensor reaches (computed on one such cell).
    """
    r0, r1, c0, c1 = bounds
    nowhere = _fused_grids(site, {name: _empty_grids(len(site.altitudes), (1, 1)) for name in site.sited})
    grids = {key: np.full((r1 - r0, c1 - c0), grid[0, 0], np.float32) for key, grid in nowhere["grids"].items()}
    boxes = [box for name in site.sited if (box := _overlap(site, name, bounds)) is not None]
    if not boxes:
        return {"grids": grids, "fresnel": nowhere["fresnel"]}
    active = (min(b[0] for b in boxes), max(b[1] for b in boxes), min(b[2] for b in boxes), max(b[3] for b in boxes))
    found = _fused_grids(site, {name: _sensor_tile(site, name, active) for name in site.sited})
    inner = (slice(active[0] - r0, active[1] - r0), slice(active[2] - c0, active[3] - c0))
    for key, grid in found["grids"].items():
        grids[key][inner] = grid
    return {"grids": grids, "fresnel": found["fresnel"]}


def _fused_grids(site: TiledSite, per_sensor: dict) -> dict:
    """The layers' float32 grids from each sensor's grids over the same cells (fused cell by cell); the Fresnel
    counts ``(sensor, altitude) -> (obstructed, judged)``."""
    fused = fused_layers(per_sensor, site.fusion_k)
    fused["visible_count"] = np.sum([g["visible"] for g in per_sensor.values()], axis=0)
    fused["min_visible_height"] = np.fmin.reduce([g["min_visible_height_m"] for g in per_sensor.values()])
    pd = fuse_or(np.array([g["pd"] for g in per_sensor.values()]))
    fused["min_detectable_height"] = lowest_detected_level_m(pd, site.altitudes)
    grids, fresnel = {}, {}
    for i, altitude in enumerate(site.altitudes):
        for name, g in per_sensor.items():
            visible = g["visible"][i].astype(np.float32)
            visible[~g["traced"]] = np.nan
            grids[(name, altitude, "visible")] = visible
            grids[(name, altitude, "detected")] = g["detected"][i].astype(np.float32)
            grids[(name, altitude, "pd")] = g["pd"][i].astype(np.float32)
            ratio = g["clearance"][i]
            grids[(name, altitude, "fresnel_clearance")] = ratio.astype(np.float32)
            judged = g["visible"][i] & np.isfinite(ratio)
            fresnel[(name, altitude)] = (int((ratio[judged] < FRESNEL_CLEAR).sum()), int(judged.sum()))
        for quantity, grid in fused.items():
            if grid.ndim == 3:
                grids[("fused", altitude, quantity)] = grid[i].astype(np.float32)
    for name, g in per_sensor.items():
        grids[(name, None, "min_altitude")] = g["min_altitude_m"].astype(np.float32)
    for quantity in ("min_visible_height", "min_detectable_height"):
        grids[("fused", None, quantity)] = fused[quantity].astype(np.float32)
    return {"grids": {key: grids[key] for key in site.layers}, "fresnel": fresnel}


def window_tiles(shape: tuple[int, int], window: tuple[slice, slice], tile: int) -> tuple[int, int]:
    """The cells of a window and the tiles of ``tile`` cells a side it touches (each traces it once)."""
    rows, cols = window
    touched = (-(-rows.stop // tile) - rows.start // tile) * (-(-cols.stop // tile) - cols.start // tile)
    return (rows.stop - rows.start) * (cols.stop - cols.start), touched


def peak_rss_mib() -> float:
    """This process's peak resident memory [MiB] (``ru_maxrss``, KiB on Linux)."""
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _tile_name(bounds: tuple) -> str:
    return f"tile-{bounds[0]:06d}-{bounds[2]:06d}"


def write_tile(site: TiledSite, bounds: tuple, folder: str, where: dict) -> dict:
    """One tile's task: its layers as the bands of ``folder/tile-R-C.tif``, then its counts in ``tile-R-C.json``
    (the mark that the tile is done). Returns the counts: covered cells per layer, Fresnel (obstructed, judged)."""
    import rasterio
    from rasterio.windows import Window, transform

    found = tile_layers(site, bounds)
    r0, r1, c0, c1 = bounds
    stem = Path(folder) / _tile_name(bounds)
    profile = {
        "driver": "GTiff",
        "height": r1 - r0,
        "width": c1 - c0,
        "count": len(site.layers),
        "dtype": "float32",
        "crs": where["crs"],
        "transform": transform(Window(c0, r0, c1 - c0, r1 - r0), where["transform"]),
        "nodata": float("nan"),
        "interleave": "band",
        **TILE_OPTIONS,
    }
    covered = []
    with atomic_path(stem.with_suffix(".tif")) as tmp, rasterio.open(tmp, "w", **profile) as dst:
        for band, layer in enumerate(site.layers, 1):
            grid = found["grids"][layer]
            dst.write(grid, band)
            covered.append(int((np.isfinite(grid) if layer[2] in site.value_kinds else np.nan_to_num(grid) > 0).sum()))
    fresnel = [list(found["fresnel"][(n, a)]) for n in site.fresnel for a in site.altitudes]
    counts = {"covered": covered, "fresnel": fresnel}
    write_text_atomic(stem.with_suffix(".json"), json.dumps(counts))
    return counts


def inputs_digest(site_table: dict, scenario, dem: str | None, tile: int) -> str:
    """SHA-256 of what the tiles depend on: the site's table, the scenario, the DEM's bytes and the tile size."""
    digest = hashlib.sha256()
    digest.update(json.dumps(site_table, sort_keys=True, default=str).encode())
    digest.update(repr(scenario).encode())
    digest.update(f"tile={tile}".encode())
    if dem is not None:
        with open(dem, "rb") as stream:
            for chunk in iter(lambda: stream.read(1 << 22), b""):
                digest.update(chunk)
    return digest.hexdigest()


def _check_state(out: Path, digest: str) -> None:
    """Refuse a folder holding another run's tiles; record this run's digest."""
    state = inside(out, STATE_NAME)
    if state.exists():
        if json.loads(state.read_text()).get("digest") != digest:
            raise ParameterError(
                "--out", str(out), "a new folder, or the folder of this same tiled run (it holds another run's tiles)"
            )
    else:
        write_text_atomic(state, json.dumps({"digest": digest}))


def _done(folder: Path, bounds: tuple, bands: int) -> dict | None:
    """A tile's counts when its files are there and whole (else None: it is run again)."""
    stem = folder / _tile_name(bounds)
    try:
        counts = json.loads(stem.with_suffix(".json").read_text())
    except (OSError, ValueError):
        return None
    if not stem.with_suffix(".tif").is_file() or len(counts.get("covered", [])) != bands:
        return None
    return counts


def run_tiles(site: TiledSite, out: Path, run: dict, where: dict, progress=None) -> dict:
    """Run every tile not yet done in ``out`` (``run``: ``scheduler``, ``workers``, ``digest``); the counts of each
    tile, by its bounds, what ran, and the peak resident memory of each process that ran tiles [MiB].
    ``progress``: the stream of the progress line (default: ``sys.stderr`` as it is at the call)."""
    progress = sys.stderr if progress is None else progress
    _check_state(out, run["digest"])
    folder = sub_folder(out, TILES_DIR)
    bounds = tile_bounds(site.shape, site.tile)
    counts = {b: c for b in bounds if (c := _done(folder, b, len(site.layers))) is not None}
    todo = [b for b in bounds if b not in counts]
    started, workers = time.perf_counter(), 1
    if run["scheduler"] == "serial" or not todo:
        for done, b in enumerate(todo, 1):
            counts[b] = write_tile(site, b, str(folder), where)
            show_progress("coverage: tiles", done, len(todo), started, progress)
        rss = [peak_rss_mib()]
    else:
        from distributed import as_completed

        client, cluster = open_client(run["scheduler"], run["workers"])
        try:
            workers = len(client.scheduler_info().get("workers", {}))
            futures = {
                client.submit(write_tile, site, b, str(folder), where, key=f"csuas-cov-{run['digest'][:12]}-{i}"): b
                for i, b in enumerate(todo)
            }
            for done, future in enumerate(as_completed(futures), 1):
                counts[futures[future]] = future.result()
                show_progress("coverage: tiles", done, len(todo), started, progress)
            rss = sorted(client.run(peak_rss_mib).values())
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    return {"counts": counts, "tiles": len(bounds), "run": len(todo), "workers": workers, "peak_rss_mib": rss}
