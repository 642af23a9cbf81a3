"""Pinhole sensor geometry, the window around the target, and jittered camera samples.

A pinhole image depends on angles only. The camera is therefore described by
its instantaneous field of view (IFOV, Eq. 15: HFOV / N_H; Eq. 22 for TIR:
pitch / focal length) and its pixel counts: the focal plane at unit distance
carries square pixels of pitch IFOV, so a pixel near the optical axis
subtends exactly the paper's IFOV. (The full frame then spans
2 atan(N_H IFOV / 2) horizontally, which differs from the nominal HFOV by
0.25 % at 10 deg and 3.5 % at 36.67 deg; only the pixels around the target
are rendered, docs/simulation.md.)

Film coordinates are continuous pixel coordinates of the FULL sensor frame:
pixel ``(i, j)`` covers ``[i, i+1) x [j, j+1)``, ``x`` to the right, ``y``
downwards. The target's centre (the origin of its body frame) is imaged at
``target_px``; by default the centre of the pixel that contains the
principal point, ``(floor(N_H/2) + 0.5, floor(N_V/2) + 0.5)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError


@dataclass(frozen=True)
class SensorGeometry:
    """Pixel grid of a pinhole sensor.

    Attributes
    ----------
    ifov_rad : float
        Pixel pitch on the unit focal plane [rad] (Eq. 15 or 22).
    n_h, n_v : int
        Pixels across and down the full frame.
    """

    ifov_rad: float
    n_h: int
    n_v: int

    @classmethod
    def from_fov(cls, hfov_deg: float, n_h: int, n_v: int) -> SensorGeometry:
        """Sensor with IFOV = HFOV / N_H (Eq. 15)."""
        if not (math.isfinite(hfov_deg) and 0.0 < hfov_deg < 180.0):
            raise ParameterError("hfov_deg", hfov_deg, "0 < x < 180")
        for name, n in (("n_h", n_h), ("n_v", n_v)):
            if int(n) != n or n < 1:
                raise ParameterError(name, n, "integer >= 1")
        return cls(math.radians(hfov_deg) / int(n_h), int(n_h), int(n_v))

    def default_target_px(self) -> tuple[float, float]:
        """Centre of the pixel containing the principal point (film coordinates)."""
        return (self.n_h // 2 + 0.5, self.n_v // 2 + 0.5)


@dataclass(frozen=True)
class Window:
    """A rectangle of whole pixels of the sensor frame.

    Attributes
    ----------
    x0, y0 : int
        Film coordinates of its top-left pixel.
    width, height : int
        Size [px].
    clipped : bool
        True when the target's angular extent reaches beyond the sensor frame.
    """

    x0: int
    y0: int
    width: int
    height: int
    clipped: bool = False

    @property
    def n_pixels(self) -> int:
        return self.width * self.height

    def as_dict(self) -> dict:
        return {"x0": self.x0, "y0": self.y0, "width": self.width, "height": self.height, "clipped": self.clipped}


@dataclass(frozen=True)
class Framing:
    """Where the target's image falls on the sensor, and which pixels a render samples.

    Attributes
    ----------
    sensor : SensorGeometry
        The sensor's pixel grid.
    window : Window
        The pixels rendered (the target's window, or the full frame).
    target_px : (float, float)
        Film coordinates of the target's centre (the render-frame origin).
    camera_distance : float
        Camera position on the render frame's +z axis [render units] = range / bounding radius.
    bounds : (x_lo, x_hi, y_lo, y_hi) or None
        Film-coordinate box containing the target's image (:func:`target_bounds`); pixels are
        sampled only inside it. None: every pixel of the window, uniformly.
    """

    sensor: SensorGeometry
    window: Window
    target_px: tuple[float, float]
    camera_distance: float
    bounds: tuple | None = None


def full_frame(sensor: SensorGeometry) -> Window:
    """The whole sensor frame as a window."""
    return Window(0, 0, sensor.n_h, sensor.n_v)


def target_window(sensor: SensorGeometry, range_m: float, radius_m: float, target_px, margin_px: int = 1) -> Window:
    """Smallest pixel window that contains the image of the target's bounding sphere.

    Parameters
    ----------
    sensor : SensorGeometry
    range_m : float
        Distance from the sensor to the target's centre [m].
    radius_m : float
        Radius of a sphere about the centre that contains the target [m], < range_m.
    target_px : (float, float)
        Film coordinates of the target's centre.
    margin_px : int
        Extra pixels on each side.

    Returns
    -------
    Window
        Clipped to the frame (``clipped`` set when the sphere reaches outside it).
    """
    # Angular radius of the sphere's outline: sin(theta) = r / R; on the unit focal plane tan(theta).
    bx0, bx1, by0, by1 = target_bounds(sensor, range_m, radius_m, target_px)
    x0, x1 = math.floor(bx0) - margin_px, math.ceil(bx1) + margin_px
    y0, y1 = math.floor(by0) - margin_px, math.ceil(by1) + margin_px
    clipped = x0 < 0 or y0 < 0 or x1 > sensor.n_h or y1 > sensor.n_v
    x0, y0 = max(x0, 0), max(y0, 0)
    x1, y1 = min(x1, sensor.n_h), min(y1, sensor.n_v)
    if x1 <= x0 or y1 <= y0:
        raise ParameterError("target_px", tuple(target_px), f"inside the {sensor.n_h} x {sensor.n_v} px frame")
    return Window(x0, y0, x1 - x0, y1 - y0, clipped)


def jittered_film_samples(window: Window, pixels: np.ndarray, n_side: int, rng: np.random.Generator, bounds=None):
    """Stratified (jittered n x n) sample positions in window pixels, optionally clipped to a box.

    Parameters
    ----------
    window : Window
    pixels : ndarray of int
        Flat indices (row-major within the window) of the pixels to sample.
    n_side : int
        Strata per side (n_side**2 samples per pixel).
    rng : numpy.random.Generator
    bounds : (x_lo, x_hi, y_lo, y_hi) or None
        Film-coordinate box that contains the target's image. Each pixel is
        sampled only where it overlaps the box (outside it no ray can hit),
        so a sub-pixel target gets n_side**2 samples across itself, not
        across the pixel: an unbiased stratified estimator on the smaller
        domain.

    Returns
    -------
    x, y : ndarray of float64, shape (len(pixels) * n_side**2,)
        Film coordinates; samples of one pixel are contiguous.
    area : ndarray of float64, shape (len(pixels),)
        Sampled area of each pixel [px^2] (1 without ``bounds``; 0 outside the box).
    """
    n2 = n_side * n_side
    px = (window.x0 + pixels % window.width).astype(float)
    py = (window.y0 + pixels // window.width).astype(float)
    x_lo, x_hi, y_lo, y_hi = px, px + 1.0, py, py + 1.0
    if bounds is not None:
        x_lo, x_hi = np.clip(x_lo, bounds[0], bounds[1]), np.clip(x_hi, bounds[0], bounds[1])
        y_lo, y_hi = np.clip(y_lo, bounds[2], bounds[3]), np.clip(y_hi, bounds[2], bounds[3])
    strata = np.arange(n2)
    sx = (strata % n_side)[None, :]
    sy = (strata // n_side)[None, :]
    u = rng.random((pixels.size, n2, 2))
    x = x_lo[:, None] + (x_hi - x_lo)[:, None] * (sx + u[..., 0]) / n_side
    y = y_lo[:, None] + (y_hi - y_lo)[:, None] * (sy + u[..., 1]) / n_side
    return x.ravel(), y.ravel(), (x_hi - x_lo) * (y_hi - y_lo)


def sampled_areas(window: Window, pixels: np.ndarray, bounds=None) -> np.ndarray:
    """Area [px^2] of each window pixel inside ``bounds`` (1 everywhere without bounds)."""
    px = (window.x0 + pixels % window.width).astype(float)
    py = (window.y0 + pixels // window.width).astype(float)
    if bounds is None:
        return np.ones(pixels.size)
    w = np.clip(px + 1.0, bounds[0], bounds[1]) - np.clip(px, bounds[0], bounds[1])
    h = np.clip(py + 1.0, bounds[2], bounds[3]) - np.clip(py, bounds[2], bounds[3])
    return w * h


def target_bounds(sensor: SensorGeometry, range_m: float, radius_m: float, target_px) -> tuple:
    """Film-coordinate box (x_lo, x_hi, y_lo, y_hi) containing the image of the bounding sphere."""
    half = radius_m / math.sqrt(range_m * range_m - radius_m * radius_m) / sensor.ifov_rad
    half *= 1.0 + 1e-6  # float32 rounding of the rays must not cut the outline
    cx, cy = target_px
    return (cx - half, cx + half, cy - half, cy + half)


def ray_directions(x, y, sensor: SensorGeometry, target_px) -> np.ndarray:
    """Unit ray directions (3, n) in the render frame for film coordinates ``x, y``.

    The render frame has the camera on the +z axis looking toward -z, image
    right along +x and image up along +y (see :mod:`csuas.render.imaging.scene`);
    the ray through ``target_px`` is exactly -z. Computed in float64, so the
    small transverse components keep full relative precision in float32.
    """
    cx, cy = target_px
    dx = (np.asarray(x) - cx) * sensor.ifov_rad
    dy = -(np.asarray(y) - cy) * sensor.ifov_rad
    norm = np.sqrt(1.0 + dx * dx + dy * dy)
    return np.stack([dx / norm, dy / norm, -1.0 / norm])
