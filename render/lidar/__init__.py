"""Lidar cross-section (LCS) of drone meshes by Monte Carlo ray tracing in Mitsuba 3 (docs/simulation.md).

>>> from csuas.render.lidar import LidarTarget, lidar_cross_section
>>> target = LidarTarget.from_drone(build_drone("dji_mini_4_pro"))
>>> lidar_cross_section(target, azimuth_deg=30, elevation_deg=10, quality="draft").lcs_m2

Modules: :mod:`~csuas.render.lidar.target` (meshes and albedos),
:mod:`~csuas.render.lidar.cross_section` (single-bounce LCS, plane or
spherical wave, beam footprint), :mod:`~csuas.render.lidar.sphere_average`
(Eq. 7 beside the projected area of Eq. 8), :mod:`~csuas.render.lidar.path` (multi-bounce
path tracing), :mod:`~csuas.render.lidar.runner` (``csuas render lidar``). Its accuracy sweeps, oracles,
checks (with the comparison against the rule of Eq. 9) and benchmark live in :mod:`csuas.validation.lidar`.
Importing this package does not import Mitsuba; the first trace selects the
``ad_mono`` variant through :func:`csuas.render.backend.use_variant`.
"""

from csuas.render.lidar.cross_section import QUALITY_PRESETS, LcsResult, RayGrid, lidar_cross_section, trace_lcs
from csuas.render.lidar.path import path_traced_lcs
from csuas.render.lidar.runner import render_lidar
from csuas.render.lidar.sphere_average import mean_lidar_cross_section
from csuas.render.lidar.target import LidarTarget, material_reflectance

__all__ = [
    "LidarTarget",
    "LcsResult",
    "QUALITY_PRESETS",
    "RayGrid",
    "lidar_cross_section",
    "material_reflectance",
    "mean_lidar_cross_section",
    "path_traced_lcs",
    "render_lidar",
    "trace_lcs",
]
