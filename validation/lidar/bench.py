"""Benchmark of the lidar cross-section for ``csuas bench``.

Measures, on the DJI Mini 4 Pro mesh: Mitsuba's raw ``ray_intersect``
throughput, the throughput of the whole LCS pipeline (ray generation,
intersection, BSDF evaluation, accumulation) and their ratio; the time and
relative standard error of one LCS at each quality preset; the time of the
sphere-averaged LCS (Eq. 7) at draft and standard quality; and one
multi-bounce path-traced LCS. Every figure is measured after a warm-up run
(Dr.Jit compiles its kernels on first use).
"""

from __future__ import annotations

import math
import time

import numpy as np

from csuas.render.lidar.cross_section import QUALITY_PRESETS, RayGrid, lidar_cross_section
from csuas.render.lidar.path import path_traced_lcs
from csuas.render.lidar.sphere_average import mean_lidar_cross_section
from csuas.render.lidar.target import LidarTarget

#: Rays of the raw-throughput measurement.
RAW_RAYS = 1 << 21

#: View used for the single-direction figures (azimuth, elevation) [deg].
BENCH_VIEW = (30.0, 20.0)


def _raw_throughput(target: LidarTarget, n_rays: int, seed: int = 0) -> float:
    """Rays per second of ``scene.ray_intersect`` alone (with the host transfer of the hit distances)."""
    import mitsuba as mi

    scene = target.scene()
    rng = np.random.default_rng(seed)
    r = target.bounding_radius_m
    origins = np.stack([rng.uniform(-r, r, n_rays), rng.uniform(-r, r, n_rays), np.full(n_rays, 1.01 * r)])
    directions = np.zeros((3, n_rays))
    directions[2] = -1.0
    origins, directions = origins.astype(np.float32), directions.astype(np.float32)
    best = math.inf
    for _ in range(3):  # upload, intersect, download the distances: what the pipeline needs at the least
        start = time.perf_counter()
        si = scene.ray_intersect(mi.Ray3f(mi.Point3f(origins), mi.Vector3f(directions)))
        np.asarray(si.t)
        best = min(best, time.perf_counter() - start)
    return n_rays / best


def bench(preset: str = "dji_mini_4_pro") -> dict:
    """Lidar cross-section benchmark figures.

    Returns
    -------
    dict
        ``variant``; ``ray_intersect_rays_per_s``; ``lcs_pipeline_rays_per_s``
        and ``pipeline_efficiency`` (pipeline / raw); ``single_direction``:
        per preset ``{time_s, rays, lcs_m2, stderr_rel}``;
        ``sphere_average``: per preset ``{time_s, rays, n_directions,
        lcs_m2, stderr_rel}``; ``multibounce``: path-traced draft LCS
        ``{time_s, lcs_m2, stderr_rel, single_bounce_lcs_m2}``.
    """
    import mitsuba as mi

    from csuas.drone_models import build_drone

    target = LidarTarget.from_drone(build_drone(preset))
    az, el = BENCH_VIEW
    lidar_cross_section(target, az, el, quality="draft")  # warm-up: kernel compilation
    raw = _raw_throughput(target, RAW_RAYS)
    big = min(
        (lidar_cross_section(target, az, el, quality=RayGrid(512, 8)) for _ in range(3)),
        key=lambda r: r.time_s,
    )
    single = {}
    for name in QUALITY_PRESETS:
        r = lidar_cross_section(target, az, el, quality=name)
        single[name] = {"time_s": r.time_s, "rays": r.rays, "lcs_m2": r.lcs_m2, "stderr_rel": r.stderr_m2 / r.lcs_m2}
    averaged = {}
    for name in ("draft", "standard"):
        r = mean_lidar_cross_section(target, name)
        averaged[name] = {
            "time_s": r["time_s"],
            "rays": r["rays"],
            "n_directions": r["n_directions"],
            "lcs_m2": r["lcs_m2"]["mean"],
            "stderr_rel": r["lcs_m2"]["stderr"] / r["lcs_m2"]["mean"],
        }
    path_traced_lcs(target, az, el, max_depth=8, quality="draft")  # warm-up
    multi = path_traced_lcs(target, az, el, max_depth=8, quality="draft")
    return {
        "variant": mi.variant(),
        "target": preset,
        "ray_intersect_rays_per_s": raw,
        "lcs_pipeline_rays_per_s": big.rays / big.time_s,
        "pipeline_efficiency": (big.rays / big.time_s) / raw,
        "single_direction": single,
        "sphere_average": averaged,
        "multibounce": {
            "time_s": multi["time_s"],
            "lcs_m2": multi["lcs_m2"],
            "stderr_rel": multi["stderr_m2"] / multi["lcs_m2"],
            "max_depth": multi["max_depth"],
            "single_bounce_lcs_m2": single["standard"]["lcs_m2"],
        },
    }
