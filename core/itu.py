"""ITU-R rain (P.838-3) and cloud/fog (P.840) specific attenuation (Eqs. 58, 60; Tables 35-36, 42-43).

The coefficients are read from ``defaults/itu.toml``. Rain uses the
polarisation combination of P.838-3 Eqs. 4-5 with the path elevation and
polarisation tilt tau (vertical: tau = 90 deg, the paper's choice; horizontal
path: elevation 0).
"""

from __future__ import annotations

import functools

import numpy as np

from csuas.core.checks import require


@functools.lru_cache(maxsize=1)
def _coefficients():
    from csuas.defaults import _load

    return _load("itu.toml")


def _gaussian_sum(log_f, coef):
    a, b, c = (np.asarray(coef[key], dtype=float) for key in ("a", "b", "c"))
    x = log_f[..., None]
    return np.sum(a * np.exp(-(((x - b) / c) ** 2)), axis=-1) + coef["m"] * log_f + coef["c0"]


def rain_coefficients(frequency_ghz, elevation_deg=0.0, tau_deg=90.0):
    """Coefficients k and alpha of gamma = k R^alpha (ITU-R P.838-3).

    Parameters
    ----------
    frequency_ghz : array_like
        Frequency [GHz], 1-1000.
    elevation_deg : array_like
        Path elevation [deg] (0: horizontal path).
    tau_deg : array_like
        Polarisation tilt relative to horizontal [deg] (90: vertical, 45: circular).

    Returns
    -------
    k, alpha : ndarray
    """
    co = _coefficients()["p838_3"]
    lo, hi = co["frequency_range_ghz"]
    f = require(
        "frequency_ghz",
        frequency_ghz,
        ge=lo,
        le=hi,
        why=f"ITU-R P.838-3 (rain attenuation) is defined for {lo:g}-{hi:g} GHz",
    )
    el = np.deg2rad(require("elevation_deg", elevation_deg, ge=-90, le=90))
    tau = np.deg2rad(require("tau_deg", tau_deg, ge=-180, le=180))
    log_f = np.log10(f)
    kh, kv = 10.0 ** _gaussian_sum(log_f, co["kh"]), 10.0 ** _gaussian_sum(log_f, co["kv"])
    ah, av = _gaussian_sum(log_f, co["alphah"]), _gaussian_sum(log_f, co["alphav"])
    mix = np.cos(el) ** 2 * np.cos(2.0 * tau)
    k = (kh + kv + (kh - kv) * mix) / 2.0
    alpha = (kh * ah + kv * av + (kh * ah - kv * av) * mix) / (2.0 * k)
    return k, alpha


def rain_specific_attenuation_db_km(frequency_ghz, rain_rate_mm_h, elevation_deg=0.0, tau_deg=90.0):
    """Specific rain attenuation gamma_R = k R^alpha [dB/km] (Eq. 58, P.838-3)."""
    r = require("rain_rate_mm_h", rain_rate_mm_h, ge=0)
    k, alpha = rain_coefficients(frequency_ghz, elevation_deg, tau_deg)
    return k * r**alpha


def water_permittivity(frequency_ghz, temperature_k):
    """Complex permittivity eps' - j eps'' of liquid water (double-Debye, ITU-R P.840).

    Returns
    -------
    eps_real, eps_imag : ndarray
    """
    co = _coefficients()["p840"]
    f = require("frequency_ghz", frequency_ghz, gt=0)
    t = require("temperature_k", temperature_k, gt=0)
    theta = 300.0 / t
    eps0 = co["eps0"][0] + co["eps0"][1] * (theta - 1.0)
    eps1 = co["eps1_ratio"] * eps0
    eps2 = co["eps2"]
    fp = co["fp"][0] + co["fp"][1] * (theta - 1.0) + co["fp"][2] * (theta - 1.0) ** 2
    fs = co["fs_ratio"] * fp
    eps_imag = f * (eps0 - eps1) / (fp * (1 + (f / fp) ** 2)) + f * (eps1 - eps2) / (fs * (1 + (f / fs) ** 2))
    eps_real = (eps0 - eps1) / (1 + (f / fp) ** 2) + (eps1 - eps2) / (1 + (f / fs) ** 2) + eps2
    return eps_real, eps_imag


def fog_coefficient_kl(frequency_ghz, temperature_k=293.15):
    """Cloud/fog specific attenuation coefficient K_l [(dB/km)/(g/m^3)] (ITU-R P.840, Eq. 60)."""
    co = _coefficients()["p840"]
    lo, hi = co["frequency_range_ghz"]
    f = require(
        "frequency_ghz",
        frequency_ghz,
        ge=lo,
        le=hi,
        why=f"ITU-R P.840 (cloud and fog attenuation) is defined for {lo:g}-{hi:g} GHz",
    )
    eps_real, eps_imag = water_permittivity(f, temperature_k)
    eta = (2.0 + eps_real) / eps_imag
    return co["k_factor"] * f / (eps_imag * (1.0 + eta**2))


def fog_specific_attenuation_db_km(frequency_ghz, lwc_g_m3, temperature_k=293.15):
    """Specific fog attenuation gamma_fog = K_l LWC [dB/km] (Eq. 60)."""
    lwc = require("lwc_g_m3", lwc_g_m3, ge=0)
    return fog_coefficient_kl(frequency_ghz, temperature_k) * lwc
