"""Programmatic Sionna RT scenes: empty space, or one flat ground of an ITU radio material.

The ground is the plane z = 0 built as a *graded* mesh: a small square at
the origin surrounded by square rings whose half-size grows by a factor
``RING_RATIO`` up to the extent needed. Sionna computes specular points in
float32 from the vertices of the triangle hit, so their error is about
1e-7 times the triangle's coordinates; on a single two-triangle plane 200 km
wide, a specular point 10 m from the origin comes out 2 cm off (measured),
while on the graded mesh every triangle's coordinates are within a factor
``RING_RATIO`` of the point's own, and the error stays at float32 precision
of the point itself.

The ground is a half-space: Sionna's radio materials model a slab of given
thickness (ITU-R P.2040-3 Eqs. 43-44); :func:`half_space_thickness_m`
makes the slab thick enough that the wave inside it is attenuated by
``HALF_SPACE_NEPERS`` before it comes back, so the reflection coefficient
is the Fresnel one of the half-space (checked by the two-ray tests). A
fixed large thickness does not do: for metal at 10 km Sionna's float32
slab formula loses the reflected path altogether (measured).
"""

from __future__ import annotations

import numpy as np

from csuas.core.units import C_LIGHT
from csuas.errors import ParameterError
from csuas.render.links.sionna_backend import load_sionna_rt
from csuas.render.links.two_ray import complex_permittivity

#: Half-size of the innermost square of the graded ground [m].
INNER_HALF_SIZE_M = 1.0
#: Ratio of the half-sizes of consecutive rings of the graded ground.
RING_RATIO = 4.0
#: Round-trip attenuation [Np] inside the slab that makes it a half-space (e^-30 = 1e-13).
HALF_SPACE_NEPERS = 30.0
#: Frequencies the links accept [GHz] (Sionna's ITU materials cover at most 0.001-100 GHz).
FREQUENCY_RANGE_GHZ = (0.1, 100.0)


def check_frequency(frequency_ghz) -> float:
    """Return the frequency as float after checking it lies in ``FREQUENCY_RANGE_GHZ``."""
    lo, hi = FREQUENCY_RANGE_GHZ
    try:
        value = float(frequency_ghz)
    except (TypeError, ValueError):
        raise ParameterError("frequency_ghz", frequency_ghz, f"{lo} to {hi} GHz") from None
    if not (np.isfinite(value) and lo <= value <= hi):
        raise ParameterError("frequency_ghz", frequency_ghz, f"{lo} to {hi} GHz")
    return value


def itu_materials() -> dict:
    """ITU-R P.2040 materials known to Sionna RT: name -> list of (f_min, f_max) [GHz] ranges."""
    load_sionna_rt()
    from sionna.rt.radio_materials.itu import ITU_MATERIALS_PROPERTIES

    return {name: sorted(ranges) for name, ranges in ITU_MATERIALS_PROPERTIES.items() if name != "vacuum"}


def ground_properties(material: str, frequency_ghz: float) -> tuple[float, float]:
    """Relative permittivity and conductivity [S/m] of an ITU material (ITU-R P.2040-3 Table 3).

    eps_r = a f^b and sigma = c f^d with f in GHz, from Sionna RT's table of
    the recommendation, checked against the frequency range of validity.

    Raises
    ------
    ParameterError
        Unknown material, or a frequency outside the material's ranges.
    """
    materials = itu_materials()
    if material not in materials:
        raise ParameterError("ground", material, "none or one of " + ", ".join(sorted(materials)))
    from sionna.rt.radio_materials.itu import ITU_MATERIALS_PROPERTIES

    for (f_min, f_max), (a, b, c, d) in ITU_MATERIALS_PROPERTIES[material].items():
        if f_min <= frequency_ghz <= f_max:
            return a * frequency_ghz**b, c * frequency_ghz**d
    ranges = ", ".join(f"{lo:g}-{hi:g} GHz" for lo, hi in materials[material])
    raise ParameterError("frequency_ghz", frequency_ghz, f"{ranges} for ground {material!r}")


def half_space_thickness_m(relative_permittivity, conductivity_s_m, frequency_ghz) -> float:
    """Slab thickness [m] whose round trip attenuates the wave by ``HALF_SPACE_NEPERS``.

    The attenuation constant inside the slab is k0 |Im sqrt(eta - sin^2 theta)|,
    smallest at normal incidence, so d = N / (2 k0 |Im sqrt(eta)|), capped at 1e4 m.
    """
    eta = complex_permittivity(relative_permittivity, conductivity_s_m, frequency_ghz)
    k0 = 2.0 * np.pi * frequency_ghz * 1e9 / C_LIGHT
    attenuation = 2.0 * k0 * abs(np.sqrt(eta).imag)
    return float(min(1.0e4, HALF_SPACE_NEPERS / attenuation)) if attenuation > 0 else 1.0e4


def graded_ground_mesh(extent_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) [m] and triangles (m, 3) of the graded square ground z = 0.

    Parameters
    ----------
    extent_m : float
        The mesh covers at least the square |x|, |y| <= extent_m.

    Returns
    -------
    vertices : numpy.ndarray of float, shape (4 (k + 1), 3)
    faces : numpy.ndarray of uint32, shape (2 + 8 k, 3), counter-clockwise seen from +z
    """
    corners = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    half_sizes = [INNER_HALF_SIZE_M]
    while half_sizes[-1] < extent_m:
        half_sizes.append(half_sizes[-1] * RING_RATIO)
    vertices = np.concatenate([np.column_stack([a * corners, np.zeros(4)]) for a in half_sizes])
    faces = [[0, 1, 2], [0, 2, 3]]
    for level in range(1, len(half_sizes)):
        inner, outer = 4 * (level - 1), 4 * level
        for j in range(4):
            i0, i1 = inner + j, inner + (j + 1) % 4
            o0, o1 = outer + j, outer + (j + 1) % 4
            faces += [[i0, o0, o1], [i0, o1, i1]]
    return vertices, np.asarray(faces, dtype=np.uint32)


def _mitsuba_mesh(name: str, vertices: np.ndarray, faces: np.ndarray):
    import mitsuba as mi

    mesh = mi.Mesh(name, vertex_count=len(vertices), face_count=len(faces),
                   has_vertex_normals=False, has_vertex_texcoords=False)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(vertices.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(faces.ravel())
    params.update()
    return mesh


def build_scene(frequency_ghz: float, ground: str | None, extent_m: float, polarization: str = "V"):
    """An empty Sionna scene, or one with the graded ground of an ITU material.

    Parameters
    ----------
    frequency_ghz : float
        Carrier frequency [GHz].
    ground : str or None
        ITU material name (see :func:`itu_materials`), or None for free space.
    extent_m : float
        Largest horizontal coordinate of any device [m]; the ground reaches
        beyond twice this.
    polarization : {"V", "H"}
        Polarisation of the isotropic antennas of all devices.

    Returns
    -------
    sionna.rt.Scene
        With single isotropic antennas set as tx and rx arrays.
    """
    rt = load_sionna_rt()
    scene = rt.load_scene()
    scene.frequency = frequency_ghz * 1e9
    if ground is not None:
        thickness = half_space_thickness_m(*ground_properties(ground, frequency_ghz), frequency_ghz)
        vertices, faces = graded_ground_mesh(max(2.0 * extent_m, 100.0))
        material = rt.ITURadioMaterial(name=f"ground-{ground}", itu_type=ground, thickness=thickness)
        scene.edit(add=[rt.SceneObject(mi_mesh=_mitsuba_mesh("ground", vertices, faces), name="ground",
                                       radio_material=material)])
    array = rt.PlanarArray(num_rows=1, num_cols=1, pattern="iso", polarization=polarization)
    scene.tx_array = array
    scene.rx_array = array
    return scene
