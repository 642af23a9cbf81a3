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
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError
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


def _sky_ground_envmap(sky_radiance: float, ground_radiance: float, up_render, rows: int = 128):
    """Environment of uniform sky radiance above the horizon and ground radiance below it."""
    import mitsuba as mi

    if sky_radiance == ground_radiance:
        return {"type": "constant", "radiance": {"type": "rgb", "value": float(sky_radiance)}}
    theta = (np.arange(rows) + 0.5) / rows * np.pi  # polar angle from local +Y of each row
    value = np.where(theta < np.pi / 2, sky_radiance, ground_radiance).astype(np.float32)
    image = np.repeat(value[:, None, None], 8, axis=1).repeat(3, axis=2)
    return {
        "type": "envmap",
        "bitmap": mi.Bitmap(np.ascontiguousarray(image)),
        "to_world": mi.ScalarTransform4f(_frame_with_up(up_render).tolist()),
    }


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

    scene = {"type": "scene", "frame": bounding_frame()}
    for i, part in enumerate(target.parts):
        scene[f"part_{i}"] = mitsuba_mesh(part, diffuse_rgb(part.material))
    if sun_irradiance > 0:
        to_sun = np.asarray(sun_direction_render, dtype=float)
        scene["sun"] = {
            "type": "directional",
            "direction": (-to_sun / np.linalg.norm(to_sun)).tolist(),
            "irradiance": {"type": "rgb", "value": float(sun_irradiance)},
        }
    if sky_radiance > 0 or ground_radiance > 0:
        scene["environment"] = _sky_ground_envmap(sky_radiance, ground_radiance, up_render)
    return mi.load_dict(scene)


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

    from csuas.core.radiometry import band_radiance

    scene = {"type": "scene", "frame": bounding_frame()}
    for i, part in enumerate(target.parts):
        eps = float(getattr(part.material, f"emissivity_{band}"))
        bsdf = mi.load_dict({"type": "diffuse", "reflectance": 1.0 - eps})
        emitted = eps * float(band_radiance(part.material.temperature_k, band))
        emitter = mi.load_dict({"type": "area", "radiance": emitted}) if emitted > 0 else None
        scene[f"part_{i}"] = mitsuba_mesh(part, bsdf, emitter)
    if surroundings_radiance > 0:
        scene["environment"] = {"type": "constant", "radiance": float(surroundings_radiance)}
    return mi.load_dict(scene)


def path_integrator(max_depth: int):
    """Mitsuba path tracer; only rays that hit the target are shaded with it (see trace.py)."""
    import mitsuba as mi

    if int(max_depth) != max_depth or max_depth < 2:
        raise ParameterError("max_depth", max_depth, "integer >= 2 (2: direct light only)")
    return mi.load_dict({"type": "path", "max_depth": int(max_depth)})
