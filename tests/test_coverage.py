"""csuas coverage (core/coverage.py, csuas/commands/coverage.py): layers, files, closed forms, bad sites."""

from __future__ import annotations

import json

import numpy as np
import pytest

from csuas import cli


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
    assert quantities == {"count", "detected", "pd"}
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
