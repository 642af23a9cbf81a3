"""Target meshes and direction conventions of the radar cross-section engine.

Directions follow docs/command-line.md: ``azimuth_deg`` from +x toward +y, ``elevation_deg``
from the xy-plane, and the direction points *from the target toward the
sensor*. The incident wave of a radar at direction ``d`` therefore propagates
along ``-d``. Polarisations use the spherical unit vectors of the direction
(theta measured from +z): V = theta-hat, H = phi-hat, so that H is horizontal
and V lies in the vertical plane containing ``d`` (IEEE Std 211 usage).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from csuas.base.errors import ParameterError

from .materials import DRONE_SHELL_THICKNESS_M, SHELL_MAX_CONDUCTIVITY_S_M, RadioMaterial, resolve_material
from .thin_wire import ThinWires, wire_of_cylinder


def polarisation_basis(azimuth_deg, elevation_deg) -> tuple[np.ndarray, np.ndarray]:
    """(theta-hat, phi-hat) of a direction, each (..., 3): the V and H unit vectors.

    theta-hat = (sin el cos az, sin el sin az, -cos el), phi-hat = (-sin az, cos az, 0);
    both are orthogonal to :func:`direction_vector` and defined at the poles
    by the azimuth.
    """
    az = np.radians(np.asarray(azimuth_deg, dtype=float))
    el = np.radians(np.asarray(elevation_deg, dtype=float))
    az, el = np.broadcast_arrays(az, el)
    theta_hat = np.stack([np.sin(el) * np.cos(az), np.sin(el) * np.sin(az), -np.cos(el)], axis=-1)
    phi_hat = np.stack([-np.sin(az), np.cos(az), np.zeros_like(az)], axis=-1)
    return theta_hat, phi_hat


def direction_angles(direction) -> tuple[np.ndarray, np.ndarray]:
    """(azimuth_deg, elevation_deg) of unit vectors (..., 3)."""
    v = np.asarray(direction, dtype=float)
    return (np.degrees(np.arctan2(v[..., 1], v[..., 0])), np.degrees(np.arcsin(np.clip(v[..., 2], -1.0, 1.0))))


@dataclass
class TargetMesh:
    """Triangle mesh prepared for ray tracing: centred, cleaned, with per-face materials.

    Attributes
    ----------
    name : str
        Preset name or file name.
    vertices : ndarray (V, 3)
        Vertex positions [m], centred on the bounding-box centre.
    faces : ndarray (F, 3)
        Triangles with non-zero area only.
    face_normals : ndarray (F, 3)
        Unit geometric normals (either side may face a ray; the engine flips).
    face_material : ndarray (F,)
        Index into ``materials`` of each face.
    materials : list of RadioMaterial
        Materials in use.
    dropped_faces : int
        Degenerate (zero-area or non-finite) faces removed on input.
    centre_m : ndarray (3,)
        The bounding-box centre subtracted from the input coordinates [m].
    wires : ThinWires or None
        Thin wires solved by the method of moments (:mod:`csuas.render.rcs.thin_wire`) instead of traced,
        in the same centred frame; a drone preset's ``wiring`` parts.
    """

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    face_normals: np.ndarray
    face_material: np.ndarray
    materials: list = field(default_factory=list)
    dropped_faces: int = 0
    centre_m: np.ndarray = field(default_factory=lambda: np.zeros(3))
    wires: ThinWires | None = None

    @property
    def bounding_radius_m(self) -> float:
        """Radius of the origin-centred sphere enclosing the mesh [m]."""
        return float(np.sqrt((self.vertices**2).sum(axis=1).max()))

    @property
    def face_areas_m2(self) -> np.ndarray:
        """Area of each face [m^2]."""
        tri = self.vertices[self.faces]
        return 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)

    @property
    def surface_area_m2(self) -> float:
        """Total area of the faces [m^2]."""
        return float(self.face_areas_m2.sum())

    def with_material(self, material) -> TargetMesh:
        """A copy whose faces are all of one material."""
        return TargetMesh(
            self.name,
            self.vertices,
            self.faces,
            self.face_normals,
            np.zeros(len(self.faces), dtype=np.uint32),
            [resolve_material(material)],
            self.dropped_faces,
            self.centre_m,
            self.wires,
        )

    def with_shells(self, thickness_m: float | None) -> TargetMesh:
        """A copy whose dielectric materials are thin shells of ``thickness_m`` [m] (0: half-spaces).

        Conductors (PEC, ITU metal, conductivity >= 1 S/m) stay half-spaces.
        """
        mats = [m.with_thickness(thickness_m) if _is_dielectric(m) else m for m in self.materials]
        return TargetMesh(
            self.name,
            self.vertices,
            self.faces,
            self.face_normals,
            self.face_material,
            mats,
            self.dropped_faces,
            self.centre_m,
            self.wires,
        )


def closed_faces(faces: np.ndarray) -> np.ndarray:
    """Whether each face lies on a closed, consistently wound surface (its normal points outward).

    True when each of the face's three directed edges is matched by the opposite edge of a
    neighbour; the open sheets of plates and corner reflectors are lit from either side.
    """
    faces = np.asarray(faces, np.int64)
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    n = int(faces.max()) + 1
    forward = directed[:, 0] * n + directed[:, 1]
    backward = directed[:, 1] * n + directed[:, 0]
    matched = np.isin(backward, forward)
    return matched.reshape(-1, 3).all(axis=1)


def _is_dielectric(material: RadioMaterial) -> bool:
    if material.is_pec or material.itu_name == "metal":
        return False
    return material.itu_name is not None or material.conductivity_s_m < SHELL_MAX_CONDUCTIVITY_S_M


def prepare_mesh(vertices, faces, face_material=None, materials=None, name: str = "mesh") -> TargetMesh:
    """Clean and centre a triangle mesh for the SBR engine.

    Faces with non-finite vertices or an area below ``1e-12`` of the squared
    bounding-box diagonal are dropped (they cannot be hit reliably and have no
    normal); a mesh left with no face is an error.

    Parameters
    ----------
    vertices : array_like (V, 3)
        Vertex positions [m].
    faces : array_like (F, 3)
        Vertex indices of triangles.
    face_material : array_like (F,), optional
        Material index of each face (default: all 0).
    materials : list, optional
        Material specifications (see :func:`resolve_material`); default PEC.

    Raises
    ------
    ParameterError
        Empty mesh, indices out of range, or no face of non-zero area.
    """
    v = np.asarray(vertices, dtype=float).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(v) == 0 or len(f) == 0:
        raise ParameterError("mesh", f"{len(v)} vertices, {len(f)} faces", "at least one triangle")
    if f.min() < 0 or f.max() >= len(v):
        raise ParameterError("mesh.faces", f"indices {f.min()}..{f.max()}", f"0..{len(v) - 1}")
    mats = [resolve_material(m) for m in (materials if materials is not None else ["pec"])]
    fm = np.zeros(len(f), dtype=np.int64) if face_material is None else np.asarray(face_material, np.int64)
    if fm.shape != (len(f),) or fm.min() < 0 or fm.max() >= len(mats):
        raise ParameterError(
            "mesh.face_material",
            f"shape {fm.shape}, range {fm.min()}..{fm.max()}",
            f"one index per face in 0..{len(mats) - 1}",
        )
    finite_v = np.isfinite(v).all(axis=1)
    used = f[finite_v[f].all(axis=1)]
    if len(used) == 0:
        raise ParameterError("mesh", "no finite vertices", "finite vertex positions [m]")
    lo, hi = v[np.unique(used)].min(axis=0), v[np.unique(used)].max(axis=0)
    centre = 0.5 * (lo + hi)
    diag2 = float(((hi - lo) ** 2).sum())
    tri = np.where(np.isfinite(v), v, 0.0)[f]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    double_area = np.linalg.norm(cross, axis=1)
    keep = finite_v[f].all(axis=1) & (double_area > 2e-12 * max(diag2, 1e-300))
    if not keep.any():
        raise ParameterError("mesh", "all faces have zero area", "at least one triangle of non-zero area")
    normals = cross[keep] / double_area[keep, None]
    return TargetMesh(
        name,
        np.where(np.isfinite(v), v - centre, 0.0),
        f[keep],
        normals,
        fm[keep].astype(np.uint32),
        mats,
        int((~keep).sum()),
        centre,
    )


def load_target(mesh_or_preset, material=None, shell_thickness_m: float | None = None) -> TargetMesh:
    """A :class:`TargetMesh` from a trimesh object, a mesh file or a drone preset name.

    Parameters
    ----------
    mesh_or_preset : trimesh.Trimesh, trimesh.Scene, TargetMesh, str or Path
        A mesh; a file trimesh reads (coordinates in metres); or a preset of
        :func:`csuas.drone_models.build_drone` (its parts keep their own radio
        materials unless ``material`` is given).
    material : str or material object, optional
        One material for every face (e.g. ``"pec"``). Default: the parts'
        materials for a drone preset, PEC for anything else.
    shell_thickness_m : float, optional
        Make every dielectric material a thin shell of this thickness [m]
        (0: half-spaces). Default: drone presets' dielectric parts are
        shells of ``DRONE_SHELL_THICKNESS_M``, everything else half-spaces.

    Raises
    ------
    ParameterError
        A path that does not exist and is not a preset, or an unreadable mesh.
    """
    import trimesh

    if isinstance(mesh_or_preset, TargetMesh):
        target = mesh_or_preset
    elif isinstance(mesh_or_preset, (trimesh.Trimesh, trimesh.Scene)):
        target = _from_trimesh(mesh_or_preset, "mesh")
    elif isinstance(mesh_or_preset, (str, Path)) and Path(mesh_or_preset).is_file():
        try:
            loaded = trimesh.load(str(mesh_or_preset), force="mesh")
        except Exception as exc:
            raise ParameterError("mesh", str(mesh_or_preset), f"a mesh file trimesh can read ({exc})") from None
        target = _from_trimesh(loaded, Path(mesh_or_preset).name)
    elif isinstance(mesh_or_preset, str):
        target = _from_preset(mesh_or_preset)
    else:
        raise ParameterError("mesh", mesh_or_preset, "a trimesh mesh, a mesh file or a drone preset name")
    if material is not None:
        target = target.with_material(material)
    return target if shell_thickness_m is None else target.with_shells(shell_thickness_m)


def _from_trimesh(mesh, name: str) -> TargetMesh:
    import trimesh

    if isinstance(mesh, trimesh.Scene):
        mesh = mesh.dump(concatenate=True)
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise ParameterError("mesh", name, "a triangle mesh with at least one face")
    return prepare_mesh(mesh.vertices, mesh.faces, name=name)


#: How a preset's rotors enter the radar model: as blades at the preset's blade phase (a radar sees blades,
#: not the swept disc the optical models use); over the sphere of aspects the blades' positions are averaged
#: as a spinning rotor's are in time.
RADAR_PROPELLERS = "blades"

#: Part kinds that are thin wires (k a << 1): solved by the method of moments (:mod:`csuas.render.rcs.thin_wire`),
#: not traced as facets (physical optics does not hold for them).
THIN_WIRE_KINDS = ("wiring",)


def _from_preset(name: str) -> TargetMesh:
    """A drone preset's radar model: its parts with rotor blades and the parts inside its shell."""
    try:
        from csuas.drone_models import build_drone, list_presets
    except ImportError:
        raise ParameterError("mesh", name, "an existing mesh file (drone presets are not installed)") from None
    if name not in list_presets():
        raise ParameterError("mesh", name, "an existing mesh file or a drone preset: " + ", ".join(list_presets()))
    drone = build_drone(name, propellers=RADAR_PROPELLERS)
    vertices, faces, face_material, materials, offset = [], [], [], [], 0
    wires = [wire_of_cylinder(p.mesh.vertices) for p in drone.radar_parts() if p.kind in THIN_WIRE_KINDS]
    for part in (p for p in drone.radar_parts() if p.kind not in THIN_WIRE_KINDS):
        index = next((i for i, m in enumerate(materials) if m == part.material), None)
        if index is None:
            materials.append(part.material)
            index = len(materials) - 1
        vertices.append(np.asarray(part.mesh.vertices, float))
        faces.append(np.asarray(part.mesh.faces, np.int64) + offset)
        face_material.append(np.full(len(part.mesh.faces), index))
        offset += len(part.mesh.vertices)
    target = prepare_mesh(
        np.concatenate(vertices), np.concatenate(faces), np.concatenate(face_material), materials, name=name
    )
    if wires:
        target.wires = ThinWires.concatenate(wires).shifted(-target.centre_m)
    return target.with_shells(DRONE_SHELL_THICKNESS_M)


def radar_part_list(name: str) -> list[dict]:
    """A drone preset's radar model part by part, as the RCS engine sees it (:func:`load_target`).

    Parameters
    ----------
    name : str
        A preset of :func:`csuas.drone_models.list_presets`.

    Returns
    -------
    list of dict
        Per part: ``name``, ``kind``, ``material``, ``relative_permittivity`` (``[eps', -eps'']`` without
        the conduction term, or ``"PEC"``), ``conductivity_s_m`` [S/m] (or ``"PEC"``), ``surface``
        (``"PEC"``, ``"conductor half-space"`` or ``"dielectric shell <t> mm"``), ``inside_airframe``,
        ``area_m2`` [m^2], ``size_m`` (bounding-box extents [m]) and the material's ``source``.
    """
    from csuas.drone_models import build_drone, list_presets

    if name not in list_presets():
        raise ParameterError("preset", name, ", ".join(list_presets()))
    drone = build_drone(name, propellers=RADAR_PROPELLERS)
    inside = {id(p) for p in drone.internal_parts}
    rows = []
    for part in drone.radar_parts():
        material = resolve_material(part.material)
        if material.is_pec:
            eps, sigma, surface = "PEC", "PEC", "PEC"
        else:
            eps = [material.relative_permittivity.real, material.relative_permittivity.imag]
            sigma = material.conductivity_s_m
            shell = _is_dielectric(material)
            surface = f"dielectric shell {DRONE_SHELL_THICKNESS_M * 1e3:g} mm" if shell else "conductor half-space"
        if part.kind in THIN_WIRE_KINDS:
            surface = "thin wire (method of moments)"
        rows.append(
            {
                "name": part.name,
                "kind": part.kind,
                "material": part.material.name,
                "relative_permittivity": eps,
                "conductivity_s_m": sigma,
                "surface": surface,
                "inside_airframe": id(part) in inside,
                "area_m2": float(part.mesh.area),
                "size_m": [float(e) for e in part.mesh.extents],
                "source": part.material.source,
            }
        )
    return rows


def formation_target(target: TargetMesh, offsets_m) -> TargetMesh:
    """N copies of ``target`` moved by ``offsets_m`` (N, 3) [m, the target's frame], one mesh traced together
    (a swarm: ``csuas rcs --swarm-*``); re-centred by :func:`prepare_mesh`, materials kept."""
    shifts = np.asarray(offsets_m, float).reshape(-1, 3)
    count = len(target.vertices)
    together = prepare_mesh(
        np.concatenate([target.vertices + shift for shift in shifts]),
        np.concatenate([target.faces + i * count for i in range(len(shifts))]),
        np.tile(target.face_material, len(shifts)),
        target.materials,
        name=f"{len(shifts)} x {target.name}",
    )
    if target.wires is not None:
        copies = ThinWires.concatenate([target.wires.shifted(shift) for shift in shifts])
        together.wires = copies.shifted(-together.centre_m)
    return together
