"""User meshes as drone models: any file trimesh reads, in metres."""

from __future__ import annotations

from pathlib import Path

import trimesh

from csuas.base.errors import ParameterError
from csuas.drone_models.drone import Drone, Part
from csuas.drone_models.materials import get_material


def load_mesh_drone(path, material: str = "plastic") -> Drone:
    """Read a mesh file as a one-part :class:`Drone` (mass unknown).

    The file's coordinates are taken as metres in the body frame (+x forward,
    +y left, +z up); the model is not re-centred. Scenes are flattened into
    one mesh with their transforms applied. Open (non-watertight) meshes are
    accepted; the silhouette code flags them.

    Parameters
    ----------
    path : str or os.PathLike
        Mesh file (PLY, OBJ, GLB/GLTF, STL, OFF, ...).
    material : str
        Material name given to the whole surface.

    Raises
    ------
    ParameterError
        When the file does not exist, cannot be read, or holds no triangles.
    """
    file = Path(path)
    if not file.is_file():
        raise ParameterError("mesh file", str(path), "an existing mesh file")
    try:
        mesh = trimesh.load(file, force="mesh")
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise ParameterError("mesh file", str(path), f"a file trimesh can read ({exc})") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise ParameterError("mesh file", str(path), "a file with at least one triangle")
    return Drone(
        name=file.stem,
        mass_kg=None,
        parts=[Part("mesh", "body", mesh, get_material(material))],
        spec={"source": str(file)},
        propellers="as file",
    )
