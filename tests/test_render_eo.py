"""EO rendering against exact geometry, the Johnson range (Eq. 18), Eq. 4 and Koschmieder (docs/validation.md).

Oracles: the exact silhouette of drone_models (polygon union of projected
triangles) and, in this file, the pinhole projection of the mesh; Eq. 4 for a
Lambertian plate under the same illuminance as its background; Koschmieder's
L(R) = L0 tau + L_h (1 - tau) with beta = 3.912 / V written inline.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely import affinity

from csuas.base.errors import ParameterError
from csuas.core.eo import contrast_limited_range_m
from csuas.core.johnson import ifov_rad, johnson_range_m
from csuas.drone_models import build_drone
from csuas.drone_models.silhouette import projected_metrics
from csuas.render.imaging import Quality, render_eo
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
from csuas.render.imaging.targets import plate

pytestmark = pytest.mark.slow

Q = Quality("test", 4, 8)  # 128 samples per pixel
IFOV = math.radians(10.0) / 1920


@pytest.fixture(scope="module")
def drone():
    return build_drone("dji_mini_4_pro")


def exact_pixel_coverage(silhouette, range_m, ifov, window, target_px):
    """Exact fractional coverage of each window pixel by the silhouette (orthographic, metres -> px)."""
    scale = 1.0 / (range_m * ifov)
    poly = affinity.affine_transform(silhouette, [scale, 0.0, 0.0, -scale, target_px[0], target_px[1]])
    jj, ii = np.mgrid[0 : window.height, 0 : window.width]
    boxes = shapely.box(
        window.x0 + ii.ravel(), window.y0 + jj.ravel(), window.x0 + ii.ravel() + 1, window.y0 + jj.ravel() + 1
    )
    return shapely.area(shapely.intersection(boxes, poly)).reshape(window.height, window.width)


@pytest.mark.parametrize(
    "range_m,azimuth_deg,elevation_deg",
    [(300.0, 0.0, 0.0), (300.0, 45.0, 30.0), (900.0, 90.0, 10.0), (300.0, 0.0, 90.0), (1500.0, 120.0, -20.0)],
)
def test_pixels_on_target_match_exact_silhouette(drone, range_m, azimuth_deg, elevation_deg):
    res = render_eo(
        drone,
        View(range_m=range_m, azimuth_deg=azimuth_deg, elevation_deg=elevation_deg),
        settings=RenderSettings(quality=Q),
    )
    exact = projected_metrics(drone.mesh(), azimuth_deg, elevation_deg)
    px_area = (range_m * IFOV) ** 2
    pot, se = res.values["pixels_on_target"], res.stderr["pixels_on_target"]
    assert se > 0
    assert abs(pot - exact["projected_area_m2"] / px_area) <= 4 * se + 2e-3 * pot
    # Extents along the image axes: d_x_proj, d_y_proj and d_crit (Eq. 1) in pixels.
    for key, ref in (
        ("pixels_across_x", exact["d_x_proj_m"]),
        ("pixels_across_y", exact["d_y_proj_m"]),
        ("pixels_across_dcrit", exact["d_crit_min_m"]),
    ):
        ref_px = ref / (range_m * IFOV)
        assert res.values[key] <= ref_px * 1.002 + 1e-3
        assert res.values[key] == pytest.approx(ref_px, rel=0.02, abs=0.03)
    # Count of pixels above 50 %: equal up to pixels whose exact coverage is within the noise of 0.5.
    cov = exact_pixel_coverage(exact["silhouette"], range_m, IFOV, res.window, (960.5, 540.5))
    assert cov.sum() == pytest.approx(exact["projected_area_m2"] / px_area, rel=1e-9)
    ambiguous = np.count_nonzero(np.abs(cov - 0.5) < 0.15)
    assert abs(res.values["pixels_above_half"] - np.count_nonzero(cov > 0.5)) <= ambiguous
    assert np.abs(res.coverage - cov).max() < 0.2


def test_perspective_at_10_m_matches_pinhole_projection(drone):
    """At 10 m the pinhole image differs from the orthographic silhouette; compare with the exact perspective union."""
    r, sensor = 10.0, EoSensor(hfov_deg=40.0, n_h=640, n_v=480)
    ifov = math.radians(40.0) / 640
    res = render_eo(
        drone,
        View(range_m=r, azimuth_deg=30.0, elevation_deg=20.0),
        sensor,
        settings=RenderSettings(quality=Quality("t", 2, 8)),
    )
    m = projected_metrics(drone.mesh(), 30.0, 20.0)
    d, h, v = m["direction"], m["h_axis"], m["v_axis"]
    tris = drone.mesh().triangles  # (n, 3, 3) body frame
    z = r - tris @ d
    px = (tris @ h) / z / ifov
    py = (tris @ v) / z / ifov
    polys = shapely.polygons(np.stack([px, py], axis=-1))
    union = shapely.union_all(polys[shapely.area(polys) > 0])
    tolerance = 4 * res.stderr["pixels_on_target"] + 2e-3 * union.area
    assert res.values["pixels_on_target"] == pytest.approx(union.area, abs=tolerance)
    xmin, ymin, xmax, ymax = union.bounds
    assert res.values["pixels_across_x"] == pytest.approx(xmax - xmin, rel=0.01)
    assert res.values["pixels_across_y"] == pytest.approx(ymax - ymin, rel=0.01)


@pytest.mark.parametrize("lp_task,n_ttpf", [(1.0, 1.0), (4.0, 1.0), (1.0, 0.5)])
def test_rendered_dcrit_spans_2_lp_nttpf_pixels_at_johnson_range(drone, lp_task, n_ttpf):
    d_crit = projected_metrics(drone.mesh(), 0.0, 0.0)["d_crit_min_m"]
    ifov = float(ifov_rad(10.0, 1920))
    r_johnson = float(johnson_range_m(d_crit, ifov, lp_task, n_ttpf))  # Eq. 18
    res = render_eo(
        drone,
        View(range_m=r_johnson),
        sensor=EoSensor(lp_task=lp_task, n_ttpf=n_ttpf),
        settings=RenderSettings(quality=Q),
    )
    assert res.values["pixels_across_dcrit"] == pytest.approx(2 * lp_task * n_ttpf, rel=0.02)
    assert res.values["johnson_range_rendered_m"] == pytest.approx(r_johnson, rel=0.02)


def test_sky_above_ground_below():
    """A horizontal Lambertian plate under the uniform sky hemisphere shows rho L_sky on top, rho L_ground below."""
    import trimesh

    from csuas.drone_models import Part
    from csuas.render.imaging.targets import grey_material

    flat = [Part("flat", "body", trimesh.creation.box((1.0, 1.0, 0.01)), grey_material(0.5))]
    light = Daylight(diffuse_fraction=1.0, ground_reflectance=0.3, illuminance_lx=70000.0)
    settings = RenderSettings(quality=Quality("t", 2, 8))
    top = render_eo(flat, View(100.0, elevation_deg=90.0), light=light, settings=settings)
    bottom = render_eo(flat, View(100.0, elevation_deg=-90.0), light=light, settings=settings)
    l_sky, l_ground = 70000.0 / math.pi, 0.3 * 70000.0 / math.pi
    assert top.values["sky_radiance"] == pytest.approx(l_sky)
    assert top.values["target_radiance"] == pytest.approx(
        0.5 * l_sky, abs=4 * top.stderr["target_radiance"] + 2e-3 * l_sky
    )
    assert bottom.values["target_radiance"] == pytest.approx(
        0.5 * l_ground, abs=4 * bottom.stderr["target_radiance"] + 1e-3 * l_ground
    )


def test_night_without_light_has_zero_contrast_and_a_note():
    res = render_eo(
        plate(),
        View(range_m=100.0),
        light=Daylight(illuminance_lx=0.0),
        settings=RenderSettings(quality=Quality("t", 1, 2)),
    )
    assert res.values["contrast"] == 0.0 and res.values["target_radiance"] == 0.0
    assert any("Weber contrast undefined" in n for n in res.notes)


def test_plate_contrast_is_eq4_under_equal_illuminance():
    """Sun only at 45 deg onto a vertical plate: its irradiance equals the horizontal illuminance E_v."""
    rho, rho_bg, e_v = 0.5, 0.2, 70000.0
    sun_only = dict(illuminance_lx=e_v, diffuse_fraction=0.0, sun_azimuth_deg=0.0, sun_elevation_deg=45.0,
                    ground_reflectance=0.0, background=rho_bg)  # fmt: skip
    settings = RenderSettings(quality=Quality("t", 2, 2))
    res = render_eo(plate(reflectance=rho), View(range_m=200.0), light=Daylight(**sun_only), settings=settings)
    assert res.values["target_radiance"] == pytest.approx(rho * e_v / math.pi, rel=1e-5)
    assert res.values["background_radiance"] == pytest.approx(rho_bg * e_v / math.pi, rel=1e-12)
    assert res.values["contrast"] == pytest.approx((rho - rho_bg) / (rho + rho_bg), rel=1e-5)
    assert res.terms == []  # no atmosphere requested, none applied: it changes nothing (docs/scenarios.md (effects))
    hazy = Daylight(**sun_only, visibility_km=1.0)
    hazy_but_off = render_eo(plate(reflectance=rho), View(range_m=200.0), light=hazy, settings=settings)
    assert hazy_but_off.terms == [] and hazy_but_off.values["contrast"] == res.values["contrast"]
    assert res.values["contrast"] == res.values["contrast_inherent"]
    assert res.values["target_radiance_apparent"] == res.values["target_radiance"]


@pytest.fixture(scope="module")
def hazy_plate():
    """A dark plate against the horizon sky in 5 km visibility, rendered at 1 and 3 km."""
    kw = dict(light=Daylight(visibility_km=5.0), atmosphere=True, settings=RenderSettings(quality=Q))
    return [render_eo(plate(reflectance=0.05), View(range_m=r), **kw) for r in (1000.0, 3000.0)]


def test_koschmieder_transmittance_and_airlight(hazy_plate):
    beta = math.log(50.0) / 5.0  # Koschmieder, 2 % threshold: V = 3.912 / beta [1/km]; Kruse factor 1 at 550 nm
    for res in hazy_plate:
        tau = math.exp(-beta * res.range_m / 1000.0)
        l_t, l_h = res.values["target_radiance"], res.values["sky_radiance"]
        assert res.values["background_radiance"] == l_h
        assert res.values["contrast_weber"] == pytest.approx(res.values["contrast_weber_inherent"] * tau, rel=1e-9)
        apparent = l_t * tau + l_h * (1 - tau)
        assert res.values["contrast"] == pytest.approx((apparent - l_h) / (apparent + l_h), rel=1e-9)
        names = [t["name"] for t in res.terms]
        assert names == ["kruse_extinction", "extinction_per_km", "transmittance", "airlight"]
        assert res.terms[2]["value"] == pytest.approx(tau, rel=1e-12)


def test_rendered_contrast_limited_range_matches_core(hazy_plate):
    c_min = 0.05
    near, far = hazy_plate
    c1, c2 = abs(near.values["contrast_weber"]), abs(far.values["contrast_weber"])
    beta_fit = math.log(c1 / c2) / ((far.range_m - near.range_m) / 1000.0)
    r_star = near.range_m + 1000.0 * math.log(c1 / c_min) / beta_fit
    c0 = abs(near.values["contrast_weber_inherent"])
    assert 0.5 < c0 < 1.0
    expected = float(contrast_limited_range_m(c0, c_min, math.log(50.0) / 5.0, "physical"))
    assert r_star == pytest.approx(expected, rel=0.01)
    # Below c_min at the far range only if beyond r_star.
    assert (c2 < c_min) == (far.range_m > r_star)


def test_same_image_at_10_m_and_20_km_after_range_normalisation(drone):
    """The drone scaled by 2000 at 20 km subtends the same angles as the drone at 10 m: same figures."""
    import dataclasses

    big = [dataclasses.replace(p, mesh=p.mesh.copy().apply_scale(2000.0)) for p in drone.parts]
    sensor, settings = EoSensor(hfov_deg=40.0, n_h=640, n_v=480), RenderSettings(quality=Quality("t", 2, 4))
    near = render_eo(drone, View(range_m=10.0), sensor, settings=settings)
    far = render_eo(big, View(range_m=20000.0), sensor, settings=settings)
    for key in ("pixels_on_target", "pixels_above_half", "pixels_across_dcrit", "contrast"):
        assert far.values[key] == pytest.approx(near.values[key], rel=1e-5, abs=1e-9)
    assert np.allclose(far.image, near.image, rtol=1e-4)


def test_plate_at_10_m_and_20_km_float32_precision():
    """The same 1 m plate at 10 m (100 px) and at 20 km (0.05 px): area x R^2 and contrast agree."""
    kw = dict(
        sensor=EoSensor(hfov_deg=57.29577951308232, n_h=1000, n_v=1000),  # IFOV = 1 mrad
        light=Daylight(
            diffuse_fraction=0.0, ground_reflectance=0.0, sun_azimuth_deg=0.0, sun_elevation_deg=45.0, background=0.2
        ),
        settings=RenderSettings(quality=Quality("t", 4, 8)),
    )
    near = render_eo(plate(), View(range_m=10.0), **kw)
    far = render_eo(plate(), View(range_m=20000.0), **kw)
    assert near.values["pixels_on_target"] == pytest.approx(1e4, rel=2e-3)
    tolerance = 4 * far.stderr["pixels_on_target"] + 1e-3 * 0.0025
    assert far.values["pixels_on_target"] == pytest.approx(1.0 / 20.0**2, abs=tolerance)
    assert far.values["pixels_across_x"] == pytest.approx(0.05, rel=0.03)
    assert far.values["contrast"] == pytest.approx(near.values["contrast"], rel=1e-5)
    assert far.values["contrast"] == pytest.approx(0.3 / 0.7, rel=1e-5)


@pytest.mark.parametrize("offset", [(0.0, 0.0), (0.5, 0.5), (0.3, -0.4)])
def test_single_pixel_and_subpixel_targets_are_stable(offset):
    r = 1000.0
    one_px = plate(width_m=r * IFOV, height_m=r * IFOV)
    sub_px = plate(width_m=0.1 * r * IFOV, height_m=0.1 * r * IFOV)
    res1 = render_eo(one_px, View(range_m=r, target_offset_px=offset), settings=RenderSettings(quality=Q))
    res2 = render_eo(sub_px, View(range_m=r, target_offset_px=offset), settings=RenderSettings(quality=Q))
    assert res1.values["pixels_on_target"] == pytest.approx(1.0, abs=4 * res1.stderr["pixels_on_target"] + 2e-3)
    assert res2.values["pixels_on_target"] == pytest.approx(0.01, abs=4 * res2.stderr["pixels_on_target"] + 2e-5)
    assert res2.stderr["pixels_on_target"] < 0.001
    assert res1.values["pixels_above_half"] == (1.0 if offset == (0.0, 0.0) else 0.0)
    # A sub-pixel target still shows in its pixel: peak-pixel contrast is the coverage-diluted contrast.
    c_in = res2.values["contrast_weber_inherent"]
    assert abs(res2.values["contrast_peak_pixel"]) < abs(res2.values["contrast"]) <= 1.0
    assert np.isfinite(c_in)


def test_edge_on_plate_and_zero_width_quad():
    import trimesh

    from csuas.drone_models import Part
    from csuas.render.imaging.targets import grey_material

    r = 100.0
    res = render_eo(plate(thickness_m=0.01), View(range_m=r, azimuth_deg=90.0), settings=RenderSettings(quality=Q))
    exact = 0.01 * 1.0 / ((r - 0.5) * IFOV) ** 2  # pinhole: the near end face (0.5 m closer) bounds the silhouette
    assert res.values["pixels_on_target"] == pytest.approx(exact, abs=4 * res.stderr["pixels_on_target"] + 1e-3 * exact)
    assert res.values["pixels_across_dcrit"] == pytest.approx(0.01 / ((r - 0.5) * IFOV), rel=0.01)
    quad = trimesh.Trimesh(
        vertices=[[0, -0.5, -0.5], [0, 0.5, -0.5], [0, 0.5, 0.5], [0, -0.5, 0.5]],
        faces=[[0, 1, 2], [0, 2, 3]],
        process=False,
    )
    res0 = render_eo(
        [Part("quad", "body", quad, grey_material())],
        View(range_m=r, azimuth_deg=90.0),
        settings=RenderSettings(quality=Quality("t", 2, 2)),
    )
    assert res0.values["pixels_on_target"] == 0.0
    assert res0.values["pixels_across_dcrit"] == 0.0
    assert res0.values["contrast"] == 0.0
    assert all(np.isfinite(v) for v in res0.values.values())
    assert res0.notes and "no sample hit" in res0.notes[0]


def test_bad_input_names_parameter():
    with pytest.raises(ParameterError, match="range_m"):
        render_eo("dji_mini_4_pro", View(range_m=0.1), settings=RenderSettings(quality="draft"))
    with pytest.raises(ParameterError, match="range_m"):
        render_eo("dji_mini_4_pro", View(range_m=float("nan")), settings=RenderSettings(quality="draft"))
    with pytest.raises(ParameterError, match="quality"):
        render_eo("dji_mini_4_pro", View(range_m=100.0), settings=RenderSettings(quality="ultra"))
    with pytest.raises(ParameterError, match="elevation_deg"):
        render_eo("dji_mini_4_pro", View(range_m=100.0, elevation_deg=95.0), settings=RenderSettings(quality="draft"))
    with pytest.raises(ParameterError, match="sun_elevation_deg"):
        render_eo(
            "dji_mini_4_pro",
            View(range_m=100.0),
            light=Daylight(sun_elevation_deg=-5.0),
            settings=RenderSettings(quality="draft"),
        )
    with pytest.raises(ParameterError, match="background"):
        render_eo(
            "dji_mini_4_pro",
            View(range_m=100.0),
            light=Daylight(background="ground"),
            settings=RenderSettings(quality="draft"),
        )
    with pytest.raises(ParameterError, match="visibility_km"):
        render_eo("dji_mini_4_pro", View(range_m=100.0), atmosphere=True, settings=RenderSettings(quality="draft"))
    with pytest.raises(ParameterError, match="hfov_deg"):
        render_eo(
            "dji_mini_4_pro",
            View(range_m=100.0),
            sensor=EoSensor(hfov_deg=0.0),
            settings=RenderSettings(quality="draft"),
        )


def test_ranges_from_1_m_to_50_km(drone):
    """At 1 m the drone overfills a small sensor (clipped window, noted); at 50 km it is 0.0005 px."""
    near = render_eo(
        drone,
        View(range_m=1.0),
        sensor=EoSensor(hfov_deg=10.0, n_h=192, n_v=108),
        settings=RenderSettings(quality=Quality("t", 1, 2)),
    )
    assert near.window.clipped and near.window.n_pixels == 192 * 108
    assert any("beyond the sensor frame" in n for n in near.notes)
    assert 0 < near.values["pixels_on_target"] <= 192 * 108
    far = render_eo(drone, View(range_m=50000.0), settings=RenderSettings(quality=Q))
    exact = projected_metrics(drone.mesh(), 0.0, 0.0)["projected_area_m2"] / (50000.0 * IFOV) ** 2
    assert exact < 1e-3
    assert far.values["pixels_on_target"] == pytest.approx(exact, abs=4 * far.stderr["pixels_on_target"] + 1e-3 * exact)
    assert far.values["pixels_across_dcrit"] == pytest.approx(0.101 / (50000.0 * IFOV), rel=0.02)


def test_same_seed_same_result_other_seed_other_noise():
    view, q = View(400.0, azimuth_deg=20.0, elevation_deg=10.0), Quality("t", 2, 4)
    a = render_eo("dji_mini_4_pro", view, settings=RenderSettings(quality=q, seed=7))
    b = render_eo("dji_mini_4_pro", view, settings=RenderSettings(quality=q, seed=7))
    c = render_eo("dji_mini_4_pro", view, settings=RenderSettings(quality=q, seed=8))
    assert a.values == b.values
    np.testing.assert_array_equal(a.image, b.image)
    assert a.values["pixels_on_target"] != c.values["pixels_on_target"]


def test_new_ranges_aspects_and_seeds_reuse_the_compiled_path_tracer(drone):
    """Only the padded wavefront size makes Dr.Jit compile the path tracer again (issue 12, section 6).

    Range, seed and aspect reach the kernels as data, not as compiled constants: over views that
    differ in all three, the path tracer's kernels (over 1000 operations) have exactly one hash per
    launch size (:func:`csuas.render.imaging.trace.padded_wavefront`, powers of two).
    """
    import drjit as dr

    views = [(500.0, 30.0, 10.0, 1), (520.0, 35.0, 12.0, 2), (700.0, 200.0, -5.0, 3), (480.0, 95.0, 25.0, 4)]
    views += [(505.0, 31.0, 10.5, 5), (690.0, 210.0, -4.0, 6)]
    dr.set_flag(dr.JitFlag.KernelHistory, True)
    try:
        dr.kernel_history()
        for range_m, azimuth_deg, elevation_deg, seed in views:
            render_eo(
                drone,
                View(range_m=range_m, azimuth_deg=azimuth_deg, elevation_deg=elevation_deg),
                settings=RenderSettings(quality="draft", seed=seed),
            )
        tracers = [k for k in dr.kernel_history() if k["type"] == dr.KernelType.JIT and k["operation_count"] > 1000]
    finally:
        dr.set_flag(dr.JitFlag.KernelHistory, False)
    assert len(tracers) == len(views)
    sizes = {k["size"] for k in tracers}
    assert all(size & (size - 1) == 0 for size in sizes)
    assert len({k["hash"] for k in tracers}) == len(sizes) < len(views)
