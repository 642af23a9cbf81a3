"""The scene cache of the Sionna RT links: a cached scene never answers for another one.

Every call is checked against a closed form written here (Friis, Eq. 54; the radar equation,
Eq. 68; the two-ray model over an ITU-R P.2040 ground, Table 3 in tests/reference), so a stale
scene (wrong frequency, ground, target, cross-section or device count) shows up as a wrong
number, and against the same call made with an empty cache (bit for bit).
"""

import csv
import os

import numpy as np
import pytest

pytestmark = pytest.mark.slow

C = 299_792_458.0
REFERENCE = os.path.join(os.path.dirname(__file__), "reference", "links_itu_p2040_table3.csv")


def itu_eta(material, f_ghz):
    """Complex relative permittivity from the transcribed ITU-R P.2040-3 Table 3."""
    with open(REFERENCE) as handle:
        rows = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    row = next(r for r in rows if r["material"] == material)
    eps = float(row["a"]) * f_ghz ** float(row["b"])
    sigma = float(row["c"]) * f_ghz ** float(row["d"])
    return eps - 1j * sigma / (2 * np.pi * f_ghz * 1e9 * 8.8541878128e-12)


def two_ray(f_ghz, d, h_t, h_r, eta):
    """Direct ray and the complex two-ray sum (V polarisation, isotropic antennas)."""
    k = 2 * np.pi * f_ghz * 1e9 / C
    l1, l2 = np.hypot(d, h_t - h_r), np.hypot(d, h_t + h_r)
    cos_i = (h_t + h_r) / l2
    root = np.sqrt(eta - (1 - cos_i**2))
    r_tm = (eta * cos_i - root) / (eta * cos_i + root)
    direct = np.exp(-1j * k * l1) / (2 * k * l1)
    return direct, direct + r_tm * np.exp(-1j * k * l2) / (2 * k * l2)


def friis_db(f_ghz, slant):
    return -20 * np.log10(4 * np.pi * slant * f_ghz * 1e9 / C)


def uncached(function, *args, **kwargs):
    from csuas.render.links.scene import clear_scene_cache

    clear_scene_cache()
    return function(*args, **kwargs)


def assert_same(a, b):
    np.testing.assert_array_equal(a.coefficients, b.coefficients)
    np.testing.assert_array_equal(a.path_gain_db, b.path_gain_db)


def test_new_frequency_or_ground_builds_a_new_scene():
    from csuas.render.links.rf import rf_path_gain

    d = np.array([20.0, 300.0, 4000.0])
    calls = [(5.0, "concrete"), (2.4, "concrete"), (2.4, "medium_dry_ground"), (5.0, "concrete")]
    for f_ghz, ground in calls:  # each call follows one on another scene
        result = rf_path_gain(f_ghz, d, 30.0, 2.0, ground=ground, budget="draft")
        direct, expected = two_ray(f_ghz, d, 30.0, 2.0, itu_eta(ground, f_ghz))
        assert np.max(np.abs(result.coefficients.sum(-1) - expected) / np.abs(direct)) < 1e-4
        assert_same(result, uncached(rf_path_gain, f_ghz, d, 30.0, 2.0, ground=ground, budget="draft"))


def test_free_space_after_ground_has_no_reflection():
    from csuas.render.links.rf import rf_path_gain

    d = np.array([50.0, 500.0])
    rf_path_gain(2.4, d, 10.0, 10.0, ground="metal", budget="draft")
    result = rf_path_gain(2.4, d, 10.0, 10.0, budget="draft")
    assert np.all(result.n_paths == 1)
    np.testing.assert_allclose(result.path_gain_db, friis_db(2.4, d), atol=0.05)


def test_devices_are_moved_added_and_removed():
    from csuas.render.links.rf import rf_path_gain

    for d, h_t in (([10.0, 100.0, 1e3, 1e4], 50.0), ([70.0], 20.0), ([30.0, 3e3, 900.0], 40.0)):
        d = np.asarray(d)
        result = rf_path_gain(2.4, d, h_t, 2.0, budget="draft")  # one scene: free space at 2.4 GHz
        assert result.coefficients.shape[0] == len(d) and np.all(result.n_paths == 1)
        np.testing.assert_allclose(result.path_gain_db, friis_db(2.4, np.hypot(d, h_t - 2.0)), atol=0.05)
        assert_same(result, uncached(rf_path_gain, 2.4, d, h_t, 2.0, budget="draft"))


def test_polarization_is_part_of_the_scene():
    from csuas.render.links.rf import rf_path_gain

    d = np.array([40.0, 400.0])
    v = rf_path_gain(5.0, d, 20.0, 2.0, ground="concrete", budget="draft", polarization="V")
    h = rf_path_gain(5.0, d, 20.0, 2.0, ground="concrete", budget="draft", polarization="H")
    # The ground reflects V and H differently (R_TM != R_TE): the cached V scene must not answer for H.
    assert np.max(np.abs(v.path_gain_db - h.path_gain_db)) > 0.1
    assert_same(h, uncached(rf_path_gain, 5.0, d, 20.0, 2.0, ground="concrete", budget="draft", polarization="H"))


def test_radar_target_height_and_cross_section_follow_each_call():
    from csuas.render.links.radar import RadarTarget, radar_link_gain

    ranges = np.array([20.0, 200.0, 2000.0])
    for h_target, rcs in ((5.0, 0.01), (40.0, 0.01), (40.0, 2.5), (40.0, lambda az, el: np.full(np.shape(az), 0.3))):
        result = radar_link_gain(
            10.0, ranges, radar_height_m=5.0, target_height_m=h_target, target=RadarTarget(rcs), budget="draft"
        )
        sigma = rcs if not callable(rcs) else 0.3
        slant = np.hypot(ranges, h_target - 5.0)
        lam = C / 10e9
        np.testing.assert_allclose(
            result.path_gain_db, 10 * np.log10(lam**2 * sigma / ((4 * np.pi) ** 3 * slant**4)), atol=0.1
        )
        assert_same(
            result,
            uncached(
                radar_link_gain,
                10.0,
                ranges,
                radar_height_m=5.0,
                target_height_m=h_target,
                target=RadarTarget(rcs),
                budget="draft",
            ),
        )


def test_cache_is_bounded():
    from csuas.render.links import scene
    from csuas.render.links.rf import rf_path_gain

    scene.clear_scene_cache()
    for f_ghz in np.linspace(1.0, 3.0, scene.SCENE_CACHE_SIZE + 3):
        rf_path_gain(f_ghz, [100.0], 10.0, 10.0, budget="draft")
    assert len(scene._scene_cache) == scene.SCENE_CACHE_SIZE
