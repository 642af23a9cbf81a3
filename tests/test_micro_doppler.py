"""Rotor micro-Doppler: the closed form of rotating blades and the PO field of rotating meshes.

References: the blade line integral summed numerically (midpoint rule) for Eq. MD-1; the flash
period and line spacings written out from Chen et al., IEEE TAES 42(1), 2006, Sec. V; the PO field of
flat rectangular blades, which equals Eq. MD-1a times ``w sin(beta)`` exactly.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core import micro_doppler as md
from csuas.render.rcs.micro_doppler import drone_rotors, micro_doppler, rotor_field, spectrum_m2
from csuas.validation.report.checks_micro_doppler import flash_period_s, straight_blade_rotor, time_mean_rcs_m2

C = 299_792_458.0


def test_blade_signal_is_the_line_integral_along_each_blade():
    wavelength = C / 10e9
    t = np.linspace(0.0, 0.01, 7)
    length, beta, rate = 0.076, math.radians(20.0), 100.0
    r = (np.arange(20_000) + 0.5) * length / 20_000
    expected = np.zeros(len(t), complex)
    for k in range(3):
        theta = 2 * np.pi * rate * t + 2 * np.pi * k / 3
        phase = 4 * np.pi / wavelength * np.cos(beta) * np.cos(theta)[:, None] * r[None, :]
        expected += np.exp(1j * phase).sum(axis=1) * length / len(r)
    got = md.rotor_blade_signal(t, length, 3, rate, 10.0, 20.0)
    assert np.max(np.abs(got - expected)) < 1e-7 * length


def test_flash_period_line_spacing_and_tip_doppler_closed_forms():
    assert md.blade_flash_period_s(2, 100.0) == pytest.approx(1 / 200)
    assert md.blade_flash_period_s(3, 100.0) == pytest.approx(1 / 600)
    assert md.blade_flash_period_s(3, -100.0) == pytest.approx(1 / 600)
    assert md.line_spacing_hz(2, 100.0) == pytest.approx(200.0)
    assert md.line_spacing_hz(3, 100.0) == pytest.approx(300.0)
    tip = 2 * (2 * np.pi * 0.076 * 100.0) * math.cos(math.radians(20.0)) / (C / 10e9)
    assert md.max_tip_doppler_hz(0.076, 100.0, 10.0, 20.0) == pytest.approx(tip, rel=1e-12)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: md.blade_flash_period_s(2.5, 100.0), "n_blades"),
        (lambda: md.line_spacing_hz(2, 0.0), "rotation_rate_hz"),
        (lambda: md.rotor_blade_signal(0.0, -1.0, 2, 100.0, 10.0), "blade_length_m"),
        (lambda: md.rotor_blade_signal(0.0, 0.1, 2, 100.0, 10.0, elevation_deg=95.0), "elevation_deg"),
        (lambda: md.max_tip_doppler_hz(0.1, 100.0, float("nan")), "frequency_ghz"),
    ],
)
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ParameterError) as info:
        call()
    assert info.value.name == name


@pytest.mark.parametrize("n_blades", [2, 3])
def test_po_of_rotating_flat_blades_is_the_closed_form(n_blades):
    chord, beta, rate, prf = 0.0015, 20.0, 100.0, 60_000.0
    t = np.arange(600) / prf
    po = rotor_field(straight_blade_rotor(0.076, chord, n_blades), rate, t, 10.0, 0.0, beta)
    exact = (
        math.sin(math.radians(beta)) * chord * md.rotor_blade_signal(t, 0.076, n_blades, rate, 10.0, beta, 0.0, chord)
    )
    assert np.max(np.abs(po - exact)) < 1e-9 * np.max(np.abs(exact))
    assert flash_period_s(t, po) == pytest.approx(md.blade_flash_period_s(n_blades, rate), abs=1 / prf)
    # time-mean RCS over one turn (600 samples at 60 kHz, 100 rev/s) against quadrature of the closed form
    time_mean = np.mean(np.abs(po) ** 2) * 4 * np.pi / (C / 10e9) ** 2
    assert time_mean == pytest.approx(time_mean_rcs_m2(n_blades, chord), rel=1e-9)


def test_three_blades_iq_lines_at_n_omega_power_lines_at_twice():
    t = np.arange(3000) / 60_000.0  # five turns at 100 rev/s
    s = md.rotor_blade_signal(t, 0.076, 3, 100.0, 10.0, 20.0)
    bins, power = spectrum_m2(s, "rectangular")
    frequency = bins * 60_000.0 / len(t)
    strong = frequency[(power > 1e-9 * power.max()) & (frequency > 0)]
    assert strong.min() == pytest.approx(300.0)
    assert np.allclose(strong % 300.0, 0.0)
    assert 0 < (np.isclose(strong % 600.0, 300.0)).sum()  # odd multiples of N Omega carry lines too
    bins, envelope = spectrum_m2(np.abs(s) ** 2, "rectangular")
    frequency = bins * 60_000.0 / len(t)
    assert frequency[(envelope > 1e-9 * envelope.max()) & (frequency > 0)].min() == pytest.approx(600.0)


def test_mini_4_pro_rotors_are_four_two_blade_rotors_with_both_spins():
    rotors, body = drone_rotors("dji_mini_4_pro")
    assert len(rotors) == 4 and all(r.n_blades == 2 for r in rotors)
    assert sorted(r.spin for r in rotors) == [-1, -1, 1, 1]
    tip = math.hypot(6 * 0.0254 / 2, 0.010 / 2)  # radius and half the tip chord (presets.py, multirotor.py)
    assert all(r.tip_radius_m == pytest.approx(tip, rel=1e-9) for r in rotors)
    assert all(p.kind != "propeller" for p in body.parts)


def test_prf_below_twice_the_tip_doppler_is_refused():
    with pytest.raises(ParameterError) as info:
        micro_doppler("dji_mini_4_pro", 10.0, 4000.0, 0.01)
    assert info.value.name == "prf_hz"


def test_mini_4_pro_spectrum_has_lines_only_at_multiples_of_n_omega():
    result = micro_doppler("dji_mini_4_pro", 10.0, 10_000.0, 0.02, 6000.0, (30.0, 15.0), "rectangular")
    assert result.line_spacing_hz == pytest.approx(200.0) and not result.aliased
    blades = np.where(result.frequency_hz == 0.0, 0.0, result.spectrum_m2)
    off = ~np.isclose(np.mod(result.frequency_hz, 200.0), 0.0) & ~np.isclose(np.mod(result.frequency_hz, 200.0), 200.0)
    assert blades[off].sum() < 1e-9 * blades.sum()
    parseval = np.mean(np.abs(result.field_m) ** 2) * 4 * np.pi / (C / 10e9) ** 2  # rectangular window
    assert result.spectrum_m2.sum() == pytest.approx(parseval, rel=1e-9)


def test_cli_writes_the_json_and_png_and_refuses_an_aliasing_prf(tmp_path, capsys):
    from csuas import cli

    out = tmp_path / "md"
    code = cli.main(["micro-doppler", "dji_mini_4_pro", "--out", str(out), "--dwell-s", "0.02", "--json"])
    printed = json.loads(capsys.readouterr().out)
    written = json.loads((out / "micro_doppler.json").read_text())
    assert code == 0 and (out / "micro_doppler.png").stat().st_size > 0
    assert printed["line_spacing_hz"] == written["line_spacing_hz"] == pytest.approx(200.0)
    assert written["flash_period_s"] == pytest.approx(0.005) and not written["aliased"]
    assert len(written["spectrum"]["frequency_hz"]) == 400  # 20 kHz x 0.02 s
    assert cli.main(["micro-doppler", "dji_mini_4_pro", "--out", str(tmp_path / "x"), "--prf-hz", "3000"]) == 2
    assert "prf_hz" in capsys.readouterr().err and not (tmp_path / "x").exists()
    code = cli.main(["micro-doppler", "dji_mini_4_pro", "--out", str(tmp_path / "y"), "--rpm", "-5", "--dwell-s", "0"])
    err = capsys.readouterr().err
    assert code == 2 and "rpm" in err and "dwell_s" in err


def test_cost_estimate_is_samples_times_blade_facets_and_refuses_before_making_out(tmp_path, capsys):
    from csuas import cli
    from csuas.render.rcs import micro_doppler as module

    plan = module.plan_micro_doppler("dji_mini_4_pro", 10.0, 200_000.0, 10.0)  # 2e6 samples x 480 facets
    estimate = module.estimate_cost(plan)
    blades = 2_000_000 * 480 * module.SECONDS_PER_SAMPLE_FACET
    assert plan.samples == 2_000_000 and blades < estimate.seconds < blades + module.OVERHEAD_SECONDS + 1.0
    out = tmp_path / "long"
    argv = ["micro-doppler", "dji_mini_4_pro", "--out", str(out), "--prf-hz", "200000", "--dwell-s", "10"]
    assert cli.main(argv) == 2  # 960 s of blades above the default 600 s
    err = capsys.readouterr().err
    assert "max_seconds" in err and "2,000,000 samples x 480 blade facets" in err and not out.exists()
    assert cli.main([*argv, "--max-seconds", "1e9", "--max-memory-gb", "1e-3"]) == 2
    assert "max_memory_gb" in capsys.readouterr().err and not out.exists()
