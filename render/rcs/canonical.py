"""Canonical radar targets as triangle meshes, for oracles, convergence studies and benchmarks.

Every mesh is a :class:`trimesh.Trimesh` in metres. Open surfaces (plates,
dihedral and trihedral faces) are single sheets of zero thickness, which the
SBR engine illuminates from either side. The closed-form RCS of each target is
in ``docs/validation.md``; the tests restate the formulas independently.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError


def _mesh(vertices, faces):
    import trimesh

    return trimesh.Trimesh(vertices=np.asarray(vertices, float), faces=np.asarray(faces, np.int64), process=False)


def plate(a_m: float, b_m: float | None = None):
    """Rectangular plate a x b [m] in the xy-plane, side a along x, centred at the origin."""
    b_m = a_m if b_m is None else b_m
    x, y = a_m / 2.0, b_m / 2.0
    return _mesh([[-x, -y, 0], [x, -y, 0], [x, y, 0], [-x, y, 0]], [[0, 1, 2], [0, 2, 3]])


def disk(radius_m: float, sections: int = 256):
    """Circular disk of radius [m] in the xy-plane (a fan of ``sections`` triangles)."""
    phi = np.linspace(0.0, 2 * np.pi, sections, endpoint=False)
    rim = np.stack([radius_m * np.cos(phi), radius_m * np.sin(phi), np.zeros_like(phi)], axis=1)
    faces = [[0, 1 + i, 1 + (i + 1) % sections] for i in range(sections)]
    return _mesh(np.vstack([[0, 0, 0], rim]), faces)


def dihedral(a_m: float, b_m: float):
    """90-degree dihedral: two a x b faces [m] meeting along the y axis (fold length b).

    The faces lie along (1, 0, +-1)/sqrt(2) from the fold, so the opening faces
    +x and the bisector is the direction azimuth 0, elevation 0.
    """
    u1, u2 = np.array([1, 0, 1]) / np.sqrt(2), np.array([1, 0, -1]) / np.sqrt(2)
    y = np.array([0, b_m / 2.0, 0])
    v = [-y, y, -y + a_m * u1, y + a_m * u1, -y + a_m * u2, y + a_m * u2]
    return _mesh(v, [[0, 1, 3], [0, 3, 2], [0, 4, 5], [0, 5, 1]])


def trihedral(a_m: float, kind: str = "square"):
    """Corner reflector with three mutually orthogonal faces in the positive octant.

    ``kind="square"``: square faces of side a; ``"triangular"``: right isosceles
    triangles of leg a. The symmetry axis is (1, 1, 1)/sqrt(3): azimuth 45 deg,
    elevation asin(1/sqrt(3)) = 35.264 deg.
    """
    a = float(a_m)
    if kind == "triangular":
        v = [[0, 0, 0], [a, 0, 0], [0, a, 0], [0, 0, a]]
        return _mesh(v, [[0, 1, 2], [0, 2, 3], [0, 3, 1]])
    if kind != "square":
        raise ParameterError("kind", kind, "'square' or 'triangular'")
    v = [
        [0, 0, 0],
        [a, 0, 0],
        [a, a, 0],
        [0, a, 0],  # z = 0
        [0, 0, a],
        [0, a, a],
        [a, 0, a],
    ]  # (0,a,a) on x=0, (a,0,a) on y=0
    return _mesh(v, [[0, 1, 2], [0, 2, 3], [0, 3, 5], [0, 5, 4], [0, 4, 6], [0, 6, 1]])


def cylinder(radius_m: float, length_m: float, sections: int = 512):
    """Closed circular cylinder of radius and length [m], axis along z, centred."""
    import trimesh

    return trimesh.creation.cylinder(radius=radius_m, height=length_m, sections=sections)


def sphere(radius_m: float, subdivisions: int = 6):
    """Icosphere of radius [m]; ``subdivisions=6`` has 81 920 faces (sag 8e-4 a)."""
    import trimesh

    return trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius_m)


#: Length of the NASA almond of the EMCC benchmark suite [m] (9.936 in).
ALMOND_LENGTH_M = 0.252374


def nasa_almond(length_m: float = ALMOND_LENGTH_M, stations: int = 240, sections: int = 96):
    """The NASA almond (Woo, Wang, Schuh & Sanders, IEEE APM 35(1), 1993), tip toward +x.

    With ``d = length_m`` and ``t`` the position along the axis in units of ``d``:
    for ``-0.416667 < t < 0`` (the ellipsoidal back)
    ``y = 0.193333 d sqrt(1 - (t/0.416667)^2) cos(psi)``, ``z = 0.064444 d sqrt(...) sin(psi)``;
    for ``0 < t < 0.583333`` (the pointed front)
    ``y = 4.83345 d (sqrt(1 - (t/2.08335)^2) - 0.96) cos(psi)``, ``z = 1.61115 d (...) sin(psi)``.
    The tip is at ``x = 0.583333 d``, the rounded back at ``x = -0.416667 d``; the mesh is
    closed with one vertex at each end. ``stations`` rings along x, ``sections`` around.
    """
    t_back, t_front = 0.416667, 0.583333
    # rings clustered toward both ends, where the cross-section changes fastest
    s = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, stations + 2)[1:-1])
    t = -t_back + (t_back + t_front) * s
    scale = np.where(
        t < 0,
        np.sqrt(np.clip(1 - (t / t_back) ** 2, 0, None)),
        np.sqrt(np.clip(1 - (t / 2.08335) ** 2, 0, None)) - 0.96,
    )
    ry = np.where(t < 0, 0.193333, 4.83345) * scale * length_m
    rz = np.where(t < 0, 0.064444, 1.61115) * scale * length_m
    psi = np.linspace(0.0, 2 * np.pi, sections, endpoint=False)
    x = np.repeat(t * length_m, sections)
    y = (ry[:, None] * np.cos(psi)[None, :]).ravel()
    z = (rz[:, None] * np.sin(psi)[None, :]).ravel()
    ring = np.stack([x, y, z], axis=1)
    back, tip = len(ring), len(ring) + 1
    vertices = np.vstack([ring, [[-t_back * length_m, 0, 0], [t_front * length_m, 0, 0]]])
    faces = []
    j = np.arange(sections)
    jn = (j + 1) % sections
    for i in range(stations - 1):
        a, b = i * sections + j, (i + 1) * sections + j
        an, bn = i * sections + jn, (i + 1) * sections + jn
        faces += [np.stack([a, bn, b], 1), np.stack([a, an, bn], 1)]  # outward normals
    faces.append(np.stack([np.full(sections, back), jn, j], 1))
    last = (stations - 1) * sections
    faces.append(np.stack([np.full(sections, tip), last + j, last + jn], 1))
    return _mesh(vertices, np.vstack(faces))
