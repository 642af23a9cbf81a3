"""Layers added to a rendered frame after its drone: a confuser or clutter drawn under or over the drone's window.

A frame of :func:`csuas.render.imaging.frame.eo_frame` (or ``tir_frame``, in band radiance) holds, in the drone's
window, R + u (B - U): R the window's rendered light (the drone's own light plus the render's uniform
background U on the share u of each pixel the drone leaves uncovered) and B the frame's background behind it.
A layer of opacity a and light a L (coverage-weighted) changes the background to B' = (1 - a) B + a L:

* over everything (a layer nearer than the drone, or where there is no drone): F' = (1 - a) F + a L;
* under the drone: F' = R + u (B' - U) = F + u a L - a u B, and u B = F - R + u U, so

      F' = F + u a L - a (F - R + u U),

  exact without dividing by u (a pixel the drone covers fully, u = 0, keeps its drone: F' = F - a (F - R) = R).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class DroneWindow:
    """The drone's window in a frame (module docstring): origin [px], R, u, U and the drone's range [m]."""

    x0: int
    y0: int
    rendered: np.ndarray
    uncovered: np.ndarray
    uniform: float
    range_m: float


def _overlap(frame_shape: tuple, origin: tuple, shape: tuple) -> tuple | None:
    """Frame slices and window slices of a window at ``origin`` (x0, y0) where it overlaps the frame, or None."""
    (n_v, n_h), (x0, y0) = frame_shape, origin
    ys, xs, ye, xe = max(y0, 0), max(x0, 0), min(y0 + shape[0], n_v), min(x0 + shape[1], n_h)
    if ye <= ys or xe <= xs:
        return None
    return (slice(ys, ye), slice(xs, xe)), (slice(ys - y0, ye - y0), slice(xs - x0, xe - x0))


def _drone_terms(drone: DroneWindow | None, origin: tuple, shape: tuple) -> tuple:
    """u and R - u U of the drone over a layer's window (1 and 0 outside the drone's window)."""
    uncovered, own = np.ones(shape), np.zeros(shape)
    if drone is not None:
        d_x0, d_y0 = drone.x0 - origin[0], drone.y0 - origin[1]
        parts = _overlap(shape, (d_x0, d_y0), drone.uncovered.shape)
        if parts is not None:
            mine, theirs = parts
            uncovered[mine] = drone.uncovered[theirs]
            own[mine] = drone.rendered[theirs] - drone.uncovered[theirs] * drone.uniform
    return uncovered, own


def blend(frame: np.ndarray, origin: tuple, alpha: np.ndarray, light: np.ndarray, under: DroneWindow | None) -> None:
    """Add a layer of opacity ``alpha`` and light ``light`` (a L) at ``origin`` (x0, y0) to ``frame`` in place,
    under the drone window ``under`` or over everything (None) (module docstring)."""
    parts = _overlap(frame.shape, origin, alpha.shape)
    if parts is None:
        return
    inside, window = parts
    a, a_l, f = alpha[window], light[window], frame[inside]
    uncovered, own = _drone_terms(under, (inside[1].start, inside[0].start), f.shape)
    frame[inside] = f + uncovered * a_l - a * (f - own)
