"""A swarm traced together by SBR-PO (issue 26, section 3): N PEC spheres against the closed form of N point
scatterers (one sphere's RCS times the array factor |sum exp(j 2 k u . r_i)|^2)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from csuas.cli import main
from csuas.core.swarm import array_factor, line_of_sight_axes, target_frame_offsets_m
from csuas.render.rcs import canonical
from csuas.render.rcs.geometry import formation_target, load_target
from csuas.render.rcs.solver import compute_rcs
from csuas.validation.rcs.model_error import po_sphere_over_pia2

C = 299_792_458.0
A_M, KA = 0.05, 10.0
F_GHZ = KA * C / (2 * math.pi * A_M) / 1e9
LAMBDA_M = C / (F_GHZ * 1e9)
#: Three spheres 0.25-0.39 m apart across the line of sight (radar along +x), a few mm apart along it: the
#: phases 2 k x differ by about a radian; no sphere shadows another.
OFFSETS_M = np.array([[0.0, 0.0, 0.0], [0.0123, 0.3, 0.0], [-0.0071, -0.25, 0.2]])


def _db(x):
    return 10 * math.log10(x)


def test_the_formation_frame_points_x_away_from_the_sensor():
    axes = line_of_sight_axes(90.0, 30.0)  # the sensor toward +y, 30 deg up
    np.testing.assert_allclose(axes[0], [0, -math.cos(math.radians(30)), -0.5], atol=1e-15)
    np.testing.assert_allclose(axes[1], [-1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(axes @ axes.T, np.eye(3), atol=1e-15)
    assert target_frame_offsets_m([[0, 2.0, 0]], 0.0, 0.0).tolist() == [[0, 2.0, 0]]


def test_array_factor_closed_forms():
    # N in phase (a line across the line of sight, broadside): N^2; two half a wavelength apart along it: 0
    assert array_factor([[0, y, 0] for y in (0, 1, 2, 3)], [1, 0, 0], [1, 0, 0], 0.03) == pytest.approx(16.0)
    assert array_factor([[0, 0, 0], [0.25 * 0.03, 0, 0]], [1, 0, 0], [1, 0, 0], 0.03) == pytest.approx(0, abs=1e-28)


def test_n_spheres_traced_together_are_one_sphere_times_the_array_factor():
    one = load_target(canonical.sphere(A_M, 5))
    kwargs = dict(rays_per_wavelength=10, max_bounces=1, error_estimate=False)
    sigma_one = compute_rcs(one, F_GHZ, 0.0, 0.0, **kwargs).rcs_m2("VV").ravel()[0]
    sigma_n = compute_rcs(formation_target(one, OFFSETS_M), F_GHZ, 0.0, 0.0, **kwargs).rcs_m2("VV").ravel()[0]
    factor = array_factor(OFFSETS_M, [1, 0, 0], [1, 0, 0], LAMBDA_M)
    assert 1.0 < factor < 5.0  # neither in phase (9) nor cancelling: the phases matter
    # single bounces: exactly the coherent sum of the three spheres' fields (the tube grid moves with each)
    assert abs(_db(sigma_n) - _db(factor * sigma_one)) < 0.01
    # against the PO sphere (Knott et al., ch. 5) times the array factor, the tolerance of tests/test_rcs_oracles
    # (point-sampled tubes lack the shadow-boundary term, relative amplitude 2 / (2 ka))
    po = math.pi * A_M**2 * po_sphere_over_pia2(KA) * factor
    assert abs(_db(sigma_n) - _db(po)) <= 0.25 + 20 * math.log10(1 + 4.0 / (2 * KA))


def test_csuas_rcs_traces_a_swarm_and_reports_the_closed_form_beside_it(tmp_path, capsys):
    mesh = tmp_path / "sphere.stl"
    canonical.sphere(A_M, 5).export(mesh)
    argv = ["rcs", str(mesh), "--frequency-ghz", repr(F_GHZ), "--rays-per-wavelength", "10", "--max-bounces", "1"]
    offsets = ";".join(",".join(repr(float(v)) for v in row) for row in OFFSETS_M)
    assert main([*argv, "--no-error-estimate", f"--swarm-offsets-m={offsets}", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    swarm = out["swarm"]
    assert swarm["count"] == 3 and swarm["formation"] == "offsets"
    # the radar along +x: x away from it is -x of the mesh, y and z as they are
    np.testing.assert_allclose(swarm["mesh_offsets_m"], OFFSETS_M * [-1, 1, 1], atol=1e-15)
    factor = array_factor(OFFSETS_M * [-1, 1, 1], [1, 0, 0], [1, 0, 0], LAMBDA_M)
    assert swarm["array_factor"] == pytest.approx(factor, rel=1e-12)
    assert abs(_db(out["rcs_m2"]) - _db(swarm["point_scatterer_rcs_m2"])) < 0.01
    assert swarm["random_phase_mean_rcs_m2"] == pytest.approx(3 * swarm["single_rcs_m2"], rel=1e-12)


def test_bad_swarm_options_name_the_option(tmp_path, capsys):
    mesh = tmp_path / "sphere.stl"
    canonical.sphere(A_M, 2).export(mesh)
    assert main(["rcs", str(mesh), "--frequency-ghz", "3", "--swarm-count", "3"]) == 2
    assert "swarm = {'count': 3} is invalid; allowed: count and spacing_m together" in capsys.readouterr().err
    assert main(["rcs", str(mesh), "--frequency-ghz", "3", "--swarm-count", "1", "--swarm-spacing-m", "2"]) == 2
    assert "swarm.count = 1" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["rcs", str(mesh), "--frequency-ghz", "3", "--swarm-offsets-m", "1,2;3,4,5"])
    assert exc.value.code == 2 and "'1,2' is not X,Y,Z" in capsys.readouterr().err
