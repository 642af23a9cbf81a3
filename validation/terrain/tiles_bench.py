"""Benchmark ``coverage_tiles``: ``csuas coverage --scheduler local --workers 2`` on a large synthetic DEM.

The DEM is a seeded synthetic relief (:func:`synthetic_relief`: a sum of 8 plane waves of 2-40 km wavelength,
about 600 m of relief, 10 m cells) written block by block to a tiled, DEFLATE-compressed GeoTIFF in a temporary
folder, so no process ever holds the whole DEM; the site places four sensors of the default scenario whose
mapped reach is finite (EO, thermal, acoustic, radar: 0.2-6.8 km) at one flight level with 2-of-4 fusion. The
command runs as a child process (the CLI, as a user runs it) and reports its wall time, and each worker's peak
resident memory (``ru_maxrss``, coverage.json ``tiles.peak_rss_mib``); bytes per cell are that peak over the
cells of the DEM, the figure that stays bounded as the DEM grows.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

#: Cells a side of the benchmark's DEM (issue 25's figure) and of its tiles; cell size [m].
CELLS, TILE, CELL_M = 20_000, 2048, 10.0
#: Rows of the DEM generated and written at a time.
STRIP_ROWS = 512
WEST, NORTH = 300_000.0, 5_500_000.0
#: Sensors of the default scenario with a finite mapped reach, at fractions (down, across) of the DEM.
SENSORS = {"eo": (0.3, 0.3), "tir": (0.3, 0.7), "acoustic": (0.7, 0.3), "radar": (0.7, 0.7)}


def synthetic_relief(rows: slice, cols: slice, seed: int = 11, waves: int = 8) -> np.ndarray:
    """Heights [m] of a seeded relief over the given rows and columns: ``waves`` plane waves of random direction,
    2-40 km wavelength and 10-60 m amplitude on 10 m cells, plus 800 m; the same cells always get the same heights.

    Each wave sin(u r + v c + phase) is summed as sin(u r + phase) cos(v c) + cos(u r + phase) sin(v c): two outer
    products a wave instead of a sine a cell.
    """
    rng = np.random.default_rng(seed)
    bearing = rng.uniform(0.0, np.pi, waves)
    wavenumber = 2 * np.pi / (rng.uniform(2_000.0, 40_000.0, waves) / CELL_M)  # [rad / cell]
    amplitude, phase = rng.uniform(10.0, 60.0, waves), rng.uniform(0.0, 2 * np.pi, waves)
    r = np.arange(rows.start, rows.stop, dtype=float)[:, None]
    c = np.arange(cols.start, cols.stop, dtype=float)[None, :]
    heights = np.full((r.size, c.size), 800.0)
    for k in range(waves):
        down, across = r * wavenumber[k] * np.cos(bearing[k]) + phase[k], c * wavenumber[k] * np.sin(bearing[k])
        heights += amplitude[k] * (np.sin(down) * np.cos(across) + np.cos(down) * np.sin(across))
    return heights


def write_relief(path: Path, cells: int) -> None:
    """The relief of ``cells`` x ``cells`` as a tiled, compressed float32 GeoTIFF (UTM 33N), strip by strip."""
    import rasterio
    from rasterio.transform import from_origin
    from rasterio.windows import Window

    profile = {"driver": "GTiff", "height": cells, "width": cells, "count": 1, "dtype": "float32"}
    profile.update(crs="EPSG:32633", transform=from_origin(WEST, NORTH, CELL_M, CELL_M), tiled=True)
    profile.update(blockxsize=256, blockysize=256, compress="deflate", predictor=3, BIGTIFF="IF_SAFER")
    with rasterio.open(path, "w", **profile) as dst:
        for top in range(0, cells, STRIP_ROWS):
            bottom = min(top + STRIP_ROWS, cells)
            strip = synthetic_relief(slice(top, bottom), slice(0, cells)).astype(np.float32)
            dst.write(strip, 1, window=Window(0, top, cells, bottom - top))


def _site_text(cells: int) -> str:
    lines = ['dem = "dem.tif"', "altitudes_agl_m = [60.0]", "fusion_k = 2"]
    for name, (down, across) in SENSORS.items():
        x, y = WEST + (across * cells + 0.5) * CELL_M, NORTH - (down * cells + 0.5) * CELL_M
        lines += [f"[sensors.{name}]", f"x = {x:.1f}", f"y = {y:.1f}", "mast_m = 10.0"]
    return "\n".join(lines) + "\n"


def bench_coverage_tiles(cells: int = CELLS, tile: int | None = None, workers: int = 2, out_dir=None) -> dict:
    """Wall time, each worker's peak memory and bytes per cell of a tiled coverage run of ``cells`` x ``cells``.

    Parameters
    ----------
    cells : int
        Cells a side of the DEM (20 000 in issue 25; smaller for a quick run).
    tile : int, optional
        Cells a side of a tile (default: :data:`TILE`, or a quarter of the side of a smaller DEM: 16 tiles).
    workers : int
        Local Dask workers.
    out_dir : str, optional
        Where the DEM and the layers go (default: a temporary folder, removed after).
    """
    tile = tile or min(TILE, -(-cells // 4))
    if out_dir is not None:
        Path(out_dir).mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=out_dir) as folder:
        root = Path(folder)
        started = time.perf_counter()
        write_relief(root / "dem.tif", cells)
        dem_s = time.perf_counter() - started
        (root / "site.toml").write_text(_site_text(cells))
        command = [sys.executable, "-m", "csuas.cli", "coverage", str(root / "site.toml"), "--out", str(root / "out")]
        command += ["--scheduler", "local", "--workers", str(workers), "--tile", str(tile), "--json"]
        started = time.perf_counter()
        done = subprocess.run(command + ["--max-seconds", "1e6"], capture_output=True, text=True)
        wall_s = time.perf_counter() - started
        if done.returncode != 0:
            raise RuntimeError(f"csuas coverage failed ({done.returncode}): {done.stderr[-2000:]}")
        tiles = json.loads(done.stdout)["tiles"]
        layers = len(json.loads(done.stdout)["layers"])
        cog_mb = sum(p.stat().st_size for p in (root / "out").glob("*.tif")) / 1e6
    peak = max(tiles["peak_rss_mib"])
    return {
        "cells": f"{cells}x{cells}",
        "tile": tile,
        "tiles": tiles["tiles"],
        "workers": tiles["workers"],
        "layers": layers,
        "dem_write_s": dem_s,
        "wall_s": wall_s,
        "peak_rss_per_worker_mib": peak,
        "bytes_per_cell": peak * 2**20 / (cells * cells),
        "client_peak_rss_mib": tiles["client_peak_rss_mib"],
        "cog_mb": cog_mb,
    }
