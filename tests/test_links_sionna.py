"""Sionna RT links against closed forms written here: Friis (Eq. 54), radar equation (Eq. 68),
two-ray and four-path models over ITU-R P.2040 grounds (Table 3 in tests/reference).

Tolerances: Sionna's amplitudes are float32 (1e-7 relative, 1e-6 dB); the phases come from float64
path lengths whose only error is second order in the float32 reflection points (< 1e-5 rad here).
The measured errors are below 3e-5 dB; the asserted ones keep a wide margin: 0.05 dB (Friis,
as asked), 0.1 dB (radar equation), and over ground 1e-4 of the direct ray's amplitude on the complex
sum (which stays meaningful inside nulls, where dB are not) plus 0.01 dB where the sum is within 20 dB
of the direct ray.
"""

import csv
import json
import os

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.render.links.budget import LinkBudget

pytestmark = pytest.mark.slow

C = 299_792_458.0
REFERENCE = os.path.join(os.path.dirname(__file__), "reference", "links_itu_p2040_table3.csv")


def itu_eta(material, f_ghz):
    """Complex relative permittivity from the transcribed ITU-R P.2040-3 Table 3."""
    with open(REFERENCE) as handle:
        rows = [r for r in csv.DictReader(line for line in handle if not line.startswith("#"))]
    row = next(r for r in rows if r["material"] == material)
    eps = float(row["a"]) * f_ghz ** float(row["b"])
    sigma = float(row["c"]) * f_ghz ** float(row["d"])
    return eps - 1j * sigma / (2 * np.pi * f_ghz * 1e9 * 8.8541878128e-12)


def r_tm(cos_i, eta):
    root = np.sqrt(eta - (1 - cos_i**2))
    return (eta * cos_i - root) / (eta * cos_i + root)


def leg(x, h_a, h_b, lam, eta, bounce):
    """Scalar field factor of one vertical-plane leg, V polarisation: g e^{-jkL}/L."""
    if not bounce:
        length = np.hypot(x, h_a - h_b)
        return np.exp(-2j * np.pi * length / lam) / length
    length = np.hypot(x, h_a + h_b)
    return r_tm((h_a + h_b) / length, eta) * np.exp(-2j * np.pi * length / lam) / length


@pytest.fixture(scope="module")
def links():
    from csuas.render.links import radar, rf

    return rf, radar


def test_sionna_runs_on_the_variant_csuas_selects():
    from csuas.render.backend import cuda_available
    from csuas.render.links.sionna_backend import active_variant, load_sionna_rt

    rt = load_sionna_rt()
    import mitsuba as mi

    expected = "cuda_ad_mono_polarized" if cuda_available() else "llvm_ad_mono_polarized"
    assert mi.variant() == active_variant() == expected
    mi.set_variant("llvm_ad_rgb")  # another renderer switches ...
    assert load_sionna_rt() is rt and mi.variant() == expected  # ... and the links switch back


@pytest.mark.parametrize("f_ghz", [1.0, 2.4, 10.0, 24.0, 40.0])
def test_free_space_path_gain_is_friis(links, f_ghz):
    rf, _ = links
    d = np.array([10.0, 100.0, 1e3, 1e4, 5e4])
    result = rf.rf_path_gain(f_ghz, d, tx_height_m=50.0, rx_height_m=50.0)  # one call, all distances
    friis = -20 * np.log10(4 * np.pi * d / (C / (f_ghz * 1e9)))
    assert np.all(result.n_paths == 1)
    np.testing.assert_allclose(result.path_gain_db, friis, atol=0.05)
    assert result.time_s > 0


@pytest.mark.parametrize("f_ghz, material", [(2.4, "medium_dry_ground"), (24.0, "concrete"), (5.0, "metal")])
def test_path_gain_over_ground_is_two_ray_with_lobes(links, f_ghz, material):
    rf, _ = links
    h_t, h_r = 30.0, 2.0
    d = np.geomspace(10.0, 5e4, 41)
    result = rf.rf_path_gain(f_ghz, d, h_t, h_r, ground=material, budget="draft")
    lam = C / (f_ghz * 1e9)
    eta = itu_eta(material, f_ghz)
    direct = lam / (4 * np.pi) * leg(d, h_t, h_r, lam, eta, False)
    expected = direct + lam / (4 * np.pi) * leg(d, h_t, h_r, lam, eta, True)
    assert np.all(result.n_paths == 2)
    measured = result.coefficients.sum(-1)
    assert np.max(np.abs(measured - expected) / np.abs(direct)) < 1e-4
    away_from_nulls = np.abs(expected) > 0.1 * np.abs(direct)
    np.testing.assert_allclose(
        result.path_gain_db[away_from_nulls], 20 * np.log10(np.abs(expected[away_from_nulls])), atol=0.01
    )
    lobing = result.path_gain_db - 20 * np.log10(np.abs(direct))
    assert lobing.max() > 3.0 and lobing.min() < -10.0  # above and below Friis: two-ray lobes


def test_ground_material_outside_its_frequency_range(links):
    rf, _ = links
    with pytest.raises(ParameterError, match="frequency_ghz"):
        rf.rf_path_gain(24.0, 100.0, ground="medium_dry_ground")  # ITU: 1-10 GHz only


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"frequency_ghz": 0.05}, "frequency_ghz"),
        ({"frequency_ghz": 101.0}, "frequency_ghz"),
        ({"frequency_ghz": float("nan")}, "frequency_ghz"),
        ({"distance_m": 0.0}, "distance_m"),
        ({"distance_m": [10.0, np.inf]}, "distance_m"),
        ({"distance_m": 2e6}, "distance_m"),
        ({"ground": "lava"}, "ground"),
        ({"ground": "concrete", "rx_height_m": 0.0}, "rx_height_m"),
        ({"tx_height_m": -1.0}, "tx_height_m"),
        ({"polarization": "X"}, "polarization"),
        ({"budget": LinkBudget("custom", 0, 1)}, "samples"),
        ({"budget": "best"}, "budget"),
    ],
)
def test_rf_bad_input(links, kwargs, name):
    rf, _ = links
    args = {"frequency_ghz": 2.4, "distance_m": 100.0, **kwargs}
    with pytest.raises(ParameterError, match=name):
        rf.rf_path_gain(**args)


@pytest.mark.parametrize("f_ghz", [2.4, 24.0])
def test_radar_link_free_space_is_radar_equation(links, f_ghz):
    _, radar = links
    ranges = np.array([10.0, 100.0, 500.0, 1e3, 1e4])
    result = radar.radar_link_gain(f_ghz, ranges, radar_height_m=5.0, target_height_m=5.0)
    lam = C / (f_ghz * 1e9)
    eq68 = 10 * np.log10(lam**2 * 0.01 / ((4 * np.pi) ** 3 * ranges**4))  # sigma = 0.01 m^2 (Table 8)
    assert np.all(result.n_paths == 1)
    np.testing.assert_allclose(result.path_gain_db, eq68, atol=0.1)


def test_radar_link_reads_the_rcs_table_at_the_radar_aspect(links):
    from csuas.render.links.rcs_table import RCSTable

    _, radar = links
    az = np.arange(0.0, 360.0, 15.0)
    el = np.array([-45.0, 0.0, 45.0])
    sigma = np.outer(0.001 * (1.0 + az / 15.0), [1.0, 1.0, 1.0])  # 0.001 m^2 at 0 deg ... 0.024 at 345
    ranges = np.array([200.0, 2000.0])
    result = radar.radar_link_gain(
        10.0, ranges, 20.0, 20.0, target=radar.RadarTarget(RCSTable(az, el, sigma), azimuth_deg=-30.0)
    )
    lam = C / 10e9
    sigma_330 = 0.001 * (1.0 + 330.0 / 15.0)  # -30 deg is the 330 deg node
    np.testing.assert_allclose(
        result.path_gain_db, 10 * np.log10(lam**2 * sigma_330 / ((4 * np.pi) ** 3 * ranges**4)), atol=0.01
    )
    result = radar.radar_link_gain(
        10.0, ranges, 20.0, 20.0, target=radar.RadarTarget(lambda a, e: 0.5 + 0 * a, azimuth_deg=10.0)
    )
    np.testing.assert_allclose(
        result.path_gain_db, 10 * np.log10(lam**2 * 0.5 / ((4 * np.pi) ** 3 * ranges**4)), atol=0.01
    )


@pytest.mark.parametrize("f_ghz, material", [(2.4, "medium_dry_ground"), (24.0, "concrete")])
def test_radar_link_over_ground_is_four_path_model(links, f_ghz, material):
    _, radar = links
    h_radar, h_drone, sigma = 5.0, 30.0, 0.01
    ranges = np.geomspace(20.0, 2e4, 41)
    result = radar.radar_link_gain(
        f_ghz, ranges, h_radar, h_drone, radar.RadarTarget(sigma), ground=material, budget="draft"
    )
    lam = C / (f_ghz * 1e9)
    eta = itu_eta(material, f_ghz)
    amplitude = lam * np.sqrt(sigma) / (4 * np.pi) ** 1.5
    direct = amplitude * leg(ranges, h_radar, h_drone, lam, eta, False) ** 2
    one_way = leg(ranges, h_radar, h_drone, lam, eta, False) + leg(ranges, h_radar, h_drone, lam, eta, True)
    expected = amplitude * one_way**2  # (direct + ground)^2: the four paths
    assert np.all(result.n_paths == 4)
    measured = result.coefficients.sum(-1)
    assert np.max(np.abs(measured - expected) / np.abs(direct)) < 1e-4
    lobing = result.path_gain_db - 20 * np.log10(np.abs(direct))
    assert lobing.max() > 3.0 and lobing.min() < -10.0


def test_radar_bad_input(links):
    _, radar = links
    with pytest.raises(ParameterError, match="rcs"):
        radar.radar_link_gain(10.0, 100.0, target=radar.RadarTarget(-1.0))
    with pytest.raises(ParameterError, match="target_height_m"):
        radar.radar_link_gain(10.0, 100.0, target_height_m=0.02, ground="concrete")
    with pytest.raises(ParameterError, match="rcs"):
        radar.radar_link_gain(10.0, 100.0, target=radar.RadarTarget(lambda a, e: np.full(np.shape(a), np.nan)))


def test_accuracy_vs_time_rows(links):
    from csuas.render.links.budget import LinkBudget
    from csuas.validation.links.accuracy import accuracy_vs_time

    budgets = (LinkBudget("one_ray", 1, 1), LinkBudget("draft", 16, 1))
    rows = accuracy_vs_time("rf", 2.4, (100.0, 1000.0), 30.0, 2.0, "medium_dry_ground", budgets, repeats=1)
    assert [r["budget"] for r in rows] == ["one_ray", "draft"]
    assert rows[0]["paths_found"] == 1 and rows[0]["max_error_db"] > 1.0  # one ray misses the ground
    assert rows[1]["paths_found"] == 2 and rows[1]["max_error_db"] < 1e-3
    assert all(r["time_s"] > 0 and r["cold_time_s"] > 0 for r in rows)


def test_cli_pathloss(capsys):
    from csuas.cli import main

    assert (
        main(
            [
                "pathloss",
                "--frequency-ghz",
                "2.4",
                "--distance-m",
                "100",
                "1000",
                "--tx-height-m",
                "30",
                "--rx-height-m",
                "2",
                "--ground",
                "medium_dry_ground",
                "--budget",
                "draft",
                "--json",
            ]
        )
        == 0
    )
    out = json.loads(capsys.readouterr().out)
    assert len(out["path_gain_db"]) == len(out["friis_db"]) == len(out["time_s"]) == len(out["two_ray_db"]) == 2
    np.testing.assert_allclose(out["path_gain_db"], out["two_ray_db"], atol=0.01)
    assert main(["pathloss", "--frequency-ghz", "24", "--distance-m", "500", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert "two_ray_db" not in out and isinstance(out["time_s"], float)
    assert abs(out["path_gain_db"] - out["friis_db"]) < 0.05
    assert main(["pathloss", "--frequency-ghz", "24", "--distance-m", "500"]) == 0
    assert "Friis" in capsys.readouterr().out
    for bad in (
        ["--frequency-ghz", "150", "--distance-m", "5"],
        ["--frequency-ghz", "2", "--distance-m", "-1"],
        ["--frequency-ghz", "0.5", "--distance-m", "5", "--ground", "concrete"],
    ):
        assert main(["pathloss", *bad]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "invalid" in err


def test_bench_links_structure():
    from csuas.validation.links.bench import SCENES, bench_links

    result = bench_links(repeats=1)
    assert set(result["scenes"]) == set(SCENES)
    for scene in result["scenes"].values():
        assert scene["equal_accuracy"]
        assert scene["sionna_default"]["samples"] == 1_000_000 and scene["sionna_default"]["max_depth"] == 3
        assert scene["speedup"] > 0 and scene["cold_speedup"] > 0
        assert scene["sionna_floor"]["samples"] == 1
        assert scene["sionna_floor"]["max_depth"] == scene["chosen"]["max_depth"]
        assert all(scene[row]["cold_time_s"] > 0 for row in ("chosen", "sionna_default", "sionna_floor"))
        assert scene["speedup_ceiling"] > 0
