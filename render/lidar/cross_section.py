"""Monostatic lidar cross-section (LCS) of a Lambertian mesh by Monte Carlo ray tracing.

Physics (single bounce)
-----------------------
A monostatic lidar at distance ``R`` in direction ``d`` (from the target
toward the sensor) illuminates the target with irradiance ``E`` and measures
the radiant intensity ``I`` scattered back toward itself; the lidar
cross-section is ``sigma = 4 pi I / E`` (docs/simulation.md; paper Section 2.3.6). For a
Lambertian surface element ``dA`` of albedo ``rho`` hit at incidence ``theta``
the irradiance is ``E cos(theta)``, the radiance ``(rho / pi) E cos(theta)``,
and the intensity sent back along the same line
``dI = (rho / pi) E cos^2(theta) dA``. Writing ``dA_p = cos(theta) dA`` for
the element's area projected on the plane normal to the beam,

    sigma = 4 pi I / E = 4 pi * sum (rho / pi) cos(theta) dA_p = 4 rho * sum cos(theta) dA_p,

which gives the oracles ``(8/3) rho pi a^2`` for a sphere and
``4 rho A cos^2(theta)`` for a flat plate (docs/validation.md). Rays are cast from
the sensor side toward the target through a jittered grid over the target's
projected window; each first hit contributes Mitsuba's BSDF value
``f_r cos(theta_o)`` (``bsdf.eval`` of a two-sided ``diffuse``) times the
area of its grid cell. Shadowing is exact: the return path to a monostatic
sensor is the incoming ray reversed, which the first-hit query has already
found unobstructed. Multiple bounces between parts are ignored (they add
light scattered off a second surface; for albedos below ~0.5 and the open
geometry of a drone they are a few per cent at most).

Range-normalised coordinates and the near-range correction
----------------------------------------------------------
The ray tracer works in float32, so the sensor is never placed at its true
position. The target stays at the origin (:class:`LidarTarget` is centred in
float64) and the rays start on a plane just in front of it; only their
directions carry the range. For ``range_m = inf`` (plane wave, the far-field
LCS of Eqs. 7-9) they are all ``-d``. For a finite range they diverge from the
sensor position ``R d`` (a point source: spherical wave) and each ray is
weighted by the exact solid angle it represents and by ``(R / r)^4`` for the
spread to and from its hit point at distance ``r`` (computed in float64 from
the hit distance), so that the result is ``4 pi R^2 P_rx / (E_0 A_rx)``, the
cross-section referred to the target centre that a lidar equation with range
``R`` needs. This differs from the far-field LCS by ``O(size / R)``: for a
Lambertian sphere of radius ``a`` it is
``8 pi rho a^2 * integral_eps^1 (x - eps)^2 / (1 - 2 eps x + eps^2)^3 dx``
with ``eps = a / R`` (+1.5 % for a = 0.1 m at 10 m), and the tests check that
closed form at 10 m and the far-field value at 20 km.

Monte Carlo estimate and error
------------------------------
The window (bounding box of the perspective-projected vertices) is divided
into ``grid x grid`` roughly square cells with one uniformly jittered ray per
cell (stratified sampling; error ``~ N^(-3/4)`` for silhouette edges). The
whole grid is repeated ``replicates`` times with independent jitter; each
replicate is an unbiased estimate, and the spread of the replicate values
gives the standard error (Owen, "Monte Carlo theory, methods and examples",
ch. 10 and 17).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from csuas.base.errors import ParameterError
from csuas.drone_models.geometry import direction_vector, validate_angles, view_basis
from csuas.render.quality import LIDAR

#: Single-direction accuracy presets from :data:`csuas.render.quality.LIDAR`: name -> (grid cells per side, replicates).
QUALITY_PRESETS = LIDAR.presets()

#: Rays handed to Mitsuba per ``ray_intersect`` call (bounds memory: ~100 bytes per ray).
MAX_RAYS_PER_BATCH = 1 << 22

#: The ray origins lie on the plane ``x . d = ORIGIN_PLANE_FACTOR * bounding radius``.
ORIGIN_PLANE_FACTOR = 1.01

#: Smallest window side, as a fraction of the bounding radius (edge-on flat targets).
MIN_WINDOW_FRACTION = 1e-9

#: The sensor must be farther than this multiple of the bounding radius.
MIN_RANGE_FACTOR = 1.05


@dataclass
class LcsResult:
    """Lidar cross-section toward one direction.

    Attributes
    ----------
    lcs_m2, stderr_m2 : float
        LCS ``4 pi I / E`` [m^2] and its Monte Carlo standard error [m^2].
    projected_area_m2, projected_area_stderr_m2 : float
        Ray-traced projected (silhouette) area on the plane through the
        target centre [m^2], a by-product of the same rays, with its error.
    range_m : float
        Sensor distance [m] (``inf``: plane wave).
    direction : numpy.ndarray, shape (3,)
        Unit vector from the target toward the sensor.
    grid, replicates, rays : int
        Cells per side, independent jitter replicates, rays traced.
    quality : str
        Preset name, or ``"custom"``.
    time_s : float
        Wall time [s], scene building excluded.
    window_m : tuple of float
        ``(u_min, u_max, v_min, v_max)`` of the sampled window in the image
        axes ``h``, ``v`` of :func:`csuas.drone_models.geometry.view_basis` [m].
    image_m2 : numpy.ndarray or None
        LCS per cell, shape ``(n_v, n_u)``, row 0 at ``v_max`` [m^2 per
        pixel]; sums to ``lcs_m2``.
    """

    lcs_m2: float
    stderr_m2: float
    projected_area_m2: float
    projected_area_stderr_m2: float
    range_m: float
    direction: np.ndarray
    grid: int
    replicates: int
    rays: int
    quality: str
    time_s: float
    window_m: tuple
    image_m2: np.ndarray | None = field(default=None, repr=False)

    def as_dict(self) -> dict:
        """JSON-ready summary (no image)."""
        return {
            "lcs_m2": self.lcs_m2,
            "stderr": self.stderr_m2,
            "projected_area_traced_m2": self.projected_area_m2,
            "projected_area_traced_stderr_m2": self.projected_area_stderr_m2,
            "range_m": self.range_m,
            "direction": [float(x) for x in self.direction],
            "grid": self.grid,
            "replicates": self.replicates,
            "rays": self.rays,
            "quality": self.quality,
            "time_s": self.time_s,
            "method": "single_bounce",
        }


@dataclass(frozen=True)
class RayGrid:
    """The rays of one direction: a quality of its own, beside the presets of :data:`QUALITY_PRESETS`.

    Attributes
    ----------
    grid : int
        Cells per window side (one jittered ray per cell; ~ film pixels per side of a path-traced render).
    replicates : int
        Independent jitter replicates (renders), whose spread gives the standard error.
    """

    grid: int
    replicates: int


def resolve_quality(quality, presets: dict = QUALITY_PRESETS) -> tuple:
    """Return ``(grid, replicates, name)`` of a preset name, or of a :class:`RayGrid` (name ``"custom"``).

    Raises
    ------
    ParameterError
        Unknown preset, ``grid < 1`` or ``replicates < 2``.
    """
    if isinstance(quality, RayGrid):
        g, r, name = quality.grid, quality.replicates, "custom"
    elif quality in presets:
        (g, r), name = presets[quality], quality
    else:
        raise ParameterError("quality", quality, ", ".join(presets) + " or a RayGrid")
    if not isinstance(g, (int, np.integer)) or isinstance(g, bool) or g < 1:
        raise ParameterError("grid", g, "integer >= 1")
    if not isinstance(r, (int, np.integer)) or isinstance(r, bool) or r < 2:
        raise ParameterError("replicates", r, "integer >= 2")
    return int(g), int(r), name


def check_range(range_m, bounding_radius_m: float) -> float:
    """Validate a sensor range [m]: ``inf`` or finite and beyond the target's bounding sphere."""
    try:
        r = float(range_m)
    except (TypeError, ValueError):
        raise ParameterError("range_m", range_m, "a number > 0 m") from None
    limit = MIN_RANGE_FACTOR * bounding_radius_m
    if math.isnan(r) or r <= limit:
        raise ParameterError(
            "range_m",
            range_m,
            f"x > {limit:.4g} m ({MIN_RANGE_FACTOR} x the target's bounding radius), or inf for a plane wave",
        )
    return r


@dataclass
class _Window:
    """Sampling window of one direction: origin corner, cell sizes and counts."""

    d: np.ndarray
    h: np.ndarray
    v: np.ndarray
    u0: float
    w0: float
    du: float
    dw: float
    n_u: int
    n_v: int


def sampling_windows(
    vertices: np.ndarray, radius: float, d: np.ndarray, az, range_m: float, grid: int, beam_radius_m: float | None
) -> list:
    """Sampling windows, one per direction, on the plane through the target centre normal to it.

    Each window is the bounding box of the vertices' perspective projection
    from the sensor (orthographic for ``range_m = inf``) in the image axes of
    :func:`csuas.drone_models.geometry.view_basis`, clipped to the beam, and
    split into about ``grid^2`` square cells.
    """
    h, v = view_basis(d, az)
    x, y, z = vertices @ h.T, vertices @ v.T, vertices @ d.T  # (n_vert, n_dir)
    if math.isfinite(range_m):
        scale = range_m / (range_m - z)
        x, y = x * scale, y * scale
    # an edge-on flat target projects to a segment: widen zero extents to a sliver so the window has an area
    sliver = 0.5 * MIN_WINDOW_FRACTION * radius
    lo_u, hi_u = x.min(axis=0), x.max(axis=0)
    lo_w, hi_w = y.min(axis=0), y.max(axis=0)
    mid_u, mid_w = 0.5 * (lo_u + hi_u), 0.5 * (lo_w + hi_w)
    lo_u, hi_u = np.minimum(lo_u, mid_u - sliver), np.maximum(hi_u, mid_u + sliver)
    lo_w, hi_w = np.minimum(lo_w, mid_w - sliver), np.maximum(hi_w, mid_w + sliver)
    if beam_radius_m is not None:
        lo_u, hi_u = np.maximum(lo_u, -beam_radius_m), np.minimum(hi_u, beam_radius_m)
        lo_w, hi_w = np.maximum(lo_w, -beam_radius_m), np.minimum(hi_w, beam_radius_m)
    out = []
    for j in range(len(d)):
        wu, ww = hi_u[j] - lo_u[j], hi_w[j] - lo_w[j]
        if wu <= 0.0 or ww <= 0.0:  # beam misses the target's window
            out.append(_Window(d[j], h[j], v[j], 0.0, 0.0, 0.0, 0.0, 0, 0))
            continue
        n_u = int(np.clip(round(grid * math.sqrt(wu / ww)), 1, grid * grid))
        n_v = int(np.clip(round(grid * grid / n_u), 1, grid * grid))
        out.append(_Window(d[j], h[j], v[j], lo_u[j], lo_w[j], wu / n_u, ww / n_v, n_u, n_v))
    return out


def _intersect(scene, origins: np.ndarray, directions: np.ndarray) -> tuple:
    """First hits of rays (float64 arrays (n, 3)): ``(f_r cos, distance, hit)`` as NumPy arrays.

    ``f_r cos`` is Mitsuba's BSDF value toward the sensor (the reversed ray).
    """
    import drjit as dr
    import mitsuba as mi

    ray = mi.Ray3f(
        mi.Point3f(np.ascontiguousarray(origins.T, dtype=np.float32)),
        mi.Vector3f(np.ascontiguousarray(directions.T, dtype=np.float32)),
    )
    si = scene.ray_intersect(ray)
    hit = si.is_valid()
    bsdf = si.bsdf(ray)
    value = bsdf.eval(mi.BSDFContext(), si, si.to_local(-ray.d), hit)
    value = dr.select(hit, value, 0.0)
    distance = dr.select(hit, si.t, 0.0)
    dr.eval(value, distance, hit)
    return (
        np.asarray(value, dtype=np.float64).ravel(),
        np.asarray(distance, dtype=np.float64),
        np.asarray(hit, dtype=bool),
    )


def trace_lcs(
    target,
    directions,
    azimuth_deg=None,
    range_m: float = math.inf,
    rays: RayGrid = RayGrid(128, 8),
    seed: int = 0,
    beam_radius_m: float | None = None,
    keep_images: bool = False,
) -> dict:
    """LCS and traced projected area of ``target`` for many directions and jitter replicates.

    Parameters
    ----------
    target : LidarTarget
    directions : array_like, shape (n, 3)
        Unit vectors from the target toward the sensor.
    azimuth_deg : array_like, optional
        Azimuths [deg] of the directions (only for the image axes at the poles).
    range_m : float
        Sensor distance [m], ``inf`` for a plane wave.
    rays : RayGrid
        Cells per window side and independent jitter replicates (not checked: 1 replicate is allowed).
    seed : int
        Seed of the jitter (results are deterministic for a seed).
    beam_radius_m : float, optional
        Radius of a top-hat beam centred on the target centre, on the plane
        through it [m]; ``None``: the whole target is illuminated.
    keep_images : bool
        Also return the per-cell LCS images (averaged over replicates).

    Returns
    -------
    dict
        ``lcs_m2`` and ``area_m2`` of shape (n, replicates) [m^2],
        ``windows`` (list), ``rays`` (int), ``images`` (list or None).
    """
    scene = target.scene()
    grid, replicates = rays.grid, rays.replicates
    d = np.atleast_2d(np.asarray(directions, dtype=float))
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    radius = target.bounding_radius_m
    windows = sampling_windows(target.vertices, radius, d, azimuth_deg, range_m, grid, beam_radius_m)
    rng = np.random.default_rng(seed)
    sums = _LcsSums(
        np.zeros((len(d), replicates)),
        np.zeros((len(d), replicates)),
        [np.zeros((w.n_v, w.n_u)) for w in windows] if keep_images else None,
    )
    # tasks = (direction, replicate); batched so one batch holds at most MAX_RAYS_PER_BATCH rays
    tasks = [(j, r) for j in range(len(d)) for r in range(replicates) if windows[j].n_u]
    batch, batch_rays = [], 0
    total_rays = 0
    for task in tasks + [None]:
        n_task = 0 if task is None else windows[task[0]].n_u * windows[task[0]].n_v
        if batch and (task is None or batch_rays + n_task > MAX_RAYS_PER_BATCH):
            total_rays += _trace_batch(scene, windows, batch, range_m, radius, rng, beam_radius_m, sums)
            batch, batch_rays = [], 0
        if task is not None:
            batch.append(task)
            batch_rays += n_task
    images = None if sums.images is None else [img / replicates for img in sums.images]
    return {"lcs_m2": sums.lcs, "area_m2": sums.area, "windows": windows, "rays": total_rays, "images": images}


@dataclass
class _LcsSums:
    """Per (direction, replicate) LCS and traced area [m^2], and per-direction LCS images summed over replicates."""

    lcs: np.ndarray
    area: np.ndarray
    images: list | None


def _trace_batch(scene, windows, batch, range_m, radius, rng, beam_radius_m, sums: _LcsSums) -> int:
    """Trace one batch of (direction, replicate) tasks and accumulate into ``sums``."""
    origins, dirs, weights_pre, uu, ww, sizes = [], [], [], [], [], []
    r_front = ORIGIN_PLANE_FACTOR * radius
    for j, _ in batch:
        w = windows[j]
        iu, iv = np.meshgrid(np.arange(w.n_u), np.arange(w.n_v), indexing="xy")
        u = w.u0 + (iu.ravel() + rng.random(iu.size)) * w.du
        v = w.w0 + (iv.ravel() + rng.random(iv.size)) * w.dw
        p = u[:, None] * w.h + v[:, None] * w.v  # on the plane through the centre
        if math.isfinite(range_m):
            dist = np.sqrt(range_m * range_m + u * u + v * v)  # sensor to p
            direction = (p - range_m * w.d) / dist[:, None]
            s = -r_front * dist / range_m  # step back from p to the origin plane (negative)
            origin = p + s[:, None] * direction
            # solid angle (cos alpha / |p - S|^2) and 1/r^2 spread, normalised by R: (R/dist)^3, (R/r)^2 below
            weights_pre.append(np.stack([(range_m / dist) ** 3, dist + s], axis=1))
        else:
            direction = np.broadcast_to(-w.d, p.shape)
            origin = p + r_front * w.d
            weights_pre.append(np.ones((len(u), 2)))
        if beam_radius_m is not None:
            weights_pre[-1][:, 0] *= (u * u + v * v) <= beam_radius_m * beam_radius_m
        origins.append(origin)
        dirs.append(direction)
        uu.append(u)
        ww.append(v)
        sizes.append(len(u))
    value, distance, hit = _intersect(scene, np.concatenate(origins), np.concatenate(dirs))
    pre = np.concatenate(weights_pre)
    factor = pre[:, 0]
    if math.isfinite(range_m):
        factor = factor * (range_m / (pre[:, 1] + distance)) ** 2
    bounds = np.cumsum([0] + sizes)
    for k, (j, r) in enumerate(batch):
        sl = slice(bounds[k], bounds[k + 1])
        cell = windows[j].du * windows[j].dw
        contribution = 4.0 * math.pi * cell * value[sl] * factor[sl]
        sums.lcs[j, r] = contribution.sum()
        sums.area[j, r] = cell * np.count_nonzero(hit[sl] & (pre[sl, 0] > 0.0))
        if sums.images is not None:
            sums.images[j] += contribution.reshape(windows[j].n_v, windows[j].n_u)[::-1]
    return int(bounds[-1])


def lidar_cross_section(
    target,
    azimuth_deg: float = 0.0,
    elevation_deg: float = 0.0,
    range_m: float = math.inf,
    quality: str | RayGrid = "standard",
    seed: int = 0,
    beam_radius_m: float | None = None,
    keep_image: bool = False,
) -> LcsResult:
    """Monostatic LCS of ``target`` seen from one direction, with its standard error and time.

    Parameters
    ----------
    target : LidarTarget
    azimuth_deg, elevation_deg : float
        Direction from the target toward the sensor [deg] (docs/command-line.md convention).
    range_m : float
        Sensor distance [m]; ``inf`` (default) for a plane wave.
    quality : {"draft", "standard", "reference"} or RayGrid
        Preset of :data:`QUALITY_PRESETS`, or the rays' grid and replicates (quality ``"custom"``).
    seed : int
    beam_radius_m : float, optional
        Radius of a top-hat beam centred on the target centre [m], on the
        plane through the centre normal to the view; ``None`` illuminates it
        all. ``projected_area_m2`` is then the illuminated projected area.
    keep_image : bool
        Return the per-pixel LCS image.

    Returns
    -------
    LcsResult
    """
    az, el = validate_angles(azimuth_deg, elevation_deg)
    if az.ndim or el.ndim:
        raise ParameterError("azimuth_deg/elevation_deg", (azimuth_deg, elevation_deg), "scalars")
    g, r, name = resolve_quality(quality)
    rng_m = check_range(range_m, target.bounding_radius_m)
    if beam_radius_m is not None and not (math.isfinite(float(beam_radius_m)) and beam_radius_m > 0.0):
        raise ParameterError("beam_radius_m", beam_radius_m, "x > 0 m, or None for full illumination")
    target.scene()  # build (and select the variant) outside the timed section
    start = time.perf_counter()
    d = direction_vector(az, el)
    out = trace_lcs(target, d[None, :], np.atleast_1d(az), rng_m, RayGrid(g, r), seed, beam_radius_m, keep_image)
    values, areas = out["lcs_m2"][0], out["area_m2"][0]
    w = out["windows"][0]
    elapsed = time.perf_counter() - start
    return LcsResult(
        lcs_m2=float(values.mean()),
        stderr_m2=float(values.std(ddof=1) / math.sqrt(r)),
        projected_area_m2=float(areas.mean()),
        projected_area_stderr_m2=float(areas.std(ddof=1) / math.sqrt(r)),
        range_m=rng_m,
        direction=d,
        grid=g,
        replicates=r,
        rays=out["rays"],
        quality=name,
        time_s=elapsed,
        window_m=(w.u0, w.u0 + w.n_u * w.du, w.w0, w.w0 + w.n_v * w.dw),
        image_m2=out["images"][0] if keep_image else None,
    )
