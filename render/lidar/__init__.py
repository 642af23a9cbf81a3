"""Lidar cross-section (LCS) of drone meshes by Monte Carlo ray tracing in Mitsuba 3 (SPEC 6).

>>> from csuas.render.lidar import LidarTarget, lidar_cross_section
>>> target = LidarTarget.from_drone(build_drone("dji_mini_4_pro"))
>>> lidar_cross_section(target, azimuth_deg=30, elevation_deg=10, quality="draft").lcs_m2

Importing this package does not import Mitsuba; the first trace selects the
``ad_mono`` variant through :func:`csuas.render.backend.use_variant`.
"""

from csuas.render.lidar.cross_section import QUALITY_PRESETS, LcsResult, lidar_cross_section, trace_lcs
from csuas.render.lidar.target import LidarTarget, material_reflectance

__all__ = ["LidarTarget", "LcsResult", "QUALITY_PRESETS", "lidar_cross_section", "material_reflectance",
           "trace_lcs"]
