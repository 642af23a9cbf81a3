"""A drone as a Doppler-spread radar target: its body line, its blade lines, and a drone-or-bird decision.

A coherent radar that integrates ``n`` pulses at the PRF over one dwell splits the echo into Doppler
bins ``PRF / n`` wide. A drone's return there is a line spectrum (:func:`csuas.core.micro_doppler.blade_line_rcs_m2`):
the body line at zero Doppler (the body's RCS ``sigma_b``, which the radar's budget already holds) and
the rotors' blade lines at multiples ``m N Omega`` out to the tip Doppler (kHz at X band), each of RCS
``sigma_m``. The target's power splits over the lines in proportion to their RCS (Eq. DS-1), so the
single-pulse SNR of line ``m`` is the body's times ``sigma_m / sigma_b`` and after coherent
integration ``n`` times that (a steady line adds in phase: :func:`csuas.core.radar_detection.pd_exact`,
``integration="coherent"``). The lines are resolved when the bins are narrower than their spacing,
``n / PRF >= 1 / (N Omega)``, which is required here.

A bird's wing-beat moves its wing tips at ``v_w = 2 pi f_wb theta_a b / 2`` at most (wing-beat rate
``f_wb``, a few Hz; stroke half-amplitude ``theta_a``; span ``b``; sinusoidal flapping about the
shoulder), a few m/s, so its echo stays within the guard band ``|f| <= 2 v_w / lambda`` around its body
line (Eq. DS-2; Chen 2019, Ch. 5, flapping wings). The decision (Eq. DS-3): declare a drone when any of
the ``K`` Doppler bins outside the guard band (``guard < |f| <= PRF / 2``) crosses the threshold of
Pfa per bin. For a drone the ``L`` bins holding blade lines detect with their own Pd and the rest with
Pfa, so

    P(drone | drone) = 1 - prod_m (1 - Pd_m) (1 - Pfa)^(K - L),
    P(drone | bird or noise) = 1 - (1 - Pfa)^K,

the second because a bird puts no power outside the guard band. Lines of one dwell fluctuate together
scan to scan as the blades' aspect changes; each line is taken here as an independent Swerling 1
target (exponential power, one draw per dwell), an assumption that leaves out the correlation of
the lines of one dwell.

References
----------
Chen, V. C. (2019). The Micro-Doppler Effect in Radar, 2nd ed. Artech House (rotor blades Ch. 4,
    birds' flapping wings Ch. 5).
Richards, M. A. (2014). Fundamentals of Radar Signal Processing, 2nd ed. McGraw-Hill (Doppler filter
    banks, ch. 5; detection, ch. 6).
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require, require_all
from csuas.core.radar_detection import pd_exact
from csuas.core.units import wavelength_m

#: Swerling case of each blade line (module docstring: one exponential draw per dwell, assumed).
LINE_SWERLING = 1


def line_snr_fractions(body_rcs_m2, line_rcs_m2) -> tuple[float, np.ndarray]:
    """Shares of the target's power in the body line and in each blade line (Eq. DS-1); they sum to 1.

    Parameters
    ----------
    body_rcs_m2 : float
        RCS of the body, the zero-Doppler line [m^2], > 0.
    line_rcs_m2 : array_like (L,)
        RCS of each blade line [m^2], >= 0.

    Returns
    -------
    (float, ndarray (L,))
        ``sigma_b / sigma_total`` and ``sigma_m / sigma_total``.
    """
    body = float(require("body_rcs_m2", body_rcs_m2, gt=0))
    lines = np.atleast_1d(require("line_rcs_m2", line_rcs_m2, ge=0))
    total = body + float(lines.sum())
    return body / total, lines / total


def bird_guard_doppler_hz(wingspan_m, wingbeat_hz, stroke_amplitude_deg, frequency_ghz):
    """Largest Doppler of a bird's wing tips about its body line, ``2 v_w / lambda`` [Hz] (Eq. DS-2).

    Parameters
    ----------
    wingspan_m : float
        Wing span ``b`` [m], > 0.
    wingbeat_hz : float
        Wing-beat rate ``f_wb`` [Hz], > 0.
    stroke_amplitude_deg : float
        Half-amplitude ``theta_a`` of the flapping angle [deg], 0..90.
    frequency_ghz : float
        Radar frequency [GHz], > 0.
    """
    span, rate, amplitude, f = require_all(
        ("wingspan_m", wingspan_m, {"gt": 0}),
        ("wingbeat_hz", wingbeat_hz, {"gt": 0}),
        ("stroke_amplitude_deg", stroke_amplitude_deg, {"ge": 0, "le": 90}),
        ("frequency_ghz", frequency_ghz, {"gt": 0}),
    )
    tip_speed = 2.0 * np.pi * rate * np.radians(amplitude) * span / 2.0
    return 2.0 * tip_speed / wavelength_m(f)


def tested_bins(n_pulses: int, prf_hz: float, guard_hz: float) -> np.ndarray:
    """Doppler frequencies [Hz] of the bins the decision tests: ``guard < |k PRF / n| <= PRF / 2``."""
    n = int(n_pulses)
    frequency = np.fft.fftshift(np.fft.fftfreq(n, 1.0 / prf_hz))
    return frequency[np.abs(frequency) > guard_hz]


def _check_dwell(n_pulses, prf_hz, guard_hz, line_frequency_hz, pfa):
    n, prf, guard, pfa = require_all(
        ("n_pulses", n_pulses, {"ge": 1, "le": 10_000}),
        ("prf_hz", prf_hz, {"gt": 0}),
        ("guard_hz", guard_hz, {"ge": 0}),
        ("pfa", pfa, {"gt": 0, "lt": 1}),
    )
    lines = np.atleast_1d(require("line_frequency_hz", line_frequency_hz))
    spacing = np.min(np.diff(np.unique(lines))) if lines.size > 1 else np.inf
    if not float(n).is_integer():
        raise ParameterError("n_pulses", n_pulses, "a whole number of pulses")
    if spacing < prf / n:
        raise ParameterError(
            "n_pulses", n_pulses, f">= PRF / line spacing = {prf / spacing:.0f}: a dwell that resolves the blade lines"
        )
    return int(n), float(prf), float(guard), float(pfa), lines


def blade_feature_pd(snr1_db, body_rcs_m2, line_frequency_hz, line_rcs_m2, pfa, prf_hz, n_pulses, guard_hz):
    """Probability of declaring a drone from its blade lines, for a drone and for a bird (Eq. DS-3).

    Parameters
    ----------
    snr1_db : array_like (R,)
        Single-pulse SNR of the body line [dB] (the radar budget's SNR of ``body_rcs_m2``).
    body_rcs_m2 : float
        The body's RCS [m^2], > 0.
    line_frequency_hz, line_rcs_m2 : array_like (L,)
        Doppler [Hz] and RCS [m^2] of each line (:func:`csuas.core.micro_doppler.blade_line_rcs_m2`);
        the zero-Doppler line and lines beyond ``PRF / 2`` or inside the guard band are not tested.
    pfa : float
        False-alarm probability per Doppler bin, 0 < Pfa < 1.
    prf_hz : float
        Pulse repetition frequency [Hz], > 0.
    n_pulses : int
        Pulses integrated coherently in the dwell, 1..10000; the bins ``PRF / n`` must resolve the lines.
    guard_hz : float
        Half-width of the band about the body line left out (:func:`bird_guard_doppler_hz`) [Hz], >= 0.

    Returns
    -------
    dict
        ``pd_drone`` (R,), ``p_bird`` (the false declaration, a scalar), ``tested_bins`` K, ``lines_tested``
        L, ``line_snr_db`` (R, L) integrated SNR of each tested line [dB] and ``line_frequency_hz`` (L,).
    """
    n, prf, guard, pfa, lines = _check_dwell(n_pulses, prf_hz, guard_hz, line_frequency_hz, pfa)
    rcs = np.broadcast_to(np.atleast_1d(require("line_rcs_m2", line_rcs_m2, ge=0)), lines.shape)
    body = float(require("body_rcs_m2", body_rcs_m2, gt=0))
    snr1 = np.atleast_1d(require("snr1_db", snr1_db)).astype(float)
    bins = tested_bins(n, prf, guard)
    tested = (np.abs(lines) > guard) & (np.abs(lines) <= prf / 2.0) & (rcs > 0)
    with np.errstate(divide="ignore"):
        line_snr1_db = snr1[:, None] + 10.0 * np.log10(rcs[tested] / body)[None, :]
    pd_lines = pd_exact(line_snr1_db, pfa, n, LINE_SWERLING, "coherent")
    quiet = bins.size - int(tested.sum())
    miss = np.prod(1.0 - pd_lines, axis=1) * (1.0 - pfa) ** quiet
    return {
        "pd_drone": 1.0 - miss,
        "p_bird": float(-np.expm1(bins.size * np.log1p(-pfa))),
        "tested_bins": int(bins.size),
        "lines_tested": int(tested.sum()),
        "line_snr_db": line_snr1_db + 10.0 * np.log10(n),
        "line_frequency_hz": lines[tested],
    }
