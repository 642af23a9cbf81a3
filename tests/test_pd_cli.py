"""``csuas pd`` and ``csuas pd-radar``: public JSON keys, every embedded scenario, bad input exits 2."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from csuas.cli import main
from csuas.core.radar_detection import pd_exact
from csuas.core.scenario import embedded_scenarios, load_scenario


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


# Issue 24, section 2: what the approach model got wrong (each failed on main at 1833a22).

#: The 4/3-Earth radio horizon of a 2 m sensor and a 120 m target, sqrt(2 k a h1) + sqrt(2 k a h2) [m].
RADIO_HORIZON_2_120_M = math.sqrt(2 * 4 / 3 * 6_371_000.0 * 2.0) + math.sqrt(2 * 4 / 3 * 6_371_000.0 * 120.0)


def _default_radar():
    p = load_scenario("default").sensors["radar"].params
    assert (p["swerling"], p["integration"], p["looks"]) == (1, "coherent", "independent")  # the closed form below
    return p


def _radar_pd(range_m, r_star, p):
    """Coherent Swerling 1: one pulse at N chi, Pd = Pfa^(1 / (1 + N chi)); N chi = snr_min_db at R*, R^-4 (Eq. 80)."""
    snr = 10 ** (p["snr_min_db"] / 10) * (r_star / np.asarray(range_m)) ** 4
    return p["pfa"] ** (1.0 / (1.0 + snr))


def test_median_first_detection_is_a_look_of_the_discrete_distribution(capsys):
    """Main interpolated 42.2 m between two looks; the median of the first-detection distribution is a look."""
    out = _json(capsys, ["pd", "default", "--approach-speed-m-s", "15"])
    p, radar = _default_radar(), out["sensors"]["radar"]
    looks = out["range_m"][-1] - 15.0 / p["look_rate_hz"] * np.arange(int(out["range_m"][-1] / 15.0) + 1)
    cumulative = 1.0 - np.cumprod(1.0 - _radar_pd(looks, radar["deterministic_range_m"], p))
    j = int(np.argmax(cumulative >= 0.5))  # the first look by which detection has happened with P >= 0.5
    assert cumulative[j - 1] < 0.5 <= cumulative[j]
    assert radar["median_first_detection_range_m"] == pytest.approx(looks[j], rel=1e-12)
    assert 30.0 < looks[j] < 45.0


def test_k_of_n_fuses_the_approach_by_its_rule(capsys):
    """Main fused the approach by OR under a k-of-n:2 label; exact enumeration of the 2^6 sensor subsets."""
    out = _json(capsys, ["pd", "default", "--fusion", "k-of-n:2", "--approach-speed-m-s", "15"])
    c = np.array([s["cumulative_pd"] for s in out["sensors"].values()])
    at_least_two = np.zeros(c.shape[1])
    for detected in itertools.product([False, True], repeat=len(c)):
        if sum(detected) >= 2:
            at_least_two += np.prod([ci if d else 1 - ci for ci, d in zip(c, detected)], axis=0)
    np.testing.assert_allclose(out["fused"]["cumulative_pd"], at_least_two, atol=1e-12)
    assert "approach_note" not in out["fused"]


def test_approach_stops_at_the_horizon_and_false_alarms_are_labelled(capsys, tmp_path, monkeypatch):
    """Main's fused median first detection was 367 km (RF beyond its 51 km horizon), false alarms an unlabelled 0.22."""
    import matplotlib.figure

    figures = []
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", lambda fig, *a, **k: figures.append(fig))
    out = _json(capsys, ["pd", "default", "--approach-speed-m-s", "15", "--plot", str(tmp_path / "pd.png")])
    grid = np.array(out["range_m"])
    assert RADIO_HORIZON_2_120_M - 1.5 <= out["fused"]["median_first_detection_range_m"] <= RADIO_HORIZON_2_120_M
    assert np.all(np.array(out["sensors"]["rf"]["pd"])[grid > RADIO_HORIZON_2_120_M] == 0.0)
    # the acoustic sensor (no horizon) looks at 10 Hz from the grid's end: n(R) looks at or beyond R
    acoustic, pfa = out["sensors"]["acoustic"], load_scenario("default").sensors["acoustic"].params["pfa"]
    looks_by = np.floor((grid[-1] - grid) / 1.5 + 1e-9) + 1
    np.testing.assert_allclose(acoustic["false_alarm_cumulative_pd"], 1 - (1 - pfa) ** looks_by, rtol=1e-9)
    labels = [t.get_text() for t in figures[0].axes[1].get_legend().get_texts()]
    assert "acoustic: false alarms alone" in labels


def test_range_at_pd_is_solved_on_the_model_with_a_short_list(capsys):
    """Main interpolated between 8 given ranges; the model's own crossing, against closed forms."""
    out = _json(capsys, ["pd", "default", "--range-m", "10", "20", "50", "100", "200", "500", "1000", "2000"])
    p, radar = _default_radar(), out["sensors"]["radar"]
    snr_90 = math.log(p["pfa"]) / math.log(0.9) - 1.0  # Pfa^(1/(1+S)) = 0.9
    r90 = radar["deterministic_range_m"] * (10 ** (p["snr_min_db"] / 10) / snr_90) ** 0.25
    assert radar["range_at_pd"]["0.9"] == pytest.approx(r90, rel=1e-7)
    # thermal TTPF: P = x^E / (1 + x^E), E = 2.7 + 0.7 x, x = R50 / R (Holst 2008), R50 = R* at p_desired 0.5
    x90 = brentq(lambda x: x ** (2.7 + 0.7 * x) / (1 + x ** (2.7 + 0.7 * x)) - 0.9, 1.0, 10.0, xtol=1e-14)
    tir = out["sensors"]["tir"]
    assert load_scenario("default").sensors["tir"].params["p_desired"] == 0.5
    assert tir["range_at_pd"]["0.9"] == pytest.approx(tir["deterministic_range_m"] / x90, rel=1e-7)
