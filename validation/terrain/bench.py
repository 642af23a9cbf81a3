"""Benchmark of the viewshed against GDAL's ``gdal_viewshed`` on the same DEM, observer and curvature.

CPU seconds, not wall time: csuas's viewshed runs in this process (Numba, one thread; the kernels are
compiled before timing), GDAL's in a child process whose CPU (``RUSAGE_CHILDREN``) includes its own
start-up and the reading and writing of its GeoTIFFs. The DEM is a seeded random surface (integrated
Gaussian noise, 100 m of relief, 5 m cells); the observer stands on a 10 m mast off-centre and the
target flies 30 m above the terrain. Both results are also judged against the exact sight line
(:func:`csuas.validation.terrain.viewshed_oracles.sight_line_clearance_m`) on random cells.

Peak memory is the rise of the process's resident high-water mark (``VmHWM``, reset before the call
through ``/proc/self/clear_refs``; Linux) over its resident size before it, per cell of the DEM: what
the viewshed holds beyond the DEM (its result, one byte a cell, and its working arrays).
"""

from __future__ import annotations

import resource
import time
from pathlib import Path

import numpy as np

from csuas.core.terrain import viewshed
from csuas.validation.terrain.viewshed_oracles import (
    cell_relief_m,
    gdal_available,
    gdal_viewshed,
    sight_line_clearance_m,
)

#: Sizes of the comparison [cells per side].
SIZES = (1000, 2000, 4000, 8000)
CELL_M, MAST_M, TARGET_M, K_FACTOR = 5.0, 10.0, 30.0, 4.0 / 3.0
#: Random cells judged against the exact sight line at each size.
EXACT_CELLS = 300


def _children_cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _status_kib(field: str) -> float:
    """A ``/proc/self/status`` memory field [KiB] (NaN where there is none)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith(field + ":"):
                return float(line.split()[1])
    except OSError:
        pass
    return float("nan")


def _reset_peak() -> float:
    """Resets the resident high-water mark (Linux: ``clear_refs`` 5) and returns the resident size [KiB]."""
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        pass
    return _status_kib("VmRSS")


def random_relief(size: int, seed: int = 3) -> np.ndarray:
    """A seeded DEM of ``size`` x ``size`` cells with 100 m of relief, rounded to float32 as GDAL reads it [m]."""
    rng = np.random.default_rng(seed)
    dem = np.cumsum(np.cumsum(rng.normal(0.0, 1.0, (size, size)), 0), 1)
    dem = 100.0 * (dem - dem.min()) / (dem.max() - dem.min())
    return dem.astype(np.float32).astype(float)


def _exact_agreement(dem, row, col, results, seed: int) -> dict:
    """Share of ``EXACT_CELLS`` random cells where each result meets the exact sight line, and the largest
    miss of csuas's as a share of the DEM's largest step between neighbouring cells."""
    cells = np.random.default_rng(seed).integers(0, dem.shape, size=(EXACT_CELLS, 2))
    clearance = sight_line_clearance_m(dem, CELL_M, row, col, MAST_M, TARGET_M, K_FACTOR, cells)
    exact = clearance >= 0.0
    ours, theirs = (result[cells[:, 0], cells[:, 1]] for result in results)
    return {
        "csuas_exact": float(np.mean(ours == exact)),
        "gdal_exact": float(np.mean(theirs == exact)),
        "csuas_worst_miss_of_step": float(np.max(np.abs(clearance[ours != exact]), initial=0.0) / cell_relief_m(dem)),
    }


def bench_against_gdal(sizes=SIZES) -> list[dict]:
    """Per size: csuas's and GDAL's CPU seconds, their ratio, the share of cells they agree on, each one's
    agreement with the exact sight line, csuas's peak memory beyond the DEM per cell.

    Returns no rows when GDAL's program is missing.
    """
    if not gdal_available():
        return []
    viewshed(random_relief(16), CELL_M, 8, 5, MAST_M, TARGET_M, K_FACTOR)  # compile before timing
    rows = []
    for size in sizes:
        dem = random_relief(size)
        row, col = size // 2, size // 3
        rss_before = _reset_peak()
        cpu = time.process_time()
        ours = viewshed(dem, CELL_M, row, col, MAST_M, TARGET_M, K_FACTOR)
        ours_s = time.process_time() - cpu
        peak = _status_kib("VmHWM")
        children = _children_cpu_s()
        theirs = gdal_viewshed(dem, CELL_M, row, col, MAST_M, TARGET_M, K_FACTOR)
        gdal_s = _children_cpu_s() - children
        rows.append(
            {
                "cells": size * size,
                "csuas_cpu_s": ours_s,
                "gdal_cpu_s": gdal_s,
                "cpu_ratio": ours_s / gdal_s,
                "agreement": float(np.mean(ours == theirs)),
                **_exact_agreement(dem, row, col, (ours, theirs), seed=size),
                "peak_rise_bytes_per_cell": max(peak - rss_before, 0.0) * 1024.0 / (size * size),
            }
        )
    return rows
