"""Lidar targets: triangle meshes with Lambertian albedos at the laser wavelength.

A :class:`LidarTarget` holds the parts of a target (mesh and diffuse albedo
each) in *target-relative* coordinates: the vertices are shifted by the
centre of the bounding box in float64 before they are handed to Mitsuba in
float32, so the ray tracer never sees the range to the sensor (see
:mod:`csuas.render.lidar.cross_section`). The Mitsuba scene is built lazily,
on first use, with the variant chosen by
:func:`csuas.render.backend.use_variant` (``ad_mono``: one spectral channel
at the laser wavelength).

Each part gets a two-sided ``diffuse`` BSDF (Lambertian, albedo ``rho``), so
open surfaces such as a bare plate reflect from both sides and inside-out
shells of a mesh cannot go black.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from csuas.base.errors import ParameterError

#: Wavelengths [nm] at which :class:`csuas.drone_models.Material` tabulates diffuse albedo.
TABULATED_WAVELENGTHS_NM = (550.0, 1550.0)

#: Mitsuba variant family used for the lidar cross-section (one channel at the laser wavelength).
VARIANT_FAMILY = "ad_mono"


def check_reflectance(value, name: str = "reflectance") -> float:
    """Validate a diffuse albedo: a finite number in [0, 1].

    Raises
    ------
    ParameterError
        Naming ``name``, the value and the allowed interval.
    """
    try:
        rho = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, "a number 0 <= x <= 1") from None
    if not (np.isfinite(rho) and 0.0 <= rho <= 1.0):
        raise ParameterError(name, value, "0 <= x <= 1")
    return rho


def material_reflectance(material, wavelength_nm: float = 1550.0) -> float:
    """Diffuse albedo of a drone-part material at the laser wavelength.

    Materials tabulate albedo at 550 nm and 1550 nm
    (:class:`csuas.drone_models.Material`); between them the albedo is
    interpolated linearly in wavelength, outside them the nearest tabulated
    value is used. The paper's lidars work at 850-1560 nm (Section 4.8.1,
    Table 46), where the 1550 nm value dominates.

    Parameters
    ----------
    material : csuas.drone_models.Material
    wavelength_nm : float
        Laser wavelength [nm], > 0.
    """
    wl = float(wavelength_nm)
    if not (np.isfinite(wl) and wl > 0.0):
        raise ParameterError("lidar.wavelength_nm", wavelength_nm, "x > 0 nm")
    rho = np.interp(wl, TABULATED_WAVELENGTHS_NM, (material.reflectance_550nm, material.reflectance_1550nm))
    return check_reflectance(rho, f"material.{material.name}.reflectance")


@dataclass
class LidarPart:
    """One part of a lidar target.

    Attributes
    ----------
    name : str
    vertices : numpy.ndarray, shape (n, 3)
        Target-relative vertex positions [m] (float64).
    faces : numpy.ndarray, shape (m, 3)
        Vertex indices of the triangles.
    reflectance : float
        Lambertian albedo at the laser wavelength [0..1].
    """

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    reflectance: float


@dataclass
class LidarTarget:
    """A target prepared for lidar cross-section tracing.

    Build it with :meth:`from_mesh` or :meth:`from_drone`.

    Attributes
    ----------
    name : str
    parts : list of LidarPart
    centre_m : numpy.ndarray, shape (3,)
        Bounding-box centre subtracted from the input coordinates [m].
    bounding_radius_m : float
        Radius of the sphere about the centre that encloses every vertex [m].
    wavelength_nm : float
        Laser wavelength the albedos refer to [nm].
    """

    name: str
    parts: list
    centre_m: np.ndarray
    bounding_radius_m: float
    wavelength_nm: float
    _shapes: tuple = field(default=None, repr=False)

    @classmethod
    def from_mesh(cls, mesh, reflectance: float, name: str = "mesh", wavelength_nm: float = 1550.0) -> LidarTarget:
        """One-material target from a ``trimesh.Trimesh`` (or a list of them), metres.

        Parameters
        ----------
        mesh : trimesh.Trimesh or list of trimesh.Trimesh
        reflectance : float
            Lambertian albedo of every part [0..1].
        """
        rho = check_reflectance(reflectance)
        meshes = mesh if isinstance(mesh, (list, tuple)) else [mesh]
        return cls._build(name, [(f"{name}_{i}", m, rho) for i, m in enumerate(meshes)], wavelength_nm)

    @classmethod
    def from_drone(cls, drone, wavelength_nm: float = 1550.0) -> LidarTarget:
        """Target from a :class:`csuas.drone_models.Drone`, each part with its material's albedo."""
        items = [(p.name, p.mesh, material_reflectance(p.material, wavelength_nm)) for p in drone.parts]
        return cls._build(drone.name, items, wavelength_nm)

    @classmethod
    def _build(cls, name: str, items: list, wavelength_nm: float) -> LidarTarget:
        parts = []
        for part_name, mesh, rho in items:
            vertices = np.asarray(getattr(mesh, "vertices", None), dtype=float)
            faces = np.asarray(getattr(mesh, "faces", None), dtype=np.int64)
            if vertices.ndim != 2 or vertices.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
                raise ParameterError(
                    f"mesh.{part_name}", type(mesh).__name__, "a triangle mesh (vertices (n, 3), faces (m, 3))"
                )
            if len(faces) == 0 or not np.all(np.isfinite(vertices)):
                raise ParameterError(
                    f"mesh.{part_name}", f"{len(faces)} faces", "at least one triangle with finite vertices"
                )
            parts.append(LidarPart(part_name, vertices, faces, rho))
        if not parts:
            raise ParameterError("mesh", "no parts", "at least one mesh")
        all_vertices = np.concatenate([p.vertices for p in parts])
        centre = 0.5 * (all_vertices.min(axis=0) + all_vertices.max(axis=0))
        for p in parts:
            p.vertices = p.vertices - centre
        radius = float(np.max(np.linalg.norm(all_vertices - centre, axis=1)))
        if not radius > 0.0:
            raise ParameterError("mesh", "all vertices coincide", "a mesh of non-zero extent")
        return cls(
            name=name, parts=parts, centre_m=centre, bounding_radius_m=radius, wavelength_nm=float(wavelength_nm)
        )

    @property
    def vertices(self) -> np.ndarray:
        """All target-relative vertices, shape (n, 3) [m]."""
        return np.concatenate([p.vertices for p in self.parts])

    def shapes(self) -> dict:
        """Mitsuba mesh shapes of the parts, keyed ``part_<i>`` (built once, ``ad_mono`` variant)."""
        from csuas.render.backend import use_variant

        use_variant(VARIANT_FAMILY)
        import mitsuba as mi

        if self._shapes is not None and self._shapes[0] == mi.variant():
            return self._shapes[1]
        shapes = {}
        for i, part in enumerate(self.parts):
            mesh = mi.Mesh(part.name, len(part.vertices), len(part.faces), has_vertex_normals=False)
            params = mi.traverse(mesh)
            params["vertex_positions"] = mi.Float(np.ascontiguousarray(part.vertices, dtype=np.float32).ravel())
            params["faces"] = mi.UInt32(np.ascontiguousarray(part.faces, dtype=np.uint32).ravel())
            params.update()
            mesh.set_bsdf(
                mi.load_dict(
                    {
                        "type": "twosided",
                        "material": {
                            "type": "diffuse",
                            "reflectance": {"type": "spectrum", "value": float(part.reflectance)},
                        },
                    }
                )
            )
            shapes[f"part_{i}"] = mesh
        self._shapes = (mi.variant(), shapes, mi.load_dict({"type": "scene", **shapes}))
        return shapes

    def scene(self):
        """The Mitsuba scene of the parts alone, for ``ray_intersect`` (built once)."""
        self.shapes()
        return self._shapes[2]
