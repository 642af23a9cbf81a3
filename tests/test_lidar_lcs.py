"""Lidar cross-section of Lambertian targets against closed forms (docs/validation.md, docs/simulation.md).

Oracles written here, independent of csuas:
* Lambertian sphere, radius a, albedo rho: LCS = (8/3) rho pi a^2.
* Convex polyhedron (each facet a plate, no self-shadowing): LCS = 4 rho sum_f A_f max(0, n_f . d)^2;
  its sphere average is (2/3) rho S (the orientation mean of max(0, cos)^2 is 1/6), S the surface area.
* Lambertian flat plate, area A, incidence theta: LCS = 4 rho A cos^2(theta) (4 rho A at normal incidence):
  the plate intercepts E A cos(theta) and sends (rho / pi) E cos(theta) A cos(theta) back per unit solid angle.
* Point source at distance R from a Lambertian sphere, cross-section referred to the centre:
  sigma(R) = 8 pi rho a^2 * int_eps^1 (x - eps)^2 / (1 - 2 eps x + eps^2)^3 dx, eps = a / R
  (surface element at polar angle acos x: distance^2 = R^2 (1 - 2 eps x + eps^2),
  cos(incidence) = (x - eps) / (distance / R)).
"""

import math

import numpy as np
import pytest
import trimesh
from scipy.integrate import quad

from csuas.base.errors import ParameterError
from csuas.render.lidar import LidarTarget, lidar_cross_section, material_reflectance
from csuas.render.lidar.cross_section import RayGrid
from csuas.render.lidar.path import path_traced_lcs
from csuas.render.lidar.sphere_average import mean_lidar_cross_section
from csuas.validation.lidar.accuracy import accuracy_vs_time, preset_accuracy

pytestmark = pytest.mark.slow

RHO_SPHERE, A_SPHERE = 0.5, 0.1
RHO_PLATE, PLATE_X, PLATE_Y = 0.3, 0.2, 0.1


def unit(az_deg, el_deg):
    az, el = math.radians(az_deg), math.radians(el_deg)
    return np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])


def plate_mesh(x=PLATE_X, y=PLATE_Y, z=0.0):
    v = [[-x / 2, -y / 2, z], [x / 2, -y / 2, z], [x / 2, y / 2, z], [-x / 2, y / 2, z]]
    return trimesh.Trimesh(v, [[0, 1, 2], [0, 2, 3]], process=False)


def within(value, expected, stderr, rel=0.0, sigmas=5.0):
    return abs(value - expected) <= sigmas * stderr + rel * abs(expected) + 1e-15


@pytest.fixture(scope="module")
def icosphere():
    return trimesh.creation.icosphere(subdivisions=4, radius=A_SPHERE)


@pytest.fixture(scope="module")
def sphere(icosphere):
    return LidarTarget.from_mesh(icosphere, RHO_SPHERE, name="sphere")


@pytest.fixture(scope="module")
def plate():
    return LidarTarget.from_mesh(plate_mesh(), RHO_PLATE, name="plate")


def faceted_exact(mesh, rho, d):
    cos = np.clip(mesh.face_normals @ d, 0.0, None)
    return 4.0 * rho * float(np.sum(mesh.area_faces * cos**2))


# ---------------------------------------------------------------- sphere
@pytest.mark.parametrize("az,el", [(20.0, 30.0), (0.0, 90.0), (-135.0, -60.0)])
def test_sphere_lcs_matches_faceted_and_smooth_closed_forms(sphere, icosphere, az, el):
    r = lidar_cross_section(sphere, az, el, quality="standard")
    exact = faceted_exact(icosphere, RHO_SPHERE, unit(az, el))
    assert within(r.lcs_m2, exact, r.stderr_m2, rel=2e-5)
    smooth = 8.0 / 3.0 * RHO_SPHERE * math.pi * A_SPHERE**2
    # faceting: the icosphere's LCS differs from the smooth sphere's by its flat facets (~0.1-0.2 %)
    assert abs(r.lcs_m2 / smooth - 1.0) < 3e-3
    assert abs(r.projected_area_m2 / (math.pi * A_SPHERE**2) - 1.0) < 5e-3
    assert 0.0 < r.stderr_m2 < 1e-3 * r.lcs_m2 and r.time_s > 0.0 and r.rays == 128 * 128 * 8


def test_sphere_average_equals_two_thirds_rho_surface():
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=A_SPHERE)
    target = LidarTarget.from_mesh(mesh, 0.4)
    r = mean_lidar_cross_section(target, "draft")
    expected = 2.0 / 3.0 * 0.4 * mesh.area
    assert within(r["lcs_m2"]["mean"], expected, r["lcs_m2"]["stderr"], rel=1e-4)
    assert r["n_directions"] == 96 and r["time_s"] > 0.0
    # Cauchy: mean projected area of a convex body = S / 4
    assert within(r["projected_area_m2"]["mean"], mesh.area / 4.0, r["projected_area_m2"]["stderr"], rel=1e-3)


# ---------------------------------------------------------------- plate
def test_plate_normal_incidence_is_four_rho_area(plate):
    for el in (90.0, -90.0):  # both faces
        r = lidar_cross_section(plate, 0.0, el, quality="draft")
        assert r.lcs_m2 == pytest.approx(4.0 * RHO_PLATE * PLATE_X * PLATE_Y, rel=1e-5)


@pytest.mark.parametrize("theta_deg", [10.0, 30.0, 45.0, 60.0, 80.0, 89.0])
@pytest.mark.parametrize("az", [0.0, 37.0, 90.0])
def test_plate_oblique_incidence_cos_squared(plate, theta_deg, az):
    r = lidar_cross_section(plate, az, 90.0 - theta_deg, quality="draft")
    expected = 4.0 * RHO_PLATE * PLATE_X * PLATE_Y * math.cos(math.radians(theta_deg)) ** 2
    assert within(r.lcs_m2, expected, r.stderr_m2, rel=1e-4)


def test_plate_edge_on_is_zero_and_finite(plate):
    for az in (0.0, 90.0, 33.0):
        r = lidar_cross_section(plate, az, 0.0, quality="draft")
        assert math.isfinite(r.lcs_m2) and math.isfinite(r.stderr_m2)
        assert 0.0 <= r.lcs_m2 < 1e-12


@pytest.mark.parametrize("el", [0.001, 0.01, 0.1, 1.0])
def test_plate_grazing_incidence_stable(plate, el):
    r = lidar_cross_section(plate, 20.0, el, quality="draft")
    expected = 4.0 * RHO_PLATE * PLATE_X * PLATE_Y * math.sin(math.radians(el)) ** 2
    assert math.isfinite(r.lcs_m2) and r.lcs_m2 >= 0.0
    assert within(r.lcs_m2, expected, r.stderr_m2, rel=1e-3)


def test_shadowing_of_a_rear_plate_by_a_front_plate():
    # front 0.1 x 0.1 at z = +0.05 over rear 0.2 x 0.1 at z = -0.05; seen from +z (0 and 20 deg off normal about y)
    # the front plate's shadow falls fully on the rear one (shift 0.1 tan 20 deg = 0.036 < 0.05)
    target = LidarTarget.from_mesh([plate_mesh(0.1, 0.1, 0.05), plate_mesh(0.2, 0.1, -0.05)], 0.5)
    for theta in (0.0, 20.0):
        r = lidar_cross_section(target, 0.0, 90.0 - theta, quality="standard")
        visible = 0.01 + (0.02 - 0.01)  # front + unshadowed rear
        assert within(r.lcs_m2, 4.0 * 0.5 * visible * math.cos(math.radians(theta)) ** 2, r.stderr_m2, rel=1e-4)


# ---------------------------------------------------------------- range normalisation
def test_same_far_field_result_at_20_km_and_plane_wave(sphere):
    plane = lidar_cross_section(sphere, 20.0, 30.0, math.inf, "standard", seed=3)
    far = lidar_cross_section(sphere, 20.0, 30.0, 2.0e4, "standard", seed=3)
    assert within(far.lcs_m2, plane.lcs_m2, math.hypot(far.stderr_m2, plane.stderr_m2), rel=1e-6)
    assert far.range_m == 2.0e4


def test_near_range_sphere_closed_form_at_10_m(sphere, icosphere):
    eps = A_SPHERE / 10.0
    ratio, _ = quad(lambda x: (x - eps) ** 2 / (1 - 2 * eps * x + eps * eps) ** 3, eps, 1.0)
    ratio *= 3.0  # relative to the far-field 1/3
    near = lidar_cross_section(sphere, 20.0, 30.0, 10.0, "standard", seed=3)
    plane = lidar_cross_section(sphere, 20.0, 30.0, math.inf, "standard", seed=3)
    assert near.lcs_m2 / plane.lcs_m2 == pytest.approx(ratio, abs=1e-3)
    assert ratio == pytest.approx(1.0152, abs=1e-4)


def test_beam_footprint_on_a_plate_is_a_disk(plate):
    radius = 0.03
    r = lidar_cross_section(plate, 0.0, 90.0, quality="standard", beam_radius_m=radius)
    assert within(r.lcs_m2, 4.0 * RHO_PLATE * math.pi * radius**2, r.stderr_m2, rel=1e-4)
    assert within(r.projected_area_m2, math.pi * radius**2, r.projected_area_stderr_m2, rel=1e-4)


# ---------------------------------------------------------------- properties
def test_linear_in_albedo_deterministic_and_image_sums_to_lcs(icosphere):
    a = lidar_cross_section(LidarTarget.from_mesh(icosphere, 0.2), 10.0, 5.0, quality="draft", seed=7, keep_image=True)
    b = lidar_cross_section(LidarTarget.from_mesh(icosphere, 0.4), 10.0, 5.0, quality="draft", seed=7)
    c = lidar_cross_section(LidarTarget.from_mesh(icosphere, 0.2), 10.0, 5.0, quality="draft", seed=7)
    assert b.lcs_m2 == pytest.approx(2.0 * a.lcs_m2, rel=1e-6)
    assert c.lcs_m2 == a.lcs_m2
    assert a.image_m2.sum() == pytest.approx(a.lcs_m2, rel=1e-9)
    assert np.all(a.image_m2 >= 0.0)


def test_batched_passes_give_identical_results(sphere, monkeypatch):
    # memory bound: rays go to Mitsuba in passes of at most MAX_RAYS_PER_BATCH; passes do not change the estimate
    import csuas.render.lidar.cross_section as cs

    whole = lidar_cross_section(sphere, 10.0, 20.0, quality="draft", seed=5)
    monkeypatch.setattr(cs, "MAX_RAYS_PER_BATCH", 1000)
    passes = lidar_cross_section(sphere, 10.0, 20.0, quality="draft", seed=5)
    assert passes.lcs_m2 == pytest.approx(whole.lcs_m2, rel=1e-12) and passes.rays == whole.rays


def test_degenerate_and_open_meshes_give_finite_results(icosphere):
    v = np.vstack([icosphere.vertices, [[0.0, 0.0, 0.0]] * 3])
    n = len(icosphere.vertices)
    f = np.vstack([icosphere.faces, [[n, n + 1, n + 2], [0, 0, 1]]])  # zero-area faces
    dirty = trimesh.Trimesh(v, f, process=False)
    clean = lidar_cross_section(LidarTarget.from_mesh(icosphere, 0.5), 0, 45, quality="draft", seed=1)
    r = lidar_cross_section(LidarTarget.from_mesh(dirty, 0.5), 0, 45, quality="draft", seed=1)
    assert r.lcs_m2 == pytest.approx(clean.lcs_m2, rel=1e-6)
    half = trimesh.Trimesh(icosphere.vertices, icosphere.faces[icosphere.triangles_center[:, 2] > 0], process=False)
    open_r = lidar_cross_section(LidarTarget.from_mesh(half, 0.5), 0, 90, quality="draft")
    assert math.isfinite(open_r.lcs_m2) and open_r.lcs_m2 > 0.0


def test_material_albedo_interpolation():
    from csuas.drone_models import get_material

    paint = get_material("paint")
    assert material_reflectance(paint, 1550.0) == paint.reflectance_1550nm
    assert material_reflectance(paint, 1560.0) == paint.reflectance_1550nm
    mid = material_reflectance(paint, 1050.0)
    assert mid == pytest.approx(0.5 * (paint.reflectance_550nm + paint.reflectance_1550nm))


# ---------------------------------------------------------------- multi-bounce (path tracing)
def test_path_traced_single_bounce_matches_ray_tracer_and_plate(plate):
    r = path_traced_lcs(plate, 30.0, 50.0, max_depth=2, quality="draft")
    exact = 4.0 * RHO_PLATE * PLATE_X * PLATE_Y * math.sin(math.radians(50.0)) ** 2
    assert within(r["lcs_m2"], exact, r["stderr_m2"], rel=1e-4)


def test_multibounce_adds_interreflection_in_a_corner():
    # 90-degree dihedral seen along its bisector: single bounce sees both faces at 45 deg,
    # multiple bounces add light reflected from one face onto the other and back
    a = 0.1
    faces = [
        trimesh.Trimesh([[0, 0, 0], [a, 0, 0], [a, 0, a], [0, 0, a]], [[0, 1, 2], [0, 2, 3]], process=False),
        trimesh.Trimesh([[0, 0, 0], [0, a, 0], [0, a, a], [0, 0, a]], [[0, 1, 2], [0, 2, 3]], process=False),
    ]
    target = LidarTarget.from_mesh(faces, 0.8)
    single = lidar_cross_section(target, 45.0, 0.0, quality="standard")
    assert within(single.lcs_m2, 2 * 4.0 * 0.8 * a * a * 0.5, single.stderr_m2, rel=1e-4)
    p2 = path_traced_lcs(target, 45.0, 0.0, max_depth=2, quality="draft")
    many = path_traced_lcs(target, 45.0, 0.0, max_depth=16, quality="draft")
    assert within(p2["lcs_m2"], single.lcs_m2, math.hypot(p2["stderr_m2"], single.stderr_m2), rel=1e-4)
    assert many["lcs_m2"] > p2["lcs_m2"] + 5 * math.hypot(many["stderr_m2"], p2["stderr_m2"])


# ---------------------------------------------------------------- accuracy against time
def test_presets_measured_error_within_their_stated_error():
    rows = preset_accuracy()
    assert [r["quality"] for r in rows] == ["draft", "standard", "reference"]
    for r in rows:
        assert abs(r["error_rel"]) <= 5.0 * r["stderr_rel"] + 2e-5
        assert r["time_s"] > 0.0
    assert rows[0]["stderr_rel"] > rows[1]["stderr_rel"] > rows[2]["stderr_rel"]


def test_accuracy_vs_time_rows():
    rows = accuracy_vs_time(grids=(8, 32, 128), replicates=4)
    assert [r["grid"] for r in rows] == [8, 32, 128]
    assert rows[0]["stderr_rel"] > rows[1]["stderr_rel"] > rows[2]["stderr_rel"]
    assert all(abs(r["error_rel"]) <= 5.0 * r["stderr_rel"] + 2e-5 for r in rows)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize("rho", [-0.1, 1.5, float("nan"), "grey"])
def test_bad_reflectance(icosphere, rho):
    with pytest.raises(ParameterError, match="reflectance"):
        LidarTarget.from_mesh(icosphere, rho)


@pytest.mark.parametrize("range_m", [0.0, -5.0, float("nan"), 0.1, "far"])
def test_bad_range(sphere, range_m):
    with pytest.raises(ParameterError, match="range_m"):
        lidar_cross_section(sphere, 0.0, 0.0, range_m, "draft")


@pytest.mark.parametrize(
    "kwargs,name",
    [
        ({"quality": "ultra"}, "quality"),
        ({"quality": RayGrid(0, 8)}, "grid"),
        ({"quality": RayGrid(48, 1)}, "replicates"),
        ({"azimuth_deg": 400.0}, "azimuth_deg"),
        ({"elevation_deg": 95.0}, "elevation_deg"),
        ({"beam_radius_m": 0.0}, "beam_radius_m"),
    ],
)
def test_bad_options(sphere, kwargs, name):
    with pytest.raises(ParameterError, match=name):
        lidar_cross_section(sphere, **kwargs)


def test_bad_meshes_and_path_options(plate):
    with pytest.raises(ParameterError, match="mesh"):
        LidarTarget.from_mesh(trimesh.Trimesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=int)), 0.5)
    with pytest.raises(ParameterError, match="mesh"):
        LidarTarget.from_mesh(trimesh.Trimesh([[0, 0, 0]] * 3, [[0, 1, 2]], process=False), 0.5)
    with pytest.raises(ParameterError, match="max_depth"):
        path_traced_lcs(plate, max_depth=1)
    with pytest.raises(ParameterError, match="spp"):
        path_traced_lcs(plate, spp=0)


def test_report_oracle_rows_pass_at_draft_quality():
    from csuas.validation.lidar.oracles import near_range_sphere_factor, oracle_comparisons

    rows = oracle_comparisons("draft")
    assert len(rows) == 7 and all(r["ok"] for r in rows), [r["name"] for r in rows if not r["ok"]]
    assert all(r["time_s"] > 0.0 and r["stderr"] >= 0.0 for r in rows)
    assert near_range_sphere_factor(0.1, 1e9) == pytest.approx(1.0, abs=1e-7)
