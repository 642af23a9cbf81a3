"""Acoustic detection range: spherical spreading, ambient and wind noise, array gain (Eqs. 32-49, 106-108).

R = 10^((SL - SNR_req - N_total + G_array) / 20), with N_total the power sum
of the noise terms present (Eq. 108): ambient N_lvl and, when the wind is at
least 1 m/s, the wind noise received from a source at ``wind_distance_m``,
RL_wind = N_wind(v) - 20 log10(r) (Eq. 46, Table 31).

The physical convention adds atmospheric sound absorption (ISO 9613-1),
solved exactly with :func:`csuas.core.solve.solve_log_linear`, and, behind terrain, the barrier
attenuation of one or two diffracting edges (ISO 9613-2:1996, Section 7.4, Eqs. 12-18).
"""

from __future__ import annotations

import numpy as np

from csuas.core.checks import require, require_registry_bounds
from csuas.core.result import RangeResult, Term, check_convention
from csuas.core.solve import solve_log_linear
from csuas.core.units import linear_to_db, power_sum_db
from csuas.defaults import load_tables

#: Wind below this speed [m/s] produces no wind-noise term (Table 31 starts at 1 m/s).
WIND_NOISE_MIN_M_S = 1.0


def _wind_table():

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


#: ISO 9613-1 reference temperature [K], triple-point isotherm [K] and reference pressure [kPa] (Section 3).
T_REFERENCE_K, T_TRIPLE_K, P_REFERENCE_KPA = 293.15, 273.16, 101.325


def _molar_water_vapour_pct(relative_humidity_pct, temperature_k, pressure_ratio):
    """Molar concentration of water vapour h [%] (ISO 9613-1, Annex B, Eqs. B.1-B.3)."""
    p_sat_ratio = 10.0 ** (-6.8346 * (T_TRIPLE_K / temperature_k) ** 1.261 + 4.6151)
    return relative_humidity_pct * p_sat_ratio / pressure_ratio


def _oxygen_relaxation_hz(pressure_ratio, h):
    """Relaxation frequency of oxygen f_rO [Hz] (ISO 9613-1, Eq. 3)."""
    return pressure_ratio * (24.0 + 4.04e4 * h * (0.02 + h) / (0.391 + h))


def _nitrogen_relaxation_hz(pressure_ratio, temperature_k, h):
    """Relaxation frequency of nitrogen f_rN [Hz] (ISO 9613-1, Eq. 4)."""
    tr = temperature_k / T_REFERENCE_K
    return pressure_ratio * tr**-0.5 * (9.0 + 280.0 * h * np.exp(-4.170 * (tr ** (-1.0 / 3.0) - 1.0)))


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
    pa = require("pressure_kpa", pressure_kpa, gt=0) / P_REFERENCE_KPA
    h = _molar_water_vapour_pct(hr, t, pa)
    fr_o, fr_n = _oxygen_relaxation_hz(pa, h), _nitrogen_relaxation_hz(pa, t, h)
    tr = t / T_REFERENCE_K
    return (
        8.686
        * f**2
        * (
            1.84e-11 / pa * tr**0.5
            + tr**-2.5
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


def iso9613_absorption_db_km(frequency_hz, temperature_c, relative_humidity_pct, pressure_kpa):
    """Atmospheric absorption coefficient alpha [dB/km] (ISO 9613-1:1993, Eq. 5; ISO 9613-2 Table 2).

    Parameters
    ----------
    frequency_hz : array_like
        Frequency [Hz]; for a band, its exact mid-band frequency (1000 * 10^(k/10) Hz for
        one-third-octave bands, ISO 9613-1 Section 8.2.1).
    temperature_c : array_like
        Air temperature [deg C], -60 to +50 for ISO 9613-1's +-10 % accuracy.
    relative_humidity_pct : array_like
        Relative humidity [%].
    pressure_kpa : array_like
        Atmospheric pressure [kPa].

    Returns
    -------
    ndarray
        alpha [dB/km]; 4.98 at 1 kHz, 20 deg C, 70 %, 101.325 kPa.
    """
    t_k = require("temperature_c", temperature_c, gt=-273.15) + 273.15
    return 1000.0 * iso9613_absorption_db_m(frequency_hz, t_k, relative_humidity_pct, pressure_kpa)


#: Nominal octave bands of ISO 9613-2 Table 3 [Hz].
ISO9613_OCTAVES_HZ = (63, 125, 250, 500, 1000, 2000, 4000, 8000)


def octave_band_index(frequency_hz):
    """Index in :data:`ISO9613_OCTAVES_HZ` of the octave band holding a frequency (ends extended to all f)."""
    f = require("frequency_hz", frequency_hz, gt=0)
    return np.clip(np.rint(10.0 * np.log10(f / 1000.0) / 3.0).astype(int) + 4, 0, 7)


def _height_factor(octave_index, height_m, distance_m):
    """Factors a'(h), b'(h), c'(h), d'(h) of the 125-1000 Hz bands, 0 elsewhere (ISO 9613-2, Table 3 notes)."""
    h, dp = height_m, distance_m
    near = 1.0 - np.exp(-dp / 50.0)
    factors = [
        1.5
        + 3.0 * np.exp(-0.12 * (h - 5.0) ** 2) * near
        + 5.7 * np.exp(-0.09 * h**2) * (1.0 - np.exp(-2.8e-6 * dp**2)),
        1.5 + 8.6 * np.exp(-0.09 * h**2) * near,
        1.5 + 14.0 * np.exp(-0.46 * h**2) * near,
        1.5 + 5.0 * np.exp(-0.9 * h**2) * near,
    ]
    return np.select([octave_index == k for k in (1, 2, 3, 4)], factors, default=0.0)


def _end_region_ground_db(octave_index, ground_factor, height_m, distance_m):
    """Source- or receiver-region ground attenuation A_s or A_r [dB] (ISO 9613-2, Table 3)."""
    g = ground_factor
    return np.select(
        [octave_index == 0, octave_index <= 4],
        [-1.5, -1.5 + g * _height_factor(octave_index, height_m, distance_m)],
        default=-1.5 * (1.0 - g),
    )


def _middle_region_ground_db(octave_index, ground_factor, q):
    """Middle-region ground attenuation A_m [dB] (ISO 9613-2, Table 3): -3q, or -3q (1 - G_m) from 125 Hz."""
    return np.where(octave_index == 0, -3.0 * q, -3.0 * q * (1.0 - ground_factor))


def _middle_q(distance_m, source_height_m, receiver_height_m):
    """Middle-region factor q (ISO 9613-2, Table 3 note): 0 up to 30 (h_s + h_r), then 1 - 30 (h_s + h_r) / d_p."""
    reach = 30.0 * (source_height_m + receiver_height_m)
    return np.where(distance_m <= reach, 0.0, 1.0 - reach / np.maximum(distance_m, reach))


def iso9613_ground_db(frequency_hz, distance_m, source_height_m, receiver_height_m, g_source, g_middle, g_receiver):
    """Ground attenuation A_gr = A_s + A_r + A_m [dB] of flat ground (ISO 9613-2:1996, Section 7.3.1, Eq. 9).

    Parameters
    ----------
    frequency_hz : array_like
        Frequency [Hz]; the value of the octave band of Table 3 holding it (63 Hz to 8 kHz,
        extended below and above).
    distance_m : array_like
        Source-receiver distance projected on the ground d_p [m].
    source_height_m, receiver_height_m : array_like
        Heights above ground h_s, h_r [m].
    g_source, g_middle, g_receiver : array_like
        Ground factors G of the three regions: 0 hard (paving, water), 1 porous (grass, farmland).

    Returns
    -------
    ndarray
        A_gr [dB]; negative where the ground reflection adds to the level.
    """
    k = octave_band_index(frequency_hz)
    dp = require("distance_m", distance_m, gt=0)
    hs = require("source_height_m", source_height_m, ge=0)
    hr = require("receiver_height_m", receiver_height_m, ge=0)
    gs, gm, gr = (
        require(n, v, ge=0, le=1)
        for n, v in (("g_source", g_source), ("g_middle", g_middle), ("g_receiver", g_receiver))
    )
    return (
        _end_region_ground_db(k, gs, hs, dp)
        + _end_region_ground_db(k, gr, hr, dp)
        + _middle_region_ground_db(k, gm, _middle_q(dp, hs, hr))
    )


def iso9613_cmet_db(distance_m, source_height_m, receiver_height_m, c0_db):
    """Meteorological correction C_met [dB] (ISO 9613-2:1996, Section 8, Eqs. 21-22).

    0 up to d_p = 10 (h_s + h_r), then C_0 (1 - 10 (h_s + h_r) / d_p): the long-term average level is
    the downwind level less C_met.

    Parameters
    ----------
    distance_m : array_like
        Ground-projected distance d_p [m].
    source_height_m, receiver_height_m : array_like
        Heights h_s, h_r [m].
    c0_db : array_like
        C_0 [dB] from the local wind and temperature-gradient statistics (0-5 dB).
    """
    dp = require("distance_m", distance_m, gt=0)
    reach = 10.0 * (
        require("source_height_m", source_height_m, ge=0) + require("receiver_height_m", receiver_height_m, ge=0)
    )
    c0 = require("c0_db", c0_db, ge=0)
    return np.where(dp <= reach, 0.0, c0 * (1.0 - reach / np.maximum(dp, reach)))


#: ISO 9613-2 Eq. 14 constant C2 (ground reflections taken into account by the image sources).
BARRIER_C2 = 20.0
#: Upper bounds of D_z for single and double diffraction [dB] (ISO 9613-2, Section 7.4).
BARRIER_CAP_SINGLE_DB, BARRIER_CAP_DOUBLE_DB = 20.0, 25.0
#: Speed of sound of the barrier's wavelength lambda = c / f [m/s] (air at 15 C, ISO 9613-2 uses the nominal value).
SPEED_OF_SOUND_M_S = 340.0


def iso9613_barrier_met_factor(path_difference_m, source_edge_m, edge_receiver_m, distance_m):
    """Meteorological correction factor K_met of top-edge diffraction (ISO 9613-2:1996, Eq. 18).

    K_met = exp(-(1/2000) sqrt(d_ss d_sr d / (2 z))) for z > 0, and 1 for z <= 0.

    Parameters
    ----------
    path_difference_m : array_like
        Path-length difference z [m] (Eq. 16 or 17).
    source_edge_m, edge_receiver_m, distance_m : array_like
        Source to edge d_ss, edge to receiver d_sr and source to receiver d distances [m].
    """
    z = require("path_difference_m", path_difference_m)
    product = (
        require("source_edge_m", source_edge_m, ge=0)
        * require("edge_receiver_m", edge_receiver_m, ge=0)
        * require("distance_m", distance_m, ge=0)
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = np.exp(-np.sqrt(product / (2.0 * z)) / 2000.0)
    return np.where(z > 0, factor, 1.0)


def iso9613_barrier_c3(frequency_hz, edge_separation_m):
    """Factor C3 of ISO 9613-2 Eq. 14 for an edge separation e [-] (Eq. 15; 1 for single diffraction).

    C3 = (1 + (5 lambda / e)^2) / (1/3 + (5 lambda / e)^2), lambda = c / f with c = 340 m/s: 1 at e = 0
    (one edge: the limit of Eq. 15), rising to 3 for edges many wavelengths apart.

    Parameters
    ----------
    frequency_hz : array_like
        Frequency [Hz], > 0.
    edge_separation_m : array_like
        Distance e between the first and the last diffracting edge [m], >= 0 (0: single diffraction).
    """
    wavelength = SPEED_OF_SOUND_M_S / require("frequency_hz", frequency_hz, gt=0)
    x = (require("edge_separation_m", edge_separation_m, ge=0) / (5.0 * wavelength)) ** 2
    return 3.0 * (1.0 + x) / (3.0 + x)  # Eq. 15 with numerator and denominator times (e / 5 lambda)^2


def iso9613_barrier_db(frequency_hz, path_difference_m, met_factor=1.0, ground_db=0.0, edge_separation_m=0.0):
    """Barrier attenuation A_bar = D_z - A_gr of top-edge diffraction [dB] (ISO 9613-2:1996, Eqs. 12, 14, 15).

    D_z = 10 lg(3 + (C2 / lambda) C3 z K_met), C2 = 20, C3 from the edge separation e
    (:func:`iso9613_barrier_c3`: 1 for one edge), lambda = c / f with c = 340 m/s, capped at 20 dB for
    single and 25 dB for double diffraction (e > 0; Section 7.4); A_bar = D_z - A_gr, not below 0
    (Eq. 12: the barrier replaces the ground effect of the blocked path).

    Parameters
    ----------
    frequency_hz : array_like
        Frequency [Hz] (the band's mid-band frequency).
    path_difference_m : array_like
        Path-length difference z [m] between the diffracted and the direct path (Eq. 16 or 17), >= 0
        (:func:`csuas.core.terrain.diffraction_path_difference_m` from a terrain profile).
    met_factor : array_like
        K_met (Eq. 18, :func:`iso9613_barrier_met_factor`); 1 for short paths.
    ground_db : array_like
        A_gr of the unblocked path [dB] (:func:`iso9613_ground_db`); 0 where the model has no ground term.
    edge_separation_m : array_like
        Distance e between the two diffracting edges of double diffraction [m] (Eq. 15); 0: one edge.

    Returns
    -------
    ndarray
        A_bar [dB].
    """
    f = require("frequency_hz", frequency_hz, gt=0)
    z = require("path_difference_m", path_difference_m, ge=0)
    k_met = require("met_factor", met_factor, gt=0, le=1)
    e = require("edge_separation_m", edge_separation_m, ge=0)
    wavelength = SPEED_OF_SOUND_M_S / f
    d_z = 10.0 * np.log10(3.0 + BARRIER_C2 / wavelength * iso9613_barrier_c3(f, e) * z * k_met)
    cap = np.where(e > 0, BARRIER_CAP_DOUBLE_DB, BARRIER_CAP_SINGLE_DB)
    return np.maximum(np.minimum(d_z, cap) - require("ground_db", ground_db), 0.0)


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
