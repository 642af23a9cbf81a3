"""The report's HTML layout: a contents table with counts, text shared by a table printed once, folding
sections, and plot labels that never print over each other (issue 22, section 6)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from csuas.base.checks import Check
from csuas.validation.report import checks_lidar, checks_rcs, runner
from csuas.validation.report.registry import CheckSpec, Section

SHARED_TOLERANCE = "three standard errors of the ray-traced estimate (shared by every row)"


def _rcs_checks(_knob):
    """3 passing, 1 failed, 2 known deviations, 1 limitation; one tolerance source for all, one method each."""
    made = [(1.0, 1.0, {}), (2.0, 2.0, {}), (3.0, 3.0, {}), (1.0, 9.0, {})]
    made += [(1.0, 5.0, {"known_deviation": "the paper's rounding"})] * 2
    made += [(1.0, 5.0, {"limitation": "no edge waves"})]
    return Section(
        outcomes=[
            Check(f"layout.rcs.{i}", e, m, 0.1, tolerance_source=SHARED_TOLERANCE, method=f"method number {i}", **kw)
            for i, (e, m, kw) in enumerate(made)
        ]
    )


def _lidar_checks(_knob):
    return Section(outcomes=[Check("layout.lidar.a", 1.0, 1.0, 0.1), Check("layout.lidar.b", 1.0, 1.0, 0.1)])


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    specs = [
        CheckSpec("layout.rcs", "RCS rows", checks_rcs.GROUP, "a", "spec-level tolerance text", _rcs_checks),
        CheckSpec("layout.lidar", "lidar rows", checks_lidar.GROUP, "b", "c", _lidar_checks),
    ]
    out = tmp_path_factory.mktemp("report")
    runner.run_report("quick", out, specs=specs)
    return (out / "report.html").read_text(encoding="utf-8")


def _contents_row(page: str, group: str) -> list[str]:
    row = re.search(rf"<tr><td><a href='#{group}'>.*?</tr>", page).group(0)
    return re.findall(r"<td class='num[^']*'>([^<]*)</td>", row)


def test_the_contents_table_counts_each_sections_checks_by_verdict(page):
    assert "<th>checks</th><th>passed</th><th>failed</th><th>known deviations</th><th>limitations</th>" in page
    assert _contents_row(page, "rcs")[:5] == ["7", "3", "1", "2", "1"]
    assert _contents_row(page, "lidar")[:5] == ["2", "2", "0", "0", "0"]
    assert "href='#terrain'" not in page  # only the groups run are listed


def test_text_every_row_shares_is_printed_once_and_differing_text_per_row(page):
    body = page.split("id='rcs'")[1]  # the group itself (the failed check is also listed at the top)
    assert body.count(SHARED_TOLERANCE) == 1
    assert all(body.count(f"method number {i}") == 1 for i in range(7))
    assert page.count("spec-level tolerance text") == 1  # under the heading only, not again per row


def test_every_group_folds_and_says_its_counts(page):
    for group in ("rcs", "lidar"):
        assert f"<details class='group' id='{group}' open>" in page
    assert "id='imaging'" not in page
    assert "7 checks: 3 passed, 1 failed, 2 known deviations, 1 limitations</span>" in page
    assert page.count("<details class='group'") == page.count("</details>") - page.count("<details class='rows'")


def _placed_boxes(ax, renderer):
    return [a.get_window_extent(renderer) for a in ax.texts]


def test_crowded_point_labels_are_placed_apart_or_counted_as_left_out():
    """12 points within a few pixels of each other: no two placed labels overlap, none covers another point."""
    from csuas.validation.report.figures import _label_points, _pyplot

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(4.0, 3.0), dpi=90)
    x = np.linspace(1.0, 1.05, 12)
    y = np.linspace(1.0, 1.06, 12)
    ax.plot(x, y, "o")
    ax.set_xlim(0.5, 1.5)
    ax.set_ylim(0.5, 1.5)
    labels = [(f"knob {i}", xi, yi, "black") for i, (xi, yi) in enumerate(zip(x, y))]
    left_out = _label_points(ax, labels, list(zip(x, y)))
    renderer = fig.canvas.get_renderer()
    boxes = _placed_boxes(ax, renderer)
    assert len(boxes) + left_out == 12 and 0 < len(boxes) < 12
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])
    inside = ax.get_window_extent(renderer)
    assert all(inside.x0 <= b.x0 and b.x1 <= inside.x1 and inside.y0 <= b.y0 and b.y1 <= inside.y1 for b in boxes)
    plt.close(fig)


def test_spread_point_labels_are_all_placed():
    from csuas.validation.report.figures import _label_points, _pyplot

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(4.0, 3.0), dpi=90)
    x = y = np.array([1.0, 2.0, 3.0, 4.0])
    ax.plot(x, y, "o")
    ax.set_xlim(0.0, 5.0)
    ax.set_ylim(0.0, 5.0)
    assert _label_points(ax, [(str(v), v, v, "black") for v in x], list(zip(x, y))) == 0
    assert [t.get_text() for t in ax.texts] == ["1.0", "2.0", "3.0", "4.0"]
    plt.close(fig)
