"""A dataset frame with what lies between its background and its drone and in front of it: clutter
(:mod:`csuas.render.imaging.clutter`) and confusers (:mod:`csuas.render.imaging.confusers`), added to a frame
rendered without chain stages, then the whole chain.

Clutter is drawn under the drone (it lies beyond it) except a power line nearer than the drone, drawn over
it; confusers under or over the drone by their range (:func:`csuas.render.imaging.compose.blend`). With
``render["object_path"]`` (a scenario that declares weather) each layer and confuser takes the frame's path at its
own range, as the drone does at its range (:func:`csuas.render.imaging.path.eo_path_at` / ``tir_path_at``).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from csuas.core.camera import auto_exposure_s
from csuas.core.radiometry import band_radiance, radiance_temperature
from csuas.render.imaging.compose import DroneWindow, blend

#: Share of the full well the 99th percentile of a layered frame may reach under its auto-exposure.
HIGHLIGHT_FILL = 0.9


def _add_layers(signal: np.ndarray, drone: DroneWindow, render: dict, band: str) -> dict:
    """The sun, clutter and confusers on the frame's light (luminance or band radiance) in place: what lies beyond
    the drone under it, then the confusers, then what is nearer (a power line, the sun's ghosts in the lens) over
    everything; the confusers' labels (``layers``) and the class map (``classes``)."""
    from csuas.render.imaging.clutter import CLASSES, clutter_layers, frame_rays
    from csuas.render.imaging.confusers import eo_confusers, tir_confusers

    out: dict = {"layers": None}
    item, sensor, ifov, clutter = render["item"], render["sensor"], drone_ifov(render), render.get("clutter")
    beyond, near = [], []
    if clutter is not None:
        sun = _sun_layers(signal.shape, ifov, render)
        rays = frame_rays(sensor.n_h, sensor.n_v, ifov, item)
        context = {"band": band, "ambient_k": render["ambient_k"], "ifov_rad": ifov, "path": render.get("object_path")}
        context["illuminance_lx"] = getattr(render.get("light"), "illuminance_lx", 0.0)
        layers, codes = clutter_layers(rays, clutter, context, render["clutter_seed"])
        for layer in sun[:1] + layers:
            (beyond if layer[2] > drone.range_m else near).append(layer)
        near += sun[1:]
        if sun:
            codes[sun[0][0] > 0.5] = CLASSES.index("sun")
        out["classes"] = codes
    for alpha, light, _ in beyond:
        blend(signal, (0, 0), alpha, light, drone)
    if "confusers" in item:
        add = eo_confusers if band == "eo" else tir_confusers
        out["layers"] = add(signal, item["confusers"], ifov, render, drone)
    for alpha, light, _ in near:
        blend(signal, (0, 0), alpha, light, None)
    return out


def _sun_layers(shape: tuple, ifov: float, render: dict) -> list:
    """The sun's disk and its ghosts (:func:`csuas.render.imaging.clutter.sun_and_flare`) where the spec puts
    the sun, as bright as the drone's render's direct sunlight; none without ``sun_offset_deg``."""
    from csuas.render.imaging.clutter import sun_and_flare, sun_pixel
    from csuas.render.imaging.eo import sun_and_sky

    clutter, light = render["clutter"], render.get("light")
    if clutter.sun_offset_deg is None or light is None:
        return []
    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    sun_px = sun_pixel((shape[1], shape[0]), ifov, clutter.sun_offset_deg)
    return sun_and_flare(shape, ifov, sun_px, sky["sun_irradiance_lx"], clutter.lens_flare)


def drone_ifov(render: dict) -> float:
    """The frame's IFOV [rad] (HFOV / N_H)."""
    return math.radians(render["sensor"].hfov_deg) / render["sensor"].n_h


def with_eo_layers(frame: dict, render: dict, chain, seed: int) -> dict:
    """An :func:`~csuas.render.imaging.frame.eo_frame` rendered without chain stages, with its clutter and
    confusers added, exposed again (:func:`csuas.core.camera.auto_exposure_s`: the median at half the full well,
    shortened where the 99th percentile would pass ``HIGHLIGHT_FILL`` of it),
    then the whole chain; ``layers`` holds the confusers' labels, ``classes`` the class map.

    ``render``: :func:`csuas.render.imaging.confusers.eo_render_settings`'s, with ``item``, ``target``,
    ``view`` (the drone's), ``full_well_e``, ``max_exposure_s``, ``clutter`` and ``clutter_seed``.
    """
    from csuas.render.imaging.eo import LUMINANCE_WEIGHTS
    from csuas.render.imaging.frame import frame_label
    from csuas.render.imaging.sensor_chain import apply_chain

    res, luminance = frame["result"], frame["luminance"]
    uniform = float(res.values["background_radiance_apparent"])  # the render's background, after its path
    rendered = np.tensordot(LUMINANCE_WEIGHTS, res.image, axes=1)
    drone = DroneWindow(res.window.x0, res.window.y0, rendered, 1.0 - res.coverage, uniform, res.range_m)
    rate_per_nit = float(np.sum(frame["electrons"]) / np.sum(luminance)) / frame["exposure_s"]  # e/s per cd/m^2
    added = _add_layers(luminance, drone, render, "eo")
    # auto-exposure again on the frame with its layers: the median at half the full well, unless that would
    # put the 99th percentile (bright clouds, white roofs) above HIGHLIGHT_FILL of it
    median, highlight = np.percentile(luminance, [50.0, 99.0])
    exposure = float(auto_exposure_s(rate_per_nit * median, render["full_well_e"], render["max_exposure_s"]))
    highlight_fill = auto_exposure_s(rate_per_nit * highlight, render["full_well_e"], exposure, HIGHLIGHT_FILL)
    exposure = float(highlight_fill)
    scale = exposure / frame["exposure_s"]
    electrons = luminance * rate_per_nit * exposure
    settings = replace(chain, exposure_s=exposure, full_well_e=render["full_well_e"])
    sensor = render["sensor"]
    return {
        **frame,
        **added,
        "exposure_s": exposure,
        "target_excess_e": frame["target_excess_e"] * scale,
        "background_behind_e": frame["background_behind_e"] * scale,
        "electrons": electrons,
        "chain": apply_chain(electrons, settings, seed),
        "label": frame_label(render["target"], render["view"], res, sensor.n_h, sensor.n_v, chain),
    }


def with_tir_layers(frame: dict, render: dict, chain, seed: int) -> dict:
    """A :func:`~csuas.render.imaging.frame.tir_frame` rendered without chain stages, with its clutter and
    confusers added in band radiance, then the chain's thermal stages (keys as :func:`with_eo_layers`).

    ``render``: as :func:`csuas.render.imaging.confusers.tir_confusers`'s, with ``item``, ``target``, ``view``,
    ``clutter`` and ``clutter_seed``.
    """
    from csuas.render.imaging.frame import frame_label
    from csuas.render.imaging.sensor_chain import apply_chain

    res, sensor = frame["result"], render["sensor"]
    radiance = np.asarray(band_radiance(frame["temperature"], sensor.band), dtype=float)
    uncovered = res.coverage == 0
    uniform = float(np.median(res.image[0][uncovered] if uncovered.any() else res.image[0]))  # as tir_frame's
    drone = DroneWindow(res.window.x0, res.window.y0, res.image[0], 1.0 - res.coverage, uniform, res.range_m)
    added = _add_layers(radiance, drone, render, sensor.band)
    temperature = radiance_temperature(radiance, sensor.band)
    return {
        **frame,
        **added,
        "temperature": temperature,
        "chain": apply_chain(temperature, chain, seed, thermal=True),
        "label": frame_label(render["target"], render["view"], res, sensor.n_h, sensor.n_v, chain),
    }
