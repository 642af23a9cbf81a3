"""The sensor chain measured by the methods a camera lab uses (report ``imaging.sensor_chain``).

* :func:`slanted_edge_mtf` -- ISO 12233: a half-plane tilted 5 degrees, box-filtered by the pixels
  (supersampled), through the chain's optics; the pixels' distances to the edge give a super-resolved
  edge spread function in quarter-pixel bins, its derivative the line spread function, whose Fourier
  transform (corrected for the binning and the central difference, sinc(nu d) sinc(2 nu d)) is the MTF.
* :func:`photon_transfer` -- EMVA 1288: flat fields at ten levels, the variance of the difference of
  two frames against the mean; the slope is 1/gain, the intercept the read noise plus 1/12 DN^2.
* :func:`flat_field_netd` -- the temporal standard deviation of a flat thermal frame.
* :func:`rendered_snr_against_core` and :func:`rendered_light_limited_range` -- rendered full frames'
  target SNR, and the range where it meets the detection threshold, against the core's camera model.
"""

from __future__ import annotations

import math

import numpy as np

from csuas.core import camera, detection
from csuas.defaults import default_values
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
    from csuas.render.imaging.frame import camera_from_params, eo_frame, target_snr
    from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View

    optics = camera_from_params()
    read = float(default_values("eo")["read_noise_e"])
    rows = []
    for lux in illuminances_lx:
        light = Daylight(illuminance_lx=float(lux), background=0.3)
        frame = eo_frame(
            "dji_mini_4_pro",
            View(range_m, 30.0, 10.0),
            EoSensor(),
            light,
            optics,
            ChainSettings(stages=()),
            settings=RenderSettings(quality="draft", seed=0),
        )
        background = frame["background_behind_e"]
        pixels = float(frame["label"]["pixels_on_target"])
        rendered = target_snr(frame, read)
        luminance = 0.3 * float(lux) / math.pi
        rate = camera.electron_rate(
            camera.focal_plane_illuminance_lx(luminance, optics["f_number"], optics["optics_transmittance"]),
            optics["pixel_pitch_um"],
            optics["quantum_efficiency"],
            camera.photons_per_lumen(),
        )
        exposure = camera.auto_exposure_s(rate, optics["full_well_e"], optics["max_exposure_ms"] / 1000.0)
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


def _relative_stderr(result) -> float:
    """Relative standard error of a render's blob SNR: those of its pixels on target and contrast combined."""
    values, stderr = result.values, result.stderr
    return math.hypot(
        stderr["pixels_on_target"] / values["pixels_on_target"], stderr["contrast"] / abs(values["contrast"])
    )


def rendered_light_limited_range(
    illuminances_lx=(70000.0, 3.0, 0.01), quality: str = "standard", reference_range_m: float = 300.0
) -> list[dict]:
    """The range where rendered frames' target SNR falls to the detection threshold, against the core's.

    Rendered: :func:`csuas.render.imaging.frame.target_snr` of the DJI Mini 4 Pro's full frames (default
    camera, 30 deg azimuth, 10 deg elevation, Lambertian 0.3 background, no atmosphere) at ranges found
    by bisection in log range until the SNR meets Q^-1(Pfa) - Q^-1(p_desired) of the scenario's EO
    (0.01 % in range). Core: :func:`csuas.core.camera.light_limited_range_m` given the render's inherent
    Michelson contrast and projected area (pixels on target times the pixel footprint at
    ``reference_range_m``), no transmittance loss, and no dark current (the frame's SNR counts shot and
    read noise only). The render's pixels and contrast enter both, so what is compared is how the
    frame's SNR falls with range: resolved blobs, sub-pixel dilution and the frame assembly.

    Returns
    -------
    list of dict
        ``illuminance_lx``, ``range_rendered_m``, ``range_core_m``, ``required_snr``,
        ``relative_stderr`` (of the rendered SNR at its range and of the reference render's, which
        the core is given: their Monte Carlo errors of pixels on target and contrast combined),
        ``renders``.
    """
    from csuas.render.imaging.frame import camera_from_params, eo_frame, target_snr
    from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View

    optics = camera_from_params()
    eo = default_values("eo")
    read = float(eo["read_noise_e"])
    required = float(detection.gaussian_required_snr(eo["p_desired"], eo["pfa"]))
    rows = []
    for lux in illuminances_lx:
        light = Daylight(illuminance_lx=float(lux), background=0.3)

        def frame_at(range_m, light=light):
            view = View(float(range_m), 30.0, 10.0)
            return eo_frame(
                "dji_mini_4_pro",
                view,
                EoSensor(),
                light,
                optics,
                ChainSettings(stages=()),
                settings=RenderSettings(quality=quality, seed=0),
            )

        reference = frame_at(reference_range_m)["result"]
        ifov = reference.ifov_rad
        area = reference.values["pixels_on_target"] * (reference_range_m * ifov) ** 2
        # the frame's camera: f-number, optics, pixel, QE, exposure limit, full well
        chain = camera.CameraChain(**optics, read_noise_e=read, dark_current_e_s=0.0, required_snr=required)
        core, _ = camera.light_limited_range_m(
            chain,
            illuminance_lx=float(lux),
            background_reflectance=0.3,
            c_eo=float(reference.values["contrast"]),
            transmittance_at=np.ones_like,
            projected_area_m2=area,
            ifov_rad_=ifov,
        )
        low, high, renders = math.log(core / 2.0), math.log(core * 2.0), 0
        while high - low > 1e-4:
            middle = 0.5 * (low + high)
            renders += 1
            if target_snr(frame_at(math.exp(middle)), read) >= required:
                low = middle
            else:
                high = middle
        at_root = frame_at(math.exp(0.5 * (low + high)))["result"]
        relative = math.hypot(_relative_stderr(at_root), _relative_stderr(reference))
        rows.append(
            {
                "illuminance_lx": float(lux),
                "range_rendered_m": math.exp(0.5 * (low + high)),
                "range_core_m": float(core),
                "required_snr": required,
                "relative_stderr": relative,
                "renders": renders + 2,
            }
        )
    return rows
