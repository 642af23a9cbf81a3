"""Spectral acoustic detection (physical convention): outdoor propagation per one-third-octave band.

The drone is a source spectrum: harmonics of its blade-passing frequency plus broadband noise, scaled
so that its A-weighted level at 1 m is the target's ``sl_db``. Each one-third-octave band (exact
base-10 mid-band frequencies 1000 * 10^(k/10) Hz, 50 Hz to 10 kHz) travels with spherical
spreading, ISO 9613-1 absorption at its mid-band frequency and, where the scenario gives the
sensor's height, ISO 9613-2 ground attenuation and C_met. Ambient noise is pink (equal power per
band) scaled to the A-weighted ``noise_level_db``; wind noise in a microphone or its windshield
follows Strasberg's one-third-octave law. The array adds its gain (Eq. 42) against both noises,
uncorrelated from microphone to microphone; the detector listens in the band where the SNR is
highest, so the range is the largest of the per-band ranges.

References
----------
ISO 9613-1:1993 (absorption); ISO 9613-2:1996 (ground, Eq. 9, Table 3; C_met, Eqs. 21-22);
IEC 61260-1:2014 (base-10 band mid frequencies); IEC 61672-1:2013, Annex E (A-weighting);
M. Strasberg, "Dimensional analysis of windscreen noise", J. Acoust. Soc. Am. 83 (1988) 544-548.
"""

from __future__ import annotations

import functools

import numpy as np

from csuas.core.acoustic import iso9613_absorption_db_km, iso9613_cmet_db, iso9613_ground_db
from csuas.core.checks import require
from csuas.core.result import RangeResult, Term
from csuas.core.solve import bracketed_root, solve_log_linear
from csuas.defaults import load_tables

#: Band numbers k of the one-third-octave bands 50 Hz (k = -13) to 10 kHz (k = 10), IEC 61260-1.
BAND_NUMBERS = np.arange(-13, 11)
#: Wind below this speed [m/s] adds no wind noise (the lower end of Table 31 and of Strasberg's data).
WIND_NOISE_MIN_M_S = 1.0


def third_octave_bands_hz():
    """Exact mid-band frequencies 1000 * 10^(k/10) [Hz] of the bands 50 Hz to 10 kHz (IEC 61260-1, base 10)."""
    return 1000.0 * 10.0 ** (BAND_NUMBERS / 10.0)


def band_index(frequency_hz):
    """Index in :func:`third_octave_bands_hz` of the band holding a frequency, -1 outside 50 Hz-10 kHz."""
    k = np.rint(10.0 * np.log10(require("frequency_hz", frequency_hz, gt=0) / 1000.0)).astype(int)
    return np.where((k >= BAND_NUMBERS[0]) & (k <= BAND_NUMBERS[-1]), k - BAND_NUMBERS[0], -1)


def a_weighting_db(frequency_hz):
    """A-weighting A(f) [dB] (IEC 61672-1:2013, Eqs. E.6 with the pole frequencies of E.2-E.5)."""
    f2 = require("frequency_hz", frequency_hz, gt=0) ** 2
    f1, f2p, f3, f4 = 20.598997, 107.65265, 737.86223, 12194.217
    response = f4**2 * f2**2 / ((f2 + f1**2) * np.sqrt((f2 + f2p**2) * (f2 + f3**2)) * (f2 + f4**2))
    return 20.0 * np.log10(response) + 2.000


@functools.lru_cache(maxsize=1)
def _rotor_shape() -> dict:

    return load_tables()["acoustic"]["rotor_spectrum"]


def _power_db(power):
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(power)


def rotor_spectrum_db(sl_dba, blade_passing_hz):
    """Band levels at 1 m [dB, unweighted] of a rotor: blade-passing harmonics plus pink broadband.

    Harmonic n (n = 1 ... ``n_harmonics``) lies at n f_BPF with a power ``harmonic_decay_db`` (n - 1)
    below the first; the tones' A-weighted power is ``tonal_to_broadband_db`` above that of the
    broadband part (``defaults/tables.toml`` [acoustic.rotor_spectrum]); the whole spectrum is scaled
    so that its A-weighted level is ``sl_dba``.

    Parameters
    ----------
    sl_dba : array_like
        A-weighted source level at 1 m [dB] (Table 8).
    blade_passing_hz : array_like
        Blade-passing frequency [Hz]: blades per rotor times revolutions per second.

    Returns
    -------
    ndarray
        Shape ``broadcast(sl_dba, blade_passing_hz).shape + (24,)``.
    """
    shape = _rotor_shape()
    sl = require("sl_db", sl_dba)
    bpf = require("blade_passing_hz", blade_passing_hz, gt=0)
    sl, bpf = np.broadcast_arrays(sl, bpf)
    bands, order = third_octave_bands_hz(), np.arange(1, shape["n_harmonics"] + 1)
    tones_hz = bpf[..., None] * order
    tone_power = 10.0 ** (-shape["harmonic_decay_db"] * (order - 1) / 10.0) * np.ones_like(tones_hz)
    index = band_index(tones_hz)
    tone_power = np.where(index >= 0, tone_power, 0.0)  # tones beyond 10 kHz fall outside the bands
    tonal = np.sum(tone_power[..., None] * (index[..., None] == np.arange(bands.size)), axis=-2)
    a_weight = 10.0 ** (a_weighting_db(bands) / 10.0)
    broadband_a = np.sum(a_weight)
    tonal_scale = 10.0 ** (shape["tonal_to_broadband_db"] / 10.0) * broadband_a / np.sum(tonal * a_weight, axis=-1)
    power = tonal * tonal_scale[..., None] + 1.0
    return sl[..., None] + _power_db(power) - _power_db(np.sum(power * a_weight, axis=-1))[..., None]


def ambient_spectrum_db(noise_level_dba):
    """Band levels [dB, unweighted] of ambient noise: pink (equal power per band) at an A-weighted total.

    Parameters
    ----------
    noise_level_dba : array_like
        A-weighted ambient level N_lvl [dBA] (Table 30); -inf for silence.
    """
    n = require("noise_level_db", noise_level_dba, lt=np.inf, allow_inf=True)
    a_total = _power_db(np.sum(10.0 ** (a_weighting_db(third_octave_bands_hz()) / 10.0)))
    return n[..., None] - a_total + np.zeros(BAND_NUMBERS.size)


def wind_noise_spectrum_db(wind_speed_m_s, diameter_m):
    """One-third-octave wind noise [dB] in a windshield or bare microphone of diameter D (Strasberg 1988).

    L = 40 log10(V / 1 m/s) - 23 log10(f D / V) + 15 dB re 20 uPa, fitted to 2.5-25 cm windscreens at
    6-23 m/s within about 3 dB for 0.1 < f D / V < 5; a bare microphone (D about 1.3 cm) lies
    below the fitted diameters. Below 1 m/s: no wind noise (-inf).

    Parameters
    ----------
    wind_speed_m_s : array_like
        Wind speed at the microphone [m/s].
    diameter_m : array_like
        Windshield diameter, or the microphone's own without one [m].
    """
    v = require("wind_speed_m_s", wind_speed_m_s, ge=0)
    d = require("diameter_m", diameter_m, gt=0)
    v, d = np.broadcast_arrays(v, d)
    with np.errstate(divide="ignore"):
        level = (
            40.0 * np.log10(v[..., None])
            - 23.0 * np.log10(third_octave_bands_hz() * d[..., None] / v[..., None])
            + 15.0
        )
    return np.where(v[..., None] >= WIND_NOISE_MIN_M_S, level, -np.inf)


def _ground_loss_db(range_m, ground: dict):
    """ISO 9613-2 A_gr + C_met [dB] per band at slant ranges ``range_m`` (bands on the last axis)."""
    hr = ground["receiver_height_m"]
    hs = np.maximum(hr + ground["altitude_m"], 0.0)
    dp = np.sqrt(np.maximum(range_m**2 - ground["altitude_m"] ** 2, 1e-4))  # at least 1 cm on the ground
    a_gr = iso9613_ground_db(
        third_octave_bands_hz(), dp, hs, hr, ground["g_source"], ground["g_middle"], ground["g_receiver"]
    )
    return a_gr + iso9613_cmet_db(dp, hs, hr, ground["c0_db"])


#: Largest ground gain of ISO 9613-2 (hard ground in all three regions) [dB]: bounds the range from above.
GROUND_GAIN_MAX_DB = 6.0


def band_ranges_m(budget_db, absorption_db_km, ground=None):
    """Range [m] of each band: 20 log10 R + alpha R + A_gr(R) + C_met(R) = budget (bands on the last axis).

    Without ``ground`` the closed form (Lambert W) of :func:`csuas.core.solve.solve_log_linear`; with it a
    bracketed solve in log R (the ground terms grow with distance, so the residual falls monotonically).
    """
    alpha = np.asarray(absorption_db_km, float) / 1000.0
    free = solve_log_linear(budget_db, alpha, n=2.0)
    if ground is None:
        return free
    upper = solve_log_linear(np.asarray(budget_db) + GROUND_GAIN_MAX_DB, alpha, n=2.0)
    solvable = np.isfinite(upper) & (upper > 1e-3)
    hi = np.log10(np.where(solvable, upper, 1.0)) + 1e-6
    lo = np.full(hi.shape, -3.0)

    def residual(log_r):
        r = 10.0**log_r
        return budget_db - 20.0 * log_r - alpha * r - _ground_loss_db(r, ground)

    root, found = bracketed_root(residual, lo, hi, xtol=1e-10)
    return np.where(solvable & found, 10.0 ** np.nan_to_num(root, nan=-3.0), np.where(np.isinf(upper), np.inf, 0.0))


def spectral_acoustic_range(*, sl_db, blade_passing_hz, snr_req_db, g_array_db, noise_level_db, air, wind, ground=None):
    """Acoustic detection range [m] of a band-limited array detector (physical convention).

    Parameters
    ----------
    sl_db, blade_passing_hz : array_like
        A-weighted source level at 1 m [dB] and blade-passing frequency [Hz] of the drone.
    snr_req_db, g_array_db : array_like
        Required SNR in the detection band [dB] and array gain (Eq. 42) [dB].
    noise_level_db : array_like
        A-weighted ambient level [dBA].
    air : dict
        ``temperature_k``, ``relative_humidity_pct``, ``pressure_kpa`` (ISO 9613-1).
    wind : dict
        ``wind_speed_m_s`` and ``diameter_m`` (windshield, or the bare microphone).
    ground : dict, optional
        ``receiver_height_m``, ``altitude_m`` (target above the sensor), ``g_source``, ``g_middle``,
        ``g_receiver`` and ``c0_db``: ISO 9613-2 ground effect and C_met; None leaves both out.

    Returns
    -------
    RangeResult
        With the chosen band, its levels and the propagation terms at the range.
    """
    bands = third_octave_bands_hz()
    source = rotor_spectrum_db(sl_db, blade_passing_hz)
    ambient = ambient_spectrum_db(noise_level_db)
    wind_noise = wind_noise_spectrum_db(wind["wind_speed_m_s"], wind["diameter_m"])
    noise = _power_db(10.0 ** (ambient / 10.0) + 10.0 ** (wind_noise / 10.0))
    t_k, rh, p_kpa = (
        np.asarray(air[k], float)[..., None] for k in ("temperature_k", "relative_humidity_pct", "pressure_kpa")
    )
    alpha = iso9613_absorption_db_km(bands, t_k - 273.15, rh, p_kpa)
    if ground is not None:
        ground = {key: np.asarray(value, float)[..., None] for key, value in ground.items()}
    budget = source - noise + np.asarray(require("g_array_db", g_array_db), float)[..., None]
    budget = budget - np.asarray(require("snr_req_db", snr_req_db), float)[..., None]
    ranges = band_ranges_m(budget, alpha, ground)
    best = np.argmax(ranges, axis=-1)
    r = np.take_along_axis(ranges, best[..., None], axis=-1)[..., 0]

    def at_best(values):
        return np.take_along_axis(np.broadcast_to(values, ranges.shape), best[..., None], axis=-1)[..., 0]

    terms = [
        Term("detector_band_hz", bands[best], "Hz", "band of highest SNR (one-third octave, IEC 61260-1 base 10)"),
        Term("band_source_level_db", at_best(source), "dB", "rotor spectrum at 1 m, A-weighted total = sl_db"),
        Term("band_ambient_noise_db", at_best(ambient), "dB", "pink ambient noise, A-weighted total = N_lvl"),
        Term("g_array_db", np.asarray(g_array_db, float), "dB", "Eq. 42"),
        Term("absorption_db_km", at_best(alpha), "dB/km", "ISO 9613-1 at the mid-band frequency"),
    ]
    if np.any(np.isfinite(wind_noise)):
        terms.append(Term("band_wind_noise_db", at_best(wind_noise), "dB", "Strasberg 1988 (one-third octave)"))
    if ground is not None:
        at_range = np.where(np.isfinite(ranges) & (ranges > 0), ranges, 1.0)
        terms.append(
            Term("ground_and_cmet_db", at_best(_ground_loss_db(at_range, ground)), "dB", "ISO 9613-2 Eq. 9, Eqs. 21-22")
        )
    reason = np.where(np.isinf(r), "unbounded: silence and no wind, absorption does not bound a budget this large", "")
    model = "band-limited array detector (ISO 9613-1" + (", ISO 9613-2 ground" if ground is not None else "") + ")"
    return RangeResult(r, "acoustic", model, terms, reason if np.any(np.isinf(r)) else None)
