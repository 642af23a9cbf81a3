"""Parametric single-rotor nano helicopter: fuselage, mast, main rotor, tail boom, tail rotor."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh

from csuas.drone_models import parts as P
from csuas.drone_models.drone import Drone, Part
from csuas.drone_models.materials import Material
from csuas.drone_models.rotorcraft import BladePlan, build_rotorcraft, rotor_mesh

#: Default material per part kind of a nano helicopter.
DEFAULT_HELICOPTER_MATERIALS = {
    "body": "paint",
    "mast": "aluminium",
    "propeller": "dark_plastic",
    "tail_boom": "carbon_fibre",
    "tail_rotor": "dark_plastic",
    "gimbal": "dark_plastic",
}


@dataclass
class HelicopterParams:
    """Geometry of a single-main-rotor helicopter, metres, heights from the ground (z = 0).

    Attributes
    ----------
    fuselage_extents_m, fuselage_center_m : tuple of 3 float
        Ellipsoidal fuselage: full axes (length, width, height) and centre.
    main_rotor_diameter_m : float
        Main rotor tip-to-tip diameter.
    main_rotor_center_m : tuple of 3 float
        Centre of the main rotor plane (hub).
    main_rotor_thickness_m : float
        Swept-disc thickness, or twice the blade thickness.
    mast_diameter_m : float
        Rotor mast diameter (the mast runs from the fuselage centre line up to the hub).
    n_blades, blade_root_chord_m, blade_tip_chord_m, hub_diameter_m, blade_phase_deg
        Main rotor blades (style ``"blades"``).
    tail_boom_end_m : tuple of 3 float
        Rear end of the tail boom (it starts inside the fuselage rear).
    tail_boom_diameter_m : float
        Boom tube diameter.
    tail_rotor_diameter_m, tail_rotor_thickness_m : float
        Tail rotor (axis along y) centred on the boom end.
    camera_extents_m, camera_center_m : tuple of 3 float or None
        Nose camera pod.
    materials : dict
        Part kind -> material name (:data:`DEFAULT_HELICOPTER_MATERIALS`).
    sections : int
        Facets around round parts.
    """

    fuselage_extents_m: tuple
    fuselage_center_m: tuple
    main_rotor_diameter_m: float
    main_rotor_center_m: tuple
    tail_boom_end_m: tuple
    main_rotor_thickness_m: float = 0.003
    mast_diameter_m: float = 0.004
    n_blades: int = 2
    blade_root_chord_m: float = 0.012
    blade_tip_chord_m: float = 0.009
    hub_diameter_m: float = 0.008
    blade_phase_deg: float = 90.0
    tail_boom_diameter_m: float = 0.004
    tail_rotor_diameter_m: float = 0.020
    tail_rotor_thickness_m: float = 0.002
    camera_extents_m: tuple | None = None
    camera_center_m: tuple | None = None
    materials: dict = field(default_factory=lambda: dict(DEFAULT_HELICOPTER_MATERIALS))
    sections: int = P.DEFAULT_SECTIONS


def build_helicopter(
    name: str, params: HelicopterParams, mass_kg: float, spec: dict | None = None, propellers: str = "disc"
) -> Drone:
    """Assemble a single-rotor helicopter (e.g. a Black Hornet class nano sUAS).

    Parameters
    ----------
    name : str
        Model name.
    params : HelicopterParams
        Geometry and materials.
    mass_kg : float
        Take-off mass [kg].
    spec : dict, optional
        Published figures, stored on the result.
    propellers : {"disc", "blades", "none"}
        Representation of both rotors.

    Returns
    -------
    Drone
        Centred on its bounding box.
    """
    materials = {**DEFAULT_HELICOPTER_MATERIALS, **params.materials}
    return build_rotorcraft(
        name, mass_kg, materials, lambda mat: _airframe(params, mat, propellers), spec=spec, propellers=propellers
    )


def _airframe(params: HelicopterParams, mat: dict[str, Material], propellers: str) -> list[Part]:
    """Fuselage, mast, tail boom, both rotors and the camera pod of a helicopter, uncentred."""
    f_c = np.asarray(params.fuselage_center_m, dtype=float)
    f_ext = np.asarray(params.fuselage_extents_m, dtype=float)
    hub = np.asarray(params.main_rotor_center_m, dtype=float)
    parts = [Part("fuselage", "body", P.ellipsoid(f_c, f_ext), mat["body"])]
    mast_bottom = np.array([hub[0], hub[1], f_c[2]])
    parts.append(
        Part("mast", "mast", P.cylinder_between(mast_bottom, hub, params.mast_diameter_m / 2.0, 16), mat["mast"])
    )
    tail_end = np.asarray(params.tail_boom_end_m, dtype=float)
    boom_start = f_c - [f_ext[0] / 4.0, 0.0, 0.0]
    parts.append(
        Part(
            "tail_boom",
            "tail_boom",
            P.cylinder_between(boom_start, tail_end, params.tail_boom_diameter_m / 2.0, 16),
            mat["tail_boom"],
        )
    )
    if propellers != "none":
        plan = BladePlan.of(params)
        rotor = rotor_mesh(
            hub, params.main_rotor_diameter_m, params.main_rotor_thickness_m, propellers, plan, params.sections
        )
        tail = _tail_rotor(params, tail_end, propellers)
        parts.append(Part("main_rotor", "propeller", rotor, mat["propeller"], spin_axis=(0.0, 0.0, 1.0)))
        parts.append(Part("tail_rotor", "tail_rotor", tail, mat["tail_rotor"]))
    if params.camera_extents_m is not None:
        parts.append(
            Part("camera", "gimbal", P.ellipsoid(params.camera_center_m, params.camera_extents_m, 2), mat["gimbal"])
        )
    return parts


def _tail_rotor(params: HelicopterParams, tail_end, style: str):
    """The tail rotor, axis along y at the boom's end: a swept disc, or two blades of fixed proportions."""
    d = params.tail_rotor_diameter_m
    if style == "disc":
        half = np.array([0.0, params.tail_rotor_thickness_m / 2.0, 0.0])
        return P.cylinder_between(tail_end - half, tail_end + half, d / 2.0, params.sections)
    plan = BladePlan(2, d / 6.0, d / 8.0, d / 5.0, 0.0)
    tail = rotor_mesh([0.0, 0.0, 0.0], d, params.tail_rotor_thickness_m, "blades", plan, params.sections)
    tail.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2.0, [1.0, 0.0, 0.0]))
    tail.apply_translation(tail_end)
    return tail
