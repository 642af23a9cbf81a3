"""Lidar cross-section with multiple bounces, by Mitsuba 3 path tracing.

The single-bounce tracer (:mod:`csuas.render.lidar.cross_section`) ignores
light that reaches the sensor after scattering off a second part (e.g. from
the body onto an arm and back). Here the monostatic geometry is rendered
with Mitsuba's ``path`` integrator: a ``directional`` emitter of irradiance
``E = 1`` shining along ``-d`` (plane wave from the sensor), an
``orthographic`` camera looking along ``-d`` whose film covers the target's
window, box pixel filter. The film holds the radiance ``L`` toward the
sensor, so ``I = sum L * A_pixel`` and ``sigma = 4 pi I / E``.
Next-event estimation toward the directional emitter tests the shadow ray
along ``d``, the same line as the camera ray, so shadowing is monostatic.
``max_depth = 2`` (camera -> surface -> emitter) is the single-bounce LCS
from an independent code path; a larger depth adds the inter-reflections.

The standard error comes from ``replicates`` renders with independent seeds.
"""

from __future__ import annotations

import math
import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.drone_models.geometry import direction_vector, validate_angles
from csuas.render.lidar.cross_section import ORIGIN_PLANE_FACTOR, RayGrid, resolve_quality, sampling_windows


def path_traced_lcs(
    target,
    azimuth_deg: float = 0.0,
    elevation_deg: float = 0.0,
    max_depth: int = 8,
    quality: str | RayGrid = "standard",
    spp: int = 4,
    seed: int = 0,
) -> dict:
    """Far-field LCS with up to ``max_depth - 1`` bounces, its standard error and time.

    Parameters
    ----------
    target : LidarTarget
    azimuth_deg, elevation_deg : float
        Direction from the target toward the sensor [deg].
    max_depth : int
        Mitsuba path length (>= 2; 2 = single bounce, -1 = unlimited with
        Russian roulette).
    quality : str or RayGrid
        Film size (``grid`` ~ pixels per side) and independent renders, as in
        :func:`csuas.render.lidar.cross_section.resolve_quality`.
    spp : int
        Samples per pixel per render (>= 1).
    seed : int

    Returns
    -------
    dict
        ``lcs_m2``, ``stderr_m2`` [m^2], ``max_depth``, ``grid``,
        ``replicates``, ``spp``, ``samples``, ``time_s`` [s],
        ``method`` (``"path_tracing"``).
    """
    az, el = validate_angles(azimuth_deg, elevation_deg)
    g, r, name = resolve_quality(quality)
    _check_path_options(max_depth, spp)
    shapes = target.shapes()  # selects the variant (and libLLVM) before Mitsuba is imported here
    import mitsuba as mi

    start = time.perf_counter()
    d = direction_vector(az, el)
    w = sampling_windows(target.vertices, target.bounding_radius_m, d[None, :], np.atleast_1d(az), math.inf, g, None)[0]
    half_u, half_v = 0.5 * w.n_u * w.du, 0.5 * w.n_v * w.dw
    scene = mi.load_dict(_monostatic_scene(shapes, w, d, target.bounding_radius_m, spp, max_depth))
    pixel_area = (2.0 * half_u) * (2.0 * half_v) / (w.n_u * w.n_v)
    values = (
        4.0
        * math.pi
        * pixel_area
        * np.array([float(np.sum(np.asarray(mi.render(scene, seed=seed + k), dtype=float))) for k in range(r)])
    )
    return {
        "lcs_m2": float(values.mean()),
        "stderr_m2": float(values.std(ddof=1) / math.sqrt(r)),
        "max_depth": int(max_depth),
        "grid": g,
        "replicates": r,
        "spp": int(spp),
        "quality": name,
        "samples": int(r * spp * w.n_u * w.n_v),
        "time_s": time.perf_counter() - start,
        "method": "path_tracing",
    }


def _check_path_options(max_depth, spp) -> None:
    """``max_depth`` an integer >= 2 or -1 (unlimited), ``spp`` an integer >= 1."""
    depth_ok = (
        isinstance(max_depth, (int, np.integer))
        and not isinstance(max_depth, bool)
        and (max_depth == -1 or max_depth >= 2)
    )
    if not depth_ok:
        raise ParameterError("max_depth", max_depth, "integer >= 2, or -1 (unlimited)")
    if not isinstance(spp, (int, np.integer)) or isinstance(spp, bool) or spp < 1:
        raise ParameterError("spp", spp, "integer >= 1")


def _monostatic_scene(shapes: dict, w, d: np.ndarray, bounding_radius_m: float, spp: int, max_depth: int) -> dict:
    """The scene of the module docstring: target, orthographic camera over window ``w``, directional beam E = 1."""
    import mitsuba as mi

    half_u, half_v = 0.5 * w.n_u * w.du, 0.5 * w.n_v * w.dw
    centre = (w.u0 + half_u) * w.h + (w.w0 + half_v) * w.v
    origin = centre + ORIGIN_PLANE_FACTOR * bounding_radius_m * d
    to_world = mi.ScalarTransform4f().look_at(
        origin=origin.tolist(), target=(origin - d).tolist(), up=w.v.tolist()
    ) @ mi.ScalarTransform4f().scale([half_u, half_v * w.n_u / w.n_v, 1.0])  # the film's y spans +-1/aspect
    return {
        "type": "scene",
        **shapes,
        "sensor": {
            "type": "orthographic",
            "to_world": to_world,
            "film": {
                "type": "hdrfilm",
                "width": w.n_u,
                "height": w.n_v,
                "rfilter": {"type": "box"},
                "pixel_format": "luminance",
            },
            "sampler": {"type": "independent", "sample_count": int(spp)},
        },
        "emitter": {
            "type": "directional",
            "direction": (-d).tolist(),
            "irradiance": {"type": "spectrum", "value": 1.0},
        },
        "integrator": {"type": "path", "max_depth": int(max_depth), "hide_emitters": True},
    }
