"""A sweep job kind is one declaration: a dummy job added to ``sweep/kinds.py`` alone runs through ``csuas sweep``.

The package is copied to a temporary folder laid out as installed (``csuas/``, ``csuas/base/``, ...,
pyproject.toml's ``package-dir``); only the files ARCHITECTURE.md's "Where to make a change" row names
are edited there; a subprocess with the copy first on its path runs a sweep of the dummy job on the
serial scheduler (no Dask) and checks its table against the job's formula.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import tomllib

from csuas.sweep.kinds import JOB_KINDS, kind_of

ROOT = Path(__file__).resolve().parents[1]
ROW = "a sweep job kind"
#: The dummy job: an options model, a chunk function (each point's index times ``scale``) and its record.
DUMMY = '''

class DummyOptions(Schema):
    """``[options]`` of the dummy job."""

    scale: number(0.0, None) = key(2.0, "factor of each point's index")


def _dummy_chunk(spec, columns, start, stop):
    return {"scaled": np.arange(start, stop) * spec.options["scale"]}


JOB_KINDS["dummy"] = JobKind(
    "dummy", DummyOptions, 2, _dummy_chunk, lambda spec: ["scaled"], JobCost(1e8, seconds_per_point=1.0),
    takes_scenario=False, prepare=lambda spec: replace(spec, count=5),
)
'''
DUMMY_IMPORTS = (
    "from dataclasses import replace\nimport numpy as np\nfrom csuas.base.schema import Schema, key, number\n"
)
CHECK = """
import json, sys
import csuas
from csuas.cli import main
from csuas.sweep import read_results
from csuas.sweep.spec import parse_spec
assert csuas.__file__.startswith(sys.argv[1]), csuas.__file__
assert main(["sweep", sys.argv[2], "--out", sys.argv[3], "--scheduler", "serial", "--json"]) == 0
table = read_results(sys.argv[3] + "/results.parquet")
try:
    parse_spec({"job": "nothing"})
except Exception as exc:
    refused = str(exc)
print(json.dumps({"columns": list(table), "scaled": table["scaled"].tolist(), "refused": refused}))
"""


def _row_files() -> list[str]:
    """The files ARCHITECTURE.md's row for a sweep job kind names."""
    for line in (ROOT / "ARCHITECTURE.md").read_text(encoding="utf-8").splitlines():
        if line.startswith(f"| {ROW} |"):
            return [part for part in line.split("`") if part.endswith((".py", ".md"))]
    raise AssertionError(f"ARCHITECTURE.md has no row '{ROW}'")


def _installed_layout(tmp_path: Path) -> Path:
    """The package copied as pyproject.toml's ``package-dir`` installs it."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    site = tmp_path / "site"
    for package, folder in sorted(project["tool"]["setuptools"]["package-dir"].items()):
        shutil.copytree(
            ROOT / folder, site / package.replace(".", "/"), ignore=shutil.ignore_patterns("__pycache__", "*.pyc")
        )
    return site


def test_the_row_names_the_record_and_the_registry_holds_every_job():
    assert "sweep/kinds.py" in _row_files()
    assert list(JOB_KINDS) == ["range", "pd", "render", "rcs", "engage"]
    for name, kind in JOB_KINDS.items():
        assert kind.schema.model_fields["job"].annotation.__args__ == (name,)
        assert kind_of(name) is kind


def test_a_dummy_job_added_in_the_named_files_runs_a_sweep(tmp_path):
    site = _installed_layout(tmp_path)
    kinds = site / "csuas" / "sweep" / "kinds.py"
    assert "sweep/kinds.py" in _row_files()
    text = kinds.read_text(encoding="utf-8")
    head, _, body = text.partition("from __future__ import annotations\n")
    kinds.write_text(head + "from __future__ import annotations\n" + DUMMY_IMPORTS + body + DUMMY, encoding="utf-8")
    spec = tmp_path / "dummy.toml"
    spec.write_text('job = "dummy"\n[options]\nscale = 3.0\n', encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": str(site)}
    done = subprocess.run(
        [sys.executable, "-c", CHECK, str(site), str(spec), str(tmp_path / "out")],
        env=env,
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    found = json.loads(done.stdout.strip().splitlines()[-1])
    assert found["columns"] == ["point", "scaled", "time_s"]
    assert found["scaled"] == pytest.approx([0.0, 3.0, 6.0, 9.0, 12.0], abs=0.0)
    assert "range, pd, render, rcs, engage, dummy" in found["refused"]
    sweep = json.loads((tmp_path / "out" / "sweep.json").read_text())
    assert (sweep["job"], sweep["points"], sweep["chunks"]) == ("dummy", 5, 3)
