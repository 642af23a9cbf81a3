"""Monte Carlo tally of a pixel window: coverage, target radiance and silhouette extents.

Camera rays are generated here (float64 directions, jittered n x n per pixel,
see :mod:`csuas.render.imaging.camera`) and intersected with the Mitsuba
scene; rays that hit the target are shaded by Mitsuba's path tracer
(``SamplingIntegrator.sample``). The sky or background behind the target is
not traced: it is uniform and known, and is composited analytically from
the coverage (:mod:`csuas.render.imaging.measure`).

Samples are drawn in ``n_batches`` independent batches (distinct seeds) so
that every figure gets a Monte Carlo standard error, and each batch is
launched in chunks of at most ``max_launch`` rays, which bounds memory
whatever the sample count.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from csuas.render.imaging.camera import Framing, Window, jittered_film_samples, ray_directions, sampled_areas

#: Rays per Dr.Jit launch (bounds memory: about 0.5 GiB on the LLVM back-end).
MAX_LAUNCH = 1 << 21
#: A target's box gets at least the samples of a target this many pixels in area (per batch,
#: times n_side**2): sub-pixel targets keep the precision of an 8 x 8 px image.
MIN_BOX_PIXELS = 64
#: Alignment Dr.Jit's LLVM kernels assume of an input that allows it [bytes].
JIT_ALIGNMENT_BYTES = 64


def _aligned_copy(values: np.ndarray) -> np.ndarray:
    """A float32 copy of ``values`` whose buffer starts on a 64-byte boundary."""
    buffer = np.empty(values.size + JIT_ALIGNMENT_BYTES // 4, dtype=np.float32)
    start = (-buffer.ctypes.data % JIT_ALIGNMENT_BYTES) // 4
    out = buffer[start : start + values.size]
    out[:] = values
    return out


def padded_wavefront(size: int) -> int:
    """The number of rays a shading launch of ``size`` rays is padded to: the next power of two.

    Mitsuba's sampler compiles its wavefront size into the kernel, so launches of as many sizes as
    there are hit counts would each build the path tracer anew; padded, a whole data set needs a few.
    """
    return 1 << max(int(size) - 1, 0).bit_length()


def camera_rays(camera_distance: float, directions: np.ndarray):
    """Mitsuba rays from the camera at (0, 0, distance) of the render frame along ``directions`` (3, n).

    Built so that every render reuses the kernels Dr.Jit has already compiled: the camera's
    position is an opaque input rather than a constant of the kernel, and the directions, which
    Dr.Jit maps from NumPy without a copy, sit on 64-byte boundaries, since Dr.Jit compiles a
    kernel for each alignment of its inputs (with :func:`padded_wavefront` for the sampler's size).
    Otherwise a new range or an unlucky allocation builds the path tracer anew: about 0.14 s of LLVM
    compilation on 2 cores, against 0.02 s of tracing at draft quality.
    """
    import drjit as dr
    import mitsuba as mi

    origin = dr.opaque(mi.Point3f, [0.0, 0.0, float(camera_distance)])
    return mi.Ray3f(origin, mi.Vector3f(*(_aligned_copy(c) for c in directions)))


@dataclass
class WindowTally:
    """Per-batch Monte Carlo estimates over a window.

    Attributes
    ----------
    coverage : ndarray, shape (K, H, W)
        Fraction of each pixel's area covered by the target, per batch.
    radiance : ndarray, shape (K, C, H, W)
        Pixel-averaged radiance of the target alone (0 where no target), per batch.
    extent : ndarray, shape (K, 4)
        Silhouette extremes per batch, x_min, x_max, y_min, y_max [film px]:
        each batch's extreme hits refined by :func:`refine_extremes` (NaN
        where a batch has no hit).
    samples : int
        Camera rays traced in total.
    n_side : int
        Strata per pixel side actually used (raised for small targets, see :data:`MIN_BOX_PIXELS`).
    nonfinite_samples : int
        Shaded samples whose radiance was NaN or inf (counted as 0 and reported).
    time_s : float
        Wall time of the tally [s].
    """

    coverage: np.ndarray
    radiance: np.ndarray
    extent: np.ndarray
    samples: int
    time_s: float
    n_side: int
    nonfinite_samples: int = 0

    @property
    def n_batches(self) -> int:
        return self.coverage.shape[0]


@dataclass(frozen=True)
class Sampling:
    """How many camera rays a window tally traces, and in launches of what size.

    Attributes
    ----------
    n_side, n_batches : int
        Samples per pixel and batch (n_side**2) and number of independent batches.
    seed : int
        Seed of the batch generators (deterministic results for a given seed).
    channels : int
        3 for ``*_rgb`` variants, 1 for ``*_mono``.
    max_launch : int
        Upper bound of rays per launch (memory bound).
    min_box_pixels : int
        With the framing's ``bounds``: n_side is raised until the box gets at least
        ``min_box_pixels * n_side**2`` samples per batch (0: never raised).
    """

    n_side: int
    n_batches: int
    seed: int = 0
    channels: int = 3
    max_launch: int = MAX_LAUNCH
    min_box_pixels: int = MIN_BOX_PIXELS


def trace_window(
    scene, integrator, framing: Framing, sampling: Sampling, *, medium=None, geometry=None, progress=None
) -> WindowTally:
    """Trace ``n_batches`` x ``n_side**2`` jittered samples in every pixel of the framing's window.

    Parameters
    ----------
    scene, integrator
        Mitsuba scene in the render frame and a sampling integrator.
    framing : Framing
        Sensor, window, target position, camera distance and the sampling box ``bounds``: pixels
        are sampled only inside it (:func:`~csuas.render.imaging.camera.jittered_film_samples`),
        and pixels outside it are not sampled at all.
    sampling : Sampling
        Samples per pixel, batches, seed, channels and launch size.
    medium : mitsuba.Medium or None
        Medium that contains the camera (a participating atmosphere); None: vacuum.
    geometry : mitsuba.Scene or None
        Scene of the target alone, for coverage and extents, when ``scene``
        holds more shapes (a medium's boundary); None: ``scene``.
    progress : callable(done_fraction) or None
    """
    import drjit as dr

    t0 = time.perf_counter()
    window, bounds, n_batches, channels = framing.window, framing.bounds, sampling.n_batches, sampling.channels
    n_px = window.n_pixels
    active = np.flatnonzero(sampled_areas(window, np.arange(n_px), bounds) > 0)
    n_side = _strata_per_side(sampling, active.size, bounds)
    sums = _Sums.empty(n_batches, n_px, channels)
    geometry = scene if geometry is None else geometry
    shading = _Shading(scene, integrator, medium, framing.camera_distance, channels, sampling.seed, n_batches)
    rngs = [np.random.default_rng([int(sampling.seed), b]) for b in range(n_batches)]
    launches = _launches(n_batches, active.size, n_side, sampling.max_launch)
    for i, launch in enumerate(launches):
        x, y, weight, owner, batch = _launch_samples(window, bounds, active, launch, n_side, rngs)
        d = ray_directions(x, y, framing.sensor, framing.target_px).astype(np.float32)
        hit = np.array(geometry.ray_intersect(camera_rays(framing.camera_distance, d)).is_valid(), dtype=bool)
        idx = np.flatnonzero(hit)
        if idx.size:
            sums.add(owner[idx], weight[idx], shading.values(d, idx))
            sums.push_anchors(x, y, batch, idx)
        if progress is not None:
            progress((i + 1) / len(launches))
    dr.sync_thread()
    shape = (window.height, window.width)
    return WindowTally(
        sums.coverage.reshape(n_batches, *shape),
        sums.radiance.reshape(channels, n_batches, n_px).transpose(1, 0, 2).reshape(n_batches, channels, *shape),
        _refined_extent(geometry, framing, sums.anchors, n_side),
        n_batches * active.size * n_side * n_side,
        time.perf_counter() - t0,
        n_side,
        shading.nonfinite,
    )


#: Sides of the silhouette's extremes, (axis, sign): x_min, x_max, y_min, y_max.
_SIDES = ((0, -1.0), (0, 1.0), (1, -1.0), (1, 1.0))


def _strata_per_side(sampling: Sampling, n_active: int, bounds) -> int:
    """The strata per pixel side: ``sampling.n_side``, raised for a small box (:data:`MIN_BOX_PIXELS`)."""
    n_side = sampling.n_side
    if bounds is not None and sampling.min_box_pixels > 0:
        n_side = max(n_side, math.ceil(n_side * math.sqrt(sampling.min_box_pixels / n_active)))
    return n_side


def _launches(n_batches: int, n_active: int, n_side: int, max_launch: int) -> list:
    """Work units (batch, first pixel, last pixel) packed into launches of at most ``max_launch`` rays."""
    n2 = n_side * n_side
    chunk = max(1, max_launch // n2)
    units = [(b, p0, min(p0 + chunk, n_active)) for b in range(n_batches) for p0 in range(0, n_active, chunk)]
    launches, current, size = [], [], 0
    for unit in units:
        rays = (unit[2] - unit[1]) * n2
        if current and size + rays > max_launch:
            launches.append(current)
            current, size = [], 0
        current.append(unit)
        size += rays
    launches.append(current)
    return launches


def _launch_samples(window: Window, bounds, active: np.ndarray, launch: list, n_side: int, rngs: list) -> tuple:
    """Film positions x, y, weights [px^2], owning (batch, pixel) cells and batches of one launch's samples."""
    n2, n_px = n_side * n_side, window.n_pixels
    xs, ys, areas, owners, batches = [], [], [], [], []
    for b, p0, p1 in launch:
        pixels = active[p0:p1]
        x, y, area = jittered_film_samples(window, pixels, n_side, rngs[b], bounds)
        xs.append(x)
        ys.append(y)
        areas.append(np.repeat(area / n2, n2))
        owners.append(np.repeat(b * n_px + pixels, n2))
        batches.append(np.full(x.size, b))
    return tuple(np.concatenate(v) for v in (xs, ys, areas, owners, batches))


@dataclass
class _Shading:
    """Mitsuba's path tracer on the camera rays that hit, with its own seeds and a count of non-finite samples."""

    scene: object
    integrator: object
    medium: object
    camera_distance: float
    channels: int
    seed: int
    n_batches: int
    nonfinite: int = 0

    def __post_init__(self):
        import mitsuba as mi

        self.sampler = mi.load_dict({"type": "independent"})
        # path-tracer seeds, apart from the positions
        self.rng = np.random.default_rng([int(self.seed), self.n_batches, 1])

    def values(self, d: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """Radiance (channels, len(idx)) of the rays ``d[:, idx]``; non-finite samples counted and set to 0."""
        import drjit as dr
        import mitsuba as mi

        shaded = np.resize(idx, padded_wavefront(idx.size))  # repeats the first hits up to the padded size
        self.sampler.seed(dr.opaque(mi.UInt32, int(self.rng.integers(1 << 31))), shaded.size)
        value, _, _ = self.integrator.sample(
            self.scene, self.sampler, camera_rays(self.camera_distance, d[:, shaded]), self.medium
        )
        value = np.array(value, dtype=float).reshape(-1, shaded.size)[: self.channels, : idx.size]
        bad = ~np.isfinite(value)
        if np.any(bad):
            self.nonfinite += int(np.any(bad, axis=0).sum())
            value = np.where(bad, 0.0, value)
        return value


@dataclass
class _Sums:
    """Running sums of a tally: coverage, radiance and each batch's extreme hits, anchors[b, side] = (x, y)."""

    coverage: np.ndarray
    radiance: np.ndarray
    anchors: np.ndarray

    @classmethod
    def empty(cls, n_batches: int, n_px: int, channels: int) -> _Sums:
        return cls(
            np.zeros(n_batches * n_px), np.zeros((channels, n_batches * n_px)), np.full((n_batches, 4, 2), np.nan)
        )

    def add(self, owner: np.ndarray, weight: np.ndarray, value: np.ndarray) -> None:
        """Add hits' covered areas and their weighted radiance (channels, hits) to their cells."""
        self.coverage += np.bincount(owner, weights=weight, minlength=self.coverage.size)
        for ch in range(value.shape[0]):
            self.radiance[ch] += np.bincount(owner, weights=value[ch] * weight, minlength=self.coverage.size)

    def push_anchors(self, x: np.ndarray, y: np.ndarray, batch: np.ndarray, idx: np.ndarray) -> None:
        """Move each batch's extreme hits outward to the hits ``idx`` beyond them."""
        for b in np.unique(batch[idx]):
            sel = idx[batch[idx] == b]
            for side, (axis, sign) in enumerate(_SIDES):
                coord = (x, y)[axis]
                j = sel[np.argmax(sign * coord[sel])]
                if np.isnan(self.anchors[b, side, 0]) or sign * coord[j] > sign * self.anchors[b, side, axis]:
                    self.anchors[b, side] = (x[j], y[j])


def _refined_extent(geometry, framing: Framing, anchors: np.ndarray, n_side: int) -> np.ndarray:
    """Silhouette extremes (n_batches, 4) [film px]: the batches' extreme hits refined (NaN without hits)."""
    extent = np.full((anchors.shape[0], 4), np.nan)
    found = ~np.isnan(anchors[:, 0, 0])
    if found.any():
        bounds = framing.bounds
        step = 2.0 / n_side * (1.0 if bounds is None else min(1.0, bounds[1] - bounds[0]))
        points = anchors[found].reshape(-1, 2)
        side_of = np.tile(np.arange(4), int(found.sum()))
        extent[found] = refine_extremes(geometry, framing, points, side_of, step).reshape(-1, 4)
    return extent


def refine_extremes(
    scene, framing: Framing, points, sides, step: float, grid: int = 24, iterations: int = 3
) -> np.ndarray:
    """Push extreme hits of the silhouette outward by local grid searches.

    The extreme hit of random samples falls short of the silhouette's true
    extent by the gap to the nearest sample (for a rounded outline of radius r
    about (S sqrt(r))^(-2/3) px at S samples per px^2). Beyond each extreme hit
    (x*, y*) a ``grid`` x ``grid`` search over [x*, x* + g] x [y* - 2g, y* + 2g]
    (for an x_max side; alike for the others) moves the extreme to the
    outermost hit; g shrinks to 4 grid cells each iteration. All points are
    searched together, one launch per iteration.

    Parameters
    ----------
    scene : mitsuba.Scene
        The target's geometry in the render frame.
    framing : Framing
        Sensor, target position and camera distance of the render.
    points : ndarray, shape (m, 2)
        Extreme hits [film px].
    sides : ndarray of int, shape (m,)
        Side of each point: 0 x_min, 1 x_max, 2 y_min, 3 y_max.
    step : float
        Initial search depth g [px] (about twice the sample spacing).

    Returns
    -------
    ndarray, shape (m,)
        Refined extreme coordinate of each point along its side's axis [film px].
    """
    u = (np.arange(grid) + 0.5) / grid
    best = np.array(points, dtype=float)
    m = len(best)
    axis = np.asarray(sides) // 2
    sign = np.where(np.asarray(sides) % 2 == 0, -1.0, 1.0)
    rows = np.arange(m)
    g = step
    for _ in range(iterations):
        along = best[rows, axis][:, None] + sign[:, None] * g * u[None, :]  # (m, grid)
        across = best[rows, 1 - axis][:, None] + g * (4.0 * u[None, :] - 2.0)  # (m, grid)
        a = np.repeat(along, grid, axis=1)
        c = np.tile(across, (1, grid))
        pts = np.where((axis == 0)[:, None, None], np.stack([a, c], axis=1), np.stack([c, a], axis=1))  # (m, 2, n)
        d = ray_directions(pts[:, 0].ravel(), pts[:, 1].ravel(), framing.sensor, framing.target_px).astype(np.float32)
        rays = camera_rays(framing.camera_distance, d)
        hit = np.array(scene.ray_intersect(rays).is_valid(), dtype=bool).reshape(m, -1)
        coord = pts[rows, axis]  # (m, n)
        score = np.where(hit, sign[:, None] * coord, -np.inf)
        k = np.argmax(score, axis=1)
        improved = hit.any(axis=1)
        best[improved] = pts[rows, :, k][improved]
        g = 4.0 * g / grid
    return best[rows, axis]
