"""Aspect sweeps, Eq. 6 sphere average, polar plots, default checks, convergence rule and benchmarks."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from csuas.base.checks import Check
from csuas.base.errors import InputErrors, ParameterError
from csuas.render.rcs import canonical
from csuas.render.rcs.convergence import ERROR_COEFFICIENT_DB, density_for_accuracy, silhouette_perimeter_area
from csuas.render.rcs.sweep import aspect_sweep, band_sweep, plot_polar, sphere_average
from csuas.validation.rcs.convergence import convergence_curve, preset_errors

C = 299_792_458.0


def test_sphere_average_of_an_isotropic_target_equals_its_rcs():
    """A sphere's RCS is the same from every aspect, so Eq. 6 returns it after the first batch."""
    ka, a = 30.0, 0.1
    f_ghz = ka * C / (2 * math.pi * a) / 1e9
    avg = sphere_average(canonical.sphere(a, 5), f_ghz, rays_per_wavelength=4)
    assert avg["mean_m2"][0] == pytest.approx(math.pi * a * a, rel=0.12)  # optical limit, |PO - exact| < 0.3 dB
    assert avg["std_of_dbsm"][0] < 0.1
    assert avg["converged"] and avg["error_db"][0] < 0.05
    # one batch: 8 rotated lattices of 16 aspects and as many drawn around the facets' normals
    assert avg["n_aspects"] == 256 and avg["samples_m2"]["VV"].shape == (1, 128)


def _plate_sphere_mean_m2(a_m, f_ghz):
    """Eq. 6 of a square plate's PO RCS (closed form, both sides) by a dense Gauss-Legendre x trapezoid rule.

    sigma = 4 pi A^2 cos^2(t) / lambda^2 * sinc^2(k a u) * sinc^2(k a v), with (u, v, cos t) the
    direction's components (Knott et al., ch. 5; docs/validation.md).
    """
    lam = C / (f_ghz * 1e9)
    k = 2 * math.pi / lam
    mu, w = np.polynomial.legendre.leggauss(2000)  # mu = cos(t), the component along the normal
    phi = (np.arange(2000) + 0.5) * 2 * math.pi / 2000
    sin_t = np.sqrt(1 - mu**2)[:, None]
    u, v = sin_t * np.cos(phi)[None, :], sin_t * np.sin(phi)[None, :]
    sigma = 4 * math.pi * a_m**4 * mu[:, None] ** 2 / lam**2 * np.sinc(k * a_m * u / math.pi) ** 2
    sigma *= np.sinc(k * a_m * v / math.pi) ** 2
    return float((sigma.mean(axis=1) * w).sum() / 2)


@pytest.mark.slow
def test_sphere_average_of_a_plate_meets_its_accuracy():
    """A plate's RCS is one narrow flash per side: the adaptive average keeps adding aspects until the
    95 % bound meets the request, and the bound holds against a dense quadrature of the plate's PO
    closed form (about A/2 by Parseval's theorem for a two-sided plate, 0.005 m^2 here)."""
    exact = _plate_sphere_mean_m2(0.1, 10.0)
    assert exact == pytest.approx(0.01 / 2, rel=0.1)
    avg = sphere_average(canonical.plate(0.1), 10.0, accuracy_db=1.0, rays_per_wavelength=4)
    assert avg["converged"] and avg["error_db"][0] <= 1.0 and avg["n_aspects"] > 256
    assert abs(10 * np.log10(avg["mean_m2"][0] / exact)) <= avg["error_db"][0]


def test_sphere_average_refuses_bad_settings_all_at_once():
    with pytest.raises(InputErrors) as caught:
        sphere_average(canonical.plate(0.1), 10.0, accuracy_db=0.0, replicates=1, aspects_per_replicate=2)
    text = str(caught.value)
    assert "accuracy_db" in text and "replicates" in text and "aspects_per_replicate" in text
    with pytest.raises(InputErrors, match="max_aspects"):
        sphere_average(canonical.plate(0.1), 10.0, max_aspects=10)


def test_aspect_sweep_and_polar_plot(tmp_path):
    az = np.arange(0.0, 360.0, 10.0)
    cut = aspect_sweep(canonical.cylinder(0.05, 0.3), 10.0, az, 0.0, rays_per_wavelength=6)
    vv = cut["rcs_dbsm"]["VV"][0]
    exact = 10 * math.log10(2 * math.pi * 0.05 * 0.09 / (C / 10e9))
    assert np.all(np.abs(vv - exact) < 0.7)  # a cylinder is round in azimuth
    assert cut["error_db"]["VV"].shape == (1, len(az))
    out = plot_polar(az, {"VV": vv, "HH": cut["rcs_dbsm"]["HH"][0]}, tmp_path / "polar.png", title="cylinder")
    data = (tmp_path / "polar.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and out == tmp_path / "polar.png"
    assert [p.name for p in tmp_path.iterdir()] == ["polar.png"]  # no temporary file left


@pytest.mark.slow
def test_band_sweep_of_the_drone_at_two_bands():
    sweep = band_sweep("dji_mini_4_pro", (2.4, 35.0), accuracy_db=3.0, cut_step_deg=30.0, quality="draft")
    assert [b["frequency_ghz"] for b in sweep] == [2.4, 35.0]
    for band in sweep:
        assert np.isfinite(band["mean_dbsm"]) and -45.0 < band["mean_dbsm"] < 0.0
        assert len(band["azimuth_cut"]["rcs_dbsm"]["VV"]) == 12
        assert len(band["elevation_cut"]["rcs_dbsm"]["HH"]) == 7
        assert band["time_s"] > 0 and band["rays"] > 0


@pytest.mark.slow
def test_default_checks_compare_the_drone_with_table8_and_3gpp():
    checks = __import__("csuas.validation.rcs.checks", fromlist=["default_checks"]).default_checks({"accuracy_db": 3.0})
    assert [c.name for c in checks] == [
        "rcs.dji_mini_4_pro.mean_dbsm.table8",
        "rcs.dji_mini_4_pro.mean_of_dbsm.3gpp_tr38901",
    ]
    assert all(isinstance(c, Check) and math.isfinite(c.measured) for c in checks)
    assert checks[0].expected == pytest.approx(-20.0) and checks[1].expected == pytest.approx(-12.81)
    for c in checks:
        note = c.known_deviation or c.limitation
        assert c.ok or (note and f"{abs(c.measured - c.expected):.1f} dB" in note)
        assert c.as_dict()["rays_per_wavelength"] == 2.0 and c.as_dict()["error_db"] <= 3.0


def test_convergence_follows_the_perimeter_rule():
    curve = convergence_curve((1, 4, 16), trials=16)
    err = [c["mean_abs_error_db"] for c in curve]
    assert err[0] > err[1] > err[2]
    for c in curve:  # rule (1) within a factor 2 either way
        assert 0.5 * c["model_error_db"] < c["mean_abs_error_db"] < 2.0 * c["model_error_db"]
        assert c["time_s"] > 0 and c["tubes"] > 0
    random = convergence_curve((4,), trials=16, orientation="random")
    assert random[0]["mean_abs_error_db"] < err[1]  # rotated grids err less: the rule is conservative


def test_density_rule():
    lam = C / 10e9
    n = density_for_accuracy(0.1, 0.4, 0.01, 10.0)
    assert n == pytest.approx(ERROR_COEFFICIENT_DB * 0.4 * lam / (0.01 * 0.1))
    assert density_for_accuracy(100.0, 0.4, 0.01, 10.0) == 1.0
    with pytest.raises(ParameterError, match="error_db"):
        density_for_accuracy(0.0, 0.4, 0.01, 10.0)
    perimeter, area = silhouette_perimeter_area(canonical.plate(0.1), 0.0, 90.0)
    assert perimeter == pytest.approx(0.4) and area == pytest.approx(0.01)
    p_box, a_box = silhouette_perimeter_area(trimesh.creation.box(extents=(0.1, 0.2, 0.3)), 0.0, 0.0)
    assert p_box == pytest.approx(1.0) and a_box == pytest.approx(0.06)


@pytest.mark.slow
def test_quality_presets_measured_error_ordering():
    errors = preset_errors(["draft", "reference"])
    assert errors["reference"]["mean_abs_error_db"] < errors["draft"]["mean_abs_error_db"]
    assert errors["reference"]["max_abs_error_db"] < 0.6
    assert errors["reference"]["cases"].keys() == errors["draft"]["cases"].keys()


def test_bench_returns_throughputs():
    from csuas.validation.rcs.bench import bench_sbr

    out = bench_sbr(
        canonical.dihedral(0.1, 0.15),
        frequency_ghz=10.0,
        rays_per_wavelength=8,
        n_aspects=4,
        raw_rays=1 << 14,
        repeats=1,
    )
    for key in (
        "sbr_rays_x_bounces_per_s",
        "ray_intersect_rays_per_s",
        "ray_intersect_preliminary_rays_per_s",
        "ratio_sbr_to_ray_intersect",
    ):
        assert out[key] > 0 and math.isfinite(out[key])
