"""What every rotorcraft builder shares: the propeller styles, a rotor's mesh and the assembly.

The multirotor (:mod:`csuas.drone_models.multirotor`) and the single-rotor helicopter
(:mod:`csuas.drone_models.helicopter`) differ in their airframes; both resolve part materials
over their defaults, draw rotors as a swept disc or as blades, and return a :class:`Drone`
centred on its bounding box, here.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from csuas.base.errors import ParameterError
from csuas.drone_models import parts as P
from csuas.drone_models.drone import Drone, Part
from csuas.drone_models.materials import Material, get_material

#: Accepted propeller representations.
PROPELLER_STYLES = ("disc", "blades", "none")


@dataclass(frozen=True)
class BladePlan:
    """Plan form of a rotor's blades (style ``"blades"``).

    Attributes
    ----------
    n_blades : int
        Blades per rotor.
    root_chord_m, tip_chord_m : float
        Blade chord at the root and at the tip [m].
    hub_diameter_m : float
        Hub diameter [m].
    phase_deg : float
        Azimuth of the first blade [deg].
    """

    n_blades: int
    root_chord_m: float
    tip_chord_m: float
    hub_diameter_m: float
    phase_deg: float

    @classmethod
    def of(cls, params) -> BladePlan:
        """The plan form of a builder's parameters.

        ``params`` has ``n_blades``, ``blade_root_chord_m``, ``blade_tip_chord_m``, ``hub_diameter_m``
        and ``blade_phase_deg`` (:class:`MultirotorParams`, :class:`HelicopterParams`).
        """
        return cls(
            params.n_blades,
            params.blade_root_chord_m,
            params.blade_tip_chord_m,
            params.hub_diameter_m,
            params.blade_phase_deg,
        )


def rotor_mesh(hub, diameter_m: float, thickness_m: float, style: str, blades: BladePlan, sections: int):
    """A horizontal rotor at ``hub`` as a swept disc or as blades (``style`` "disc" or "blades").

    ``thickness_m`` is the swept disc's thickness, or twice the blades' thickness.
    """
    if style == "disc":
        return P.vertical_disc(hub, diameter_m, thickness_m, sections)
    return P.propeller_blades(
        hub,
        diameter_m,
        blades.n_blades,
        blades.root_chord_m,
        blades.tip_chord_m,
        thickness_m / 2.0,
        blades.hub_diameter_m,
        blades.phase_deg,
    )


def build_rotorcraft(
    name: str,
    mass_kg: float,
    materials: dict[str, str],
    airframe: Callable[[dict[str, Material]], list[Part]],
    spec: dict | None = None,
    propellers: str = "disc",
    internals: Callable[[dict[str, Material]], list[Part]] | None = None,
) -> Drone:
    """Assemble a rotorcraft: check the propeller style, resolve materials, build and centre its parts.

    Parameters
    ----------
    name : str
        Model name.
    mass_kg : float
        Take-off mass [kg].
    materials : dict
        Part kind -> material name (the builder's defaults updated with the user's).
    airframe : callable
        Part kind -> :class:`Material` mapping -> the drone's parts (the builder's geometry).
    spec : dict, optional
        Published figures, stored on the result.
    propellers : {"disc", "blades", "none"}
        Representation of the rotors.
    internals : callable, optional
        Part kind -> :class:`Material` mapping -> the parts inside the airframe
        (:attr:`Drone.internal_parts`, seen by the radar only).

    Returns
    -------
    Drone
        Centred on its bounding box.
    """
    if propellers not in PROPELLER_STYLES:
        raise ParameterError("propellers", propellers, ", ".join(PROPELLER_STYLES))
    resolved = {kind: get_material(material) for kind, material in materials.items()}
    parts = airframe(resolved)
    inside = internals(resolved) if internals is not None else []
    return Drone(
        name=name,
        mass_kg=float(mass_kg),
        parts=parts,
        spec=dict(spec or {}),
        propellers=propellers,
        internal_parts=inside,
    ).centred()
