"""The layer contract of ARCHITECTURE.md, checked on every import of the package, and its debts.

Layers, lowest first: base <- defaults <- core <- drone_models <- render <- sweep <- validation <- cli
(``csuas.cli``, ``csuas.commands``). A module may import its own layer and the layers below it.
Every way of importing counts: ``import`` and ``from`` statements at any depth (a lazy import is still
a dependency), relative imports (resolved against the module's package), ``importlib.import_module``
``__import__`` and ``resolve`` calls with a literal name, and registry strings ``"csuas.x.y:attribute"``
that :func:`csuas.base.registry.resolve` imports when used. A self-test plants each kind of upward import
in a copy of the package and sees the checker fail.

Imports of the cheap layers (base, defaults, core) sit at module level: a function-level one defers nothing
worth deferring, and ``LAZY_CHEAP_IMPORTS`` lists the few that must stay, each with its reason (it may
only shrink); a self-test plants one and sees the check fail.

``KNOWN_DEBTS`` records the functions longer than 100 lines or with more than 8 parameters (the
limits of CONTRIBUTING.md): the list may only shrink. A new debt fails, and so does a listed debt that
grew or was paid off (remove its line).
"""

import ast
import re
import shutil
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
#: numba compiles the core's loops that NumPy cannot vectorise (the viewshed's rays); it ships with
#: bempp-cl and is a dependency of its own.
THIRD_PARTY = {
    "base": {"numpy", "matplotlib", "pydantic", "tomli"},
    "defaults": {"tomli", "pydantic"},
    "core": {"numpy", "scipy", "tomli", "numba"},
}

#: A registry entry: ``"csuas.package.module:attribute"`` (a bare dotted name counts when it is passed to
#: ``resolve``, ``import_module`` or ``__import__``; a ``python -m csuas.cli`` argument is a process, not an import).
_REGISTRY_STRING = re.compile(r"^csuas(\.[A-Za-z_][A-Za-z0-9_]*)+:[A-Za-z_][A-Za-z0-9_.]*$")

#: Limits of CONTRIBUTING.md.
MAX_LINES = 100
MAX_PARAMETERS = 8

#: (file, function, limit broken) -> its size when recorded. May only shrink.
KNOWN_DEBTS = {
    # kept: of_paper is the named constructor of the Check record, its parameters are Check's own fields
    # (name, values, unit, provenance, tolerances, verdict notes, details); grouping them would add records
    # only to unpack them again, and would touch its 32 calls in 6 files (2026-11-27)
    ("base/checks.py", "Check.of_paper", "parameters"): 11,
    ("core/acoustic.py", "acoustic_range", "parameters"): 9,
    ("core/eo.py", "eo_range", "parameters"): 13,  # +1 rain extinction (Marshall-Palmer), +1 fog layer, 2026-11-27
    ("core/lidar.py", "lidar_range", "parameters"): 10,
    ("core/radar.py", "radar_range", "parameters"): 24,  # public keyword wrapper of radar_range_of (records)
    ("core/rf.py", "rf_range", "parameters"): 12,  # +1 parameter: the gas term (ITU-R P.676), 2026-11-27
    ("core/sensitivity.py", "radar_model", "parameters"): 9,  # keyword interface: sensitivity.toml names its parameters
    ("core/tir.py", "tir_mrtd_range", "parameters"): 10,
    ("core/tir.py", "tir_netd_range", "parameters"): 10,
    ("render/rcs/solver.py", "compute_rcs", "parameters"): 16,  # public keyword wrapper of rcs_of (records)
}


def _layer_of_module(module: str) -> str | None:
    parts = module.split(".")
    if parts[0] != "csuas":
        return None
    if len(parts) == 1:
        return "cli"
    return parts[1] if parts[1] in LAYERS else "cli"


def _package_of(path: Path, root: Path) -> list[str]:
    """The dotted package of a module file, as the installed namespace spells it."""
    rel = path.relative_to(root).with_suffix("").parts
    top = rel[0] if rel[0] == "csuas" else f"csuas.{rel[0]}"
    return [*top.split("."), *rel[1:-1]]


def _relative(node: ast.ImportFrom, package: list[str]) -> list[str]:
    base = package[: len(package) - (node.level - 1)] if node.level > 1 else package
    stem = ".".join(base + ([node.module] if node.module else []))
    return [stem] if node.module else [f"{stem}.{alias.name}" for alias in node.names]


def _dynamic(node: ast.Call) -> str | None:
    name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
    if name in ("import_module", "__import__", "resolve") and node.args and isinstance(node.args[0], ast.Constant):
        return str(node.args[0].value)
    return None


def _imports(path: Path, root: Path = ROOT):
    """Every module ``path`` imports, in any of the ways of the module docstring."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = _package_of(path, root)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level > 0:
            yield from _relative(node, package)
        elif isinstance(node, ast.ImportFrom) and node.module:
            if node.module == "csuas":
                yield from (f"csuas.{alias.name}" for alias in node.names)
            else:
                yield node.module
        elif isinstance(node, ast.Call) and (target := _dynamic(node)):
            yield target
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and _REGISTRY_STRING.match(node.value):
            yield node.value.partition(":")[0]


def _violations(root: Path = ROOT):
    found = set()
    for folder, layer in FOLDERS.items():
        for path in (root / folder).rglob("*.py"):
            rel = str(path.relative_to(root))
            for module in _imports(path, root):
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


#: One planted module per kind of import, each reaching above its layer.
PLANTED = {
    "statement": ("core/planted.py", "import csuas.render.backend\n"),
    "from": ("core/planted.py", "from csuas.validation import report\n"),
    "lazy": ("drone_models/planted.py", "def f():\n    from csuas.render import backend\n"),
    "relative": ("render/rcs/planted.py", "from ...validation import report\n"),
    "relative module": ("render/rcs/planted.py", "from ... import sweep\n"),
    "importlib": ("core/planted.py", "import importlib\nimportlib.import_module('csuas.render.backend')\n"),
    "__import__": ("base/planted.py", "__import__('csuas.core.radar')\n"),
    "resolve": ("core/planted.py", "from csuas.base.registry import resolve\nresolve('csuas.render.backend')\n"),
    "registry": ("render/planted.py", "MODES = {'x': 'csuas.validation.report.runner:SPEC_LISTS'}\n"),
    "third party in core": ("core/planted.py", "import mitsuba\n"),
}


@pytest.fixture(scope="module")
def package_copy(tmp_path_factory):
    copy = tmp_path_factory.mktemp("package")
    for folder in FOLDERS:
        shutil.copytree(ROOT / folder, copy / folder, ignore=shutil.ignore_patterns("__pycache__"))
    return copy


@pytest.mark.parametrize("kind", PLANTED)
def test_a_planted_upward_import_fails_the_checker(package_copy, kind):
    rel, text = PLANTED[kind]
    planted = package_copy / rel
    planted.write_text(text, encoding="utf-8")
    try:
        assert {v for v in _violations(package_copy) if v[0] == rel}, f"{kind} import not seen"
    finally:
        planted.unlink()
    assert _violations(package_copy) == set()


def _function_sizes(root: Path = ROOT):
    """``{(file, qualified function, limit): size}`` of every function breaking a limit."""
    found = {}
    for folder in FOLDERS:
        for path in sorted((root / folder).rglob("*.py")):
            rel = str(path.relative_to(root))
            stack = [(ast.parse(path.read_text(encoding="utf-8")), "")]
            while stack:
                node, prefix = stack.pop()
                for child in ast.iter_child_nodes(node):
                    if isinstance(child, ast.ClassDef):
                        stack.append((child, f"{prefix}{child.name}."))
                    elif isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                        name = f"{prefix}{child.name}"
                        arguments = child.args.posonlyargs + child.args.args + child.args.kwonlyargs
                        count = len([a for a in arguments if a.arg not in ("self", "cls")])
                        lines = child.end_lineno - child.lineno + 1
                        if lines > MAX_LINES:
                            found[(rel, name, "lines")] = lines
                        if count > MAX_PARAMETERS:
                            found[(rel, name, "parameters")] = count
                        stack.append((child, f"{name}."))
    return found


def test_known_debts_only_shrink():
    sizes = _function_sizes()
    new = {key: size for key, size in sizes.items() if key not in KNOWN_DEBTS}
    grown = {key: (KNOWN_DEBTS[key], size) for key, size in sizes.items() if size > KNOWN_DEBTS.get(key, size)}
    paid = sorted(set(KNOWN_DEBTS) - set(sizes))
    assert new == {}, f"new functions over {MAX_LINES} lines or {MAX_PARAMETERS} parameters"
    assert grown == {}, "known debts that grew (recorded, now)"
    assert paid == [], "paid debts: remove them from KNOWN_DEBTS"


#: The cheap layers: a function-level import of them defers nothing worth deferring (they import no
#: renderer; the core's numba and SciPy load with the core's own modules anyway).
CHEAP_LAYERS = ("csuas.base", "csuas.defaults", "csuas.core")

#: (file, module) -> why that function-level import of a cheap layer stays inside its function.
#: May only shrink: a new lazy import of base, defaults or core fails, and so does a listed one that is gone.
LAZY_CHEAP_IMPORTS = {
    ("csuas/cli.py", "csuas.base.fileio"): "NumPy is imported only after the interrupt handlers are in place",
}


def _statement_modules(node: ast.Import | ast.ImportFrom, package: list[str]) -> list[str]:
    """The modules one import statement names, relative ones resolved against ``package``."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if node.level > 0:
        return _relative(node, package)
    return [f"csuas.{alias.name}" for alias in node.names] if node.module == "csuas" else [node.module or ""]


def _lazy_cheap_imports(root: Path = ROOT) -> set[tuple[str, str]]:
    """``{(file, module)}`` of every import of a cheap layer inside a function."""
    found = set()
    for folder in FOLDERS:
        for path in sorted((root / folder).rglob("*.py")):
            rel, package = str(path.relative_to(root)), _package_of(path, root)
            for function in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    continue
                for node in ast.walk(function):
                    if isinstance(node, (ast.Import, ast.ImportFrom)):
                        for module in _statement_modules(node, package):
                            if any(module == layer or module.startswith(f"{layer}.") for layer in CHEAP_LAYERS):
                                found.add((rel, module))
    return found


def test_cheap_layers_are_imported_at_module_level():
    found = _lazy_cheap_imports()
    assert found - set(LAZY_CHEAP_IMPORTS) == set(), "function-level imports of base, defaults or core"
    assert set(LAZY_CHEAP_IMPORTS) - found == set(), "gone: remove them from LAZY_CHEAP_IMPORTS"


@pytest.mark.parametrize(
    "text",
    [
        "def f():\n    from csuas.core import units\n",
        "def f():\n    import csuas.defaults\n",
        "class C:\n    def m(self):\n        from ...base.errors import ParameterError\n",
    ],
)
def test_a_planted_lazy_import_of_a_cheap_layer_fails_the_check(package_copy, text):
    planted = package_copy / "render" / "rcs" / "planted.py"
    planted.write_text(text, encoding="utf-8")
    try:
        assert {rel for rel, _ in _lazy_cheap_imports(package_copy) - set(LAZY_CHEAP_IMPORTS)} == {
            "render/rcs/planted.py"
        }
    finally:
        planted.unlink()
    assert _lazy_cheap_imports(package_copy) - set(LAZY_CHEAP_IMPORTS) == set()
