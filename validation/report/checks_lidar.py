"""Lidar cross-section by ray tracing against the Lambertian oracles, and its accuracy against time.

Oracles (docs/validation.md): Lambertian plate at normal incidence LCS = 4 rho A;
Lambertian sphere (8/3) rho pi a^2 (the faceted icosphere's exact value is
``4 rho sum A_f cos^2``, :func:`csuas.validation.lidar.accuracy.convex_polyhedron_lcs`).
Knob: the ray grid and jitter replicates (:data:`csuas.render.lidar.QUALITY_PRESETS`).
The drone's mean LCS against k_LCS A_p is in ``defaults.lidar``.
"""

from __future__ import annotations

import math

from csuas.base.checks import Check
from csuas.validation.report.figures import AccuracyColumns
from csuas.validation.report.figures import accuracy_vs_time as plot_accuracy
from csuas.validation.report.registry import CheckGroup, CheckSpec, Section, timed

QUALITY = {"quick": "draft", "full": "reference"}
GRIDS = {"quick": (8, 16, 32, 64), "full": (8, 16, 32, 64, 128, 256)}
N_SIGMA = 3.0
ALBEDO = 0.5


def oracles(quality: str) -> Section:
    """Plate at normal incidence and spheres (faceted exact and smooth) against the ray-traced LCS."""
    import trimesh

    from csuas.drone_models.geometry import direction_vector
    from csuas.render.lidar import LidarTarget, lidar_cross_section
    from csuas.validation.lidar.accuracy import convex_polyhedron_lcs

    s = Section()
    side = 0.2
    plate = trimesh.Trimesh(
        vertices=[
            [-side / 2, -side / 2, 0],
            [side / 2, -side / 2, 0],
            [side / 2, side / 2, 0],
            [-side / 2, side / 2, 0],
        ],
        faces=[[0, 1, 2], [0, 2, 3]],
        process=False,
    )
    res, elapsed = timed(lidar_cross_section, LidarTarget.from_mesh(plate, ALBEDO, "plate"), 0.0, 90.0, quality=quality)
    exact = 4.0 * ALBEDO * side * side
    s.outcomes.append(
        Check(
            "lidar.oracle.plate_normal.lcs_m2",
            exact,
            res.lcs_m2,
            N_SIGMA * res.stderr_m2 + 1e-3 * exact,
            "m^2",
            error_estimate=res.stderr_m2,
            time_s=elapsed,
            source="4 rho A (docs/validation.md)",
            method=f"Mitsuba ray grid {res.grid} x {res.replicates} replicates, rho = {ALBEDO}",
        )
    )
    radius = 0.1
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=radius)
    az, el = 20.0, 30.0
    res, elapsed = timed(lidar_cross_section, LidarTarget.from_mesh(sphere, ALBEDO, "sphere"), az, el, quality=quality)
    faceted = convex_polyhedron_lcs(sphere, ALBEDO, direction_vector(az, el))
    smooth = 8.0 / 3.0 * ALBEDO * math.pi * radius**2
    s.outcomes.append(
        Check(
            "lidar.oracle.sphere_faceted.lcs_m2",
            faceted,
            res.lcs_m2,
            N_SIGMA * res.stderr_m2 + 1e-3 * faceted,
            "m^2",
            error_estimate=res.stderr_m2,
            time_s=elapsed,
            source="4 rho sum A_f max(0, cos)^2 of the icosphere's facets",
            method=f"Mitsuba ray grid {res.grid} x {res.replicates}, icosphere 10242 vertices",
        )
    )
    s.outcomes.append(
        Check(
            "lidar.oracle.sphere_smooth.lcs_m2",
            smooth,
            res.lcs_m2,
            N_SIGMA * res.stderr_m2 + abs(faceted - smooth) + 1e-3 * smooth,
            "m^2",
            error_estimate=res.stderr_m2,
            time_s=elapsed,
            source="(8/3) rho pi a^2 (docs/validation.md)",
            method="same render; the tolerance includes the faceting difference",
        )
    )
    return s


def accuracy(grids) -> Section:
    """Relative error and time of the LCS of the reference icosphere against the ray grid."""
    from csuas.validation.lidar.accuracy import accuracy_vs_time

    s = Section()
    rows, elapsed = timed(accuracy_vs_time, grids, replicates=8)
    from csuas.render.lidar.cross_section import QUALITY_PRESETS

    s.figures.append(
        plot_accuracy(
            "lidar_accuracy_vs_time",
            "Lidar cross-section: |error| vs time (Lambertian icosphere)",
            rows,
            columns=AccuracyColumns(
                "grid", "error_rel", error_label="|relative error| vs exact", stderr_key="stderr_rel"
            ),
            caption="8 jitter replicates per grid; labels: grid cells per side.",
            presets={name: grid for name, (grid, _) in QUALITY_PRESETS.items()},
        )
    )
    for r in rows:
        s.outcomes.append(
            Check(
                f"lidar.accuracy.grid{r['grid']}.error_rel",
                0.0,
                r["error_rel"],
                N_SIGMA * r["stderr_rel"] + 1e-3,
                "-",
                error_estimate=r["stderr_rel"],
                time_s=r["time_s"],
                source="exact faceted-sphere LCS",
                method=f"grid {r['grid']} x 8 replicates, {r['rays']} rays",
                details={"lcs_m2": r["lcs_m2"], "exact_m2": r["exact_m2"]},
            )
        )
    s.table = rows
    s.notes.append(f"sweep {elapsed:.1f} s")
    return s


#: The report section of these checks.
GROUP = CheckGroup(
    "lidar",
    "Lidar cross-section vs oracles",
    60,
    "Ray-traced lidar cross-sections against the Lambertian plate and sphere, and their accuracy against the ray grid.",
)


SPECS = [
    CheckSpec(
        "lidar.oracles",
        "Lidar cross-section vs Lambertian oracles",
        GROUP,
        "closed-form LCS of a Lambertian plate and sphere vs Mitsuba ray tracing",
        f"{N_SIGMA:g} standard errors + 0.1 % (+ faceting for the smooth sphere)",
        oracles,
        "ray grid and replicates (quality preset)",
        QUALITY,
        True,
    ),
    CheckSpec(
        "lidar.accuracy",
        "Lidar cross-section accuracy vs time",
        GROUP,
        "relative error of the LCS vs the ray grid, with its wall time",
        f"each point unbiased within {N_SIGMA:g} standard errors + 0.1 %",
        accuracy,
        "grids swept",
        GRIDS,
        True,
    ),
]
