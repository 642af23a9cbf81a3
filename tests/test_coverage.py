"""csuas coverage (core/coverage.py, csuas/commands/coverage.py): layers, files, closed forms, bad sites."""

from __future__ import annotations

import json
import math
import shutil
import subprocess

import numpy as np
import pytest

from csuas import cli
from csuas.base.errors import ParameterError


def _write_dem(path, dem, crs="EPSG:32633", nodata=None):
    import rasterio
    from rasterio.transform import from_origin

    profile = {
        "driver": "GTiff",
        "height": dem.shape[0],
        "width": dem.shape[1],
        "count": 1,
        "dtype": "float32",
        "transform": from_origin(400_000.0, 5_010_000.0, 50.0, 50.0),
    }
    if crs is not None:
        profile["crs"] = crs
    if nodata is not None:
        profile["nodata"] = nodata
    with rasterio.open(path, "w", **profile) as dst:
        dst.write(dem.astype(np.float32), 1)


@pytest.mark.slow
def test_the_demo_site_writes_every_layer_with_the_dems_crs(tmp_path, capsys):
    import rasterio

    assert cli.main(["coverage", "demo", "--out", str(tmp_path / "c"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    summary = json.loads((tmp_path / "c" / "coverage.json").read_text())
    kinds = {(layer["sensor"], layer["kind"], layer["altitude_m"]) for layer in summary["layers"]}
    assert ("radar", "visible", 30.0) in kinds and ("eo", "min_altitude", None) in kinds
    assert ("fused", "fused", 120.0) in kinds and out["crs"] == "EPSG:32633"
    quantities = {layer.get("quantity") for layer in summary["layers"] if layer["kind"] == "fused"}
    assert quantities == {  # the demo asks for 2 of 3
        "count",
        "detected",
        "pd",
        "k_of_n",
        "pd_k_of_n",
        "visible_count",
        "min_visible_height",
        "min_detectable_height",
    }
    assert {layer["geojson"] for layer in summary["layers"] if "geojson" in layer} >= {
        "eo_detected_30m.geojson",
        "fused_k_of_n_120m.geojson",
    }
    with (
        rasterio.open(tmp_path / "c" / "rf_visible_30m.tif") as visible,
        rasterio.open(tmp_path / "c" / "rf_detected_30m.tif") as detected,
        rasterio.open(tmp_path / "c" / "fused_detected_30m.tif") as fused,
    ):
        assert str(visible.crs) == "EPSG:32633" and visible.transform.a == 25.0
        v, d, f = visible.read(1), detected.read(1), fused.read(1)
    assert np.all(d <= v) and np.all(f >= d)  # detected only where seen; the OR covers each sensor
    assert 0.0 < v.mean() < 1.0  # the hills hide part of the site


def test_flat_terrain_detects_within_the_sensors_range(tmp_path, capsys):
    """Flat DEM: every cell is seen (short distances), and detected exactly where the slant distance from
    the eye (20 m mast) to the drone at 100 m is within the sensor's range (the default radar: 47.1 m)."""
    dem_path = tmp_path / "flat.tif"
    _write_dem(dem_path, np.full((60, 60), 50.0))
    site = tmp_path / "site.toml"
    site.write_text(
        f'dem = "{dem_path.name}"\nscenario = "default"\naltitudes_agl_m = [100.0]\n'
        "[sensors.acoustic]\nx = 401500.0\ny = 5008500.0\nmast_m = 20.0\n"
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "f"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    reach = out["sensors"]["acoustic"]["range_m"]
    import rasterio

    with rasterio.open(tmp_path / "f" / "acoustic_detected_100m.tif") as src:
        detected = src.read(1)
    row, col = out["sensors"]["acoustic"]["row"], out["sensors"]["acoustic"]["col"]
    rr, cc = np.indices(detected.shape)
    slant = np.hypot(np.hypot(rr - row, cc - col) * 50.0, 80.0)
    clear = np.abs(slant - reach) > 50.0  # cells near the range circle may fall either way
    assert np.array_equal(detected[clear] > 0, (slant <= reach)[clear])


def test_bad_sites_are_refused_with_one_line_each(tmp_path, capsys):
    dem_path = tmp_path / "nocrs.tif"
    _write_dem(dem_path, np.zeros((10, 10)), crs=None)
    site = tmp_path / "bad.toml"
    site.write_text(
        f'dem = "{dem_path.name}"\naltitudes_agl_m = [-5.0]\n[sensors.radar]\nx = 1.0\ny = 2.0\n'
        "[sensors.sonar]\nx = 1.0\ny = 2.0\n"
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "b")]) == 2
    err = capsys.readouterr().err
    assert "altitudes_agl_m" in err and "sensors.sonar" in err
    good = tmp_path / "outside.toml"
    good.write_text(f'dem = "{dem_path.name}"\n[sensors.radar]\nx = 1.0\ny = 2.0\n')
    assert cli.main(["coverage", str(good), "--out", str(tmp_path / "b2")]) == 2
    assert "projected CRS" in capsys.readouterr().err


def _flat_layers(altitude_m, **pointing):
    """The default EO camera (detection range 555.5 m) on a 10 m mast at the centre cell of a flat 1.2 km square of
    5 m cells: its layers at one flight level, and each cell's ground distance [m] and bearing [deg]."""
    from csuas.core.coverage import SitedSensor, sensor_layers
    from csuas.core.scenario import load_scenario

    dem = np.zeros((241, 241))
    layers = sensor_layers(
        dem, 5.0, load_scenario("default"), SitedSensor("eo", 120.0, 120.0, 10.0, **pointing), [altitude_m]
    )
    rr, cc = np.indices(dem.shape)
    east, north = (cc - 120.0) * 5.0, (120.0 - rr) * 5.0
    return layers, np.hypot(east, north), np.degrees(np.arctan2(east, north)) % 360.0


def _discretisation_m2(outer_m, inner_m, sector_deg, cell_m):
    """Largest area error of counting whole cells by their centres inside an annular sector [m^2].

    A point of a cell is classed with the cell's centre, within delta = cell / sqrt(2) of it: a misclassed point
    lies within delta of the boundary, whose delta-band (two curves at most) covers at most
    2 delta P + 2 pi delta^2, P = (R + r) theta + 2 (R - r) the perimeter (no radial edges all round).
    """
    theta = math.radians(sector_deg)
    perimeter = (outer_m + inner_m) * theta + (2 * (outer_m - inner_m) if sector_deg < 360 else 0.0)
    delta = cell_m / math.sqrt(2.0)
    return 2 * delta * perimeter + 2 * math.pi * delta**2


def test_a_sector_with_dead_zones_covers_its_closed_form_annular_sector():
    """Flat ground, drone h = 50 m above the eye: detected where the slant distance lies between the minimum
    range (100 m: ground r = sqrt(100^2 - h^2) = 86.6 m) and the detection range (R_g = sqrt(555.5^2 - h^2)),
    within 45 degrees of the boresight 40 degrees (north-east): cell by cell away from the edges, and in
    area pi (R_g^2 - r^2) 90 / 360 within the cells' discretisation."""
    layers, ground, bearing = _flat_layers(60.0, azimuth_deg=40.0, sector_deg=90.0, min_range_m=100.0)
    reach, h = layers["range_m"], 50.0
    outer, inner = math.sqrt(reach**2 - h**2), math.sqrt(100.0**2 - h**2)
    off = np.abs((bearing - 40.0 + 180.0) % 360.0 - 180.0)
    expected = (ground >= inner) & (ground <= outer) & (off <= 45.0)
    detected, pd = layers["detected"][0], layers["pd"][0]
    clear = (np.abs(ground - inner) > 1e-6) & (np.abs(ground - outer) > 1e-6) & (np.abs(off - 45.0) > 1e-6)
    assert np.array_equal(detected[clear], expected[clear])
    area, exact = detected.sum() * 25.0, math.pi * (outer**2 - inner**2) * 90.0 / 360.0
    assert abs(area - exact) <= _discretisation_m2(outer, inner, 90.0, 5.0)  # 234 539 m^2, bound 13 786 m^2
    assert abs(area - exact) < 0.01 * exact  # in fact: the errors of the edges cancel
    # Pd is zero outside the sector and in the dead zone; beyond the detection range it is the detector's tail
    regard = (ground >= inner) & (off <= 45.0)
    assert np.array_equal(pd[clear] > 0, regard[clear]) and pd[regard & (ground > outer)].max() < 0.5
    assert layers["visible"][0][off <= 45.0].all()  # flat ground: in the sector (the only rays traced) all is seen


def test_the_overhead_cone_of_silence_and_the_lower_elevation_limit():
    """Elevation limits on flat ground, drone h = 50 m above the eye: above elevation_max_deg = 60 the cone of
    silence reaches out to h / tan(60 deg) = 28.9 m; below elevation_min_deg = 10 the drone is out of the beam
    beyond h / tan(10 deg) = 283.6 m. The nearest and farthest detected cell centres lie within one cell
    diagonal outside those radii, and the area is the annulus pi (R^2 - r^2)."""
    layers, ground, _ = _flat_layers(60.0, elevation_min_deg=10.0, elevation_max_deg=60.0)
    detected = layers["detected"][0]
    inner, outer = 50.0 / math.tan(math.radians(60.0)), 50.0 / math.tan(math.radians(10.0))
    assert inner <= ground[detected].min() <= inner + math.sqrt(2) * 5.0
    assert outer - math.sqrt(2) * 5.0 <= ground[detected].max() <= outer
    exact = math.pi * (outer**2 - inner**2)
    assert abs(detected.sum() * 25.0 - exact) <= _discretisation_m2(outer, inner, 360.0, 5.0)
    # the default limits (-90, +90) keep the cell under the sensor, a sector covers the drone overhead
    layers, ground, _ = _flat_layers(60.0, azimuth_deg=200.0, sector_deg=10.0)
    assert layers["detected"][0][120, 120] and layers["detected"][0][ground > 0].sum() > 0


def test_the_boresight_is_a_bearing_clockwise_from_grid_north():
    for azimuth, toward in ((0.0, (60, 120)), (90.0, (120, 180)), (180.0, (180, 120)), (270.0, (120, 60))):
        layers, _, bearing = _flat_layers(60.0, azimuth_deg=azimuth, sector_deg=30.0)
        detected = layers["detected"][0]
        assert detected[toward] and detected.sum() > 100
        others = [(60, 120), (120, 180), (180, 120), (120, 60)]
        assert not any(detected[o] for o in others if o != toward)


def test_k_of_n_fusion_against_enumeration_and_the_binomial():
    """fused_layers' k-of-n Pd against the sum over all 2^n subsets of at least k detecting sensors, and the
    binomial tail sum_j>=k C(n, j) p^j (1 - p)^(n - j) when every Pd is p; k_of_n is count >= k."""
    import itertools

    from csuas.core.coverage import fused_layers

    rng = np.random.default_rng(11)
    n, shape = 4, (2, 5, 7)
    pd = rng.uniform(0, 1, (n, *shape))
    pd[:, 0, 0, :2] = [[0.0, 1.0], [1.0, 1.0], [0.0, 0.0], [0.5, 1.0]]  # certain and impossible sensors
    detected = rng.uniform(0, 1, (n, *shape)) < 0.5
    per_sensor = {f"s{i}": {"detected": detected[i], "pd": pd[i]} for i in range(n)}
    for k in range(1, n + 1):
        fused = fused_layers(per_sensor, k)
        brute = np.zeros(shape)
        for chosen in itertools.product((False, True), repeat=n):
            if sum(chosen) >= k:
                brute += np.prod([p if c else 1.0 - p for p, c in zip(pd, chosen)], axis=0)
        np.testing.assert_allclose(fused["pd_k_of_n"], brute, rtol=0, atol=1e-14)
        assert np.array_equal(fused["k_of_n"], detected.sum(axis=0) >= k)
    np.testing.assert_allclose(fused_layers(per_sensor, 1)["pd_k_of_n"], fused_layers(per_sensor)["pd"], atol=1e-15)
    assert "k_of_n" not in fused_layers(per_sensor)
    p = np.linspace(0.0, 1.0, 11)
    equal = {f"s{i}": {"detected": p > 0.5, "pd": p} for i in range(5)}
    for k in range(1, 6):
        binomial = sum(math.comb(5, j) * p**j * (1 - p) ** (5 - j) for j in range(k, 6))
        np.testing.assert_allclose(fused_layers(equal, k)["pd_k_of_n"], binomial, rtol=0, atol=1e-15)


def test_the_mapped_reach_ends_where_nothing_more_is_detected_or_likely():
    """Beyond the reach no sensor of the default scenario detects or has Pd >= 0.001 (on a fine grid out to the
    site's edge); two lookup steps inside it, one of the two still holds (it overshoots by one step at most)."""
    from csuas.core.coverage import PD_NEGLIGIBLE, REACH_GRID_POINTS, mapped_reach_m
    from csuas.core.pd_curves import sensor_pd
    from csuas.core.scenario import load_scenario

    scenario = load_scenario("default")
    step = 1000.0 ** (1.0 / (REACH_GRID_POINTS - 1))  # the lookup grid's ratio (three decades)
    for name in scenario.sensors:
        reach = mapped_reach_m(scenario, name, 20_000.0)
        detection = float(sensor_pd(scenario, name, [1.0]).deterministic_range_m)
        if np.isinf(reach):  # detected or likely out to the edge
            assert detection >= 20_000.0 or sensor_pd(scenario, name, [20_000.0]).pd[0] >= PD_NEGLIGIBLE, name
            continue
        beyond = np.linspace(reach, 20_000.0, 4000)
        assert reach >= detection and (sensor_pd(scenario, name, beyond).pd < PD_NEGLIGIBLE).all(), name
        inside = reach / step**2
        assert inside <= detection or sensor_pd(scenario, name, [inside]).pd[0] >= PD_NEGLIGIBLE, name


def test_geojson_polygons_cover_exactly_the_detected_cells_and_the_reach_bounds_the_trace(tmp_path, capsys):
    """Behind a ridge (shadows, holes): each detected layer's GeoJSON polygons, in the DEM's CRS, have the
    layer's area exactly (the same cells); the visible layer is nodata (NaN) beyond the sensor's mapped reach;
    the 2-of-2 layer is the cells both sensors detect."""
    import pyogrio.raw
    import rasterio
    import shapely
    import shapely.geometry
    from rasterio.warp import transform_geom

    dem = np.full((60, 60), 50.0)
    dem[20:40, 25] = 75.0  # a wall east of the sensors
    dem_path = tmp_path / "ridge.tif"
    _write_dem(dem_path, dem)
    site = tmp_path / "site.toml"
    site.write_text(
        f'dem = "{dem_path.name}"\naltitudes_agl_m = [10.0]\nfusion_k = 2\n'
        "[sensors.acoustic]\nx = 401000.0\ny = 5008500.0\nmast_m = 5.0\n"
        "[sensors.eo]\nx = 401000.0\ny = 5008400.0\nmast_m = 5.0\nazimuth_deg = 90.0\nsector_deg = 120.0\n"
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "g"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    summary = json.loads((tmp_path / "g" / "coverage.json").read_text())
    polygons = [layer for layer in summary["layers"] if "geojson" in layer]
    assert {(layer["sensor"], layer.get("quantity", layer["kind"])) for layer in polygons} == {
        ("acoustic", "detected"),
        ("eo", "detected"),
        ("fused", "detected"),
        ("fused", "k_of_n"),
    }
    for layer in polygons:
        # the GeoPackage holds the polygons in the DEM's CRS: exactly the layer's cells
        stem = layer["geojson"].removesuffix(".geojson")
        geometries = pyogrio.raw.read(tmp_path / "g" / summary["vectors"]["geopackage"], layer=stem)[2]
        native = [shapely.from_wkb(g) for g in geometries]
        area = sum(p.area for p in native)
        assert area / 1e6 == pytest.approx(layer["area_km2"], rel=1e-12) and area > 0
        with rasterio.open(tmp_path / "g" / layer["path"]) as src:
            bounds = shapely.geometry.box(*src.bounds)
        assert all(bounds.covers(p) for p in native)
        # the GeoJSON: RFC 7946, longitude and latitude on WGS 84, no crs member; back in UTM, the same area
        collection = json.loads((tmp_path / "g" / layer["geojson"]).read_text())
        assert "crs" not in collection
        back = [transform_geom("EPSG:4326", "EPSG:32633", f["geometry"]) for f in collection["features"]]
        assert sum(shapely.geometry.shape(g).area for g in back) == pytest.approx(area, rel=1e-9)
        lon, lat = np.array([c for f in collection["features"] for c in f["geometry"]["coordinates"][0]]).T
        assert np.all((13.0 < lon) & (lon < 15.0)) and np.all((45.0 < lat) & (lat < 46.0))
    with rasterio.open(tmp_path / "g" / "acoustic_visible_10m.tif") as src:
        visible = src.read(1)
    with rasterio.open(tmp_path / "g" / "acoustic_detected_10m.tif") as src:
        detected = src.read(1)
    sensor = out["sensors"]["acoustic"]
    rr, cc = np.indices(visible.shape)
    ground = np.hypot(rr - sensor["row"], cc - sensor["col"]) * 50.0
    assert sensor["reach_m"] is not None and sensor["reach_m"] >= sensor["range_m"]
    assert np.array_equal(np.isnan(visible), ground > sensor["reach_m"]) and (ground > sensor["reach_m"]).any()
    assert (visible[ground <= sensor["reach_m"]] == 0).any()  # the wall's shadow
    assert not detected[ground > sensor["range_m"]].any()
    with (
        rasterio.open(tmp_path / "g" / "eo_detected_10m.tif") as eo,
        rasterio.open(tmp_path / "g" / "fused_k_of_n_10m.tif") as both,
    ):
        assert np.array_equal(both.read(1) > 0, (eo.read(1) > 0) & (detected > 0))


def test_bad_pointing_and_fusion_keys_are_named_all_at_once(tmp_path, capsys):
    dem_path = tmp_path / "flat.tif"
    _write_dem(dem_path, np.zeros((10, 10)))
    site = tmp_path / "bad.toml"
    site.write_text(
        f'dem = "{dem_path.name}"\nfusion_k = 3\n'
        "[sensors.radar]\nx = 400100.0\ny = 5009900.0\nazimuth_deg = 400.0\nsector_deg = 0.0\nmin_range_m = -1.0\n"
        "[sensors.eo]\nx = 400100.0\ny = 5009900.0\nelevation_min_deg = 50.0\nelevation_max_deg = 40.0\n"
        'azimuth_deg = "north"\n'
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "b")]) == 2
    err = capsys.readouterr().err
    for name in (
        "fusion_k = 3",
        "sensors.radar.azimuth_deg = 400.0",
        "sensors.radar.sector_deg = 0.0",
        "sensors.radar.min_range_m = -1.0",
        "sensors.eo.elevation_max_deg = 40.0",
        "sensors.eo.azimuth_deg = 'north'",
    ):
        assert name in err, name
    assert not (tmp_path / "b" / "coverage.json").exists()
    # the core's own record refuses the same values, all at once
    from csuas.base.errors import InputErrors
    from csuas.core.coverage import SitedSensor

    with pytest.raises(InputErrors, match="sensors.radar.sector_deg") as caught:
        SitedSensor("radar", 1.0, 1.0, 10.0, azimuth_deg=-1.0, sector_deg=400.0)
    assert "sensors.radar.azimuth_deg" in str(caught.value)
    with pytest.raises(ParameterError, match="elevation_max_deg"):
        SitedSensor("radar", 1.0, 1.0, 10.0, elevation_min_deg=10.0, elevation_max_deg=10.0)


def test_a_south_up_dem_is_read_north_up(tmp_path, capsys):
    """A DEM stored with its rows running north (positive y step) is flipped: the boresight still points north."""
    import rasterio
    from rasterio.transform import Affine

    dem_path = tmp_path / "south_up.tif"
    profile = {"driver": "GTiff", "height": 40, "width": 40, "count": 1, "dtype": "float32", "crs": "EPSG:32633"}
    with rasterio.open(dem_path, "w", transform=Affine(25.0, 0, 400_000.0, 0, 25.0, 5_000_000.0), **profile) as dst:
        dst.write(np.zeros((1, 40, 40), np.float32))
    site = tmp_path / "site.toml"
    site.write_text(
        f'dem = "{dem_path.name}"\naltitudes_agl_m = [30.0]\n'
        "[sensors.eo]\nx = 400500.0\ny = 5000500.0\nmast_m = 5.0\nazimuth_deg = 0.0\nsector_deg = 20.0\n"
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "s"), "--json"]) == 0
    capsys.readouterr()
    with rasterio.open(tmp_path / "s" / "eo_detected_30m.tif") as src:
        detected, transform = src.read(1) > 0, src.transform
    assert transform.e < 0  # written north-up
    rows, cols = np.nonzero(detected)
    ys = np.array([(transform * (c + 0.5, r + 0.5))[1] for r, c in zip(rows, cols)])
    assert rows.size > 10 and (ys >= 5_000_500.0 - 12.5).all() and ys.max() > 5_000_800.0


def test_multipath_detection_reads_a_path_gain_as_its_free_space_range():
    """A path gain equal to free space at distance r detects iff r <= R_det, with the Pd of r itself."""
    from csuas.core.coverage import free_space_equivalent_range_m, link_frequency_ghz, multipath_detection
    from csuas.core.pd_curves import sensor_pd
    from csuas.core.ranges import evaluate
    from csuas.core.rf import free_space_path_loss_db
    from csuas.core.scenario import load_scenario
    from csuas.core.units import C_LIGHT

    scenario = load_scenario("default")
    assert link_frequency_ghz(scenario, "rf") == 2.4  # the drone's link (Table 33)
    assert link_frequency_ghz(scenario, "radar") == pytest.approx(C_LIGHT / 0.0125 / 1e9)  # Table 39's wavelength
    with pytest.raises(ParameterError, match="sensors.eo"):
        link_frequency_ghz(scenario, "eo")
    detection = float(evaluate(scenario)["rf"].range_m)
    distance = detection * np.array([[0.1, 0.5, 0.999, 1.001, 2.0, 10.0]])
    gain = -free_space_path_loss_db(2.4, distance)
    assert np.allclose(free_space_equivalent_range_m(gain, 2.4), distance, rtol=1e-12)
    detected, pd = multipath_detection(scenario, "rf", gain, np.ones(gain.shape, bool))
    assert detected.tolist() == [[True, True, True, False, False, False]]
    assert np.allclose(pd, sensor_pd(scenario, "rf", distance).pd, rtol=1e-9)
    blocked = np.array([[-np.inf, gain[0, 0]]])
    detected, pd = multipath_detection(scenario, "rf", blocked, np.array([[True, False]]))
    assert not detected.any() and not pd.any()  # no path; outside the field of regard


@pytest.mark.slow
def test_a_radio_map_site_adds_multipath_layers_beside_the_line_of_sight(tmp_path, capsys):
    """The demo terrain with a radio map of its RF sensor: path gain, bound, detection and Pd layers; where
    the map is reliable, the power sum of Sionna's rays detects at least what the direct path alone does."""
    site = tmp_path / "radio.toml"
    site.write_text(
        "altitudes_agl_m = [60.0]\n[sensors.rf]\nx = 502500.0\ny = 5007000.0\nmast_m = 10.0\n"
        '[radio_map]\nsensors = ["rf"]\nstep = 16\nsamples = 262144\n'
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "r"), "--json"]) == 0
    capsys.readouterr()
    summary = json.loads((tmp_path / "r" / "coverage.json").read_text())
    kinds = {layer["kind"] for layer in summary["layers"] if layer["sensor"] == "rf"}
    assert {"path_gain", "path_gain_error", "detected_multipath", "pd_multipath"} <= kinds
    (stats,) = summary["radio_maps"]["maps"]["rf"]
    assert stats["samples"] == 262144 and stats["frequency_ghz"] == 2.4
    assert stats["detected_only_in_line_of_sight_cells"] == 0
    assert stats["agreement_with_line_of_sight"] > 0.9
    assert 0.0 < stats["reliable_visible_fraction"] <= 1.0


def test_bad_radio_map_settings_are_named_all_at_once(tmp_path, capsys):
    site = tmp_path / "bad_radio.toml"
    site.write_text(
        "altitudes_agl_m = [0.0, 30.0]\n[sensors.radar]\nx = 505000.0\ny = 5005000.0\n"
        "[sensors.eo]\nx = 505000.0\ny = 5005100.0\n"
        '[radio_map]\nsensors = ["radar", "eo"]\nstep = 0\nsamples = 5\ncolour = 1\n'
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "b")]) == 2
    err = capsys.readouterr().err
    for name in ("radio_map.sensors", "radio_map.step", "radio_map.samples", "radio_map.colour", "altitudes_agl_m"):
        assert name in err, name
    site.write_text('[sensors.radar]\nx = 505000.0\ny = 5005000.0\n[radio_map]\nground = "medium_dry_ground"\n')
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "b")]) == 2
    assert "radio_map.ground (for radar)" in capsys.readouterr().err  # 24 GHz: the ITU ground spans 1-10 GHz


@pytest.mark.slow
def test_a_radar_over_a_ground_of_given_constants_is_mapped_at_24_ghz(tmp_path, capsys):
    """Beyond the ITU grounds' 1-10 GHz a ground is given by its constants; bad constants are refused."""
    site = tmp_path / "radar.toml"
    head = "altitudes_agl_m = [30.0]\n[sensors.radar]\nx = 505000.0\ny = 5005000.0\nmast_m = 10.0\n"
    site.write_text(head + "[radio_map]\nstep = 16\nsamples = 65536\nground = {relative_permittivity = 0.5}\n")
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "bad")]) == 2
    assert "radio_map.ground" in capsys.readouterr().err
    site.write_text(
        head + "[radio_map]\nstep = 16\nsamples = 65536\n"
        "ground = {relative_permittivity = 0.5, conductivity_s_m = 1.0}\n"
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "bad")]) == 2
    assert "relative_permittivity >= 1" in capsys.readouterr().err
    site.write_text(
        head + "[radio_map]\nstep = 1\nsamples = 65536\n"
        "ground = {relative_permittivity = 15.0, conductivity_s_m = 10.0}\n"
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "r"), "--json"]) == 0
    capsys.readouterr()
    (stats,) = json.loads((tmp_path / "r" / "coverage.json").read_text())["radio_maps"]["maps"]["radar"]
    assert stats["frequency_ghz"] == pytest.approx(23.98, abs=0.01)
    assert stats["samples"] == 65536
    # only what the site calls for: the map covers twice the radar's mapped reach (85 m), not the 10 km DEM
    assert stats["mapped_cells"] < 20 * 20


@pytest.mark.slow
def test_a_radio_map_traces_only_the_sensors_sector(tmp_path, capsys):
    """A 90-degree sector facing east: the map's cells lie inside it (NaN, not mapped, outside), as the
    line of sight's do."""
    rasterio = pytest.importorskip("rasterio")
    site = tmp_path / "sector.toml"
    site.write_text(
        "altitudes_agl_m = [60.0]\n[sensors.rf]\nx = 502500.0\ny = 5007000.0\nmast_m = 10.0\n"
        'azimuth_deg = 90.0\nsector_deg = 90.0\n[radio_map]\nsensors = ["rf"]\nstep = 16\nsamples = 65536\n'
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "s"), "--json"]) == 0
    capsys.readouterr()
    summary = json.loads((tmp_path / "s" / "coverage.json").read_text())
    (layer,) = [entry for entry in summary["layers"] if entry["sensor"] == "rf" and entry["kind"] == "path_gain"]
    with rasterio.open(tmp_path / "s" / layer["path"]) as raster:
        gain = raster.read(1)
        rows, cols = np.indices(gain.shape)
        x, y = rasterio.transform.xy(raster.transform, rows.ravel(), cols.ravel())
    east, north = np.asarray(x) - 502500.0, np.asarray(y) - 5007000.0
    off = ((np.degrees(np.arctan2(east, north)) - 90.0 + 180.0) % 360.0 - 180.0).reshape(gain.shape)
    mapped = np.isfinite(gain)
    assert mapped.any() and np.all(np.abs(off[mapped]) <= 45.0 + 1e-6)
    assert mapped[np.abs(off) < 40.0].mean() > 0.5
    (stats,) = summary["radio_maps"]["maps"]["rf"]
    assert stats["mapped_cells"] >= mapped.sum()  # every mapped cell in the sector; some got no ray


@pytest.mark.skipif(shutil.which("gdalinfo") is None, reason="GDAL's programs are not installed")
def test_gis_files_open_in_gdal_and_ogr_without_a_warning(tmp_path, capsys):
    """GeoTIFFs tiled, DEFLATE-compressed, with a band description, unit and NaN nodata; the GeoJSON, the
    GeoPackage (one table per vector layer) and the KML read by OGR with nothing on its error stream."""
    dem_path = tmp_path / "flat.tif"
    _write_dem(dem_path, np.full((60, 60), 50.0))
    site = tmp_path / "site.toml"
    site.write_text(
        f'dem = "{dem_path.name}"\naltitudes_agl_m = [10.0]\nfusion_k = 1\n'
        "[sensors.acoustic]\nx = 401000.0\ny = 5008500.0\nmast_m = 5.0\n"
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "g"), "--json"]) == 0
    capsys.readouterr()
    out = tmp_path / "g"
    info = subprocess.run(["gdalinfo", out / "acoustic_pd_10m.tif"], capture_output=True, text=True, check=True)
    assert info.stderr == ""
    expected = ("COMPRESSION=DEFLATE", "Block=256x256", "Description = acoustic: pd at 10 m AGL", "NoData Value=nan")
    assert all(text in info.stdout for text in expected), info.stdout
    assert "Unit Type: Pd" in info.stdout
    layers = {"acoustic_detected_10m", "fused_detected_10m", "fused_k_of_n_10m"}
    for name in ("coverage.gpkg", "coverage.kml", "acoustic_detected_10m.geojson"):
        listing = subprocess.run(["ogrinfo", "-ro", "-so", "-al", out / name], capture_output=True, text=True)
        assert listing.returncode == 0 and listing.stderr == "", (name, listing.stderr)
    tables = subprocess.run(["ogrinfo", "-ro", "-q", out / "coverage.gpkg"], capture_output=True, text=True).stdout
    assert {line.split(":")[1].split("(")[0].strip() for line in tables.splitlines() if ":" in line} == layers


def test_fresnel_clearance_layer_is_the_knife_edges_ratio_and_its_obstructed_share(tmp_path, capsys):
    """A 9 m wall across flat ground midway between the RF sensor (10 m mast) and a drone 4 km away at 10 m
    (50 m cells, k = 4/3): at the crest the sight line stands 10 - L^2/(4 kR) + (L/2)^2/(2 kR) - 9 m above
    the terrain, its clearance ratio that over r1 = sqrt(lambda L / 4) at the link's carrier; the layer's
    obstructed_fraction is the share of the visible cells below 0.6, as read back from the two GeoTIFFs."""
    import rasterio

    from csuas.core.coverage import link_frequency_ghz
    from csuas.core.scenario import load_scenario

    dem = np.zeros((21, 81))
    dem[:, 40] = 9.0
    dem_path = tmp_path / "wall.tif"
    _write_dem(dem_path, dem)
    site = tmp_path / "site.toml"
    site.write_text(
        f'dem = "{dem_path.name}"\naltitudes_agl_m = [10.0]\n[sensors.rf]\nx = 400025.0\ny = 5009475.0\nmast_m = 10.0\n'
    )
    assert cli.main(["coverage", str(site), "--out", str(tmp_path / "w"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    (layer,) = [item for item in out["layers"] if item["kind"] == "fresnel_clearance"]
    assert layer["path"] == "rf_fresnel_clearance_10m.tif" and (tmp_path / "w" / layer["png"]).is_file()
    wavelength = 299_792_458.0 / (link_frequency_ghz(load_scenario("default"), "rf") * 1e9)
    k_r = 4.0 / 3.0 * 6_371_000.0
    gap = 10.0 - 4000.0**2 / (4 * k_r) + 2000.0**2 / (2 * k_r) - 9.0
    with (
        rasterio.open(tmp_path / "w" / layer["path"]) as fresnel,
        rasterio.open(tmp_path / "w" / "rf_visible_10m.tif") as visible,
    ):
        ratio, seen = fresnel.read(1), visible.read(1)
        assert fresnel.nodata is None or np.isnan(fresnel.nodata)
    assert ratio[10, 80] == pytest.approx(gap / math.sqrt(wavelength * 1000.0), rel=1e-6)
    assert np.isnan(ratio[10, 0])  # the sensor's own cell: no terrain between
    judged = (seen > 0) & np.isfinite(ratio)
    assert layer["obstructed_fraction"] == pytest.approx((ratio[judged] < 0.6).mean(), abs=1e-12)
    assert 0.0 < layer["obstructed_fraction"] < 1.0


def test_the_lowest_detected_level_is_the_lowest_flight_level_reaching_the_pd():
    """Levels given out of order (120, 30, 60 m): each cell's lowest level with Pd >= 0.5, NaN where none."""
    from csuas.core.coverage import lowest_detected_level_m

    pd = np.array([[[0.9, 0.9, 0.1, 0.5]], [[0.2, 0.7, 0.1, 0.49]], [[0.6, 0.5, 0.3, 0.0]]])
    lowest = lowest_detected_level_m(pd, [120.0, 30.0, 60.0])
    np.testing.assert_array_equal(lowest, [[60.0, 30.0, np.nan, 120.0]])


def test_fused_visibility_behind_a_wall_is_the_nearer_sensors_sight_line():
    """Flat ground, a 20 m wall across the grid at column 50 (10 m cells), the EO camera (5 m mast) at column
    10 and the RF sensor (5 m mast) at column 30 of row 20: in front of the wall both see the ground (0);
    behind it the lowest height either sees is the sight line over the crest, with the Earth's curvature
    (each sensor's k), h(d) = (20 - c_w - 5) d / d_w + 5 + c(d), c(d) = d^2 / (2 k R) (d_w the wall's
    distance), and the EO camera's, the farther from the wall, is the lower. Both see every cell at 30 m
    in front of the wall; the fused Pd's lowest detected level is 30 m where either detects at 30 m."""
    from csuas.core.coverage import (
        K_FACTOR,
        SitedSensor,
        fresnel_layers,
        fused_layers,
        fused_visibility,
        sensor_layers,
    )
    from csuas.core.scenario import load_scenario

    dem = np.zeros((41, 121))
    dem[:, 50] = 20.0
    scenario = load_scenario("default")
    sited = {"eo": SitedSensor("eo", 20.0, 10.0, 5.0), "rf": SitedSensor("rf", 20.0, 30.0, 5.0)}
    per_sensor = {name: sensor_layers(dem, 10.0, scenario, placed, [30.0, 300.0]) for name, placed in sited.items()}
    fused = fused_visibility(dem, 10.0, scenario, sited, per_sensor)

    def sight_line(col, k):
        drop = lambda d: d**2 / (2 * k * 6_371_000.0)
        d, d_w = (np.arange(121) - col) * 10.0, (50 - col) * 10.0
        return (20.0 - drop(d_w) - 5.0) * d / d_w + 5.0 + drop(d)

    behind = np.arange(121) > 50
    expected = np.minimum(sight_line(10, K_FACTOR["eo"]), sight_line(30, K_FACTOR["rf"]))
    np.testing.assert_allclose(fused["min_visible_height_m"][20, behind], expected[behind], rtol=1e-9)
    assert np.all(fused["min_visible_height_m"][20, 11:50] == 0.0)
    assert np.all(fused["visible_count"][0][:, 11:50] == 2)
    either = fused_layers(per_sensor)["pd"][0] >= 0.5
    assert np.all(fused["min_detectable_height_m"][either] == 30.0)
    # the RF link's Fresnel clearance on the sensor's row: below 0 exactly where the wall hides the drone
    clearance = fresnel_layers(dem, 10.0, scenario, sited["rf"], per_sensor["rf"])["clearance"][0][20]
    hidden = ~per_sensor["rf"]["visible"][0][20]
    assert hidden[51:].any() and np.array_equal(clearance[32:] < 0, hidden[32:])


def test_a_dem_in_longitude_and_latitude_is_reprojected_to_its_utm_zone(tmp_path, capsys):
    """A synthetic SRTM-style DEM (EPSG:4326, 3 arc-second cells around 15.05 E, 45.05 N) is read in UTM zone
    33N (zone floor((15.05 + 180) / 6) + 1 = 33), on square cells; a sensor given by lat/lon lands on the cell
    its x/y (PROJ's transform to EPSG:32633) gives; a sensor with x and lat is refused, naming both."""
    import rasterio
    from pyproj import Transformer
    from rasterio.transform import from_origin

    n, step = 41, 1.0 / 1200.0
    lon, lat = np.meshgrid(15.05 + (np.arange(n) - 20) * step, 45.05 - (np.arange(n) - 20) * step)
    profile = {"driver": "GTiff", "height": n, "width": n, "count": 1, "dtype": "float32", "crs": "EPSG:4326"}
    profile["transform"] = from_origin(15.05 - 20.5 * step, 45.05 + 20.5 * step, step, step)
    with rasterio.open(tmp_path / "srtm.tif", "w", **profile) as dst:
        dst.write((100.0 + 2000.0 * (lon - 15.0) + 1000.0 * (lat - 45.0)).astype(np.float32), 1)
    x, y = Transformer.from_crs("EPSG:4326", "EPSG:32633", always_xy=True).transform(15.052, 45.049)
    placed = {}
    for pair, where in (("geographic", "lat = 45.049\nlon = 15.052\n"), ("projected", f"x = {x}\ny = {y}\n")):
        site = tmp_path / f"{pair}.toml"
        site.write_text(f'dem = "srtm.tif"\naltitudes_agl_m = [30.0]\n[sensors.eo]\n{where}mast_m = 5.0\n')
        assert cli.main(["coverage", str(site), "--out", str(tmp_path / pair), "--json"]) == 0
        out = json.loads(capsys.readouterr().out)
        placed[pair] = (out["sensors"]["eo"]["row"], out["sensors"]["eo"]["col"])
        assert out["crs"] == "EPSG:32633"
    assert placed["geographic"] == pytest.approx(placed["projected"], abs=1e-6)
    with rasterio.open(tmp_path / "geographic" / "eo_visible_30m.tif") as layer:
        assert layer.crs.to_epsg() == 32633 and abs(layer.transform.a) == pytest.approx(abs(layer.transform.e))
    bad = tmp_path / "bad.toml"
    bad.write_text('dem = "srtm.tif"\n[sensors.eo]\nx = 500000.0\nlat = 45.0\n')
    assert cli.main(["coverage", str(bad), "--out", str(tmp_path / "bad")]) == 2
    err = capsys.readouterr().err
    assert "sensors.eo" in err and "x and y, or lat and lon (given: x, lat)" in err


def _ridge_layers(convention):
    """An acoustic array (broadband detector, 1.5 m mast) west of an 8 m ridge 100 m away; drones 10 m up."""
    from csuas.core.coverage import SitedSensor, sensor_layers
    from csuas.core.scenario import parse_scenario

    scenario = parse_scenario(
        {"convention": convention, "sensors": {"a": {"modality": "acoustic", "detector": "broadband"}}}
    )
    dem = np.zeros((21, 121))
    dem[:, 20] = 8.0  # 10 m cells: the ridge 100 m east of the sensor at column 10
    return scenario, sensor_layers(dem, 10.0, scenario, SitedSensor("a", 10.0, 10.0, 1.5), [10.0])


def test_physical_acoustic_coverage_hears_over_a_ridge_by_iso9613():
    """Cell 200 m east, behind the ridge: not visible; Pd at the margin less A_bar = 10 lg(3 + 20 f z K_met / 340)."""
    from csuas.core.modality import BY_NAME
    from csuas.core.pd_curves import acoustic_pd_with_loss, margin_db

    scenario, layers = _ridge_layers("physical")
    k = BY_NAME["acoustic"].line_of_sight.k
    drop = lambda d: d**2 / (2 * k * 6_371_000.0)  # curvature drop d^2 / (2 k R_E)
    near = math.hypot(100.0, 8.0 - drop(100.0) - 1.5)
    far = math.hypot(100.0, 10.0 - drop(200.0) - (8.0 - drop(100.0)))
    z = near + far - math.hypot(200.0, 10.0 - drop(200.0) - 1.5)
    slant = math.hypot(200.0, 8.5)
    k_met = math.exp(-math.sqrt(near * far * slant / (2 * z)) / 2000.0)
    f = scenario.sensors["a"].params["frequency_hz"]
    a_bar = min(10 * math.log10(3 + 20 * f / 340.0 * z * k_met), 20.0)
    assert not layers["visible"][0, 10, 30]
    expected = float(acoustic_pd_with_loss(scenario, "a", [slant], [a_bar])[0])
    assert layers["pd"][0, 10, 30] == pytest.approx(expected, abs=1e-12)
    margin = float(margin_db(scenario, scenario.sensors["a"], "physical", [slant])[0])
    assert bool(layers["detected"][0, 10, 30]) == (margin >= a_bar)
    assert 0.05 < expected < float(layers["pd"][0, 10, 15])  # heard behind the ridge, less than in front of it
    _, paper = _ridge_layers("paper")
    assert paper["pd"][0, 10, 30] == 0.0 and not paper["detected"][0, 10, 30]
