"""Closing the loop: a detector run on rendered, noisy frames gives an empirical Pd against range.

For each range the drone is rendered once (its window, exact coverage), turned into mean
photoelectrons by the camera (:func:`csuas.render.imaging.frame.eo_frame`'s radiometry) and
blurred by the optics; then ``trials`` noisy frames with the target and as many without it are
drawn by the sensor chain (shot and read noise). The detector is a matched filter: the statistic
T = sum_i w_i (x_i - b) with the target's noise-free excess w as template and the known background
b; its threshold is the (1 - Pfa) quantile of T over the target-free frames. The empirical Pd (the
share of target frames above it) is set beside

* the matched filter's Gaussian prediction Pd = Q((Q^-1(Pfa) sigma_0 - sum w^2) / sigma_1), with
  sigma_0^2 = sum w^2 (b + r^2) and sigma_1^2 = sum w^2 (m_i + r^2) the variances of T without and
  with the target (shot and read noise; Kay, *Fundamentals of Statistical Signal Processing,
  Vol. II*, 1998, ch. 4); ``snr_matched_filter`` = sum w^2 / sigma_0;
* the core's light-limited model (:mod:`csuas.core.camera`: a uniform blob of the rendered contrast
  and pixels on target against the background's noise);
* the TTPF of the Johnson cycles (the paper's Pd model, :func:`csuas.core.detection.imaging_pd`).
"""

from __future__ import annotations

import math

import numpy as np

from csuas.core import camera, detection
from csuas.defaults import default_values
from csuas.render.imaging.eo import LUMINANCE_WEIGHTS, render_eo
from csuas.render.imaging.frame import camera_from_params
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
from csuas.render.imaging.sensor_chain import ChainSettings, apply_chain

#: The default camera of the closed loop (defaults/parameters.toml's eo section), with its read noise.
CAMERA = {**camera_from_params(), "read_noise_e": float(default_values("eo")["read_noise_e"])}


def _matched_filter(rng, mean, background, template, read_noise, count):
    """T = sum w (x - b) of ``count`` frames of Poisson(mean) electrons plus Gaussian read noise."""
    frames = rng.poisson(np.broadcast_to(mean, (count, *mean.shape))) + read_noise * rng.standard_normal(
        (count, *mean.shape)
    )
    return np.tensordot(frames - background, template, axes=([1, 2], [0, 1]))


def closed_loop_pd(
    ranges_m,
    *,
    drone: str = "dji_mini_4_pro",
    illuminance_lx: float = 0.05,
    pfa: float = 0.01,
    trials: int = 2000,
    seed: int = 0,
    quality: str = "draft",
) -> list[dict]:
    """Empirical and predicted Pd per range (module docstring).

    Parameters
    ----------
    ranges_m : sequence of float
        Slant ranges [m].
    drone : str
        Drone preset.
    illuminance_lx : float
        Scene illuminance [lx] (default 50 mlx: deep twilight, where noise decides).
    pfa : float
        False-alarm probability of the threshold (per frame: the detector looks at the target's window).
    trials : int
        Noisy frames with and without the target per range.
    seed, quality
        Render seed and quality.

    Returns
    -------
    list of dict
        Per range: ``range_m``, ``pd_empirical`` and its binomial standard error, ``pd_matched_filter``,
        ``snr_matched_filter``, ``pd_core_light`` (the core's blob model), ``pd_ttpf``,
        ``pixels_on_target``, ``contrast``.
    """
    sensor = EoSensor()
    light = Daylight(illuminance_lx=illuminance_lx)
    per_lux = camera.electron_rate(
        1.0, CAMERA["pixel_pitch_um"], CAMERA["quantum_efficiency"], camera.photons_per_lumen()
    )
    chain = ChainSettings(stages=("psf",), f_number=CAMERA["f_number"], pixel_pitch_um=CAMERA["pixel_pitch_um"])
    rows = []
    for index, r in enumerate(ranges_m):
        res = render_eo(drone, View(float(r), 30.0, 10.0), sensor, light, settings=RenderSettings(quality, seed))
        background_l = float(res.values["sky_radiance"])
        pad = 8
        window = np.pad(np.tensordot(LUMINANCE_WEIGHTS, res.image, axes=1), pad, constant_values=background_l)
        rate = per_lux * camera.focal_plane_illuminance_lx(window, CAMERA["f_number"], CAMERA["optics_transmittance"])
        background_rate = per_lux * float(
            camera.focal_plane_illuminance_lx(background_l, CAMERA["f_number"], CAMERA["optics_transmittance"])
        )
        exposure = float(
            camera.auto_exposure_s(background_rate, CAMERA["full_well_e"], CAMERA["max_exposure_ms"] / 1000.0)
        )
        b = background_rate * exposure
        mean = apply_chain(rate * exposure, chain, seed)["signal"].astype(float)  # optics blur, no noise
        template = mean - b
        rng = np.random.default_rng([seed, index])
        read = CAMERA["read_noise_e"]

        null = _matched_filter(rng, np.full_like(mean, b), b, template, read, trials)
        threshold = np.quantile(null, 1.0 - pfa)
        hits = _matched_filter(rng, mean, b, template, read, trials) > threshold
        pd = float(hits.mean())
        # Gaussian prediction: T has mean sum w^2 and standard deviation sigma_1 with the target,
        # sigma_0 without; the threshold sits at Q^-1(Pfa) sigma_0
        signal = float(np.sum(template**2))
        sigma_0 = math.sqrt(float(np.sum(template**2 * (b + read**2))))
        sigma_1 = math.sqrt(float(np.sum(template**2 * (np.maximum(mean, 0.0) + read**2))))
        snr_mf = signal / sigma_0
        pd_mf = float(
            detection.gaussian_pd(
                max(
                    (signal - detection.gaussian_required_snr(0.5, pfa) * sigma_0) / sigma_1
                    + detection.gaussian_required_snr(0.5, pfa),
                    0.0,
                ),
                pfa,
            )
        )
        pixels = float(res.values["pixels_on_target"])
        contrast = float(res.values.get("contrast_inherent", res.values["contrast"]))  # Michelson (Eq. 3)
        excess = abs(float(camera.luminance_excess(contrast))) * b
        snr_core = float(detection.blob_snr(excess, math.sqrt(b + read**2), pixels))
        ifov = math.radians(sensor.hfov_deg) / sensor.n_h
        r50 = 0.101 / (ifov * 2.0)  # Table 8's d_crit, 1 lp of 2 px (Eq. 17 at n_TTPF = 1)
        rows.append(
            {
                "range_m": float(r),
                "pd_empirical": pd,
                "pd_empirical_stderr": math.sqrt(max(pd * (1 - pd), 1.0 / trials) / trials),
                "pd_matched_filter": pd_mf,
                "snr_matched_filter": snr_mf,
                "pd_core_light": float(detection.gaussian_pd(snr_core, pfa)),
                "pd_ttpf": float(detection.imaging_pd(float(r), r50, "johnson", np.inf)),
                "pixels_on_target": pixels,
                "contrast": contrast,
                "background_e": b,
            }
        )
    return rows
