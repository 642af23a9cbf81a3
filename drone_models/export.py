"""Mesh export of drone models to PLY, OBJ and GLB, written atomically.

* GLB (glTF binary) and OBJ keep one named object per part (the part name);
* PLY holds the concatenated mesh.

Every format carries per-face colours from the part material's
``reflectance_rgb`` (PLY, GLB; OBJ colours are dropped by its writer
without a material file). Units are metres, body frame (+x forward, +y left, +z up).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

from csuas.base.errors import ParameterError
from csuas.base.fileio import atomic_path

#: File suffix -> trimesh file type.
EXPORT_FORMATS = {".ply": "ply", ".obj": "obj", ".glb": "glb"}


def drone_scene(drone) -> trimesh.Scene:
    """A scene with one coloured, named geometry per part of ``drone``."""
    scene = trimesh.Scene()
    for part in drone.parts:
        mesh = part.mesh.copy()
        rgba = np.r_[np.round(np.asarray(part.material.reflectance_rgb) * 255.0), 255].astype(np.uint8)
        mesh.visual = trimesh.visual.ColorVisuals(mesh, face_colors=rgba)
        scene.add_geometry(mesh, node_name=part.name, geom_name=part.name)
    return scene


def export_format(path) -> str:
    """The trimesh file type for ``path``'s suffix; :class:`ParameterError` if unsupported."""
    file_type = EXPORT_FORMATS.get(Path(path).suffix.lower())
    if file_type is None:
        raise ParameterError("export", str(path), "a file name ending in " + ", ".join(EXPORT_FORMATS))
    return file_type


def export_drone(drone, path) -> Path:
    """Write ``drone`` to ``path``; the format follows the suffix (.ply, .obj, .glb).

    The file is written atomically (complete or absent).

    Raises
    ------
    ParameterError
        For an unsupported suffix.
    """
    target = Path(path)
    file_type = export_format(target)
    scene = drone_scene(drone)
    if file_type == "ply":
        data = trimesh.util.concatenate(list(scene.geometry.values())).export(file_type="ply")
    else:
        data = scene.export(file_type=file_type)
    with atomic_path(target) as tmp:
        tmp.write_bytes(data.encode("utf-8") if isinstance(data, str) else data)
    return target
