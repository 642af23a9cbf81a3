"""A full EO frame as the camera delivers it: the rendered target in its window, the background around
it, the camera's radiometry (:mod:`csuas.core.camera`), the sensor chain
(:mod:`csuas.render.imaging.sensor_chain`) and the target's label (:mod:`csuas.render.imaging.labels`).

The target is rendered in its window only (range-normalised, exact geometry,
:func:`csuas.render.imaging.eo.render_eo`); the rest of the frame is the background's luminance:
uniform (the horizon sky of the render or a Lambertian background) or the CIE clear sky with the
ground below the horizon (:mod:`csuas.render.imaging.background`). Luminance becomes mean
photoelectrons through the camera equation and the exposure that auto-exposure sets on the
background; the chain then adds blur, noise and quantisation.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from csuas.core.camera import auto_exposure_s, electron_rate, focal_plane_illuminance_lx, photons_per_lumen
from csuas.core.checks import require
from csuas.core.detection import blob_snr
from csuas.core.radiometry import band_radiance, radiance_temperature
from csuas.defaults import default_values
from csuas.render.imaging.background import clear_sky_frame
from csuas.render.imaging.camera import SensorGeometry
from csuas.render.imaging.common import silhouette_box_px
from csuas.render.imaging.eo import LUMINANCE_WEIGHTS, render_eo
from csuas.render.imaging.labels import label
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
from csuas.render.imaging.sensor_chain import ChainSettings, apply_chain

#: The EO parameters of the camera's radiometry (defaults/parameters.toml, section eo).
CAMERA_KEYS = (
    "f_number",
    "optics_transmittance",
    "pixel_pitch_um",
    "quantum_efficiency",
    "max_exposure_ms",
    "full_well_e",
)


def camera_from_params(params: dict | None = None) -> dict:
    """The ``camera`` argument of :func:`eo_frame` from a scenario's EO parameters (default: the defaults)."""

    source = default_values("eo") if params is None else params
    return {key: source[key] for key in CAMERA_KEYS}


def eo_frame(
    target,
    view: View,
    sensor: EoSensor,
    light: Daylight,
    camera: dict,
    chain: ChainSettings,
    *,
    settings: RenderSettings = RenderSettings(quality="draft"),
    atmosphere: bool = False,
) -> dict:
    """Render, expose, degrade and label one full EO frame.

    Parameters
    ----------
    target : str or Drone
        Drone preset or model.
    view, sensor, light
        As :func:`csuas.render.imaging.eo.render_eo`; ``light.background`` may also be ``"clear_sky"``: the
        CIE clear sky's gradient from the sun and the ground below the horizon
        (:mod:`csuas.render.imaging.background`), without atmosphere, with ``light.cloud_cover`` of its sky
        under seeded clouds (0..1).
    camera : dict
        ``f_number``, ``optics_transmittance``, ``pixel_pitch_um``, ``quantum_efficiency``,
        ``max_exposure_ms``, ``full_well_e`` (a scenario's EO parameters).
    chain : ChainSettings
        Sensor-chain stages and constants; its exposure is replaced by the auto-exposure.
    settings : RenderSettings
        The render's quality (default draft) and seed, which also seeds the clouds and the chain's noise.
    atmosphere : bool
        Koschmieder path of the render (``light``'s visibility, rain, convention and fog layer): the frame's
        uniform background is the render's apparent one; over a ``"clear_sky"`` gradient the target's covered
        share takes the path's transmittance and the horizon sky's airlight while the gradient itself (the sky
        seen through the whole atmosphere) stays as it is (the ground's own aerial perspective is left out).

    Returns
    -------
    dict
        ``result`` (the window's ImagingResult), ``luminance`` (frame, cd/m^2), ``electrons`` (mean
        signal), ``target_excess_e`` (the target's electrons over the background behind it, summed),
        ``background_behind_e`` (the mean background electrons of the target's window), ``chain``
        (:func:`apply_chain`'s output), ``label``, ``exposure_s`` and ``background_luminance`` (the
        uniform background, or the gradient frame's median, which the auto-exposure uses).
    """
    gradient = light.background == "clear_sky"
    lit = replace(light, background="sky") if gradient else light
    seed = settings.seed
    res = render_eo(target, view, sensor, lit, atmosphere=atmosphere, settings=settings)
    # the render's uniform background at the sensor (the sky, or rho E / pi), after the path when there is one
    background = float(res.values["background_radiance_apparent"])
    window = res.window
    rows = slice(window.y0, window.y0 + window.height)
    cols = slice(window.x0, window.x0 + window.width)
    rendered = np.tensordot(LUMINANCE_WEIGHTS, res.image, axes=1)
    if gradient:
        geometry = SensorGeometry(res.ifov_rad, sensor.n_h, sensor.n_v)
        frame = clear_sky_frame(geometry, view, light, cloud_cover=light.cloud_cover, seed=seed)
        behind = frame[rows, cols].copy()
        uncovered = 1.0 - res.coverage
        # the render's uniform sky leaves the target's own light; the gradient fills what it does not cover
        frame[rows, cols] = rendered - uncovered * background + uncovered * behind
        background = float(np.median(frame))
    else:
        frame = np.full((sensor.n_v, sensor.n_h), background)
        behind = np.full(rendered.shape, background)
        frame[rows, cols] = rendered
    per_lux = electron_rate(1.0, camera["pixel_pitch_um"], camera["quantum_efficiency"], photons_per_lumen())
    rate = per_lux * focal_plane_illuminance_lx(frame, camera["f_number"], camera["optics_transmittance"])
    background_rate = per_lux * focal_plane_illuminance_lx(
        background, camera["f_number"], camera["optics_transmittance"]
    )
    exposure = float(auto_exposure_s(background_rate, camera["full_well_e"], camera["max_exposure_ms"] / 1000.0))
    electrons = rate * exposure
    electrons_per_nit = float(
        per_lux * focal_plane_illuminance_lx(1.0, camera["f_number"], camera["optics_transmittance"])
    )
    exposed_chain = replace(chain, exposure_s=exposure, full_well_e=camera["full_well_e"])
    return {
        "result": res,
        "luminance": frame,
        "electrons": electrons,
        "target_excess_e": float(np.sum(frame[rows, cols] - behind)) * electrons_per_nit * exposure,
        "background_behind_e": float(np.mean(behind)) * electrons_per_nit * exposure,
        "chain": apply_chain(electrons, exposed_chain, seed),
        "label": frame_label(target, view, res, sensor.n_h, sensor.n_v, chain),
        "exposure_s": exposure,
        "background_luminance": background,
    }


def frame_label(target, view: View, result, n_h: int, n_v: int, chain: ChainSettings | None = None) -> dict:
    """The target's label (:func:`csuas.render.imaging.labels.label`) from the render's coverage.

    ``clipped`` is set whenever any part of the silhouette (its projected mesh, :func:`silhouette_box_px`) lies
    outside the frame: the render's window stops at the frame's edge, so its coverage cannot show what lies
    beyond; ``visibility`` is the share of the silhouette's box inside the frame. With the chain's
    ``rolling_shutter`` the coverage is read row by row as the frame is
    (:func:`csuas.render.imaging.sensor_chain.rolling_shutter`), so the box follows the skewed drone.
    """
    window = result.window
    coverage, x0, y0 = result.coverage, window.x0, window.y0
    if chain is not None and "rolling_shutter" in chain.stages and chain.line_time_s > 0:
        coverage, x0, y0 = _read_by_rows(coverage, x0, y0, chain, n_v)
    out = label(coverage, x0, y0, n_h, n_v)
    geometry = SensorGeometry(result.ifov_rad, n_h, n_v)
    cx, cy = geometry.default_target_px()
    centre = (cx + view.target_offset_px[0], cy + view.target_offset_px[1])
    x_lo, x_hi, y_lo, y_hi = silhouette_box_px(
        target, view.range_m, view.azimuth_deg, view.elevation_deg, geometry, centre
    )
    out["clipped"] = bool(out["clipped"] or x_lo < 0 or y_lo < 0 or x_hi > n_h or y_hi > n_v)
    inside = max(min(x_hi, n_h) - max(x_lo, 0.0), 0.0) * max(min(y_hi, n_v) - max(y_lo, 0.0), 0.0)
    out["visibility"] = float(inside / max((x_hi - x_lo) * (y_hi - y_lo), 1e-12))
    return out


def _read_by_rows(coverage: np.ndarray, x0: int, y0: int, chain: ChainSettings, n_v: int) -> tuple:
    """A window's coverage as the rolling shutter reads it, padded by the farthest its rows move, and its origin."""
    from csuas.render.imaging.sensor_chain import rolling_shutter

    farthest_s = max(abs(y0 - (n_v - 1) / 2.0), abs(y0 + coverage.shape[0] - (n_v - 1) / 2.0)) * chain.line_time_s
    pad = int(math.ceil(math.hypot(*chain.velocity_px_s) * farthest_s)) + 2
    padded = np.pad(coverage, pad)
    read = rolling_shutter(padded, chain.line_time_s, chain.velocity_px_s, first_row=y0 - pad, rows=n_v)
    return np.clip(read, 0.0, 1.0), x0 - pad, y0 - pad


def target_snr(frame: dict, read_noise_e: float) -> float:
    """Blob SNR of an :func:`eo_frame`'s target: its excess electrons over the pixels it covers (at least one)
    against the shot noise of the background behind it and the read noise (:func:`csuas.core.detection.blob_snr`)."""

    pixels = float(max(frame["label"]["pixels_on_target"], 1e-12))
    noise = math.sqrt(frame["background_behind_e"] + read_noise_e**2)
    return float(blob_snr(abs(frame["target_excess_e"]) / pixels, noise, pixels))


def tir_frame(
    target,
    view: View,
    sensor,
    scene,
    chain: ChainSettings,
    *,
    settings: RenderSettings = RenderSettings(quality="draft"),
    reflected_surroundings: bool = True,
    sky_temperature_k: float | None = None,
) -> dict:
    """Render, degrade and label one full thermal frame (apparent temperature through the chain).

    The path (transmittance and path radiance, :func:`csuas.render.imaging.path.tir_path`) is the scene's
    where it gives ``extinction_db_km`` (a scenario's, :func:`csuas.render.imaging.modes.scenario_thermal_scene`),
    none where that is None; the background around the window is then the render's apparent one (a sky of
    ``sky_temperature_k`` is the sky seen through the whole atmosphere already).

    The window's band radiance (:func:`csuas.render.imaging.tir.render_tir`) is pasted on the
    background's (the window's uncovered pixels, uniform), turned into apparent temperature
    (:func:`csuas.core.radiometry.radiance_temperature`) and passed through the chain's thermal stages
    (``psf`` at the chain's wavelength, ``netd``, ``agc``, ``quantise``). With ``sky_temperature_k``
    the frame is split at the horizon (:func:`csuas.render.imaging.background.view_rays`): a blackbody
    sky of that apparent temperature [K] above it, the scene's background below, and the window's
    uncovered share of each pixel shows what lies behind it. ``settings``: the render's quality
    (default draft) and seed, which also seeds the chain's noise.

    Returns
    -------
    dict
        ``result``, ``temperature`` (frame [K]), ``chain``, ``label``, ``background_k`` (the ground, or
        the uniform background), ``target_excess_k`` (the target's apparent temperature over what lies
        behind it, summed over its window [K px]) and ``delta_t_k`` (the render's silhouette-averaged
        Delta T, taken against what lies behind the silhouette).
    """
    from csuas.render.imaging.background import view_rays
    from csuas.render.imaging.tir import render_tir

    res = render_tir(
        target,
        view,
        sensor,
        scene,
        atmosphere=scene.extinction_db_km is not None,
        reflected_surroundings=reflected_surroundings,
        settings=settings,
    )
    radiance = res.image[0]
    uncovered = res.coverage == 0
    background = float(np.median(radiance[uncovered])) if uncovered.any() else float(np.median(radiance))
    frame = np.full((sensor.n_v, sensor.n_h), background)
    if sky_temperature_k is not None:
        rays = view_rays(
            sensor.n_h, sensor.n_v, res.ifov_rad, view.azimuth_deg, view.elevation_deg, view.target_offset_px
        )
        sky = float(band_radiance(require("sky_temperature_k", sky_temperature_k, gt=0), sensor.band))
        frame = np.where(rays[..., 2] > 0.0, sky, background)
    window = res.window
    rows, cols = slice(window.y0, window.y0 + window.height), slice(window.x0, window.x0 + window.width)
    behind = frame[rows, cols].copy()
    frame[rows, cols] = radiance + (1.0 - res.coverage) * (behind - background)
    temperature = radiance_temperature(frame, sensor.band)
    behind_k = radiance_temperature(behind, sensor.band)
    excess = float(np.sum(temperature[rows, cols] - behind_k))
    background_k = float(radiance_temperature(background, sensor.band))
    covered = float(np.sum(res.coverage))
    behind_target_k = float(np.sum(res.coverage * behind_k) / covered) if covered > 0 else background_k
    return {
        "result": res,
        "temperature": temperature,
        "chain": apply_chain(temperature, chain, settings.seed, thermal=True),
        "label": frame_label(target, view, res, sensor.n_h, sensor.n_v, chain),
        "background_k": background_k,
        "target_excess_k": excess,
        "delta_t_k": float(res.values["delta_t_k"]) + background_k - behind_target_k,
    }
