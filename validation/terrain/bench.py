"""Benchmark of the viewshed against GDAL's ``gdal_viewshed`` on the same DEM, observer and curvature.

CPU seconds, not wall time: csuas's viewshed runs in this process (Numba, one thread; the kernels are
compiled before timing), GDAL's in a child process whose CPU (``RUSAGE_CHILDREN``) includes its own
start-up and the reading and writing of its GeoTIFFs. The DEM is a seeded random surface (integrated
Gaussian noise, 100 m of relief, 5 m cells); the observer stands on a 10 m mast off-centre and the
target flies 30 m above the terrain.
"""

from __future__ import annotations

import resource
import time

import numpy as np

from csuas.core.terrain import viewshed
from csuas.validation.terrain.viewshed_oracles import gdal_available, gdal_viewshed

#: Sizes of the comparison [cells per side].
SIZES = (1000, 2000, 4000, 8000)
CELL_M, MAST_M, TARGET_M, K_FACTOR = 5.0, 10.0, 30.0, 4.0 / 3.0


def _children_cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def random_relief(size: int, seed: int = 3) -> np.ndarray:
    """A seeded DEM of ``size`` x ``size`` cells with 100 m of relief, rounded to float32 as GDAL reads it [m]."""
    rng = np.random.default_rng(seed)
    dem = np.cumsum(np.cumsum(rng.normal(0.0, 1.0, (size, size)), 0), 1)
    dem = 100.0 * (dem - dem.min()) / (dem.max() - dem.min())
    return dem.astype(np.float32).astype(float)


def bench_against_gdal(sizes=SIZES) -> list[dict]:
    """Per size: csuas's and GDAL's CPU seconds, their ratio, the share of cells they agree on, csuas's peak memory.

    Returns no rows when GDAL's program is missing.
    """
    if not gdal_available():
        return []
    viewshed(random_relief(16), CELL_M, 8, 5, MAST_M, TARGET_M, K_FACTOR)  # compile before timing
    rows = []
    for size in sizes:
        dem = random_relief(size)
        row, col = size // 2, size // 3
        rss_before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        cpu = time.process_time()
        ours = viewshed(dem, CELL_M, row, col, MAST_M, TARGET_M, K_FACTOR)
        ours_s = time.process_time() - cpu
        rss_after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
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
                "peak_rise_bytes_per_cell": max(rss_after - rss_before, 0) * 1024.0 / (size * size),
            }
        )
    return rows
