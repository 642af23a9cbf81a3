"""Orientation-averaged lidar cross-section (Eq. 7) beside the exact projected area (Eq. 8).

Eq. 7 averages the LCS over all directions with the ``cos(phi)`` Jacobian,
i.e. uniformly over the sphere. The average is estimated by randomised
quasi-Monte Carlo, as the silhouette averages of
:mod:`csuas.drone_models.sphere_average`: ``replicates`` independent,
uniformly random rotations of a Fibonacci lattice of
``directions_per_replicate`` points, each direction traced with one jittered
ray grid (:func:`csuas.render.lidar.cross_section.trace_lcs`, plane wave).
Every replicate is an unbiased estimate of the mean; the spread of the
replicate means is the standard error, and it contains both the direction
sampling and the ray sampling error.

The comparison with the paper's rule of thumb ``sigma = k_LCS * A_p``
(Eq. 9, ``k_LCS = 0.1``, Titterton; :func:`csuas.validation.lidar.checks.drone_lcs_versus_rule`)
uses the exact projected area of the same directions (polygon union,
:mod:`csuas.drone_models.silhouette`), which :func:`mean_lidar_cross_section` returns.
For a Lambertian convex body ``<sigma> / <A_p>`` is ``4 rho <cos>`` weighted
by projected area, ``(8/3) rho`` for a sphere, so ``k_LCS = 0.1`` stands for
a sphere of albedo 0.0375.
"""

from __future__ import annotations

import math
import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.drone_models.geometry import rotated_lattices
from csuas.drone_models.silhouette import SilhouetteModel, metrics_for_directions
from csuas.render.lidar.cross_section import RayGrid, trace_lcs
from csuas.render.lidar.target import LidarTarget
from csuas.render.quality import LIDAR_SPHERE

#: Sphere-average presets from :data:`csuas.render.quality.LIDAR_SPHERE`:
#: name -> (replicates, directions per replicate, grid cells per side).
SPHERE_QUALITY_PRESETS = LIDAR_SPHERE.presets()

#: The paper's rule-of-thumb ratio of mean LCS to projected area (Eq. 9, Titterton [48]).
K_LCS_PAPER = 0.1


def _resolve(quality, replicates, directions_per_replicate, grid) -> tuple:
    if quality not in SPHERE_QUALITY_PRESETS:
        raise ParameterError("quality", quality, ", ".join(SPHERE_QUALITY_PRESETS))
    r0, m0, g0 = SPHERE_QUALITY_PRESETS[quality]
    values = {
        "replicates": r0 if replicates is None else replicates,
        "directions_per_replicate": m0 if directions_per_replicate is None else directions_per_replicate,
        "grid": g0 if grid is None else grid,
    }
    minimum = {"replicates": 2, "directions_per_replicate": 1, "grid": 1}
    for key, value in values.items():
        if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < minimum[key]:
            raise ParameterError(key, value, f"integer >= {minimum[key]}")
    custom = any(v is not None for v in (replicates, directions_per_replicate, grid))
    return (
        int(values["replicates"]),
        int(values["directions_per_replicate"]),
        int(values["grid"]),
        "custom" if custom else quality,
    )


def mean_lidar_cross_section(
    target: LidarTarget,
    quality: str = "standard",
    replicates: int | None = None,
    directions_per_replicate: int | None = None,
    grid: int | None = None,
    seed: int = 0,
    exact_area_mesh=None,
) -> dict:
    """Sphere-averaged LCS (Eq. 7) with its standard error and time.

    Parameters
    ----------
    target : LidarTarget
    quality : {"draft", "standard", "reference"}
        Preset of :data:`SPHERE_QUALITY_PRESETS`; the other arguments override it.
    replicates : int, optional
        Randomly rotated lattices, >= 2.
    directions_per_replicate : int, optional
        Fibonacci points per lattice, >= 1.
    grid : int, optional
        Ray grid cells per window side for each direction.
    seed : int
        Seed of the rotations and the jitter.
    exact_area_mesh : trimesh.Trimesh or Drone, optional
        Geometry for the exact projected area of the same directions (the
        target's own mesh); when given, ``projected_area_m2`` and
        ``k_lcs_measured`` use it instead of the ray-traced area.

    Returns
    -------
    dict
        ``lcs_m2`` and ``projected_area_m2``: ``{"mean", "stderr", "min",
        "max"}`` [m^2]; ``projected_area_traced_m2`` (same form, from the
        rays); ``k_lcs_measured``: ``{"mean", "stderr"}`` (ratio of the
        means, error from the replicate ratios); ``n_directions``, ``rays``,
        ``replicates``, ``directions_per_replicate``, ``grid``, ``quality``,
        ``seed``, ``method`` and ``time_s`` [s].
    """
    r, m, g, name = _resolve(quality, replicates, directions_per_replicate, grid)
    target.scene()
    start = time.perf_counter()
    directions = rotated_lattices(r, m, seed).reshape(-1, 3)
    traced = trace_lcs(target, directions, None, math.inf, RayGrid(g, 1), seed + 1)
    lcs = traced["lcs_m2"][:, 0].reshape(r, m)
    area_traced = traced["area_m2"][:, 0].reshape(r, m)
    if exact_area_mesh is not None:
        model = (
            exact_area_mesh
            if isinstance(exact_area_mesh, SilhouetteModel)
            else SilhouetteModel.from_mesh(exact_area_mesh, warn=False)
        )
        area = metrics_for_directions(model, directions)["projected_area_m2"].reshape(r, m)
    else:
        area = area_traced
    ratio = lcs.mean(axis=1) / area.mean(axis=1)
    out = {
        "lcs_m2": _summary(lcs),
        "projected_area_m2": _summary(area),
        "projected_area_traced_m2": _summary(area_traced),
        "k_lcs_measured": {"mean": float(lcs.mean() / area.mean()), "stderr": float(ratio.std(ddof=1) / math.sqrt(r))},
        "n_directions": r * m,
        "rays": traced["rays"],
        "replicates": r,
        "directions_per_replicate": m,
        "grid": g,
        "quality": name,
        "seed": int(seed),
        "method": "single_bounce",
        "time_s": time.perf_counter() - start,
    }
    return out


def _summary(values: np.ndarray) -> dict:
    per_replicate = values.mean(axis=1)
    return {
        "mean": float(per_replicate.mean()),
        "stderr": float(per_replicate.std(ddof=1) / math.sqrt(len(per_replicate))),
        "min": float(values.min()),
        "max": float(values.max()),
    }
