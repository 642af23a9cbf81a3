"""Passive RF detection range: Friis (Eqs. 50-57) with rain and fog losses (Eqs. 58-61).

Conventions (docs/conventions.md point 4): ``paper`` applies the rain and fog losses over
fixed path lengths d_rain, d_fog (Table 37: 1 km); ``physical`` applies the
specific attenuations over the actual range and solves
20 log10(4 pi R / lambda) + (gamma_rain + gamma_fog + gamma_gas) R = budget exactly, the gases
(oxygen and water vapour, ITU-R P.676) only where they cost more than 0.01 dB over the range.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require, require_registry_bounds
from csuas.core.itu import fog_specific_attenuation_db_km, gas_loss_matters, rain_specific_attenuation_db_km
from csuas.core.result import RangeResult, Term, check_convention, unbounded_reason
from csuas.core.solve import solve_log_linear
from csuas.core.units import watt_to_dbm, wavelength_m


def free_space_path_loss_db(frequency_ghz, distance_m):
    """Free-space path loss (Eq. 54): 20 log10(4 pi d / lambda) [dB]."""
    f = require("frequency_ghz", frequency_ghz, gt=0)
    d = require("distance_m", distance_m, gt=0)
    return 20.0 * np.log10(4.0 * np.pi * d / wavelength_m(f))


def received_power_dbm(p_tx_w, g_tx_dbi, g_rx_db, frequency_ghz, distance_m):
    """Received power in free space (Eq. 55) [dBm]."""
    p = require("rf_power_w", p_tx_w, gt=0)
    return (
        watt_to_dbm(p) + np.asarray(g_tx_dbi) + np.asarray(g_rx_db) - free_space_path_loss_db(frequency_ghz, distance_m)
    )


#: Arguments of :func:`rf_range` -> their defaults/parameters.toml entries (upper bounds checked).
RF_REGISTRY = {
    "p_tx_w": "target.rf_power_w",
    "g_tx_dbi": "target.rf_gain_dbi",
    "g_rx_db": "rf.g_rx_db",
    "frequency_ghz": "rf.frequency_ghz",
    "s_rx_dbm": "rf.s_rx_dbm",
    "rain_rate_mm_h": "environment.rain_rate_mm_h",
    "lwc_g_m3": "environment.lwc_g_m3",
    "temperature_k": "environment.temperature_k",
    "d_rain_km": "rf.d_rain_km",
    "d_fog_km": "rf.d_fog_km",
}


def rf_range(
    *,
    p_tx_w,
    g_tx_dbi,
    g_rx_db,
    frequency_ghz,
    s_rx_dbm,
    rain_rate_mm_h=0.0,
    lwc_g_m3=0.0,
    temperature_k=293.15,
    d_rain_km=1.0,
    d_fog_km=1.0,
    gas_db_km=0.0,
    convention="paper",
) -> RangeResult:
    """Passive RF detection range [m] (Eq. 57 with the losses of Eqs. 59, 61).

    Parameters
    ----------
    p_tx_w, g_tx_dbi : array_like
        Power [W] and gain [dBi] of the sUAS transmitter (Table 8).
    g_rx_db, s_rx_dbm : array_like
        Sensor antenna gain [dB] and sensitivity [dBm] (Table 33).
    frequency_ghz : array_like
        Carrier frequency [GHz].
    rain_rate_mm_h, lwc_g_m3, temperature_k : array_like
        Rain rate, fog liquid water content and air temperature; a zero rate
        or LWC adds no term.
    d_rain_km, d_fog_km : array_like
        Fixed loss path lengths of the paper convention (Table 37).
    gas_db_km : array_like
        Gaseous specific attenuation [dB/km] (ITU-R P.676, :func:`csuas.core.itu.gaseous_attenuation_db_km`),
        physical convention only; applied where it costs more than 0.01 dB over the range.
    convention : {"paper", "physical"}

    Returns
    -------
    RangeResult
        A link budget too large for a float64 range (e.g. s_rx_dbm = -7000) gives R = inf with
        ``reason``, never a bare infinity.

    Raises
    ------
    ParameterError
        NaN or an infinite dB value, naming the parameter.
    """
    require_registry_bounds(locals(), RF_REGISTRY)
    check_convention(convention)
    if convention == "paper" and np.any(np.asarray(gas_db_km) != 0):
        raise ParameterError("gas_db_km", float(np.max(gas_db_km)), "0 in the paper convention (it has no gas term)")
    f = require("frequency_ghz", frequency_ghz, gt=0)
    budget = (
        watt_to_dbm(require("rf_power_w", p_tx_w, gt=0))
        + require("g_tx_dbi", g_tx_dbi)
        + require("g_rx_db", g_rx_db)
        - require("s_rx_dbm", s_rx_dbm)
    )
    lam = wavelength_m(f)
    terms = [Term("p_tx_dbm", watt_to_dbm(p_tx_w), "dBm", "Eq. 52"), Term("link_budget_db", budget, "dB", "Eq. 57")]
    rain_present, fog_present = np.any(np.asarray(rain_rate_mm_h) > 0), np.any(np.asarray(lwc_g_m3) > 0)
    gamma = 0.0
    if rain_present:
        g_rain = rain_specific_attenuation_db_km(f, rain_rate_mm_h)
        terms.append(Term("gamma_rain_db_km", g_rain, "dB/km", "Eq. 58 (ITU-R P.838-3)"))
        gamma = gamma + g_rain
    if fog_present:
        g_fog = fog_specific_attenuation_db_km(f, lwc_g_m3, temperature_k)
        terms.append(Term("gamma_fog_db_km", g_fog, "dB/km", "Eq. 60 (ITU-R P.840)"))
        gamma = gamma + g_fog
    k_db = budget + 20.0 * np.log10(lam / (4.0 * np.pi))
    if convention == "paper":
        fixed = 0.0
        if rain_present:
            fixed = fixed + g_rain * require("d_rain_km", d_rain_km, ge=0)
            terms.append(Term("rain_loss_db", g_rain * d_rain_km, "dB", "Eq. 59"))
        if fog_present:
            fixed = fixed + g_fog * require("d_fog_km", d_fog_km, ge=0)
            terms.append(Term("fog_loss_db", g_fog * d_fog_km, "dB", "Eq. 61"))
        r = solve_log_linear(k_db - fixed, 0.0, n=2.0)
    else:
        r = solve_log_linear(k_db, np.asarray(gamma, float) / 1000.0, n=2.0)
        if rain_present or fog_present:
            terms.append(Term("weather_loss_db", np.asarray(gamma) * r / 1000.0, "dB", "Eqs. 59, 61 over R"))
        r = _with_gases(r, k_db, gamma, require("gas_db_km", gas_db_km, ge=0), terms)
    return RangeResult(r, "rf", "friis (Eq. 57)", terms, unbounded_reason(r))


def _with_gases(r_without, k_db, gamma_weather_db_km, gas_db_km, terms):
    """Range with the gaseous loss over R where it exceeds 0.01 dB, and its terms (ITU-R P.676)."""
    matters = gas_loss_matters(gas_db_km, r_without)
    if not np.any(matters):
        return r_without
    gas = np.where(matters, gas_db_km, 0.0)
    r = solve_log_linear(k_db, (np.asarray(gamma_weather_db_km, float) + gas) / 1000.0, n=2.0)
    terms.append(Term("gamma_gas_db_km", gas, "dB/km", "ITU-R P.676-12 Annex 1 (oxygen and water vapour)"))
    terms.append(Term("gas_loss_db", gas * r / 1000.0, "dB", "ITU-R P.676-12 over R"))
    return r
