"""Exact silhouette metrics against exact geometry (boxes, prisms, spheres, degenerate meshes).

Independent references: the projected area of a convex polytope is the sum of
|n_i . d| A_i / 2 over its faces (each point of the shadow is covered twice);
for an axis-aligned box a x b x c that is b c |d_x| + a c |d_y| + a b |d_z|,
and its extent along a unit image axis u is a |u_x| + b |u_y| + c |u_z|.
A right prism with cap polygon P (area A) and height H projects to the
Minkowski sum of P's projection and the projected axis segment:
A |cos t| + H sin t * w, with w P's width across the axis and d.
"""

import warnings

import numpy as np
import pytest
import shapely
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

from csuas.base.errors import ParameterError
from csuas.drone_models.geometry import direction_vector, fibonacci_sphere, random_rotations
from csuas.drone_models.silhouette import (
    NonWatertightWarning,
    SilhouetteModel,
    metrics_for_directions,
    projected_metrics,
)
from csuas.drone_models.sphere_average import sphere_average

RNG = np.random.default_rng(20240611)
ANGLES = [
    (float(a), float(e)) for a, e in zip(RNG.uniform(-180, 180, 12), np.degrees(np.arcsin(RNG.uniform(-1, 1, 12))))
]


def image_axes(d):
    """The documented image axes, written out independently: h = z x d / |z x d|, v = d x h."""
    h = np.cross([0.0, 0.0, 1.0], d)
    h /= np.linalg.norm(h)
    return h, np.cross(d, h)


def box_reference(extents, rotation, d):
    a, b, c = extents
    dl = rotation.T @ d
    h, v = image_axes(d)
    hl, vl = rotation.T @ h, rotation.T @ v
    area = b * c * abs(dl[0]) + a * c * abs(dl[1]) + a * b * abs(dl[2])
    return area, np.dot(extents, np.abs(hl)), np.dot(extents, np.abs(vl))


@pytest.mark.parametrize("az, el", ANGLES)
def test_rotated_box_at_arbitrary_direction(az, el):
    extents = np.array([0.31, 0.17, 0.05])
    rotation = random_rotations(1, np.random.default_rng(int(1000 + az)))[0]
    transform = np.eye(4)
    transform[:3, :3] = rotation
    transform[:3, 3] = [0.1, -0.2, 0.3]
    mesh = trimesh.creation.box(extents=extents, transform=transform)
    d = direction_vector(az, el)
    area, dx, dy = box_reference(extents, rotation, d)
    m = projected_metrics(mesh, az, el)
    assert m["projected_area_m2"] == pytest.approx(area, rel=1e-12)
    assert m["d_x_proj_m"] == pytest.approx(dx, rel=1e-12)
    assert m["d_y_proj_m"] == pytest.approx(dy, rel=1e-12)
    assert m["d_crit_min_m"] == pytest.approx(min(dx, dy), rel=1e-12)
    assert m["d_crit_geometric_mean_m"] == pytest.approx(np.sqrt(dx * dy), rel=1e-12)
    assert m["sphere_equivalent_radius_m"] == pytest.approx(np.sqrt(area / np.pi), rel=1e-12)
    assert m["silhouette"].area == pytest.approx(area, rel=1e-12)
    assert m["watertight"] and m["n_degenerate_faces"] == 0


def test_box_triangle_union_path_matches_convex_path():
    mesh = trimesh.creation.box(extents=[0.2, 0.1, 0.04])
    dirs = fibonacci_sphere(40)
    fast = metrics_for_directions(SilhouetteModel.from_mesh(mesh), dirs)
    slow = metrics_for_directions(SilhouetteModel.from_mesh(mesh, use_convex_hulls=False), dirs)
    ref = np.array([box_reference([0.2, 0.1, 0.04], np.eye(3), d)[0] for d in dirs])
    np.testing.assert_allclose(fast["projected_area_m2"], ref, rtol=1e-12)
    np.testing.assert_allclose(slow["projected_area_m2"], ref, rtol=1e-12)


@pytest.mark.parametrize("az, el", ANGLES[:6] + [(0.0, 0.0), (37.0, 90.0), (10.0, -90.0)])
def test_tilted_cylinder_prism(az, el):
    radius, height, sections = 0.05, 0.2, 64
    axis_rot = random_rotations(1, np.random.default_rng(7))[0]
    a = axis_rot @ [0.0, 0.0, 1.0]
    mesh = trimesh.creation.cylinder(radius=radius, segment=[-a * height / 2, a * height / 2], sections=sections)
    d = direction_vector(az, el)
    cos_t = abs(a @ d)
    sin_t = np.sqrt(max(0.0, 1 - cos_t**2))
    cap = mesh.vertices[np.abs(mesh.vertices @ a - height / 2) < 1e-9]
    cap_area = sections / 2 * radius**2 * np.sin(2 * np.pi / sections)  # regular n-gon, circumradius r
    across = np.cross(a, d)
    width = np.ptp(cap @ (across / np.linalg.norm(across))) if sin_t > 1e-12 else 0.0
    area = cap_area * cos_t + height * sin_t * width
    # extents: smooth cylinder value minus at most the facet sagitta
    h, v = image_axes(d) if abs(d[2]) < 1 else (None, None)
    m = projected_metrics(mesh, az, el)
    assert m["projected_area_m2"] == pytest.approx(area, rel=1e-10)
    smooth_area = np.pi * radius**2 * cos_t + 2 * radius * height * sin_t
    assert m["projected_area_m2"] <= smooth_area * (1 + 1e-12)
    assert m["projected_area_m2"] >= smooth_area * np.cos(np.pi / sections) ** 2
    if h is not None:
        for axis, key in ((h, "d_x_proj_m"), (v, "d_y_proj_m")):
            ua = axis @ a
            smooth = 2 * radius * np.sqrt(max(0.0, 1 - ua**2)) + height * abs(ua)
            assert smooth * np.cos(np.pi / sections) - 1e-12 <= m[key] <= smooth + 1e-12


@pytest.mark.parametrize("subdivisions", [2, 4])
def test_icosphere_area_within_faceting_bounds(subdivisions):
    r = 0.1
    mesh = trimesh.creation.icosphere(subdivisions=subdivisions, radius=r)
    centroids = mesh.triangles_center
    r_in = np.min(np.abs(np.sum(mesh.face_normals * centroids, axis=1)))  # inscribed-sphere radius
    dirs = fibonacci_sphere(30)
    out = metrics_for_directions(SilhouetteModel.from_mesh(mesh), dirs)
    assert np.all(out["projected_area_m2"] <= np.pi * r**2)
    assert np.all(out["projected_area_m2"] >= np.pi * r_in**2)
    assert np.all(out["d_x_proj_m"] <= 2 * r + 1e-15) and np.all(out["d_x_proj_m"] >= 2 * r_in)


def test_sphere_average_of_convex_body_is_quarter_surface_area():
    """Cauchy's formula: mean projected area of a convex body = surface area / 4."""
    rot = random_rotations(1, np.random.default_rng(5))[0]
    transform = np.eye(4)
    transform[:3, :3] = rot
    mesh = trimesh.creation.box(extents=[0.3, 0.12, 0.02], transform=transform)
    avg = sphere_average(mesh, quality="draft", seed=11)
    a = avg["projected_area_m2"]
    exact = mesh.area / 4
    assert abs(a["mean"] - exact) < 5 * a["stderr"] + 1e-12
    assert a["stderr"] < 5e-3 * exact
    # the error estimate shrinks with more directions
    finer = sphere_average(mesh, replicates=8, directions_per_replicate=256, seed=11)["projected_area_m2"]
    assert finer["stderr"] < a["stderr"]
    assert abs(finer["mean"] - exact) < 5 * finer["stderr"] + 1e-12
    assert avg["n_directions"] == 256 and avg["time_s"] > 0


def test_sphere_average_deterministic_for_seed_and_validates():
    mesh = trimesh.creation.box(extents=[0.1, 0.1, 0.1])
    a = sphere_average(mesh, quality="draft", seed=3)
    b = sphere_average(mesh, quality="draft", seed=3)
    assert a["projected_area_m2"] == b["projected_area_m2"]
    with pytest.raises(ParameterError, match="quality"):
        sphere_average(mesh, quality="ultra")
    with pytest.raises(ParameterError, match="replicates"):
        sphere_average(mesh, replicates=1)


def test_zero_area_faces_are_dropped_and_counted():
    box = trimesh.creation.box(extents=[0.2, 0.1, 0.05])
    mid = (box.vertices[0] + box.vertices[1]) / 2
    vertices = np.vstack([box.vertices, mid])
    degenerate = [[0, 0, 1], [0, 1, len(vertices) - 1], [2, 3, 3]]  # repeated vertex, collinear, repeated
    mesh = trimesh.Trimesh(vertices=vertices, faces=np.vstack([box.faces, degenerate]), process=False)
    ref = projected_metrics(box, 25.0, 35.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the cleaned mesh is watertight: no warning
        m = projected_metrics(mesh, 25.0, 35.0)
    assert m["n_degenerate_faces"] == 3
    assert m["watertight"]
    for key in ("projected_area_m2", "d_x_proj_m", "d_y_proj_m"):
        assert m[key] == pytest.approx(ref[key], rel=1e-13)


def test_all_faces_degenerate_is_an_error():
    mesh = trimesh.Trimesh(vertices=[[0, 0, 0], [1, 0, 0], [2, 0, 0]], faces=[[0, 1, 2]], process=False)
    with pytest.raises(ParameterError, match="zero area"):
        projected_metrics(mesh, 0.0, 0.0)


@pytest.mark.parametrize("az, el", ANGLES[:5] + [(0.0, 90.0), (0.0, -90.0), (90.0, 0.0)])
def test_open_box_warns_and_stays_exact(az, el):
    """A box without its top still casts the full box shadow (every line through it crosses two faces)."""
    extents = [0.2, 0.1, 0.05]
    box = trimesh.creation.box(extents=extents)
    top = np.where(box.face_normals[:, 2] > 0.5)[0]
    open_box = trimesh.Trimesh(box.vertices, np.delete(box.faces, top, axis=0), process=False)
    assert not open_box.is_watertight
    with pytest.warns(NonWatertightWarning):
        m = projected_metrics(open_box, az, el)
    assert m["watertight"] is False
    area, dx, dy = (
        box_reference(extents, np.eye(3), direction_vector(az, el)) if abs(el) < 90 else (0.2 * 0.1, 0.1, 0.2)
    )
    assert m["projected_area_m2"] == pytest.approx(area, rel=1e-12)
    assert m["d_x_proj_m"] == pytest.approx(dx, rel=1e-12)
    assert m["d_y_proj_m"] == pytest.approx(dy, rel=1e-12)


def test_zero_thickness_plate_edge_on_has_zero_area_and_zero_d_crit():
    plate = trimesh.Trimesh(
        vertices=[[-0.1, -0.05, 0], [0.1, -0.05, 0], [0.1, 0.05, 0], [-0.1, 0.05, 0]],
        faces=[[0, 1, 2], [0, 2, 3]],
        process=False,
    )
    with pytest.warns(NonWatertightWarning):
        model = SilhouetteModel.from_mesh(plate)
    m = projected_metrics(model, 0.0, 0.0)  # looking along x: the plate is a line
    assert m["projected_area_m2"] == 0.0
    assert m["d_y_proj_m"] == 0.0 and m["d_x_proj_m"] == pytest.approx(0.1)
    assert m["d_crit_min_m"] == 0.0 and m["d_crit_geometric_mean_m"] == 0.0
    assert m["sphere_equivalent_radius_m"] == 0.0
    tilted = projected_metrics(model, 0.0, 30.0)
    assert tilted["projected_area_m2"] == pytest.approx(0.02 * np.sin(np.radians(30)), rel=1e-12)
    assert all(np.isfinite(v) for k, v in m.items() if k.endswith(("_m", "_m2")))


def test_thin_closed_plate_edge_on():
    t = 1e-4
    plate = trimesh.creation.box(extents=[0.2, 0.1, t])
    m = projected_metrics(plate, 0.0, 0.0)
    assert m["d_x_proj_m"] == pytest.approx(0.1, rel=1e-12)
    assert m["d_y_proj_m"] == pytest.approx(t, rel=1e-9)
    assert m["projected_area_m2"] == pytest.approx(0.1 * t, rel=1e-9)
    assert m["d_crit_min_m"] == pytest.approx(t, rel=1e-9)
    assert m["d_crit_geometric_mean_m"] == pytest.approx(np.sqrt(0.1 * t), rel=1e-9)


def test_straight_down_and_up_views_use_documented_axes():
    box = trimesh.creation.box(extents=[0.3, 0.2, 0.1])
    down = projected_metrics(box, 0.0, 90.0)  # h = +y, v = -x
    assert (down["d_x_proj_m"], down["d_y_proj_m"]) == pytest.approx((0.2, 0.3), rel=1e-12)
    np.testing.assert_allclose(down["h_axis"], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(down["v_axis"], [-1, 0, 0], atol=1e-15)
    up = projected_metrics(box, 0.0, -90.0)  # h = +y, v = +x
    np.testing.assert_allclose(up["v_axis"], [1, 0, 0], atol=1e-15)
    assert (up["d_x_proj_m"], up["d_y_proj_m"]) == pytest.approx((0.2, 0.3), rel=1e-12)
    turned = projected_metrics(box, 90.0, 90.0)  # h = -x
    assert (turned["d_x_proj_m"], turned["d_y_proj_m"]) == pytest.approx((0.3, 0.2), rel=1e-12)
    for m in (down, up, turned):
        assert m["projected_area_m2"] == pytest.approx(0.06, rel=1e-12)


def test_non_convex_l_prism():
    """A watertight non-convex solid uses the front-facing triangle union; compare with two convex boxes."""
    l_shape = shapely.Polygon([(0, 0), (0.2, 0), (0.2, 0.05), (0.05, 0.05), (0.05, 0.15), (0, 0.15)])
    prism = trimesh.creation.extrude_polygon(l_shape, 0.03)
    assert prism.is_watertight and not prism.is_convex
    boxes = [
        trimesh.creation.box(
            extents=[0.2, 0.05, 0.03], transform=trimesh.transformations.translation_matrix([0.1, 0.025, 0.015])
        ),
        trimesh.creation.box(
            extents=[0.05, 0.15, 0.03], transform=trimesh.transformations.translation_matrix([0.025, 0.075, 0.015])
        ),
    ]
    top = projected_metrics(prism, 0.0, 90.0)
    assert top["projected_area_m2"] == pytest.approx(l_shape.area, rel=1e-12)
    dirs = fibonacci_sphere(25)
    a = metrics_for_directions(SilhouetteModel.from_mesh(prism), dirs)
    b = metrics_for_directions(SilhouetteModel.from_mesh(boxes), dirs)
    model = SilhouetteModel.from_mesh(prism)
    assert model.n_convex_shells == 0 and len(model.triangles) == len(prism.faces)
    for key in ("projected_area_m2", "d_x_proj_m", "d_y_proj_m"):
        np.testing.assert_allclose(a[key], b[key], rtol=1e-11, atol=1e-15)


def test_inside_out_mesh_gives_the_same_silhouette():
    prism = trimesh.creation.extrude_polygon(
        shapely.Polygon([(0, 0), (1, 0), (1, 0.2), (0.2, 0.2), (0.2, 1), (0, 1)]), 0.1
    )
    flipped = prism.copy()
    flipped.invert()
    dirs = fibonacci_sphere(10)
    a = metrics_for_directions(SilhouetteModel.from_mesh(prism), dirs)["projected_area_m2"]
    b = metrics_for_directions(SilhouetteModel.from_mesh(flipped), dirs)["projected_area_m2"]
    np.testing.assert_allclose(a, b, rtol=1e-12)


@settings(max_examples=25, deadline=None)
@given(scale=st.floats(0.01, 100.0), az=st.floats(-180, 180), el=st.floats(-89.0, 89.0))
def test_scaling_and_antipodal_symmetry(scale, az, el):
    mesh = trimesh.creation.box(extents=[0.3, 0.2, 0.1])
    big = mesh.copy()
    big.apply_scale(scale)
    m = projected_metrics(mesh, az, el)
    s = projected_metrics(big, az, el)
    assert s["projected_area_m2"] == pytest.approx(scale**2 * m["projected_area_m2"], rel=1e-10)
    assert s["d_crit_min_m"] == pytest.approx(scale * m["d_crit_min_m"], rel=1e-10)
    back = projected_metrics(mesh, az + 180.0 if az < 0 else az - 180.0, -el)
    assert back["projected_area_m2"] == pytest.approx(m["projected_area_m2"], rel=1e-10)
    assert back["d_y_proj_m"] == pytest.approx(m["d_y_proj_m"], rel=1e-10)


def test_bad_inputs():
    box = trimesh.creation.box(extents=[0.1, 0.1, 0.1])
    with pytest.raises(ParameterError, match="elevation_deg"):
        projected_metrics(box, 0.0, 91.0)
    with pytest.raises(ParameterError, match="azimuth_deg"):
        projected_metrics(box, float("nan"), 0.0)
    with pytest.raises(ParameterError, match="mesh"):
        projected_metrics("box.ply", 0.0, 0.0)
    with pytest.raises(ParameterError, match="directions"):
        metrics_for_directions(SilhouetteModel.from_mesh(box), np.zeros((3, 2)))


@pytest.mark.slow
def test_many_views_of_a_large_mesh_stay_within_a_bounded_memory():
    """Projections of every vertex at every view at once took 6 GB for a 2.97 M-face mesh at 256 views.

    An icosphere of 164 k vertices at 128 views would need 2 x 164 k x 128 x 8 B = 336 MB for the
    extents alone; batched, NumPy's peak stays a fraction of that (GEOS memory is not counted here).
    """
    import tracemalloc

    import trimesh

    from csuas.drone_models.silhouette import SilhouetteModel, metrics_for_directions

    sphere = trimesh.creation.icosphere(subdivisions=7, radius=0.1)
    model = SilhouetteModel.from_mesh(sphere)
    rng = np.random.default_rng(3)
    directions = rng.normal(size=(128, 3))
    tracemalloc.start()
    out = metrics_for_directions(model, directions)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert peak < 150e6
    np.testing.assert_allclose(out["projected_area_m2"], np.pi * 0.1**2, rtol=2e-3)  # faceted sphere's disc
