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

import time
from dataclasses import dataclass

import numpy as np

from csuas.render.imaging.camera import SensorGeometry, Window, jittered_film_samples, ray_directions

#: Rays per Dr.Jit launch (bounds memory: about 0.5 GiB on the LLVM back-end).
MAX_LAUNCH = 1 << 21


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
        Extremal film coordinates of target hits per batch: x_min, x_max,
        y_min, y_max [px] (NaN where a batch has no hit).
    samples : int
        Camera rays traced in total.
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
    nonfinite_samples: int = 0

    @property
    def n_batches(self) -> int:
        return self.coverage.shape[0]


def trace_window(scene, integrator, sensor: SensorGeometry, window: Window, target_px, camera_distance: float, *,
                 n_side: int, n_batches: int, seed: int = 0, channels: int = 3, max_launch: int = MAX_LAUNCH,
                 bounds=None, progress=None) -> WindowTally:
    """Trace ``n_batches`` x ``n_side**2`` jittered samples in every pixel of ``window``.

    Parameters
    ----------
    scene, integrator
        Mitsuba scene in the render frame and a sampling integrator.
    sensor : SensorGeometry
    window : Window
    target_px : (float, float)
        Film coordinates of the target's centre (the render-frame origin).
    camera_distance : float
        Camera position on the +z axis [render units] = range / bounding radius.
    n_side, n_batches : int
        Samples per pixel and batch (n_side**2) and number of independent batches.
    seed : int
        Seed of the batch generators (deterministic results for a given seed).
    channels : int
        3 for ``*_rgb`` variants, 1 for ``*_mono``.
    max_launch : int
        Upper bound of rays per launch (memory bound).
    bounds : (x_lo, x_hi, y_lo, y_hi) or None
        Box containing the target's image; pixels are sampled only inside it
        (:func:`~csuas.render.imaging.camera.jittered_film_samples`).
    progress : callable(done_fraction) or None
    """
    import drjit as dr
    import mitsuba as mi

    t0 = time.perf_counter()
    n2 = n_side * n_side
    n_px = window.n_pixels
    chunk = max(1, max_launch // n2)
    coverage = np.zeros((n_batches, n_px))
    radiance = np.zeros((n_batches, channels, n_px))
    extent = np.full((n_batches, 4), np.nan)
    nonfinite = 0
    origin = mi.Point3f(0.0, 0.0, float(camera_distance))
    sampler = mi.load_dict({"type": "independent"})
    n_chunks = -(-n_px // chunk)
    for b in range(n_batches):
        rng = np.random.default_rng([int(seed), b])
        lo = np.array([np.inf, np.inf])
        hi = -lo
        for c in range(n_chunks):
            pixels = np.arange(c * chunk, min((c + 1) * chunk, n_px))
            x, y, area = jittered_film_samples(window, pixels, n_side, rng, bounds)
            d = ray_directions(x, y, sensor, target_px).astype(np.float32)
            ray = mi.Ray3f(origin, mi.Vector3f(d[0], d[1], d[2]))
            hit = np.array(scene.ray_intersect(ray).is_valid(), dtype=bool)
            idx = np.flatnonzero(hit)
            if idx.size:
                local = idx // n2
                owner = pixels[local]
                weight = area[local] / n2
                coverage[b] += np.bincount(owner, weights=weight, minlength=n_px)
                hit_ray = mi.Ray3f(origin, mi.Vector3f(d[0][idx], d[1][idx], d[2][idx]))
                sampler.seed(int(rng.integers(1 << 31)), idx.size)
                value, _, _ = integrator.sample(scene, sampler, hit_ray)
                value = np.array(value, dtype=float).reshape(-1, idx.size)[:channels]
                bad = ~np.isfinite(value)
                if np.any(bad):
                    nonfinite += int(np.any(bad, axis=0).sum())
                    value = np.nan_to_num(value, nan=0.0, posinf=0.0, neginf=0.0)
                for ch in range(channels):
                    radiance[b, ch] += np.bincount(owner, weights=value[ch] * weight, minlength=n_px)
                lo = np.minimum(lo, [x[idx].min(), y[idx].min()])
                hi = np.maximum(hi, [x[idx].max(), y[idx].max()])
            if progress is not None:
                progress((b * n_chunks + c + 1) / (n_batches * n_chunks))
        if np.isfinite(lo[0]):
            extent[b] = [lo[0], hi[0], lo[1], hi[1]]
        dr.sync_thread()
    shape = (window.height, window.width)
    return WindowTally(coverage.reshape(n_batches, *shape), radiance.reshape(n_batches, channels, *shape),
                       extent, n_batches * n_px * n2, time.perf_counter() - t0, nonfinite)
