"""The layer contract of ARCHITECTURE.md, checked on every import statement of the package.

Layers, lowest first: base <- defaults <- core <- drone_models <- render <- sweep <- validation <- cli
(``csuas.cli``, ``csuas.commands``, ``csuas.core.scenario``, ``csuas.core.ranges``). A module may import its
own layer and the layers below it. Imports inside functions count too: a lazy import is still a
dependency.
"""

import ast
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: folder -> layer name, lowest first
LAYERS = ("base", "defaults", "core", "drone_models", "render", "sweep", "validation", "cli")
FOLDERS = {
    "base": "base",
    "defaults": "defaults",
    "core": "core",
    "drone_models": "drone_models",
    "render": "render",
    "sweep": "sweep",
    "validation": "validation",
    "csuas": "cli",
}

#: What each layer may import besides csuas and the standard library.
#: (tomli is the standard library's tomllib on Python 3.10.)
THIRD_PARTY = {
    "base": {"numpy", "matplotlib", "pydantic", "tomli"},
    "defaults": {"tomli", "pydantic"},
    "core": {"numpy", "scipy", "tomli"},
}


def _layer_of_module(module: str) -> str | None:
    parts = module.split(".")
    if parts[0] != "csuas":
        return None
    if len(parts) == 1:
        return "cli"
    return parts[1] if parts[1] in LAYERS else "cli"


def _imports(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module == "csuas":
                yield from (f"csuas.{alias.name}" for alias in node.names)
            else:
                yield node.module


def _violations():
    found = set()
    for folder, layer in FOLDERS.items():
        for path in (ROOT / folder).rglob("*.py"):
            rel = str(path.relative_to(ROOT))
            for module in _imports(path):
                other = _layer_of_module(module)
                top = module.split(".")[0]
                if other is not None:
                    if LAYERS.index(other) > LAYERS.index(layer):
                        found.add((rel, module))
                elif layer in THIRD_PARTY and top not in sys.stdlib_module_names and top != "__future__":
                    if top not in THIRD_PARTY[layer]:
                        found.add((rel, module))
    return found


def test_no_layer_imports_a_layer_above_it():
    violations = _violations()
    assert violations == set(), "imports against the layer contract"


@pytest.mark.parametrize(
    "rel, module",
    [
        ("core/x.py", "csuas.render.rcs"),
        ("render/x.py", "csuas.validation"),
        ("drone_models/x.py", "csuas.render"),
        ("validation/x.py", "csuas.cli"),
    ],
)
def test_the_checker_sees_an_upward_import(rel, module):
    layer = FOLDERS[rel.split("/")[0]]
    assert LAYERS.index(_layer_of_module(module)) > LAYERS.index(layer)
