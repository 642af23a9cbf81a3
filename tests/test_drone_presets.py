"""Drone presets against their published specifications, parts, materials and Eqs. 1, 2, 8, 9."""

import csv
from pathlib import Path

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.drone_models import build_drone, get_material, list_presets
from csuas.drone_models import parts as P
from csuas.drone_models.materials import MATERIALS, PAPER_EMISSIVITY_RANGES, paper_component_mean_emissivity
from csuas.drone_models.multirotor import MultirotorParams, build_multirotor
from csuas.drone_models.parts import radial_layout
from csuas.drone_models.signature import critical_dimension, lcs_estimate, sphere_equivalent_radius
from csuas.drone_models.silhouette import projected_metrics

STYLES = ("disc", "blades", "none")
SPECS_FILE = Path(__file__).parent / "reference" / "drone_specs.csv"


def published_specs():
    """preset -> row of tests/reference/drone_specs.csv (after the units row)."""
    with SPECS_FILE.open(encoding="utf-8") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    assert rows[0]["length_x"] == "m" and rows[0]["mass"] == "kg"  # units row
    return {r["preset"]: r for r in rows[1:]}


SPECS = published_specs()


def spec_values(preset, *keys):
    return [float(SPECS[preset][k]) for k in keys]


@pytest.fixture(scope="module")
def mini():
    return build_drone("dji_mini_4_pro")


def test_list_presets_names():
    assert set(list_presets()) == {
        "dji_mini_4_pro",
        "dji_mavic_3",
        "black_hornet_3",
        "euclid_class_fixed_wing",
        "small_delta_wing",
    }


def test_mini_4_pro_bbox_within_1_percent_of_spec(mini):
    assert SPECS["dji_mini_4_pro"]["configuration"] == "unfolded_with_propellers"
    np.testing.assert_allclose(
        mini.extents(), spec_values("dji_mini_4_pro", "length_x", "width_y", "height_z"), rtol=0.01
    )
    assert mini.mass_kg == pytest.approx(spec_values("dji_mini_4_pro", "mass")[0])


def test_mini_4_pro_origin_at_bbox_centre(mini):
    b = mini.bounds()
    np.testing.assert_allclose(b[0] + b[1], 0.0, atol=1e-15)


def test_mavic_3_bbox_without_propellers_within_1_percent():
    drone = build_drone("dji_mavic_3")
    assert SPECS["dji_mavic_3"]["configuration"] == "unfolded_without_propellers"
    spec = spec_values("dji_mavic_3", "length_x", "width_y", "height_z")
    np.testing.assert_allclose(drone.extents(exclude_kinds=("propeller",)), spec, rtol=0.01)
    np.testing.assert_allclose(build_drone("dji_mavic_3", "none").extents(), spec, rtol=0.01)
    assert drone.mass_kg == pytest.approx(spec_values("dji_mavic_3", "mass")[0])
    assert drone.extents()[0] > drone.extents(exclude_kinds=("propeller",))[0] + 0.2  # 9.4-inch discs overhang


def test_black_hornet_3_dimensions():
    drone = build_drone("black_hornet_3")
    length, width, height = drone.extents()
    spec_length, spec_rotor, spec_mass = spec_values("black_hornet_3", "length_x", "width_y", "mass")
    assert length == pytest.approx(spec_length, rel=0.01)  # about 168 mm long
    assert width == pytest.approx(spec_rotor, rel=0.01)  # 123 mm rotor, the widest part
    assert drone.mass_kg == pytest.approx(spec_mass)
    assert {p.kind for p in drone.parts} >= {"body", "propeller", "tail_boom", "tail_rotor", "mast"}


def test_mini_side_view_d_crit_min_within_3_percent_of_table_8(mini):
    m = projected_metrics(mini, 90.0, 0.0)
    assert m["d_crit_min_m"] == pytest.approx(0.101, rel=0.03)
    assert m["d_x_proj_m"] == pytest.approx(0.298, rel=0.01)  # seen from the side: length x height
    front = projected_metrics(mini, 0.0, 0.0)
    assert front["d_x_proj_m"] == pytest.approx(0.373, rel=0.01)
    assert front["d_crit_min_m"] == pytest.approx(0.101, rel=0.03)


def test_black_hornet_3_side_view_d_crit_within_10_percent_of_table_52():
    m = projected_metrics(build_drone("black_hornet_3"), 90.0, 0.0)
    assert m["d_crit_min_m"] == pytest.approx(0.025, rel=0.10)


@pytest.mark.parametrize("preset", ["dji_mini_4_pro", "dji_mavic_3", "black_hornet_3"])
@pytest.mark.parametrize("style", STYLES)
def test_every_part_is_watertight_and_named_uniquely(preset, style):
    drone = build_drone(preset, style)
    names = [p.name for p in drone.parts]
    assert len(set(names)) == len(names)
    for part in drone.parts:
        assert part.mesh.is_watertight, part.name
        assert part.mesh.is_winding_consistent, part.name
        assert part.mesh.volume > 0, part.name
        assert part.material.name in MATERIALS
    assert (style == "none") == (not any(p.kind == "propeller" for p in drone.parts))


def test_blades_fit_inside_the_swept_discs():
    discs = build_drone("dji_mini_4_pro", "disc")
    blades = build_drone("dji_mini_4_pro", "blades")
    b_d, b_b = discs.bounds(), blades.bounds()
    assert np.all(b_b[0] >= b_d[0] - 1e-12) and np.all(b_b[1] <= b_d[1] + 1e-12)
    top_d = projected_metrics(discs, 0, 90)["projected_area_m2"]
    top_b = projected_metrics(blades, 0, 90)["projected_area_m2"]
    assert top_b < top_d


def test_bad_preset_and_style_raise():
    with pytest.raises(ParameterError, match="preset"):
        build_drone("dji_phantom_99")
    with pytest.raises(ParameterError, match="propellers"):
        build_drone("dji_mini_4_pro", "ducted")


def test_generic_hexacopter_rotor_count():
    layout = radial_layout(6, 0.3, z_m=0.05, phase_deg=0.0)
    params = MultirotorParams(
        body_extents_m=(0.2, 0.2, 0.08),
        body_center_m=(0, 0, 0.06),
        rotor_positions_m=layout,
        propeller_diameter_m=0.25,
        arm_profile="tube",
        arm_width_m=0.02,
    )
    drone = build_multirotor("hex", params, 3.0)
    assert sum(p.kind == "propeller" for p in drone.parts) == 6
    assert sum(p.kind == "arm" for p in drone.parts) == 6
    # rotors on a 0.3 m circle with 0.25 m discs: x extent = 2 * (0.3 + 0.125)
    assert drone.extents()[0] == pytest.approx(0.85, rel=1e-9)
    with pytest.raises(ParameterError, match="n_rotors"):
        radial_layout(0, 0.3)


def test_part_primitive_errors():
    with pytest.raises(ParameterError, match="corner_radius"):
        P.rounded_box([0, 0, 0], [0.1, 0.1, 0.02], 0.02)
    with pytest.raises(ParameterError, match="radius"):
        P.cylinder_between([0, 0, 0], [0, 0, 1], -1.0)
    with pytest.raises(ParameterError, match="end"):
        P.cylinder_between([0, 0, 0], [0, 0, 0], 1.0)
    with pytest.raises(ParameterError, match="bar axis"):
        P.bar_between([0, 0, 0], [0, 0, 1], 0.01, 0.01)


def test_rounded_box_has_exact_extents():
    mesh = P.rounded_box([0.1, 0.2, 0.3], [0.12, 0.08, 0.05], 0.01)
    np.testing.assert_allclose(mesh.extents, [0.12, 0.08, 0.05], rtol=1e-12)
    assert mesh.is_convex


def test_material_emissivities_are_mid_points_of_paper_ranges():
    for name, (lo, hi) in PAPER_EMISSIVITY_RANGES.items():
        assert get_material(name).emissivity_lwir == pytest.approx((lo + hi) / 2)
    # Section 4.4.3: (0.95 + 0.82 + 0.075 + 0.875) / 4 = 0.68
    assert paper_component_mean_emissivity() == pytest.approx(0.68, abs=1e-12)
    with pytest.raises(ParameterError, match="material"):
        get_material("unobtainium")


def test_material_radio_properties():
    al = get_material("aluminium")
    eps0 = 8.8541878128e-12
    eps = al.complex_permittivity(10.0)
    assert eps.imag == pytest.approx(-3.5e7 / (2 * np.pi * 10e9 * eps0), rel=1e-12)
    assert get_material("pec").is_pec
    plastic = get_material("plastic").complex_permittivity(2.4)
    assert plastic == pytest.approx(complex(2.8, -0.03))
    for m in MATERIALS.values():
        assert m.temperature_k == pytest.approx(288.15)  # Table 8 T_sUAS
    with pytest.raises(ParameterError, match="frequency_ghz"):
        al.complex_permittivity(0.0)


def test_mesh_emissivity_summary(mini):
    e = mini.emissivity("lwir")
    assert 0.075 < e["area_weighted"] < 0.95
    assert e["paper_component_mean"] == pytest.approx(0.68)
    surfaces = [p for p in mini.parts if p.kind != "propeller"]
    manual = sum(p.mesh.area * p.material.emissivity_lwir for p in surfaces) / sum(p.mesh.area for p in surfaces)
    assert e["area_weighted"] == pytest.approx(manual, rel=1e-12)
    with pytest.raises(ParameterError, match="band"):
        mini.emissivity("uv")


def test_eq1_eq2_eq8_eq9():
    assert critical_dimension(0.298, 0.101, "min") == pytest.approx(0.101)
    assert critical_dimension(0.298, 0.101, "geometric_mean") == pytest.approx(np.sqrt(0.298 * 0.101))
    np.testing.assert_allclose(critical_dimension([0.1, 0.3], [0.2, 0.0]), [0.1, 0.0])
    # Table 8: k_LCS = 0.1, T_illum = 1 and sigma = 0.006 m^2 <=> A_p = 0.06 m^2
    assert lcs_estimate(0.06) == pytest.approx(0.006)
    assert lcs_estimate(0.06, k_lcs=0.1, t_illum=0.5) == pytest.approx(0.003)
    assert sphere_equivalent_radius(np.pi * 0.138**2) == pytest.approx(0.138)
    with pytest.raises(ParameterError, match="t_illum"):
        lcs_estimate(0.06, t_illum=1.5)
    with pytest.raises(ParameterError, match="k_lcs"):
        lcs_estimate(0.06, k_lcs=0.0)
    with pytest.raises(ParameterError, match="method"):
        critical_dimension(0.1, 0.1, "mean")
    with pytest.raises(ParameterError):
        critical_dimension(-0.1, 0.1)


def test_parameter_overrides():
    # blades turned across (+y) reach the swept-disc edge: the specified width
    across = build_drone("dji_mini_4_pro", "blades", blade_phase_deg=90.0)
    assert across.extents()[1] == pytest.approx(spec_values("dji_mini_4_pro", "width_y")[0], rel=1e-9)
    repainted = build_drone("dji_mini_4_pro", materials={"body": "plastic"})
    assert repainted.part("body").material.name == "plastic"
    assert repainted.part("arm_0_front_left").material.name == "carbon_fibre"  # other kinds keep the preset's
    with pytest.raises(ParameterError, match="wings"):
        build_drone("dji_mini_4_pro", wings=2)
    with pytest.raises(ParameterError, match="material"):
        build_drone("black_hornet_3", materials={"body": "balsa"})


def test_single_rotor_above_the_body_has_no_arm():
    params = MultirotorParams(
        body_extents_m=(0.1, 0.1, 0.05),
        body_center_m=(0, 0, 0.025),
        rotor_positions_m=((0.0, 0.0, 0.05),),
        propeller_diameter_m=0.2,
    )
    drone = build_multirotor("coaxial", params, 0.1)
    assert not any(p.kind == "arm" for p in drone.parts)
    assert drone.extents()[:2] == pytest.approx([0.2, 0.2], rel=1e-9)
