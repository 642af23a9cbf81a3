"""The flying-wing delta preset against its stated dimensions, closed-form volumes and its target preset."""

import json
import math

import numpy as np
import pytest
from test_fixed_wing import _cli_json, _target

from csuas.base.errors import ParameterError
from csuas.drone_models import build_drone
from csuas.drone_models.materials import MATERIALS, T_SUAS_K
from csuas.drone_models.presets import FIXED_WING_MOTOR_EXCESS_K, preset_parameters
from csuas.drone_models.silhouette import projected_metrics

PRESET = "small_delta_wing"


@pytest.mark.parametrize("style", ["disc", "blades", "none"])
def test_parts_are_closed_and_named_uniquely(style):
    drone = build_drone(PRESET, style)
    names = [p.name for p in drone.parts]
    assert len(set(names)) == len(names)
    for part in drone.parts:
        assert part.mesh.is_watertight and part.mesh.is_winding_consistent and part.mesh.volume > 0, part.name
        assert part.material.name in MATERIALS
    assert (style == "none") == ("propeller" not in names)


def test_span_length_and_height_are_the_stated_ones_exactly():
    _, params, spec = preset_parameters(PRESET)
    extents = build_drone(PRESET).extents()
    assert extents == pytest.approx([spec["length_m"], spec["span_m"], spec["height_m"]], abs=1e-12)
    # the straight trailing edge: root leading edge + root chord = tip leading edge + tip chord
    assert params.wing_leading_edge_x_m - params.root_chord_m == pytest.approx(
        params.wing_leading_edge_x_m - params.leading_edge_sweep_m - params.tip_chord_m, abs=1e-12
    )


def test_wing_half_is_the_frustum_of_its_similar_sections():
    """Root and tip sections are rectangles c x (t/c) c: the hull is a frustum, V = h/3 (A1 + A2 + sqrt(A1 A2))."""
    _, params, _ = preset_parameters(PRESET)
    ratio, half = params.wing_thickness_ratio, params.span_m / 2.0
    a1, a2 = ratio * params.root_chord_m**2, ratio * params.tip_chord_m**2
    volume = half / 3.0 * (a1 + a2 + math.sqrt(a1 * a2))
    assert build_drone(PRESET).part("wing_left").mesh.volume == pytest.approx(volume, rel=1e-12)


def test_target_preset_carries_the_mesh_side_view_the_computed_rcs_and_the_motor_heat():
    from csuas.core.radiometry import band_radiance
    from csuas.defaults import load_drone_rcs_statistics

    target, drone = _target(PRESET), build_drone(PRESET)
    side = projected_metrics(drone, 90.0, 0.0)
    assert target["d_crit_m"] == pytest.approx(side["d_crit_min_m"], rel=1e-3)
    assert target["projected_area_m2"] == pytest.approx(side["projected_area_m2"], rel=1e-3)
    assert target["sigma_lidar_m2"] == pytest.approx(0.1 * target["projected_area_m2"], rel=1e-3)
    assert target["mass_g"] == pytest.approx(1000.0 * preset_parameters(PRESET)[2]["mass_kg"])
    rows = [r for r in load_drone_rcs_statistics() if r["preset"] == PRESET]
    at_24 = next(r for r in rows if r["frequency_ghz"] == 24.0 and r["polarisation"] == "VV")
    assert target["sigma_radar_m2"] == pytest.approx(10.0 ** (at_24["mean_dbsm"] / 10.0), rel=5e-3)
    without = projected_metrics([p.mesh for p in drone.parts if p.name != "motor"], 90.0, 0.0)["projected_area_m2"]
    share = (side["projected_area_m2"] - without) / side["projected_area_m2"]
    eps = drone.part("motor").material.emissivity_lwir
    gain = share * eps * (band_radiance(T_SUAS_K + FIXED_WING_MOTOR_EXCESS_K, "lwir") - band_radiance(T_SUAS_K, "lwir"))
    rise = target["emissivity_suas"] * (band_radiance(target["t_suas_k"], "lwir") - band_radiance(T_SUAS_K, "lwir"))
    assert rise == pytest.approx(gain, rel=0.02)


def test_layouts_that_cannot_meet_the_box_are_refused():
    with pytest.raises(ParameterError, match="height_m"):
        build_drone(PRESET, height_m=0.15)  # below the 8-inch disc's top
    with pytest.raises(ParameterError, match="length_m"):
        build_drone(PRESET, length_m=0.7)  # not the nose-to-propeller length of the layout
    with pytest.raises(ParameterError, match="dihedral_deg"):
        build_drone(PRESET, dihedral_deg=5.0)


def test_range_against_the_mini_follows_the_papers_scaling_laws(capsys):
    """`delta_wing` over `default`: EO, TIR linear in d_crit, acoustic 10^(dSL/20), radar sigma^(1/4) (Eqs. 44, 80)."""
    delta = _cli_json(capsys, ["range", "delta_wing"])["sensors"]
    mini = _cli_json(capsys, ["range", "default"])["sensors"]
    dw, mn = _target(PRESET), _target("dji_mini_4_pro")
    expected = {
        "eo": dw["d_crit_m"] / mn["d_crit_m"],
        "tir": dw["d_crit_m"] / mn["d_crit_m"],
        "acoustic": 10.0 ** ((dw["sl_db"] - mn["sl_db"]) / 20.0),
        "radar": (dw["sigma_radar_m2"] / mn["sigma_radar_m2"]) ** 0.25,
    }
    for sensor, ratio in expected.items():
        assert delta[sensor]["range_m"] / mini[sensor]["range_m"] == pytest.approx(ratio, rel=1e-9), sensor
    pd = _cli_json(capsys, ["pd", "delta_wing", "--range-m", "100", "1000"])["sensors"]
    assert pd["eo"]["deterministic_range_m"] == pytest.approx(delta["eo"]["range_m"], rel=1e-12)


def test_rcs_of_the_preset_uses_its_part_materials(capsys):
    result = _cli_json(capsys, ["rcs", PRESET, "--frequency-ghz", "10", "--quality", "draft"])
    assert set(result["materials"]) == {p.material.name for p in build_drone(PRESET).parts}
    assert np.isfinite(result["rcs_dbsm"]) and result["error_db"] > 0.0


@pytest.mark.slow
def test_eo_render_nose_on_shows_the_span(tmp_path, capsys):
    result = _cli_json(
        capsys, ["render", "eo", "delta_wing", "--range-m", "300", "--quality", "draft", "--out", str(tmp_path)]
    )["results"][0]
    pixel_m = 300.0 * result["ifov_rad"]
    front = projected_metrics(build_drone(PRESET), 0.0, 0.0)
    assert result["pixels_across_x"] * pixel_m == pytest.approx(front["d_x_proj_m"], rel=1e-3)  # the 1 m span


@pytest.mark.slow
def test_tir_render_side_on_sees_the_height(tmp_path, capsys):
    argv = ["render", "tir", "delta_wing", "--range-m", "60", "--azimuth-deg", "90", "--quality", "draft"]
    result = _cli_json(capsys, [*argv, "--out", str(tmp_path)])["results"][0]
    assert result["d_crit_rendered_m"] == pytest.approx(0.22, rel=0.02)  # the 0.22 m height (Eq. 1, side view)


@pytest.mark.slow
def test_dataset_labels_a_box_as_wide_as_the_span(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text(
        'seed = 2\ncount = 1\nscenario = "delta_wing"\ndrones = ["small_delta_wing"]\nrange_m = [250.0]\n'
        'azimuth_deg = [0.0]\nelevation_deg = [0.0]\nposition = "centre"\n'
    )
    assert _cli_json(capsys, ["dataset", str(spec), "--out", str(tmp_path / "d")])["images"] == 1
    coco = json.loads((tmp_path / "d" / "annotations.json").read_text())
    assert [c["name"] for c in coco["categories"]] == [PRESET]
    ifov = _cli_json(capsys, ["range", "delta_wing"])["sensors"]["eo"]["terms"]["ifov_rad"]["value"]
    assert coco["annotations"][0]["bbox"][2] == pytest.approx(1.0 / (250.0 * ifov), abs=3.0)


def test_drone_json_and_the_pusher_s_rotor(capsys):
    from csuas.render.rcs.micro_doppler import drone_rotors

    result = _cli_json(capsys, ["drone", PRESET])
    assert result["bbox_m"] == pytest.approx([0.585, 1.0, 0.22], abs=1e-12)
    (rotor,), _ = drone_rotors(PRESET)  # the pusher turns about x (tests/test_micro_doppler_axis.py)
    assert rotor.spin_axis.tolist() == [1.0, 0.0, 0.0]
