"""The install declares what the code needs, and CI proves it on a fresh virtual environment.

A dependency installed by hand once hid a missing one (trimesh's polygon triangulation needs
``mapbox-earcut``, which nothing declared): these tests make such a gap fail here rather than on a
user's fresh machine.
"""

import ast
import importlib.metadata
import re
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

import numpy as np
import trimesh
from shapely.geometry import Polygon

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def _normalise(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def _declared(requirements) -> set[str]:
    return {_normalise(re.split(r"[ ;<>=!~\[]", req, maxsplit=1)[0]) for req in requirements}


def _third_party_imports(folders) -> dict[str, set[str]]:
    """Top-level module names imported anywhere (also inside functions) -> files importing them."""
    found: dict[str, set[str]] = {}
    for folder in folders:
        local = {p.stem for p in (ROOT / folder).rglob("*.py")}  # sibling modules (a test's shared oracle)
        for path in (ROOT / folder).rglob("*.py"):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.Import):
                    names = [alias.name for alias in node.names]
                elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                    names = [node.module]
                else:
                    continue
                for name in names:
                    top = name.split(".")[0]
                    if top not in sys.stdlib_module_names and top not in ("csuas", "__future__", *local):
                        found.setdefault(top, set()).add(str(path.relative_to(ROOT)))
    return found


def _undeclared(folders, requirements) -> dict[str, set[str]]:
    declared = _declared(requirements)
    distributions = importlib.metadata.packages_distributions()
    missing = {}
    for module, files in _third_party_imports(folders).items():
        dists = {_normalise(d) for d in distributions.get(module, [module])}
        if not dists & declared:
            missing[module] = files
    return missing


#: Optional extras of the package and the modules that may import them (lazily, inside functions).
OPTIONAL_EXTRAS = {"detector": ("validation/detector/training.py", "validation/detector/detector_loop.py")}


def test_every_third_party_import_of_the_package_is_a_declared_dependency():
    folders = sorted(set(PYPROJECT["tool"]["setuptools"]["package-dir"].values()))
    requirements = PYPROJECT["project"]["dependencies"]
    for extra in OPTIONAL_EXTRAS:
        requirements = requirements + PYPROJECT["project"]["optional-dependencies"][extra]
    assert _undeclared(folders, requirements) == {}


def test_an_optional_extra_is_imported_only_inside_functions_of_its_modules():
    """``import csuas...`` works without the extra (CI does not install it): no module-level import of it, and
    only the modules named in OPTIONAL_EXTRAS import it at all."""
    folders = sorted(set(PYPROJECT["tool"]["setuptools"]["package-dir"].values()))
    for extra, allowed in OPTIONAL_EXTRAS.items():
        modules = _declared(PYPROJECT["project"]["optional-dependencies"][extra])
        users = {f for m, files in _third_party_imports(folders).items() if _normalise(m) in modules for f in files}
        assert users and users <= set(allowed), (extra, users)
        for name in allowed:
            tree = ast.parse((ROOT / name).read_text(encoding="utf-8"))
            top = [n for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom))]
            named = {
                (a.name if isinstance(n, ast.Import) else n.module or "").split(".")[0] for n in top for a in n.names
            }
            assert not {_normalise(m) for m in named} & modules, (name, named)


def test_every_third_party_import_of_the_tests_is_declared():
    requirements = PYPROJECT["project"]["dependencies"] + PYPROJECT["project"]["optional-dependencies"]["test"]
    # hypothesis' pytest plugin and pytest itself are imported by name in tests
    assert _undeclared(["tests"], requirements) == {}


def test_trimesh_can_triangulate_a_non_convex_polygon():
    """The dependency that was missing: extrusion needs a triangulation engine (mapbox-earcut)."""
    l_shape = Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
    prism = trimesh.creation.extrude_polygon(l_shape, height=0.5)
    assert prism.is_watertight
    np.testing.assert_allclose(prism.volume, 3.0 * 0.5, rtol=1e-12)


def test_ci_installs_into_a_fresh_virtual_environment_and_runs_the_readme_test_command():
    ci = (ROOT / ".ci" / "run").read_text()
    readme = (ROOT / "README.md").read_text()
    makefile = (ROOT / "Makefile").read_text()
    assert "mktemp -d" in ci and "CSUAS_VENV=" in ci, "CI must create its virtual environment anew"
    assert re.search(r"^make test$", ci, re.M), "CI must run the README's test command"
    assert "make test" in readme and "make report" in readme
    assert re.search(r"^test: setup$", makefile, re.M) and re.search(r"^report: setup$", makefile, re.M)
    setup = (ROOT / "tools" / "setup.sh").read_text()
    assert "python3 -m venv" in setup and "CSUAS_VENV" in setup
