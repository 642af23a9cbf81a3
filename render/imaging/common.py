"""Shared steps of the EO and thermal renderers: geometry, window, tally."""

from __future__ import annotations

import math

import numpy as np

from csuas.base.errors import ParameterError
from csuas.render.imaging.camera import Framing, SensorGeometry, full_frame, target_bounds, target_window
from csuas.render.imaging.records import View
from csuas.render.imaging.scene import normalise_target


def check_range(range_m) -> float:
    """Validate a slant range [m] (finite, > 0)."""
    try:
        r = float(range_m)
    except (TypeError, ValueError):
        raise ParameterError("range_m", range_m, "a number > 0 [m]") from None
    if not math.isfinite(r) or r <= 0:
        raise ParameterError("range_m", range_m, "finite and > 0 [m]")
    return r


def prepare(target, view: View, sensor, *, full: bool = False) -> tuple:
    """Slant range [m], normalised target and framing of one render.

    Parameters
    ----------
    target : str, Drone or list of parts
    view : View
        Slant range, aspect and the target's pixel offset.
    sensor : EoSensor or ThermalSensor
        Its ``hfov_deg``, ``n_h`` and ``n_v`` (IFOV = HFOV / N_H, Eq. 15).
    full : bool
        The full frame (the benchmark's naive reference) samples every pixel uniformly; otherwise
        the window samples only the box that contains the target's image.

    Returns
    -------
    (float, NormalisedTarget, Framing)

    Raises
    ------
    ParameterError
        When the sensor would sit inside the target's bounding sphere.
    """
    r = check_range(view.range_m)
    geometry = SensorGeometry.from_fov(sensor.hfov_deg, sensor.n_h, sensor.n_v)
    normalised = normalise_target(target, view.azimuth_deg, view.elevation_deg)
    if r <= 1.001 * normalised.radius_m:
        raise ParameterError("range_m", r, f"> {normalised.radius_m * 1.001:.4g} m (the target's bounding radius)")
    cx, cy = geometry.default_target_px()
    ox, oy = (float(v) for v in view.target_offset_px)
    target_px = (cx + ox, cy + oy)
    window = full_frame(geometry) if full else target_window(geometry, r, normalised.radius_m, target_px)
    bounds = None if full else target_bounds(geometry, r, normalised.radius_m, target_px)
    return r, normalised, Framing(geometry, window, target_px, r / normalised.radius_m, bounds)


def silhouette_box_px(target, range_m: float, azimuth_deg: float, elevation_deg: float, sensor, target_px) -> tuple:
    """Film-coordinate box (x_lo, x_hi, y_lo, y_hi) of the target's silhouette, from its projected mesh.

    The pinhole camera of the render (:func:`csuas.render.imaging.camera.ray_directions`, the camera on
    the render frame's +z axis at ``range_m``) maps each vertex to the film; a triangle's image lies in the
    hull of its vertices' images, so their extremes are the silhouette's exact extent.

    Parameters
    ----------
    target : str, Drone or list of parts
    range_m, azimuth_deg, elevation_deg : float
        The view (:class:`csuas.render.imaging.records.View`) [m], [deg].
    sensor : SensorGeometry
    target_px : (float, float)
        Film coordinates of the target's centre.
    """
    normalised = normalise_target(target, azimuth_deg, elevation_deg)
    vertices = np.concatenate([part.vertices for part in normalised.parts])
    depth = check_range(range_m) / normalised.radius_m - vertices[:, 2]
    x = target_px[0] + vertices[:, 0] / depth / sensor.ifov_rad
    y = target_px[1] - vertices[:, 1] / depth / sensor.ifov_rad
    return float(x.min()), float(x.max()), float(y.min()), float(y.max())


def window_notes(window, tally) -> list:
    """Notes of a window render: a target beyond the frame, and shaded samples that were not finite."""
    notes = []
    if window.clipped:
        notes.append("the target reaches beyond the sensor frame; figures cover the visible part only")
    if tally.nonfinite_samples:
        notes.append(f"{tally.nonfinite_samples} shaded samples were not finite and counted as 0")
    return notes


def progress_printer(label: str, stream):
    """A progress callback writing ``label: NN %`` to ``stream`` at 10 % steps (None: silent)."""
    if stream is None:
        return None
    state = {"last": -1}

    def report(fraction: float):
        step = int(fraction * 10)
        if step > state["last"]:
            state["last"] = step
            print(f"{label}: {step * 10:3d} %", file=stream, flush=True)

    return report
