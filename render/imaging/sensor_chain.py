"""The camera after the lens: optics blur, detector noise and quantisation, each stage a seeded switch.

Input: the mean signal of each pixel of a rendered frame, already integrated over the pixel's area
(the renderer's box filter is the detector footprint), as photoelectrons for EO
(:func:`csuas.core.camera.electron_rate` times the exposure) or as apparent temperature [K] for
thermal frames. Only the stages named in ``stages`` run, in this order:

``frame_exposure``
    A video camera integrates at most one frame period: the exposure becomes min(``exposure_s``,
    1 / ``frame_rate_hz``) and an EO signal (electrons at ``exposure_s``) scales by the same ratio; the
    later stages (``motion``, ``dark_current``) use that exposure.
``rolling_shutter``
    Rows read one after another, ``line_time_s`` apart: row r samples the scene at time
    tau = (r - r_mid) ``line_time_s`` (r_mid the middle row, the frame's reference time), when the scene
    moving at ``velocity_px_s`` (vx, vy) has moved by tau (vx, vy); a vertical edge moving along x is
    skewed by vx ``line_time_s`` pixels per row (Liang, Chang and Chen, IEEE Trans. Image Processing 17,
    1323-1330, 2008). Sampled by linear interpolation, the frame's edge pixels extended.
``psf``
    Diffraction of a circular aperture at the f-number and wavelength, MTF
    (2/pi)(acos x - x sqrt(1 - x^2)), x = nu / nu_c, nu_c = 1 / (lambda N) (Goodman, *Introduction to
    Fourier Optics*, 3rd ed., 2005, Eq. 6-31), and Gaussian line-of-sight jitter of ``jitter_px``
    rms, MTF exp(-2 pi^2 sigma^2 nu^2) (Holst 2008, ch. 10); applied by FFT on the pixel grid
    (periodic boundaries).
``defocus``
    A uniform blur disk of ``defocus_px`` diameter (geometric defocus), MTF 2 J1(pi b nu) / (pi b nu).
``motion``
    Linear motion of ``motion_px`` during the exposure along ``motion_angle_deg`` (from +x toward +y,
    the image's rows downward), MTF sinc(L nu . u); with ``motion_px`` 0 and a ``velocity_px_s``, the
    motion during the exposure: |v| t_exp along v.
``shot_noise``
    Poisson photoelectrons (EO). With ``normal_shot_noise_above_e`` set, a pixel whose mean is above
    it draws the normal approximation N(lambda, lambda), rounded, instead (about twice as fast; mean and
    variance exact, the Poisson skewness 1 / sqrt(lambda) left out: under 0.032 above 1000 e, so only
    where such a tail does not matter, as for training frames; off by default).
``dark_current``
    Poisson dark electrons, ``dark_current_e_s`` x ``exposure_s`` (EO).
``prnu``, ``dsnu``
    Fixed pattern: a per-pixel gain of 1 + ``prnu`` N(0, 1) and an offset of ``dsnu_e`` N(0, 1)
    electrons, drawn from the camera's own seed, the same for every frame of that camera.
``read_noise``
    Gaussian read noise of ``read_noise_e`` rms (EO); for thermal frames ``netd``: Gaussian temporal
    noise of ``netd_k`` rms on the temperature.
``agc``
    Automatic gain: the signal is scaled so that its ``agc_percentile`` reaches ``agc_level`` of the DN
    range (EO: in electrons of the conversion gain; thermal: the span is set to the frame's 1st to
    ``agc_percentile``-th percentile).
``quantise``
    EO: the conversion gain ``full_well_e / (2^bits - 1)`` electrons per DN, clipped at full well
    (saturation) and rounded to ``bits`` bits; thermal: the span ``t_min_k`` to ``t_max_k`` over the
    DN range.
``jpeg``
    Lossy compression of the 8-bit image through Pillow's JPEG codec at ``jpeg_quality`` (``bits`` = 8).

The chain's analytic MTF (:func:`chain_mtf`) is the product of the optics and jitter MTFs and the
pixel footprint's sinc; tests measure it on a slanted edge (ISO 12233) and the noise stages by a
photon-transfer curve (EMVA 1288).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

import numpy as np
from scipy import special

from csuas.base.errors import InputErrors, ParameterError

#: Stage names in the order they run.
STAGES = (
    "frame_exposure",
    "rolling_shutter",
    "psf",
    "defocus",
    "motion",
    "shot_noise",
    "dark_current",
    "prnu",
    "dsnu",
    "read_noise",
    "netd",
    "agc",
    "quantise",
    "jpeg",
)


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
    normal_shot_noise_above_e : float
        Mean [e] above which ``shot_noise`` draws its normal approximation (inf: exact Poisson everywhere).
    netd_k, t_min_k, t_max_k : float
        Thermal: temporal noise [K rms] and the temperature span of the DN range [K].
    bits : int
        Quantisation depth, 8, 10, 12, 14 or 16.
    frame_rate_hz, line_time_s, velocity_px_s : float, float, (float, float)
        Video: frames per second [Hz], the rolling shutter's time between rows [s] and the scene's
        image velocity (x right, y down) [px/s].
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
    defocus_px: float = 0.0
    motion_px: float = 0.0
    motion_angle_deg: float = 0.0
    normal_shot_noise_above_e: float = math.inf
    frame_rate_hz: float = 30.0
    line_time_s: float = 0.0
    velocity_px_s: tuple = (0.0, 0.0)
    agc_percentile: float = 99.0
    agc_level: float = 0.8
    jpeg_quality: int = 85

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
        for name in (
            "jitter_px",
            "read_noise_e",
            "dark_current_e_s",
            "prnu",
            "dsnu_e",
            "netd_k",
            "defocus_px",
            "motion_px",
            "line_time_s",
        ):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0):
                errors.append(ParameterError(name, value, "0 <= x < inf"))
        if not self.normal_shot_noise_above_e >= 100.0:
            errors.append(ParameterError("normal_shot_noise_above_e", self.normal_shot_noise_above_e, ">= 100 e"))
        if not (np.isfinite(self.frame_rate_hz) and self.frame_rate_hz > 0):
            errors.append(ParameterError("frame_rate_hz", self.frame_rate_hz, "0 < x < inf"))
        if len(self.velocity_px_s) != 2 or not np.isfinite(np.asarray(self.velocity_px_s, float)).all():
            errors.append(ParameterError("velocity_px_s", self.velocity_px_s, "two finite numbers [px/s]"))
        if self.bits not in (8, 10, 12, 14, 16):
            errors.append(ParameterError("bits", self.bits, "8, 10, 12, 14 or 16"))
        if not (0.0 < self.agc_percentile <= 100.0):
            errors.append(ParameterError("agc_percentile", self.agc_percentile, "0 < x <= 100"))
        if not (0.0 < self.agc_level <= 1.0):
            errors.append(ParameterError("agc_level", self.agc_level, "0 < x <= 1"))
        if not (isinstance(self.jpeg_quality, int) and 1 <= self.jpeg_quality <= 95):
            errors.append(ParameterError("jpeg_quality", self.jpeg_quality, "an integer 1 to 95"))
        if "jpeg" in self.stages and (self.bits != 8 or "quantise" not in self.stages):
            errors.append(ParameterError("stages", "jpeg", "jpeg after quantise with bits = 8"))
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


def blur_transfer(fx, fy, settings: ChainSettings, stages) -> np.ndarray:
    """Transfer function of the blur stages among ``stages`` at frequencies (fx, fy) [cycles per pixel]."""
    radial = np.hypot(fx, fy)
    transfer = optics_mtf(radial, settings) if "psf" in stages else np.ones_like(radial)
    if "defocus" in stages and settings.defocus_px > 0:
        x = np.pi * settings.defocus_px * radial
        safe = np.where(x > 1e-8, x, 1.0)
        transfer = transfer * np.where(x > 1e-8, 2.0 * special.j1(safe) / safe, 1.0)
    if "motion" in stages and settings.motion_px > 0:
        angle = np.radians(settings.motion_angle_deg)
        transfer = transfer * np.sinc(settings.motion_px * (fx * np.cos(angle) + fy * np.sin(angle)))
    return transfer


#: The settings the optics' transfer depends on (the key of its cache).
OPTICS_FIELDS = ("f_number", "wavelength_um", "pixel_pitch_um", "jitter_px", "defocus_px")


@functools.lru_cache(maxsize=4)
def _optics_transfer(shape: tuple, optics: tuple, stages: frozenset) -> np.ndarray:
    """:func:`blur_transfer` of ``psf`` and ``defocus`` on a frame's real-FFT grid (float32), once per optics."""
    fy = np.fft.fftfreq(shape[0])[:, None]
    fx = np.fft.rfftfreq(shape[1])[None, :]
    settings = ChainSettings(**dict(zip(OPTICS_FIELDS, optics)))
    transfer = blur_transfer(fx, fy, settings, stages & {"psf", "defocus"}).astype(np.float32)
    transfer.flags.writeable = False
    return transfer


def _blur(image: np.ndarray, settings: ChainSettings, stages) -> np.ndarray:
    """The frame through the blur stages, by a float32 real FFT (scipy.fft; 7 significant digits, a
    relative error near 1e-7 of the signal: 0.001 e at 10^4 e, far below its shot noise of 100 e)."""
    from scipy import fft

    optics = tuple(getattr(settings, name) for name in OPTICS_FIELDS)
    transfer = _optics_transfer(image.shape, optics, frozenset(stages))
    if "motion" in stages and settings.motion_px > 0:
        fy = np.fft.fftfreq(image.shape[0]).astype(np.float32)[:, None]
        fx = np.fft.rfftfreq(image.shape[1]).astype(np.float32)[None, :]
        angle = np.radians(settings.motion_angle_deg)
        along = np.float32(np.cos(angle)) * fx + np.float32(np.sin(angle)) * fy
        transfer = transfer * np.sinc(np.float32(settings.motion_px) * along)
    spectrum = fft.rfft2(image.astype(np.float32)) * transfer
    return fft.irfft2(spectrum, s=image.shape).astype(float)


@functools.lru_cache(maxsize=2)
def fixed_pattern(shape: tuple, camera_seed: int) -> tuple[np.ndarray, np.ndarray]:
    """The camera's per-pixel gain and offset patterns, standard normal, from the camera's own stream.

    Drawn once per camera (shape and seed) and kept, read-only: every frame of the camera shares them.
    """
    rng = np.random.default_rng([int(camera_seed), 1])
    gain, offset = rng.standard_normal(shape), rng.standard_normal(shape)
    gain.flags.writeable = offset.flags.writeable = False
    return gain, offset


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
        ``quantise``, ``dn`` (uint16) and ``saturated`` (the fraction of pixels clipped); with
        ``frame_exposure``, ``exposure_s`` (the exposure the frame rate allows [s]).
    """
    settings.validate()
    image = np.asarray(signal, dtype=float)
    if image.ndim != 2 or not np.isfinite(image).all() or (not thermal and image.min() < 0):
        raise ParameterError("signal", f"array of shape {image.shape}", "a finite 2-D frame, >= 0 for EO")
    rng = np.random.default_rng([int(seed), 0])
    stages = set(settings.stages)
    out: dict = {}
    if "frame_exposure" in stages:
        exposure = min(settings.exposure_s, 1.0 / settings.frame_rate_hz)
        if not thermal:
            image = image * (exposure / settings.exposure_s)
        settings = replace(settings, exposure_s=exposure)
        out["exposure_s"] = exposure
    if "rolling_shutter" in stages:
        image = rolling_shutter(image, settings.line_time_s, settings.velocity_px_s)
    settings = _motion_from_velocity(settings)
    if stages & {"psf", "defocus", "motion"}:
        image = _blur(image, settings, stages)
        if not thermal:
            image = np.maximum(image, 0.0)  # ringing of the band-limited blur below zero
    if thermal:
        if "netd" in stages:
            image = image + settings.netd_k * rng.standard_normal(image.shape)
    else:
        dark_e = settings.dark_current_e_s * settings.exposure_s if "dark_current" in stages else 0.0
        if "shot_noise" in stages:  # the photon and dark counts together: Poisson(a) + Poisson(b) = Poisson(a + b)
            image = _shot_noise(image + dark_e, settings.normal_shot_noise_above_e, rng)
        elif dark_e > 0:
            image = image + rng.poisson(dark_e, image.shape)
        if stages & {"prnu", "dsnu"}:
            gain_pattern, offset_pattern = fixed_pattern(image.shape, int(camera_seed))
            if "prnu" in stages:
                image = image * (1.0 + settings.prnu * gain_pattern)
            if "dsnu" in stages:
                image = image + settings.dsnu_e * offset_pattern
        if "read_noise" in stages:
            image = image + settings.read_noise_e * rng.standard_normal(image.shape)
    out["signal"] = image.astype(np.float32)
    top = 2**settings.bits - 1
    t_min, t_max, gain = settings.t_min_k, settings.t_max_k, settings.gain_e_per_dn
    if "agc" in stages:
        high = float(np.percentile(image, settings.agc_percentile))
        if thermal:
            t_min = float(np.percentile(image, 1.0))
            t_max = t_min + max(high - t_min, 1e-9) / settings.agc_level
        else:
            gain = max(high, 1e-9) / (settings.agc_level * top)
        out["agc_gain"] = gain if not thermal else (t_max - t_min) / top
    if "quantise" in stages:
        scaled = (image - t_min) / (t_max - t_min) * top if thermal else image / gain
        out["saturated"] = float(np.mean(scaled > top))
        out["dn"] = np.clip(np.rint(scaled), 0, top).astype(np.uint16)
    if "jpeg" in stages:
        out["dn"] = _jpeg(out["dn"].astype(np.uint8), settings.jpeg_quality)
    return out


def rolling_shutter(image: np.ndarray, line_time_s: float, velocity_px_s, first_row: int = 0, rows: int | None = None):
    """The frame as a rolling shutter reads it (module docstring): row r shows the scene at tau = (r - r_mid) t_line.

    Parameters
    ----------
    image : ndarray (H, W)
        The scene at the frame's reference time (the middle row's read).
    line_time_s : float
        Time between the reads of successive rows [s].
    velocity_px_s : (float, float)
        The scene's image velocity, x right and y down [px/s].
    first_row, rows : int
        Frame row of ``image``'s first row, and the frame's height (default: ``image`` is the whole frame).
    """
    from scipy import ndimage

    vx, vy = (float(v) for v in velocity_px_s)
    if line_time_s == 0 or (vx == 0 and vy == 0):
        return np.array(image, dtype=float)  # nothing moves between the rows' reads
    height, width = image.shape
    frame_rows = height if rows is None else int(rows)
    row = np.arange(height, dtype=float)[:, None]
    tau = (first_row + row - (frame_rows - 1) / 2.0) * float(line_time_s)
    y = np.broadcast_to(row - vy * tau, (height, width))
    x = np.arange(width, dtype=float)[None, :] - vx * tau
    return ndimage.map_coordinates(image, [y, x], order=1, mode="nearest")


def _shot_noise(mean: np.ndarray, normal_above_e: float, rng: np.random.Generator) -> np.ndarray:
    """Poisson counts of ``mean`` [e]; above ``normal_above_e`` the rounded normal approximation (module docstring)."""
    if not np.isfinite(normal_above_e):
        return rng.poisson(mean).astype(float)
    counts = np.rint(mean + np.sqrt(mean) * rng.standard_normal(mean.shape, dtype=np.float32))
    small = mean <= normal_above_e
    if small.any():
        counts[small] = rng.poisson(mean[small])
    return np.maximum(counts, 0.0)


def _motion_from_velocity(settings: ChainSettings) -> ChainSettings:
    """Settings whose ``motion`` is the image velocity's path over the exposure, when no ``motion_px`` is set."""
    vx, vy = (float(v) for v in settings.velocity_px_s)
    if settings.motion_px > 0 or (vx == 0 and vy == 0) or "motion" not in settings.stages:
        return settings
    length = math.hypot(vx, vy) * settings.exposure_s
    return replace(settings, motion_px=length, motion_angle_deg=math.degrees(math.atan2(vy, vx)))


def _jpeg(image: np.ndarray, quality: int) -> np.ndarray:
    """An 8-bit image after a round trip through Pillow's JPEG codec (baseline, 4:4:4 grey)."""
    import io

    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(image).save(buffer, format="JPEG", quality=int(quality))
    buffer.seek(0)
    return np.asarray(Image.open(buffer)).astype(np.uint16)
