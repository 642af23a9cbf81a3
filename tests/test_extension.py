"""Adding a sensor modality touches only the files ARCHITECTURE.md's "Where to make a change" names.

A copy of the package, laid out as installed (``csuas/`` with ``base/``, ``defaults/`` and ``core/`` in it,
as ``package-dir`` maps them), gets a dummy modality, ``beacon``: an isotropic emitter of power P seen by a
receiver that needs the intensity I_min, so its range is the inverse-square law's R = sqrt(P / (4 pi I_min)).
Only the files the table's row lists are written: its model (``core/beacon.py``), its parameters and presets
(``defaults/parameters.toml``, ``defaults/presets.toml``) and one record (``core/modality.py``). ``csuas range``
and ``csuas pd`` then run on a scenario with two beacons, in a process that imports the copy. A modality
section without its record fails the import, naming the modality.
"""

import json
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: The row of ARCHITECTURE.md this test follows.
ROW = re.compile(r"^\| a sensor modality \| (.*) \|$", re.MULTILINE)

MODEL = '''"""A dummy modality: an isotropic emitter seen by an intensity threshold, R = sqrt(P / (4 pi I_min))."""

import numpy as np

from csuas.core.pd_curves import margin_db
from csuas.core.result import RangeResult, Term


def beacon_range(scenario, sensor, convention):
    p = sensor.params
    r = np.sqrt(p["power_w"] / (4.0 * np.pi * p["intensity_min_w_m2"]))
    return RangeResult(r, "beacon", "inverse square", [Term("power_w", p["power_w"], "W", "sensor")])


def beacon_pd(scenario, sensor, convention, range_m, result):
    return (margin_db(scenario, sensor, convention, range_m) >= 0.0).astype(float), ["a step at the range"]
'''

PARAMETERS = """
[beacon]
power_w = {value = 1.0, unit = "W", source = "test", min = 0.0, max = 1e6, min_exclusive = true, description = "P"}
intensity_min_w_m2 = {value = 1e-7, unit = "W/m^2", source = "test", min = 0.0, max = 1.0, min_exclusive = true, \
description = "I_min"}
looks = {value = "independent", unit = "-", source = "test", choices = ["independent", "correlated"], description = "x"}
look_rate_hz = {value = 1.0, unit = "Hz", source = "test", min = 0.0, max = 1e3, min_exclusive = true, \
description = "f"}
"""

PRESETS = """
[sensor.beacon.strong]
description = "ten watts"
source = "test"
power_w = 10.0
"""

RECORD = """    Modality(
        "beacon",
        model="csuas.core.beacon:beacon_range",
        detector="csuas.core.beacon:beacon_pd",
        horizon=None,
        threshold="intensity_min_w_m2",
        renderer=None,
        report_group="propagation",
    ),
"""

SCENARIO = """
[sensors.weak]
modality = "beacon"

[sensors.strong]
modality = "beacon"
preset = "strong"
"""


def _append(path: Path, text: str) -> None:
    path.write_text(path.read_text(encoding="utf-8") + text, encoding="utf-8")


@pytest.fixture()
def installed_copy(tmp_path):
    """The package as installed: ``csuas/`` holding the layers the range and pd commands import."""
    package = tmp_path / "site" / "csuas"
    shutil.copytree(ROOT / "csuas", package, ignore=shutil.ignore_patterns("__pycache__"))
    for layer in ("base", "defaults", "core"):
        shutil.copytree(ROOT / layer, package / layer, ignore=shutil.ignore_patterns("__pycache__"))
    return package


def _run(package: Path, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(package.parent)}
    return subprocess.run([sys.executable, *args], capture_output=True, text=True, env=env, cwd=package.parent)


def test_the_table_names_the_files_this_test_touches():
    row = ROW.search((ROOT / "ARCHITECTURE.md").read_text(encoding="utf-8")).group(1)
    named = re.findall(r"`([\w/<>.]+\.(?:py|toml|md))`", row)
    assert named == [
        "core/<modality>.py",
        "defaults/parameters.toml",
        "defaults/presets.toml",
        "core/modality.py",
        "docs/scenarios.md",
    ]


def test_a_dummy_modality_added_in_its_files_runs_range_and_pd(installed_copy, tmp_path):
    (installed_copy / "core" / "beacon.py").write_text(MODEL, encoding="utf-8")
    _append(installed_copy / "defaults" / "parameters.toml", PARAMETERS)
    _append(installed_copy / "defaults" / "presets.toml", PRESETS)
    records = installed_copy / "core" / "modality.py"
    text = records.read_text(encoding="utf-8")
    assert text.count("\nRECORDS = (\n") == 1
    records.write_text(text.replace("\nRECORDS = (\n", "\nRECORDS = (\n" + RECORD), encoding="utf-8")
    scenario = tmp_path / "beacons.toml"
    scenario.write_text(SCENARIO, encoding="utf-8")

    ran = _run(installed_copy, "-m", "csuas.cli", "range", str(scenario), "--json")
    assert ran.returncode == 0, ran.stderr
    sensors = json.loads(ran.stdout)["sensors"]
    for name, power_w in (("weak", 1.0), ("strong", 10.0)):
        assert sensors[name]["modality"] == "beacon"
        assert sensors[name]["range_m"] == pytest.approx(math.sqrt(power_w / (4 * math.pi * 1e-7)), rel=1e-12)

    r_weak = math.sqrt(1.0 / (4 * math.pi * 1e-7))
    ranges = [0.5 * r_weak, 0.99 * r_weak, 1.01 * r_weak, 2.0 * r_weak]
    ran = _run(installed_copy, "-m", "csuas.cli", "pd", str(scenario), "--json", "--range-m", *map(str, ranges))
    assert ran.returncode == 0, ran.stderr
    curves = json.loads(ran.stdout)["sensors"]
    assert curves["weak"]["pd"] == [1.0, 1.0, 0.0, 0.0]
    assert curves["strong"]["pd"] == [1.0, 1.0, 1.0, 1.0]


def test_a_modality_section_without_its_record_fails_the_import_naming_it(installed_copy):
    _append(installed_copy / "defaults" / "parameters.toml", PARAMETERS)
    _append(installed_copy / "defaults" / "presets.toml", PRESETS)
    ran = _run(installed_copy, "-c", "import csuas.core.ranges")
    assert ran.returncode != 0
    assert "modality 'beacon': a section of defaults/parameters.toml without a Modality record" in ran.stderr
