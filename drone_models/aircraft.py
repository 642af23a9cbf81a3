"""A procedural light aircraft (Cessna 172-like high-wing single): a confuser of imagery datasets at distance.

Closed convex shells in the body frame (+x forward, +y left, +z up, metres), so that the renderers and
the exact silhouette code take it as they take a drone:

* ``fuselage``: an ellipsoid of the overall length L and a cabin of width 1.1 m and height 1.5 m;
* ``wing``: a flat plate of the span b and a constant chord c = S / b (S the wing area), on top of the
  cabin (high wing), its quarter chord 0.3 L behind the nose;
* ``tailplane``: a flat plate of span 3.4 m and chord 1.1 m at the tail;
* ``fin``: a vertical plate from the tail cone to the overall height H above the wheels' contact plane;
* ``gear``: three struts to the wheels (a box each), so that the overall height holds.

Dimensions (Cessna 172S Skyhawk, Pilot's Operating Handbook, Section 1 "Descriptive data" and
the three-view drawing, Textron Aviation 2007): overall length 8.28 m, wing span 11.0 m, overall
height 2.72 m, wing area 16.2 m^2; horizontal tail span 3.4 m (three-view). Skin: white paint
(``paint`` reflectance scaled to 0.8, emissivity 0.875) at the ambient temperature (no engine plume:
the exhaust, a few per cent of the silhouette, is left out and stated).

References
----------
- Cessna Aircraft Company, Model 172S Pilot's Operating Handbook, 2007, Section 1.
"""

from __future__ import annotations

import dataclasses

from csuas.drone_models import parts as P
from csuas.drone_models.drone import Drone, Part
from csuas.drone_models.materials import T_SUAS_K, get_material

#: Published dimensions of the Cessna 172S [m] and [m^2] (module docstring).
LENGTH_M, SPAN_M, HEIGHT_M, WING_AREA_M2 = 8.28, 11.0, 2.72, 16.2
#: Tailplane span and chord, cabin width and height [m] (three-view drawing, rounded).
TAIL_SPAN_M, TAIL_CHORD_M, CABIN_WIDTH_M, CABIN_HEIGHT_M = 3.4, 1.1, 1.1, 1.5
#: Visible reflectance of white aircraft paint (assumption: fresh white enamel 0.7-0.85).
WHITE_REFLECTANCE = 0.8
#: Wheel height below the fuselage's lowest point [m], chosen so that the overall height is HEIGHT_M.
GEAR_DROP_M = 0.45


def build_light_aircraft(ambient_k: float = T_SUAS_K) -> Drone:
    """The Cessna 172-like light aircraft (module docstring), centred on its bounding box.

    Parameters
    ----------
    ambient_k : float
        Skin temperature [K] (the ambient air's).

    Returns
    -------
    Drone
        Parts ``fuselage``, ``wing``, ``tailplane``, ``fin``, ``gear_*``; ``propellers`` "none".
    """
    chord = WING_AREA_M2 / SPAN_M
    nose_x = LENGTH_M / 2.0
    wing_x = nose_x - 0.3 * LENGTH_M + chord / 4.0  # quarter chord 0.3 L behind the nose
    wing_z = CABIN_HEIGHT_M / 2.0 + 0.05
    tail_x = -nose_x + TAIL_CHORD_M / 2.0
    bottom_z = -CABIN_HEIGHT_M / 2.0 - GEAR_DROP_M
    fin_top = bottom_z + HEIGHT_M
    shells = {
        "fuselage": P.ellipsoid((0.0, 0.0, 0.0), (LENGTH_M, CABIN_WIDTH_M, CABIN_HEIGHT_M)),
        "wing": P.box((wing_x, 0.0, wing_z), (chord, SPAN_M, 0.12)),
        "tailplane": P.box((tail_x, 0.0, 0.1), (TAIL_CHORD_M, TAIL_SPAN_M, 0.06)),
        "fin": P.box((tail_x, 0.0, (0.1 + fin_top) / 2.0), (TAIL_CHORD_M, 0.08, fin_top - 0.1)),
        "gear_nose": P.box((nose_x - 1.2, 0.0, bottom_z + 0.35), (0.15, 0.15, 0.7)),
        "gear_left": P.box((wing_x - 0.8, 1.2, bottom_z + 0.35), (0.15, 0.15, 0.7)),
        "gear_right": P.box((wing_x - 0.8, -1.2, bottom_z + 0.35), (0.15, 0.15, 0.7)),
    }
    paint = get_material("paint")
    white = dataclasses.replace(
        paint, name="white_paint", reflectance_rgb=(WHITE_REFLECTANCE,) * 3, reflectance_550nm=WHITE_REFLECTANCE
    ).with_temperature(ambient_k)
    kinds = {name: "gear" if name.startswith("gear") else "body" for name in shells}
    parts = [Part(name, kinds[name], mesh, white) for name, mesh in shells.items()]
    spec = {
        "length_m": LENGTH_M,
        "wingspan_m": SPAN_M,
        "height_m": HEIGHT_M,
        "wing_area_m2": WING_AREA_M2,
        "source": "Cessna 172S Pilot's Operating Handbook, Section 1",
    }
    return Drone("light_aircraft", 1111.0, parts, spec, propellers="none").centred()
