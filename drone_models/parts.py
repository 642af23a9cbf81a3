"""Watertight solid primitives from which drone parts are assembled.

Every function returns a :class:`trimesh.Trimesh` in metres that is a closed,
consistently wound surface. Most are single convex solids; compound parts
(propeller blades with a hub, a gimbal with its lens) are concatenations of
closed convex shells, which keeps every shell watertight and lets the
silhouette code use the exact convex-hull shortcut per shell
(:mod:`csuas.drone_models.silhouette`). Shells may overlap; no boolean union
is performed.
"""

from __future__ import annotations

import numpy as np
import trimesh

from csuas.base.errors import ParameterError

#: Facets around a full circle for round parts (motors, discs, tubes).
DEFAULT_SECTIONS = 48


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not (np.isfinite(value) and value > 0.0):
        raise ParameterError(name, value, "finite, > 0")
    return value


def _point(name: str, value) -> np.ndarray:
    p = np.asarray(value, dtype=float)
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        raise ParameterError(name, value, "three finite coordinates [m]")
    return p


def box(center, extents) -> trimesh.Trimesh:
    """Axis-aligned box.

    Parameters
    ----------
    center : array_like, shape (3,)
        Centre [m].
    extents : array_like, shape (3,)
        Edge lengths along x, y, z [m], each > 0.
    """
    ext = [_positive(f"extents[{i}]", e) for i, e in enumerate(extents)]
    transform = trimesh.transformations.translation_matrix(_point("center", center))
    return trimesh.creation.box(extents=ext, transform=transform)


def rounded_box(center, extents, corner_radius, subdivisions: int = 2) -> trimesh.Trimesh:
    """Convex box with rounded edges and corners (a body shell).

    Built as the convex hull of eight spheres of radius ``corner_radius``
    placed inside the corners, so the outer extents are exactly ``extents``.

    Parameters
    ----------
    center : array_like, shape (3,)
        Centre [m].
    extents : array_like, shape (3,)
        Overall length, width, height [m].
    corner_radius : float
        Rounding radius [m], ``0 < r <= min(extents) / 2``.
    subdivisions : int
        Icosphere subdivision level of the corner spheres (2 -> 162 points each).
    """
    ext = np.array([_positive(f"extents[{i}]", e) for i, e in enumerate(extents)])
    r = _positive("corner_radius", corner_radius)
    if r > ext.min() / 2.0:
        raise ParameterError("corner_radius", r, f"0 < x <= {ext.min() / 2.0:.6g} m (half the smallest extent)")
    # the six axis points make the outer extents exact whatever the icosphere's orientation
    sphere = np.concatenate(
        [
            trimesh.creation.icosphere(subdivisions=subdivisions, radius=r).vertices,
            r * np.concatenate([np.eye(3), -np.eye(3)]),
        ]
    )
    half = ext / 2.0 - r
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
    points = (corners[:, None, :] + sphere[None, :, :]).reshape(-1, 3) + _point("center", center)
    return trimesh.convex.convex_hull(points)


def ellipsoid(center, extents, subdivisions: int = 3) -> trimesh.Trimesh:
    """Convex ellipsoid with full axes ``extents`` along x, y, z [m] (a fuselage)."""
    ext = np.array([_positive(f"extents[{i}]", e) for i, e in enumerate(extents)])
    mesh = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
    mesh.apply_scale(ext / 2.0)
    mesh.apply_translation(_point("center", center))
    return mesh


def cylinder_between(start, end, radius, sections: int = DEFAULT_SECTIONS) -> trimesh.Trimesh:
    """Closed cylinder (prism with a regular ``sections``-gon) from ``start`` to ``end``.

    Parameters
    ----------
    start, end : array_like, shape (3,)
        Centres of the two end caps [m]; must differ.
    radius : float
        Circumradius of the cross-section polygon [m].
    sections : int
        Number of facets around the axis.
    """
    p0, p1 = _point("start", start), _point("end", end)
    if np.linalg.norm(p1 - p0) <= 0.0:
        raise ParameterError("end", end.tolist() if hasattr(end, "tolist") else end, "a point different from start")
    return trimesh.creation.cylinder(
        radius=_positive("radius", radius), segment=np.stack([p0, p1]), sections=int(sections)
    )


def vertical_disc(center, diameter, thickness, sections: int = DEFAULT_SECTIONS) -> trimesh.Trimesh:
    """Thin disc with a vertical (z) axis centred at ``center``: a spinning rotor's swept disc."""
    c = _point("center", center)
    half = np.array([0.0, 0.0, _positive("thickness", thickness) / 2.0])
    return cylinder_between(c - half, c + half, _positive("diameter", diameter) / 2.0, sections)


def bar_between(start, end, width, thickness) -> trimesh.Trimesh:
    """Rectangular bar (a flat arm) from ``start`` to ``end``.

    The bar's width lies in the horizontal plane, perpendicular to its axis;
    its thickness is perpendicular to both. The axis must not be vertical.

    Parameters
    ----------
    start, end : array_like, shape (3,)
        Centres of the two end faces [m].
    width, thickness : float
        Cross-section [m].
    """
    p0, p1 = _point("start", start), _point("end", end)
    axis = p1 - p0
    length = float(np.linalg.norm(axis))
    if length <= 0.0:
        raise ParameterError("end", list(p1), "a point different from start")
    ax = axis / length
    side = np.cross([0.0, 0.0, 1.0], ax)
    if np.linalg.norm(side) < 1e-9:
        raise ParameterError("bar axis", list(ax), "not vertical")
    side /= np.linalg.norm(side)
    up = np.cross(ax, side)
    transform = np.eye(4)
    transform[:3, 0], transform[:3, 1], transform[:3, 2] = ax, side, up
    transform[:3, 3] = (p0 + p1) / 2.0
    return trimesh.creation.box(
        extents=[length, _positive("width", width), _positive("thickness", thickness)], transform=transform
    )


def propeller_blades(
    center, diameter, n_blades, root_chord, tip_chord, thickness, hub_diameter, phase_deg: float = 0.0
) -> trimesh.Trimesh:
    """Propeller as ``n_blades`` flat tapered blades around a cylindrical hub.

    Each blade is a convex trapezoidal plate from the hub axis to radius
    ``diameter / 2`` (chord ``root_chord`` at the axis, ``tip_chord`` at the
    tip), lying in the horizontal plane through ``center``. The blade tips
    reach exactly ``diameter / 2`` along their centre lines.

    Parameters
    ----------
    center : array_like, shape (3,)
        Hub centre [m].
    diameter : float
        Tip-to-tip diameter [m].
    n_blades : int
        Number of blades, >= 1.
    root_chord, tip_chord : float
        Blade chord at the axis and at the tip [m].
    thickness : float
        Blade thickness [m].
    hub_diameter : float
        Hub cylinder diameter [m]; its height is ``2 * thickness``.
    phase_deg : float
        Azimuth of the first blade from +x toward +y [deg].
    """
    c = _point("center", center)
    radius = _positive("diameter", diameter) / 2.0
    if int(n_blades) < 1:
        raise ParameterError("n_blades", n_blades, "integer >= 1")
    t = _positive("thickness", thickness)
    c_root, c_tip = _positive("root_chord", root_chord), _positive("tip_chord", tip_chord)
    outline = np.array([[0.0, -c_root / 2], [radius, -c_tip / 2], [radius, c_tip / 2], [0.0, c_root / 2]])
    shells = []
    for k in range(int(n_blades)):
        a = np.radians(phase_deg) + 2.0 * np.pi * k / int(n_blades)
        rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        xy = outline @ rot.T
        pts = np.concatenate([np.column_stack([xy, np.full(4, -t / 2)]), np.column_stack([xy, np.full(4, t / 2)])]) + c
        shells.append(trimesh.convex.convex_hull(pts))
    shells.append(vertical_disc(c, _positive("hub_diameter", hub_diameter), 2.0 * t, sections=24))
    return trimesh.util.concatenate(shells)


def radial_layout(n_rotors: int, radius_m: float, z_m: float = 0.0, phase_deg: float = 45.0) -> list:
    """Rotor positions equally spaced on a circle (a symmetric multirotor).

    Parameters
    ----------
    n_rotors : int
        Rotor count, >= 1.
    radius_m : float
        Distance of each rotor axis from the body centre [m].
    z_m : float
        Height of the motor bases [m].
    phase_deg : float
        Azimuth of the first rotor from +x toward +y [deg] (45 = "X" quad).

    Returns
    -------
    list of tuple
        ``(x, y, z)`` per rotor [m].
    """
    if int(n_rotors) < 1:
        raise ParameterError("n_rotors", n_rotors, "integer >= 1")
    r = _positive("radius_m", radius_m)
    angles = np.radians(phase_deg) + 2.0 * np.pi * np.arange(int(n_rotors)) / int(n_rotors)
    return [(float(r * np.cos(a)), float(r * np.sin(a)), float(z_m)) for a in angles]
