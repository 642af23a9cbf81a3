"""Procedural drone models, materials and exact silhouette metrics (docs/simulation.md).

>>> from csuas.drone_models import build_drone, list_presets
>>> drone = build_drone("dji_mini_4_pro")
"""

from csuas.drone_models.drone import Drone, Part
from csuas.drone_models.materials import MATERIALS, Material, get_material
from csuas.drone_models.presets import build_drone, list_presets

__all__ = ["Drone", "Part", "Material", "MATERIALS", "get_material", "build_drone", "list_presets"]
