"""Bird meshes (drone_models/birds.py): the table's size at mid-stroke, the flapping angle, watertight
convex shells, plumage at the table's temperature; rendered (slow) against the exact silhouette and the
Planck band closed form (validation/imaging/birds.py)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.cli import main
from csuas.defaults import load_birds
from csuas.drone_models import birds as B
from csuas.drone_models import build_drone, list_presets

CLASSES = sorted(load_birds())


def test_every_class_of_the_table_has_a_bird():
    assert CLASSES == ["gull", "pigeon", "raptor"] and set(B.list_birds()) == set(CLASSES)
    assert not set(CLASSES) & set(list_presets())  # birds are confusers, not drone presets


@pytest.mark.parametrize("name", CLASSES)
@pytest.mark.parametrize("phase", [0.25, 0.75, 1.25])
def test_mid_stroke_length_span_and_depth_equal_the_table(name, phase):
    """Wings level (phase 0.25 + k/2): head to tail L, tip to tip W, body diameter D, box centred."""
    row = load_birds()[name]
    bird = B.build_bird(name, phase)
    lower, upper = bird.bounds()
    np.testing.assert_allclose(
        upper - lower, [row["body_length_m"], row["wingspan_m"], row["body_diameter_m"]], rtol=1e-12
    )
    np.testing.assert_allclose(upper + lower, 0.0, atol=1e-12)
    for part in bird.parts:
        assert part.mesh.is_watertight and part.mesh.is_winding_consistent and part.mesh.volume > 0, part.name
        assert part.mesh.is_convex, part.name  # the silhouette code's exact convex-hull shortcut applies


@pytest.mark.parametrize("name", CLASSES)
def test_raised_wings_follow_the_stroke_angle(name):
    """Top of the stroke (phase 0): each wing turned by A_s about its hinge; the tips' outer edge at
    y = y_h + s cos A + (t / 2) sin A and z = z_h + s sin A + (t / 2) cos A (a rotated plate)."""
    row = load_birds()[name]
    amplitude = math.radians(row["wing_stroke_amplitude_deg"])
    d, w = row["body_diameter_m"], row["wingspan_m"]
    y_h, z_h = B.HINGE_Y_FRACTION * d, B.HINGE_Z_FRACTION * d
    reach = w / 2 - y_h
    half_t = B.WING_THICKNESS_FRACTION * (2 * w / row["wing_aspect_ratio"] / (1 + B.WING_TAPER)) / 2
    for phase, sign in ((0.0, 1.0), (0.5, -1.0)):
        wing = B.build_bird(name, phase).part("wing_left").mesh
        assert wing.bounds[1, 1] == pytest.approx(y_h + reach * math.cos(amplitude) + half_t * math.sin(amplitude))
        tip_z = wing.bounds[1, 2] if sign > 0 else wing.bounds[0, 2]
        assert tip_z == pytest.approx(z_h + sign * (reach * math.sin(amplitude) + half_t * math.cos(amplitude)))
    assert B.wing_angle_deg(30.0, [0.0, 0.25, 0.5, 0.75, 1.0]) == pytest.approx([30.0, 0.0, -30.0, 0.0, 30.0])


def test_plumage_at_the_table_temperature_and_build_drone_access():
    row = load_birds()["gull"]
    bird = build_drone("gull", wingbeat_phase=0.1, ambient_k=270.0)
    for part in bird.parts:
        assert part.material.temperature_k == pytest.approx(270.0 + row["surface_temperature_excess_k"])
        assert part.material.emissivity_lwir == 0.95 and part.material.name == row["plumage"]
    assert bird.mass_kg == row["mass_kg"] and bird.propellers == "none"
    assert bird.spec["wing_angle_deg"] == pytest.approx(row["wing_stroke_amplitude_deg"] * math.cos(0.2 * math.pi))
    assert {p.kind for p in bird.parts} == {"body", "head", "tail", "wing"}
    from csuas.render.imaging.scene import target_parts  # a bird's name is a render target, as a preset's

    assert [p.name for p in target_parts("raptor")] == ["body", "head", "tail", "wing_left", "wing_right"]


@pytest.mark.parametrize(
    "call, fragment",
    [
        (lambda: build_drone("pigeon", blade_phase_deg=3.0), "blade_phase_deg"),
        (lambda: B.build_bird("eagle"), "pigeon"),
        (lambda: B.build_bird("pigeon", float("nan")), "wingbeat_phase"),
        (lambda: B.build_bird("pigeon", ambient_k=-1.0), "ambient_k"),
        (lambda: build_drone("crow"), "raptor"),
    ],
)
def test_bad_input_names_the_parameter(call, fragment):
    with pytest.raises(ParameterError, match=fragment):
        call()


def test_drone_command_reports_a_bird(capsys):
    assert main(["drone", "pigeon", "--quality", "none", "--azimuth-deg", "0", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["bbox_m"] == pytest.approx([0.32, 0.66, 0.075], rel=1e-12)
    assert out["mesh"]["parts_watertight"] and out["mesh"]["watertight"] and out["propellers"] == "none"
    assert out["d_x_proj_m"] == pytest.approx(0.66) and out["emissivity"]["area_weighted"] == pytest.approx(0.95)
    assert main(["drone", "pigeon", "--quality", "none", "--wingbeat-phase", "0", "--json"]) == 0
    raised = json.loads(capsys.readouterr().out)
    assert raised["spec"]["wing_angle_deg"] == pytest.approx(45.0) and raised["bbox_m"][1] < 0.66


def test_the_thermal_closed_form_against_planck_by_quadrature():
    """apparent_excess_k's band radiances against an independent trapezoidal Planck integral over 8-12 um."""
    from csuas.validation.imaging.birds import apparent_excess_k

    lam = np.linspace(8e-6, 12e-6, 40001)
    h, c, k = 6.62607015e-34, 299792458.0, 1.380649e-23

    def band(t):
        return np.trapezoid(2 * h * c**2 / lam**5 / np.expm1(h * c / (lam * k * t)), lam)

    target = 0.95 * band(293.15) + 0.05 * band(288.15)
    lo, hi = 288.0, 294.0
    for _ in range(60):  # bisection on the radiance temperature
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if band(mid) < target else (lo, mid)
    assert apparent_excess_k(0.95, 5.0, 288.15) == pytest.approx(0.5 * (lo + hi) - 288.15, abs=1e-6)


@pytest.mark.slow
def test_rendered_bird_against_its_exact_silhouette_and_the_planck_closed_form():
    from csuas.validation.imaging.birds import eo_checks, tir_checks

    checks = eo_checks("draft", seed=3) + tir_checks("draft", seed=3)
    assert len(checks) == 6
    for check in checks:
        assert abs(check.measured - check.expected) <= check.tolerance, check.name
