"""Procedural bird meshes with flapping wings: the confusers of engagements and imagery datasets.

Each class of ``defaults/birds.toml`` (pigeon, gull, raptor) becomes a :class:`~csuas.drone_models.Drone`
of five closed convex shells in the body frame (+x forward, +y left, +z up, metres), so that every
renderer and the exact silhouette code take a bird as they take a drone:

* ``body``: a prolate spheroid (the water-filled spheroid of Vaughn 1985), length 0.55 L and
  diameter D (``body_diameter_m``), centred at x = 0;
* ``head``: an ellipsoid 0.2 L long and 0.55 D wide, its centre 0.325 L ahead of the body's;
* ``tail``: a flat fan from inside the body's rear to the tail tip, 1.2 D wide at the tip;
* ``wing_left``, ``wing_right``: flat tapered plates (taper 0.5, mean chord W / A with A the
  ``wing_aspect_ratio``) hinged inside the body at y = +-0.3 D, z = 0.15 D, 0.1 L ahead of its centre.

Head front to tail tip is the ``body_length_m`` L of the class (Svensson et al. measure birds bill to
tail), and with the wings level their tips lie at y = +-W / 2, the ``wingspan_m`` W. The wings flap
about their hinges through the angle

    theta(phase) = A_s cos(2 pi phase)        (A_s: ``wing_stroke_amplitude_deg``)

with the wingbeat phase in cycles: 0 the top of the stroke, 0.25 mid-downstroke (wings level),
0.5 the bottom, 0.75 mid-upstroke (level again). Time t gives phase = f t with f the ``wingbeat_hz``.
The model is placed so that its mid-stroke bounding box is centred on the origin at every phase
(the body does not move as the wings beat). Every part is plumage (``plumage``, drone_models/materials.py:
LWIR emissivity 0.95) at the ambient temperature plus ``surface_temperature_excess_k``.

References
----------
- C. R. Vaughn, "Birds and insects as radar targets: a review", Proc. IEEE 73(2), 1985.
- L. Svensson et al., Collins Bird Guide, 2nd ed., 2010 (length bill to tail, wingspan).
- C. J. Pennycuick, Modelling the Flying Bird, Academic Press, 2008 (wingbeat frequency).
"""

from __future__ import annotations

import numpy as np
import trimesh

from csuas.base.errors import ParameterError
from csuas.defaults import load_birds
from csuas.drone_models import parts as P
from csuas.drone_models.drone import Drone, Part
from csuas.drone_models.materials import T_SUAS_K, get_material

#: Fractions of the bird's length L: body (torso) length, head length, head centre ahead of the body's,
#: wing hinge ahead of the body's centre.
BODY_LENGTH_FRACTION, HEAD_LENGTH_FRACTION, HEAD_AHEAD_FRACTION, HINGE_AHEAD_FRACTION = 0.55, 0.2, 0.325, 0.1
#: Fractions of the body diameter D: head width, tail root and tip width, hinge offsets in y and z.
HEAD_WIDTH_FRACTION, TAIL_ROOT_FRACTION, TAIL_TIP_FRACTION = 0.55, 0.5, 1.2
HINGE_Y_FRACTION, HINGE_Z_FRACTION = 0.3, 0.15
#: Wing tip chord over root chord; wing and tail thickness over the root chord and the length.
WING_TAPER, WING_THICKNESS_FRACTION, TAIL_THICKNESS_FRACTION = 0.5, 0.05, 0.015
#: Wingbeat phase of level wings on the downstroke [cycles]: the mid-stroke the span is measured at.
MID_STROKE_PHASE = 0.25


def list_birds() -> dict:
    """Bird class -> one-line description (``defaults/birds.toml``)."""
    return {name: entry["description"] for name, entry in load_birds().items()}


def bird_class(name: str) -> dict:
    """The figures of one bird class of ``defaults/birds.toml``."""
    birds = load_birds()
    if name not in birds:
        raise ParameterError("bird", name, ", ".join(birds))
    return birds[name]


def wing_angle_deg(stroke_amplitude_deg: float, wingbeat_phase) -> np.ndarray:
    """Flapping angle of the wings above level [deg]: A_s cos(2 pi phase) (module docstring).

    Parameters
    ----------
    stroke_amplitude_deg : float
        Half-amplitude of the stroke [deg], 0..90.
    wingbeat_phase : float or array_like
        Phase in the wingbeat cycle [cycles], finite (0: top of the stroke, 0.25: level).
    """
    phase = np.asarray(wingbeat_phase, dtype=float)
    if not np.all(np.isfinite(phase)):
        raise ParameterError("wingbeat_phase", wingbeat_phase, "finite [cycles]")
    if not 0.0 <= stroke_amplitude_deg <= 90.0:
        raise ParameterError("wing_stroke_amplitude_deg", stroke_amplitude_deg, "0..90 [deg]")
    return stroke_amplitude_deg * np.cos(2.0 * np.pi * phase)


def _wing(bird: dict, side: int, angle_deg: float) -> trimesh.Trimesh:
    """One wing (side +1 left, -1 right): a tapered plate from the hinge to the tip, raised by the angle."""
    length, span, diameter = bird["body_length_m"], bird["wingspan_m"], bird["body_diameter_m"]
    hinge = np.array([HINGE_AHEAD_FRACTION * length, side * HINGE_Y_FRACTION * diameter, HINGE_Z_FRACTION * diameter])
    reach = span / 2.0 - HINGE_Y_FRACTION * diameter  # hinge to tip
    mean_chord = span / bird["wing_aspect_ratio"]
    root = 2.0 * mean_chord / (1.0 + WING_TAPER)
    tip = WING_TAPER * root
    half_t = WING_THICKNESS_FRACTION * root / 2.0
    # planform in the wing's own frame: x along the body, s outward from the hinge; leading edge 0.4 chord ahead
    outline = [(0.4 * root, 0.0), (-0.6 * root, 0.0), (0.4 * tip, reach), (-0.6 * tip, reach)]
    theta = np.radians(angle_deg)
    spanwise = np.array([0.0, side * np.cos(theta), np.sin(theta)])
    normal = np.array([0.0, -side * np.sin(theta), np.cos(theta)])
    points = [hinge + [x, 0.0, 0.0] + s * spanwise + t * normal for x, s in outline for t in (-half_t, half_t)]
    return trimesh.convex.convex_hull(np.array(points))


def _tail(bird: dict) -> trimesh.Trimesh:
    """A flat fan from inside the body's rear to the tail tip, L from the head's front."""
    length, diameter = bird["body_length_m"], bird["body_diameter_m"]
    head_front = (HEAD_AHEAD_FRACTION + HEAD_LENGTH_FRACTION / 2.0) * length
    root_x, tip_x = -0.4 * BODY_LENGTH_FRACTION * length, head_front - length
    half_t = TAIL_THICKNESS_FRACTION * length / 2.0
    corners = [
        (x, side * width / 2.0, z)
        for x, width in ((root_x, TAIL_ROOT_FRACTION * diameter), (tip_x, TAIL_TIP_FRACTION * diameter))
        for side in (-1, 1)
        for z in (-half_t, half_t)
    ]
    return trimesh.convex.convex_hull(np.array(corners))


def build_bird(name: str, wingbeat_phase: float = MID_STROKE_PHASE, ambient_k: float = T_SUAS_K) -> Drone:
    """A bird of a ``defaults/birds.toml`` class at a phase of its wingbeat (module docstring).

    Parameters
    ----------
    name : str
        Bird class (:func:`list_birds`).
    wingbeat_phase : float
        Phase in the wingbeat [cycles]: 0 top of the stroke, 0.25 level (default), 0.5 bottom.
    ambient_k : float
        Ambient air temperature [K], > 0; the plumage is ``surface_temperature_excess_k`` warmer.

    Returns
    -------
    Drone
        Parts ``body``, ``head``, ``tail``, ``wing_left``, ``wing_right`` (kinds body, head, tail,
        wing), mass from the class, ``spec`` the class's figures, ``propellers`` "none".
    """
    bird = bird_class(name)
    if not (np.isfinite(ambient_k) and ambient_k > 0.0):
        raise ParameterError("ambient_k", ambient_k, "> 0 [K], finite")
    angle = float(wing_angle_deg(bird["wing_stroke_amplitude_deg"], wingbeat_phase))
    length, diameter = bird["body_length_m"], bird["body_diameter_m"]
    head_width = HEAD_WIDTH_FRACTION * diameter
    shells = {
        "body": P.ellipsoid((0.0, 0.0, 0.0), (BODY_LENGTH_FRACTION * length, diameter, diameter)),
        "head": P.ellipsoid(
            (HEAD_AHEAD_FRACTION * length, 0.0, 0.0), (HEAD_LENGTH_FRACTION * length, head_width, head_width)
        ),
        "tail": _tail(bird),
        "wing_left": _wing(bird, 1, angle),
        "wing_right": _wing(bird, -1, angle),
    }
    material = get_material(bird["plumage"]).with_temperature(ambient_k + bird["surface_temperature_excess_k"])
    kinds = {"body": "body", "head": "head", "tail": "tail", "wing_left": "wing", "wing_right": "wing"}
    parts = [Part(part, kinds[part], mesh, material) for part, mesh in shells.items()]
    head_front = (HEAD_AHEAD_FRACTION + HEAD_LENGTH_FRACTION / 2.0) * length
    spec = {**bird, "wingbeat_phase": float(wingbeat_phase), "wing_angle_deg": angle, "source": "defaults/birds.toml"}
    drone = Drone(name, bird["mass_kg"], parts, spec, propellers="none")
    return drone.translated((length / 2.0 - head_front, 0.0, 0.0))  # mid-stroke box centred on the origin
