"""The quality ladder is declared once per simulator (csuas.base.quality, csuas.render.quality) and every list of
rung names, preset and --quality help comes from it."""

import ast
import re
from pathlib import Path

import pytest
from pydantic import TypeAdapter, ValidationError

from csuas.base.errors import ParameterError
from csuas.base.quality import RUNGS, QualityLadder, Setting
from csuas.base.registry import resolve
from csuas.render.quality import LADDERS

ROOT = Path(__file__).resolve().parents[1]

#: The one place that types the rung names as a collection.
DECLARATION = ("base/quality.py", "RUNGS")


def _code_files():
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT)
        if rel.parts[0] in ("tests", ".venv", "build") or any(p.endswith(".egg-info") for p in rel.parts):
            continue
        yield rel, ast.parse(path.read_text(encoding="utf-8"))


def _names(nodes) -> set:
    return {n.value for n in nodes if isinstance(n, ast.Constant) and isinstance(n.value, str)}


def test_no_list_of_rung_names_is_typed_outside_the_declaration():
    """A tuple, list, set, dict or call naming all three rungs is RUNGS itself, or it drifts."""
    typed = []
    for rel, tree in _code_files():
        for node in ast.walk(tree):
            if isinstance(node, ast.Dict):
                elements = node.keys
            elif isinstance(node, (ast.Tuple, ast.List, ast.Set)):
                elements = node.elts
            elif isinstance(node, ast.Call):
                elements = node.args
            else:
                continue
            if set(RUNGS) <= _names(elements):
                typed.append(f"{rel}:{node.lineno}")
    assert typed == [f"{DECLARATION[0]}:{_line_of(DECLARATION)}"]


def _line_of(declaration) -> int:
    path, name = declaration
    tree = ast.parse((ROOT / path).read_text(encoding="utf-8"))
    return next(n.lineno for n in tree.body if isinstance(n, ast.Assign) and n.targets[0].id == name)


def test_rung_keywords_are_only_the_checked_ones():
    """Per-rung values named by keyword go through QualityLadder or its per_rung check, nothing else."""
    calls = []
    for _rel, tree in _code_files():
        for node in ast.walk(tree):
            if isinstance(node, ast.Call) and set(RUNGS) <= {k.arg for k in node.keywords}:
                func = node.func
                calls.append(func.attr if isinstance(func, ast.Attribute) else func.id)
    assert set(calls) == {"QualityLadder", "per_rung"}
    assert calls.count("QualityLadder") == len(LADDERS)


@pytest.mark.parametrize("reference", LADDERS)
def test_every_ladder_has_the_three_rungs_and_a_value_per_knob(reference):
    ladder = resolve(reference)
    assert ladder.names == RUNGS == ("draft", "standard", "reference")
    for rung in RUNGS:
        assert list(ladder.values(rung)) == [s.name for s in ladder.settings]
    with pytest.raises(ParameterError, match="quality.*best.*draft, standard, reference"):
        ladder.values("best")


def test_a_ladder_missing_a_value_or_a_rung_fails_on_import():
    knobs = (Setting("a", "one"), Setting("b", "two"))
    with pytest.raises(TypeError, match="rung standard has 1 values for 2 settings"):
        QualityLadder("x", "y", knobs, draft=(1, 2), standard=(1,), reference=(1, 2))
    with pytest.raises(TypeError):  # a rung left out
        QualityLadder("x", "y", knobs, draft=(1, 2), standard=(1, 2))
    with pytest.raises(TypeError):  # a rung that is not one
        QualityLadder("x", "y", knobs, draft=(1, 2), standard=(1, 2), reference=(1, 2), best=(1, 2))
    ladder = QualityLadder("x", "y", knobs, draft=(1, 2), standard=(3, 4), reference=(5, 6))
    with pytest.raises(TypeError, match="not the rungs"):
        ladder.per_rung(draft=1, standard=2)
    with pytest.raises(TypeError, match="not the rungs"):
        ladder.per_rung(draft=1, reference=3, standard=2)  # cheapest first
    assert ladder.per_rung(draft=1, standard=2, reference=3) == {"draft": 1, "standard": 2, "reference": 3}


def _help(command: str) -> str:
    from csuas.cli import build_parser

    parser = build_parser(command)
    sub = next(a for a in parser._actions if a.dest == "command").choices[command]
    return " ".join(sub.format_help().split())


def test_the_rcs_help_states_the_presets_the_solver_runs():
    """csuas rcs --help once said draft 4/3, standard 10/5, reference 20/8; the solver ran 2/3, 5/5, 10/8."""
    from csuas.render.rcs.solver import resolve_quality

    text = _help("rcs")
    for rung in RUNGS:
        rays, bounces = resolve_quality(rung)
        assert f"{rung} {rays:g} rays per wavelength, {bounces} bounces" in text


def test_the_render_help_states_the_samples_the_renderers_use():
    from csuas.render.imaging.quality import resolve_quality
    from csuas.render.lidar.cross_section import resolve_quality as lidar_quality

    text = _help("render")
    for rung in RUNGS:
        spp = resolve_quality(rung).n_side ** 2 * resolve_quality(rung).n_batches
        grid, replicates, _ = lidar_quality(rung)
        assert f"{rung} {spp:,} samples per pixel" in text
        assert f"{rung} {grid}^2 x {replicates} rays" in text
    assert re.search(r"draft 32 samples per pixel; standard 128 samples per pixel; reference 2,048", text)


def test_the_sweep_and_dataset_schemas_allow_exactly_the_rungs():
    from csuas.render.imaging.dataset_schema import DatasetSchema
    from csuas.sweep.schema import QUALITY

    adapter = TypeAdapter(QUALITY)
    assert [adapter.validate_python(rung) for rung in RUNGS] == list(RUNGS)
    with pytest.raises(ValidationError, match="draft, standard or reference"):
        adapter.validate_python("best")
    for rung in RUNGS:
        assert DatasetSchema.model_validate({"quality": rung}).quality == rung
    with pytest.raises(ValidationError, match="quality\n  Value error, draft, standard or reference"):
        DatasetSchema.model_validate({"quality": "best"})
