"""A layered fog's slant transmittance rendered through a Mitsuba fog slab (docs/scenarios.md, fog_top_m).

The fog fills a slab from far below the ground to its top h_top as a purely absorbing ``homogeneous``
medium (albedo 0: the transmittance alone, no path radiance) of extinction beta; a camera at height h_s
looks at a disc emitter of unit radiance at height h_d a ground distance away, through black
surroundings. The volumetric path tracer (``volpath``) samples the free flight of each camera ray in
the medium, so each pixel's mean is the slant path's transmittance exp(-beta L_fog) by Monte Carlo
(each ray carries 1 or 0: a binomial error, estimated here from independent batches). It checks the
closed form of :func:`csuas.core.atmosphere.fog_path_fraction`.
"""

from __future__ import annotations

import math
import time

import numpy as np

#: Camera field of view [deg] and pixels a side: every ray ends on the emitter disc (3x the field at the target).
SLAB_FOV_DEG, SLAB_PIXELS = 0.5, 8
#: Independent renders whose spread gives the standard error.
SLAB_BATCHES = 8


def _slab_scene(camera, target, fog_top_m: float, beta_per_km: float):
    import mitsuba as mi

    medium = {"type": "homogeneous", "sigma_t": beta_per_km / 1000.0, "albedo": 0.0}
    extent = 10.0 * (float(np.linalg.norm(target - camera)) + abs(fog_top_m) + 10.0)
    centre, half = (fog_top_m - extent) / 2.0, (fog_top_m + extent) / 2.0
    slab = {
        "type": "cube",
        "bsdf": {"type": "null"},
        "interior": medium,
        "to_world": mi.ScalarTransform4f().translate([0.0, 0.0, centre]).scale([extent, extent, half]),
    }
    distance = float(np.linalg.norm(target - camera))
    up = [0.0, 0.0, 1.0] if abs(target[2] - camera[2]) < 0.9 * distance else [1.0, 0.0, 0.0]
    radius = 3.0 * distance * math.tan(math.radians(SLAB_FOV_DEG))
    disc = {
        "type": "disk",
        "emitter": {"type": "area", "radiance": 1.0},
        "to_world": mi.ScalarTransform4f()
        .look_at(origin=target.tolist(), target=camera.tolist(), up=up)
        .scale([radius, radius, 1.0]),
    }
    film = {"type": "hdrfilm", "width": SLAB_PIXELS, "height": SLAB_PIXELS, "rfilter": {"type": "box"}}
    sensor = {
        "type": "perspective",
        "fov": SLAB_FOV_DEG,
        "to_world": mi.ScalarTransform4f().look_at(origin=camera.tolist(), target=target.tolist(), up=up),
        "film": {**film, "pixel_format": "luminance"},
    }
    if camera[2] < fog_top_m:
        sensor["medium"] = medium  # the camera starts inside the fog
    return mi.load_dict({"type": "scene", "slab": slab, "disc": disc, "sensor": sensor})


def fog_slab_transmittance(
    sensor_height_m: float,
    target_height_m: float,
    ground_range_m: float,
    fog_top_m: float,
    beta_per_km: float,
    samples_per_pixel: int = 1024,
    seed: int = 0,
) -> dict:
    """Rendered transmittance of a straight slant path through a fog slab, with its Monte Carlo error.

    Parameters
    ----------
    sensor_height_m, target_height_m : float
        Heights of the camera and the emitter above the ground [m].
    ground_range_m : float
        Horizontal distance between them [m], > 0.
    fog_top_m : float
        Height of the fog's top [m].
    beta_per_km : float
        Extinction of the fog [1/km].
    samples_per_pixel : int
        Samples per pixel over all batches.
    seed : int

    Returns
    -------
    dict
        ``transmittance``, its ``stderr`` (spread of SLAB_BATCHES renders), ``slant_range_m``, ``time_s``.
    """
    from csuas.render.backend import use_variant

    t0 = time.perf_counter()
    use_variant("ad_mono")
    import mitsuba as mi

    camera = np.array([0.0, 0.0, float(sensor_height_m)])
    target = np.array([float(ground_range_m), 0.0, float(target_height_m)])
    scene = _slab_scene(camera, target, float(fog_top_m), float(beta_per_km))
    integrator = mi.load_dict({"type": "volpath", "max_depth": 2})
    per_batch = max(samples_per_pixel // SLAB_BATCHES, 1)
    means = np.array(
        [
            float(
                np.mean(
                    np.asarray(mi.render(scene, integrator=integrator, seed=seed * SLAB_BATCHES + b, spp=per_batch))
                )
            )
            for b in range(SLAB_BATCHES)
        ]
    )
    return {
        "transmittance": float(means.mean()),
        "stderr": float(means.std(ddof=1) / math.sqrt(SLAB_BATCHES)),
        "slant_range_m": float(np.linalg.norm(target - camera)),
        "time_s": time.perf_counter() - t0,
    }
