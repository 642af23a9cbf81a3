"""Accuracy against time of the lidar cross-section, measured on a problem with an exact answer.

The reference problem is a Lambertian icosphere (radius 0.1 m, 2562 vertices,
albedo 0.5) seen from azimuth 20 deg, elevation 30 deg. A convex
polyhedron does not shadow itself, so its single-bounce monostatic LCS is the
closed form ``4 rho * sum_f A_f max(0, n_f . d)^2`` over its faces (each
facet is a plate, docs/validation.md); the smooth sphere's ``(8/3) rho pi a^2``
differs from it by the faceting (0.12 % here).
"""

from __future__ import annotations

import math

import numpy as np

from csuas.drone_models.geometry import direction_vector
from csuas.render.lidar.cross_section import QUALITY_PRESETS, RayGrid, lidar_cross_section
from csuas.render.lidar.target import LidarTarget

#: The reference problem: icosphere subdivisions, radius [m], albedo, azimuth and elevation [deg].
REFERENCE_PROBLEM = {"subdivisions": 4, "radius_m": 0.1, "reflectance": 0.5, "azimuth_deg": 20.0, "elevation_deg": 30.0}

#: Grid sizes of the default sweep (cells per side).
DEFAULT_GRIDS = (8, 16, 32, 64, 128, 256)


def convex_polyhedron_lcs(mesh, reflectance: float, direction) -> float:
    """Exact single-bounce LCS of a convex Lambertian polyhedron [m^2]: ``4 rho sum A_f max(0, cos)^2``."""
    d = np.asarray(direction, dtype=float)
    cosines = np.clip(np.asarray(mesh.face_normals) @ (d / np.linalg.norm(d)), 0.0, None)
    return float(4.0 * reflectance * np.sum(np.asarray(mesh.area_faces) * cosines**2))


def reference_problem() -> tuple:
    """``(target, exact_lcs_m2, problem)`` of :data:`REFERENCE_PROBLEM`."""
    import trimesh

    p = REFERENCE_PROBLEM
    mesh = trimesh.creation.icosphere(subdivisions=p["subdivisions"], radius=p["radius_m"])
    target = LidarTarget.from_mesh(mesh, p["reflectance"], name="icosphere")
    exact = convex_polyhedron_lcs(mesh, p["reflectance"], direction_vector(p["azimuth_deg"], p["elevation_deg"]))
    return target, exact, dict(p)


def _row(result, exact: float) -> dict:
    return {
        "grid": result.grid,
        "replicates": result.replicates,
        "rays": result.rays,
        "lcs_m2": result.lcs_m2,
        "stderr_m2": result.stderr_m2,
        "exact_m2": exact,
        "error_rel": (result.lcs_m2 - exact) / exact,
        "stderr_rel": result.stderr_m2 / exact,
        "time_s": result.time_s,
    }


def accuracy_vs_time(grids=DEFAULT_GRIDS, replicates: int = 8, seed: int = 0) -> list:
    """Error and wall time of the reference problem's LCS against the ray grid.

    Parameters
    ----------
    grids : sequence of int
        Cells per window side (rays per replicate ~ grid^2).
    replicates : int
        Independent jitter replicates per point (>= 2).
    seed : int

    Returns
    -------
    list of dict
        One row per grid: ``grid``, ``replicates``, ``rays``, ``lcs_m2``,
        ``stderr_m2``, ``exact_m2``, ``error_rel`` (signed, measured against
        the closed form), ``stderr_rel``, ``time_s``.
    """
    target, exact, p = reference_problem()
    return [
        _row(
            lidar_cross_section(
                target,
                p["azimuth_deg"],
                p["elevation_deg"],
                math.inf,
                RayGrid(int(g), replicates),
                seed=seed,
            ),
            exact,
        )
        for g in grids
    ]


def preset_accuracy(seed: int = 0) -> list:
    """Measured error and time of each quality preset on the reference problem (rows as above plus ``quality``)."""
    target, exact, p = reference_problem()
    rows = []
    for name in QUALITY_PRESETS:
        result = lidar_cross_section(target, p["azimuth_deg"], p["elevation_deg"], math.inf, name, seed=seed)
        rows.append({"quality": name, **_row(result, exact)})
    return rows
