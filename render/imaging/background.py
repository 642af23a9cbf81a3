"""Backgrounds of a full EO frame: the CIE clear sky with its gradient from the sun, clouds, and the ground.

Sky luminance follows the CIE standard general sky, type 12 "CIE standard clear sky, low
luminance turbidity" (ISO 15469:2004 / CIE S 011/E:2003):

    L(Z, chi) / L_z = f(chi) phi(Z) / (f(Z_s) phi(0)),
    phi(Z) = 1 + a exp(b / cos Z),   f(chi) = 1 + c (exp(d chi) - exp(d pi / 2)) + e cos^2 chi,
    a = -1, b = -0.32, c = 10, d = -3, e = 0.45,

with Z the zenith angle of the viewing direction, chi its angle from the sun and Z_s the sun's zenith
angle. The zenith luminance L_z is set so that the sky gives the horizontal diffuse illuminance of the
render's daylight (``integral L cos Z dOmega`` over the sky hemisphere). Below the horizon the frame
sees Lambertian ground of luminance rho_g E_v / pi. Directions are in the drone's body frame (z up,
docs/command-line.md); the camera looks from the sensor toward the target, its image axes those of
:func:`csuas.drone_models.geometry.view_basis`.
"""

from __future__ import annotations

import math

import numpy as np

from csuas.base.errors import ParameterError
from csuas.drone_models.geometry import direction_vector, view_basis
from csuas.render.imaging.camera import SensorGeometry
from csuas.render.imaging.records import Daylight, View

#: CIE standard general sky type 12 (clear sky, low turbidity): gradation a, b and indicatrix c, d, e.
CIE_CLEAR_SKY = {"a": -1.0, "b": -0.32, "c": 10.0, "d": -3.0, "e": 0.45}


def _gradation(zenith_rad, p=CIE_CLEAR_SKY):
    cos_z = np.maximum(np.cos(zenith_rad), 1e-6)
    return 1.0 + p["a"] * np.exp(p["b"] / cos_z)


def _indicatrix(chi_rad, p=CIE_CLEAR_SKY):
    return 1.0 + p["c"] * (np.exp(p["d"] * chi_rad) - math.exp(p["d"] * math.pi / 2)) + p["e"] * np.cos(chi_rad) ** 2


def relative_sky_luminance(zenith_rad, sun_angle_rad, sun_zenith_rad):
    """L / L_z of the CIE clear sky (module docstring) [-]: 1 at the zenith."""
    return (
        _indicatrix(np.asarray(sun_angle_rad, float))
        * _gradation(np.asarray(zenith_rad, float))
        / (_indicatrix(sun_zenith_rad) * _gradation(0.0))
    )


def zenith_luminance(diffuse_illuminance_lx: float, sun_zenith_rad: float, samples: int = 400) -> float:
    """L_z [cd/m^2] whose clear sky gives ``diffuse_illuminance_lx`` on a horizontal plane (midpoint rule)."""
    z = (np.arange(samples) + 0.5) * (math.pi / 2) / samples
    phi = (np.arange(2 * samples) + 0.5) * (2 * math.pi) / (2 * samples)
    zz, pp = np.meshgrid(z, phi, indexing="ij")
    # angle to the sun (at azimuth 0): cos chi = cos Z cos Zs + sin Z sin Zs cos phi
    cos_chi = np.cos(zz) * math.cos(sun_zenith_rad) + np.sin(zz) * math.sin(sun_zenith_rad) * np.cos(pp)
    rel = relative_sky_luminance(zz, np.arccos(np.clip(cos_chi, -1.0, 1.0)), sun_zenith_rad)
    d_omega = np.sin(zz) * (math.pi / 2 / samples) * (2 * math.pi / (2 * samples))
    return float(diffuse_illuminance_lx / np.sum(rel * np.cos(zz) * d_omega))


def view_rays(n_h: int, n_v: int, ifov_rad: float, azimuth_deg: float, elevation_deg: float, target_offset_px):
    """Unit viewing direction (n_v, n_h, 3) of every pixel of a frame looking at the target, body frame.

    The target lies at pixel (n_h // 2 + 0.5, n_v // 2 + 0.5) + ``target_offset_px``; ``azimuth_deg`` and
    ``elevation_deg`` give the direction from the target toward the sensor. A pixel sees the sky where
    its direction points up (z > 0) and the ground below the horizon.
    """
    d = direction_vector(azimuth_deg, elevation_deg)
    h, v = view_basis(d, azimuth_deg)
    cx = n_h // 2 + 0.5 + float(target_offset_px[0])
    cy = n_v // 2 + 0.5 + float(target_offset_px[1])
    x = (np.arange(n_h) + 0.5 - cx) * ifov_rad
    y = (np.arange(n_v) + 0.5 - cy) * ifov_rad
    rays = -d[None, None, :] + x[None, :, None] * h[None, None, :] - y[:, None, None] * v[None, None, :]
    # d, h and v are orthonormal: |rays|^2 = 1 + x^2 + y^2, without a norm over the frame's 3-vectors
    return rays / np.sqrt(1.0 + x[None, :, None] ** 2 + y[:, None, None] ** 2)


def clear_sky_frame(
    geometry: SensorGeometry, view: View, light: Daylight, *, cloud_cover: float = 0.0, seed: int = 0
) -> np.ndarray:
    """Background luminance [cd/m^2] of every pixel of a frame looking at the target (module docstring).

    Parameters
    ----------
    geometry : SensorGeometry
        The frame's pixel grid (IFOV [rad], N_H, N_V).
    view : View
        The target lies at pixel (n_h // 2 + 0.5, n_v // 2 + 0.5) + ``view.target_offset_px``;
        ``view.azimuth_deg``/``view.elevation_deg`` give the direction from the target toward the sensor.
    light : Daylight
        Illuminance E_v [lx] and its diffuse share (the sky's horizontal illuminance), the sun (its
        azimuth None: behind the sensor, at the view's azimuth) and the ground's reflectance.
    cloud_cover : float
        With ``cloud_cover`` > 0 the sky carries seeded clouds (:func:`cloud_opacity`) as bright as a white
        Lambertian sheet under the scene illuminance, E_v / pi.
    seed : int
        Seed of the clouds.
    """
    n_h, n_v = geometry.n_h, geometry.n_v
    illuminance_lx = light.illuminance_lx
    diffuse_illuminance_lx = light.diffuse_fraction * illuminance_lx
    sun_azimuth_deg = view.azimuth_deg if light.sun_azimuth_deg is None else light.sun_azimuth_deg
    sun_elevation_deg = light.sun_elevation_deg
    rays = view_rays(n_h, n_v, geometry.ifov_rad, view.azimuth_deg, view.elevation_deg, view.target_offset_px)
    sun = direction_vector(sun_azimuth_deg, sun_elevation_deg)
    sun_zenith = math.radians(90.0 - sun_elevation_deg)
    zenith = np.arccos(np.clip(rays[..., 2], -1.0, 1.0))
    chi = np.arccos(np.clip(rays @ sun, -1.0, 1.0))
    sky = zenith_luminance(diffuse_illuminance_lx, sun_zenith) * relative_sky_luminance(zenith, chi, sun_zenith)
    ground = light.ground_reflectance * illuminance_lx / math.pi
    is_sky = rays[..., 2] > 0.0
    frame = np.where(is_sky, sky, ground)
    if cloud_cover > 0.0:
        frame = with_clouds(frame, is_sky, cloud_opacity(n_v, n_h, cloud_cover, seed), illuminance_lx / math.pi)
    return frame


#: Power-spectrum exponent of the cloud field: P(f) ~ f^-beta (beta = 3, the 2-D fractional Brownian surface
#: of Hurst exponent 0.5 often used for cloud fields; Cahalan et al., J. Atmos. Sci. 51(16), 1994).
CLOUD_SPECTRUM_EXPONENT = 3.0


def cloud_field(n_v: int, n_h: int, seed: int, scale_px: float = 400.0) -> np.ndarray:
    """A seeded Gaussian field (n_v, n_h) of power f^-beta above 1 / ``scale_px`` (flat below), by FFT synthesis."""
    rng = np.random.default_rng([int(seed), 2])
    fy = np.fft.fftfreq(n_v)[:, None]
    fx = np.fft.rfftfreq(n_h)[None, :]
    f = np.maximum(np.hypot(fx, fy), 1.0 / scale_px)
    noise = rng.standard_normal((n_v, n_h // 2 + 1)) + 1j * rng.standard_normal((n_v, n_h // 2 + 1))
    return np.fft.irfft2(noise * f ** (-CLOUD_SPECTRUM_EXPONENT / 2.0), s=(n_v, n_h))


def cloud_opacity(n_v: int, n_h: int, cover: float, seed: int, scale_px: float = 400.0) -> np.ndarray:
    """A seeded cloud opacity field (n_v, n_h) in [0, 1] covering about ``cover`` of the frame.

    :func:`cloud_field` (largest features ``scale_px``), thresholded at its ``1 - cover`` quantile with
    a soft edge of a tenth of the field's spread.
    """
    if not 0.0 <= cover <= 1.0:
        raise ParameterError("cloud_cover", cover, "0 <= x <= 1")
    field = cloud_field(n_v, n_h, seed, scale_px)
    if cover <= 0.0:
        return np.zeros_like(field)
    if cover >= 1.0:
        return np.ones_like(field)
    edge = np.quantile(field, 1.0 - cover)
    width = 0.1 * float(np.std(field))
    return np.clip((field - edge) / width + 0.5, 0.0, 1.0)


def with_clouds(sky_frame: np.ndarray, is_sky: np.ndarray, opacity: np.ndarray, cloud_luminance: float) -> np.ndarray:
    """The sky's pixels seen through clouds of ``cloud_luminance`` [cd/m^2] and ``opacity``; the ground unchanged."""
    alpha = np.where(is_sky, opacity, 0.0)
    return (1.0 - alpha) * sky_frame + alpha * cloud_luminance
