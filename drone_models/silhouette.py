"""Exact projected cross-section (silhouette) of a mesh seen from any direction.

The projected cross-section (PCS) of the paper's Section 2.3.1 is the shadow
of the drone on a plane perpendicular to the view direction. It is computed
exactly (to floating point) as the polygon union of the orthographic
projections of the mesh's triangles:

* Zero-area triangles are dropped first (their projection has no area); the
  count is reported.
* The mesh is split into connected shells. A closed (watertight) convex shell
  projects onto the convex hull of its projected vertices, which is used
  directly. A closed non-convex shell projects onto the union of its
  front-facing triangles (a line through the solid enters it through one of
  them). An open shell (non-watertight input) uses all its triangles, both
  orientations; it is flagged (``watertight = False``) and a
  :class:`NonWatertightWarning` is issued, but the union is still exact for
  the surface as given.
* The shells' polygons are merged with ``shapely.union_all`` (GEOS OverlayNG).

Image-plane axes follow :mod:`csuas.drone_models.geometry`: ``d_x_proj`` is
the extent along the horizontal axis ``h`` (perpendicular to the view
direction and to world +z), ``d_y_proj`` the extent along ``v = d x h``.
Extents come from the projected vertices of the non-degenerate triangles.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse
import scipy.sparse.csgraph
import shapely
import trimesh

from csuas.base.errors import ParameterError
from csuas.drone_models.geometry import direction_vector, validate_angles, view_basis
from csuas.drone_models.signature import critical_dimension, sphere_equivalent_radius

#: Triangles with area below this fraction of the squared bounding-box diagonal are degenerate.
DEGENERATE_AREA_FRACTION = 1e-14

#: Directions processed per vectorised batch (bounds memory).
BATCH_DIRECTIONS = 128

#: At most this many projected triangles are held at once (directions x triangles of non-convex shells).
TRIANGLE_BUDGET = 200_000

#: At most this many projected convex-shell vertices are held at once (directions x hull points): a
#: 2.97 M-face mesh of convex parts (1.9 M points) at 128 directions a batch peaked at 15.6 GB.
POINT_BUDGET = 4_000_000

#: Triangles of one direction united per GEOS call; larger meshes are united chunk by chunk and the
#: partial silhouettes united last, so that memory stays bounded for meshes of millions of faces.
TRIANGLE_CHUNK = 100_000


class NonWatertightWarning(UserWarning):
    """The mesh has open shells: silhouettes use both faces of every triangle."""


@dataclass
class SilhouetteModel:
    """A mesh prepared for repeated silhouette queries.

    Build it once with :meth:`from_mesh` (or :meth:`from_drone`) and query many
    directions with :func:`metrics_for_directions`.

    Attributes
    ----------
    convex_groups : list of numpy.ndarray, each shape (n_shells, k, 3)
        Vertices of the closed convex shells, grouped by vertex count (padded
        by repetition to the group's power-of-two size ``k``).
    triangles : numpy.ndarray, shape (n_tri, 3, 3)
        Triangles of non-convex shells [m].
    normals : numpy.ndarray, shape (n_tri, 3)
        Their unit normals.
    cullable : numpy.ndarray of bool, shape (n_tri,)
        True where the triangle belongs to a closed shell (back faces may be skipped).
    extent_vertices : numpy.ndarray, shape (n_vert, 3)
        Vertices of all non-degenerate triangles (for the extents).
    watertight : bool
        False when any shell is open.
    n_shells, n_convex_shells, n_degenerate_faces : int
        Book-keeping for reports.
    """

    convex_groups: list
    triangles: np.ndarray
    normals: np.ndarray
    cullable: np.ndarray
    extent_vertices: np.ndarray
    watertight: bool
    n_shells: int
    n_convex_shells: int
    n_degenerate_faces: int

    @property
    def n_hull_points(self) -> int:
        """Vertices of the convex shells (padding included): the size of one view's hull work."""
        return sum(g.shape[0] * g.shape[1] for g in self.convex_groups)

    @classmethod
    def from_mesh(cls, mesh, use_convex_hulls: bool = True, warn: bool = True) -> SilhouetteModel:
        """Prepare ``mesh`` (a trimesh.Trimesh, a Drone, or a sequence of meshes).

        Parameters
        ----------
        mesh : trimesh.Trimesh or Drone or sequence of trimesh.Trimesh
            Geometry in metres.
        use_convex_hulls : bool
            Use the convex-hull shortcut for closed convex shells (exact);
            False forces the triangle union everywhere (the reference path).
        warn : bool
            Issue :class:`NonWatertightWarning` for open shells.
        """
        meshes = _as_mesh_list(mesh)
        vertices = np.concatenate([m.vertices for m in meshes])
        offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
        faces = np.concatenate([m.faces + o for m, o in zip(meshes, offsets)])
        if len(faces) == 0 or not np.all(np.isfinite(vertices)):
            raise ParameterError("mesh", f"{len(faces)} faces", "at least one triangle with finite vertices")
        tri = vertices[faces]
        cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        area2 = np.linalg.norm(cross, axis=1)
        diag2 = float(np.sum(np.ptp(vertices, axis=0) ** 2))
        keep = area2 > 2.0 * DEGENERATE_AREA_FRACTION * diag2
        if not np.any(keep):
            raise ParameterError("mesh", "all faces have zero area", "at least one triangle of non-zero area")
        kept = faces[keep]
        shells = _shells(vertices, kept)
        convex, tris, norms, cull = [], [], [], []
        watertight = True
        for shell_faces in shells:
            closed, oriented = _closure(shell_faces)
            watertight &= closed
            used, local = np.unique(shell_faces, return_inverse=True)
            shell = trimesh.Trimesh(vertices=vertices[used], faces=local.reshape(-1, 3), process=False)
            if use_convex_hulls and oriented and shell.is_convex:
                convex.append(vertices[used])
                continue
            outward = -1.0 if oriented and shell.volume < 0.0 else 1.0  # inside-out shells: flip normals
            tris.append(vertices[shell_faces])
            norms.append(outward * np.asarray(shell.face_normals))
            cull.append(np.full(len(shell_faces), oriented))
        if not watertight and warn:
            warnings.warn(
                "mesh is not watertight: its silhouette uses both faces of every triangle of the open "
                "shells (exact for the surface as given)",
                NonWatertightWarning,
                stacklevel=2,
            )
        groups: dict = {}
        for verts in convex:
            k = 1 << int(np.ceil(np.log2(max(len(verts), 2))))
            groups.setdefault(k, []).append(np.concatenate([verts, np.repeat(verts[-1:], k - len(verts), axis=0)]))
        return cls(
            convex_groups=[np.stack(g) for _, g in sorted(groups.items())],
            triangles=np.concatenate(tris) if tris else np.zeros((0, 3, 3)),
            normals=np.concatenate(norms) if norms else np.zeros((0, 3)),
            cullable=np.concatenate(cull) if cull else np.zeros(0, dtype=bool),
            extent_vertices=vertices[np.unique(kept)],
            watertight=watertight,
            n_shells=len(shells),
            n_convex_shells=len(convex),
            n_degenerate_faces=int(np.count_nonzero(~keep)),
        )

    @classmethod
    def from_drone(cls, drone, **kwargs) -> SilhouetteModel:
        """Prepare all parts of a :class:`~csuas.drone_models.drone.Drone`."""
        return cls.from_mesh([p.mesh for p in drone.parts], **kwargs)


def _shells(vertices: np.ndarray, faces: np.ndarray) -> list:
    """Face index arrays of the edge-connected shells (connectivity as given: no vertex merging)."""
    n = len(vertices)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    graph = scipy.sparse.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, labels = scipy.sparse.csgraph.connected_components(graph, directed=False)
    face_label = labels[faces[:, 0]]
    order = np.argsort(face_label, kind="stable")
    splits = np.flatnonzero(np.diff(face_label[order])) + 1
    return [faces[idx] for idx in np.split(order, splits)]


def _closure(faces: np.ndarray) -> tuple[bool, bool]:
    """(closed, consistently oriented): every edge shared by exactly two faces, each direction once."""
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    undirected = np.sort(directed, axis=1)
    _, counts = np.unique(undirected, axis=0, return_counts=True)
    closed = bool(np.all(counts == 2))
    oriented = closed and len(np.unique(directed, axis=0)) == len(directed)
    return closed, oriented


def _as_mesh_list(mesh) -> list:
    if isinstance(mesh, trimesh.Trimesh):
        return [mesh]
    if hasattr(mesh, "parts"):
        return [p.mesh for p in mesh.parts]
    if isinstance(mesh, (list, tuple)) and mesh and all(isinstance(m, trimesh.Trimesh) for m in mesh):
        return list(mesh)
    raise ParameterError("mesh", type(mesh).__name__, "trimesh.Trimesh, Drone, or a non-empty list of trimesh.Trimesh")


def _silhouettes(model: SilhouetteModel, d: np.ndarray, h: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Union polygons for a batch of directions (arrays of shape (n, 3))."""
    n = len(d)
    columns = []
    for group in model.convex_groups:
        n_cvx, k_max, _ = group.shape
        pts = group.reshape(-1, 3)
        uv = np.stack([pts @ h.T, pts @ v.T], axis=-1)  # (n_cvx*k_max, n, 2)
        uv = uv.reshape(n_cvx, k_max, n, 2).transpose(2, 0, 1, 3)  # (n, n_cvx, k_max, 2)
        # a line string through the points has their convex hull and is ~40x cheaper to build than a multipoint
        hulls = shapely.convex_hull(shapely.linestrings(uv.reshape(n * n_cvx, k_max, 2))).reshape(n, n_cvx)
        hulls[shapely.get_type_id(hulls) != 3] = None  # edge-on shells (segments, points) have no area
        columns.append(hulls)
    for start in range(0, len(model.triangles), TRIANGLE_CHUNK):
        columns.append(_triangle_union(model, slice(start, start + TRIANGLE_CHUNK), d, h, v))
    geoms = np.concatenate(columns, axis=1)
    return shapely.union_all(geoms, axis=1)


#: Measured costs on 2 CPU cores [s per element and view]: the union of projected triangles of
#: non-convex or open shells (400 k open triangles: 7.0 s a view) and the convex hulls of convex shells'
#: vertices (a 2.97 M-face subdivided DJI Mini 4 Pro, 1.88 M hull points: 0.53 s a view).
SECONDS_PER_TRIANGLE_VIEW = 1.8e-5
SECONDS_PER_HULL_POINT_VIEW = 2.9e-7


def estimated_seconds(model: SilhouetteModel, n_directions: int) -> float:
    """Rough wall time of the silhouettes of ``n_directions`` views of ``model`` on 2 CPU cores [s]."""
    per_view = SECONDS_PER_TRIANGLE_VIEW * len(model.triangles) + SECONDS_PER_HULL_POINT_VIEW * model.n_hull_points
    return per_view * n_directions


def _triangle_union(model: SilhouetteModel, part: slice, d, h, v) -> np.ndarray:
    """Union of the projected triangles ``model.triangles[part]`` per direction, shape (n, 1)."""
    triangles, normals, cullable = model.triangles[part], model.normals[part], model.cullable[part]
    n = len(d)
    t = triangles.reshape(-1, 3)
    uv = np.stack([t @ h.T, t @ v.T], axis=-1).reshape(len(triangles), 3, n, 2).transpose(2, 0, 1, 3)
    e1, e2 = uv[:, :, 1] - uv[:, :, 0], uv[:, :, 2] - uv[:, :, 0]
    area2 = np.abs(e1[..., 0] * e2[..., 1] - e1[..., 1] * e2[..., 0])  # (n, n_tri)
    scale = np.sum(np.ptp(model.extent_vertices, axis=0) ** 2)
    facing = (normals @ d.T).T > 0.0
    use = (area2 > 2.0 * DEGENERATE_AREA_FRACTION * scale) & (facing | ~cullable[None, :])
    polys = np.full(use.shape, None, dtype=object)
    polys[use] = shapely.polygons(uv[use])
    return shapely.union_all(polys, axis=1)[:, None]


def metrics_for_directions(model: SilhouetteModel, directions, azimuth_deg=None, keep_polygons: bool = False) -> dict:
    """Exact silhouette metrics for many view directions.

    Parameters
    ----------
    model : SilhouetteModel
        Prepared mesh.
    directions : array_like, shape (n, 3)
        Unit directions from the target toward the sensor.
    azimuth_deg : array_like, shape (n,), optional
        Azimuths used only for the straight up/down axis fallback.
    keep_polygons : bool
        Also return the silhouette polygons (shapely) under ``"silhouette"``.

    Returns
    -------
    dict of numpy.ndarray, each shape (n,)
        ``d_x_proj_m``, ``d_y_proj_m`` [m], ``d_crit_min_m`` (Eq. 1),
        ``d_crit_geometric_mean_m`` (Eq. 2) [m], ``projected_area_m2`` [m^2],
        ``sphere_equivalent_radius_m`` (Eq. 8, T_illum = 1) [m].
    """
    d = np.atleast_2d(np.asarray(directions, dtype=float))
    if d.ndim != 2 or d.shape[1] != 3:
        raise ParameterError("directions", d.shape, "array of shape (n, 3)")
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    h, v = view_basis(d, azimuth_deg)
    batch = max(
        1,
        min(
            BATCH_DIRECTIONS,
            TRIANGLE_BUDGET // max(1, len(model.triangles)),
            POINT_BUDGET // max(1, model.n_hull_points),
        ),
    )
    batches = [slice(i, i + batch) for i in range(0, len(d), batch)]
    # extents per batch too: (n_vert, n) projections of a million-vertex mesh at 256 views took 6 GB
    dx = np.concatenate([np.ptp(model.extent_vertices @ h[b].T, axis=0) for b in batches])
    dy = np.concatenate([np.ptp(model.extent_vertices @ v[b].T, axis=0) for b in batches])
    polygons = np.concatenate([_silhouettes(model, d[b], h[b], v[b]) for b in batches])
    area = shapely.area(polygons)
    out = {
        "d_x_proj_m": dx,
        "d_y_proj_m": dy,
        "d_crit_min_m": critical_dimension(dx, dy, "min"),
        "d_crit_geometric_mean_m": critical_dimension(dx, dy, "geometric_mean"),
        "projected_area_m2": area,
        "sphere_equivalent_radius_m": sphere_equivalent_radius(area),
    }
    if keep_polygons:
        out["silhouette"] = polygons
    return out


def projected_metrics(mesh, azimuth_deg: float, elevation_deg: float) -> dict:
    """Exact silhouette metrics of ``mesh`` seen from one direction.

    Parameters
    ----------
    mesh : trimesh.Trimesh or Drone or SilhouetteModel or list of trimesh.Trimesh
        Geometry [m] in the body frame.
    azimuth_deg : float
        From +x toward +y [deg], -360..360.
    elevation_deg : float
        From the xy-plane [deg], -90..90; the direction points from the target to the sensor.

    Returns
    -------
    dict
        Scalars ``d_x_proj_m``, ``d_y_proj_m``, ``d_crit_min_m`` (Eq. 1),
        ``d_crit_geometric_mean_m`` (Eq. 2), ``projected_area_m2``,
        ``sphere_equivalent_radius_m``; ``direction`` (unit vector),
        ``h_axis``, ``v_axis`` (image axes in the body frame), ``watertight``,
        ``n_degenerate_faces`` and ``silhouette`` (shapely geometry in image
        coordinates ``(h, v)`` [m]).
    """
    az, el = validate_angles(azimuth_deg, elevation_deg)
    if az.ndim or el.ndim:
        raise ParameterError(
            "azimuth_deg/elevation_deg",
            (azimuth_deg, elevation_deg),
            "scalars (use metrics_for_directions for many directions)",
        )
    model = mesh if isinstance(mesh, SilhouetteModel) else SilhouetteModel.from_mesh(mesh)
    d = direction_vector(az, el)
    h, v = view_basis(d, az)
    m = metrics_for_directions(model, d[None, :], np.atleast_1d(az), keep_polygons=True)
    out = {k: (val[0] if k == "silhouette" else float(val[0])) for k, val in m.items()}
    out.update(
        direction=d, h_axis=h, v_axis=v, watertight=model.watertight, n_degenerate_faces=model.n_degenerate_faces
    )
    return out
