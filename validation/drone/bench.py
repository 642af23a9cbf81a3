"""Benchmark: exact silhouette metrics of the DJI Mini 4 Pro for many view directions."""

from __future__ import annotations

import time

import numpy as np

from csuas.drone_models.geometry import fibonacci_sphere
from csuas.drone_models.presets import build_drone
from csuas.drone_models.silhouette import SilhouetteModel, metrics_for_directions


def bench_silhouette(n_directions: int = 1000, n_reference: int = 50, preset: str = "dji_mini_4_pro") -> dict:
    """Time the silhouette metrics of ``preset`` for ``n_directions`` Fibonacci directions.

    The fast path (convex hull per closed convex shell, then polygon union)
    is compared on the first ``n_reference`` directions with the reference
    path (union of every front-facing triangle); both are exact, so their
    areas must agree to rounding.

    Returns
    -------
    dict
        ``n_directions``, ``n_faces``, ``n_shells``, ``prepare_s``, ``time_s``,
        ``directions_per_s``, ``ms_per_direction``, ``reference_ms_per_direction``,
        ``speedup_vs_triangle_union``, ``max_area_difference_m2``, ``mean_projected_area_m2``.
    """
    drone = build_drone(preset)
    directions = fibonacci_sphere(n_directions)
    start = time.perf_counter()
    model = SilhouetteModel.from_drone(drone)
    prepare = time.perf_counter() - start
    start = time.perf_counter()
    fast = metrics_for_directions(model, directions)
    elapsed = time.perf_counter() - start
    reference_model = SilhouetteModel.from_drone(drone, use_convex_hulls=False)
    start = time.perf_counter()
    reference = metrics_for_directions(reference_model, directions[:n_reference])
    reference_elapsed = time.perf_counter() - start
    ms_fast = 1e3 * elapsed / n_directions
    ms_ref = 1e3 * reference_elapsed / n_reference
    return {
        "preset": preset,
        "n_directions": n_directions,
        "n_faces": int(sum(len(p.mesh.faces) for p in drone.parts)),
        "n_shells": model.n_shells,
        "prepare_s": prepare,
        "time_s": elapsed,
        "directions_per_s": n_directions / elapsed,
        "ms_per_direction": ms_fast,
        "reference_ms_per_direction": ms_ref,
        "speedup_vs_triangle_union": ms_ref / ms_fast,
        "max_area_difference_m2": float(
            np.max(np.abs(fast["projected_area_m2"][:n_reference] - reference["projected_area_m2"]))
        ),
        "mean_projected_area_m2": float(np.mean(fast["projected_area_m2"])),
    }
