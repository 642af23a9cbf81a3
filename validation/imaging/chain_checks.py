"""The sensor chain measured by the methods a camera lab uses (report ``imaging.sensor_chain``).

* :func:`slanted_edge_mtf` -- ISO 12233: a half-plane tilted 5 degrees, box-filtered by the pixels
  (supersampled), through the chain's optics; the pixels' distances to the edge give a super-resolved
  edge spread function in quarter-pixel bins, its derivative the line spread function, whose Fourier
  transform (corrected for the binning and the central difference, sinc(nu d) sinc(2 nu d)) is the MTF.
* :func:`photon_transfer` -- EMVA 1288: flat fields at ten levels, the variance of the difference of
  two frames against the mean; the slope is 1/gain, the intercept the read noise plus 1/12 DN^2.
* :func:`flat_field_netd` -- the temporal standard deviation of a flat thermal frame.
"""

from __future__ import annotations

import math

import numpy as np

from csuas.render.imaging.sensor_chain import ChainSettings, apply_chain, chain_mtf


def edge_image(size: int = 128, angle_deg: float = 5.0, supersample: int = 32) -> tuple[np.ndarray, np.ndarray]:
    """A dark-to-bright half-plane through the frame's centre, box-filtered by square pixels, and its unit normal."""
    theta = math.radians(angle_deg)
    normal = np.array([math.cos(theta), math.sin(theta)])
    sub = (np.arange(size * supersample) + 0.5) / supersample - size / 2.0
    x, y = np.meshgrid(sub, sub, indexing="xy")
    bright = (x * normal[0] + y * normal[1] > 0.0).astype(float)
    return bright.reshape(size, supersample, size, supersample).mean(axis=(1, 3)), normal


def slanted_edge_mtf(settings: ChainSettings, size: int = 128, step: float = 0.25) -> dict:
    """Measured and analytic MTF up to Nyquist of the chain's optics on a slanted edge (module docstring).

    Returns
    -------
    dict
        ``frequency_cy_px``, ``measured``, ``analytic`` (arrays) and ``max_abs_difference``.
    """
    edge, normal = edge_image(size)
    image = apply_chain(1000.0 * edge, settings, seed=0)["signal"].astype(float)
    centre = (np.arange(size) + 0.5) - size / 2.0
    x, y = np.meshgrid(centre, centre, indexing="xy")
    distance = (x * normal[0] + y * normal[1]).ravel()
    near = np.abs(distance) < 16.0
    bins = np.floor(distance[near] / step).astype(int)
    bins -= bins.min()
    esf = np.bincount(bins, weights=image.ravel()[near]) / np.bincount(bins)
    lsf = np.gradient(esf, step)
    spectrum = np.abs(np.fft.rfft(lsf))
    frequency = np.fft.rfftfreq(len(lsf), d=step)
    measured = spectrum / spectrum[0] / (np.sinc(frequency * step) * np.sinc(2 * frequency * step))
    keep = frequency <= 0.5
    analytic = chain_mtf(frequency[keep], settings)
    return {
        "frequency_cy_px": frequency[keep],
        "measured": measured[keep],
        "analytic": analytic,
        "max_abs_difference": float(np.max(np.abs(measured[keep] - analytic))),
    }


def photon_transfer(settings: ChainSettings, levels_e=None, size: int = 256) -> dict:
    """Gain [e/DN] and read noise [e] from a photon-transfer curve (module docstring)."""
    levels = np.geomspace(20.0, 0.8 * settings.full_well_e, 10) if levels_e is None else np.asarray(levels_e)
    means, variances = [], []
    for level in levels:
        flat = np.full((size, size), float(level))
        a = apply_chain(flat, settings, seed=1)["dn"].astype(float)
        b = apply_chain(flat, settings, seed=2)["dn"].astype(float)
        means.append(0.5 * (a.mean() + b.mean()))
        variances.append(np.var(a - b) / 2.0)
    slope, intercept = np.polyfit(means, variances, 1)
    gain = 1.0 / slope
    return {"gain_e_per_dn": float(gain), "read_noise_e": float(math.sqrt(max(intercept - 1.0 / 12.0, 0.0)) * gain)}


def flat_field_netd(settings: ChainSettings, temperature_k: float = 300.0, size: int = 256) -> float:
    """Temporal noise [K] of a flat thermal frame through the chain."""
    return float(np.std(apply_chain(np.full((size, size), temperature_k), settings, seed=4, thermal=True)["signal"]))


def rendered_snr_against_core(illuminances_lx=(70000.0, 3.0, 0.01), range_m: float = 300.0) -> list[dict]:
    """The target's blob SNR measured on rendered full frames against the core's camera model, per light level.

    Rendered: the DJI Mini 4 Pro's frame in mean photoelectrons (:func:`csuas.render.imaging.frame.eo_frame`,
    default camera), its electrons above the background behind it summed over its window, against
    that background's shot and read noise (:func:`csuas.render.imaging.frame.target_snr`). Core: the same
    camera's background electrons from :mod:`csuas.core.camera` (camera equation, photons per lumen,
    auto-exposure) and the render's Michelson contrast and pixels on target (Eq. 3 inverted).

    Returns
    -------
    list of dict
        ``illuminance_lx``, ``snr_rendered``, ``snr_core``, ``background_e_rendered``, ``background_e_core``.
    """
    from csuas.core import camera, detection
    from csuas.defaults import default_values
    from csuas.render.imaging.frame import camera_from_params, eo_frame, target_snr
    from csuas.render.imaging.records import Daylight, EoSensor, View

    settings = camera_from_params()
    read = float(default_values("eo")["read_noise_e"])
    rows = []
    for lux in illuminances_lx:
        light = Daylight(illuminance_lx=float(lux), background=0.3)
        frame = eo_frame(
            "dji_mini_4_pro", View(range_m, 30.0, 10.0), EoSensor(), light, settings, ChainSettings(stages=()), seed=0
        )
        background = frame["background_behind_e"]
        pixels = float(frame["label"]["pixels_on_target"])
        rendered = target_snr(frame, read)
        luminance = 0.3 * float(lux) / math.pi
        rate = camera.electron_rate(
            camera.focal_plane_illuminance_lx(luminance, settings["f_number"], settings["optics_transmittance"]),
            settings["pixel_pitch_um"],
            settings["quantum_efficiency"],
            camera.photons_per_lumen(),
        )
        exposure = camera.auto_exposure_s(rate, settings["full_well_e"], settings["max_exposure_ms"] / 1000.0)
        s_b = float(rate * exposure)
        contrast = float(frame["result"].values["contrast"])
        core = float(
            detection.blob_snr(abs(float(camera.luminance_excess(contrast))) * s_b, math.sqrt(s_b + read**2), pixels)
        )
        rows.append(
            {
                "illuminance_lx": float(lux),
                "snr_rendered": rendered,
                "snr_core": core,
                "background_e_rendered": background,
                "background_e_core": s_b,
            }
        )
    return rows
