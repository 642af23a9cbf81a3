"""Acoustic detection range: spherical spreading, ambient and wind noise, array gain (Eqs. 32-49, 106-108).

R = 10^((SL - SNR_req - N_total + G_array) / 20), with N_total the power sum
of the noise terms present (Eq. 108): ambient N_lvl and, when the wind is at
least 1 m/s, the wind noise received from a source at ``wind_distance_m``,
RL_wind = N_wind(v) - 20 log10(r) (Eq. 46, Table 31).

The physical convention adds atmospheric sound absorption (ISO 9613-1),
solved exactly with :func:`csuas.core.solve.solve_log_linear`.
"""

from __future__ import annotations

import numpy as np

from csuas.core.checks import require, require_registry_bounds
from csuas.core.result import RangeResult, Term, check_convention
from csuas.core.solve import solve_log_linear
from csuas.core.units import linear_to_db, power_sum_db

#: Wind below this speed [m/s] produces no wind-noise term (Table 31 starts at 1 m/s).
WIND_NOISE_MIN_M_S = 1.0


def _wind_table():
    from csuas.defaults import load_tables

    table = load_tables()["acoustic"]["wind_noise"]
    return np.asarray(table["wind_speed_m_s"], dtype=float), np.asarray(table["noise_db"], dtype=float)


def wind_noise_db(wind_speed_m_s):
    """Wind noise level N_wind [dB] by linear interpolation of Table 31.

    Above 12 m/s (e.g. the paper's Strong Breeze, 12.3 m/s) the last value,
    89 dB, is held: the measurements end there. Below 1 m/s the table's first
    value is returned; the range model omits the wind term there.
    """
    v = require("wind_speed_m_s", wind_speed_m_s, ge=0)
    speeds, levels = _wind_table()
    return np.interp(v, speeds, levels)


def wind_noise_extrapolated(wind_speed_m_s):
    """True where the wind speed lies outside Table 31's 1-12 m/s."""
    v = np.asarray(wind_speed_m_s, dtype=float)
    speeds, _ = _wind_table()
    return (v < speeds[0]) | (v > speeds[-1])


def array_gain_db(n_micro, g_micro_db=0.0):
    """Array gain (Eq. 42): 10 log10(N_micro) + G_micro [dB]; 128 microphones give 21.07 dB."""
    n = require("n_micro", n_micro, ge=1)
    return linear_to_db(n) + np.asarray(g_micro_db, dtype=float)


def iso9613_absorption_db_m(frequency_hz, temperature_k=293.15, relative_humidity_pct=70.0, pressure_kpa=101.325):
    """Pure-tone sound absorption coefficient of air [dB/m] (ISO 9613-1:1993, Eqs. 3-5, B.1).

    Parameters
    ----------
    frequency_hz : array_like
        Frequency [Hz].
    temperature_k : array_like
        Air temperature [K].
    relative_humidity_pct : array_like
        Relative humidity [%].
    pressure_kpa : array_like
        Atmospheric pressure [kPa].
    """
    f = require("frequency_hz", frequency_hz, gt=0)
    t = require("temperature_k", temperature_k, gt=0)
    hr = require("relative_humidity_pct", relative_humidity_pct, ge=0, le=100)
    pa = require("pressure_kpa", pressure_kpa, gt=0) / 101.325
    t0, t01 = 293.15, 273.16
    psat = 10.0 ** (-6.8346 * (t01 / t) ** 1.261 + 4.6151)
    h = hr * psat / pa
    fr_o = pa * (24.0 + 4.04e4 * h * (0.02 + h) / (0.391 + h))
    fr_n = pa * (t / t0) ** -0.5 * (9.0 + 280.0 * h * np.exp(-4.170 * ((t / t0) ** (-1.0 / 3.0) - 1.0)))
    return (
        8.686
        * f**2
        * (
            1.84e-11 / pa * (t / t0) ** 0.5
            + (t / t0) ** -2.5
            * (
                0.01275 * np.exp(-2239.1 / t) / (fr_o + f**2 / fr_o)
                + 0.1068 * np.exp(-3352.0 / t) / (fr_n + f**2 / fr_n)
            )
        )
    )


#: Arguments of :func:`acoustic_range` -> their defaults/parameters.toml entries (upper bounds checked).
ACOUSTIC_REGISTRY = {
    "sl_db": "target.sl_db",
    "snr_req_db": "acoustic.snr_req_db",
    "noise_level_db": "environment.noise_level_db",
    "g_array_db": "acoustic.g_array_db",
    "wind_speed_m_s": "environment.wind_speed_m_s",
    "wind_distance_m": "acoustic.wind_distance_m",
}


def acoustic_range(
    *,
    sl_db,
    snr_req_db,
    noise_level_db,
    g_array_db,
    wind_speed_m_s=0.0,
    wind_distance_m=50.0,
    wind_noise_level_db=None,
    absorption_db_m=0.0,
    convention="paper",
) -> RangeResult:
    """Acoustic detection range [m] (Eqs. 39, 44, 49, 106-108).

    Parameters
    ----------
    sl_db : array_like
        Source level at 1 m [dB] (Table 8).
    snr_req_db : array_like
        Required SNR [dB] (Table 28).
    noise_level_db : array_like
        Ambient noise N_lvl [dBA] (Table 30); -inf for silence.
    g_array_db : array_like
        Array gain [dB] (Eq. 42, Table 32).
    wind_speed_m_s : array_like
        Wind speed [m/s]; the wind term applies from 1 m/s (Table 31).
    wind_distance_m : array_like
        Distance from the wind-noise source to the sensor [m] (Eq. 46).
    wind_noise_level_db : array_like, optional
        Wind noise N_wind [dB] given directly (Table 50 perturbs it); replaces
        the Table 31 lookup and applies whatever the wind speed.
    absorption_db_m : array_like
        Air absorption [dB/m]; 0 in the paper convention.
    convention : {"paper", "physical"}

    Returns
    -------
    RangeResult
        Ranges below 1 m are returned as computed (spreading is referred to 1 m).

        Silence (N_lvl = -inf), or a budget so large that R overflows, without wind or absorption
        gives R = inf with ``reason`` saying the range is unbounded.

    Raises
    ------
    ParameterError
        For NaN or out-of-domain inputs, naming the parameter.
    """
    require_registry_bounds(locals(), ACOUSTIC_REGISTRY)
    check_convention(convention)
    sl = require("sl_db", sl_db)
    snr = require("snr_req_db", snr_req_db)
    n_lvl = require("noise_level_db", noise_level_db, lt=np.inf, allow_inf=True)
    gain = require("g_array_db", g_array_db)
    v = require("wind_speed_m_s", wind_speed_m_s, ge=0)
    r_wind = require("wind_distance_m", wind_distance_m, gt=0)
    alpha = require("absorption_db_m", absorption_db_m, ge=0)
    terms = [
        Term("sl_db", sl, "dB", "Table 8"),
        Term("snr_req_db", snr, "dB", "Eq. 38"),
        Term("noise_level_db", n_lvl, "dBA", "Eq. 41 (Table 30)"),
        Term("g_array_db", gain, "dB", "Eq. 42"),
    ]
    if wind_noise_level_db is None:
        windy = v >= WIND_NOISE_MIN_M_S
        n_wind = np.where(windy, wind_noise_db(v), -np.inf)
    else:
        n_wind = require("wind_noise_level_db", wind_noise_level_db, lt=np.inf, allow_inf=True)
        windy = np.isfinite(n_wind)
    noise = n_lvl
    if np.any(windy):
        rl_wind = np.where(windy, n_wind - 20.0 * np.log10(r_wind), -np.inf)
        noise = power_sum_db(n_lvl, rl_wind)
        held = wind_noise_level_db is None and np.any(windy & wind_noise_extrapolated(v))
        terms.append(
            Term(
                "wind_noise_db",
                n_wind,
                "dB",
                "Table 31, beyond its 1-12 m/s: the 12 m/s value (89 dB) held" if held else "Table 31",
            )
        )
        terms.append(Term("wind_noise_at_sensor_db", rl_wind, "dB", "Eq. 46"))
        terms.append(Term("noise_total_db", noise, "dB", "Eq. 108"))
    budget = sl - snr - noise + gain
    if np.any(alpha > 0):
        terms.append(Term("absorption_db_m", alpha, "dB/m", "ISO 9613-1"))
    r = solve_log_linear(budget, alpha, n=2.0)
    reason = np.where(
        np.isinf(r),
        "unbounded: the noise is so low (or the source so loud) that spherical "
        "spreading alone never brings the signal below the required SNR, and neither wind noise nor "
        "absorption bounds it",
        "",
    )
    terms.append(Term("budget_db", budget, "dB", "Eq. 44"))
    model = "spherical_spreading+noise (Eqs. 44, 106-108)" + (" + ISO 9613-1 absorption" if np.any(alpha > 0) else "")
    return RangeResult(r, "acoustic", model, terms, reason if np.any(np.isinf(r)) else None)
