"""Parametric flying-wing delta sUAS: a pod, a swept tapered wing with a straight trailing edge, tip winglets
and a pusher propeller on the trailing edge.

The layout is that of a small tailless delta (the class of the foam flying wings of about 1 m span used
as small fixed-wing drones): a pod fuselage on the centre line, a wing whose leading edge sweeps back to
the tips while its trailing edge stays straight (a delta planform cropped at the tips), a vertical
winglet at each tip (the only fins), and an electric motor on the trailing edge at the centre line
driving a pusher propeller whose axis is the fuselage axis (+x forward). Every part is a closed convex
shell:

* ``fuselage``: an ellipsoid, its nose at x = 0;
* ``wing_left``, ``wing_right``: tapered slabs from the centre line (root chord) to the tip (tip chord),
  built as the fixed-wing's (:func:`csuas.drone_models.fixed_wing.wing_panel`), the tips at y = +-span/2;
* ``winglet_left``, ``winglet_right``: tapered slabs standing on the tips, their tops at ``height_m``;
* ``motor``: a cylinder behind the trailing edge (``MOTOR_INSET_M`` inside the wing);
* ``propeller``: the pusher's swept disc, its blades or nothing, as the fixed-wing's
  (:func:`csuas.drone_models.fixed_wing.pusher_propeller`); the disc's lowest point is the model's bottom.

References
----------
- D. P. Raymer, Aircraft Design: A Conceptual Approach, 6th ed., AIAA, 2018 (tailless and delta
  planforms, winglets).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from csuas.base.errors import ParameterError
from csuas.drone_models import parts as P
from csuas.drone_models.drone import Drone, Part
from csuas.drone_models.fixed_wing import (
    DEFAULT_FIXED_WING_MATERIALS,
    MOTOR_INSET_M,
    motor_and_pusher,
    slab,
    wing_panel,
)
from csuas.drone_models.materials import get_material
from csuas.drone_models.rotorcraft import PROPELLER_STYLES


@dataclass
class FlyingWingParams:
    """Geometry of a flying-wing delta, metres, +x forward, nose at x = 0, bottom at z = 0.

    Attributes
    ----------
    span_m, length_m, height_m : float
        Wingspan (tip to tip), overall length (nose to the propeller's rear face) and overall height
        (propeller disc bottom to winglet tops).
    fuselage_length_m, fuselage_diameter_m : float
        Pod fuselage (an ellipsoid of revolution about the x axis).
    root_chord_m, tip_chord_m : float
        Wing chord at the centre line and at the tips.
    wing_leading_edge_x_m : float
        x of the wing root's leading edge (negative: behind the nose).
    leading_edge_sweep_m : float
        Tip leading edge behind the root's [m]; ``root - tip chord`` gives a straight trailing edge.
    wing_thickness_ratio, dihedral_deg : float
        Slab thickness over the local chord [-] and dihedral [deg].
    winglet_root_chord_m, winglet_tip_chord_m, winglet_thickness_m : float
        The tip winglets (their height is what ``height_m`` leaves above the wing's plane).
    propeller_diameter_m, propeller_thickness_m, n_blades, blade_root_chord_m, blade_tip_chord_m,
    hub_diameter_m, blade_phase_deg
        The pusher propeller, as :class:`csuas.drone_models.fixed_wing.FixedWingParams`.
    motor_diameter_m, motor_length_m : float
        Motor behind the trailing edge, the propeller right behind it.
    motor_temperature_k : float or None
        Motor case temperature [K]; None: the material's.
    materials : dict
        Part kind -> material name (the fixed-wing's defaults).
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
    wing_leading_edge_x_m: float = -0.05
    leading_edge_sweep_m: float = 0.38
    wing_thickness_ratio: float = 0.08
    dihedral_deg: float = 0.0
    winglet_root_chord_m: float = 0.12
    winglet_tip_chord_m: float = 0.07
    winglet_thickness_m: float = 0.006
    propeller_thickness_m: float = 0.010
    n_blades: int = 2
    blade_root_chord_m: float = 0.022
    blade_tip_chord_m: float = 0.012
    hub_diameter_m: float = 0.020
    blade_phase_deg: float = 90.0
    motor_diameter_m: float = 0.028
    motor_length_m: float = 0.030
    motor_temperature_k: float | None = None
    materials: dict = field(default_factory=lambda: dict(DEFAULT_FIXED_WING_MATERIALS))
    sections: int = P.DEFAULT_SECTIONS


def trailing_edge_x(params: FlyingWingParams) -> float:
    """x of the root's trailing edge [m], where the motor is mounted."""
    return params.wing_leading_edge_x_m - params.root_chord_m


def _check(params: FlyingWingParams) -> None:
    """Refuse layouts whose parts would leave the stated box."""
    prop_r = params.propeller_diameter_m / 2.0
    lowest = max(2.0 * prop_r, prop_r + params.wing_thickness_ratio * params.root_chord_m / 2.0)
    if params.height_m <= lowest:
        raise ParameterError("height_m", params.height_m, f"> {lowest:.6g} m (winglets above the disc and the wing)")
    if prop_r >= params.span_m / 2.0:
        raise ParameterError("propeller_diameter_m", params.propeller_diameter_m, "< span_m")
    rear = -trailing_edge_x(params) - MOTOR_INSET_M + params.motor_length_m + params.propeller_thickness_m
    if abs(rear - params.length_m) > 1e-9 or params.fuselage_length_m >= rear:
        raise ParameterError(
            "length_m", params.length_m, f"{rear:.6g} m, nose to the propeller's rear face, longer than the pod"
        )
    if params.dihedral_deg != 0.0:
        raise ParameterError("dihedral_deg", params.dihedral_deg, "0 (the winglets stand on a flat wing)")


def build_flying_wing(
    name: str, params: FlyingWingParams, mass_kg: float, spec: dict | None = None, propellers: str = "disc"
) -> Drone:
    """Assemble a flying-wing delta (module docstring); the arguments of
    :func:`csuas.drone_models.fixed_wing.build_fixed_wing`.

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
    fus_c = np.array([-params.fuselage_length_m / 2.0, 0.0, axis_z])
    fus_d = params.fuselage_diameter_m
    parts = [Part("fuselage", "body", P.ellipsoid(fus_c, (params.fuselage_length_m, fus_d, fus_d)), mat["body"])]
    tip_front = params.wing_leading_edge_x_m - params.leading_edge_sweep_m
    for side, label in ((1, "left"), (-1, "right")):
        parts.append(Part(f"wing_{label}", "wing", wing_panel(params, side, axis_z), mat["wing"]))
        y = side * (params.span_m - params.winglet_thickness_m) / 2.0  # the winglet's outer face on the tip
        root = (tip_front, tip_front - params.winglet_root_chord_m, y, axis_z)
        top = (tip_front - params.winglet_root_chord_m + params.winglet_tip_chord_m, root[1], y, params.height_m)
        parts.append(Part(f"winglet_{label}", "tail", slab(root, top, params.winglet_thickness_m), mat["tail"]))
    motor_front = trailing_edge_x(params) + MOTOR_INSET_M
    parts += motor_and_pusher(params, mat, motor_front, axis_z, propellers)
    return Drone(name=name, mass_kg=float(mass_kg), parts=parts, spec=dict(spec or {}), propellers=propellers).centred()
