"""`csuas drone`, mesh export, the defaults checks and the benchmark function."""

import json

import numpy as np
import pytest
import trimesh

from csuas.base.checks import Check
from csuas.base.errors import ParameterError
from csuas.cli import main
from csuas.drone_models import build_drone
from csuas.drone_models.export import export_drone
from csuas.validation.drone.bench import bench_silhouette
from csuas.validation.drone.checks import default_checks


def run_json(capsys, *argv):
    code = main(["drone", *argv, "--json"])
    out = capsys.readouterr().out
    return code, json.loads(out)


def test_cli_json_keys_and_values(capsys):
    code, result = run_json(capsys, "dji_mini_4_pro", "--quality", "draft")
    assert code == 0
    assert result["bbox_m"] == pytest.approx([0.298, 0.373, 0.101], rel=0.01)
    assert result["d_crit_m"]["min"] == pytest.approx(0.101, rel=0.03)  # default view: side
    assert result["d_crit_m"]["geometric_mean"] == pytest.approx(np.sqrt(0.298 * 0.101), rel=0.02)
    assert result["projected_area_m2"] > 0
    assert result["mass_kg"] == pytest.approx(0.249)
    avg = result["sphere_average"]
    assert avg["n_directions"] == 256
    assert avg["projected_area_m2"]["stderr"] < 0.02 * avg["projected_area_m2"]["mean"]
    assert result["lcs_m2"]["sphere_average"] == pytest.approx(0.1 * avg["projected_area_m2"]["mean"])
    assert result["mesh"]["parts_watertight"] is True
    assert result["time_s"] > 0


def test_cli_view_from_above(capsys):
    code, result = run_json(
        capsys, "black_hornet_3", "--azimuth-deg", "0", "--elevation-deg", "90", "--quality", "none"
    )
    assert code == 0 and "sphere_average" not in result
    assert result["view"]["h_axis"] == pytest.approx([0, 1, 0], abs=1e-12)
    assert result["d_y_proj_m"] == pytest.approx(0.168, rel=0.01)  # seen from above: length along v
    assert result["d_x_proj_m"] == pytest.approx(0.123, rel=0.01)  # rotor disc across
    code, bare = run_json(
        capsys, "black_hornet_3", "--elevation-deg", "90", "--quality", "none", "--propellers", "none"
    )
    assert bare["propellers"] == "none" and bare["projected_area_m2"] < 0.2 * result["projected_area_m2"]


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["dji_mini_5"], "preset"),
        (["dji_mini_4_pro", "--elevation-deg", "120"], "elevation_deg"),
        (["dji_mini_4_pro", "--azimuth-deg", "nan"], "azimuth_deg"),
        (["dji_mini_4_pro", "--export", "drone.stl"], "export"),
        (["dji_mini_4_pro", "--t-illum", "0"], "t_illum"),
    ],
)
def test_cli_bad_input_is_one_line_exit_2(capsys, argv, fragment):
    assert main(["drone", *argv, "--quality", "none"]) == 2
    err = capsys.readouterr().err
    assert fragment in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_cli_reads_an_open_mesh_file(tmp_path, capsys):
    box = trimesh.creation.box(extents=[0.3, 0.2, 0.1])
    top = np.where(box.face_normals[:, 2] > 0.5)[0]
    trimesh.Trimesh(box.vertices, np.delete(box.faces, top, axis=0), process=False).export(tmp_path / "open.obj")
    code, result = run_json(capsys, str(tmp_path / "open.obj"), "--azimuth-deg", "0", "--quality", "none")
    assert code == 0
    assert result["mesh"]["watertight"] is False and len(result["warnings"]) == 1
    assert result["mass_kg"] is None
    assert result["projected_area_m2"] == pytest.approx(0.2 * 0.1, rel=1e-6)  # seen along x: width x height
    assert main(["drone", str(tmp_path / "missing.ply")]) == 2


def test_cli_text_output(capsys):
    assert main(["drone", "dji_mavic_3", "--quality", "draft"]) == 0
    text = capsys.readouterr().out
    assert "d_crit (Eq. 1 min)" in text and "sphere average" in text


@pytest.mark.parametrize("suffix", [".ply", ".obj", ".glb"])
def test_export_round_trip(tmp_path, suffix):
    drone = build_drone("black_hornet_3")
    path = export_drone(drone, tmp_path / f"bh3{suffix}")
    assert [p.name for p in tmp_path.iterdir()] == [f"bh3{suffix}"]  # no temporary left behind
    loaded = trimesh.load(path, force="mesh")
    assert loaded.area == pytest.approx(sum(p.mesh.area for p in drone.parts), rel=1e-5)
    np.testing.assert_allclose(loaded.bounds, drone.bounds(), atol=1e-6)
    if suffix == ".glb":
        scene = trimesh.load(path)
        assert set(scene.geometry) == {p.name for p in drone.parts}


def test_export_bad_suffix_writes_nothing(tmp_path):
    with pytest.raises(ParameterError, match="export"):
        export_drone(build_drone("black_hornet_3"), tmp_path / "x.stl")
    assert list(tmp_path.iterdir()) == []


def test_cli_export(tmp_path, capsys):
    target = tmp_path / "mini.glb"
    code, result = run_json(capsys, "dji_mini_4_pro", "--quality", "none", "--export", str(target))
    assert code == 0 and result["export"] == str(target) and target.stat().st_size > 1000


def test_default_checks():
    checks = {c.name: c for c in default_checks()}
    assert all(isinstance(c, Check) for c in checks.values())
    d_crit = checks["T8.d_crit_m.dji_mini_4_pro"]
    assert d_crit.ok and d_crit.expected == 0.101 and d_crit.details["rel_tol"] == 0.03
    assert checks["T52.d_crit_m.black_hornet_3"].ok
    lcs = checks["T8.sigma_lidar_m2.dji_mini_4_pro"]
    assert lcs.expected == 0.006
    # recomputed from the mesh: k_LCS x sphere-averaged projected area
    assert lcs.measured == pytest.approx(0.1 * lcs.details["projected_area_mean_m2"])
    assert lcs.details["projected_area_side_m2"] < lcs.measured / 0.1 < lcs.details["projected_area_top_m2"]
    assert lcs.ok or lcs.known_deviation
    emissivity = checks["T27.emissivity_suas.dji_mini_4_pro"]
    assert emissivity.ok or emissivity.known_deviation
    for c in checks.values():
        d = c.as_dict()
        assert {"name", "paper", "computed", "ok"} <= set(d)
        json.dumps(d)


def test_bench_function_small():
    figures = bench_silhouette(n_directions=40, n_reference=4)
    assert figures["n_directions"] == 40 and figures["time_s"] > 0
    assert figures["max_area_difference_m2"] < 1e-12  # fast and reference paths are both exact
    assert figures["speedup_vs_triangle_union"] > 1


def test_a_sphere_average_beyond_the_time_budget_is_refused_before_it_starts(capsys, tmp_path):
    """An open mesh forces the triangle union: 20 k triangles x 256 views at 1.8e-5 s each is about 92 s."""
    import time

    import numpy as np
    import trimesh

    from csuas.cli import main

    sphere = trimesh.creation.icosphere(subdivisions=5)  # 20480 faces
    open_mesh = trimesh.Trimesh(sphere.vertices, sphere.faces[:-1], process=False)
    path = tmp_path / "open.ply"
    open_mesh.export(path)
    start = time.process_time()  # this process's CPU time: the average would spend 92 s of it, load adds none
    assert main(["drone", str(path), "--quality", "draft", "--max-seconds", "10"]) == 2
    err = capsys.readouterr().err
    assert "max_seconds" in err and "--max-seconds" in err and "256 views" in err
    assert time.process_time() - start < 10.0
    estimate = float(err.split("estimated ")[1].split(" s")[0])
    assert estimate == pytest.approx(1.8e-5 * (len(open_mesh.faces)) * 256, rel=0.05)
    assert np.isfinite(estimate)
