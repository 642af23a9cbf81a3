"""``csuas render eo|tir``: JSON keys of docs/command-line.md, EXR metadata, PNG previews, errors, lazy imports."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from csuas.cli import main

pytestmark = pytest.mark.slow


def run_cli(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_render_eo_json_and_files(tmp_path, capsys):
    import OpenEXR

    code, out, err = run_cli(
        capsys,
        "render",
        "eo",
        "default",
        "--range-m",
        "300",
        "2000",
        "--quality",
        "draft",
        "--out",
        str(tmp_path),
        "--json",
    )
    assert code == 0
    data = json.loads(out)
    assert [r["range_m"] for r in data["results"]] == [300.0, 2000.0]
    for row in data["results"]:
        for key in ("pixels_on_target", "pixels_across_dcrit", "contrast", "stderr", "time_s", "files"):
            assert key in row
        assert row["stderr"]["pixels_on_target"] >= 0
        # the EO range applies Kruse's clear-air extinction at 10 km visibility (3.912 / 10 km, Eq. 12, at 550 nm),
        # read in dB by the default scenario's paper convention (Eq. 10): so does the render
        assert [t["name"] for t in row["terms"]] == [
            "kruse_extinction",
            "extinction_per_km",
            "transmittance",
            "airlight",
        ]
        assert row["convention"] == "paper" and row["terms"][0]["unit"] == "dB/km"
        assert row["terms"][0]["value"] == pytest.approx(-np.log(0.02) / 10.0, rel=1e-12)
        tau = 10.0 ** (-(-np.log(0.02) / 10.0) * row["range_m"] / 1e4)
        assert row["terms"][2]["value"] == pytest.approx(tau, rel=1e-12)
        exr, png = row["files"]
        assert exr.endswith(".exr") and png.endswith(".png")
        with OpenEXR.File(exr, separate_channels=True) as f:
            header, channels = f.header(), f.channels()
            assert header["csuas_range_m"] == row["range_m"]
            assert header["csuas_ifov_rad"] == pytest.approx(np.radians(10.0) / 1920)
            assert header["csuas_modality"] == "eo" and header["csuas_units"] == "cd m^-2"
            assert set(channels) == {"R", "G", "B", "A"}
            assert channels["R"].pixels.dtype == np.float32
            assert channels["A"].pixels.sum() == pytest.approx(row["pixels_on_target"], rel=1e-5)
        with open(png, "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert "render eo 300 m" in err  # progress on stderr
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary files left


def test_render_convention_overrides_the_scenarios_as_range_does(capsys):
    code, out, _ = run_cli(
        capsys,
        "render",
        "eo",
        "default",
        "--range-m",
        "300",
        "--quality",
        "draft",
        "--convention",
        "physical",
        "--json",
    )
    assert code == 0
    (row,) = json.loads(out)["results"]
    terms = {t["name"]: t for t in row["terms"]}
    assert row["convention"] == "physical" and terms["kruse_extinction"]["unit"] == "1/km"
    # Koschmieder at 550 nm, 10 km (Eq. 12), Beer-Lambert over 300 m
    assert terms["transmittance"]["value"] == pytest.approx(np.exp(-(-np.log(0.02) / 10.0) * 0.3), rel=1e-12)
    code, out, _ = run_cli(capsys, "range", "default", "--convention", "physical", "--json")
    assert (
        json.loads(out)["sensors"]["eo"]["terms"]["kruse_extinction"]["source"] == terms["kruse_extinction"]["source"]
    )


def test_render_tir_text_and_atmosphere_on(capsys):
    code, out, err = run_cli(
        capsys,
        "render",
        "tir",
        "default",
        "--range-m",
        "150",
        "--quality",
        "draft",
        "--atmosphere",
        "on",
        "--quiet",
        "--json",
    )
    assert code == 0 and err == ""
    row = json.loads(out)["results"][0]
    assert {"delta_t_k", "delta_t_linear_k", "mrtd_range_m", "files"} <= set(row)
    assert row["files"] == []
    assert [t["name"] for t in row["terms"]] == ["extinction_db_km", "transmittance", "path_radiance"]
    assert row["delta_t_linear_k"] == pytest.approx(0.68 * 288.15 - 0.77 * 298.15)
    code, out, _ = run_cli(capsys, "render", "tir", "default", "--range-m", "150", "--quality", "draft", "--quiet")
    assert code == 0 and "Delta T" in out


@pytest.mark.parametrize(
    "argv,fragment",
    [
        (["render", "eo", "default", "--range-m", "-5"], "range_m"),
        (["render", "eo", "default", "--range-m", "0.1"], "range_m"),
        (["render", "eo", "default", "--range-m", "100", "--sensor", "nope"], "sensor"),
        (["render", "eo", "no_such_scenario", "--range-m", "100"], "scenario"),
        (["render", "eo", "default", "--range-m", "100", "--elevation-deg", "120"], "elevation_deg"),
    ],
)
def test_bad_input_exit_code_2_one_line(capsys, argv, fragment):
    code, out, err = run_cli(capsys, *argv, "--quiet")
    assert code == 2 and out == ""
    assert fragment in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_command_import_does_not_import_mitsuba():
    code = (
        "import sys, csuas.cli, csuas.commands.render, csuas.render.imaging; "
        "csuas.cli.build_parser(); print('mitsuba' in sys.modules, 'drjit' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False False"


def test_mode_dispatch_is_a_dict_of_lazy_entries():
    from csuas.commands import render

    assert set(render.MODES) >= {"eo", "tir"}
    assert callable(render.resolve_mode("eo"))
