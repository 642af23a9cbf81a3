"""ITU-R rain (P.838-3), cloud/fog (P.840) and gaseous (P.676) specific attenuation (Eqs. 58, 60).

The coefficients are read from ``defaults/itu.toml``. Gases (oxygen and water vapour) follow the
line-by-line method of ITU-R P.676-12 Annex 1 (Tables 1-2), in the reference atmosphere of
ITU-R P.835-6 unless the scenario gives its own; humidity becomes vapour density through
ITU-R P.453-14 Eqs. 8-10. Rain uses the
polarisation combination of P.838-3 Eqs. 4-5 with the path elevation and
polarisation tilt tau (vertical: tau = 90 deg, the paper's choice; horizontal
path: elevation 0).
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require
from csuas.defaults import load_itu


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
    co = load_itu()["p838_3"]
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
    co = load_itu()["p840"]
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
    co = load_itu()["p840"]
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


#: Frequencies of ITU-R P.676 Annex 1 [GHz].
P676_FREQUENCY_RANGE_GHZ = (1.0, 1000.0)


def standard_atmosphere() -> dict:
    """Sea-level mean annual global reference atmosphere (ITU-R P.835-6, Section 1).

    Returns
    -------
    dict
        ``temperature_k`` (288.15), ``pressure_hpa`` (1013.25, total) and
        ``water_vapour_density_g_m3`` (7.5).
    """
    co = load_itu()["p835"]
    return {key: co[key] for key in ("temperature_k", "pressure_hpa", "water_vapour_density_g_m3")}


def saturation_vapour_pressure_hpa(temperature_k, pressure_hpa):
    """Saturation vapour pressure over water [hPa] (ITU-R P.453-14, Eq. 9 with its enhancement factor EF)."""
    co = load_itu()["p453"]
    t_c = require("temperature_k", temperature_k, gt=0) - 273.15
    p = require("pressure_hpa", pressure_hpa, gt=0)
    ef = 1.0 + 1e-4 * (co["ef"][0] + p * (co["ef"][1] + co["ef"][2] * t_c**2))
    return ef * co["a"] * np.exp((co["b"] - t_c / co["d"]) * t_c / (t_c + co["c"]))


def water_vapour_density_g_m3(relative_humidity_pct, temperature_k, pressure_hpa):
    """Water vapour density rho [g/m^3] at a relative humidity (ITU-R P.453-14, Eqs. 8 and 10: rho = 216.7 e / T)."""
    h = require("relative_humidity_pct", relative_humidity_pct, ge=0, le=100)
    e = h / 100.0 * saturation_vapour_pressure_hpa(temperature_k, pressure_hpa)
    return load_itu()["p453"]["vapour_constant"] * e / np.asarray(temperature_k, float)


def water_vapour_pressure_hpa(water_vapour_density_g_m3, temperature_k):
    """Water vapour partial pressure e = rho T / 216.7 [hPa] (ITU-R P.676-12, Annex 1, Eq. 4)."""
    return np.asarray(water_vapour_density_g_m3, float) * temperature_k / load_itu()["p453"]["vapour_constant"]


def _lines(name: str) -> np.ndarray:
    return np.asarray(load_itu()["p676"][name], dtype=float).T


def _line_shape(f, f_line, width, correction):
    """Line shape factor F_i [1/GHz] (P.676-12, Annex 1, Eq. 5)."""
    return (f / f_line) * (
        (width - correction * (f_line - f)) / ((f_line - f) ** 2 + width**2)
        + (width - correction * (f_line + f)) / ((f_line + f) ** 2 + width**2)
    )


def _oxygen_lines_sum(f, p_dry, e, theta):
    """Sum over the oxygen lines of S_i F_i (P.676-12, Annex 1, Eqs. 3, 5, 6a, 7; Table 1)."""
    f0, a1, a2, a3, a4, a5, a6 = _lines("oxygen_lines")
    strength = a1 * 1e-7 * p_dry * theta**3 * np.exp(a2 * (1.0 - theta))
    width = a3 * 1e-4 * (p_dry * theta ** (0.8 - a4) + 1.1 * e * theta)
    width = np.sqrt(width**2 + 2.25e-6)
    correction = (a5 + a6 * theta) * 1e-4 * (p_dry + e) * theta**0.8
    return np.sum(strength * _line_shape(f, f0, width, correction), axis=-1)


def _water_vapour_lines_sum(f, p_dry, e, theta):
    """Sum over the water-vapour lines of S_i F_i (P.676-12, Annex 1, Eqs. 3, 5, 6b; Table 2; delta = 0)."""
    f0, b1, b2, b3, b4, b5, b6 = _lines("water_vapour_lines")
    strength = b1 * 1e-1 * e * theta**3.5 * np.exp(b2 * (1.0 - theta))
    width = b3 * 1e-4 * (p_dry * theta**b4 + b5 * e * theta**b6)
    width = 0.535 * width + np.sqrt(0.217 * width**2 + 2.1316e-12 * f0**2 / theta)
    return np.sum(strength * _line_shape(f, f0, width, 0.0), axis=-1)


def _dry_continuum(f, p_dry, e, theta):
    """Dry-air continuum N''_D(f): Debye spectrum of oxygen and pressure-induced nitrogen (P.676-12, Eqs. 8-9)."""
    d = 5.6e-4 * (p_dry + e) * theta**0.8
    return (
        f
        * p_dry
        * theta**2
        * (6.14e-5 / (d * (1.0 + (f / d) ** 2)) + 1.4e-12 * p_dry * theta**1.5 / (1.0 + 1.9e-5 * f**1.5))
    )


def gaseous_attenuation_components_db_km(frequency_ghz, pressure_hpa, temperature_k, water_vapour_density_g_m3):
    """Oxygen (dry air) and water-vapour specific attenuations [dB/km] (ITU-R P.676-12, Annex 1, Eqs. 1-2).

    Parameters are those of :func:`gaseous_attenuation_db_km`.

    Returns
    -------
    gamma_oxygen, gamma_water_vapour : ndarray
    """
    lo, hi = P676_FREQUENCY_RANGE_GHZ
    f = require(
        "frequency_ghz",
        frequency_ghz,
        ge=lo,
        le=hi,
        why=f"ITU-R P.676 Annex 1 (gaseous attenuation) is defined for {lo:g}-{hi:g} GHz",
    )
    p_total = require("pressure_hpa", pressure_hpa, gt=0)
    t = require("temperature_k", temperature_k, gt=0)
    rho = require("water_vapour_density_g_m3", water_vapour_density_g_m3, ge=0)
    e = water_vapour_pressure_hpa(rho, t)
    p_dry = p_total - e
    if np.any(p_dry <= 0):
        raise ParameterError(
            "water_vapour_density_g_m3",
            float(np.max(rho)),
            f"a partial pressure rho T / 216.7 below the total pressure ({float(np.min(p_total)):g} hPa)",
        )
    theta = 300.0 / t
    f, p_dry, e, theta = (x[..., None] for x in np.broadcast_arrays(f, p_dry, e, theta))
    oxygen = _oxygen_lines_sum(f, p_dry, e, theta) + _dry_continuum(f[..., 0], p_dry[..., 0], e[..., 0], theta[..., 0])
    water = _water_vapour_lines_sum(f, p_dry, e, theta)
    return 0.1820 * f[..., 0] * oxygen, 0.1820 * f[..., 0] * water


def gaseous_attenuation_db_km(frequency_ghz, pressure_hpa, temperature_k, water_vapour_density_g_m3):
    """Specific attenuation of the atmospheric gases gamma = gamma_o + gamma_w [dB/km] (ITU-R P.676-12, Annex 1, Eq. 1).

    Line-by-line sum over the 44 oxygen and 35 water-vapour lines of Tables 1-2
    (``defaults/itu.toml``) with the dry-air continuum.

    Parameters
    ----------
    frequency_ghz : array_like
        Frequency [GHz], 1-1000.
    pressure_hpa : array_like
        Total barometric pressure p + e [hPa] (P.835-6 sea level: 1013.25); the dry-air
        pressure p of Eq. 3 is this minus the vapour pressure e.
    temperature_k : array_like
        Air temperature [K] (P.835-6 sea level: 288.15).
    water_vapour_density_g_m3 : array_like
        Water vapour density rho [g/m^3] (P.835-6 sea level: 7.5).

    Returns
    -------
    ndarray
        gamma [dB/km]; 0.173 at 24 GHz, 0.100 at 35 GHz, 14.66 at 60 GHz in the P.835 sea-level atmosphere.
    """
    oxygen, water = gaseous_attenuation_components_db_km(
        frequency_ghz, pressure_hpa, temperature_k, water_vapour_density_g_m3
    )
    return oxygen + water


#: A gas loss at most this large over a sensor's range [dB] is left out of its terms (docs/conventions.md).
GAS_LOSS_NEGLIGIBLE_DB = 0.01


def gas_loss_matters(gamma_db_km, range_m, ways=1):
    """Whether the gas loss ``ways`` gamma R over a range without it exceeds :data:`GAS_LOSS_NEGLIGIBLE_DB`.

    Parameters
    ----------
    gamma_db_km : array_like
        Gaseous specific attenuation [dB/km].
    range_m : array_like
        Range found without the gases [m]; the range with them is shorter, so this bounds the loss.
    ways : int
        1 for a one-way link (RF), 2 for a radar's two-way path.

    Returns
    -------
    ndarray of bool
    """
    with np.errstate(invalid="ignore"):
        loss = ways * np.asarray(gamma_db_km, float) * np.asarray(range_m, float) / 1000.0
    return np.nan_to_num(loss, nan=0.0) > GAS_LOSS_NEGLIGIBLE_DB
