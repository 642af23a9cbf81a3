"""Parametric fixed-wing sUAS: fuselage, tapered wing with dihedral, twin booms, H-tail, pusher propeller.

The layout is that of a small electric pusher UAV (the class of the 2 m-span Euclid of Kapoulas et al.
2023): a pod fuselage with an electric motor at its rear driving a pusher propeller whose axis is the
fuselage axis (+x forward), a shoulder wing, and two tail booms outside the propeller disc that carry a
horizontal stabiliser between them and a fin on each boom. Every part is a closed convex shell:

* ``fuselage``: an ellipsoid, its nose at x = 0;
* ``wing_left``, ``wing_right``: tapered slabs from the centre line (root chord, inside the fuselage) to
  the tip (tip chord), rising at the dihedral angle; each section is a flat slab of the stated thickness
  ratio, so the tips lie exactly at y = +-span / 2;
* ``boom_left``, ``boom_right``: tubes from the wing's mid-chord to the tail's trailing edge;
* ``stabiliser``: a rectangular slab between the booms, its trailing edge at x = -length;
* ``fin_left``, ``fin_right``: tapered slabs standing on the booms, their tips at the stated height;
* ``motor``: a cylinder behind the fuselage's tail (5 mm inside it);
* ``propeller``: the pusher's swept disc (axis x), its blades (turning in the y-z plane, the phase from +y
  toward +z), or nothing (``propellers``); the disc's lowest point is the bottom of the model (z = 0).

References
----------
- I. K. Kapoulas et al., "Small Fixed-Wing UAV Radar Cross-Section Signature Investigation and Detection
  and Classification of Distance Estimation Using Realistic Parameters of a Commercial Anti-Drone
  System", Drones 7(1):39, 2023 (the Euclid: 2 m wingspan).
- D. P. Raymer, Aircraft Design: A Conceptual Approach, 6th ed., AIAA, 2018 (taper, dihedral, tail volume).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh

from csuas.base.errors import ParameterError
from csuas.drone_models import parts as P
from csuas.drone_models.drone import Drone, Part
from csuas.drone_models.materials import get_material
from csuas.drone_models.rotorcraft import PROPELLER_STYLES

#: Default material per part kind of a fixed-wing (painted glass/carbon composite airframe, anodised motor bell).
DEFAULT_FIXED_WING_MATERIALS = {
    "body": "paint",
    "wing": "paint",
    "tail_boom": "carbon_fibre",
    "tail": "paint",
    "motor": "anodised_aluminium",
    "pusher_propeller": "dark_plastic",
    "gimbal": "dark_plastic",
}


#: How far the motor's front reaches into the fuselage's tail [m] (its mount).
MOTOR_INSET_M = 0.005
#: The pusher's rotation axis in the body frame: the fuselage axis, +x (forward).
PUSHER_AXIS = (1.0, 0.0, 0.0)


@dataclass
class FixedWingParams:
    """Geometry of a twin-boom pusher fixed-wing, metres, +x forward, nose at x = 0, bottom at z = 0.

    Attributes
    ----------
    span_m, length_m, height_m : float
        Wingspan (tip to tip), overall length (nose to tail trailing edge) and overall height (propeller
        disc bottom to fin tips).
    fuselage_length_m, fuselage_diameter_m : float
        Pod fuselage (an ellipsoid of revolution about the x axis).
    root_chord_m, tip_chord_m : float
        Wing chord at the centre line and at the tips.
    wing_thickness_ratio : float
        Slab thickness over the local chord [-].
    dihedral_deg : float
        Wing dihedral [deg].
    wing_leading_edge_x_m : float
        x of the wing root's leading edge (negative: behind the nose).
    leading_edge_sweep_m : float
        Tip leading edge behind the root's [m].
    wing_z_above_axis_m : float
        Height of the wing root above the fuselage axis.
    boom_y_m, boom_diameter_m : float
        Lateral position and diameter of the two tail booms (outside the propeller disc).
    stabiliser_chord_m, stabiliser_thickness_m : float
        Horizontal stabiliser between the booms.
    fin_root_chord_m, fin_tip_chord_m, fin_thickness_m : float
        The two fins (their height is what ``height_m`` leaves above the booms).
    propeller_diameter_m, propeller_thickness_m : float
        Pusher propeller (thickness of the swept disc, twice the blade thickness for blades).
    n_blades, blade_root_chord_m, blade_tip_chord_m, hub_diameter_m, blade_phase_deg
        Propeller blades (style ``"blades"``); phase from +y toward +z.
    motor_diameter_m, motor_length_m : float
        Motor behind the fuselage, the propeller right behind it.
    camera_extents_m : tuple of 3 float or None
        Camera pod under the nose (ellipsoid), or none.
    motor_temperature_k : float or None
        Motor case temperature [K] (its heat in thermal renders); None: the material's.
    materials : dict
        Part kind -> material name (:data:`DEFAULT_FIXED_WING_MATERIALS`).
    sections : int
        Facets around round parts.
    """

    span_m: float
    length_m: float
    height_m: float
    fuselage_length_m: float
    fuselage_diameter_m: float
    root_chord_m: float
    tip_chord_m: float
    propeller_diameter_m: float
    wing_thickness_ratio: float = 0.12
    dihedral_deg: float = 3.0
    wing_leading_edge_x_m: float = -0.25
    leading_edge_sweep_m: float = 0.04
    wing_z_above_axis_m: float = 0.04
    boom_y_m: float = 0.24
    boom_diameter_m: float = 0.02
    stabiliser_chord_m: float = 0.14
    stabiliser_thickness_m: float = 0.012
    fin_root_chord_m: float = 0.16
    fin_tip_chord_m: float = 0.10
    fin_thickness_m: float = 0.012
    propeller_thickness_m: float = 0.012
    n_blades: int = 2
    blade_root_chord_m: float = 0.035
    blade_tip_chord_m: float = 0.018
    hub_diameter_m: float = 0.03
    blade_phase_deg: float = 90.0
    motor_diameter_m: float = 0.045
    motor_length_m: float = 0.04
    camera_extents_m: tuple | None = (0.10, 0.07, 0.06)
    motor_temperature_k: float | None = None
    materials: dict = field(default_factory=lambda: dict(DEFAULT_FIXED_WING_MATERIALS))
    sections: int = P.DEFAULT_SECTIONS


def wing_panel(params: FixedWingParams, side: int, z_root: float) -> trimesh.Trimesh:
    """One wing half (side +1 left, -1 right): root slab at y = 0, tip slab at y = side * span / 2.

    The panel runs along (0, cos G, sin G) (G the dihedral), so the tip is ``span / 2 * tan G`` above the
    root; each section is a slab ``wing_thickness_ratio`` x chord thick, centred on the wing's plane.
    """
    half_span = params.span_m / 2.0
    rise = half_span * np.tan(np.radians(params.dihedral_deg))
    points = []
    for y, chord, le_x, z in (
        (0.0, params.root_chord_m, params.wing_leading_edge_x_m, z_root),
        (
            side * half_span,
            params.tip_chord_m,
            params.wing_leading_edge_x_m - params.leading_edge_sweep_m,
            z_root + rise,
        ),
    ):
        half_t = params.wing_thickness_ratio * chord / 2.0
        points += [(x, y, z + dz) for x in (le_x, le_x - chord) for dz in (-half_t, half_t)]
    return trimesh.convex.convex_hull(np.array(points))


def slab(root: tuple, tip: tuple, thickness: float) -> trimesh.Trimesh:
    """A tapered slab between two straight sections, each ``(x_front, x_rear, y, z)``, ``thickness`` across.

    The thickness is along y for a vertical surface (the sections differ more in z than in y) and along z
    for a horizontal one.
    """
    vertical = abs(tip[3] - root[3]) > abs(tip[2] - root[2])
    half = thickness / 2.0
    points = [
        (x, y + d, z) if vertical else (x, y, z + d)
        for x_front, x_rear, y, z in (root, tip)
        for x in (x_front, x_rear)
        for d in (-half, half)
    ]
    return trimesh.convex.convex_hull(np.array(points))


def motor_and_pusher(params, mat: dict, motor_front: float, axis_z: float, propellers: str) -> list[Part]:
    """The motor (a cylinder on the x axis from ``motor_front`` [m] rearward) and, unless ``propellers`` is
    ``"none"``, the pusher propeller behind it, turning about :data:`PUSHER_AXIS`."""
    motor_rear = motor_front - params.motor_length_m
    motor = P.cylinder_between((motor_front, 0.0, axis_z), (motor_rear, 0.0, axis_z), params.motor_diameter_m / 2.0, 24)
    parts = [Part("motor", "motor", motor, mat["motor"])]
    if propellers != "none":
        hub = np.array([motor_rear - params.propeller_thickness_m / 2.0, 0.0, axis_z])
        propeller = pusher_propeller(hub, params, propellers)
        parts.append(Part("propeller", "pusher_propeller", propeller, mat["pusher_propeller"], spin_axis=PUSHER_AXIS))
    return parts


def pusher_propeller(centre: np.ndarray, params: FixedWingParams, style: str) -> trimesh.Trimesh:
    """The pusher's swept disc (axis x) or its blades turned into the y-z plane (phase from +y toward +z)."""
    if style == "disc":
        half = np.array([params.propeller_thickness_m / 2.0, 0.0, 0.0])
        return P.cylinder_between(centre - half, centre + half, params.propeller_diameter_m / 2.0, params.sections)
    blades = P.propeller_blades(
        [0.0, 0.0, 0.0],
        params.propeller_diameter_m,
        params.n_blades,
        params.blade_root_chord_m,
        params.blade_tip_chord_m,
        params.propeller_thickness_m / 2.0,
        params.hub_diameter_m,
        params.blade_phase_deg,
    )
    # x-y plane -> y-z plane: x -> y, y -> z, z -> x (a cyclic permutation, a proper rotation)
    to_yz = np.eye(4)
    to_yz[:3, :3] = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    blades.apply_transform(to_yz)
    blades.apply_translation(centre)
    return blades


def lowest_wing_z(params: FixedWingParams) -> float:
    """Height of the wing root above the model's bottom (the disc's lowest point) [m]."""
    return params.propeller_diameter_m / 2.0 + params.wing_z_above_axis_m


def _check(params: FixedWingParams) -> None:
    """Refuse layouts whose parts would leave the stated box (booms inside the disc, wing tips above the fins)."""
    prop_r = params.propeller_diameter_m / 2.0
    if params.boom_y_m <= prop_r:
        raise ParameterError("boom_y_m", params.boom_y_m, f"> {prop_r:.6g} m (outside the propeller disc)")
    lowest = max(lowest_wing_z(params), params.propeller_diameter_m)
    if params.height_m <= lowest:
        raise ParameterError("height_m", params.height_m, f"> {lowest:.6g} m (fins above the wing and the disc)")
    tip_top = (
        lowest_wing_z(params)
        + params.span_m / 2.0 * np.tan(np.radians(params.dihedral_deg))
        + params.wing_thickness_ratio * params.tip_chord_m / 2.0
    )
    if not 0.0 <= params.dihedral_deg < 90.0 or tip_top >= params.height_m:
        raise ParameterError("dihedral_deg", params.dihedral_deg, "0 <= x < 90 with the wing tips below the fin tips")
    if params.fuselage_length_m + params.motor_length_m + params.propeller_thickness_m >= params.length_m:
        raise ParameterError("length_m", params.length_m, "longer than fuselage, motor and propeller together")


def build_fixed_wing(
    name: str, params: FixedWingParams, mass_kg: float, spec: dict | None = None, propellers: str = "disc"
) -> Drone:
    """Assemble a twin-boom pusher fixed-wing (module docstring).

    Parameters
    ----------
    name : str
        Model name.
    params : FixedWingParams
        Geometry and materials.
    mass_kg : float
        Take-off mass [kg].
    spec : dict, optional
        Published figures, stored on the result.
    propellers : {"disc", "blades", "none"}
        The pusher propeller as a swept disc, as blades, or left out.

    Returns
    -------
    Drone
        Centred on its bounding box; span along y, length along x, height along z.
    """
    if propellers not in PROPELLER_STYLES:
        raise ParameterError("propellers", propellers, ", ".join(PROPELLER_STYLES))
    _check(params)
    mat = {kind: get_material(m) for kind, m in {**DEFAULT_FIXED_WING_MATERIALS, **params.materials}.items()}
    if params.motor_temperature_k is not None:
        mat["motor"] = mat["motor"].with_temperature(params.motor_temperature_k)
    axis_z = params.propeller_diameter_m / 2.0  # the disc's lowest point at z = 0
    wing_z = lowest_wing_z(params)
    fus_c = np.array([-params.fuselage_length_m / 2.0, 0.0, axis_z])
    fus_d = params.fuselage_diameter_m
    parts = [Part("fuselage", "body", P.ellipsoid(fus_c, (params.fuselage_length_m, fus_d, fus_d)), mat["body"])]
    for side, label in ((1, "left"), (-1, "right")):
        parts.append(Part(f"wing_{label}", "wing", wing_panel(params, side, wing_z), mat["wing"]))
    tail_rear = -params.length_m
    tail_front = tail_rear + params.stabiliser_chord_m
    boom_front = params.wing_leading_edge_x_m - params.root_chord_m / 2.0
    fin_front = tail_rear + params.fin_root_chord_m
    fin_tip_front = tail_rear + params.fin_tip_chord_m
    for side, label in ((1, "left"), (-1, "right")):
        y = side * params.boom_y_m
        boom = P.cylinder_between((boom_front, y, wing_z), (tail_rear, y, wing_z), params.boom_diameter_m / 2.0, 16)
        parts.append(Part(f"boom_{label}", "tail_boom", boom, mat["tail_boom"]))
        fin_root, fin_tip = (fin_front, tail_rear, y, wing_z), (fin_tip_front, tail_rear, y, params.height_m)
        fin = slab(fin_root, fin_tip, params.fin_thickness_m)
        parts.append(Part(f"fin_{label}", "tail", fin, mat["tail"]))
    stabiliser = slab(
        (tail_front, tail_rear, -params.boom_y_m, wing_z),
        (tail_front, tail_rear, params.boom_y_m, wing_z),
        params.stabiliser_thickness_m,
    )
    parts.append(Part("stabiliser", "tail", stabiliser, mat["tail"]))
    motor_front = -params.fuselage_length_m + MOTOR_INSET_M  # mounted on the fuselage's tail
    parts += motor_and_pusher(params, mat, motor_front, axis_z, propellers)
    if params.camera_extents_m is not None:
        cam = np.asarray(params.camera_extents_m, dtype=float)
        centre = (-0.2 * params.fuselage_length_m, 0.0, axis_z - fus_d / 2.0 + cam[2] / 4.0)
        parts.append(Part("camera", "gimbal", P.ellipsoid(centre, cam, 2), mat["gimbal"]))
    return Drone(name=name, mass_kg=float(mass_kg), parts=parts, spec=dict(spec or {}), propellers=propellers).centred()
