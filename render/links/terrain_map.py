"""Radio maps over terrain: Sionna RT's RadioMapSolver on a mesh of the DEM, at a flight level above it.

Geometry. The terrain is a triangle mesh with one vertex per DEM cell centre (two triangles per
square of four neighbouring centres) in a local frame: x east along the columns, y north against
the rows (y = -row), both in metres from the grid's centre, z the DEM height. The Earth's curvature
with refraction is folded into the heights: every vertex drops by d^2 / (2 k R_E), d its distance
from the grid's centre (the parabolic effective Earth of ITU-R P.834-9 Eq. 1, as in
:mod:`csuas.core.terrain`; a sphere looks the same from every point, so straight rays in this frame
clear the terrain as the viewshed's do from the sensor's own tangent plane). ``k_factor=None`` keeps
the ground flat. The terrain is a half-space of an ITU-R P.2040-3 material (the slab of
:func:`csuas.render.links.scene.half_space_thickness_m`), reflecting only: rays that enter the
ground never come back.

Measurement surface. The flight level is a second mesh whose vertices sit at the corners of
measurement cells (blocks of ``step`` x ``step`` DEM cells), ``altitude_m`` above the terrain
(bilinear DEM, :func:`csuas.core.terrain.height_at`) less the same curvature drop. Corners are
clipped to the span of the terrain mesh (cell centre to cell centre), so the outermost blocks are
half a cell narrower and every point of the surface lies over the terrain. Each block is two
triangles; Sionna returns per triangle the path gain averaged over its area (RadioMapSolver, Eq.
``cm_def``: g = (1/|C|) integral over C of |h(s)|^2 ds), and the block's value is the
area-weighted mean of its two triangles: the path gain averaged over the block. A block is flat
between its corners, so with a coarse ``step`` a hill inside a block can rise through the flight
level (rays then cross it inside the terrain and that part of the block stays dark).

Power, not field. Sionna's radio map adds the *powers* of the rays that cross a cell (the
``|h(s)|^2`` of ``cm_def`` is "the sum of the squared amplitudes of the path coefficients"): over
flat ground it is |h_direct|^2 + |h_ground|^2, the two-ray model without its interference lobes.
The coherent sum at points is :func:`csuas.render.links.rf.rf_path_gain` (PathSolver).

Error estimate. Sionna shoots its rays along a spherical Fibonacci lattice fixed in the world
frame, and with reflection only its sampler draws nothing: a seed changes no result, so a second
run gives no error estimate. The run is instead made of ``replicas`` solves, each with the lattice
turned about the transmitter by the transpose R^T of an independent uniformly distributed rotation R
(Haar measure on SO(3); :func:`turned_rays`). Relative to the ground these are the rays of a
replica in which the whole scene (terrain, measurement surface, transmitter and its antenna) is
rigidly rotated by R about the transmitter, as csuas first did, but the scene and its acceleration
structure are built once per map and never moved (rotating the scene cost 0.4 s of BVH rebuild per
replica of the demo's 400^2-cell terrain, more than the trace). This leaves the physics unchanged
and makes the lattice's directions uniform relative to the scene: each replica is an unbiased
estimate of every cell's mean power (a randomised quasi-Monte Carlo rule; Owen, *Monte Carlo theory,
methods and examples*, 2013, Ch. 17). The map is the replicas' mean, its standard error SE = s /
sqrt(K) comes from their spread s, and

    error_db = -10 log10(1 - t SE / mean),    t = t_{(1 + p) / 2}(K - 1)  (Student),

the larger side of the two-sided bound at the Student model's level ``p = BOUND_LEVEL = 0.99``
(infinite once t SE >= mean). The level csuas states for the bound is ``STATED_COVERAGE = 0.95``:
the replicas of cells crossed by few rays are skewed, so the model's nominal level is kept above
it; over flat ground the bound covered the true error in 98-100 % of the reliable cells from
2^16 to 2^22 rays per replica (:mod:`csuas.validation.links.terrain_map`, ``links.terrain_map``
in the report). A cell that some replica left without a ray is flagged unreliable: its replica
values are far from normal and the bound is not trusted there. Cells no replica reached have no
power at all: ``path_gain_db`` is -inf and ``error_db`` inf there, either because no path exists
(hidden cells in a line-of-sight map) or because the budget is too small for them; never NaN.

Cost. The rays crossing a cell scale with its solid angle seen from the transmitter, A sin(e) / r^2
(A the cell's area, e the elevation of the line of sight), so a cell of side c at distance r on a
flight level dh above the transmitter collects about N c^2 dh / (4 pi r^3) rays of the N per
replica: far, grazing cells need the most. :func:`radio_map_budget` doubles the rays per replica
until the bound meets a requested value over a requested fraction of the map.

Sector. A sensor with an azimuth sector (:class:`RadioMapSite` ``sector_deg``) gets rays only over
it and a measurement surface only over its blocks: the turned lattice's azimuths are folded linearly
onto a band (:func:`fold_directions`, which keeps directions uniform, each ray standing for a solid
angle smaller by the band's share of the turn, by which the map is scaled), the sector widened to
the whole footprint of every measured block (:func:`ray_band`). All the rays per replica then cross
the sector. Cells outside it are NaN in ``path_gain_db`` and ``error_db`` (not measured); the blocks
around the sensor, of which the band lights only a part, are not reliable.

References: Sionna RT 2.2 ``RadioMapSolver`` and ``MeshRadioMap`` documentation; Sionna RT
technical report, Sec. 4 (radio maps); ITU-R P.2040-3 (materials); 3GPP TR 38.901 Eq. 7.1-4
(rotation angles).
"""

from __future__ import annotations

import hashlib
import time
from collections import OrderedDict
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from functools import cache
from typing import Any

import numpy as np

from csuas.base.errors import InputErrors, ParameterError, raise_all
from csuas.core.horizon import K_RADIO
from csuas.core.terrain import bearing_deg, curvature_drop_m, height_at, off_boresight_deg, viewshed
from csuas.render.links.budget import LinkBudget, resolve_budget
from csuas.render.links.rf import check_height
from csuas.render.links.scene import (
    check_frequency,
    ground_properties,
    half_space_thickness_m,
    triangle_mesh,
)
from csuas.render.links.sionna_backend import active_variant, load_sionna_rt
from csuas.render.rcs.solver import lower_side_db

#: ITU-R P.2040 material of the terrain by default.
DEFAULT_GROUND = "medium_dry_ground"
#: Rays per replica by default (0.2-0.4 s per replica for an 81 x 81 grid on 2 CPU cores, measured).
DEFAULT_SAMPLES = 1_000_000
#: Interactions per path by default: the ground bounce and one more off a slope.
DEFAULT_MAX_DEPTH = 2
#: Rotated replicas of a run (module docstring).
REPLICAS = 8
#: Two-sided level of the Student model behind the error bound (module docstring).
BOUND_LEVEL = 0.99
#: Fraction of the cells whose error the bound covers, as csuas states and checks it.
STATED_COVERAGE = 0.95
#: Terrain scenes :func:`terrain_scene` keeps (least recently used dropped first).
TERRAIN_CACHE_SIZE = 2
#: Measurement surfaces kept per terrain scene (flight level, step).
SURFACE_CACHE_SIZE = 4


def check_dem(dem_m, cell_m) -> tuple[np.ndarray, float]:
    """The DEM as a float array and the cell size [m], or every mistake at once.

    Raises
    ------
    ParameterError or InputErrors
        ``dem_m`` not a finite 2-D grid of at least 2 x 2 cells; ``cell_m`` not in (0, 1e5] m.
    """
    errors = []
    try:
        dem = np.asarray(dem_m, dtype=float)
        if dem.ndim != 2 or min(dem.shape) < 2 or not np.isfinite(dem).all():
            raise ValueError
    except (TypeError, ValueError):
        shape = getattr(dem_m, "shape", type(dem_m).__name__)
        errors.append(ParameterError("dem_m", f"array of shape {shape}", "a finite 2-D grid of at least 2 x 2 cells"))
        dem = np.zeros((2, 2))
    try:
        cell = float(cell_m)
        if not (np.isfinite(cell) and 0 < cell <= 1e5):
            raise ValueError
    except (TypeError, ValueError):
        errors.append(ParameterError("cell_m", cell_m, "(0, 1e5] m"))
        cell = 1.0
    raise_all(errors)
    return dem, cell


def local_xy(rows, cols, shape, cell_m) -> tuple[np.ndarray, np.ndarray]:
    """Local frame [m] of fractional (row, col) cell positions: x east = columns, y north = -rows.

    The origin is the centre of the grid of ``shape`` (rows, cols), so coordinates stay within half
    the grid's extent (float32 keeps 0.5 mm at 7 km).
    """
    x = (np.asarray(cols, float) - (shape[1] - 1) / 2.0) * cell_m
    y = -(np.asarray(rows, float) - (shape[0] - 1) / 2.0) * cell_m
    return x, y


def surface_drop_m(x_m, y_m, k_factor) -> np.ndarray:
    """Drop [m] of the effective Earth at (x, y) below the tangent plane at the grid's centre; 0 if flat."""
    if k_factor is None:
        return np.zeros(np.broadcast(x_m, y_m).shape)
    return curvature_drop_m(np.hypot(x_m, y_m), k_factor)


def grid_faces(n_rows: int, n_cols: int) -> np.ndarray:
    """Triangles of a grid of vertices (row-major): two per square, counter-clockwise seen from +z.

    Returns
    -------
    numpy.ndarray of uint32, shape (2 (n_rows - 1) (n_cols - 1), 3)
        Square q (row-major over the (n_rows - 1) x (n_cols - 1) squares) is faces 2q and 2q + 1,
        split along its diagonal from the top-left (north-west) to the bottom-right vertex.
    """
    index = np.arange(n_rows * n_cols).reshape(n_rows, n_cols)
    nw, ne = index[:-1, :-1].ravel(), index[:-1, 1:].ravel()
    sw, se = index[1:, :-1].ravel(), index[1:, 1:].ravel()
    return np.stack([np.stack([nw, sw, se], 1), np.stack([nw, se, ne], 1)], 1).reshape(-1, 3).astype(np.uint32)


def terrain_mesh(dem_m: np.ndarray, cell_m: float, k_factor=K_RADIO) -> tuple[np.ndarray, np.ndarray]:
    """The DEM as a triangle mesh: vertices (rows cols, 3) [m] at the cell centres, and its faces.

    Parameters
    ----------
    dem_m : numpy.ndarray (rows, cols)
        Terrain heights [m].
    cell_m : float
        Cell size [m].
    k_factor : float or None
        Effective Earth-radius factor of the curvature drop (module docstring); None: flat.
    """
    rows, cols = np.indices(dem_m.shape)
    x, y = local_xy(rows, cols, dem_m.shape, cell_m)
    z = dem_m - surface_drop_m(x, y, k_factor)
    return np.column_stack([x.ravel(), y.ravel(), z.ravel()]), grid_faces(*dem_m.shape)


def block_edges(n: int, step: int) -> np.ndarray:
    """Fractional cell coordinates of the edges of blocks of ``step`` cells along an axis of ``n`` cells.

    Block b covers cells b step .. min((b + 1) step, n) - 1; its edges lie half a cell beyond them,
    clipped to the span 0 .. n - 1 of the cell centres.
    """
    return np.clip(np.append(np.arange(0, n, step), n) - 0.5, 0.0, n - 1.0)


def measurement_mesh(
    dem_m: np.ndarray, cell_m: float, altitude_m: float, step: int = 1, k_factor=K_RADIO
) -> tuple[np.ndarray, np.ndarray]:
    """The flight level ``altitude_m`` above the terrain as a mesh of blocks of ``step`` x ``step`` cells.

    Returns
    -------
    vertices : numpy.ndarray (n_vertices, 3) [m]
        Corners of the blocks (:func:`block_edges`), in the frame of :func:`terrain_mesh`.
    faces : numpy.ndarray of uint32
        Two triangles per block (:func:`grid_faces`), blocks row-major.
    """
    r_edges, c_edges = block_edges(dem_m.shape[0], step), block_edges(dem_m.shape[1], step)
    rows, cols = np.meshgrid(r_edges, c_edges, indexing="ij")
    x, y = local_xy(rows, cols, dem_m.shape, cell_m)
    z = height_at(dem_m, rows, cols) + altitude_m - surface_drop_m(x, y, k_factor)
    return np.column_stack([x.ravel(), y.ravel(), z.ravel()]), grid_faces(len(r_edges), len(c_edges))


def triangle_areas_m2(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Areas [m^2] of the triangles ``faces`` of ``vertices``."""
    v0, v1, v2 = (vertices[faces[:, i].astype(np.int64)] for i in range(3))
    return 0.5 * np.linalg.norm(np.cross(v1 - v0, v2 - v0), axis=1)


def blocks_to_grid(values: np.ndarray, shape, step: int) -> np.ndarray:
    """Spread per-block values (n_block_rows, n_block_cols) over the DEM cells of each block."""
    return np.repeat(np.repeat(values, step, axis=0), step, axis=1)[: shape[0], : shape[1]]


def sector_cells(shape, tx_row: float, tx_col: float, sector_deg=None) -> np.ndarray:
    """The cells of a grid of ``shape`` inside the sensor's azimuth sector (all of them for None).

    ``sector_deg`` is ``(azimuth, width)`` [deg] as :class:`csuas.core.terrain.RayLimits`: a cell is inside
    when its bearing from (``tx_row``, ``tx_col``) (:func:`csuas.core.terrain.bearing_deg`) lies within
    ``width / 2`` of ``azimuth``, as the coverage layers' ``aimed`` cells; the sensor's own cell is in every
    sector.
    """
    if sector_deg is None:
        return np.ones(shape, dtype=bool)
    rows, cols = np.indices(shape)
    d_row, d_col = rows - tx_row, cols - tx_col
    aside = np.abs(off_boresight_deg(bearing_deg(d_row, d_col), sector_deg[0]))
    return (aside <= sector_deg[1] / 2.0) | ((d_row == 0) & (d_col == 0))


def cells_to_blocks(cells: np.ndarray, step: int) -> np.ndarray:
    """The blocks of ``step`` x ``step`` cells (:func:`block_edges`) holding at least one True cell."""
    n_rows, n_cols = -(-cells.shape[0] // step), -(-cells.shape[1] // step)
    padded = np.zeros((n_rows * step, n_cols * step), dtype=bool)
    padded[: cells.shape[0], : cells.shape[1]] = cells
    return padded.reshape(n_rows, step, n_cols, step).any(axis=(1, 3))


def sensor_blocks(shape, step: int, tx_row: float, tx_col: float) -> np.ndarray:
    """The blocks (:func:`block_edges`) whose footprint holds the sensor (1, or 2-4 on their edges)."""
    r_edges, c_edges = block_edges(shape[0], step), block_edges(shape[1], step)
    rows = (r_edges[:-1] <= tx_row) & (tx_row <= r_edges[1:])
    cols = (c_edges[:-1] <= tx_col) & (tx_col <= c_edges[1:])
    return rows[:, None] & cols[None, :]


def ray_band(sector_deg, shape, step: int, tx_row: float, tx_col: float, blocks: np.ndarray) -> tuple[float, float]:
    """The azimuth band the rays are folded into: (its first angle [rad], its share of the full turn).

    The sector ``(azimuth, width)`` widened to the whole footprint of every measured block (``blocks``,
    each corner's bearing from the sensor), so that no measured block is half lit; the blocks holding
    the sensor (:func:`sensor_blocks`) are left out of the widening (they surround it). Angles are
    counter-clockwise from east (x) in the local frame, a bearing b (clockwise from north) being the angle
    90 deg - b. None, or a band of a full turn: (-pi, 1), which leaves every direction where it is.
    """
    if sector_deg is None:
        return -np.pi, 1.0
    azimuth, width = sector_deg
    r_edges, c_edges = block_edges(shape[0], step), block_edges(shape[1], step)
    rows, cols = np.nonzero(blocks & ~sensor_blocks(shape, step, tx_row, tx_col))
    corners = [(r_edges[rows + i], c_edges[cols + j]) for i in (0, 1) for j in (0, 1)]
    off = np.array([off_boresight_deg(bearing_deg(r - tx_row, c - tx_col), azimuth) for r, c in corners])
    low, high = min(-width / 2.0, float(off.min(initial=0.0))), max(width / 2.0, float(off.max(initial=0.0)))
    # a block behind the sensor straddles the seam at 180 degrees (its corners on both sides)
    if high - low >= 360.0 or np.any(np.ptp(off, axis=0) > 180.0):
        return -np.pi, 1.0
    return float(np.radians(90.0 - azimuth - high)), float(high - low) / 360.0


def fold_directions(x, y, z, band: tuple[float, float]):
    """Unit directions (x, y, z) with their azimuth phi in [-pi, pi] mapped onto ``band``, z kept.

    phi' = first + share (phi + pi): uniform directions on the sphere map to uniform directions on the
    band (the area element dz dphi is scaled by ``share``), so each ray then stands for a solid angle
    ``share`` times the 4 pi / N Sionna gives it, and the radio map is scaled by ``share``. On Dr.Jit
    arrays.
    """
    import drjit as dr

    first, share = band
    phi = first + share * (dr.atan2(y, x) + np.pi)
    across = dr.safe_sqrt(1.0 - z * z)
    return across * dr.cos(phi), across * dr.sin(phi), z


@contextmanager
def turned_rays(rotation: np.ndarray, band: tuple[float, float] = (-np.pi, 1.0)):
    """Sionna's radio map solver shooting its Fibonacci lattice turned by ``rotation``, folded into ``band``.

    Sionna RT 2.2 fixes the lattice in the world frame (``spawn_ray_from_sources(fibonacci_lattice,
    ...)`` in ``sionna.rt.radio_map_solvers.radio_map_solver``) and has no argument for it, so this
    wraps that function for the duration of a solve: the lattice's directions d become R d, then
    :func:`fold_directions` maps them onto the sensor's azimuth band (left as they are for the full
    turn). Turning the rays by R^T is the same replica as turning the scene and the transmitter by R
    about the transmitter (what csuas did before), without rebuilding the scene's acceleration
    structure. R and the band enter as opaque Dr.Jit values, so every replica reuses one kernel.
    """
    import drjit as dr
    import mitsuba as mi
    from sionna.rt.radio_map_solvers import radio_map_solver as solver_module

    original = solver_module.spawn_ray_from_sources
    matrix = mi.Matrix3f(mi.ScalarMatrix3f(np.asarray(rotation, dtype=float)))
    first, share = dr.opaque(mi.Float, band[0]), dr.opaque(mi.Float, band[1])
    dr.make_opaque(matrix)

    def spawn(lattice, samples_per_src, src_positions):
        ray = original(lattice, samples_per_src, src_positions)
        d = matrix @ ray.d
        if band[1] < 1.0:
            d = mi.Vector3f(*fold_directions(d.x, d.y, d.z, (first, share)))
        ray.d = d
        return ray

    solver_module.spawn_ray_from_sources = spawn
    try:
        yield
    finally:
        solver_module.spawn_ray_from_sources = original


def rotation_matrix(angles_rad) -> np.ndarray:
    """Rotation matrix R = R_z(alpha) R_y(beta) R_x(gamma) of angles (alpha, beta, gamma) [rad].

    Sionna RT's convention for the orientation of devices and objects (3GPP TR 38.901 Eq. 7.1-4).
    """
    a, b, c = (float(v) for v in angles_rad)
    ca, sa, cb, sb, cc, sc = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(c), np.sin(c)
    return np.array(
        [
            [ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc],
            [sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc],
            [-sb, cb * sc, cb * cc],
        ]
    )


def random_rotation_angles(count: int, rng: np.random.Generator) -> np.ndarray:
    """Angles (count, 3) [rad] of rotations uniformly distributed over SO(3) (Haar measure).

    For R_z(alpha) R_y(beta) R_x(gamma) the Haar density is uniform in alpha, gamma and in sin(beta).
    """
    alpha, gamma = rng.uniform(-np.pi, np.pi, (2, count))
    beta = np.arcsin(rng.uniform(-1.0, 1.0, count))
    return np.column_stack([alpha, beta, gamma])


def bound_db(replicas: np.ndarray, level: float = BOUND_LEVEL) -> tuple[np.ndarray, np.ndarray]:
    """Mean of replicas (axis 0) of a power and the larger side of its error bound [dB] at ``level``.

    Returns
    -------
    mean : numpy.ndarray
    error_db : numpy.ndarray
        -10 log10(1 - t SE / mean) (module docstring); inf where t SE >= mean or the mean is 0.
    """
    from scipy.stats import t as student

    k = replicas.shape[0]
    mean = replicas.mean(axis=0)
    se = replicas.std(axis=0, ddof=1) / np.sqrt(k)
    factor = float(student.ppf(0.5 + level / 2.0, k - 1))
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where(mean > 0, factor * se / np.where(mean > 0, mean, 1.0), np.inf)
    return mean, lower_side_db(relative, 10.0)


@dataclass
class MeasurementSurface:
    """A flight level of a :class:`TerrainScene`, with the Mitsuba scene that holds it beside the terrain.

    Attributes
    ----------
    mesh : mitsuba.Mesh
        Two triangles per measured block (those of ``blocks``), blocks row-major.
    blocks : numpy.ndarray of bool (n_block_rows, n_block_cols)
        The blocks the surface holds (all of them, or those of the sensor's sector).
    areas_m2 : numpy.ndarray
        Triangle areas [m^2].
    mi_scene : mitsuba.Scene
        The terrain and this surface, built once (Sionna's ``modified_scene``): without it the radio
        map solver rebuilds a scene with the surface on every call (0.55 s of a 0.9 s replica, measured).
    """

    mesh: object
    blocks: np.ndarray
    areas_m2: np.ndarray
    mi_scene: object


@dataclass
class TerrainScene:
    """A Sionna scene holding one terrain mesh and one transmitter, and its flight levels.

    The scene stays where it was built: each replica turns the rays (:func:`turned_rays`), not the
    scene, so no replica rebuilds an acceleration structure.

    Attributes
    ----------
    scene : sionna.rt.Scene
    dem_m : numpy.ndarray
    cell_m : float
    k_factor : float or None
    transmitter : sionna.rt.Transmitter
    surfaces : OrderedDict
        (altitude_m, step, measured blocks) -> :class:`MeasurementSurface`, least recently used first.
    """

    scene: object
    dem_m: np.ndarray
    cell_m: float
    k_factor: float | None
    transmitter: object
    surfaces: OrderedDict = field(default_factory=OrderedDict)

    def surface(self, altitude_m: float, step: int, blocks: np.ndarray) -> MeasurementSurface:
        """The measurement surface ``altitude_m`` above the terrain over the ``blocks`` of ``step`` cells (cached)."""
        key = (float(altitude_m), int(step), blocks.shape, np.packbits(blocks).tobytes())
        if key in self.surfaces:
            self.surfaces.move_to_end(key)
            return self.surfaces[key]
        from sionna.rt.scene_utils import extend_scene_with_mesh

        vertices, faces = measurement_mesh(self.dem_m, self.cell_m, altitude_m, step, self.k_factor)
        faces = faces.reshape(-1, 2, 3)[blocks.ravel()].reshape(-1, 3)
        mesh = triangle_mesh("measurement", vertices, faces)
        surface = MeasurementSurface(
            mesh, blocks.copy(), triangle_areas_m2(vertices, faces), extend_scene_with_mesh(self.scene.mi_scene, mesh)
        )
        self.surfaces[key] = surface
        while len(self.surfaces) > SURFACE_CACHE_SIZE:
            self.surfaces.popitem(last=False)
        return surface


_terrain_cache: OrderedDict = OrderedDict()


def _terrain_key(dem: np.ndarray, cell_m: float, frequency_ghz: float, ground, k_factor) -> tuple:
    digest = hashlib.sha1(np.ascontiguousarray(dem).tobytes()).hexdigest()
    return digest, dem.shape, float(cell_m), float(frequency_ghz), ground, k_factor


def terrain_scene(dem_m: np.ndarray, cell_m: float, frequency_ghz: float, ground, k_factor=K_RADIO) -> TerrainScene:
    """The Sionna scene of a terrain at one frequency and material, built once and then reused.

    Parameters
    ----------
    dem_m : numpy.ndarray (rows, cols)
        Terrain heights [m] (checked by the caller).
    cell_m : float
        Cell size [m].
    frequency_ghz : float
        Carrier frequency [GHz], inside the ITU ranges of ``ground``.
    ground : str or tuple
        ITU-R P.2040 material of the terrain, or (relative permittivity, conductivity [S/m])
        (:func:`csuas.render.links.scene.ground_properties`).
    k_factor : float or None
        Effective Earth-radius factor of the curvature drop; None: flat.

    Returns
    -------
    TerrainScene
        With one transmitter ``tx0``, placed and oriented by each solve.
    """
    key = _terrain_key(dem_m, cell_m, frequency_ghz, ground, k_factor)
    cached = _terrain_cache.get(key)
    rt = load_sionna_rt()
    if cached is not None:
        _terrain_cache.move_to_end(key)
        return cached
    eps_r, sigma = ground_properties(ground, frequency_ghz)
    vertices, faces = terrain_mesh(dem_m, cell_m, k_factor)
    scene = rt.load_scene()
    scene.frequency = frequency_ghz * 1e9
    thickness = half_space_thickness_m(eps_r, sigma, frequency_ghz)
    if isinstance(ground, str):
        material = rt.ITURadioMaterial(name=f"terrain-{ground}", itu_type=ground, thickness=thickness)
    else:  # constants given: the same at every frequency
        material = rt.RadioMaterial(
            name="terrain-given", relative_permittivity=eps_r, conductivity=sigma, thickness=thickness
        )
    mesh = triangle_mesh("terrain", vertices, faces)
    scene.edit(add=[rt.SceneObject(mi_mesh=mesh, name="terrain", radio_material=material)])
    transmitter = rt.Transmitter(name="tx0", position=[0.0, 0.0, 0.0])
    scene.add(transmitter)
    cached = TerrainScene(scene, dem_m.copy(), float(cell_m), k_factor, transmitter)
    _terrain_cache[key] = cached
    while len(_terrain_cache) > TERRAIN_CACHE_SIZE:
        _terrain_cache.popitem(last=False)
    return cached


@cache
def radio_map_solver():
    """The process's ``sionna.rt.RadioMapSolver`` (it holds only its sampler).

    Its loops stay in Sionna's default symbolic mode: the evaluated mode the path solvers use
    (``SOLVER_LOOP_MODE``) keeps every ray's state per bounce in memory, 4.0 GB at 2^24 rays per
    replica against 0.27 GB symbolic, and was no faster (81 x 81 cells, 2 CPU cores, measured).
    """
    return load_sionna_rt().RadioMapSolver()


@dataclass
class TerrainRadioMap:
    """Path gain at a flight level over a DEM, per DEM cell.

    Attributes
    ----------
    path_gain_db : numpy.ndarray (rows, cols)
        10 log10 of the path gain averaged over the cell's measurement block (power sum of the rays,
        isotropic antennas) [dB]; -inf where no replica collected any ray, NaN outside the sensor's
        sector (not measured).
    error_db : numpy.ndarray (rows, cols)
        Bound on |path_gain_db - true| [dB] at level ``level``; inf where no bound exists, NaN outside
        the sector.
    reached : numpy.ndarray of bool (rows, cols)
        Some replica collected power there.
    reliable : numpy.ndarray of bool (rows, cols)
        Every replica collected power there (the bound holds at its level; elsewhere too few rays).
    time_s : float
        Wall time: scene look-up (or build), every replica's turned solve, post-processing [s].
    budget : LinkBudget
        Rays per replica (``samples``) and maximum depth.
    replicas : int
    level : float
    variant : str
        Mitsuba variant Sionna ran on.
    extra : dict
        Transmitter position in the local frame [m], measurement step, ground permittivity and
        conductivity, replica times [s], the cells measured (``in_sector``).
    """

    path_gain_db: np.ndarray
    error_db: np.ndarray
    reached: np.ndarray
    reliable: np.ndarray
    time_s: float
    budget: LinkBudget
    replicas: int
    level: float
    variant: str
    extra: dict = field(default_factory=dict)


@dataclass(frozen=True)
class RadioMapSite:
    """Where a terrain radio map is computed: the DEM, the sensor on its mast, the flight level, the carrier.

    Attributes
    ----------
    dem_m : array_like (rows, cols)
        Terrain heights [m], finite, square cells.
    cell_m : float
        Cell size [m].
    tx_row, tx_col : float
        The sensor's fractional cell position, inside the grid.
    mast_m : float
        The sensor's antenna above the terrain under it (bilinear DEM) [m], in (0, 1e5].
    altitude_m : float
        The flight level above the terrain [m], in (0, 1e5].
    frequency_ghz : float
        Carrier frequency [GHz], inside the ITU ranges of the ground (e.g. 1-10 GHz for
        ``medium_dry_ground``).
    sector_deg : (float, float), optional
        The sensor's azimuth sector ``(azimuth, width)`` [deg] (azimuth 0-360 clockwise from north, width
        in (0, 360]; :func:`sector_cells`): rays leave only over it and only its cells are measured. None:
        all round.
    """

    dem_m: Any
    cell_m: Any
    tx_row: Any
    tx_col: Any
    mast_m: Any
    altitude_m: Any
    frequency_ghz: Any
    sector_deg: Any = None


@dataclass(frozen=True)
class RadioMapOptions:
    """How a terrain radio map is traced.

    Attributes
    ----------
    ground : str or tuple
        ITU-R P.2040 material of the terrain (:func:`csuas.render.links.scene.itu_materials`), or
        its constants (relative permittivity, conductivity [S/m]) at any frequency.
    samples : int
        Rays per replica (1 to 1e8; :func:`radio_map_budget` chooses it for a requested bound).
    max_depth : int
        Maximum reflections per path (0 to 10).
    seed : int
        Seed of the replicas' rotations (and of Sionna's sampler); a seed gives the same map up to
        the order of Sionna's atomic float32 sums over the rays (1e-7 dB, measured).
    replicas : int
        Rotated solves (2 to 64); the error bound comes from their spread.
    step : int
        DEM cells per side of a measurement block (>= 1): 1 measures every cell.
    k_factor : float or None
        Effective Earth-radius factor (4/3 for radio); None for a flat Earth.
    polarization : {"V", "H"}
        Polarisation of the isotropic antenna of the sensor (the map is for an isotropic receiver
        summing both polarisations).
    los, reflection : bool
        Keep the direct rays / the specular reflections off the terrain.
    """

    ground: Any = DEFAULT_GROUND
    samples: Any = DEFAULT_SAMPLES
    max_depth: Any = DEFAULT_MAX_DEPTH
    seed: Any = 1
    replicas: Any = REPLICAS
    step: Any = 1
    k_factor: Any = K_RADIO
    polarization: Any = "V"
    los: Any = True
    reflection: Any = True


def _check_count(name: str, value, low: int, high: int, errors: list) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not low <= value <= high:
        errors.append(ParameterError(name, value, f"an integer from {low} to {high}"))
        return low
    return int(value)


def _check_inputs(site: RadioMapSite, options: RadioMapOptions, errors: list):
    """The arguments that shape the scene, checked; mistakes go to ``errors``.

    Returns the DEM, the cell size, the transmitter's row and column, the mast, the altitude and
    the frequency, each a usable placeholder where it was wrong.
    """
    dem, cell = np.zeros((2, 2)), 1.0
    try:
        dem, cell = check_dem(site.dem_m, site.cell_m)
    except ParameterError as exc:
        errors.append(exc)
    except InputErrors as exc:
        errors.extend(exc.errors)
    n_r, n_c = dem.shape
    try:
        row, col = float(site.tx_row), float(site.tx_col)
        if not (0.0 <= row <= n_r - 1 and 0.0 <= col <= n_c - 1):
            raise ValueError
    except (TypeError, ValueError):
        errors.append(
            ParameterError("tx position", (site.tx_row, site.tx_col), f"inside the grid 0..{n_r - 1} x 0..{n_c - 1}")
        )
        row = col = 0.0
    heights = []
    for name, value in (("mast_m", site.mast_m), ("altitude_m", site.altitude_m)):
        try:
            heights.append(check_height(name, value, over_ground=True))
        except ParameterError as exc:
            errors.append(exc)
            heights.append(1.0)
    frequency = 1.0
    try:
        frequency = check_frequency(site.frequency_ghz)
        ground_properties(options.ground, frequency)
    except ParameterError as exc:
        errors.append(exc)
    _check_sector(site.sector_deg, errors)
    k_factor = options.k_factor
    if k_factor is not None:
        try:
            if not (np.isfinite(float(k_factor)) and float(k_factor) > 0):
                raise ValueError
        except (TypeError, ValueError):
            errors.append(ParameterError("k_factor", k_factor, "None (flat Earth) or a number > 0"))
    if options.polarization not in ("V", "H"):
        errors.append(ParameterError("polarization", options.polarization, "V or H"))
    return dem, cell, row, col, heights[0], heights[1], frequency


def _check_sector(sector_deg, errors: list) -> None:
    """``sector_deg`` None or (azimuth in [0, 360], width in (0, 360]) [deg]; a mistake goes to ``errors``."""
    if sector_deg is None:
        return
    try:
        azimuth, width = (float(v) for v in sector_deg)
        if not (0.0 <= azimuth <= 360.0 and 0.0 < width <= 360.0):
            raise ValueError
    except (TypeError, ValueError):
        errors.append(ParameterError("sector_deg", sector_deg, "None or (azimuth in [0, 360], width in (0, 360]) deg"))


def _check_tracing(options: RadioMapOptions, shape, errors: list) -> tuple[RadioMapOptions, LinkBudget | None]:
    """The counts and flags of ``options`` checked (counts as ints), and the rays' budget; mistakes go to ``errors``."""
    step = _check_count("step", options.step, 1, max(shape), errors)
    replicas = _check_count("replicas", options.replicas, 2, 64, errors)
    seed = _check_count("seed", options.seed, 0, 2**31 - 1, errors)
    for name, flag in (("los", options.los), ("reflection", options.reflection)):
        if not isinstance(flag, bool):
            errors.append(ParameterError(name, flag, "True or False"))
    budget = None
    try:
        budget = resolve_budget(LinkBudget("custom", 1, 0), samples=options.samples, max_depth=options.max_depth)
    except ParameterError as exc:
        errors.append(exc)
    return replace(options, step=step, replicas=replicas, seed=seed), budget


def terrain_radio_map(site: RadioMapSite, options: RadioMapOptions = RadioMapOptions()) -> TerrainRadioMap:
    """Path gain [dB] from a sensor on a mast to every cell of a flight level over a DEM, by Sionna RT.

    Parameters
    ----------
    site : RadioMapSite
        The DEM, the sensor's cell and mast, the flight level and the carrier.
    options : RadioMapOptions
        Ground, rays per replica, depth, seed, replicas, measurement step, Earth, polarisation and
        which paths are kept.

    Returns
    -------
    TerrainRadioMap
        Arrays on the DEM grid (module docstring: -inf / inf where no ray came, NaN outside the sector);
        ``extra["in_sector"]`` the cells measured.

    Raises
    ------
    ParameterError or InputErrors
        Every invalid argument at once.
    """
    errors: list = []
    dem, cell, row, col, mast, altitude, frequency = _check_inputs(site, options, errors)
    options, budget = _check_tracing(options, dem.shape, errors)
    raise_all(errors)

    rt = load_sionna_rt()  # the first call imports Sionna: not part of the map's time
    start = time.perf_counter()
    sector = None if site.sector_deg is None else tuple(float(v) for v in site.sector_deg)
    inside = sector_cells(dem.shape, row, col, sector)
    terrain = terrain_scene(dem, cell, frequency, options.ground, options.k_factor)
    surface = terrain.surface(altitude, options.step, cells_to_blocks(inside, options.step))
    x, y = local_xy(row, col, dem.shape, cell)
    drop = float(surface_drop_m(x, y, options.k_factor))
    z = float(height_at(dem, np.array([row]), np.array([col]))[0]) + mast - drop
    tx_m = np.array([float(x), float(y), z])
    array = rt.PlanarArray(num_rows=1, num_cols=1, pattern="iso", polarization=options.polarization)
    terrain.scene.tx_array = terrain.scene.rx_array = array
    terrain.transmitter.position = [float(v) for v in tx_m]
    terrain.transmitter.orientation = [0.0, 0.0, 0.0]  # the rays turn, the antenna keeps its attitude
    band = ray_band(sector, dem.shape, options.step, row, col, surface.blocks)
    stack, replica_times = _replica_powers(terrain, surface, band, budget, options)
    mean, error = bound_db(stack, BOUND_LEVEL)
    reached, reliable = np.any(stack > 0, axis=0), np.all(stack > 0, axis=0)
    if band[1] < 1.0:  # the sector covers part of the blocks around the sensor: their mean is too low
        reliable &= ~sensor_blocks(dem.shape, options.step, row, col)
    with np.errstate(divide="ignore"):
        gain_db = 10.0 * np.log10(mean)
    elapsed = time.perf_counter() - start
    eps_r, sigma = ground_properties(options.ground, frequency)
    step = options.step
    return TerrainRadioMap(
        np.where(inside, blocks_to_grid(gain_db, dem.shape, step), np.nan),
        np.where(inside, blocks_to_grid(error, dem.shape, step), np.nan),
        blocks_to_grid(reached, dem.shape, step) & inside,
        blocks_to_grid(reliable, dem.shape, step) & inside,
        elapsed,
        budget,
        options.replicas,
        BOUND_LEVEL,
        active_variant() or "",
        {
            "tx_position_m": tx_m,
            "step": step,
            "relative_permittivity": eps_r,
            "conductivity_s_m": sigma,
            "replica_times_s": replica_times,
            "in_sector": inside,
        },
    )


def _replica_powers(terrain: TerrainScene, surface: MeasurementSurface, band, budget, options):
    """Block-averaged path gain of every rotated replica (replicas, *blocks) and each replica's time [s].

    Each replica turns the rays by the transpose of seeded random rotations, folds them into the
    sensor's azimuth ``band`` (:func:`turned_rays`) and solves Sionna's radio map on the measurement
    surface of the unmoved scene; blocks outside the surface stay 0 (not measured).
    """
    rng = np.random.default_rng(options.seed)
    areas = surface.areas_m2.reshape(-1, 2)
    powers, replica_times = [], []
    for k, angles in enumerate(random_rotation_angles(options.replicas, rng)):
        t0 = time.perf_counter()
        with turned_rays(rotation_matrix(angles).T, band):
            radio_map = radio_map_solver()(
                terrain.scene,
                measurement_surface=surface.mesh,
                samples_per_tx=budget.samples,
                max_depth=budget.max_depth,
                los=options.los,
                specular_reflection=options.reflection,
                diffuse_reflection=False,
                refraction=False,
                diffraction=False,
                seed=options.seed + k,
                modified_scene=surface.mi_scene,
            )
            gain = np.asarray(radio_map.path_gain.numpy(), dtype=float)[0].reshape(-1, 2) * band[1]
        power = np.zeros(surface.blocks.shape)
        power[surface.blocks] = np.sum(gain * areas, axis=1) / areas.sum(axis=1)
        powers.append(power)
        replica_times.append(time.perf_counter() - t0)
    return np.stack(powers), replica_times


#: Rays per replica :func:`radio_map_budget` starts from and may not exceed.
BUDGET_START_SAMPLES = 2**16
BUDGET_MAX_SAMPLES = 2**24


def radio_map_budget(
    target_db,
    site: RadioMapSite,
    options: RadioMapOptions = RadioMapOptions(),
    fraction=0.95,
    judged=None,
    start_samples=BUDGET_START_SAMPLES,
    max_samples=BUDGET_MAX_SAMPLES,
) -> tuple[LinkBudget, TerrainRadioMap]:
    """The rays per replica whose error bound meets ``target_db``: doubled from ``start_samples`` up to ``max_samples``.

    A cell meets the target when it is reliable (every replica reached it) and its bound is at
    most ``target_db``; the budget is met when a ``fraction`` of the ``judged`` cells do.

    Parameters
    ----------
    target_db : float
        Requested bound on the path gain's error [dB] (at the map's level, 95 %), > 0.
    site, options : RadioMapSite, RadioMapOptions
        As for :func:`terrain_radio_map` (``options.samples`` is replaced by each step's).
    fraction : float
        Fraction of the judged cells that must meet the target, in (0, 1].
    judged : numpy.ndarray of bool (rows, cols), optional
        Cells the target applies to. By default those in the sensor's line of sight
        (:func:`csuas.core.terrain.viewshed` with the map's ``k_factor``, 1e12 for a flat Earth) and its
        sector:
        a path surely reaches them, while a hidden cell may have none at any budget.
    start_samples, max_samples : int
        First and largest rays per replica (1 to 1e8).

    Returns
    -------
    budget : LinkBudget
        Named ``"bound_<target>dB"``, with the rays per replica reached and the depth.
    result : TerrainRadioMap
        The map of the last budget tried; ``extra["budget_steps"]`` lists each step's samples,
        met fraction and time [s], ``extra["budget_met"]`` whether the target was met.
    """

    k_factor = options.k_factor
    errors: list = []
    dem, cell, row, col, mast, altitude, _ = _check_inputs(site, options, errors)
    try:
        target = float(target_db)
        if not (np.isfinite(target) and target > 0):
            raise ValueError
    except (TypeError, ValueError):
        errors.append(ParameterError("target_db", target_db, "a bound > 0 dB"))
    try:
        share = float(fraction)
        if not 0 < share <= 1:
            raise ValueError
    except (TypeError, ValueError):
        errors.append(ParameterError("fraction", fraction, "(0, 1]"))
    first = _check_count("start_samples", start_samples, 1, 100_000_000, errors)
    last = _check_count("max_samples", max_samples, first, 100_000_000, errors)
    if judged is not None and not any(e.name == "dem_m" for e in errors):
        judged = np.asarray(judged)
        if judged.shape != dem.shape or judged.dtype != bool:
            errors.append(
                ParameterError("judged", f"array of shape {judged.shape}", f"a bool mask of shape {dem.shape}")
            )
    raise_all(errors)
    if judged is None:
        judged = viewshed(dem, cell, row, col, mast, altitude, 1e12 if k_factor is None else k_factor)
        judged &= sector_cells(dem.shape, row, col, site.sector_deg)
    samples, steps = first, []
    while True:
        result = terrain_radio_map(site, replace(options, samples=samples))
        met = result.reliable & (result.error_db <= target)
        share_met = float(met[judged].mean()) if judged.any() else 1.0
        steps.append({"samples": samples, "fraction_met": share_met, "time_s": result.time_s})
        if share_met >= share or 2 * samples > last:
            break
        samples *= 2
    result.extra.update(budget_steps=steps, budget_met=share_met >= share)
    return LinkBudget(f"bound_{target:g}dB", samples, result.budget.max_depth), result
