"""Micro-Doppler of a propeller about any axis (issue 26, section 2): a fixed-wing's pusher turns about its flight
axis. References: Eq. MD-6 by hand (sin beta = a . d, cos beta = |a x d|); the PO field of flat blades turning
about a tilted axis against the closed form of Eq. MD-1a with beta and theta_0 from the geometry; the flash
period (Chen et al. 2006, Sec. V), the lines at N Omega and the tip Doppler 2 v_tip |a x d| / lambda; a
multirotor's rotors against the unchanged formula of a +z rotor (turning the radar's azimuth)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from csuas.base.errors import ParameterError
from csuas.core import micro_doppler as md
from csuas.drone_models.geometry import direction_vector
from csuas.render.rcs.facet_po import facet_po_amplitude
from csuas.render.rcs.micro_doppler import (
    drone_rotors,
    plan_micro_doppler,
    rotor_about,
    rotor_field,
    rotor_frame,
    spectrum_m2,
)
from csuas.validation.report.checks_micro_doppler import flash_period_s, straight_blade_rotor

C = 299_792_458.0
#: A tilted axis: z turned about (0.7, -0.4, 0.9) by its norm, 1.21 rad: a = (-0.031, -0.701, 0.713).
TILT = Rotation.from_rotvec([0.7, -0.4, 0.9]).as_matrix()


def test_elevation_above_the_rotor_plane_is_asin_of_axis_dot_direction():
    d = direction_vector(30.0, 10.0)
    # a pusher (axis +x) seen at azimuth 30, elevation 10: sin beta = cos 10 cos 30
    beta = md.rotor_plane_elevation_deg([1.0, 0.0, 0.0], d)
    assert beta == pytest.approx(math.degrees(math.asin(math.cos(math.radians(10)) * math.cos(math.radians(30)))))
    assert math.cos(math.radians(beta)) == pytest.approx(np.linalg.norm(np.cross([1.0, 0.0, 0.0], d)), rel=1e-12)
    assert md.rotor_plane_elevation_deg([0.0, 0.0, 2.0], d) == pytest.approx(10.0, rel=1e-12)  # a rotor: el
    assert md.rotor_plane_elevation_deg([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]) == pytest.approx(90.0)  # nose-on
    with pytest.raises(ParameterError) as info:
        md.rotor_plane_elevation_deg([0.0, 0.0, 0.0], d)
    assert info.value.name == "spin_axis"


def test_rotor_frames_are_right_handed_with_the_axis_third():
    assert rotor_frame([0.0, 0.0, 1.0]) is None
    for axis in ([1.0, 0.0, 0.0], [0.0, 0.0, -1.0], TILT @ [0.0, 0.0, 1.0]):
        frame = rotor_frame(axis)
        np.testing.assert_allclose(frame @ frame.T, np.eye(3), atol=1e-15)
        assert np.linalg.det(frame) == pytest.approx(1.0) and np.allclose(frame[2], axis)


@pytest.mark.parametrize(("azimuth_deg", "elevation_deg"), [(-20.0, 0.0), (-100.0, 30.0), (-60.0, 0.0)])
def test_po_of_flat_blades_about_a_tilted_axis_is_the_closed_form(azimuth_deg, elevation_deg):
    length, chord, n_blades, rate, prf = 0.076, 0.0015, 2, 100.0, 60_000.0
    flat = straight_blade_rotor(length, chord, n_blades)  # blades in the xy-plane, blade 0 along +x
    axis, blade0 = TILT @ [0.0, 0.0, 1.0], TILT @ [1.0, 0.0, 0.0]
    rotor = rotor_about("tilted", trimesh.Trimesh(flat.vertices @ TILT.T, flat.faces, process=False), axis, 1, 2)
    assert rotor.tip_radius_m == pytest.approx(math.hypot(length, chord / 2.0), rel=1e-12)
    d = direction_vector(azimuth_deg, elevation_deg)
    beta = float(md.rotor_plane_elevation_deg(axis, d))  # 12.2, 73.5 and 36.3 deg
    projected = d - (axis @ d) * axis  # theta_0: blade 0 from d's projection, counter-clockwise about the axis
    theta0 = math.degrees(math.atan2(axis @ np.cross(projected, blade0), projected @ blade0))
    t = np.arange(600) / prf  # one turn
    po = rotor_field(rotor, rate, t, 10.0, azimuth_deg, elevation_deg)
    exact = math.sin(math.radians(beta)) * chord * md.rotor_blade_signal(t, length, 2, rate, 10.0, beta, theta0, chord)
    assert np.max(np.abs(po - exact)) < 1e-9 * np.max(np.abs(exact))
    assert flash_period_s(t, po) == pytest.approx(md.blade_flash_period_s(n_blades, rate), abs=1 / prf)
    bins, power = spectrum_m2(po, "rectangular")
    frequency = bins * prf / len(t)
    spacing = md.line_spacing_hz(n_blades, rate)
    assert np.allclose(np.mod(frequency[power > 1e-12 * power.max()], spacing), 0.0)  # lines at N Omega only
    # the spectrum ends at the tip Doppler with the projection factor |a x d| (Eq. MD-4, MD-6): measured, under
    # 1 % of the blades' spread power beyond it (the flashes' short ends) and over 5 % in its last fifth
    tip = 2.0 * (2.0 * math.pi * length * rate) * np.linalg.norm(np.cross(axis, d)) / (C / 10e9)
    assert md.max_tip_doppler_hz(length, rate, 10.0, beta) == pytest.approx(tip, rel=1e-12)
    spread = np.where(frequency == 0.0, 0.0, power)
    assert spread[np.abs(frequency) > tip].sum() < 0.01 * spread.sum()
    assert spread[(np.abs(frequency) > 0.8 * tip) & (np.abs(frequency) <= tip)].sum() > 0.05 * spread.sum()


def test_multirotor_rotors_are_turned_exactly_as_before():
    rotors, body = drone_rotors("dji_mini_4_pro")
    assert all(r.frame is None and np.array_equal(r.spin_axis, [0.0, 0.0, 1.0]) for r in rotors)
    t, az, el = np.arange(64) / 20_000.0, 30.0, 15.0
    k = 2.0 * np.pi / (C / 10e9)
    for rotor in rotors:  # the +z formula: the radar's azimuth turned by -psi, the hub's phase
        psi = rotor.spin * 360.0 * 100.0 * t
        turned_az = (az - psi + 180.0) % 360.0 - 180.0
        shift = np.exp(
            2j * k * ((direction_vector(az, el) - direction_vector(turned_az, np.full_like(t, el))) @ rotor.centre_m)
        )
        expected = shift * facet_po_amplitude(rotor.vertices, rotor.faces, 10.0, turned_az, el)
        assert np.array_equal(rotor_field(rotor, 100.0, t, 10.0, az, el), expected)
    # the same rotor tilted with the radar (the general frame) gives the same field
    rotor = rotors[0]
    mesh = trimesh.Trimesh(rotor.vertices @ TILT.T, rotor.faces, process=False)
    tilted = rotor_about("tilted", mesh, TILT @ [0.0, 0.0, 1.0], rotor.spin, rotor.n_blades)
    d = TILT @ direction_vector(az, el)
    turned = rotor_field(tilted, 100.0, t, 10.0, math.degrees(math.atan2(d[1], d[0])), math.degrees(math.asin(d[2])))
    original = rotor_field(rotor, 100.0, t, 10.0, az, el)
    assert np.max(np.abs(turned - original)) < 1e-9 * np.max(np.abs(original))


@pytest.mark.parametrize("preset", ["euclid_class_fixed_wing", "small_delta_wing"])
def test_a_fixed_wing_pusher_turns_about_its_flight_axis(preset):
    from csuas.drone_models.presets import preset_parameters

    (rotor,), body = drone_rotors(preset)
    _, params, _ = preset_parameters(preset)
    assert np.array_equal(rotor.spin_axis, [1.0, 0.0, 0.0]) and rotor.n_blades == params.n_blades
    radius = params.propeller_diameter_m / 2.0
    assert radius <= rotor.tip_radius_m <= math.hypot(radius, params.blade_tip_chord_m / 2.0) + 1e-12
    assert all(p.spin_axis is None for p in body.parts)
    for az, el in ((0.0, 10.0), (60.0, 10.0), (90.0, 0.0)):
        plan = plan_micro_doppler(preset, 10.0, 20_000.0, 0.01, 6000.0, (az, el))
        projection = np.linalg.norm(np.cross([1.0, 0.0, 0.0], direction_vector(az, el)))
        expected = 2.0 * (2.0 * math.pi * rotor.tip_radius_m * 100.0) * projection / (C / 10e9)
        assert plan.tip_doppler_hz == pytest.approx(expected, rel=1e-12)
    # nose-on, the disc faces the radar: no Doppler spread
    assert plan_micro_doppler(preset, 10.0, 20_000.0, 0.01, 6000.0, (0.0, 0.0)).tip_doppler_hz < 1e-9


@pytest.mark.slow
def test_micro_doppler_of_the_pusher_has_lines_at_n_omega(tmp_path, capsys):
    from csuas import cli

    out = tmp_path / "md"
    args = ["micro-doppler", "small_delta_wing", "--out", str(out), "--azimuth-deg", "60", "--dwell-s", "0.02"]
    assert cli.main([*args, "--window", "rectangular", "--json"]) == 0
    capsys.readouterr()
    result = json.loads((out / "micro_doppler.json").read_text())
    assert result["line_spacing_hz"] == pytest.approx(200.0)  # 2 blades at 6000 rpm
    (rotor,) = result["rotors"]
    assert rotor["spin_axis"] == [1.0, 0.0, 0.0]
    assert rotor["elevation_above_rotor_plane_deg"] == pytest.approx(
        math.degrees(math.asin(math.cos(math.radians(10.0)) * math.cos(math.radians(60.0)))), rel=1e-12
    )


def _pd_micro_doppler(capsys, *extra) -> dict:
    from csuas import cli

    assert cli.main(["pd", "fixed_wing", "--micro-doppler", "--range-m", "10", "50", "--json", *extra]) == 0
    return json.loads(capsys.readouterr().out)["sensors"]["radar"]["micro_doppler"]


def test_pd_classifies_a_pusher_by_its_propeller_lines_seen_from_its_aspect(capsys):
    from csuas.core.radar import radar_frequency_ghz
    from csuas.core.scenario import load_scenario

    scenario = load_scenario("fixed_wing")
    wavelength = C / (radar_frequency_ghz(scenario.sensors["radar"].params) * 1e9)
    (rotor,), _ = drone_rotors(scenario.target_preset)
    rate = scenario.target["blade_passing_hz"] / rotor.n_blades  # 225 Hz / 2 blades
    nose_on = _pd_micro_doppler(capsys)  # approaching: azimuth 0, elevation 10: 80 deg above the pusher's plane
    assert nose_on["line_spacing_hz"] == pytest.approx(scenario.target["blade_passing_hz"], rel=1e-12)
    tip = 2.0 * (2.0 * math.pi * rotor.tip_radius_m * rate) * math.cos(math.radians(80.0)) / wavelength
    assert nose_on["max_tip_doppler_hz"] == pytest.approx(tip, rel=1e-9)
    assert "80 deg above the propeller plane" in " ".join(nose_on["assumptions"])
    assert nose_on["blade_power_fraction"] > 0.01 and nose_on["pd_classified_drone"][0] > 0.5
    # side-on the flat blades turn edge-on to the radar (beta 0: PO amplitude w sin(beta) = 0): no lines at all
    side = _pd_micro_doppler(capsys, "--micro-doppler-azimuth-deg", "90", "--micro-doppler-elevation-deg", "0.5")
    assert side["blade_power_fraction"] < 1e-30
    assert side["pd_classified_drone"] == pytest.approx([side["p_bird_classified_drone"]] * 2, rel=1e-9)


def test_the_report_s_axis_checks_pass():
    from csuas.validation.report.checks_micro_doppler import axis_cases

    section = axis_cases()
    assert len(section.outcomes) == 8 and all(check.ok for check in section.outcomes)
    assert [row["note"].split(";")[0] for row in section.table] == ["beta 12.2 deg", "beta 73.5 deg", "beta 36.3 deg"]
