"""``csuas rcs``: JSON keys of docs/command-line.md, mesh files, presets, plots and one-line errors."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas.cli import main
from csuas.render.rcs import canonical, model_error

C = 299_792_458.0


def run_cli(capsys, *argv):
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_rcs_of_a_mesh_file_json(tmp_path, capsys):
    path = tmp_path / "plate.ply"
    canonical.plate(0.1).export(path)
    code, out, _ = run_cli(
        capsys,
        "rcs",
        str(path),
        "--frequency-ghz",
        "10",
        "--elevation-deg",
        "90",
        "--rays-per-wavelength",
        "10",
        "--json",
    )
    assert code == 0
    data = json.loads(out)
    for key in (
        "rcs_m2",
        "rcs_dbsm",
        "rays",
        "time_s",
        "polarisation",
        "error_db",
        "bounces",
        "rcs_m2_by_polarisation",
        "rays_x_bounces_per_s",
    ):
        assert key in data
    exact = 4 * math.pi * 0.01**2 / (C / 10e9) ** 2
    assert data["rcs_dbsm"] == pytest.approx(10 * math.log10(exact), abs=0.3)
    assert data["rcs_m2"] == pytest.approx(data["rcs_m2_by_polarisation"]["VV"])
    assert data["rays"] > 0 and data["materials"] == ["pec"]
    assert data["bounces"]["max_reached"] == 1
    # the bound against the exact answer: discretisation and PO's model term 1.5/(k a), a = half the diagonal
    bound = data["error_bound"]
    ka = 2 * math.pi / (C / 10e9) * 0.1 / math.sqrt(2)
    assert bound["model_ka"] == pytest.approx(ka, rel=1e-6)
    assert bound["model_db"] == pytest.approx(-20 * math.log10(1 - 1.5 / ka), rel=1e-6)
    assert bound["truncation_db"] == 0.0  # one bounce and out: nothing truncated
    # PO's floor sqrt(K lambda^2 / sigma) on the computed RCS (K = 0.1 of render/rcs/model_error.py)
    floor = math.sqrt(model_error.PO_FLOOR_COEFFICIENT * (C / 10e9) ** 2 / data["rcs_m2"])
    assert bound["model_floor_db"] == pytest.approx(-20 * math.log10(1 - floor), rel=1e-6)
    e_total = 1.5 / ka + floor + 1 - 10 ** (-bound["discretisation_db"] / 20)
    assert data["error_db"] == bound["total_db"] == pytest.approx(-20 * math.log10(1 - e_total), rel=1e-6)


def test_rcs_of_a_drone_preset_with_plot_and_text(tmp_path, capsys):
    png = tmp_path / "cut.png"
    code, out, _ = run_cli(
        capsys,
        "rcs",
        "dji_mini_4_pro",
        "--frequency-ghz",
        "12",
        "--azimuth-deg",
        "30",
        "--elevation-deg",
        "-10",
        "--quality",
        "draft",
        "--no-error-estimate",
        "--plot",
        str(png),
    )
    assert code == 0
    assert "dBsm" in out and "dji_mini_4_pro" in out
    assert png.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize(
    "argv, name",
    [
        (["--frequency-ghz", "-3"], "frequency_ghz"),
        (["--frequency-ghz", "10", "--rays-per-wavelength", "0.5"], "rays_per_wavelength"),
        (["--frequency-ghz", "10", "--material", "kryptonite"], "material"),
        (["--frequency-ghz", "10", "--max-bounces", "0"], "max_bounces"),
        (["--frequency-ghz", "10", "--elevation-deg", "120"], "elevation_deg"),
        (["--frequency-ghz", "10", "--truncation-fraction", "1.5"], "truncation_fraction"),
    ],
)
def test_bad_input_is_one_line_and_exit_code_2(tmp_path, capsys, argv, name):
    path = tmp_path / "plate.stl"
    canonical.plate(0.1).export(path)
    code, out, err = run_cli(capsys, "rcs", str(path), *argv)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and name in err and "Traceback" not in err


def test_unknown_preset_or_missing_file(capsys):
    code, _, err = run_cli(capsys, "rcs", "no_such_drone", "--frequency-ghz", "10")
    assert code == 2 and "dji_mini_4_pro" in err


def test_bistatic_plate_from_the_cli(tmp_path, capsys):
    """Normal incidence, receiver 5 deg off the normal: H-pol PO (4 pi A^2/lambda^2) sinc^2(k a sin t / 2)."""
    path = tmp_path / "plate.obj"
    canonical.plate(0.1).export(path)
    code, out, _ = run_cli(
        capsys,
        "rcs",
        str(path),
        "--frequency-ghz",
        "10",
        "--elevation-deg",
        "90",
        "--observe-azimuth-deg",
        "0",
        "--observe-elevation-deg",
        "85",
        "--polarisation",
        "HH",
        "--json",
    )
    data = json.loads(out)
    k = 2 * math.pi / (C / 10e9)
    u = 0.5 * k * 0.1 * math.sin(math.radians(5.0))
    exact = 4 * math.pi * 0.01**2 / (C / 10e9) ** 2 * (math.sin(u) / u) ** 2
    assert code == 0 and data["geometry"] == "bistatic"
    assert data["rcs_dbsm"] == pytest.approx(10 * math.log10(exact), abs=0.4)


def test_rcs_table_grid_for_link_simulators():
    from csuas.render.rcs.sweep import rcs_table

    table = rcs_table(
        canonical.cylinder(0.05, 0.3),
        10.0,
        [0.0, 90.0, 180.0],
        [-10.0, 0.0],
        rays_per_wavelength=6,
        error_estimate=False,
    )
    assert table["rcs_m2"].shape == (3, 2) and table["error_db"] is None
    broadside = 2 * math.pi * 0.05 * 0.09 / (C / 10e9)
    assert 10 * np.log10(table["rcs_m2"][:, 1]) == pytest.approx(np.full(3, 10 * math.log10(broadside)), abs=0.7)
    assert np.all(table["rcs_m2"][:, 0] < table["rcs_m2"][:, 1])  # broadside is the maximum


def test_truncation_fraction_raises_the_bounce_limit_until_the_corner_is_complete(tmp_path, capsys):
    """Square trihedral on its axis: its return needs three bounces, 12 pi a^4 / lambda^2 (Knott et al. ch. 5)."""
    path = tmp_path / "corner.ply"
    canonical.trihedral(0.1).export(path)
    el = math.degrees(math.asin(1 / math.sqrt(3)))
    argv = ["rcs", str(path), "--frequency-ghz", "10", "--azimuth-deg", "45", "--elevation-deg", str(el)]
    code, out, _ = run_cli(capsys, *argv, "--max-bounces", "2", "--json")
    data = json.loads(out)
    assert data["error_db"] is None and data["error_bound"]["truncation_db"] is None
    assert any("bounce limit (2)" in w for w in data["warnings"])
    code, out, _ = run_cli(capsys, *argv, "--max-bounces", "1", "--truncation-fraction", "0.01", "--json")
    data = json.loads(out)
    assert code == 0 and [t["max_bounces"] for t in data["bounces_tried"]] == [1, 2, 3]
    assert data["bounces_tried"][-1]["truncated_fraction"] == 0.0 and data["max_bounces"] == 3
    exact = 12 * math.pi * 0.1**4 / (C / 10e9) ** 2
    assert abs(data["rcs_dbsm"] - 10 * math.log10(exact)) <= data["error_db"]


def test_edge_diffraction_adds_its_residual_term_to_the_bound(tmp_path, capsys):
    """A 0.1 m plate at normal incidence: four broadside rim edges (V's H along two, its E along the other
    two) and four corners give the edge term by hand (render/rcs/edge_residual.py)."""
    from csuas.render.rcs.edge_residual import C_CORNER, C_HARD, C_SOFT

    path = tmp_path / "plate.ply"
    canonical.plate(0.1).export(path)
    argv = ("rcs", str(path), "--frequency-ghz", "10", "--elevation-deg", "90", "--rays-per-wavelength", "10")
    code, out, _ = run_cli(capsys, *argv, "--edge-diffraction", "--json")
    assert code == 0
    data = json.loads(out)
    k = 2 * math.pi * 10e9 / C
    residual = (C_HARD + C_SOFT) * 2 * 0.1 / (4 * math.pi) + C_CORNER * 4 / (4 * math.pi * k)
    e_edge = residual / math.sqrt(data["rcs_m2"] / (4 * math.pi))
    bound = data["error_bound"]
    assert bound["edge_residual_db"] == pytest.approx(-20 * math.log10(1 - e_edge), rel=1e-6)
    terms = ("discretisation_db", "model_db", "model_floor_db", "truncation_db")
    e_total = sum(1 - 10 ** (-bound[key] / 20) for key in terms)
    assert data["error_db"] == pytest.approx(-20 * math.log10(1 - e_total - e_edge), rel=1e-6)
    code, out, _ = run_cli(capsys, *argv, "--json")
    assert json.loads(out)["error_bound"]["edge_residual_db"] is None
