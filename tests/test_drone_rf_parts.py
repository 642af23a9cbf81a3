"""The multirotors' radar model part by part: materials against closed forms, the part list, the shipped table."""

from __future__ import annotations

import cmath
import csv
import json
import math
import re
from importlib import resources

import pytest

from csuas.cli import main
from csuas.drone_models import build_drone
from csuas.render.rcs import canonical, load_target
from csuas.render.rcs.solver import compute_rcs

C = 299_792_458.0
EPS0 = 8.8541878128e-12
BANDS_GHZ = (2.4, 24.0)
#: Kinds of part the radar model of a multirotor preset must have (issue 26, section 2).
RADAR_KINDS = {
    "body",
    "arm",
    "motor",
    "propeller",
    "gimbal",
    "battery",
    "camera_module",
    "flight_controller",
    "ground_plane",
    "wiring",
}


def total_permittivity(eps: complex, sigma_s_m: float, f_ghz: float) -> complex:
    """eps - j sigma / (omega eps0) (e^{+j omega t})."""
    return eps - 1j * sigma_s_m / (2 * math.pi * f_ghz * 1e9 * EPS0)


def half_space_reflection(eps: complex) -> complex:
    """Fresnel coefficient of a half-space at normal incidence, (1 - sqrt(eps)) / (1 + sqrt(eps))."""
    n = cmath.sqrt(eps)
    return (1 - n) / (1 + n)


def sheet_reflection(eps: complex, thickness_m: float, f_ghz: float) -> complex:
    """Airy sum of a slab in air at normal incidence: G (1 - e^{-2j d}) / (1 - G^2 e^{-2j d}), d = k h sqrt(eps)."""
    g = half_space_reflection(eps)
    phase = cmath.exp(-2j * (2 * math.pi * f_ghz * 1e9 / C) * thickness_m * cmath.sqrt(eps))
    return g * (1 - phase) / (1 - g * g * phase)


@pytest.mark.parametrize("preset", ["dji_mini_4_pro"])
def test_each_radar_material_reflects_like_its_closed_form(preset):
    """A 0.2 m plate of each material of the radar model, seen face on: sigma / sigma_PEC = |r|^2 at 2.4 and 24 GHz,
    r the half-space Fresnel coefficient (conductors) or the slab's (the 2 mm dielectric shells)."""
    plate = canonical.plate(0.1)
    pec = compute_rcs(plate, BANDS_GHZ, 0.0, 90.0, material="pec", error_estimate=False).rcs_m2("VV")[:, 0, 0]
    materials = load_target(preset).materials
    assert {m.name for m in materials} >= {"copper", "fr4", "carbon_fibre", "dark_plastic", "battery_pack"}
    for material in materials:
        got = compute_rcs(plate, BANDS_GHZ, 0.0, 90.0, material=material, error_estimate=False).rcs_m2("VV")[:, 0, 0]
        for f, ratio in zip(BANDS_GHZ, got / pec):
            eps = total_permittivity(material.relative_permittivity, material.conductivity_s_m, f)
            if material.thickness_m:
                r = sheet_reflection(eps, material.thickness_m, f)
            else:
                r = half_space_reflection(eps)
            assert ratio == pytest.approx(abs(r) ** 2, rel=0.02), (material.name, f)


def test_board_and_battery_materials_are_the_stated_ones():
    """Copper 5.8e7 S/m, FR-4 4.4 - 0.088j (tan d 0.02), the battery's aluminium laminate 3.5e7 S/m, CFRP 1e4 S/m."""
    by_name = {m.name: m for m in load_target("dji_mavic_3").materials}
    assert by_name["copper"].conductivity_s_m == 5.8e7 and by_name["copper"].thickness_m is None
    fr4 = by_name["fr4"]
    assert -fr4.relative_permittivity.imag / fr4.relative_permittivity.real == pytest.approx(0.02)
    assert 4.3 <= fr4.relative_permittivity.real <= 4.5 and fr4.thickness_m == pytest.approx(0.002)
    assert by_name["battery_pack"].conductivity_s_m == 3.5e7
    assert by_name["carbon_fibre"].conductivity_s_m == 1e4
    plastic = by_name["dark_plastic"].relative_permittivity
    assert 2.6 <= plastic.real <= 3.0 and 0.01 <= -plastic.imag <= 0.03


@pytest.mark.parametrize("preset", ["dji_mini_4_pro", "dji_mavic_3"])
def test_internal_parts_lie_inside_their_shell(preset):
    """The board, ground plane and wiring lie inside the body, the camera module inside the gimbal housing: the
    optical, thermal and lidar models, which see the outer surface, are unchanged by them."""
    drone = build_drone(preset)
    body = drone.part("body").mesh
    gimbal = drone.part("gimbal_camera").mesh
    kinds = {p.kind for p in drone.internal_parts}
    assert kinds == {"camera_module", "flight_controller", "ground_plane", "wiring"}
    assert not kinds & {p.kind for p in drone.parts}
    for part in drone.internal_parts:
        shell = gimbal if part.kind == "camera_module" else body
        assert shell.contains(part.mesh.vertices).all(), part.name
    assert sum(p.kind == "wiring" for p in drone.internal_parts) == 3 * 4 + 2  # three leads a motor, two battery


def test_drone_json_lists_the_radar_model_part_by_part(capsys):
    assert main(["drone", "dji_mini_4_pro", "--quality", "none", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert {"parts", "mesh", "emissivity", "bbox_m", "spec"} <= set(result)  # the earlier keys stay
    rows = result["rf_model"]
    assert {r["kind"] for r in rows} == RADAR_KINDS | {"landing_gear"}
    by_name = {r["name"]: r for r in rows}
    assert by_name["ground_plane"]["conductivity_s_m"] == 5.8e7
    assert by_name["ground_plane"]["surface"] == "conductor half-space" and by_name["ground_plane"]["inside_airframe"]
    assert by_name["flight_controller"]["relative_permittivity"] == pytest.approx([4.4, -0.088])
    assert by_name["flight_controller"]["surface"] == "dielectric shell 2 mm"
    assert by_name["flight_controller"]["size_m"] == pytest.approx([0.070, 0.045, 0.0016])
    assert by_name["body"]["inside_airframe"] is False
    blades = [r for r in rows if r["kind"] == "propeller"]
    assert len(blades) == 4 and all(r["material"] == "dark_plastic" for r in blades)
    # blades, not swept discs: a 2-blade rotor's plan area is far below the 6-inch disc's pi d^2 / 4
    assert all(r["area_m2"] < 0.5 * math.pi * 0.1524**2 / 4 for r in blades)
    assert all(r["source"] and r["area_m2"] > 0 for r in rows)
    assert main(["drone", "pigeon", "--quality", "none", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["rf_model"] is None


def _table_blocks() -> list[tuple[dict, list[dict]]]:
    """The shipped table's command blocks: (options of the ``csuas rcs-statistics`` comment, rows under it)."""
    text = resources.files("csuas.defaults").joinpath("drone_rcs_statistics.csv").read_text()
    blocks, columns = [], None
    for line in text.splitlines():
        command = re.search(r"--quality (\w+) --accuracy-db ([\d.]+) --max-aspects (\d+)", line)
        if line.startswith("#"):
            if command:
                quality, accuracy, max_aspects = command.groups()
                total = re.search(r"(\d+) s\b", line)
                blocks.append(({"quality": quality, "max_aspects": int(max_aspects), "total_s": total}, []))
            elif line.startswith("# total time"):
                blocks[-1][0]["total_s"] = re.search(r"(\d+) s", line)
        elif columns is None:
            columns = line.split(",")
        else:
            blocks[-1][1].append(dict(zip(columns, next(csv.reader([line])))))
    return blocks


def test_shipped_statistics_rows_agree_with_their_headers():
    """Every row was made by the command its comment names: its quality, at most its aspect budget, both
    polarisations of a band from one run (same aspects and time), and the stated total time."""
    blocks = _table_blocks()
    assert len(blocks) >= 1 and all(rows for _, rows in blocks)
    for options, rows in blocks:
        assert {r["quality"] for r in rows} == {options["quality"]}
        assert all(0 < int(r["aspects"]) <= options["max_aspects"] for r in rows)
        for vv, hh in zip(rows[::2], rows[1::2]):
            assert (vv["preset"], vv["frequency_ghz"], vv["polarisation"], hh["polarisation"]) == (
                hh["preset"],
                hh["frequency_ghz"],
                "VV",
                "HH",
            )
            assert vv["aspects"] == hh["aspects"] and vv["time_s"] == hh["time_s"]
            assert float(vv["p10_dbsm"]) <= float(vv["median_dbsm"]) <= float(vv["p90_dbsm"])
        if options["total_s"] is not None:
            assert sum(float(r["time_s"]) for r in rows[::2]) == pytest.approx(int(options["total_s"].group(1)), abs=1)


def _rows(preset, means_16, means_24, error_db):
    return [
        {"preset": preset, "frequency_ghz": f, "polarisation": pol, "mean_dbsm": m, "mean_error_db": error_db}
        for f, means in ((16.0, means_16), (24.0, means_24))
        for pol, m in zip(("VV", "HH"), means)
    ]


def test_trend_check_judges_the_rise_of_the_polarisation_mean():
    """Eq. 6 mean of VV and HH: 10 log10((10^-1.5 + 10^-1.3) / 2) = -13.88 dBsm at 16 GHz, -11.88 at 24 GHz."""
    from csuas.validation.report.checks_rcs import _trend_16_to_24

    rising = _trend_16_to_24("x", _rows("x", (-15.0, -13.0), (-13.0, -11.0), 0.5))
    assert rising.measured == pytest.approx(2.0) and rising.ok
    assert rising.tolerance == pytest.approx(math.hypot(0.5, 0.5))
    within = _trend_16_to_24("x", _rows("x", (-15.0, -13.0), (-15.5, -13.5), 0.5))  # -0.5 dB, bound 0.71 dB
    assert within.ok
    falling = _trend_16_to_24("x", _rows("x", (-15.0, -13.0), (-16.0, -14.0), 0.5))
    assert falling.measured == pytest.approx(-1.0) and not falling.ok and falling.limitation


def grounded_slab_reflection(eps: complex, depth_m: float, f_ghz: float) -> complex:
    """Air | dielectric of ``depth_m`` | perfect conductor at normal incidence: (G - e^{-2j d}) / (1 - G e^{-2j d})."""
    g = half_space_reflection(eps)
    phase = cmath.exp(-2j * (2 * math.pi * f_ghz * 1e9 / C) * depth_m * cmath.sqrt(eps))
    return (g - phase) / (1 - g * phase)


def test_board_face_on_reflects_like_fr4_over_its_ground_plane():
    """The board as the engine traces it (the FR-4 face as a 2 mm sheet, the copper plane 0.7 mm below) against the
    grounded slab air | 0.7 mm FR-4 | copper: within 0.8 dB from 2.4 to 35 GHz (the 2 mm sheet is the engine's one
    thickness for every dielectric of a preset; a 1.6 mm board is thinner)."""
    import trimesh

    from csuas.drone_models.materials import COPPER, FR4
    from csuas.drone_models.multirotor import BOARD_THICKNESS_M, GROUND_PLANE_THICKNESS_M
    from csuas.render.rcs import prepare_mesh

    depth = (BOARD_THICKNESS_M - GROUND_PLANE_THICKNESS_M) / 2.0
    face, plane = canonical.plate(0.1), canonical.plate(0.1)
    face.vertices[:, 2] += depth
    mesh = trimesh.util.concatenate([face, plane])
    board = prepare_mesh(mesh.vertices, mesh.faces, [0, 0, 1, 1], [FR4, COPPER]).with_shells(0.002)
    bands = [2.4, 9.4, 24.0, 35.0]
    pec = compute_rcs(canonical.plate(0.1), bands, 0.0, 90.0, error_estimate=False).rcs_m2("VV")[:, 0, 0]
    got = compute_rcs(
        board, bands, 0.0, 90.0, rays_per_wavelength=10, max_bounces=16, power_cutoff=1e-6, error_estimate=False
    ).rcs_m2("VV")[:, 0, 0]
    for f, ratio in zip(bands, got / pec):
        exact = abs(grounded_slab_reflection(complex(4.4, -0.088), depth, f)) ** 2
        assert 10 * math.log10(ratio) == pytest.approx(10 * math.log10(exact), abs=0.8), f
