"""Report groups come from the check modules that declare them: report.html, report.md and report.json list
exactly the groups of the checks run, a check in a new group gets its own section, and the defaults providers
are wired in one table (issue 23, section 4)."""

import json
import re

import pytest

from csuas.base.checks import Check
from csuas.validation.core.checks import SIMULATION_PROVIDERS
from csuas.validation.report import checks_defaults, checks_lidar, checks_rcs, runner
from csuas.validation.report.registry import CheckGroup, CheckSpec, Section, groups_of

NOVEL = CheckGroup("novel", "A group no table lists", 5, "Checks of a kind the report has never seen.")


def _one(name):
    return lambda _knob: Section(outcomes=[Check(name, 2.0, 2.0, 0.1)])


SPECS = [
    CheckSpec("novel.one", "a check in a new group", NOVEL, "2 vs 2", "0.1", _one("novel.one.value")),
    CheckSpec("lidar.x", "a lidar check", checks_lidar.GROUP, "2 vs 2", "0.1", _one("lidar.x.value")),
    CheckSpec("rcs.x", "an rcs check", checks_rcs.GROUP, "2 vs 2", "0.1", _one("rcs.x.value")),
]


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    out = tmp_path_factory.mktemp("groups")
    runner.run_report("quick", out, specs=SPECS)
    return (
        json.loads((out / "report.json").read_text(encoding="utf-8")),
        (out / "report.html").read_text(encoding="utf-8"),
        (out / "report.md").read_text(encoding="utf-8"),
    )


def test_a_check_in_a_new_group_has_its_own_section_in_json_html_and_markdown(outputs):
    report, page, markdown = outputs
    assert report["groups"][0] == {
        "name": "novel",
        "title": "A group no table lists",
        "order": 5,
        "description": "Checks of a kind the report has never seen.",
    }
    assert [c["group"] for c in report["checks"] if c["name"] == "novel.one.value"] == ["novel"]
    section = page.split("<details class='group' id='novel' open>")[1].split("</details>")[0]
    assert "<h2>A group no table lists</h2>" in section and "Checks of a kind the report has never seen." in section
    assert "novel.one.value" in section and "rcs.x.value" not in section
    assert "<a href='#novel'>A group no table lists</a>" in page  # in the contents
    assert "| A group no table lists | 1 | 1 | 0 | 0 | 0 | Checks of a kind the report has never seen. |" in markdown


def test_the_groups_listed_are_the_groups_run_in_their_order(outputs):
    report, page, markdown = outputs
    run = ["novel", "rcs", "lidar"]  # orders 5, 50, 60; the specs ran novel, lidar, rcs
    assert [g["name"] for g in report["groups"]] == run
    assert re.findall(r"<details class='group' id='([^']+)'", page) == run
    contents = page.split("<h2>Contents</h2>")[1].split("</table>")[0]
    assert re.findall(r"<tr><td><a href='#([^']+)'>", contents) == run
    rows = markdown.split("## Sections")[1].split("\n\n")[1].splitlines()[2:]
    assert [row.split(" | ")[0].lstrip("| ") for row in rows] == [g["title"] for g in report["groups"]]


def test_two_groups_that_share_a_name_or_an_order_are_refused_before_the_work(tmp_path):
    twin = CheckGroup("rcs", "another rcs", 999, "-")
    specs = [SPECS[2], CheckSpec("twin", "twin", twin, "-", "-", _one("twin"))]
    with pytest.raises(ValueError, match="share the name rcs"):
        runner.run_report("quick", tmp_path / "r", specs=specs)
    assert not (tmp_path / "r").exists()
    same_order = CheckGroup("other", "other", checks_rcs.GROUP.order, "-")
    with pytest.raises(ValueError, match=f"share the order {checks_rcs.GROUP.order}"):
        groups_of([SPECS[2], CheckSpec("o", "o", same_order, "-", "-", _one("o"))])
    with pytest.raises(TypeError, match="group 'rcs' is not a CheckGroup"):
        groups_of([CheckSpec("s", "s", "rcs", "-", "-", _one("s"))])


def test_every_registered_group_is_declared_once_with_a_title_and_a_description():
    groups = groups_of(runner.all_specs())  # raises on a clash
    assert [g.name for g in groups] == [
        "defaults",
        "worked_numbers",
        "conventions",
        "links",
        "rcs",
        "micro_doppler",
        "lidar",
        "imaging",
        "detection",
        "terrain",
        "engage",
        "propagation",
        "swarm",
    ]
    assert all(g.title and g.description.endswith(".") for g in groups)


def test_each_defaults_provider_has_its_report_check_and_no_other_wiring():
    """SIMULATION_PROVIDERS is the one table: the report's defaults group runs each of them by name."""
    names = [s.name for s in checks_defaults.SPECS if s.group is checks_defaults.DEFAULTS]
    assert names == ["defaults.core"] + [f"defaults.{name}" for name in SIMULATION_PROVIDERS]
