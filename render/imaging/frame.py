"""A full EO frame as the camera delivers it: the rendered target in its window, the background around
it, the camera's radiometry (:mod:`csuas.core.camera`), the sensor chain
(:mod:`csuas.render.imaging.sensor_chain`) and the target's label (:mod:`csuas.render.imaging.labels`).

The target is rendered in its window only (range-normalised, exact geometry,
:func:`csuas.render.imaging.eo.render_eo`); the rest of the frame is the background's luminance,
uniform: the horizon sky of the render or a Lambertian background. Luminance becomes mean
photoelectrons through the camera equation and the exposure that auto-exposure sets on the
background; the chain then adds blur, noise and quantisation.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from csuas.core.camera import auto_exposure_s, electron_rate, focal_plane_illuminance_lx, photons_per_lumen
from csuas.render.imaging.eo import LUMINANCE_WEIGHTS, render_eo
from csuas.render.imaging.labels import label
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
from csuas.render.imaging.sensor_chain import ChainSettings, apply_chain


def eo_frame(
    target,
    view: View,
    sensor: EoSensor,
    light: Daylight,
    camera: dict,
    chain: ChainSettings,
    *,
    seed: int,
    quality: str = "draft",
    atmosphere: bool = False,
) -> dict:
    """Render, expose, degrade and label one full EO frame.

    Parameters
    ----------
    target : str or Drone
        Drone preset or model.
    view, sensor, light
        As :func:`csuas.render.imaging.eo.render_eo`.
    camera : dict
        ``f_number``, ``optics_transmittance``, ``pixel_pitch_um``, ``quantum_efficiency``,
        ``max_exposure_ms``, ``full_well_e`` (a scenario's EO parameters).
    chain : ChainSettings
        Sensor-chain stages and constants; its exposure is replaced by the auto-exposure.
    seed : int
        Render and noise seed.
    quality : str
        Render quality preset.
    atmosphere : bool
        Koschmieder path of the render.

    Returns
    -------
    dict
        ``result`` (the window's ImagingResult), ``luminance`` (frame, cd/m^2), ``electrons`` (mean
        signal), ``chain`` (:func:`apply_chain`'s output), ``label``, ``exposure_s`` and
        ``background_luminance``.
    """
    res = render_eo(target, view, sensor, light, atmosphere=atmosphere, settings=RenderSettings(quality, seed))
    if light.background == "sky":
        background = float(res.values["sky_radiance"])
    else:
        background = float(light.background) * light.illuminance_lx / math.pi
    frame = np.full((sensor.n_v, sensor.n_h), background)
    window = res.window
    frame[window.y0 : window.y0 + window.height, window.x0 : window.x0 + window.width] = np.tensordot(
        LUMINANCE_WEIGHTS, res.image, axes=1
    )
    per_lux = electron_rate(1.0, camera["pixel_pitch_um"], camera["quantum_efficiency"], photons_per_lumen())
    rate = per_lux * focal_plane_illuminance_lx(frame, camera["f_number"], camera["optics_transmittance"])
    background_rate = per_lux * focal_plane_illuminance_lx(
        background, camera["f_number"], camera["optics_transmittance"]
    )
    exposure = float(auto_exposure_s(background_rate, camera["full_well_e"], camera["max_exposure_ms"] / 1000.0))
    electrons = rate * exposure
    settings = replace(chain, exposure_s=exposure, full_well_e=camera["full_well_e"])
    return {
        "result": res,
        "luminance": frame,
        "electrons": electrons,
        "chain": apply_chain(electrons, settings, seed),
        "label": label(res.coverage, window.x0, window.y0, sensor.n_h, sensor.n_v),
        "exposure_s": exposure,
        "background_luminance": background,
    }
