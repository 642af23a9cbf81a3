"""``csuas pd`` and ``csuas pd-radar``: public JSON keys, every embedded scenario, bad input exits 2."""

from __future__ import annotations

import json

import numpy as np
import pytest

from csuas.cli import main
from csuas.core.radar_detection import pd_exact
from csuas.core.scenario import embedded_scenarios


def _json(capsys, argv):
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("name", embedded_scenarios())
def test_pd_runs_on_every_embedded_scenario(capsys, name):
    out = _json(capsys, ["pd", name])
    grid = out["range_m"]
    assert grid[0] == 1.0 and len(grid) == 400
    longest = max(s["deterministic_range_m"] for s in out["sensors"].values())
    assert grid[-1] >= longest
    for sensor in out["sensors"].values():
        assert len(sensor["pd"]) == len(grid)
        assert set(sensor["range_at_pd"]) == {"0.5", "0.9"}
        assert sensor["assumptions"] and sensor["looks"] in ("independent", "correlated")
    assert out["fused"]["rule"] == "or" and len(out["fused"]["pd"]) == len(grid)
    fused, best = np.array(out["fused"]["pd"]), np.max([s["pd"] for s in out["sensors"].values()], axis=0)
    assert np.all(fused >= best - 1e-12)


def test_given_ranges_fusion_rule_and_approach(capsys, tmp_path):
    plot = tmp_path / "pd.png"
    out = _json(
        capsys,
        ["pd", "default", "--range-m", "50", "500", "5000", "--fusion", "k-of-n:2", "--approach-speed-m-s", "20",
         "--plot", str(plot)],
    )  # fmt: skip
    assert out["range_m"] == [50.0, 500.0, 5000.0]
    assert out["fused"]["rule"] == "k-of-n:2"
    for sensor in out["sensors"].values():
        assert len(sensor["cumulative_pd"]) == 3
        assert np.all(np.diff(sensor["cumulative_pd"][::-1]) >= -1e-12)  # grows as the drone closes
        assert "median_first_detection_range_m" in sensor
    assert len(out["fused"]["cumulative_pd"]) == 3 and "median_first_detection_range_m" in out["fused"]
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out["plot"] == str(plot)


def test_text_output_has_a_row_per_sensor_and_the_assumptions(capsys):
    assert main(["pd", "black_hornet"]) == 0
    text = capsys.readouterr().out
    assert all(name in text for name in ("eo", "acoustic", "radar", "fused or", "assumptions:", "Swerling 1"))


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["pd", "default", "--range-m", "-5"], "range_m"),
        (["pd", "default", "--fusion", "majority"], "fusion"),
        (["pd", "default", "--fusion", "k-of-n:9"], "fusion"),
        (["pd", "default", "--approach-speed-m-s", "0"], "approach_speed_m_s"),
        (["pd", "default", "--plot", "out.jpg"], "plot"),
        (["pd-radar", "--snr-db", "10", "--pfa", "1.5"], "pfa"),
        (["pd-radar", "--snr-db", "10", "--pfa", "1e-6", "--n-pulses", "0"], "n_pulses"),
        (["pd-radar", "--snr-db", "10", "--pfa", "1e-6", "--swerling", "5"], "swerling"),
        (["pd-radar", "--pd", "1", "--pfa", "1e-6"], "pd"),
        (["pd-radar", "--snr-db", "10", "--pfa", "1e-6", "--method", "albersheim"], "method"),
    ],
)
def test_bad_input_exits_2_naming_the_parameter(capsys, argv, fragment):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert fragment in err and "Traceback" not in err


def test_pd_radar_both_ways(capsys):
    out = _json(capsys, ["pd-radar", "--snr-db", "13.2", "--pfa", "1e-6", "--n-pulses", "1", "--swerling", "0"])
    assert out["pd"] == pytest.approx(float(pd_exact(13.2, 1e-6, 1, 0)))
    out = _json(capsys, ["pd-radar", "--pd", "0.9", "--pfa", "1e-6", "--swerling", "1"])
    assert out["required_snr_db"] == pytest.approx(21.1, abs=0.05)  # Meyer & Mayer
    out = _json(capsys, ["pd-radar", "--pd", "0.9", "--pfa", "1e-6", "--method", "albersheim"])
    assert out["required_snr_db"] == pytest.approx(13.1, abs=0.05)  # Richards' example
    assert main(["pd-radar", "--pd", "0.9", "--pfa", "1e-6"]) == 0
    assert "required single-pulse SNR" in capsys.readouterr().out
