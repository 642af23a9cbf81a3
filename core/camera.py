"""The EO camera as a radiometric instrument: illuminance to photoelectrons, noise, and a light-limited range.

Chain (physical convention, an extension of the paper's EO model, Section 4.3):

1. *Scene.* Illuminance E_v [lx] lights a Lambertian background of reflectance rho_b, of luminance
   L_b = rho_b E_v / pi [cd/m^2]; the target's luminance follows from the paper's Michelson contrast
   C0 = (L_t - L_b) / (L_t + L_b) (Eq. 3): L_t - L_b = 2 C0 / (1 - C0) L_b, and the path attenuates that
   difference by the transmittance, as the airlight adds to target and background alike (Eq. 21).
2. *Optics.* A distant extended source of luminance L gives the focal-plane illuminance
   E_fp = pi L tau_o / (4 N^2) [lx] (the camera equation, on axis; Holst, *Electro-Optical Imaging
   System Performance*, 5th ed., 2008, Eq. 12-5), N the f-number and tau_o the optics' transmittance.
3. *Detector.* A pixel of pitch p collects E_fp p^2 t K QE electrons in the exposure t, with K the
   photons per lumen of the illuminant in the detector's band (:func:`photons_per_lumen`) and QE the
   band-averaged quantum efficiency. Auto-exposure holds the background at half the full well, up to
   the frame's longest exposure (:func:`auto_exposure_s`). Noise per pixel: shot noise of the
   background, dark current and read noise, sqrt(S_b + D t + sigma_r^2) (EMVA 1288, 2021, Eq. 6).
4. *Detection.* The target's electrons above the background, summed over the n pixels it covers,
   against that noise: the blob SNR of :func:`csuas.core.detection.blob_snr`; a Gaussian threshold at
   Pfa detects it with Pd = Q(Q^-1(Pfa) - SNR). The light-limited range is where Pd reaches
   ``p_desired``, so twilight and night shorten the EO range where the paper's Johnson and contrast
   limits do not change.

References: CIE 1924 photopic luminosity V(lambda) by its Gaussian fit
V = 1.019 exp(-285.4 (lambda/um - 0.559)^2) (max |error| about 0.03 of its peak); Planck's law;
K_m = 683 lm/W (CIE, SI definition of the candela).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csuas.core.checks import require
from csuas.core.detection import blob_snr, target_pixels
from csuas.core.radiometry import spectral_radiance
from csuas.core.solve import bracketed_root
from csuas.core.units import C_LIGHT, H_PLANCK

#: Luminous efficacy of 555 nm (540 THz) radiation [lm/W] (SI definition of the candela).
K_M = 683.0
#: Correlated colour temperature of daylight used for the photon conversion [K] (sunlight at sea level).
DAYLIGHT_K = 5900.0


def photopic_efficiency(wavelength_um):
    """CIE 1924 photopic luminosity V(lambda) by its Gaussian fit (module docstring) [-]."""
    lam = require("wavelength_um", wavelength_um, gt=0)
    return 1.019 * np.exp(-285.4 * (lam - 0.559) ** 2)


def photons_per_lumen(colour_temperature_k=DAYLIGHT_K, band_nm=(400.0, 700.0), samples: int = 2001):
    """Photons per second in ``band_nm`` per lumen of a blackbody illuminant [photons / (lm s)].

    The ratio of the blackbody's photon flux in the band to its luminous flux 683 int V B dlambda
    (360-830 nm), each by the trapezoidal rule on ``samples`` wavelengths (V is the module's fit).
    Daylight (5900 K) in 400-700 nm: 1.095e16 photons per lumen.

    Parameters
    ----------
    colour_temperature_k : float
        Blackbody temperature of the illuminant [K].
    band_nm : tuple of float
        The detector's band [nm].
    """
    t = float(require("colour_temperature_k", colour_temperature_k, gt=0))

    def planck(lam):  # per um: the factor cancels in the ratio
        return spectral_radiance(lam * 1e6, t)

    visible = np.linspace(360e-9, 830e-9, int(samples))
    band = np.linspace(band_nm[0] * 1e-9, band_nm[1] * 1e-9, int(samples))
    luminous = K_M * np.trapezoid(planck(visible) * photopic_efficiency(visible * 1e6), visible)
    return float(np.trapezoid(planck(band) * band / (H_PLANCK * C_LIGHT), band) / luminous)


def luminance_excess(c_eo):
    """(L_t - L_b) / L_b of the paper's Michelson contrast C = (L_t - L_b) / (L_t + L_b) (Eq. 3): 2C / (1 - C).

    Parameters
    ----------
    c_eo : array_like
        Inherent contrast, -1 <= C <= 1; C = 1 (a black background) gives an infinite excess.
    """
    c = require("c_eo", c_eo, ge=-1, le=1)
    with np.errstate(divide="ignore"):
        return np.where(c < 1.0, 2.0 * c / np.where(c < 1.0, 1.0 - c, 1.0), np.inf)


def focal_plane_illuminance_lx(luminance_cd_m2, f_number, transmittance):
    """Camera equation: E_fp = pi L tau / (4 N^2) [lx] for a distant extended source on axis."""
    lum = require("luminance_cd_m2", luminance_cd_m2, ge=0)
    n = require("f_number", f_number, gt=0)
    tau = require("optics_transmittance", transmittance, ge=0, le=1)
    return np.pi * lum * tau / (4.0 * n**2)


def electron_rate(illuminance_lx, pixel_pitch_um, quantum_efficiency, photons_lm_s):
    """Photoelectrons per second of one pixel under a focal-plane illuminance [e/s]."""
    e = require("illuminance_lx", illuminance_lx, ge=0)
    pitch = require("pixel_pitch_um", pixel_pitch_um, gt=0) * 1e-6
    qe = require("quantum_efficiency", quantum_efficiency, gt=0, le=1)
    return e * pitch**2 * qe * photons_lm_s


def auto_exposure_s(background_rate_e_s, full_well_e, max_exposure_s, fill: float = 0.5):
    """Exposure that holds the background at ``fill`` of the full well, at most ``max_exposure_s`` [s]."""
    rate = require("background_rate_e_s", background_rate_e_s, ge=0)
    well = require("full_well_e", full_well_e, gt=0)
    t_max = require("max_exposure_s", max_exposure_s, gt=0)
    with np.errstate(divide="ignore"):
        return np.minimum(t_max, np.where(rate > 0, fill * well / np.where(rate > 0, rate, 1.0), np.inf))


def pixel_noise_e(signal_e, dark_e, read_noise_e):
    """Temporal noise of a pixel [e]: sqrt(shot + dark + read^2) (EMVA 1288 Eq. 6, gain-free)."""
    s = require("signal_e", signal_e, ge=0)
    d = require("dark_e", dark_e, ge=0)
    r = require("read_noise_e", read_noise_e, ge=0)
    return np.sqrt(s + d + r * r)


@dataclass(frozen=True)
class CameraChain:
    """A visible camera's optics, detector and detection threshold (``eo`` parameters of Table 23's systems).

    Attributes
    ----------
    f_number, optics_transmittance : float
        Optics: f-number [-] and transmittance [-].
    pixel_pitch_um, quantum_efficiency : float
        Detector: pixel pitch [um] and quantum efficiency [-].
    max_exposure_ms, full_well_e, read_noise_e, dark_current_e_s : float
        Exposure limit [ms], full well [e], read noise [e rms], dark current [e/s].
    required_snr : float
        Blob SNR the detection needs (Q^-1(Pfa) - Q^-1(p_desired)).
    """

    f_number: float
    optics_transmittance: float
    pixel_pitch_um: float
    quantum_efficiency: float
    max_exposure_ms: float
    full_well_e: float
    read_noise_e: float
    dark_current_e_s: float
    required_snr: float


def light_limited_range_m(
    camera: CameraChain,
    *,
    illuminance_lx,
    background_reflectance,
    c_eo,
    transmittance_at,
    projected_area_m2,
    ifov_rad_,
    range_bound_m=1e8,
):
    """Range [m] where the EO blob SNR falls to the camera's required SNR, and the chain's values (module docstring).

    Parameters
    ----------
    camera : CameraChain
        Optics, detector and the blob SNR the detection needs.
    illuminance_lx, background_reflectance, c_eo : float
        Scene illuminance [lx] (Tables 10-11), background reflectance [-] and inherent contrast [-].
    transmittance_at : callable
        tau(R) of the path for ranges R [m] (the paper's contrast attenuation, Eq. 21).
    projected_area_m2, ifov_rad_ : float
        Target area [m^2] and pixel IFOV [rad].
    range_bound_m : float
        Upper end of the search [m]; the range is infinite when the SNR still exceeds the requirement there.

    Returns
    -------
    tuple
        ``(range_m, chain)``: the range and a dict of the background electrons, exposure [s], noise
        [e] and the target's electron excess at zero range [e per pixel].
    """
    f_number, optics_transmittance = camera.f_number, camera.optics_transmittance
    pixel_pitch_um, quantum_efficiency = camera.pixel_pitch_um, camera.quantum_efficiency
    full_well_e, read_noise_e, dark_current_e_s = camera.full_well_e, camera.read_noise_e, camera.dark_current_e_s
    max_exposure_ms, required_snr = camera.max_exposure_ms, camera.required_snr
    lum_b = (
        require("illuminance_lx", illuminance_lx, ge=0)
        * require("background_reflectance", background_reflectance, ge=0, le=1)
        / np.pi
    )
    k = photons_per_lumen()
    rate_b = electron_rate(
        focal_plane_illuminance_lx(lum_b, f_number, optics_transmittance), pixel_pitch_um, quantum_efficiency, k
    )
    t_exp = auto_exposure_s(rate_b, full_well_e, max_exposure_ms / 1000.0)
    s_b = rate_b * t_exp
    noise = pixel_noise_e(s_b, dark_current_e_s * t_exp, read_noise_e)
    excess0 = np.abs(luminance_excess(c_eo)) * s_b  # target minus background, per pixel, R = 0
    chain = {
        "background_e": float(s_b),
        "exposure_s": float(t_exp),
        "noise_e": float(noise),
        "target_excess_e": float(excess0),
    }

    def snr(r):
        return blob_snr(excess0 * transmittance_at(r), noise, target_pixels(projected_area_m2, ifov_rad_, r))

    bound = float(range_bound_m)
    if excess0 <= 0 or not np.isfinite(required_snr):  # no contrast, or certainty (p_desired = 1)
        return 0.0, chain
    if float(snr(np.array([bound]))[0]) >= required_snr:
        return np.inf, chain
    root, found = bracketed_root(lambda r: snr(r) - required_snr, np.array([1e-6]), np.array([bound]), rtol=1e-12)
    return (float(root[0]) if bool(found[0]) else 0.0), chain
