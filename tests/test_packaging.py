"""Packaging: every source folder is a package of the wheel, and importing csuas stays light."""

import subprocess
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]


def test_every_package_folder_is_listed_in_pyproject():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    mapping = config["package-dir"]
    found = set()
    for package, folder in mapping.items():
        for init in (ROOT / folder).rglob("__init__.py"):
            rel = init.parent.relative_to(ROOT / folder)
            found.add(".".join([package, *rel.parts]) if rel.parts else package)
    assert found <= set(config["packages"]), sorted(found - set(config["packages"]))


def test_import_selects_no_variant_and_loads_no_renderer():
    code = (
        "import sys, csuas, csuas.core.eo, csuas.core.scenario, csuas.core.ranges, csuas.drone_models, csuas.render; "
        "print(any(m.split('.')[0] in ('mitsuba', 'drjit', 'sionna') for m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
