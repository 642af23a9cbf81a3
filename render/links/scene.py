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

Building a scene (Mitsuba scene, ground mesh, radio material, devices) and
the kernels Dr.Jit then traces for a scene it has not seen cost more than
the solver itself at small sample counts, so :func:`link_scene` keeps the
last ``SCENE_CACHE_SIZE`` scenes, keyed by everything that shapes them
(frequency, ground material, ground mesh, polarisation, sensing target),
and a call only moves the transmitters and receivers of a cached scene
(:meth:`LinkScene.place`). The solvers are built once per process
(:func:`path_solver`, :func:`rcs_solver`) and run their loops in Dr.Jit's
evaluated mode (``SOLVER_LOOP_MODE``).
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass, field
from functools import cache

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.dielectric import complex_permittivity
from csuas.core.units import wavenumber_rad_m
from csuas.render.links.sionna_backend import load_sionna_rt

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


def ground_properties(material, frequency_ghz: float) -> tuple[float, float]:
    """Relative permittivity and conductivity [S/m] of an ITU material (ITU-R P.2040-3 Table 3), or as given.

    eps_r = a f^b and sigma = c f^d with f in GHz, from Sionna RT's table of
    the recommendation, checked against the frequency range of validity. A pair
    ``(relative_permittivity, conductivity_s_m)`` stands for a ground of those constants at any
    frequency (eps_r >= 1, sigma >= 0).

    Raises
    ------
    ParameterError
        Unknown material, a frequency outside the material's ranges, or constants out of range.
    """
    if isinstance(material, tuple):
        if len(material) != 2 or not all(_is_real(v) for v in material) or material[0] < 1 or material[1] < 0:
            raise ParameterError("ground", material, "(relative_permittivity >= 1, conductivity_s_m >= 0)")
        return float(material[0]), float(material[1])
    materials = itu_materials()
    if material not in materials:
        raise ParameterError("ground", material, "none or one of " + ", ".join(sorted(materials)))
    from sionna.rt.radio_materials.itu import ITU_MATERIALS_PROPERTIES

    for (f_min, f_max), (a, b, c, d) in ITU_MATERIALS_PROPERTIES[material].items():
        if f_min <= frequency_ghz <= f_max:
            return a * frequency_ghz**b, c * frequency_ghz**d
    ranges = ", ".join(f"{lo:g}-{hi:g} GHz" for lo, hi in materials[material])
    raise ParameterError("frequency_ghz", frequency_ghz, f"{ranges} for ground {material!r}")


def _is_real(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and bool(np.isfinite(value))


def half_space_thickness_m(relative_permittivity, conductivity_s_m, frequency_ghz) -> float:
    """Slab thickness [m] whose round trip attenuates the wave by ``HALF_SPACE_NEPERS``.

    The attenuation constant inside the slab is k0 |Im sqrt(eta - sin^2 theta)|,
    smallest at normal incidence, so d = N / (2 k0 |Im sqrt(eta)|), capped at 1e4 m.
    """
    eta = complex_permittivity(relative_permittivity, conductivity_s_m, frequency_ghz)
    k0 = wavenumber_rad_m(frequency_ghz)
    attenuation = 2.0 * k0 * abs(np.sqrt(eta).imag)
    return float(min(1.0e4, HALF_SPACE_NEPERS / attenuation)) if attenuation > 0 else 1.0e4


def ground_half_sizes(extent_m: float) -> list[float]:
    """Half-sizes [m] of the squares of the graded ground covering |x|, |y| <= extent_m."""
    half_sizes = [INNER_HALF_SIZE_M]
    while half_sizes[-1] < extent_m:
        half_sizes.append(half_sizes[-1] * RING_RATIO)
    return half_sizes


def ground_extent_m(extent_m: float) -> float:
    """Extent [m] of the ground mesh under devices up to ``extent_m`` from the origin."""
    return max(2.0 * extent_m, 100.0)


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
    half_sizes = ground_half_sizes(extent_m)
    vertices = np.concatenate([np.column_stack([a * corners, np.zeros(4)]) for a in half_sizes])
    faces = [[0, 1, 2], [0, 2, 3]]
    for level in range(1, len(half_sizes)):
        inner, outer = 4 * (level - 1), 4 * level
        for j in range(4):
            i0, i1 = inner + j, inner + (j + 1) % 4
            o0, o1 = outer + j, outer + (j + 1) % 4
            faces += [[i0, o0, o1], [i0, o1, i1]]
    return vertices, np.asarray(faces, dtype=np.uint32)


def triangle_mesh(name: str, vertices: np.ndarray, faces: np.ndarray):
    """A Mitsuba triangle mesh named ``name`` of vertices (n, 3) [m] and faces (m, 3)."""
    import mitsuba as mi

    mesh = mi.Mesh(
        name, vertex_count=len(vertices), face_count=len(faces), has_vertex_normals=False, has_vertex_texcoords=False
    )
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(vertices.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(faces.ravel())
    params.update()
    return mesh


def build_scene(frequency_ghz: float, ground: str | None, extent_m: float, polarization: str = "V", objects=()):
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
    objects : iterable of sionna.rt.SceneObject
        Further objects (e.g. a sensing target), added with the ground in
        one edit of the scene.

    Returns
    -------
    sionna.rt.Scene
        With single isotropic antennas set as tx and rx arrays, no devices.
    """
    rt = load_sionna_rt()
    scene = rt.load_scene()
    scene.frequency = frequency_ghz * 1e9
    added = []
    if ground is not None:
        thickness = half_space_thickness_m(*ground_properties(ground, frequency_ghz), frequency_ghz)
        vertices, faces = graded_ground_mesh(ground_extent_m(extent_m))
        material = rt.ITURadioMaterial(name=f"ground-{ground}", itu_type=ground, thickness=thickness)
        added.append(
            rt.SceneObject(mi_mesh=triangle_mesh("ground", vertices, faces), name="ground", radio_material=material)
        )
    added += list(objects)
    if added:
        scene.edit(add=added)
    array = rt.PlanarArray(num_rows=1, num_cols=1, pattern="iso", polarization=polarization)
    scene.tx_array = array
    scene.rx_array = array
    return scene


#: Number of scenes :func:`link_scene` keeps (least recently used dropped first).
SCENE_CACHE_SIZE = 8

_scene_cache: OrderedDict = OrderedDict()


class RcsSlot:
    """Cross-section callable of a cached sensing target, replaced on every radar call.

    Sionna calls it as ``rcs(k_i, k_s, seed)``; it forwards to ``function``.
    """

    def __init__(self):
        self.function = None

    def __call__(self, k_i, k_s, seed):
        return self.function(k_i, k_s, seed)


@dataclass(frozen=True)
class TargetSpec:
    """Sensing target of a radar scene: a cuboid with one scattering point at its centre.

    Attributes
    ----------
    size_m : tuple of 3 floats
        Length, width and height of the cuboid [m].
    position_m : tuple of 3 floats
        Centre of the cuboid and scattering point [m].
    """

    size_m: tuple
    position_m: tuple


@dataclass
class LinkScene:
    """A cached Sionna scene, its devices and (for radar) the target's cross-section slot.

    Attributes
    ----------
    scene : sionna.rt.Scene
    rcs : RcsSlot or None
        Cross-section callable of the sensing target, None without target.
    """

    scene: object
    rcs: RcsSlot | None = None
    _devices: dict = field(default_factory=lambda: {"tx": [], "rx": []})

    def place(self, tx_positions, rx_positions) -> None:
        """Put transmitters ``tx0..`` and receivers ``rx0..`` at the given positions [m].

        Existing devices are moved, surplus ones removed from the end and
        missing ones added at the end, so the scene's device order is the
        order of the positions (the order of the solver's outputs).
        """
        rt = load_sionna_rt()
        for kind, positions, cls in (("tx", tx_positions, rt.Transmitter), ("rx", rx_positions, rt.Receiver)):
            devices = self._devices[kind]
            positions = [[float(v) for v in p] for p in np.asarray(positions, float)]
            surplus = devices[len(positions) :]
            if surplus:
                self.scene.remove([d.name for d in surplus])
                del devices[len(positions) :]
            for device, p in zip(devices, positions):
                device.position = p
            for i in range(len(devices), len(positions)):
                device = cls(name=f"{kind}{i}", position=positions[i])
                self.scene.add(device)
                devices.append(device)


def _scene_key(frequency_ghz, ground, extent_m, polarization, target):
    mesh = len(ground_half_sizes(ground_extent_m(extent_m))) if ground is not None else None
    return float(frequency_ghz), ground, mesh, polarization, target


def link_scene(
    frequency_ghz: float, ground: str | None, extent_m: float, polarization: str = "V", target: TargetSpec | None = None
) -> LinkScene:
    """The scene of :func:`build_scene` (plus a sensing target), built once and then reused.

    Parameters
    ----------
    frequency_ghz, ground, extent_m, polarization
        As for :func:`build_scene`; scenes whose ground mesh would be the
        same (same number of rings) share one entry.
    target : TargetSpec, optional
        Sensing target (absorbing cuboid, one scattering point at its centre
        with identity polarisation matrix and the cross-section of
        :attr:`LinkScene.rcs`).

    Returns
    -------
    LinkScene
        Devices are left where the previous call put them: place them with
        :meth:`LinkScene.place`.
    """
    key = _scene_key(frequency_ghz, ground, extent_m, polarization, target)
    cached = _scene_cache.get(key)
    if cached is not None:
        _scene_cache.move_to_end(key)
        load_sionna_rt()
        return cached
    objects, slot = [], None
    if target is not None:
        load_sionna_rt()
        from sionna.rt.rcs import ConstantCPM, ScatteringModel, SensingTarget

        slot = RcsSlot()
        model = ScatteringModel([0.0, 0.0, 0.0], rcs=slot, cpm=ConstantCPM())
        length, width, height = (float(v) for v in target.size_m)
        objects.append(
            SensingTarget(
                name="drone",
                scattering_model=model,
                length=length,
                width=width,
                height=height,
                position=[float(v) for v in target.position_m],
            )
        )
    cached = LinkScene(build_scene(frequency_ghz, ground, extent_m, polarization, objects), slot)
    _scene_cache[key] = cached
    while len(_scene_cache) > SCENE_CACHE_SIZE:
        _scene_cache.popitem(last=False)
    return cached


def clear_scene_cache() -> None:
    """Forget every cached scene (the next :func:`link_scene` call builds anew)."""
    _scene_cache.clear()


#: Dr.Jit loop mode of the solvers' image method and field calculator. "evaluated" gives the same
#: numbers bit for bit as Sionna's default "symbolic" (checked on every bench scene and budget) and
#: saves the tracing of symbolic loops: 3.9 -> 2.7 ms (rf) and 10.4 -> 4.1 ms (radar) per call in
#: free space, within 3 % either way at 1e6 rays (measured on 2 shared LLVM cores).
SOLVER_LOOP_MODE = "evaluated"


@cache
def path_solver():
    """The process's ``sionna.rt.PathSolver`` (it holds no per-call state), on ``SOLVER_LOOP_MODE``."""
    solver = load_sionna_rt().PathSolver()
    solver.loop_mode = SOLVER_LOOP_MODE
    return solver


@cache
def rcs_solver():
    """The process's ``sionna.rt.rcs.RCSSolver`` (it holds no per-call state), on ``SOLVER_LOOP_MODE``."""
    load_sionna_rt()
    from sionna.rt.rcs import RCSSolver

    solver = RCSSolver()
    solver.loop_mode = SOLVER_LOOP_MODE
    return solver
