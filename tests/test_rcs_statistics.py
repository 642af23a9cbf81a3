"""RCS statistics over aspects (core.rcs_statistics) against samples of known distributions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core.radar_detection import pd_exact
from csuas.core.rcs_statistics import (
    aspect_chi_square_dof,
    fit_chi_square,
    fit_lognormal,
    pd_chi_square_target,
    pd_over_rcs_samples,
    rcs_summary,
)


@pytest.mark.parametrize("k", [0.5, 1.0, 2.0, 5.0])
def test_chi_square_fit_recovers_the_gamma_shape(k):
    rng = np.random.default_rng(int(10 * k))
    samples = rng.gamma(k, 0.01 / k, 40_000)
    fit = fit_chi_square(samples)
    # the MLE's relative standard deviation is at most sqrt(2 / n) (large k) and below it for k <= 5
    assert fit["k"] == pytest.approx(k, rel=4 * math.sqrt(2.0 / 40_000))
    assert fit["dof"] == pytest.approx(2 * fit["k"])
    assert fit["nearest_swerling_scan"] == (1 if k <= 1.0 else 3)
    assert fit["log_likelihood_ratio"] >= 0.0


def test_lognormal_fit_and_summary():
    rng = np.random.default_rng(1)
    db = rng.normal(-12.81, 3.74, 50_000)  # 3GPP TR 38.901 small UAV
    fit = fit_lognormal(10 ** (db / 10))
    assert fit["mean_dbsm"] == pytest.approx(-12.81, abs=4 * 3.74 / math.sqrt(50_000))
    assert fit["std_db"] == pytest.approx(3.74, rel=0.02)
    summary = rcs_summary(10 ** (db / 10))
    assert summary["median_dbsm"] == pytest.approx(-12.81, abs=0.1)
    assert summary["p10_dbsm"] == pytest.approx(-12.81 - 1.2816 * 3.74, abs=0.15)
    sigma_ln = 3.74 * math.log(10) / 10  # mean of a log-normal: exp(mu + s^2 / 2)
    assert summary["mean_dbsm"] == pytest.approx(-12.81 + 10 * math.log10(math.exp(sigma_ln**2 / 2)), abs=0.1)


def test_pd_over_exponential_samples_is_swerling_1():
    """Samples of an exponential RCS give, in the limit, the Swerling 1 Pd with the same mean."""
    n = 20_000
    samples = -np.log(1 - (np.arange(n) + 0.5) / n)  # exponential quantiles: a low-noise sample
    snr = np.array([5.0, 13.0, 21.0])
    np.testing.assert_allclose(pd_over_rcs_samples(snr, samples, 1e-6), pd_exact(snr, 1e-6, 1, 1), atol=2e-3)


def test_pd_over_constant_samples_is_the_steady_pd():
    samples = np.full(16, 0.01)
    np.testing.assert_allclose(pd_over_rcs_samples([3.0, 10.0], samples, 1e-4, 8), pd_exact([3.0, 10.0], 1e-4, 8, 0))
    assert fit_chi_square(samples)["k"] == np.inf


def test_bad_samples():
    with pytest.raises(ParameterError, match="rcs_m2"):
        rcs_summary([0.01, 0.02])
    with pytest.raises(ParameterError, match="rcs_m2"):
        fit_lognormal(np.r_[np.ones(10), -1.0])


@pytest.mark.parametrize(("dof", "swerling"), [(2.0, 1), (4.0, 3)])
@pytest.mark.parametrize(("n_pulses", "integration"), [(1, "noncoherent"), (10, "noncoherent"), (10, "coherent")])
def test_chi_square_target_pd_is_swerling_1_and_3_at_2_and_4_dof(dof, swerling, n_pulses, integration):
    snr = np.linspace(-10.0, 30.0, 41)
    pd = pd_chi_square_target(snr, 1e-6, n_pulses, dof, integration)
    assert pd == pytest.approx(pd_exact(snr, 1e-6, n_pulses, swerling, integration), abs=1e-6)


def test_chi_square_target_pd_heavier_tail_needs_more_snr_and_is_monotone():
    snr = np.linspace(0.0, 40.0, 81)
    heavy, swerling_1 = pd_chi_square_target(snr, 1e-6, 1, 1.0), pd_exact(snr, 1e-6, 1, 1)
    assert np.all(np.diff(heavy) >= -1e-12) and heavy[-1] > 0.9
    assert np.all(heavy[snr > 20] < swerling_1[snr > 20])  # a dof < 2 tail misses more often at high SNR
    with pytest.raises(ParameterError, match="dof"):
        pd_chi_square_target(10.0, 1e-6, 1, 0.0)


def test_shipped_drone_table_covers_every_preset_band_and_polarisation():
    from csuas.defaults import load_drone_rcs_statistics
    from csuas.drone_models.presets import list_presets
    from csuas.validation.rcs.statistics_table import BANDS_GHZ

    rows = load_drone_rcs_statistics()
    keys = {(r["preset"], r["frequency_ghz"], r["polarisation"]) for r in rows}
    assert keys == {(p, f, pol) for p in list_presets() for f in BANDS_GHZ for pol in ("VV", "HH")}
    for r in rows:
        assert r["p10_dbsm"] <= r["median_dbsm"] <= r["p90_dbsm"]
        assert 0.0 < r["mean_error_db"] < 3.0 and r["chi2_dof"] > 0.0 and r["aspects"] >= 256
    dof, band = aspect_chi_square_dof("dji_mini_4_pro", 23.98, "VV")
    row = next(r for r in rows if r["preset"] == "dji_mini_4_pro" and r["frequency_ghz"] == 24.0)
    assert band == 24.0 and dof == row["chi2_dof"] if row["polarisation"] == "VV" else True
    assert aspect_chi_square_dof("dji_mini_4_pro", 3.0, "HH")[1] == 2.4  # nearest in log-frequency
    with pytest.raises(ParameterError, match="target preset"):
        aspect_chi_square_dof("no_such_drone", 10.0)


@pytest.mark.slow
def test_rcs_statistics_command_writes_a_table_the_loader_reads(tmp_path, capsys):
    import csv

    from csuas import cli

    out = tmp_path / "table.csv"
    code = cli.main(
        [
            "rcs-statistics",
            "--presets",
            "black_hornet_3",
            "--bands-ghz",
            "2.4",
            "--quality",
            "draft",
            "--accuracy-db",
            "2",
            "--out",
            str(out),
            "--json",
        ]
    )
    assert code == 0
    rows = list(csv.DictReader(line for line in out.read_text().splitlines() if not line.startswith("#")))
    assert [(r["preset"], r["frequency_ghz"], r["polarisation"]) for r in rows] == [
        ("black_hornet_3", "2.4000", "VV"),
        ("black_hornet_3", "2.4000", "HH"),
    ]
    assert all(float(r["mean_error_db"]) <= 2.0 for r in rows)
    assert "bands" in capsys.readouterr().err  # progress with an ETA
    assert cli.main(["rcs-statistics", "--bands-ghz", "0", "--accuracy-db", "0", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "bands_ghz" in err and "accuracy_db" in err


def test_radar_pd_with_the_aspect_fluctuation_uses_the_tables_chi_square(tmp_path):
    from csuas.core.pd_curves import sensor_pd
    from csuas.core.scenario import load_scenario

    path = tmp_path / "s.toml"
    path.write_text(
        'name = "a"\n[target]\n[environment]\n[sensors.radar]\nmodality = "radar"\nfluctuation = "aspect_hh"\n'
    )
    scenario = load_scenario(path)
    curve = sensor_pd(scenario, "radar", [10.0, 30.0, 47.0, 80.0])
    dof, band = aspect_chi_square_dof("dji_mini_4_pro", 23.98, "HH")
    assert band == 24.0 and any(f"{dof:.3g} degrees of freedom" in a for a in curve.assumptions)
