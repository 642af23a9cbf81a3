"""The camera after the lens: optics blur, detector noise and quantisation, each stage a seeded switch.

Input: the mean signal of each pixel of a rendered frame, already integrated over the pixel's area
(the renderer's box filter is the detector footprint), as photoelectrons for EO
(:func:`csuas.core.camera.electron_rate` times the exposure) or as apparent temperature [K] for
thermal frames. Only the stages named in ``stages`` run, in this order:

``psf``
    Diffraction of a circular aperture at the f-number and wavelength, MTF
    (2/pi)(acos x - x sqrt(1 - x^2)), x = nu / nu_c, nu_c = 1 / (lambda N) (Goodman, *Introduction to
    Fourier Optics*, 3rd ed., 2005, Eq. 6-31), and Gaussian line-of-sight jitter of ``jitter_px``
    rms, MTF exp(-2 pi^2 sigma^2 nu^2) (Holst 2008, ch. 10); applied by FFT on the pixel grid
    (periodic boundaries).
``shot_noise``
    Poisson photoelectrons (EO).
``dark_current``
    Poisson dark electrons, ``dark_current_e_s`` x ``exposure_s`` (EO).
``prnu``, ``dsnu``
    Fixed pattern: a per-pixel gain of 1 + ``prnu`` N(0, 1) and an offset of ``dsnu_e`` N(0, 1)
    electrons, drawn from the camera's own seed, the same for every frame of that camera.
``read_noise``
    Gaussian read noise of ``read_noise_e`` rms (EO); for thermal frames ``netd``: Gaussian temporal
    noise of ``netd_k`` rms on the temperature.
``quantise``
    EO: the conversion gain ``full_well_e / (2^bits - 1)`` electrons per DN, clipped at full well
    (saturation) and rounded to ``bits`` bits; thermal: the span ``t_min_k`` to ``t_max_k`` over the
    DN range.

The chain's analytic MTF (:func:`chain_mtf`) is the product of the optics and jitter MTFs and the
pixel footprint's sinc; tests measure it on a slanted edge (ISO 12233) and the noise stages by a
photon-transfer curve (EMVA 1288).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csuas.base.errors import InputErrors, ParameterError

#: Stage names in the order they run.
STAGES = ("psf", "shot_noise", "dark_current", "prnu", "dsnu", "read_noise", "netd", "quantise")


@dataclass(frozen=True)
class ChainSettings:
    """Camera constants of :func:`apply_chain` (see the module docstring for each stage).

    Attributes
    ----------
    stages : tuple of str
        Stages to run, a subset of :data:`STAGES`.
    f_number, wavelength_um, pixel_pitch_um, jitter_px : float
        Optics [-], centre wavelength [um], pixel pitch [um], jitter [px rms].
    exposure_s, full_well_e, read_noise_e, dark_current_e_s, prnu, dsnu_e : float
        EO detector: exposure [s], full well [e], read noise [e rms], dark current [e/s], PRNU [-],
        DSNU [e rms].
    netd_k, t_min_k, t_max_k : float
        Thermal: temporal noise [K rms] and the temperature span of the DN range [K].
    bits : int
        Quantisation depth, 8, 10, 12, 14 or 16.
    """

    stages: tuple = ("psf", "shot_noise", "read_noise", "quantise")
    f_number: float = 2.0
    wavelength_um: float = 0.55
    pixel_pitch_um: float = 2.9
    jitter_px: float = 0.0
    exposure_s: float = 0.0333
    full_well_e: float = 10000.0
    read_noise_e: float = 2.0
    dark_current_e_s: float = 5.0
    prnu: float = 0.0
    dsnu_e: float = 0.0
    netd_k: float = 0.05
    t_min_k: float = 250.0
    t_max_k: float = 350.0
    bits: int = 12

    def validate(self) -> None:
        """All invalid settings at once, each naming its value and valid range."""
        errors = []
        unknown = [s for s in self.stages if s not in STAGES]
        if unknown:
            errors.append(ParameterError("stages", unknown, ", ".join(STAGES)))
        positive = ("f_number", "wavelength_um", "pixel_pitch_um", "exposure_s", "full_well_e")
        for name in positive:
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                errors.append(ParameterError(name, value, "0 < x < inf"))
        for name in ("jitter_px", "read_noise_e", "dark_current_e_s", "prnu", "dsnu_e", "netd_k"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0):
                errors.append(ParameterError(name, value, "0 <= x < inf"))
        if self.bits not in (8, 10, 12, 14, 16):
            errors.append(ParameterError("bits", self.bits, "8, 10, 12, 14 or 16"))
        if not self.t_max_k > self.t_min_k:
            errors.append(ParameterError("t_max_k", self.t_max_k, f"> t_min_k = {self.t_min_k}"))
        if errors:
            raise InputErrors(errors)

    @property
    def gain_e_per_dn(self) -> float:
        """Conversion gain [e/DN]: the full well over the DN range."""
        return self.full_well_e / (2**self.bits - 1)


def optics_mtf(frequency_cy_px, settings: ChainSettings):
    """Diffraction times jitter MTF at spatial frequencies [cycles per pixel] (module docstring)."""
    nu = np.abs(np.asarray(frequency_cy_px, float)) / (settings.pixel_pitch_um * 1e-3)  # cycles per mm
    cutoff = 1.0 / (settings.wavelength_um * 1e-3 * settings.f_number)  # cycles per mm
    x = np.clip(nu / cutoff, 0.0, 1.0)
    diffraction = (2.0 / np.pi) * (np.arccos(x) - x * np.sqrt(1.0 - x * x))
    f_px = np.abs(np.asarray(frequency_cy_px, float))
    jitter = np.exp(-2.0 * np.pi**2 * settings.jitter_px**2 * f_px**2)
    return diffraction * jitter


def chain_mtf(frequency_cy_px, settings: ChainSettings):
    """The optics and jitter MTF times the pixel footprint's |sinc(nu)| (what a slanted edge measures)."""
    return optics_mtf(frequency_cy_px, settings) * np.abs(np.sinc(np.asarray(frequency_cy_px, float)))


def _blur(image: np.ndarray, settings: ChainSettings) -> np.ndarray:
    fy = np.fft.fftfreq(image.shape[0])[:, None]
    fx = np.fft.rfftfreq(image.shape[1])[None, :]
    transfer = optics_mtf(np.hypot(fx, fy), settings)
    return np.fft.irfft2(np.fft.rfft2(image) * transfer, s=image.shape)


def fixed_pattern(shape, camera_seed: int) -> tuple[np.ndarray, np.ndarray]:
    """The camera's per-pixel gain and offset patterns, standard normal, from the camera's own stream."""
    rng = np.random.default_rng([int(camera_seed), 1])
    return rng.standard_normal(shape), rng.standard_normal(shape)


def apply_chain(
    signal: np.ndarray, settings: ChainSettings, seed: int, *, thermal: bool = False, camera_seed: int = 0
) -> dict:
    """Run the chain's stages on a frame of mean signals (electrons, or kelvin when ``thermal``).

    Parameters
    ----------
    signal : ndarray (H, W)
        Mean photoelectrons per pixel (EO) or apparent temperature [K] (thermal), finite, >= 0 for EO.
    settings : ChainSettings
    seed : int
        Seeds the temporal noise of this frame.
    thermal : bool
        Thermal frame: only ``psf``, ``netd`` and ``quantise`` apply.
    camera_seed : int
        Seeds the camera's fixed pattern (:func:`fixed_pattern`), the same for all its frames.

    Returns
    -------
    dict
        ``signal`` (float32, the last stage before quantisation, electrons or K) and, with
        ``quantise``, ``dn`` (uint16) and ``saturated`` (the fraction of pixels clipped).
    """
    settings.validate()
    image = np.asarray(signal, dtype=float)
    if image.ndim != 2 or not np.isfinite(image).all() or (not thermal and image.min() < 0):
        raise ParameterError("signal", f"array of shape {image.shape}", "a finite 2-D frame, >= 0 for EO")
    rng = np.random.default_rng([int(seed), 0])
    stages = set(settings.stages)
    if "psf" in stages:
        image = _blur(image, settings)
        if not thermal:
            image = np.maximum(image, 0.0)  # ringing of the band-limited blur below zero
    if thermal:
        if "netd" in stages:
            image = image + settings.netd_k * rng.standard_normal(image.shape)
    else:
        if "shot_noise" in stages:
            image = rng.poisson(image).astype(float)
        if "dark_current" in stages:
            image = image + rng.poisson(settings.dark_current_e_s * settings.exposure_s, image.shape)
        gain_pattern, offset_pattern = fixed_pattern(image.shape, camera_seed)
        if "prnu" in stages:
            image = image * (1.0 + settings.prnu * gain_pattern)
        if "dsnu" in stages:
            image = image + settings.dsnu_e * offset_pattern
        if "read_noise" in stages:
            image = image + settings.read_noise_e * rng.standard_normal(image.shape)
    out = {"signal": image.astype(np.float32)}
    if "quantise" in stages:
        top = 2**settings.bits - 1
        if thermal:
            scaled = (image - settings.t_min_k) / (settings.t_max_k - settings.t_min_k) * top
        else:
            scaled = image / settings.gain_e_per_dn
        out["saturated"] = float(np.mean(scaled > top))
        out["dn"] = np.clip(np.rint(scaled), 0, top).astype(np.uint16)
    return out
