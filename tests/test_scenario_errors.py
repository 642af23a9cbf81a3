"""Scenario loading fails cleanly and says what is wrong (issue 16): one line each, exit code 2."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from csuas.cli import main
from csuas.core.scenario import MAX_SCENARIO_BYTES, check_value


def _error_lines(capsys, argv) -> list[str]:
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "Traceback" not in captured.err
    return captured.err.strip().splitlines()


def test_a_directory_is_named_a_directory_not_a_missing_file(capsys, tmp_path):
    (line,) = _error_lines(capsys, ["range", str(tmp_path)])
    assert "is a directory" in line and "no such file" not in line


def test_dev_null_is_named_a_device_not_a_missing_file(capsys):
    (line,) = _error_lines(capsys, ["range", "/dev/null"])
    assert "not a regular file" in line and "no such file" not in line


def test_an_unreadable_scenario_is_one_line_naming_the_reason(capsys, tmp_path, monkeypatch):
    path = tmp_path / "locked.toml"
    path.write_text('[sensors.e]\nmodality = "eo"\n')

    def refuse(self, *args, **kwargs):
        raise PermissionError(13, "Permission denied", str(self))

    monkeypatch.setattr(Path, "open", refuse)  # root reads a chmod 000 file: refuse at the call instead
    (line,) = _error_lines(capsys, ["range", str(path)])
    assert "cannot be read: Permission denied" in line and "locked.toml" in line


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc/self/mem is Linux's")
def test_proc_self_mem_is_one_line(capsys):
    (line,) = _error_lines(capsys, ["range", "/proc/self/mem"])
    assert "/proc/self/mem" in line and "cannot be read" in line


@pytest.mark.parametrize("opening, closing", [("[", "]"), ("{a = ", "}")])
def test_a_scenario_nested_20000_deep_is_one_line(capsys, tmp_path, opening, closing):
    path = tmp_path / "deep.toml"
    path.write_text("x = " + opening * 20000 + closing * 20000 + "\n")
    (line,) = _error_lines(capsys, ["range", str(path)])
    assert "too deeply" in line


def test_a_scenario_larger_than_the_limit_is_refused_by_its_size(capsys, tmp_path):
    path = tmp_path / "huge.toml"
    path.write_text("# " + "x" * (2 * MAX_SCENARIO_BYTES) + "\n")
    (line,) = _error_lines(capsys, ["range", str(path)])
    assert f"larger than {MAX_SCENARIO_BYTES // 1024} KiB" in line


def test_a_misspelt_embedded_scenario_lists_the_valid_names(capsys):
    embedded = sorted(p.stem for p in (Path(__file__).parents[1] / "defaults" / "scenarios").glob("*.toml"))
    (line,) = _error_lines(capsys, ["range", "defualt"])
    assert "'defualt'" in line and ", ".join(embedded) in line


def test_sensitivity_of_several_sensors_without_sensor_names_them_and_no_python_none(capsys):
    (line,) = _error_lines(capsys, ["sensitivity", "--scenario", "black_hornet", "--vary", "target.d_crit_m=0.02:0.03"])
    assert "--sensor is required" in line and "eo, acoustic, radar" in line and "None" not in line


def test_sensitivity_bounds_outside_the_valid_range_are_all_refused_before_any_range(capsys):
    lines = _error_lines(
        capsys,
        [
            "sensitivity",
            "--scenario",
            "default",
            "--sensor",
            "eo",
            "--vary",
            "sensor.hfov_deg=1:200",
            "target.d_crit_m=-1:0.2",
        ],
    )
    assert len(lines) == 2  # hfov_deg = 200 deg once gave a range of 27.8 m from tan(100 deg) < 0
    assert "sensor.hfov_deg = 200.0" in lines[0] and "180" in lines[0]
    assert "target.d_crit_m = -1.0" in lines[1]


def test_a_wrong_sensitivity_key_is_said_once_not_once_per_bound(capsys):
    (line,) = _error_lines(
        capsys, ["sensitivity", "--scenario", "default", "--sensor", "eo", "--vary", "sensor.zoom=1:2"]
    )
    assert "sensor.zoom" in line


def test_messages_show_numbers_plainly_never_numpy_reprs():
    spec = {"min": 0.0, "max": 180.0, "unit": "deg", "value": 5.0}
    with pytest.raises(Exception, match=r"^hfov_deg = 200\.0 is invalid; allowed: \[0, 180\] deg$") as info:
        check_value("hfov_deg", spec, np.float64(200.0))
    assert "np." not in str(info.value)
