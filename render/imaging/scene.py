"""Range-normalised, camera-relative Mitsuba scenes of a target (docs/simulation.md).

Far ranges must not cost float32 precision. The target is therefore rotated
into the *render frame* and scaled by its bounding radius ``r_b`` (float64,
before the cast to float32):

* render frame: image right ``h`` -> +x, image up ``v`` -> +y, the direction
  from the target toward the sensor ``d`` -> +z, with ``(h, v, d)`` from
  :func:`csuas.drone_models.geometry.view_basis` (docs/command-line.md convention; a
  right-handed rotation since ``h x v = d``);
* unit: ``r_b``, so the target fills the unit sphere about the origin and
  Mitsuba's ray-spawn offsets (proportional to ``1 + |p|``) stay tiny
  against the target at every range;
* camera: on the +z axis at ``D = R / r_b`` looking toward -z. Rays start on
  the axis (transverse origin components exactly 0) and their directions are
  computed in float64 (:func:`csuas.render.imaging.camera.ray_directions`),
  so the silhouette keeps float32 relative precision at 20 km as at 10 m.

Path effects of the true range (transmittance, airlight, path radiance) are
applied analytically afterwards (:mod:`csuas.render.imaging.path`).
"""

from __future__ import annotations

import functools
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.radiometry import band_radiance
from csuas.drone_models.geometry import direction_vector, view_basis


@dataclass
class RenderPart:
    """One closed, outward-oriented triangle mesh of the target in the render frame.

    Attributes
    ----------
    name : str
    vertices : ndarray, shape (n, 3)
        Render-frame coordinates in units of the bounding radius (float64).
    faces : ndarray of int, shape (m, 3)
    material : csuas.drone_models.Material
    """

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    material: object


@dataclass
class NormalisedTarget:
    """A target rotated into the render frame and scaled to its bounding radius.

    Attributes
    ----------
    parts : list of RenderPart
    radius_m : float
        Bounding radius about the body-frame origin [m] (the render unit).
    rotation : ndarray, shape (3, 3)
        Body frame -> render frame (rows h, v, d).
    """

    parts: list
    radius_m: float
    rotation: np.ndarray

    def to_render(self, body_vector) -> np.ndarray:
        """Rotate a body-frame vector into the render frame."""
        return self.rotation @ np.asarray(body_vector, dtype=float)


@functools.lru_cache(maxsize=8)
def _preset(name: str):
    """A drone preset's model, built once per process (its meshes take about 20 ms to generate)."""
    from csuas.drone_models import build_drone

    return build_drone(name)


def target_parts(target) -> list:
    """Parts of a target: a preset name, a :class:`~csuas.drone_models.Drone` or a list of parts.

    Each part needs ``.name``, ``.mesh`` (trimesh, metres, closed and
    outward-oriented: Mitsuba's diffuse surfaces and area emitters are one-sided)
    and ``.material``.
    """
    if isinstance(target, str):
        target = _preset(target)
    parts = list(getattr(target, "parts", target))
    if not parts:
        raise ParameterError("target", target, "a drone preset, a Drone or a non-empty list of parts")
    for part in parts:
        if len(part.mesh.faces) == 0:
            raise ParameterError("target.part", part.name, "a mesh with at least one face")
    return parts


def normalise_target(target, azimuth_deg: float, elevation_deg: float) -> NormalisedTarget:
    """Rotate the target into the render frame for the given view direction and scale it.

    Parameters
    ----------
    target : str, Drone or list of parts
        See :func:`target_parts`.
    azimuth_deg, elevation_deg : float
        Direction from the target toward the sensor (docs/command-line.md) [deg].
    """
    parts = target_parts(target)
    d = direction_vector(azimuth_deg, elevation_deg)
    h, v = view_basis(d, azimuth_deg)
    rotation = np.stack([h, v, d])
    radius = max(float(np.linalg.norm(np.asarray(p.mesh.vertices, dtype=float), axis=1).max()) for p in parts)
    if not np.isfinite(radius) or radius <= 0.0:
        raise ParameterError("target", "mesh", "finite vertices not all at the origin")
    out = [
        RenderPart(
            p.name,
            (np.asarray(p.mesh.vertices, dtype=float) @ rotation.T) / radius,
            np.asarray(p.mesh.faces, dtype=np.int64),
            p.material,
        )
        for p in parts
    ]
    return NormalisedTarget(out, radius, rotation)


def bounding_frame():
    """A mesh of two zero-area triangles at the corners (-1, -1, -1) and (1, 1, 1) of the render frame.

    No ray hits it, but it fixes the scene's bounding box to the cube around the unit sphere that
    holds every normalised target. Mitsuba compiles the scene's bounding sphere into its emitters'
    sampling code, so without the frame every aspect (every rotation of the target) would build the
    path tracer anew (0.14 s of LLVM compilation on 2 cores, against 0.02 s of tracing at draft).
    """
    import mitsuba as mi

    corners = np.repeat(np.array([[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]]), 3, axis=0)
    part = RenderPart("frame", corners, np.arange(6).reshape(2, 3), None)
    return mitsuba_mesh(part, mi.load_dict({"type": "diffuse"}))


def mitsuba_mesh(part: RenderPart, bsdf, emitter=None, exterior=None):
    """A Mitsuba mesh of ``part`` with its BSDF, optional area emitter and optional exterior medium."""
    import mitsuba as mi

    props = mi.Properties()
    props["bsdf"] = bsdf
    if emitter is not None:
        props["emitter"] = emitter
    if exterior is not None:
        props["exterior"] = exterior
    mesh = mi.Mesh(
        part.name,
        len(part.vertices),
        len(part.faces),
        props=props,
        has_vertex_normals=False,
        has_vertex_texcoords=False,
    )
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(part.vertices.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(part.faces.astype(np.uint32).ravel())
    params.update()
    return mesh


def diffuse_rgb(material):
    """Lambertian Mitsuba BSDF of a material's linear-sRGB albedo ``reflectance_rgb``."""
    import mitsuba as mi

    return mi.load_dict(
        {"type": "diffuse", "reflectance": {"type": "rgb", "value": [float(c) for c in material.reflectance_rgb]}}
    )


def _frame_with_up(up) -> np.ndarray:
    """4x4 to_world matrix mapping local +Y (Mitsuba's environment-map up) to ``up``."""
    up = np.asarray(up, dtype=float) / np.linalg.norm(up)
    helper = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    x = np.cross(up, helper)
    x /= np.linalg.norm(x)
    z = np.cross(x, up)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2] = x, up, z
    return m


def _sky_ground_pattern(sky_radiance: float, ground_radiance: float) -> tuple[float, float, float]:
    """(sky, ground, scale): the environment's two radiances as a pattern of at most 1 times a scale."""
    scale = max(sky_radiance, ground_radiance)
    return sky_radiance / scale, ground_radiance / scale, scale


def _sky_ground_envmap(pattern: tuple[float, float], scale: float, up_render, rows: int = 128):
    """Environment of uniform sky radiance above the horizon and ground radiance below it (``scale`` x pattern)."""
    import mitsuba as mi

    sky, ground = pattern
    if sky == ground:
        return {"type": "constant", "radiance": {"type": "rgb", "value": float(scale * sky)}}
    theta = (np.arange(rows) + 0.5) / rows * np.pi  # polar angle from local +Y of each row
    value = np.where(theta < np.pi / 2, sky, ground).astype(np.float32)
    image = np.repeat(value[:, None, None], 8, axis=1).repeat(3, axis=2)
    return {
        "type": "envmap",
        "bitmap": mi.Bitmap(np.ascontiguousarray(image)),
        "scale": float(scale),
        "to_world": mi.ScalarTransform4f(_frame_with_up(up_render).tolist()),
    }


def _along(direction):
    """to_world of a directional emitter whose light travels along ``direction`` (its local +z)."""
    import mitsuba as mi

    d = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    up = [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0]
    return mi.ScalarTransform4f().look_at(origin=[0.0, 0.0, 0.0], target=d.tolist(), up=up)


#: Scenes kept for reuse (:func:`reused_scene`): key -> (scene, its parameters).
_SCENES: OrderedDict = OrderedDict()
#: How many scenes are kept.
SCENE_CACHE_SIZE = 4


def _parts_key(target: NormalisedTarget, material_key) -> tuple:
    """The parts' names, topology and ``material_key(material)``: what a scene of the target is built from."""
    return tuple((p.name, len(p.vertices), hash(p.faces.tobytes()), material_key(p.material)) for p in target.parts)


def reused_scene(key: tuple, target: NormalisedTarget, build, update):
    """The scene of ``key``, built once by ``build()`` and afterwards updated in place.

    On reuse the parts' vertex positions (the aspect) are replaced and ``update(params)`` sets the
    values that may change between renders (emitters), then the scene is refreshed. Mitsuba compiles
    the identity of a scene's emitters and shapes into the path tracer, so a scene built anew for
    every render rebuilds the kernels each time (0.14 s of LLVM compilation on 2 cores against 0.02 s
    of tracing at draft quality). The last ``SCENE_CACHE_SIZE`` scenes are kept.
    """
    import mitsuba as mi

    if key not in _SCENES:
        scene = build()
        params = mi.traverse(scene)
        update(params)  # the values of a new scene are set as those of a reused one
        params.update()
        _SCENES[key] = (scene, params)
        while len(_SCENES) > SCENE_CACHE_SIZE:
            _SCENES.popitem(last=False)
        return scene
    _SCENES.move_to_end(key)
    scene, params = _SCENES[key]
    for i, part in enumerate(target.parts):
        params[f"part_{i}.vertex_positions"] = mi.Float(part.vertices.astype(np.float32).ravel())
    update(params)
    params.update()
    return scene


def build_eo_scene(
    target: NormalisedTarget,
    *,
    sun_direction_render,
    sun_irradiance: float,
    sky_radiance: float,
    ground_radiance: float,
    up_render,
):
    """Mitsuba scene (``*_ad_rgb``) for visible-band rendering.

    A scene of the same structure (:func:`_eo_scene_key`) is built once and then updated in place:
    new vertex positions (the aspect), sun direction and irradiance, sky and ground radiance and the
    horizon's orientation. Mitsuba compiles the identity of a scene's emitters and shapes into the
    path tracer, so a scene built anew for every render would rebuild the kernels each time (0.14 s of
    LLVM compilation on 2 cores against 0.02 s of tracing at draft); the last ``SCENE_CACHE_SIZE``
    scenes are kept.

    Parameters
    ----------
    target : NormalisedTarget
        Parts with diffuse albedo ``material.reflectance_rgb``.
    sun_direction_render : array_like, shape (3,)
        Unit vector toward the sun in the render frame.
    sun_irradiance : float
        Irradiance normal to the sun's rays [lx] (RGB white: Y = value).
    sky_radiance, ground_radiance : float
        Luminance of the sky hemisphere and of the ground hemisphere [cd m^-2].
    up_render : array_like, shape (3,)
        World up (body +z) in the render frame.
    """
    import mitsuba as mi

    has_sun = sun_irradiance > 0
    lit = sky_radiance > 0 or ground_radiance > 0
    sky, ground, scale = _sky_ground_pattern(sky_radiance, ground_radiance) if lit else (0.0, 0.0, 0.0)
    to_sun = np.asarray(sun_direction_render, dtype=float)

    def build():
        spec = {"type": "scene", "frame": bounding_frame()}
        for i, part in enumerate(target.parts):
            spec[f"part_{i}"] = mitsuba_mesh(part, diffuse_rgb(part.material))
        if has_sun:
            spec["sun"] = {
                "type": "directional",
                "direction": [0.0, 0.0, 1.0],
                "irradiance": {"type": "rgb", "value": 1.0},
            }
        if lit:
            spec["environment"] = _sky_ground_envmap((sky, ground), scale, up_render)
        return mi.load_dict(spec)

    def update(params):
        if has_sun:
            params["sun.to_world"] = _along(-to_sun)
            params["sun.irradiance.value"] = mi.Color3f(float(sun_irradiance))
        if lit and sky == ground:
            params["environment.radiance.value"] = mi.Color3f(float(scale * sky))
        elif lit:
            params["environment.scale"] = float(scale)
            params["environment.to_world"] = mi.ScalarTransform4f(_frame_with_up(up_render).tolist())

    key = ("eo", _parts_key(target, lambda m: tuple(m.reflectance_rgb)), has_sun, (sky, ground) if lit else None)
    return reused_scene(key, target, build, update)


def build_tir_scene(target: NormalisedTarget, *, band: str, surroundings_radiance: float):
    """Mitsuba scene (``*_ad_mono``) for thermal-infrared band radiance.

    Each part is a graybody: an area emitter of radiance eps * L_band(T)
    (:func:`csuas.core.radiometry.band_radiance`) on a diffuse surface of
    reflectance 1 - eps (Kirchhoff); the surroundings are a uniform
    environment of band radiance ``surroundings_radiance`` (0: none).

    Parameters
    ----------
    target : NormalisedTarget
    band : {"lwir", "mwir"}
        Selects ``emissivity_lwir`` or ``emissivity_mwir`` of each material.
    surroundings_radiance : float
        [W m^-2 sr^-1].
    """
    import mitsuba as mi

    def graybody(material):
        eps = float(getattr(material, f"emissivity_{band}"))
        return eps, eps * float(band_radiance(material.temperature_k, band))

    def build():
        spec = {"type": "scene", "frame": bounding_frame()}
        for i, part in enumerate(target.parts):
            eps, emitted = graybody(part.material)
            bsdf = mi.load_dict({"type": "diffuse", "reflectance": 1.0 - eps})
            emitter = mi.load_dict({"type": "area", "radiance": emitted}) if emitted > 0 else None
            spec[f"part_{i}"] = mitsuba_mesh(part, bsdf, emitter)
        if surroundings_radiance > 0:
            spec["environment"] = {"type": "constant", "radiance": float(surroundings_radiance)}
        return mi.load_dict(spec)

    def update(params):
        if surroundings_radiance > 0:
            params["environment.radiance.value"] = float(surroundings_radiance)

    key = ("tir", band, _parts_key(target, graybody), surroundings_radiance > 0)
    return reused_scene(key, target, build, update)


def path_integrator(max_depth: int):
    """Mitsuba path tracer; only rays that hit the target are shaded with it (see trace.py)."""
    import mitsuba as mi

    if int(max_depth) != max_depth or max_depth < 2:
        raise ParameterError("max_depth", max_depth, "integer >= 2 (2: direct light only)")
    return mi.load_dict({"type": "path", "max_depth": int(max_depth)})
