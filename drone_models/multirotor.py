"""Parametric multirotor generator: body, arms, motors, propellers, gimbal, legs, battery.

Inside the body shell (the drone's ``internal_parts``, seen by the radar only): the flight controller's
board (FR-4) with its copper ground plane as an inner layer, the wiring (three motor leads along each
arm's run inside the body, two battery leads) and the gimbal's metal camera module inside its ABS
housing. Wires are AWG 20 (0.81 mm, ASTM B258 table) by default.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh

from csuas.base.errors import ParameterError
from csuas.drone_models import parts as P
from csuas.drone_models.drone import Drone, Part
from csuas.drone_models.materials import Material
from csuas.drone_models.rotorcraft import BladePlan, build_rotorcraft, rotor_mesh

#: Default material per part kind (the paper's component list, Section 4.4.3:
#: plastic frame, carbon-fibre arms, aluminium supports, paint finish).
DEFAULT_MULTIROTOR_MATERIALS = {
    "body": "paint",
    "arm": "carbon_fibre",
    "motor": "aluminium",
    "propeller": "dark_plastic",
    "gimbal": "dark_plastic",
    "landing_gear": "aluminium",
    "battery": "battery_pack",
    "flight_controller": "fr4",
    "ground_plane": "copper",
    "wiring": "copper",
    "camera_module": "aluminium",
}

#: Thickness of the flight controller's board [m] (the common 1.6 mm FR-4 stack-up).
BOARD_THICKNESS_M = 0.0016
#: Thickness of the board's inner copper ground plane as meshed [m] (35 um foil, thickened for the mesh).
GROUND_PLANE_THICKNESS_M = 0.0002
#: Facets around a wire.
WIRE_SECTIONS = 8
#: Motor leads per arm (a brushless motor's three phases).
LEADS_PER_MOTOR = 3
#: Plan size of the ground plane as a fraction of the board's (the copper stops short of the board's edge).
GROUND_PLANE_FRACTION = 0.95
#: Centre-to-centre spacing of side-by-side motor leads and of the two battery leads, in wire diameters.
LEAD_PITCH_DIAMETERS = 2.5
BATTERY_LEAD_PITCH_DIAMETERS = 3.0
#: Where the motor leads leave the board: this fraction of the way from its centre toward the arm's root.
LEAD_START_FRACTION = 0.5
#: Where the battery leads leave the board: this fraction of its length from its centre toward the battery.
BATTERY_LEAD_FRACTION = 0.4


@dataclass
class MultirotorParams:
    """Geometry of a multirotor, all lengths in metres, heights from the ground (z = 0).

    The built model is re-centred on its bounding box (body frame +x forward,
    +y left, +z up).

    Attributes
    ----------
    body_extents_m, body_center_m : tuple of 3 float
        Fuselage shell size (length, width, height) and centre.
    body_corner_radius_m : float
        Rounding radius of the shell edges.
    rotor_positions_m : tuple of (x, y, z)
        Motor axis position and motor base height per rotor; the rotor count
        is ``len(rotor_positions_m)`` (see :func:`csuas.drone_models.parts.radial_layout`).
    motor_diameter_m, motor_height_m : float
        Motor bell size.
    arm_width_m, arm_thickness_m : float
        Arm cross-section (``arm_profile = "bar"``) or tube diameter and
        unused thickness (``"tube"``).
    arm_profile : {"bar", "tube"}
        Flat moulded arm or round tube.
    arm_root_fraction : float
        Arm roots lie at this fraction of the body half-length/half-width
        toward each rotor (0 = body centre, 1 = body edge).
    propeller_diameter_m : float
        Tip-to-tip diameter.
    propeller_thickness_m : float
        Swept-disc thickness (``"disc"``) or twice the blade thickness (``"blades"``).
    propeller_gap_m : float
        Gap between motor top and propeller plane bottom.
    n_blades : int
        Blades per propeller.
    blade_root_chord_m, blade_tip_chord_m, hub_diameter_m : float
        Blade plan form and hub size.
    blade_phase_deg : float
        Azimuth of the first blade of every propeller.
    gimbal_extents_m, gimbal_center_m : tuple of 3 float or None
        Gimbal camera housing; ``None`` for none.
    lens_diameter_m, lens_length_m : float
        Lens barrel protruding forward (+x) from the gimbal front face.
    landing_legs_m : tuple of ((x, y, z_top), (x, y, z_bottom))
        Straight legs.
    leg_radius_m : float
        Leg tube radius.
    battery_extents_m, battery_center_m : tuple of 3 float or None
        Exposed battery pack; ``None`` for none.
    flight_controller_extents_m, flight_controller_center_m : tuple of 2 and 3 float or None
        Plan size (length, width) and centre of the flight controller's board inside the body,
        :data:`BOARD_THICKNESS_M` thick with its ground plane at mid-thickness; ``None`` for none
        (then no wiring either).
    wire_diameter_m : float
        Diameter of the motor and battery leads [m].
    camera_module_fraction : float
        Size of the gimbal's metal camera module as a fraction of the housing's extents (0 for none).
    materials : dict
        Part kind -> material name (:data:`DEFAULT_MULTIROTOR_MATERIALS`).
    sections : int
        Facets around round parts.
    """

    body_extents_m: tuple
    body_center_m: tuple
    rotor_positions_m: tuple
    propeller_diameter_m: float
    body_corner_radius_m: float = 0.008
    motor_diameter_m: float = 0.020
    motor_height_m: float = 0.016
    arm_width_m: float = 0.012
    arm_thickness_m: float = 0.008
    arm_profile: str = "bar"
    arm_root_fraction: float = 0.6
    propeller_thickness_m: float = 0.006
    propeller_gap_m: float = 0.002
    n_blades: int = 2
    blade_root_chord_m: float = 0.018
    blade_tip_chord_m: float = 0.010
    hub_diameter_m: float = 0.010
    blade_phase_deg: float = 0.0
    gimbal_extents_m: tuple | None = None
    gimbal_center_m: tuple | None = None
    lens_diameter_m: float = 0.012
    lens_length_m: float = 0.006
    landing_legs_m: tuple = ()
    leg_radius_m: float = 0.003
    battery_extents_m: tuple | None = None
    battery_center_m: tuple | None = None
    flight_controller_extents_m: tuple | None = None
    flight_controller_center_m: tuple | None = None
    wire_diameter_m: float = 0.00081
    camera_module_fraction: float = 0.6
    materials: dict = field(default_factory=lambda: dict(DEFAULT_MULTIROTOR_MATERIALS))
    sections: int = P.DEFAULT_SECTIONS


def _rotor_label(i: int, x: float, y: float, n: int) -> str:
    if n == 4:
        return f"{'front' if x > 0 else 'rear'}_{'left' if y > 0 else 'right'}"
    return f"rotor{i}"


def propeller_mesh(center, params: MultirotorParams, style: str):
    """Propeller of ``params`` at hub ``center`` as a swept disc or as blades."""
    plan = BladePlan.of(params)
    return rotor_mesh(center, params.propeller_diameter_m, params.propeller_thickness_m, style, plan, params.sections)


def build_multirotor(
    name: str, params: MultirotorParams, mass_kg: float, spec: dict | None = None, propellers: str = "disc"
) -> Drone:
    """Assemble a multirotor from ``params``.

    Parameters
    ----------
    name : str
        Model name.
    params : MultirotorParams
        Geometry and materials.
    mass_kg : float
        Take-off mass [kg].
    spec : dict, optional
        Published figures, stored on the result.
    propellers : {"disc", "blades", "none"}
        Representation of the propellers.

    Returns
    -------
    Drone
        Centred on its bounding box.
    """
    if params.arm_profile not in ("bar", "tube"):
        raise ParameterError("arm_profile", params.arm_profile, "bar, tube")
    if not params.rotor_positions_m:
        raise ParameterError("rotor_positions_m", params.rotor_positions_m, "at least one rotor")
    materials = {**DEFAULT_MULTIROTOR_MATERIALS, **params.materials}
    return build_rotorcraft(
        name,
        mass_kg,
        materials,
        lambda mat: _airframe(params, mat, propellers),
        spec=spec,
        propellers=propellers,
        internals=lambda mat: _internals(params, mat),
    )


def _arm_root(params: MultirotorParams, x: float, y: float) -> np.ndarray:
    """Where the arm of the rotor at (x, y) starts inside the body [m] (``arm_root_fraction``)."""
    body_c = np.asarray(params.body_center_m, dtype=float)
    offset = np.array([x, y]) - body_c[:2]
    half = params.arm_root_fraction * np.asarray(params.body_extents_m, dtype=float)[:2] / 2.0
    scale = min([1.0, *(h / abs(o) for h, o in zip(half, offset) if o != 0.0)])
    return np.array([*(body_c[:2] + offset * scale), body_c[2]])


def _airframe(params: MultirotorParams, mat: dict[str, Material], propellers: str) -> list[Part]:
    """Body, arms, motors, propellers, gimbal, legs and battery of a multirotor, uncentred."""
    body_c = np.asarray(params.body_center_m, dtype=float)
    body_ext = np.asarray(params.body_extents_m, dtype=float)
    parts = [Part("body", "body", P.rounded_box(body_c, body_ext, params.body_corner_radius_m), mat["body"])]
    n = len(params.rotor_positions_m)
    for i, (x, y, z) in enumerate(params.rotor_positions_m):
        label = f"{i}_{_rotor_label(i, x, y, n)}"
        motor_mid = np.array([x, y, z + params.motor_height_m / 2.0])
        root = _arm_root(params, x, y)
        if np.linalg.norm(motor_mid[:2] - root[:2]) > 1e-9:  # a rotor above the body needs no arm
            if params.arm_profile == "bar":
                arm = P.bar_between(root, motor_mid, params.arm_width_m, params.arm_thickness_m)
            else:
                arm = P.cylinder_between(root, motor_mid, params.arm_width_m / 2.0, params.sections)
            parts.append(Part(f"arm_{label}", "arm", arm, mat["arm"]))
        motor = P.cylinder_between(
            [x, y, z], [x, y, z + params.motor_height_m], params.motor_diameter_m / 2.0, params.sections
        )
        parts.append(Part(f"motor_{label}", "motor", motor, mat["motor"]))
        if propellers != "none":
            hub = [x, y, z + params.motor_height_m + params.propeller_gap_m + params.propeller_thickness_m / 2.0]
            parts.append(
                Part(
                    f"propeller_{label}",
                    "propeller",
                    propeller_mesh(hub, params, propellers),
                    mat["propeller"],
                    spin_axis=(0.0, 0.0, 1.0),
                )
            )
    if params.gimbal_extents_m is not None:
        g_c = np.asarray(params.gimbal_center_m, dtype=float)
        g_ext = np.asarray(params.gimbal_extents_m, dtype=float)
        front = g_c + [g_ext[0] / 2.0, 0.0, 0.0]
        housing = P.rounded_box(g_c, g_ext, min(g_ext) / 4.0)
        lens = P.cylinder_between(
            front - [0.001, 0.0, 0.0],
            front + [params.lens_length_m, 0.0, 0.0],
            params.lens_diameter_m / 2.0,
            params.sections,
        )
        parts.append(Part("gimbal_camera", "gimbal", trimesh.util.concatenate([housing, lens]), mat["gimbal"]))
    for i, (top, bottom) in enumerate(params.landing_legs_m):
        parts.append(
            Part(
                f"landing_leg_{i}",
                "landing_gear",
                P.cylinder_between(top, bottom, params.leg_radius_m, 16),
                mat["landing_gear"],
            )
        )
    if params.battery_extents_m is not None:
        parts.append(
            Part("battery", "battery", P.box(params.battery_center_m, params.battery_extents_m), mat["battery"])
        )
    return parts


def _internals(params: MultirotorParams, mat: dict[str, Material]) -> list[Part]:
    """The flight controller's board and ground plane, the wiring and the camera module, uncentred."""
    parts = []
    if params.gimbal_extents_m is not None and params.camera_module_fraction > 0.0:
        module = P.box(params.gimbal_center_m, np.asarray(params.gimbal_extents_m) * params.camera_module_fraction)
        parts.append(Part("camera_module", "camera_module", module, mat["camera_module"]))
    if params.flight_controller_extents_m is None:
        return parts
    if params.flight_controller_center_m is None:
        raise ParameterError("flight_controller_center_m", None, "the board's centre (x, y, z) [m] inside the body")
    centre = np.asarray(params.flight_controller_center_m, dtype=float)
    length, width = params.flight_controller_extents_m
    parts.append(
        Part(
            "flight_controller",
            "flight_controller",
            P.box(centre, (length, width, BOARD_THICKNESS_M)),
            mat["flight_controller"],
        )
    )
    plane = P.box(centre, (GROUND_PLANE_FRACTION * length, GROUND_PLANE_FRACTION * width, GROUND_PLANE_THICKNESS_M))
    parts.append(Part("ground_plane", "ground_plane", plane, mat["ground_plane"]))
    return parts + _wiring(params, mat["wiring"], centre)


def _wiring(params: MultirotorParams, material: Material, board_centre: np.ndarray) -> list[Part]:
    """Motor leads from the board's top to each arm's root and battery leads to the pack, inside the body."""
    radius = params.wire_diameter_m / 2.0
    top = board_centre[2] + BOARD_THICKNESS_M / 2.0 + radius
    arm_top = params.body_center_m[2] + params.arm_thickness_m / 2.0 + radius
    wires = []
    for i, (x, y, _) in enumerate(params.rotor_positions_m):
        root = _arm_root(params, x, y)
        along = root[:2] - board_centre[:2]
        side = np.array([-along[1], along[0]]) / max(float(np.linalg.norm(along)), 1e-9)
        for k in range(LEADS_PER_MOTOR):
            shift = (k - (LEADS_PER_MOTOR - 1) / 2.0) * LEAD_PITCH_DIAMETERS * 2.0 * radius * side
            start = [*(board_centre[:2] + LEAD_START_FRACTION * along + shift), top]
            end = [*(root[:2] + shift), arm_top]
            wires.append(
                Part(f"wire_motor{i}_{k}", "wiring", P.cylinder_between(start, end, radius, WIRE_SECTIONS), material)
            )
    if params.battery_center_m is not None:
        b_c = np.asarray(params.battery_center_m, dtype=float)
        toward = np.sign(board_centre[0] - b_c[0])
        face_x = b_c[0] + toward * params.battery_extents_m[0] / 2.0
        board_x = board_centre[0] - toward * BATTERY_LEAD_FRACTION * params.flight_controller_extents_m[0]
        half_pitch = BATTERY_LEAD_PITCH_DIAMETERS * radius
        for k, dy in enumerate((-half_pitch, half_pitch)):
            start, end = [board_x, board_centre[1] + dy, top], [face_x, b_c[1] + dy, b_c[2]]
            wires.append(
                Part(f"wire_battery_{k}", "wiring", P.cylinder_between(start, end, radius, WIRE_SECTIONS), material)
            )
    return wires
