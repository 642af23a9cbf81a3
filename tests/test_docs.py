"""Every citation a user meets can be followed: docs/ pages exist, no citation of team-only notes."""

import re
import subprocess
from pathlib import Path

import pytest

from csuas.cli import COMMANDS, build_parser

ROOT = Path(__file__).resolve().parents[1]
TEAM_NOTES = re.compile(r"\bSPEC \d|\bSPEC\.md\b|\bORACLES\b")


def _tracked_text_files():
    names = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True).stdout.split()
    if not names:  # not a git checkout (an sdist): walk the tree
        names = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*") if p.is_file() and ".venv" not in p.parts]
    return [ROOT / n for n in names if re.search(r"\.(py|md|toml|sh)$", n) and n != "tests/test_docs.py"]


def test_nothing_cites_the_teams_design_notes():
    offenders = [
        f"{p.relative_to(ROOT)}:{i}"
        for p in _tracked_text_files()
        for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
        if TEAM_NOTES.search(line)
    ]
    assert offenders == []


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_no_help_text_cites_the_teams_design_notes(command):
    parser = build_parser(command)
    sub = next(a for a in parser._actions if a.dest == "command").choices[command]
    assert not TEAM_NOTES.search(parser.format_help() + sub.format_help())


def test_every_cited_docs_page_exists():
    cited = {
        m.group(0)
        for p in _tracked_text_files()
        for m in re.finditer(r"docs/[a-z-]+\.md", p.read_text(encoding="utf-8"))
    }
    assert cited, "the code cites its docs"
    assert sorted(c for c in cited if not (ROOT / c).is_file()) == []


def test_every_cited_convention_point_is_a_heading():
    headings = set(re.findall(r"^## Point (\d+):", (ROOT / "docs" / "conventions.md").read_text(), re.M))
    cited = {
        m.group(1)
        for p in _tracked_text_files()
        for m in re.finditer(r"docs/conventions\.md points? (\d+)", p.read_text(encoding="utf-8"))
    }
    assert cited and cited <= headings, sorted(cited - headings)
    assert headings == {str(n) for n in range(1, len(headings) + 1)}
