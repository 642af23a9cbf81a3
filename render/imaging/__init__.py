"""EO and thermal-IR imaging of drones in Mitsuba 3 (docs/simulation.md).

>>> from csuas.render.imaging import RenderSettings, View, render_eo, render_tir
>>> result = render_eo("dji_mini_4_pro", View(range_m=500.0), settings=RenderSettings(quality="draft"))
>>> result.values["pixels_on_target"], result.stderr["pixels_on_target"]

Only a window around the target is rendered, in camera-relative,
range-normalised coordinates (:mod:`~csuas.render.imaging.scene`); path
effects of the true range are applied analytically
(:mod:`~csuas.render.imaging.path`). Importing this package does not import
Mitsuba; the renderers select a variant when called.
"""

from csuas.render.imaging.eo import render_eo
from csuas.render.imaging.quality import QUALITY_PRESETS, Quality, resolve_quality
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, ThermalScene, ThermalSensor, View
from csuas.render.imaging.tir import render_tir

__all__ = [
    "render_eo",
    "render_tir",
    "View",
    "EoSensor",
    "ThermalSensor",
    "Daylight",
    "ThermalScene",
    "RenderSettings",
    "Quality",
    "QUALITY_PRESETS",
    "resolve_quality",
]
