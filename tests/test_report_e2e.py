"""End to end: ``csuas report --quick`` on the embedded defaults (every registered check, about 40 s on 2 cores)."""

import json
import re
from html.parser import HTMLParser

import pytest

from csuas import cli
from csuas.validation.report.baseline import compare
from csuas.validation.report.runner import all_specs

SPEC8_KEYS = {"name", "expected", "measured", "tolerance", "ok", "known_deviation", "time_s"}


class _Images(HTMLParser):
    def __init__(self):
        super().__init__()
        self.sources = []

    def handle_starttag(self, tag, attrs):
        self.sources += [v for k, v in attrs if tag == "img" and k == "src"]


@pytest.mark.slow
def test_quick_report_end_to_end(tmp_path, capsys):
    out = tmp_path / "report"
    code = cli.main(["report", "--quick", "--out", str(out), "--json"])
    captured = capsys.readouterr()
    result = json.loads(captured.out)
    failed = [
        (c["name"], c["details"].get("error"), c["expected"], c["measured"], c["tolerance"])
        for c in result["checks"]
        if c["verdict"] == "FAIL"
    ]
    assert failed == [] and code == 0 and result["exit_code"] == 0
    # progress: one line per registered check on standard error
    assert all(f"] {spec.name} ..." in captured.err for spec in all_specs())
    data = json.loads((out / "report.json").read_text())
    assert data["checks"] == result["checks"]
    assert all(SPEC8_KEYS <= set(c) for c in data["checks"])
    # every known deviation carries its explanation, nothing fails silently
    for c in data["checks"]:
        assert c["ok"] or c["known_deviation"] or c["limitation"], c["name"]
        assert c["tolerance_source"], c["name"]
    # no tolerance of a passing check in linear units is wider than 20 % of what it judges
    wide = [
        (c["name"], c["expected"], c["tolerance"])
        for c in data["checks"]
        if c["verdict"] == "ok"
        and not c["unit"].startswith("dB")
        and c["expected"]
        and c["tolerance"] > 0.2 * abs(c["expected"])
    ]
    assert wide == []
    # the 3GPP drone RCS and the lidar albedo are limits of csuas's models, not deviations of the paper
    verdicts = {c["name"]: c["verdict"] for c in data["checks"]}
    assert verdicts["T8.sigma_lidar_m2.dji_mini_4_pro.raytraced"] == "limit"
    assert verdicts["rcs.dji_mini_4_pro.mean_of_dbsm.3gpp_tr38901"] in ("ok", "limit")
    for name in ("report.html", "report.md"):
        # embedded PNGs are base64, whose alphabet can spell "None": look at the text only
        text = re.sub(r"data:image/png;base64,[A-Za-z0-9+/=]+", "", (out / name).read_text())
        found = [r for r in ("None", "{'", "np.float64(", "= -<") if r in text]
        assert found == [], name
    names = {c["name"] for c in data["checks"]}
    for expected in (
        "T47.eta_tl",
        "conv.2.delta_t.lwir.simulated",
        "links.rf.free_space.max_error_db",
        "links.radar.free_space.max_error_db",
        "rcs.canonical.trihedral_square.dbsm",
        "rcs.dji_mini_4_pro.mean_dbsm.table8",
        "lidar.oracle.plate_normal.lcs_m2",
        "T8.sigma_lidar_m2.dji_mini_4_pro.raytraced",
        "T8.d_crit_m.dji_mini_4_pro",
        "imaging.johnson_range_m",
        "conv.1.eo_contrast_range.simulated",
        "worked.eo.baseline_m",
    ):
        assert expected in names
    sections = {s["name"]: s for s in data["sections"]}
    assert all(s["error"] is None for s in sections.values())
    assert all(len(sections[f"conv.{n}"]["table"]) >= 1 for n in range(1, 11))
    assert len(sections["imaging.gallery"]["figures"]) == 6
    parser = _Images()
    parser.feed((out / "report.html").read_text())
    assert len(parser.sources) >= 20 and all(s.startswith("data:image/png;base64,") for s in parser.sources)
    assert "Known deviations of the paper" in (out / "report.md").read_text()
    # the report is its own baseline without regressions; one drifted figure is named
    assert compare(data["checks"], data["checks"])["regressions"] == []
    drifted = json.loads(json.dumps(data["checks"]))
    target = next(c for c in drifted if c["name"] == "imaging.johnson_range_m")
    target["measured"] += 2 * target["tolerance"]
    assert [r["name"] for r in compare(drifted, data["checks"])["regressions"]] == ["imaging.johnson_range_m"]
