"""Thin-wire method of moments (render/rcs/thin_wire.py) against closed forms and published values.

References: the resonant dipole's broadside RCS 0.86 lambda^2 at a length a few per cent below
lambda / 2 (Knott, Shaeffer and Tuley, Radar Cross Section, 2nd ed., 2004; Van Vleck, Bloch and
Hamermesh, J. Appl. Phys. 18, 274, 1947; (lambda^2 / pi) G^2 with G = 1.64, Balanis, Antenna
Theory, ch. 4 and 8); a short wire's static polarisability alpha / (4 pi eps0) = L^3 / (24 (ln(2 L / a)
- 7/3)) (Landau and Lifshitz, Electrodynamics of Continuous Media, sec. 3, problem; Vainshtein 1962),
whose next order is O(1 / Omega^2) with Omega = ln(2 L / a) - 7/3; the physical-optics plate's far
field -j k A / (2 pi) exp(2 j k d.r) in the exp(j omega t) convention (Knott et al., ch. 5).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from csuas.base.errors import ParameterError
from csuas.core.units import C_LIGHT
from csuas.drone_models.parts import cylinder_between
from csuas.render.rcs.thin_wire import (
    ERROR_FACTOR,
    ThinWires,
    scattering_amplitude,
    segment_counts,
    wire_field,
    wire_of_cylinder,
)

#: 1 m wavelength.
F_1M_GHZ = C_LIGHT / 1e9


def _monostatic(wires, f_ghz, az, el, counts=None):
    az, el = np.atleast_1d(np.asarray(az, float)), np.atleast_1d(np.asarray(el, float))
    return scattering_amplitude(wires, f_ghz, (az, el), (az[:, None], el[:, None]), counts=counts)[:, 0]


def _dipole(length, radius, axis=(0.0, 0.0, 1.0), centre=(0.0, 0.0, 0.0)):
    half = 0.5 * length * np.asarray(axis, float) / np.linalg.norm(axis)
    return ThinWires.of(np.asarray(centre) - half, np.asarray(centre) + half, radius)


def _broadside_sigma(length, radius_over_lambda):
    """sigma / lambda^2 of a z-directed wire at broadside, V (along the wire)."""
    amp = _monostatic(_dipole(length, radius_over_lambda), F_1M_GHZ, 0.0, 0.0, counts=[40])
    return 4.0 * math.pi * abs(amp[0, 0, 0]) ** 2


@pytest.mark.parametrize("radius", [1e-3, 5e-3])
def test_resonant_dipole_broadside_rcs_and_length(radius):
    """Peak broadside RCS within 3 % of 0.86 lambda^2 (the sinusoidal-current value 0.856), at 0.46-0.49 lambda."""
    best = minimize_scalar(lambda x: -_broadside_sigma(x, radius), bounds=(0.42, 0.5), method="bounded")
    assert -best.fun == pytest.approx(0.86, rel=0.03)
    assert 0.455 < best.x < 0.49


def test_thicker_dipole_resonates_shorter():
    """A thicker wire's resonance lies further below lambda / 2 (Balanis sec. 8.4: it falls with the radius)."""
    lengths = [
        minimize_scalar(lambda x, r=r: -_broadside_sigma(x, r), bounds=(0.42, 0.5), method="bounded").x
        for r in (1e-3, 5e-3)
    ]
    assert lengths[1] < lengths[0] - 0.005


@pytest.mark.parametrize("length_over_radius", [1e3, 1e4])
def test_short_wire_rayleigh_limit(length_over_radius):
    """L = lambda / 100: sigma = 4 pi k^4 (alpha / 4 pi eps0)^2 within the formula's next order 2 / Omega^2."""
    length, k = 0.01, 2.0 * math.pi
    amp = _monostatic(_dipole(length, length / length_over_radius), F_1M_GHZ, 0.0, 0.0, counts=[80])[0, 0, 0]
    omega = math.log(2.0 * length_over_radius) - 7.0 / 3.0
    alpha = length**3 / (24.0 * omega)
    assert 4.0 * math.pi * abs(amp) ** 2 == pytest.approx(4.0 * math.pi * k**4 * alpha**2, rel=2.0 / omega**2)
    # a static dipole re-radiates in phase: E_s = k^2 p / (4 pi eps0 r), a positive real amplitude
    assert abs(math.degrees(np.angle(amp))) < 0.01


def test_short_wire_dipole_pattern_and_polarisation():
    """Rayleigh dipole along z: VV falls as cos^4(el) (both antennas' projections), HH and cross terms vanish."""
    wire = _dipole(0.01, 1e-5)
    amp = _monostatic(wire, F_1M_GHZ, [0.0, 20.0], [0.0, 40.0], counts=[20])
    ratio = abs(amp[1, 0, 0]) ** 2 / abs(amp[0, 0, 0]) ** 2
    assert ratio == pytest.approx(math.cos(math.radians(40.0)) ** 4, rel=1e-3)  # (k L)^2 corrections ~ 4e-3 of 1
    assert np.abs(amp[:, 1, :]).max() < 1e-12 * abs(amp[0, 0, 0])
    assert np.abs(amp[:, :, 1]).max() < 1e-12 * abs(amp[0, 0, 0])


def test_phase_reference_moves_with_the_wire():
    """A wire moved by delta toward the radar gains exp(2 j k delta) exactly (the engine's origin convention)."""
    delta, k = 0.137, 2.0 * math.pi
    here = _monostatic(_dipole(0.47, 1e-3, axis=(1, 2, 3)), F_1M_GHZ, 30.0, 20.0, counts=[16])
    toward = np.array([math.cos(math.radians(20)) * math.cos(math.radians(30)), 0.0, math.sin(math.radians(20))])
    toward[1] = math.cos(math.radians(20)) * math.sin(math.radians(30))
    moved = _monostatic(_dipole(0.47, 1e-3, axis=(1, 2, 3), centre=delta * toward), F_1M_GHZ, 30.0, 20.0, counts=[16])
    np.testing.assert_allclose(moved, here * np.exp(2j * k * delta), rtol=1e-9, atol=1e-12)


def test_bistatic_reciprocity():
    """S(rx, tx) = S(tx, rx) transposed for swapped directions (reciprocity of a passive scatterer)."""
    wires = ThinWires.of([[0, 0, 0], [0.1, 0.05, 0.0]], [[0.3, 0.2, 0.1], [0.1, 0.4, 0.2]], 2e-3)
    a = scattering_amplitude(
        wires, F_1M_GHZ, (np.array([10.0]), np.array([5.0])), (np.array([[70.0]]), np.array([[-30.0]]))
    )
    b = scattering_amplitude(
        wires, F_1M_GHZ, (np.array([70.0]), np.array([-30.0])), (np.array([[10.0]]), np.array([[5.0]]))
    )
    np.testing.assert_allclose(a[0, 0], b[0, 0].T, rtol=1e-9)


#: Population of the error bound: length [lambda], length / radius, aspect (az, el) [deg].
BOUND_CASES = [(0.1, 40), (0.25, 400), (0.47, 40), (0.47, 400), (0.75, 40), (1.0, 80), (1.0, 400), (1.5, 60)]


def test_error_bound_covers_the_finest_solution():
    """ERROR_FACTOR |S_N - S_N/2| bounds |S_N - S_8N| for every amplitude of a population of tilted wires."""
    covered, total = 0, 0
    for length, ratio in BOUND_CASES:
        wire = _dipole(length, length / ratio, axis=(1.0, 0.5, 1.0))
        n = segment_counts(wire, F_1M_GHZ, per_wavelength=20)  # half the default density: the harder case
        fine, coarse, finest = (
            _monostatic(wire, F_1M_GHZ, [0.0, 50.0], [0.0, 25.0], c) for c in (n, (n + 1) // 2, 8 * n)
        )
        bound = ERROR_FACTOR * np.abs(fine - coarse)
        error = np.abs(fine - finest)
        covered += int((error <= bound).sum())
        total += error.size
    assert covered == total


def test_wire_field_bounds_a_dipole_against_a_finer_run():
    """wire_field's bound covers the error against eight times as many segments, by frequency job."""
    wire = _dipole(0.47, 0.0094)
    inc = (np.array([0.0, 0.0]), np.array([0.0, 30.0]))
    amp, err = wire_field(wire, np.array([F_1M_GHZ, 0.9 * F_1M_GHZ]), inc, (inc[0][:, None], inc[1][:, None]))
    for j, f in enumerate((F_1M_GHZ, 0.9 * F_1M_GHZ)):
        finest = _monostatic(wire, f, inc[0][j], inc[1][j], 8 * segment_counts(wire, f))
        assert np.all(np.abs(amp[j] - finest[0]) <= err[j] + 1e-15)


def test_wire_of_cylinder_recovers_the_axis():
    """The faceted cylinder of a drone's lead gives back its end points and radius."""
    start, end = np.array([0.01, -0.02, 0.03]), np.array([0.025, 0.004, 0.031])
    wire = wire_of_cylinder(cylinder_between(start, end, 0.000405, 8).vertices)
    ends = np.stack([wire.start_m[0], wire.end_m[0]])
    assert np.allclose(ends, [start, end], atol=1e-12) or np.allclose(ends, [end, start], atol=1e-12)
    assert wire.radius_m[0] == pytest.approx(0.000405, rel=1e-12)


def test_bad_wires_are_refused():
    with pytest.raises(ParameterError, match="wire.end_m"):
        ThinWires.of([0, 0, 0], [0, 0, 0], 1e-3)
    with pytest.raises(ParameterError, match="wire.radius_m"):
        ThinWires.of([0, 0, 0], [0, 0, 0.01], 2e-3)


def test_drone_wiring_is_solved_not_traced():
    """The Mini 4 Pro's 14 leads leave the traced facets and join the target as wires, in its centred frame."""
    from csuas.drone_models import build_drone
    from csuas.render.rcs.geometry import RADAR_PROPELLERS, load_target, radar_part_list

    target = load_target("dji_mini_4_pro")
    drone = build_drone("dji_mini_4_pro", propellers=RADAR_PROPELLERS)
    wiring = [p for p in drone.radar_parts() if p.kind == "wiring"]
    traced = sum(len(p.mesh.faces) for p in drone.radar_parts() if p.kind != "wiring")
    assert len(target.wires) == len(wiring) == 14 and len(target.faces) == traced
    lead = wiring[0].mesh.vertices
    assert np.allclose(
        np.sort([target.wires.start_m[0], target.wires.end_m[0]], axis=0) + target.centre_m,
        np.sort(np.stack([wire_of_cylinder(lead).start_m[0], wire_of_cylinder(lead).end_m[0]]), axis=0),
    )
    rows = {r["name"]: r for r in radar_part_list("dji_mini_4_pro")}
    assert rows[wiring[0].name]["surface"] == "thin wire (method of moments)"


@pytest.mark.slow
def test_against_the_efie_of_a_closed_cylinder():
    """A 6 mm AWG 20 lead (k a 0.20, near half-wave) at 24 GHz broadside: the MoM within its segments' bound plus
    the EFIE's mesh error of bempp-cl's answer for the closed (capped) cylinder (validation/rcs/fullwave.py);
    178 s at load 4-5 (numba compilation included)."""
    from csuas.validation.rcs.fullwave import EfieSettings, cylinder_mesh, monostatic_rcs_efie, richardson

    length, radius = 0.006, 0.000405
    efie = []
    for h in (0.0003, 0.0002):
        mesh = cylinder_mesh(radius, length, h)
        efie.append(monostatic_rcs_efie(mesh.vertices, mesh.faces, 24.0, 0.0, 0.0, "VV", EfieSettings(solver="lu")))
    # the two meshes differ by 1.5 in edge length (circumference 9 -> 13 cells, length 20 -> 30)
    exact, efie_error = richardson(efie[1].sigma_m2[0], efie[0].sigma_m2[0], ratio=1.5)
    amp, err = wire_field(
        _dipole(length, radius), np.array([24.0]), (np.array([0.0]), np.array([0.0])), (np.zeros((1, 1)),) * 2
    )
    relative = abs(math.sqrt(4.0 * math.pi * abs(amp[0, 0, 0, 0]) ** 2 / exact) - 1.0)
    assert relative <= err[0, 0, 0, 0] / abs(amp[0, 0, 0, 0]) + efie_error / (2.0 * exact)  # power -> amplitude


def test_wires_join_the_sbr_field_coherently():
    """compute_rcs adds the wires' amplitude to the traced field: a plate (PO closed form -j k A / (2 pi) e^{2 j k d.r},
    the same exp(j omega t) convention as the MoM) plus a half-wave wire beside it, at broadside."""
    from csuas.render.rcs import compute_rcs, prepare_mesh

    f_ghz, side, height = 10.0, 0.02, 0.02  # plate and wire amplitudes 0.013 and 0.008 m: a wrong phase shows
    k = 2.0 * math.pi * f_ghz * 1e9 / C_LIGHT
    corners = [[-side / 2, -side / 2, height], [side / 2, -side / 2, height], [side / 2, side / 2, height]]
    plate = prepare_mesh([*corners, [-side / 2, side / 2, height], [0.0, 0.0, -height]], [[0, 1, 2], [0, 2, 3]])
    centre_z = height - plate.vertices[:, 2].max()  # the plate's height in the centred frame is what prepare_mesh kept
    plate_alone = compute_rcs(plate, f_ghz, 0.0, 90.0, quality="draft", error_estimate=False)
    expected_plate = -1j * k * side**2 / (2.0 * math.pi) * np.exp(2j * k * (height - centre_z))
    assert plate_alone.rcs_m2("VV")[0, 0, 0] == pytest.approx(4.0 * math.pi * abs(expected_plate) ** 2, rel=1e-3)
    wire = _dipole(0.47 * C_LIGHT / (f_ghz * 1e9), 2e-4, axis=(1.0, 0.0, 0.0), centre=(0.0, 0.0, 0.004))
    plate.wires = wire
    both = compute_rcs(plate, f_ghz, 0.0, 90.0, quality="draft", error_estimate=False)
    wire_amp = scattering_amplitude(
        wire, f_ghz, (np.array([0.0]), np.array([90.0])), (np.zeros((1, 1)), np.full((1, 1), 90.0))
    )
    # at el 90 deg, az 0: V = theta-hat = (1, 0, 0), along the wire; H = (0, 1, 0)
    expected = 4.0 * math.pi * abs(expected_plate + wire_amp[0, 0, 0, 0]) ** 2
    assert both.rcs_m2("VV")[0, 0, 0] == pytest.approx(expected, rel=2e-3)
    assert both.rcs_m2("HH")[0, 0, 0] == pytest.approx(plate_alone.rcs_m2("HH")[0, 0, 0], rel=1e-6)
