"""The drone as a Doppler-spread target: blade lines, their share of the power, and the drone-or-bird decision.

References: the blade lines' spacing N Omega (Chen et al., IEEE TAES 42(1), 2006, Sec. V) and their sum,
the time-mean RCS by quadrature of the closed form over one turn (Parseval); the decision's
probabilities from Swerling 1's coherent closed form Pd = Pfa^(1 / (1 + n snr)) and a Monte Carlo of
the Doppler filter bank (complex Gaussian noise, an exponential line, FFT, threshold -ln Pfa).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core import micro_doppler as md
from csuas.core import micro_doppler_detection as mdd
from csuas.validation.report.checks_micro_doppler import time_mean_rcs_m2

C = 299_792_458.0


@pytest.mark.parametrize("n_blades", [2, 3])
def test_blade_lines_are_spaced_n_omega_and_sum_to_the_time_mean_rcs(n_blades):
    chord = C / 10e9 / 20.0  # the checks' flat-blade rotor: 0.076 m, 100 rev/s, 10 GHz, 20 deg, chord lambda/20
    order, frequency, rcs = md.blade_line_rcs_m2(0.076, n_blades, 100.0, 10.0, 20.0, chord)
    assert np.allclose(frequency, order * 100.0 * n_blades, rtol=0, atol=1e-9)
    assert rcs.sum() == pytest.approx(time_mean_rcs_m2(n_blades, chord), rel=1e-9)
    tip = md.max_tip_doppler_hz(0.076, 100.0, 10.0, 20.0)
    assert rcs[np.abs(frequency) > tip + 2 * 100.0 * n_blades].sum() < 1e-3 * rcs.sum()  # 8e-5 beyond the tip
    _, _, four = md.blade_line_rcs_m2(0.076, n_blades, 100.0, 10.0, 20.0, chord, n_rotors=4)
    assert np.allclose(four, 4 * rcs, rtol=1e-12, atol=0)


def test_power_shares_sum_to_one():
    body, lines = mdd.line_snr_fractions(0.01, [1e-4, 3e-4, 0.0])
    assert body == pytest.approx(0.01 / 0.0104) and body + lines.sum() == pytest.approx(1.0, abs=1e-15)
    with pytest.raises(ParameterError) as info:
        mdd.line_snr_fractions(0.0, [1e-4])
    assert info.value.name == "body_rcs_m2"


def test_bird_guard_is_the_wing_tip_doppler():
    tip_speed = 2 * math.pi * 5.5 * math.radians(45.0) * 0.33  # pigeon: 5.5 Hz, 45 deg, span 0.66 m
    assert mdd.bird_guard_doppler_hz(0.66, 5.5, 45.0, 10.0) == pytest.approx(2 * tip_speed / (C / 10e9), rel=1e-12)


def test_decision_probabilities_from_swerling_1_closed_form():
    n, prf, guard, pfa, snr1_db = 1000, 20_000.0, 1433.0, 1e-6, -20.0
    bins = n - (2 * int(guard // (prf / n)) + 1)  # bins of 20 Hz outside +-1433 Hz
    assert mdd.tested_bins(n, prf, guard).size == bins == 857
    # one line of a tenth of the body's RCS at 2 kHz, one inside the guard (not tested)
    out = mdd.blade_feature_pd(snr1_db, 0.01, [1000.0, 2000.0], [1e-3, 1e-3], pfa, prf, n, guard)
    snr = n * 10 ** (snr1_db / 10) * 0.1
    line = pfa ** (1 / (1 + snr))
    assert out["lines_tested"] == 1 and out["line_snr_db"][0, 0] == pytest.approx(10 * math.log10(snr))
    assert out["pd_drone"][0] == pytest.approx(1 - (1 - line) * (1 - pfa) ** (bins - 1), rel=1e-12)
    assert out["p_bird"] == pytest.approx(1 - (1 - pfa) ** bins, rel=1e-9)
    with pytest.raises(ParameterError) as info:  # 10 pulses: 2 kHz bins do not resolve lines 1 kHz apart
        mdd.blade_feature_pd(snr1_db, 0.01, [1000.0, 2000.0], [1e-3, 1e-3], pfa, prf, 10, guard)
    assert info.value.name == "n_pulses"


def test_decision_matches_a_monte_carlo_filter_bank():
    """64 pulses, a Swerling 1 line in bin 12, Pfa 1e-2 per bin: the share of dwells declared a drone."""
    n, prf, pfa, trials = 64, 6400.0, 1e-2, 4000
    rng = np.random.default_rng(5)
    snr1 = 10 ** (-12.0 / 10)  # the line's single-pulse SNR
    t = np.arange(n)
    noise = (rng.standard_normal((trials, n)) + 1j * rng.standard_normal((trials, n))) / math.sqrt(2)
    power = rng.exponential(snr1, trials)
    phase = rng.uniform(0, 2 * np.pi, trials)
    line = np.sqrt(power)[:, None] * np.exp(1j * (phase[:, None] + 2 * np.pi * 12 * t / n))
    spectrum = np.abs(np.fft.fft(line + noise, axis=1)) ** 2 / n  # unit noise power per bin
    frequency = np.fft.fftfreq(n, 1 / prf)
    tested = np.abs(frequency) > 350.0
    declared = np.mean((spectrum[:, tested] > -math.log(pfa)).any(axis=1))
    out = mdd.blade_feature_pd(-12.0, 1.0, [1200.0], [1.0], pfa, prf, n, 350.0)
    expected = float(out["pd_drone"][0])
    assert abs(declared - expected) < 4 * math.sqrt(expected * (1 - expected) / trials)
    noise_only = np.abs(np.fft.fft(noise, axis=1)) ** 2 / n
    bird = np.mean((noise_only[:, tested] > -math.log(pfa)).any(axis=1))
    assert abs(bird - out["p_bird"]) < 4 * math.sqrt(out["p_bird"] * (1 - out["p_bird"]) / trials)


def test_pd_reports_micro_doppler_only_when_asked(capsys):
    from csuas import cli

    assert cli.main(["pd", "default", "--range-m", "10", "100", "--json"]) == 0
    assert "micro_doppler" not in json.loads(capsys.readouterr().out)["sensors"]["radar"]
    assert cli.main(["pd", "default", "--range-m", "10", "100", "--micro-doppler", "--json"]) == 0
    radar = json.loads(capsys.readouterr().out)["sensors"]["radar"]
    m = radar["micro_doppler"]
    assert m["line_spacing_hz"] == pytest.approx(330.0)  # the default target's blade_passing_hz
    assert m["body_power_fraction"] + m["blade_power_fraction"] == pytest.approx(1.0, abs=1e-12)
    assert np.allclose(m["pd_detected_and_classified"], np.multiply(radar["pd"], m["pd_classified_drone"]))
    assert m["pd_classified_drone"][0] > 0.5 > m["pd_classified_drone"][1] >= m["p_bird_classified_drone"]
    code = cli.main(
        ["pd", "default", "--micro-doppler", "--micro-doppler-dwell-s", "2", "--micro-doppler-prf-hz", "-1"]
    )
    err = capsys.readouterr().err
    assert code == 2 and "micro_doppler.prf_hz" in err and "micro_doppler.dwell_s" in err


def test_engagement_classification_rejects_bird_tracks_and_keeps_the_drone():
    """Birds over a radar: the same runs with and without the decision; bird tracks drop, the drone's stays."""
    import dataclasses
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from test_engagement import _approach, _radar

    from csuas.render.engagement.metrics import summarise
    from csuas.render.engagement.sensors import LookSettings
    from csuas.render.engagement.simulate import run_once
    from csuas.render.rcs.drone_or_bird import ClassifierSettings

    dem = np.zeros((80, 80))
    settings = LookSettings(pfa=1e-7, clutter=False, decorrelation="independent", sigma_bearing_deg=0.5)
    _, sensor = _radar(dem, settings)
    plain = _approach(dem, sensor, birds=20.0)
    fields = {f.name: getattr(plain, f.name) for f in dataclasses.fields(plain) if f.init}
    classified = type(plain)(**{**fields, "classifier": ClassifierSettings()})
    off = [run_once(plain, i) for i in range(2)]
    on = [run_once(classified, i) for i in range(2)]
    assert [(f["cause"], f["t_s"]) for r in off for f in r["false_tracks"]] == [
        (f["cause"], f["t_s"]) for r in on for f in r["false_tracks"]
    ]
    assert all(not f["rejected"] for r in off for f in r["false_tracks"])
    birds = [f for r in on for f in r["false_tracks"] if f["cause"] == "birds"]
    assert len(birds) >= 10 and sum(not f["rejected"] for f in birds) < 0.2 * len(birds)
    assert sum(r["drone_tracks"] for r in on) >= 2 and sum(r["drone_tracks_rejected"] for r in on) == 0
    metrics = summarise(classified, on)
    kept, total = metrics["classified"]["false_tracks_per_hour"], metrics["false_tracks_per_hour"]
    assert kept["by_cause"]["birds"] < total["by_cause"]["birds"] and "classified" not in summarise(plain, off)


def test_pd_names_a_dwell_that_cannot_resolve_the_lines(capsys):
    from csuas import cli

    # 330 Hz lines need a dwell of at least 1 / 330 s = 3.03 ms
    assert cli.main(["pd", "default", "--micro-doppler", "--micro-doppler-dwell-s", "0.001", "--range-m", "100"]) == 2
    assert "micro_doppler.dwell_s" in capsys.readouterr().err
