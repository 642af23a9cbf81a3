"""``csuas rcs``: JSON keys of SPEC 8, mesh files, presets, plots and one-line errors."""

from __future__ import annotations

import json
import math

import pytest

from csuas.cli import main
from csuas.render.rcs import canonical

C = 299_792_458.0


def run_cli(capsys, *argv):
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_rcs_of_a_mesh_file_json(tmp_path, capsys):
    path = tmp_path / "plate.ply"
    canonical.plate(0.1).export(path)
    code, out, _ = run_cli(capsys, "rcs", str(path), "--frequency-ghz", "10", "--elevation-deg", "90",
                           "--rays-per-wavelength", "10", "--json")
    assert code == 0
    data = json.loads(out)
    for key in ("rcs_m2", "rcs_dbsm", "rays", "time_s", "polarisation", "error_db", "bounces",
                "rcs_m2_by_polarisation", "rays_x_bounces_per_s"):
        assert key in data
    exact = 4 * math.pi * 0.01 ** 2 / (C / 10e9) ** 2
    assert data["rcs_dbsm"] == pytest.approx(10 * math.log10(exact), abs=0.3)
    assert data["rcs_m2"] == pytest.approx(data["rcs_m2_by_polarisation"]["VV"])
    assert data["rays"] > 0 and data["materials"] == ["pec"]
    assert data["bounces"]["max_reached"] == 1


def test_rcs_of_a_drone_preset_with_plot_and_text(tmp_path, capsys):
    png = tmp_path / "cut.png"
    code, out, _ = run_cli(capsys, "rcs", "dji_mini_4_pro", "--frequency-ghz", "12", "--azimuth-deg", "30",
                           "--elevation-deg", "-10", "--quality", "draft", "--no-error-estimate",
                           "--plot", str(png))
    assert code == 0
    assert "dBsm" in out and "dji_mini_4_pro" in out
    assert png.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("argv, name", [
    (["--frequency-ghz", "-3"], "frequency_ghz"),
    (["--frequency-ghz", "10", "--rays-per-wavelength", "0.5"], "rays_per_wavelength"),
    (["--frequency-ghz", "10", "--material", "kryptonite"], "material"),
    (["--frequency-ghz", "10", "--max-bounces", "0"], "max_bounces"),
    (["--frequency-ghz", "10", "--elevation-deg", "120"], "elevation_deg"),
])
def test_bad_input_is_one_line_and_exit_code_2(tmp_path, capsys, argv, name):
    path = tmp_path / "plate.stl"
    canonical.plate(0.1).export(path)
    code, out, err = run_cli(capsys, "rcs", str(path), *argv)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and name in err and "Traceback" not in err


def test_unknown_preset_or_missing_file(capsys):
    code, _, err = run_cli(capsys, "rcs", "no_such_drone", "--frequency-ghz", "10")
    assert code == 2 and "dji_mini_4_pro" in err
