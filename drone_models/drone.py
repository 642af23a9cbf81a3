"""A drone as a list of named parts, each a watertight mesh with one material."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh

from csuas.base.errors import ParameterError
from csuas.drone_models.materials import Material, paper_component_mean_emissivity


@dataclass
class Part:
    """One component of a drone.

    Attributes
    ----------
    name : str
        Unique name within the drone, e.g. ``"arm_front_left"``.
    kind : str
        Component class: body, arm, motor, propeller, gimbal, landing_gear,
        battery, tail_boom, tail_rotor, mast; a fixed-wing adds wing, tail,
        pusher_propeller; parts inside the airframe (``Drone.internal_parts``) are
        flight_controller, ground_plane, wiring and camera_module.
    mesh : trimesh.Trimesh
        Closed surface in the body frame [m].
    material : Material
        Surface material.
    spin_axis : tuple of float, optional
        A propeller's rotation axis, a unit vector in the body frame (multirotor and helicopter rotors +z, a
        fixed-wing's pusher +x); None for every other part (render/rcs/micro_doppler.py turns blades about it).
    """

    name: str
    kind: str
    mesh: trimesh.Trimesh
    material: Material
    spin_axis: tuple | None = None


@dataclass
class Drone:
    """A drone model in its body frame (+x forward, +y left, +z up, metres).

    Attributes
    ----------
    name : str
        Preset or model name.
    mass_kg : float or None
        Take-off mass from the specification [kg] (not computed from the
        mesh); None when unknown (user meshes).
    parts : list of Part
        Components; their union is the drone.
    spec : dict
        Published figures the model was built from, with their source.
    propellers : str
        ``"disc"`` (swept discs), ``"blades"``, ``"none"``, or ``"as file"`` for user meshes.
    internal_parts : list of Part
        Parts enclosed by the airframe's dielectric shell (circuit board, wiring, camera module):
        the radar sees them through the shell (:meth:`radar_parts`); the EO, thermal, lidar and
        silhouette models, which see the opaque outer surface, do not.
    """

    name: str
    mass_kg: float | None
    parts: list
    spec: dict = field(default_factory=dict)
    propellers: str = "disc"
    internal_parts: list = field(default_factory=list)

    def radar_parts(self) -> list:
        """The parts a radar sees: the outer parts and those inside the dielectric shell."""
        return [*self.parts, *self.internal_parts]

    def mesh(self, kinds=None) -> trimesh.Trimesh:
        """All parts (or the parts whose ``kind`` is in ``kinds``) concatenated into one mesh.

        The result is a set of closed shells, not one manifold solid: shells
        may overlap and no vertices are merged.
        """
        selected = [p.mesh for p in self.parts if kinds is None or p.kind in kinds]
        if not selected:
            raise ParameterError("kinds", kinds, ", ".join(sorted({p.kind for p in self.parts})))
        return trimesh.util.concatenate(selected)

    def bounds(self, exclude_kinds=()) -> np.ndarray:
        """Axis-aligned bounds ``[[xmin, ymin, zmin], [xmax, ymax, zmax]]`` [m]."""
        verts = np.concatenate([p.mesh.vertices for p in self.parts if p.kind not in exclude_kinds])
        return np.stack([verts.min(axis=0), verts.max(axis=0)])

    def extents(self, exclude_kinds=()) -> np.ndarray:
        """Bounding-box size (length x, width y, height z) [m]."""
        b = self.bounds(exclude_kinds)
        return b[1] - b[0]

    def part(self, name: str) -> Part:
        """The part called ``name``."""
        for p in self.parts:
            if p.name == name:
                return p
        raise ParameterError("part", name, ", ".join(p.name for p in self.parts))

    def area_by_material(self) -> dict:
        """Surface area of the parts per material name [m^2]."""
        areas: dict = {}
        for p in self.parts:
            areas[p.material.name] = areas.get(p.material.name, 0.0) + float(p.mesh.area)
        return areas

    def emissivity(self, band: str = "lwir", exclude_kinds=("propeller", "pusher_propeller")) -> dict:
        """Mean thermal emissivity of the drone [-], two ways.

        ``area_weighted``: sum of emissivity x shell area over the parts
        (propellers, lifting and pusher, excluded by default: a spinning rotor's swept disc is
        mostly background). ``component_mean``: the paper's rule of
        Section 4.4.3, the unweighted mean over the distinct materials present.
        ``paper_component_mean`` is that rule applied to the paper's own list (0.68).

        Parameters
        ----------
        band : {"lwir", "mwir"}
        exclude_kinds : iterable of str
            Part kinds left out of the area weighting.
        """
        if band not in ("lwir", "mwir"):
            raise ParameterError("band", band, "lwir, mwir")
        attr = f"emissivity_{band}"
        parts = [p for p in self.parts if p.kind not in exclude_kinds]
        areas = np.array([p.mesh.area for p in parts])
        eps = np.array([getattr(p.material, attr) for p in parts])
        distinct = {p.material.name: getattr(p.material, attr) for p in parts}
        return {
            "band": band,
            "area_weighted": float(np.sum(areas * eps) / np.sum(areas)),
            "component_mean": float(np.mean(list(distinct.values()))),
            "paper_component_mean": paper_component_mean_emissivity(),
            "materials": sorted(distinct),
        }

    def translated(self, offset) -> Drone:
        """Move every part, internal ones included, by ``offset`` [m] in place and return ``self``."""
        for p in self.radar_parts():
            p.mesh.apply_translation(offset)
        return self

    def centred(self) -> Drone:
        """Put the origin at the centre of the bounding box of all parts (in place)."""
        b = self.bounds()
        return self.translated(-(b[0] + b[1]) / 2.0)
