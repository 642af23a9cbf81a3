"""``csuas report`` on a test-only registry subset: docs/command-line.md keys, baseline regressions, exceptions, HTML.

The subset holds fast, exact checks (the analytic-core defaults, docs/conventions.md
point 6) and synthetic specs (a passing figure with a plot, a known
deviation, a check that raises), so the machinery is tested in seconds; the
whole quick report runs in ``test_report_e2e.py``.
"""

import base64
import copy
import json
import math
from html.parser import HTMLParser

import numpy as np
import pytest

from csuas import cli
from csuas.base.checks import Check
from csuas.base.errors import ParameterError
from csuas.validation.report import checks_conventions, checks_links, checks_rcs, runner
from csuas.validation.report.baseline import compare
from csuas.validation.report.checks_conventions import SPECS as CONVENTION_SPECS
from csuas.validation.report.checks_defaults import SPECS as DEFAULT_SPECS
from csuas.validation.report.figures import PlotAxes, curves
from csuas.validation.report.registry import CheckSpec, Section, run_spec

SPEC8_KEYS = {"name", "expected", "measured", "tolerance", "ok", "known_deviation", "time_s"}
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _passing(_knob):
    x = np.linspace(1.0, 10.0, 20)
    fig = curves(
        "test_curve",
        "1/x",
        axes=PlotAxes("x", "y"),
        lines=[("1/x", x, 1 / x)],
        points=[("samples", x[::5], 1 / x[::5], 0.01 * np.ones(4))],
    )
    return Section(
        outcomes=[Check("synthetic.sqrt2", math.sqrt(2.0), 1.41421, 1e-5, "-", error_estimate=1e-6)], figures=[fig]
    )


def _known(_knob):
    return Section(outcomes=[Check("synthetic.known", 20.0, 21.07, 0.05, "dB", known_deviation="rounded in the paper")])


def _raises(_knob):
    raise RuntimeError("boom: the simulator is broken")


PASSING = CheckSpec(
    "synthetic.pass",
    "passing figure with a plot",
    checks_links.GROUP,
    "sqrt(2) vs 1.41421",
    "1e-5",
    _passing,
    "digits",
    {"quick": 6, "full": 9},
)
KNOWN = CheckSpec("synthetic.known", "known deviation", checks_conventions.GROUP, "20 vs 21.07 dB", "0.05 dB", _known)
RAISES = CheckSpec("synthetic.raises", "a check that raises", checks_rcs.GROUP, "nothing", "none", _raises)
FAST_REAL = [DEFAULT_SPECS[0], next(s for s in CONVENTION_SPECS if s.name == "conv.6")]


@pytest.fixture(scope="module")
def good_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("good")
    report = runner.run_report("quick", out, specs=FAST_REAL + [PASSING, KNOWN])
    return out, report


def test_exit_zero_when_every_check_passes_or_is_known(good_report):
    out, report = good_report
    assert report["exit_code"] == 0
    s = report["summary"]
    assert s["failed"] == 0 and s["known_deviation"] >= 2 and s["ok"] + s["known_deviation"] == s["total"]
    assert {"report.html", "report.json", "report.md"} <= {p.name for p in out.iterdir()}


def test_json_checks_have_the_keys_of_spec_8(good_report):
    out, report = good_report
    data = json.loads((out / "report.json").read_text())
    assert data["checks"] and data["checks"] == json.loads(json.dumps(report["checks"]))
    for check in data["checks"]:
        assert SPEC8_KEYS <= set(check)
        assert isinstance(check["ok"], bool) and check["time_s"] >= 0
        assert check["known_deviation"] is None or isinstance(check["known_deviation"], str)
    by_name = {c["name"]: c for c in data["checks"]}
    assert by_name["synthetic.sqrt2"]["ok"] and by_name["synthetic.sqrt2"]["known_deviation"] is None
    assert not by_name["synthetic.known"]["ok"] and by_name["synthetic.known"]["known_deviation"]
    # the defaults check records keep their verdicts (Table 32's 20 dB array gain is a known deviation)
    assert by_name["T32.g_array"]["verdict"] == "known"
    assert by_name["T16.sigma_fog.light"]["ok"]


class _Resources(HTMLParser):
    def __init__(self):
        super().__init__()
        self.refs = []

    def handle_starttag(self, tag, attrs):
        self.refs += [(tag, k, v) for k, v in attrs if k in ("src", "href", "srcset", "data")]


def test_html_is_self_contained_with_embedded_pngs(good_report):
    out, _ = good_report
    text = (out / "report.html").read_text()
    parser = _Resources()
    parser.feed(text)
    images = [v for tag, k, v in parser.refs if tag == "img"]
    assert images, "no embedded image"
    for _tag, key, value in parser.refs:
        if key == "href":
            assert value.startswith("#"), f"external link {value!r}"
        else:
            assert value.startswith("data:image/png;base64,"), f"external resource {value!r}"
    for value in images:
        assert base64.b64decode(value.split(",", 1)[1])[:8] == PNG_SIGNATURE
    assert "<link" not in text and "@import" not in text and "url(" not in text
    assert "docs/conventions.md point 6" in text and "Defaults check" in text and "Time of each check" in text


def test_markdown_summary_lists_known_deviations(good_report):
    out, _ = good_report
    md = (out / "report.md").read_text()
    assert "known deviations" in md and "synthetic.known" in md and "| conv.6 |" in md


def test_exception_in_a_check_is_reported_not_raised(tmp_path):
    report = runner.run_report("quick", tmp_path, specs=[PASSING, RAISES])
    failed = [c for c in report["checks"] if c["verdict"] == "FAIL"]
    assert [c["name"] for c in failed] == ["synthetic.raises.error"]
    assert "boom: the simulator is broken" in failed[0]["details"]["error"]
    assert failed[0]["known_deviation"] is None and not failed[0]["ok"]
    assert report["exit_code"] == 1
    assert "boom: the simulator is broken" in (tmp_path / "report.html").read_text()
    assert any(c["name"] == "synthetic.sqrt2" and c["ok"] for c in report["checks"])


def test_run_spec_rejects_a_wrong_return_type():
    section = run_spec(CheckSpec("bad", "bad", checks_rcs.GROUP, "-", "-", lambda _k: {"not": "a section"}), "quick")
    assert section.error and "not a Section" in section.error and not section.outcomes[0].ok


def test_outcome_verdicts():
    assert Check("a", 1.0, 1.05, 0.1).verdict == "ok"
    assert Check("a", 1.0, 1.5, 0.1).verdict == "FAIL"
    assert Check("a", 1.0, 1.5, 0.1, known_deviation="why").verdict == "known"
    assert not Check("a", 1.0, math.nan, 0.1).ok and not Check("a", math.inf, math.inf, 0.1).ok


def test_perturbed_figure_fails_the_baseline(good_report):
    _, report = good_report
    old = copy.deepcopy(report["checks"])
    assert compare(report["checks"], old)["regressions"] == []
    perturbed = copy.deepcopy(report["checks"])
    target = next(c for c in perturbed if c["name"] == "T16.sigma_fog.light")
    target["measured"] += 3 * target["tolerance"]
    regressions = compare(perturbed, old)["regressions"]
    assert [r["name"] for r in regressions] == ["T16.sigma_fog.light"]
    assert "measured moved" in regressions[0]["what"]
    # within the tolerance it is not a regression
    original = next(c for c in old if c["name"] == "T16.sigma_fog.light")
    target["measured"] = original["measured"] + 0.5 * target["tolerance"]
    assert compare(perturbed, old)["regressions"] == []


def test_baseline_names_missing_and_newly_failing_checks(good_report):
    _, report = good_report
    old = copy.deepcopy(report["checks"])
    new = [c for c in copy.deepcopy(report["checks"]) if c["name"] != "synthetic.known"]
    sqrt2 = next(c for c in new if c["name"] == "synthetic.sqrt2")
    sqrt2["ok"], sqrt2["verdict"] = False, "FAIL"
    whats = {r["name"]: r["what"] for r in compare(new, old)["regressions"]}
    assert whats == {"synthetic.known": "missing from the new report", "synthetic.sqrt2": "passed before, fails now"}


def test_cli_report_with_a_perturbed_baseline_exits_1_and_names_it(good_report, tmp_path, monkeypatch, capsys):
    out, _ = good_report
    data = json.loads((out / "report.json").read_text())
    next(c for c in data["checks"] if c["name"] == "synthetic.sqrt2")["expected"] += 1.0
    baseline = tmp_path / "old.json"
    baseline.write_text(json.dumps(data))
    monkeypatch.setattr(runner, "all_specs", lambda: FAST_REAL + [PASSING, KNOWN])
    code = cli.main(["report", "--quick", "--out", str(tmp_path / "new"), "--baseline", str(baseline), "--json"])
    captured = capsys.readouterr()
    result = json.loads(captured.out)
    assert code == 1 and result["exit_code"] == 1
    assert [r["name"] for r in result["baseline"]["regressions"]] == ["synthetic.sqrt2"]
    assert "REGRESSION synthetic.sqrt2" in captured.err and "synthetic.pass" in captured.err  # progress lines
    assert all(SPEC8_KEYS <= set(c) for c in result["checks"])
    # the unperturbed baseline passes
    code = cli.main(["report", "--out", str(tmp_path / "again"), "--baseline", str(out / "report.json")])
    assert code == 0 and "0 regression(s)" in capsys.readouterr().out


def test_bad_baseline_is_a_clear_error(tmp_path, capsys):
    with pytest.raises(ParameterError, match="baseline"):
        runner.run_report("quick", tmp_path, baseline=tmp_path / "absent.json", specs=[PASSING])
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    assert cli.main(["report", "--out", str(tmp_path / "x"), "--baseline", str(bad)]) == 2
    assert "baseline" in capsys.readouterr().err
    assert not (tmp_path / "x" / "report.html").exists()


def test_quality_is_validated(tmp_path):
    with pytest.raises(ParameterError, match="quality"):
        runner.run_report("medium", tmp_path, specs=[PASSING])


def test_registry_declares_every_check():
    specs = runner.all_specs()
    names = [s.name for s in specs]
    assert len(names) == len(set(names))
    assert {f"conv.{n}" for n in range(1, 11)} <= set(names)
    for s in specs:
        assert s.compares and s.tolerance_why and callable(s.run)
        if s.simulated:
            assert s.knob and set(s.knob_values) == {"quick", "full"}, s.name


def _check(name, expected, measured, tolerance, **extra):
    return {
        "name": name,
        "expected": expected,
        "measured": measured,
        "tolerance": tolerance,
        "ok": True,
        "known_deviation": None,
        "unit": "dB",
        **extra,
    }


def test_a_figure_moving_toward_its_reference_is_an_improvement_not_a_regression():
    from csuas.validation.report.baseline import compare

    old = [_check("err", 0.0, 1.0, 0.01), _check("drift", 5.0, 5.0, 0.01), _check("gone", 1.0, 1.0, 0.1)]
    new = [_check("err", 0.0, 3e-6, 0.01), _check("drift", 5.0, 5.5, 0.01), _check("fresh", 1.0, 1.0, 0.1)]
    result = compare(new, old)
    assert [r["name"] for r in result["improvements"]] == ["err"]
    assert sorted(r["name"] for r in result["regressions"]) == ["drift", "gone"]
    assert result["new_checks"] == ["fresh"] and result["missing_checks"] == ["gone"]


def test_new_missing_and_improved_checks_are_named_in_console_html_and_markdown():
    from csuas.commands.report import render_text
    from csuas.validation.report.html import render_html, render_markdown

    baseline = {
        "file": "old.json",
        "quality": "quick",
        "compared": 3,
        "regressions": [],
        "improvements": [
            {"name": "err", "what": "measured moved by -1 dB", "old": 1.0, "new": 3e-6, "tolerance": 0.01}
        ],
        "new_checks": ["fresh"],
        "missing_checks": ["gone"],
    }
    report = {
        "quality": "quick",
        "generated_utc": "now",
        "machine": "m",
        "version": "v",
        "time_s": 1.0,
        "summary": {"total": 0, "ok": 0, "known_deviation": 0, "limitation": 0, "failed": 0},
        "groups": [],
        "checks": [],
        "sections": [],
        "baseline": baseline,
        "exit_code": 0,
        "files": {},
    }
    for text in (render_text(report), render_html(report, []), render_markdown(report)):
        assert "fresh" in text and "gone" in text and "improvement" in text and "err" in text


def test_report_values_are_spelled_out_never_as_python_reprs():
    from csuas.validation.report.html import fmt, knob_text

    assert fmt(None) == "\u2014"
    assert fmt({"rays_per_wavelength": 3.0, "max_bounces": 2}) == "rays_per_wavelength = 3, max_bounces = 2"
    assert knob_text(None, None) == "exact (no accuracy knob)"
    assert knob_text("samples", [64, 256]) == "samples = 64, 256"


def test_two_reports_into_one_folder_at_once_are_refused(tmp_path):
    from csuas.base.errors import ParameterError
    from csuas.base.fileio import exclusive_lock
    from csuas.validation.report.runner import LOCK_NAME, run_report

    with exclusive_lock(tmp_path / LOCK_NAME, "--out"), pytest.raises(ParameterError, match="lock"):
        run_report("quick", tmp_path, specs=[])


def test_an_interrupted_report_leaves_no_old_report_json_beside_new_figures(tmp_path):
    from csuas.validation.report.registry import CheckSpec, Figure, Section
    from csuas.validation.report.runner import run_report

    (tmp_path / "report.json").write_text('{"checks": []}')
    (tmp_path / "figures").mkdir()
    (tmp_path / "figures" / "old_plot.png").write_bytes(b"old")

    def interrupted(_):
        raise KeyboardInterrupt

    def plot(_):
        return Section(figures=[Figure("new_plot", "new", b"png")])

    with pytest.raises(KeyboardInterrupt):
        run_report(
            "quick",
            tmp_path,
            specs=[
                CheckSpec("a", "a", checks_rcs.GROUP, "x", "y", plot),
                CheckSpec("b", "b", checks_rcs.GROUP, "x", "y", interrupted),
            ],
        )
    assert not (tmp_path / "report.json").exists()
    report = run_report("quick", tmp_path, specs=[CheckSpec("a", "a", checks_rcs.GROUP, "x", "y", plot)])
    assert sorted(p.name for p in (tmp_path / "figures").iterdir()) == ["new_plot.png"]
    assert report["figures"] == ["figures/new_plot.png"]


def test_the_fitted_contrast_crossing_error_covers_the_true_error():
    """Monte Carlo: noisy Koschmieder contrasts; 3 standard errors must cover |R - R_true| in >= 99 % of trials."""
    from csuas.validation.report.checks_conventions import contrast_crossing_m

    rng = np.random.default_rng(7)
    ranges = np.array([40.0, 80.0, 120.0, 160.0, 200.0, 260.0])
    c0, beta, c_min = 0.09, 9.78e-3, 0.05  # beta per metre: fog of 400 m visibility
    truth = math.log(c0 / c_min) / beta
    clean = c0 * np.exp(-beta * ranges)
    stderr = 0.004 * np.ones_like(ranges)
    errors, sigmas = [], []
    for _ in range(2000):
        r, se, _ = contrast_crossing_m(ranges, clean + rng.normal(0.0, stderr), stderr, c_min)
        errors.append(r - truth)
        sigmas.append(se)
    errors, sigmas = np.array(errors), np.array(sigmas)
    assert np.mean(np.abs(errors) <= 3 * sigmas) >= 0.99
    assert 0.7 < np.std(errors) / np.median(sigmas) < 1.3  # the estimate is neither loose nor tight
