"""Command line (docs/command-line.md): JSON keys, exit codes, one-line errors."""

import json
import subprocess
import sys

import pytest

from csuas.cli import main


def _json(capsys, *argv):
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_range_json_keys(capsys):
    out = _json(capsys, "range", "default")
    for name in ("eo", "tir", "acoustic", "rf", "radar", "lidar"):
        entry = out["sensors"][name]
        assert {"range_m", "modality", "model", "terms"} <= set(entry)
        assert entry["range_m"] > 0
    assert out["sensors"]["eo"]["range_m"] == pytest.approx(555.54, abs=0.01)


def test_range_convention_option(capsys):
    paper = _json(capsys, "range", "adverse")["sensors"]["eo"]["range_m"]
    physical = _json(capsys, "range", "adverse", "--convention", "physical")["sensors"]["eo"]["range_m"]
    assert physical < paper


def test_defaults_list_and_check(capsys):
    params = _json(capsys, "defaults", "list")["parameters"]
    assert {"name", "value", "unit", "source"} <= set(params[0])
    names = {p["name"] for p in params}
    for required in (
        "target.d_crit_m",
        "environment.visibility_km",
        "eo.c_min",
        "tir.focal_mm",
        "acoustic.wind_distance_m",
        "rf.s_rx_dbm",
        "radar.bandwidth_mhz",
        "lidar.eta_sys",
    ):
        assert required in names
    checks = _json(capsys, "defaults", "check", "--core-only")["checks"]
    assert {"name", "paper", "computed", "ok"} <= set(checks[0])
    failed = [c["name"] for c in checks if not c["ok"] and not c["known_deviation"]]
    assert not failed


def test_sensitivity_writes_tornado_plots(tmp_path, capsys):
    out = _json(capsys, "sensitivity", "--out", str(tmp_path))
    for name in ("eo", "acoustic_calm", "acoustic_wind", "radar"):
        png = tmp_path / f"tornado_{name}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert out["analyses"][name]["baseline_m"] == pytest.approx(out["analyses"][name]["paper_baseline_m"], abs=0.05)


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["range", "missing.toml"], "no such file"),
        (["range", "default", "--convention", "exact"], "invalid choice"),
        (["frobnicate"], "invalid choice"),
    ],
)
def test_errors_exit_2_with_one_line(argv, fragment):
    proc = subprocess.run([sys.executable, "-m", "csuas.cli", *argv], capture_output=True, text=True)
    assert proc.returncode == 2
    assert fragment in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "Traceback" not in proc.stderr


def test_bad_scenario_value_exit_2(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[target]\nd_crit_m = -3\n[sensors.e]\nmodality = "eo"\n')
    proc = subprocess.run([sys.executable, "-m", "csuas.cli", "range", str(path)], capture_output=True, text=True)
    assert proc.returncode == 2 and "target.d_crit_m = -3" in proc.stderr and "Traceback" not in proc.stderr
