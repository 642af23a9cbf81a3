"""Hostile input: every malformed scenario value and command line gets a clean answer.

Each case runs the command line in-process and asserts the contract of the command line: exit code
2, the offending parameter named on standard error, no traceback, nothing on standard output. The
scenario cases are generated from ``defaults/parameters.toml`` itself (every numeric parameter
below its minimum, above its maximum, NaN, infinite, of the wrong type; every text parameter with an
unknown choice), so a parameter added there is probed without touching this file. Valid but hard
cases must answer with exit code 0 and finite ranges, or with an explained reason.
"""

from __future__ import annotations

import json
import math
import sys

import pytest

from csuas.cli import main
from csuas.defaults import load_parameters

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

PARAMETERS = load_parameters()
SECTION_OF_MODALITY = {m: m for m in ("eo", "tir", "acoustic", "rf", "radar", "lidar")}


def _toml_value(value) -> str:
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, float) and math.isnan(value):
        return "nan"
    if isinstance(value, float) and math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return repr(value)


def _scenario_text(section: str, key: str, value) -> str:
    line = f"{key} = {_toml_value(value)}"
    if section in ("target", "environment"):
        return f'name = "hostile"\n[{section}]\n{line}\n[sensors.s]\nmodality = "eo"\n'
    return f'name = "hostile"\n[sensors.s]\nmodality = "{section}"\n{line}\n'


def _bad_values(spec: dict):
    """(label, value) pairs outside the parameter's domain."""
    if "choices" in spec:
        yield "unknown_choice", "no_such_choice"
        yield "number_for_text", 3.0
        return
    if spec.get("list"):
        yield "text_for_list", "abc"
        return
    low, high = spec.get("min"), spec.get("max")
    if low is not None and low > -1e8:
        yield "below_min", low - max(1.0, abs(low))
        if spec.get("min_exclusive"):
            yield "at_exclusive_min", low
    if high is not None and high < 1e8:
        yield "above_max", high + max(1.0, abs(high))
    yield "nan", float("nan")
    if high is not None and math.isfinite(high):
        yield "plus_inf", float("inf")
    yield "text_for_number", "ten"


def _scenario_cases():
    for section, params in PARAMETERS.items():
        if section not in ("target", "environment", *SECTION_OF_MODALITY):
            continue
        for key, spec in params.items():
            if not isinstance(spec, dict):
                continue
            for label, value in _bad_values(spec):
                yield pytest.param(section, key, value, id=f"{section}.{key}.{label}")


def _run(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _assert_clean_refusal(code, out, err, *must_name):
    assert "Traceback" not in err
    assert code == 2, err
    assert out == ""
    assert err.strip(), "an error must say what is wrong"
    assert len(err.strip().splitlines()) <= 20
    for text in must_name:
        assert text in err, (text, err)


@pytest.mark.parametrize("section, key, value", list(_scenario_cases()))
def test_a_value_outside_its_domain_is_refused_naming_the_parameter(tmp_path, capsys, section, key, value):
    path = tmp_path / "hostile.toml"
    path.write_text(_scenario_text(section, key, value))
    code, out, err = _run(capsys, ["range", str(path)])
    _assert_clean_refusal(code, out, err, key)


MALFORMED_FILES = {
    "not_toml": "this is not [ toml",
    "unknown_top_level_key": 'name = "x"\nsurprise = 1\n[sensors.s]\nmodality = "eo"\n',
    "unknown_target_key": 'name = "x"\n[target]\nwingspan_m = 1\n[sensors.s]\nmodality = "eo"\n',
    "unknown_sensor_key": 'name = "x"\n[sensors.s]\nmodality = "eo"\nzoom = 3\n',
    "unknown_modality": 'name = "x"\n[sensors.s]\nmodality = "sonar"\n',
    "missing_modality": 'name = "x"\n[sensors.s]\nhfov_deg = 3\n',
    "no_sensors": 'name = "x"\n',
    "sensors_not_a_table": 'name = "x"\nsensors = 3\n',
    "unknown_target_preset": 'name = "x"\n[target]\npreset = "no_drone"\n[sensors.s]\nmodality = "eo"\n',
    "unknown_environment_preset": 'name = "x"\n[environment]\npreset = "mars"\n[sensors.s]\nmodality = "eo"\n',
    "unknown_sensor_preset": 'name = "x"\n[sensors.s]\nmodality = "radar"\npreset = "no_radar"\n',
    "unknown_rain_class": 'name = "x"\n[environment]\nrain = "biblical"\n[sensors.s]\nmodality = "rf"\n',
    "unknown_fog_class": 'name = "x"\n[environment]\nfog = "pea_soup"\n[sensors.s]\nmodality = "eo"\n',
    "unknown_convention": 'name = "x"\nconvention = "mine"\n[sensors.s]\nmodality = "eo"\n',
    "radar_wavelength_and_frequency": 'name = "x"\n[sensors.s]\nmodality = "radar"\nwavelength_m = 0.03\n'
    "frequency_ghz = 10.0\n",
    "target_not_a_table": 'name = "x"\ntarget = "drone"\n[sensors.s]\nmodality = "eo"\n',
    "boolean_for_number": 'name = "x"\n[sensors.s]\nmodality = "eo"\nhfov_deg = true\n',
    "array_for_number": 'name = "x"\n[sensors.s]\nmodality = "eo"\nhfov_deg = [1, 2]\n',
    "empty_file": "",
    "binary_garbage": "\x00\x01\x02\xff",
}


@pytest.mark.parametrize("label", sorted(MALFORMED_FILES))
def test_a_malformed_scenario_file_is_one_clean_error(tmp_path, capsys, label):
    path = tmp_path / f"{label}.toml"
    path.write_text(MALFORMED_FILES[label], encoding="utf-8", errors="surrogateescape")
    code, out, err = _run(capsys, ["range", str(path)])
    _assert_clean_refusal(code, out, err)


BAD_COMMAND_LINES = {
    "missing_scenario_file": ["range", "/no/such/scenario.toml"],
    "scenario_is_a_directory": ["range", "/tmp"],
    "scenario_is_dev_null": ["range", "/dev/null"],
    "scenario_is_unreadable_device_memory": ["range", "/proc/self/mem"],
    "render_out_under_proc": ["render", "eo", "default", "--range-m", "100", "--out", "/proc/x"],
    "drone_missing_mesh_file": ["drone", "/no/such/mesh.ply"],
    "misspelt_embedded_scenario": ["range", "defualt"],
    "bad_convention_option": ["range", "default", "--convention", "mine"],
    "unknown_command": ["fly"],
    "no_command": [],
    "defaults_unknown_action": ["defaults", "burn"],
    "render_unknown_mode": ["render", "sonar", "default", "--range-m", "100"],
    "render_negative_range": ["render", "eo", "default", "--range-m", "-100"],
    "render_zero_range": ["render", "eo", "default", "--range-m", "0"],
    "render_nan_range": ["render", "eo", "default", "--range-m", "nan"],
    "render_inf_range": ["render", "eo", "default", "--range-m", "inf"],
    "render_unknown_quality": ["render", "eo", "default", "--range-m", "100", "--quality", "ultra"],
    "render_negative_seed": ["render", "eo", "default", "--range-m", "100", "--seed", "-1"],
    "render_text_range": ["render", "eo", "default", "--range-m", "far"],
    "rcs_unknown_preset": ["rcs", "no_drone", "--frequency-ghz", "10"],
    "rcs_missing_mesh_file": ["rcs", "/no/such/mesh.obj", "--frequency-ghz", "10"],
    "rcs_negative_frequency": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "-10"],
    "rcs_zero_frequency": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "0"],
    "rcs_nan_frequency": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "nan"],
    "rcs_inf_frequency": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "inf"],
    "rcs_absurd_frequency": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "1e6"],
    "rcs_zero_rays_per_wavelength": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "10", "--rays-per-wavelength", "0"],
    "rcs_negative_rays_per_wavelength": [
        "rcs",
        "dji_mini_4_pro",
        "--frequency-ghz",
        "10",
        "--rays-per-wavelength",
        "-3",
    ],
    "rcs_elevation_out_of_range": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "10", "--elevation-deg", "100"],
    "rcs_nan_azimuth": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "10", "--azimuth-deg", "nan"],
    "rcs_unknown_material": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "10", "--material", "kryptonite"],
    "rcs_absurd_bounces": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "10", "--max-bounces", "1000000"],
    "drone_unknown_preset": ["drone", "no_drone"],
    "drone_elevation_out_of_range": ["drone", "dji_mini_4_pro", "--elevation-deg", "-91"],
    "drone_nan_azimuth": ["drone", "dji_mini_4_pro", "--azimuth-deg", "nan"],
    "drone_export_unknown_format": ["drone", "dji_mini_4_pro", "--export", "/tmp/x.docx"],
    "pathloss_negative_distance": ["pathloss", "--frequency-ghz", "2.4", "--distance-m", "-5"],
    "pathloss_zero_frequency": ["pathloss", "--frequency-ghz", "0", "--distance-m", "100"],
    "pathloss_nan_frequency": ["pathloss", "--frequency-ghz", "nan", "--distance-m", "100"],
    "pathloss_unknown_ground": [
        "pathloss",
        "--frequency-ghz",
        "2.4",
        "--distance-m",
        "100",
        "--tx-height-m",
        "2",
        "--rx-height-m",
        "2",
        "--ground",
        "cheese",
    ],
    "sensitivity_unknown_analysis": ["sensitivity", "--analysis", "everything"],
    "sensitivity_unknown_sensor": [
        "sensitivity",
        "--scenario",
        "default",
        "--sensor",
        "nope",
        "--vary",
        "sensor.hfov_deg=1:20",
    ],
    "sensitivity_bad_vary": ["sensitivity", "--scenario", "default", "--sensor", "eo", "--vary", "nonsense"],
    "report_baseline_missing": ["report", "--quick", "--baseline", "/no/such/report.json"],
    "report_baseline_directory": ["report", "--quick", "--baseline", "/tmp"],
    "bench_unknown_suite": ["bench", "--only", "everything"],
    # issue 22: output paths and sweep options, refused before any work
    "rcs_plot_into_a_folder": ["rcs", "dji_mini_4_pro", "--frequency-ghz", "10", "--plot", "/tmp"],
    "pd_plot_with_a_nul": ["pd", "default", "--plot", "a\0b.png"],
    "pd_plot_name_of_300_characters": ["pd", "default", "--plot", "x" * 300 + ".png"],
    "drone_export_into_a_folder": ["drone", "dji_mini_4_pro", "--quality", "none", "--export", "/tmp/"],
    "rcs_statistics_out_is_a_folder": ["rcs-statistics", "--out", "/tmp"],
    "sweep_zero_no_worker_timeout": ["sweep", "range_rain", "--out", "/tmp/x", "--no-worker-timeout-s", "0"],
    "sweep_nan_no_worker_timeout": ["sweep", "range_rain", "--out", "/tmp/x", "--no-worker-timeout-s", "nan"],
    "sweep_inf_no_worker_timeout": ["sweep", "range_rain", "--out", "/tmp/x", "--no-worker-timeout-s", "inf"],
    "sweep_unknown_scheduler_scheme": ["sweep", "range_rain", "--out", "/tmp/x", "--scheduler", "udp://h:1"],
}


@pytest.mark.parametrize("label", sorted(BAD_COMMAND_LINES))
def test_a_bad_command_line_is_one_clean_error_before_any_work(capsys, label):
    try:
        code, out, err = _run(capsys, BAD_COMMAND_LINES[label])
    except SystemExit as exc:  # argparse's own refusals
        out, err = capsys.readouterr()
        code = exc.code
    _assert_clean_refusal(code, out, err)


def test_a_report_baseline_of_the_wrong_shape_is_refused_before_the_checks(tmp_path, capsys):
    baseline = tmp_path / "b.json"
    baseline.write_text('{"checks": [1]}')
    code, out, err = _run(capsys, ["report", "--quick", "--baseline", str(baseline), "--out", str(tmp_path / "r")])
    _assert_clean_refusal(code, out, err, "baseline")
    assert not (tmp_path / "r").exists()


def test_a_scenario_nested_20000_deep_is_one_clean_error(tmp_path, capsys):
    path = tmp_path / "deep.toml"
    path.write_text("a = " + "[" * 20000 + "]" * 20000 + "\n")
    code, out, err = _run(capsys, ["range", str(path)])
    _assert_clean_refusal(code, out, err, "too deeply")


def test_a_report_out_that_is_a_file_is_refused_before_the_checks(tmp_path, capsys):
    existing = tmp_path / "f"
    existing.write_text("keep me")
    code, out, err = _run(capsys, ["report", "--quick", "--out", str(existing)])
    _assert_clean_refusal(code, out, err, "--out")
    assert existing.read_text() == "keep me"


def test_an_output_that_is_a_file_is_refused_before_rendering(tmp_path, capsys):
    existing = tmp_path / "f"
    existing.write_text("keep me")
    code, out, err = _run(capsys, ["render", "eo", "default", "--range-m", "100", "--out", str(existing)])
    _assert_clean_refusal(code, out, err)
    assert existing.read_text() == "keep me"


HARD_BUT_VALID = {
    "dense_fog_every_sensor": 'name = "x"\n[environment]\nfog = "dense"\n'
    + "".join(f'[sensors.{m}]\nmodality = "{m}"\n' for m in SECTION_OF_MODALITY),
    "storm_rain": 'name = "x"\n[environment]\nrain_rate_mm_h = 300.0\n[sensors.rf]\nmodality = "rf"\n'
    '[sensors.radar]\nmodality = "radar"\n',
    "gale_acoustic": 'name = "x"\n[environment]\nwind_speed_m_s = 50.0\n[sensors.a]\nmodality = "acoustic"\n',
    "tiny_target": 'name = "x"\n[target]\nd_crit_m = 1e-6\n'
    + "".join(f'[sensors.{m}]\nmodality = "{m}"\n' for m in ("eo", "tir")),
    "zero_contrast": 'name = "x"\n[target]\nc_eo = 0.0\n[sensors.eo]\nmodality = "eo"\n',
    "p_desired_one": 'name = "x"\n[sensors.eo]\nmodality = "eo"\np_desired = 1.0\n',
    "visibility_at_kruse_breakpoint": 'name = "x"\n[environment]\nvisibility_km = 6.0\n[sensors.eo]\nmodality = "eo"\n',
    "visibility_at_50_km": 'name = "x"\n[environment]\nvisibility_km = 50.0\n[sensors.eo]\nmodality = "eo"\n'
    "wavelength_nm = 400.0\n",
    "high_target": 'name = "x"\n[target]\naltitude_m = 5000.0\n'
    + "".join(f'[sensors.{m}]\nmodality = "{m}"\n' for m in SECTION_OF_MODALITY),
    "silent_night": 'name = "x"\n[environment]\nnoise_level_db = -1e6\n[sensors.a]\nmodality = "acoustic"\n',
}


def _finite_or_explained(sensor: dict) -> bool:
    value = sensor["range_m"]
    finite = isinstance(value, (int, float)) and math.isfinite(value) and value > 0
    return finite or bool(sensor.get("reason"))


@pytest.mark.parametrize("label", sorted(HARD_BUT_VALID))
@pytest.mark.parametrize("convention", ["paper", "physical"])
def test_a_hard_but_valid_scenario_answers_with_a_finite_or_explained_range(tmp_path, capsys, label, convention):
    path = tmp_path / f"{label}.toml"
    path.write_text(HARD_BUT_VALID[label])
    tomllib.loads(HARD_BUT_VALID[label])  # the case itself is valid TOML
    code, out, err = _run(capsys, ["range", str(path), "--convention", convention, "--json"])
    assert "Traceback" not in err
    assert code == 0, err
    result = json.loads(out)
    for name, sensor in result["sensors"].items():
        assert _finite_or_explained(sensor), (name, sensor)
