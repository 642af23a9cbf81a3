"""Drone presets built from published specifications.

Each preset states the published figures it is built from (``spec``), then
derives the part layout from them so that the model's bounding box matches
the specification by construction; the remaining details (body shell,
motors, legs) are plausible estimates from photographs, marked as such.

* ``dji_mini_4_pro``: the paper's default class-1 sUAS (Table 8, [49]). DJI
  specification: folded (without propellers) 148 x 94 x 64 mm, unfolded
  (with propellers) 298 x 373 x 101 mm (length x width x height), take-off
  weight < 249 g. Propeller diameter 6 in (152.4 mm) is an estimate (the
  6030-class propellers of the Mini series); with it the rotor axes sit at
  x = +-72.8 mm, y = +-110.3 mm so that the discs touch the specified box.
* ``dji_mavic_3``: a larger class-1 quadcopter. DJI specification: folded
  (without propellers) 221 x 96.3 x 90.3 mm, unfolded (without propellers)
  347.5 x 283 x 107.7 mm, take-off weight 895 g; 9453F propellers
  (9.4 in = 238.8 mm). The motors touch the specified box without propellers.
* ``black_hornet_3``: nano helicopter of Table 52 (Teledyne FLIR [196]):
  33 g, main rotor 123 mm, about 168 mm long. Its overall height is not in
  the paper; 25 mm (fuselage plus rotor head) is assumed, the value that
  Table 52's d_crit = 0.025 m implies for the minimum method.
* ``euclid_class_fixed_wing``: a 2 m-span electric pusher fixed-wing in the class of the Euclid UAV
  of Kapoulas et al., Drones 7(1):39, 2023 (the abstract's 2 m wingspan is the one published figure
  used). Assumed, in the class of 2 m twin-boom pusher UAVs: length 1.20 m, height 0.40 m (pusher
  disc bottom to fin tips), take-off mass 5 kg, 14-inch (355.6 mm) pusher propeller, wing chords
  0.28 / 0.16 m (aspect ratio 9.1), dihedral 3 deg; black-anodised motor bell 30 K above T_sUAS in
  flight (brushless outrunner at cruise power, assumption). Built by
  :func:`csuas.drone_models.fixed_wing.build_fixed_wing`.
* ``small_delta_wing``: a 1 m-span flying-wing delta, 1 kg, in the class of the foam flying wings flown as
  small fixed-wing drones; no product is modelled and every figure is an assumption: length 0.585 m
  (nose to the pusher's rear face), height 0.22 m (disc bottom to winglet tops), root / tip chord
  0.50 / 0.12 m with a straight trailing edge (leading edge swept 0.38 m, about 37 deg), 8 % thick,
  8-inch (203.2 mm) two-blade pusher on the trailing edge, 0.36 m pod, tip winglets 0.12 m tall; the
  motor bell 30 K above T_sUAS in flight as the fixed-wing's. Built by
  :func:`csuas.drone_models.flying_wing.build_flying_wing`.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

from csuas.base.errors import ParameterError
from csuas.drone_models.birds import build_bird, list_birds
from csuas.drone_models.fixed_wing import FixedWingParams, build_fixed_wing
from csuas.drone_models.flying_wing import FlyingWingParams, build_flying_wing
from csuas.drone_models.helicopter import HelicopterParams, build_helicopter
from csuas.drone_models.materials import T_SUAS_K
from csuas.drone_models.multirotor import MultirotorParams, build_multirotor

if TYPE_CHECKING:
    from csuas.drone_models.drone import Drone

INCH_M = 0.0254
#: Options of a bird built through :func:`build_drone`.
BIRD_OPTIONS = ("wingbeat_phase", "ambient_k")


def _mini_4_pro():
    spec = {
        "unfolded_with_propellers_m": (0.298, 0.373, 0.101),
        "folded_without_propellers_m": (0.148, 0.094, 0.064),
        "mass_kg": 0.249,
        "propeller_diameter_m": 6.0 * INCH_M,
        "source": "DJI Mini 4 Pro specifications (dji.com), paper Table 8 [49]",
    }
    length, width, height = spec["unfolded_with_propellers_m"]
    prop_d = spec["propeller_diameter_m"]
    motor_x, motor_y = (length - prop_d) / 2.0, (width - prop_d) / 2.0  # rotor discs touch the bounding box
    motor_h, gap, prop_t = 0.016, 0.002, 0.006
    front_base = height - prop_t - gap - motor_h  # front propellers reach the top of the box
    rear_base = 0.010  # rear arms fold down (estimate)
    params = MultirotorParams(
        body_extents_m=(0.125, 0.085, 0.050),
        body_center_m=(0.0, 0.0, 0.040),
        body_corner_radius_m=0.012,
        rotor_positions_m=(
            (motor_x, motor_y, front_base),
            (motor_x, -motor_y, front_base),
            (-motor_x, motor_y, rear_base),
            (-motor_x, -motor_y, rear_base),
        ),
        propeller_diameter_m=prop_d,
        propeller_thickness_m=prop_t,
        propeller_gap_m=gap,
        motor_diameter_m=0.020,
        motor_height_m=motor_h,
        arm_width_m=0.014,
        arm_thickness_m=0.008,
        gimbal_extents_m=(0.030, 0.036, 0.032),
        gimbal_center_m=(0.075, 0.0, 0.034),
        lens_diameter_m=0.014,
        lens_length_m=0.006,
        landing_legs_m=(
            ((0.045, 0.030, 0.016), (0.045, 0.030, 0.0)),
            ((0.045, -0.030, 0.016), (0.045, -0.030, 0.0)),
            ((-motor_x, motor_y, rear_base), (-motor_x, motor_y, 0.0)),
            ((-motor_x, -motor_y, rear_base), (-motor_x, -motor_y, 0.0)),
        ),
        leg_radius_m=0.003,
        battery_extents_m=(0.014, 0.062, 0.034),
        battery_center_m=(-0.066, 0.0, 0.040),
        flight_controller_extents_m=(0.070, 0.045),
        flight_controller_center_m=(0.0, 0.0, 0.050),
    )
    return build_multirotor, params, spec


def _mavic_3():
    spec = {
        "unfolded_without_propellers_m": (0.3475, 0.283, 0.1077),
        "folded_without_propellers_m": (0.221, 0.0963, 0.0903),
        "mass_kg": 0.895,
        "propeller_diameter_m": 9.4 * INCH_M,
        "source": "DJI Mavic 3 specifications (dji.com)",
    }
    length, width, height = spec["unfolded_without_propellers_m"]
    motor_d, motor_h = 0.034, 0.022
    motor_x, motor_y = (length - motor_d) / 2.0, (width - motor_d) / 2.0  # motors touch the box without propellers
    front_base, rear_base = height - motor_h, 0.045
    params = MultirotorParams(
        body_extents_m=(0.190, 0.096, 0.075),
        body_center_m=(0.0, 0.0, 0.0575),
        body_corner_radius_m=0.015,
        rotor_positions_m=(
            (motor_x, motor_y, front_base),
            (motor_x, -motor_y, front_base),
            (-motor_x, motor_y, rear_base),
            (-motor_x, -motor_y, rear_base),
        ),
        propeller_diameter_m=spec["propeller_diameter_m"],
        propeller_thickness_m=0.008,
        propeller_gap_m=0.003,
        motor_diameter_m=motor_d,
        motor_height_m=motor_h,
        arm_width_m=0.020,
        arm_thickness_m=0.012,
        n_blades=2,
        blade_root_chord_m=0.026,
        blade_tip_chord_m=0.014,
        hub_diameter_m=0.016,
        gimbal_extents_m=(0.045, 0.050, 0.045),
        gimbal_center_m=(0.113, 0.0, 0.050),
        lens_diameter_m=0.026,
        lens_length_m=0.008,
        landing_legs_m=(
            ((motor_x, motor_y, front_base), (motor_x, motor_y, 0.0)),
            ((motor_x, -motor_y, front_base), (motor_x, -motor_y, 0.0)),
            ((-0.070, 0.030, 0.020), (-0.070, 0.030, 0.0)),
            ((-0.070, -0.030, 0.020), (-0.070, -0.030, 0.0)),
        ),
        leg_radius_m=0.004,
        battery_extents_m=(0.020, 0.070, 0.050),
        battery_center_m=(-0.095, 0.0, 0.060),
        flight_controller_extents_m=(0.100, 0.055),
        flight_controller_center_m=(0.0, 0.0, 0.072),
    )
    return build_multirotor, params, spec


def _black_hornet_3():
    spec = {
        "length_m": 0.168,
        "main_rotor_diameter_m": 0.123,
        "height_m": 0.025,
        "mass_kg": 0.033,
        "source": "paper Section 4.9.4 and Table 52 (Teledyne FLIR Black Hornet 3 [196]); "
        "height 25 mm assumed (consistent with Table 52 d_crit = 0.025 m)",
    }
    rotor_r = spec["main_rotor_diameter_m"] / 2.0
    rotor_t = 0.003
    nose_x = rotor_r  # fuselage nose under the front rotor tip
    fus_len = 0.105
    tail_rotor_d = 0.020
    tail_x = nose_x - spec["length_m"] + tail_rotor_d / 2.0  # tail rotor tip at the rear of the box
    params = HelicopterParams(
        fuselage_extents_m=(fus_len, 0.022, 0.016),
        fuselage_center_m=(nose_x - fus_len / 2.0, 0.0, 0.008),
        main_rotor_diameter_m=spec["main_rotor_diameter_m"],
        main_rotor_thickness_m=rotor_t,
        main_rotor_center_m=(0.0, 0.0, spec["height_m"] - rotor_t / 2.0),
        tail_boom_end_m=(tail_x, 0.0, 0.010),
        tail_boom_diameter_m=0.004,
        tail_rotor_diameter_m=tail_rotor_d,
        tail_rotor_thickness_m=0.002,
        camera_extents_m=(0.012, 0.010, 0.008),
        camera_center_m=(nose_x - 0.008, 0.0, 0.005),
    )
    return build_helicopter, params, spec


#: Motor case temperature above T_sUAS of the fixed-wing preset in flight [K] (assumption, module docstring).
FIXED_WING_MOTOR_EXCESS_K = 30.0


def _euclid_class_fixed_wing():
    spec = {
        "span_m": 2.0,
        "length_m": 1.20,
        "height_m": 0.40,
        "mass_kg": 5.0,
        "propeller_diameter_m": 14.0 * INCH_M,
        "motor_excess_k": FIXED_WING_MOTOR_EXCESS_K,
        "source": "span 2 m: Kapoulas et al., Drones 7(1):39, 2023 (Euclid UAV); length, height, mass, "
        "propeller and motor heat assumed for a 2 m electric pusher (drone_models/presets.py)",
    }
    params = FixedWingParams(
        span_m=spec["span_m"],
        length_m=spec["length_m"],
        height_m=spec["height_m"],
        fuselage_length_m=0.70,
        fuselage_diameter_m=0.14,
        root_chord_m=0.28,
        tip_chord_m=0.16,
        propeller_diameter_m=spec["propeller_diameter_m"],
        motor_temperature_k=T_SUAS_K + FIXED_WING_MOTOR_EXCESS_K,
    )
    return build_fixed_wing, params, spec


def _small_delta_wing():
    spec = {
        "span_m": 1.0,
        "length_m": 0.585,
        "height_m": 0.22,
        "mass_kg": 1.0,
        "propeller_diameter_m": 8.0 * INCH_M,
        "motor_excess_k": FIXED_WING_MOTOR_EXCESS_K,
        "source": "assumed 1 m-span flying-wing delta (no product modelled): span, length, height, mass, "
        "chords, propeller and motor heat stated in drone_models/presets.py",
    }
    params = FlyingWingParams(
        span_m=spec["span_m"],
        length_m=spec["length_m"],
        height_m=spec["height_m"],
        fuselage_length_m=0.36,
        fuselage_diameter_m=0.07,
        root_chord_m=0.50,
        tip_chord_m=0.12,
        propeller_diameter_m=spec["propeller_diameter_m"],
        motor_temperature_k=T_SUAS_K + FIXED_WING_MOTOR_EXCESS_K,
    )
    return build_flying_wing, params, spec


_PRESETS = {
    "dji_mini_4_pro": (_mini_4_pro, "DJI Mini 4 Pro, 249 g class-1 quadcopter (paper default, Table 8)"),
    "dji_mavic_3": (_mavic_3, "DJI Mavic 3, 895 g class-1 quadcopter"),
    "black_hornet_3": (_black_hornet_3, "Teledyne FLIR Black Hornet 3, 33 g nano helicopter (Table 52)"),
    "euclid_class_fixed_wing": (
        _euclid_class_fixed_wing,
        "2 m-span electric pusher fixed-wing, 5 kg, in the class of the Euclid UAV (Drones 7(1):39, 2023)",
    ),
    "small_delta_wing": (_small_delta_wing, "1 m-span flying-wing delta with a pusher propeller, 1 kg (assumed)"),
}


def list_presets() -> dict:
    """Preset name -> one-line description."""
    return {name: text for name, (_, text) in _PRESETS.items()}


def preset_parameters(preset: str):
    """``(builder, params, spec)`` of a preset: its generator, geometry dataclass and published figures."""
    try:
        return _PRESETS[preset][0]()
    except (KeyError, TypeError):
        raise ParameterError("preset", preset, ", ".join([*_PRESETS, *list_birds()])) from None


def build_drone(preset: str, propellers: str = "disc", **overrides) -> Drone:
    """Build a preset drone, optionally with some geometry parameters changed.

    Parameters
    ----------
    preset : str
        One of :func:`list_presets`, or a bird class of
        :func:`csuas.drone_models.birds.list_birds` (built by
        :func:`~csuas.drone_models.birds.build_bird`; ``propellers`` does not apply).
    propellers : {"disc", "blades", "none"}
        Propellers as swept discs (default; the specification's envelope),
        as blades, or left out.
    **overrides
        Fields of the preset's :class:`~csuas.drone_models.multirotor.MultirotorParams`,
        :class:`~csuas.drone_models.helicopter.HelicopterParams`,
        :class:`~csuas.drone_models.fixed_wing.FixedWingParams` or
        :class:`~csuas.drone_models.flying_wing.FlyingWingParams`, e.g.
        ``blade_phase_deg=30`` or ``materials={"body": "plastic"}`` (merged
        with the preset's materials); for a bird ``wingbeat_phase`` and ``ambient_k``.

    Raises
    ------
    ParameterError
        For an unknown preset, propeller style or parameter name.
    """
    if preset in list_birds():  # a bird class: no propellers; overrides are build_bird's options
        unknown = sorted(set(overrides) - set(BIRD_OPTIONS))
        if unknown:
            raise ParameterError("parameter", unknown[0], ", ".join(BIRD_OPTIONS))
        return build_bird(preset, **overrides)
    builder, params, spec = preset_parameters(preset)
    names = {f.name for f in dataclasses.fields(params)}
    for key in overrides:
        if key not in names:
            raise ParameterError("parameter", key, ", ".join(sorted(names)))
    if "materials" in overrides:
        overrides = {**overrides, "materials": {**params.materials, **overrides["materials"]}}
    return builder(preset, dataclasses.replace(params, **overrides), spec["mass_kg"], spec, propellers)
