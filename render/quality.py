"""The quality ladder of each simulator: what its draft, standard and reference rungs set (docs/simulation.md).

One :class:`csuas.base.quality.QualityLadder` per simulator, declared here once; the simulators build their
presets from these records (``QUALITY_PRESETS`` of :mod:`csuas.render.imaging.quality`,
:mod:`csuas.render.lidar.cross_section` and :mod:`csuas.render.rcs.solver`, ``SPHERE_QUALITY_PRESETS`` of
:mod:`csuas.render.lidar.sphere_average`, ``PRESETS`` of :mod:`csuas.render.links.budget`), the commands
their ``--quality`` help, and ``python -m csuas.schema_docs`` the table "Quality ladders" of docs/simulation.md
from :data:`LADDERS`. This module imports nothing but ``csuas.base``, so ``csuas render --help`` stays fast.

The measured accuracy and time of each rung: docstrings of :mod:`csuas.render.imaging.quality` (EO, TIR),
:data:`csuas.render.rcs.convergence.PRESET_MEASURED_ERROR_DB` (SBR-PO),
:func:`csuas.validation.links.accuracy.accuracy_vs_time` (links), docs/validation.md.
"""

from __future__ import annotations

from csuas.base.quality import QualityLadder, Setting

#: The imaging quality ladder: draft 32, standard 128, reference 2048 samples per pixel.
IMAGING = QualityLadder(
    "EO and TIR renders (Mitsuba path tracer)",
    "render_eo, render_tir and the airlight render; csuas render eo/tir, the sweep job render (eo, tir), csuas dataset",
    (
        Setting("n_side", "jittered strata per pixel side (n_side^2 samples per pixel and batch)"),
        Setting("n_batches", "independent batches (the jackknife standard error)"),
    ),
    draft=(2, 8),
    standard=(4, 8),
    reference=(16, 8),
    summary=lambda v: f"{v['n_side'] ** 2 * v['n_batches']:,} samples per pixel",
)

#: The lidar cross-section's quality ladder, toward one direction.
LIDAR = QualityLadder(
    "lidar cross-section toward one direction (Dr.Jit ray grid)",
    "lidar_cross_section, path_traced_lcs; csuas render lidar, the sweep job render (lidar)",
    (
        Setting("grid", "ray-grid cells per side of the window"),
        Setting("replicates", "independent jitter replicates (the standard error)"),
    ),
    draft=(48, 4),
    standard=(128, 8),
    reference=(384, 16),
    summary=lambda v: f"{v['grid']}^2 x {v['replicates']} rays",
)

#: The quality ladder of the sphere-averaged lidar cross-section.
LIDAR_SPHERE = QualityLadder(
    "sphere-averaged lidar cross-section, Eq. 7 (Dr.Jit ray grids)",
    "mean_lidar_cross_section, drone_lcs_versus_rule; the report's defaults.lidar",
    (
        Setting("replicates", "randomly rotated direction lattices (the standard error)"),
        Setting("directions_per_replicate", "Fibonacci directions per lattice"),
        Setting("grid", "ray-grid cells per side, each direction"),
    ),
    draft=(4, 24, 32),
    standard=(8, 64, 64),
    reference=(16, 256, 128),
    summary=lambda v: f"{v['replicates'] * v['directions_per_replicate']:,} directions of {v['grid']}^2 rays",
)

#: The links' quality ladder. Depth 1 is exact over one flat ground (one bounce at most).
LINKS = QualityLadder(
    "Sionna RT links (path and radar solvers)",
    "rf_link_gain, radar_link_gain, the terrain radio map; csuas pathloss --budget",
    (
        Setting("samples", "rays shot per source"),
        Setting("max_depth", "interactions per path at most"),
    ),
    draft=(16, 1),
    standard=(256, 1),
    reference=(16_384, 2),
    summary=lambda v: f"{v['samples']:,} rays per source, depth {v['max_depth']}",
)

#: The SBR-PO quality ladder: tube density N [rays per wavelength] and maximum bounces.
#: Measured errors against closed forms are in :data:`csuas.render.rcs.convergence.PRESET_MEASURED_ERROR_DB`.
RCS = QualityLadder(
    "radar cross-section (SBR-PO)",
    "compute_rcs and the RCS sweeps; csuas rcs, rcs-table, rcs-statistics, the sweep job rcs",
    (
        Setting("rays_per_wavelength", "tube density N (tube spacing lambda/N)"),
        Setting("max_bounces", "reflections per tube at most"),
    ),
    draft=(2.0, 3),
    standard=(5.0, 5),
    reference=(10.0, 8),
    summary=lambda v: f"{v['rays_per_wavelength']:g} rays per wavelength, {v['max_bounces']} bounces",
)

#: Every simulator's ladder, in the docs' order (csuas.base.registry); the silhouette's lives with it in
#: drone_models/, below render/.
LADDERS = (
    "csuas.render.quality:IMAGING",
    "csuas.render.quality:LIDAR",
    "csuas.render.quality:LIDAR_SPHERE",
    "csuas.drone_models.sphere_average:LADDER",
    "csuas.render.quality:RCS",
    "csuas.render.quality:LINKS",
)
