"""csuas coverage --scheduler (csuas/commands/coverage_tiles.py): tiles answer as the single-process run, cell for
cell; resume per tile; Cloud Optimised GeoTIFFs gdalinfo reads without a warning; bad options named."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from csuas import cli
from csuas.core.terrain import gaussian_hills

#: A 288 x 320 DEM of 50 m cells: 4 tiles of 160 cells a side (COG blocks of 256 cells: one overview).
ROWS, COLS, CELL_M, TILE = 288, 320, 50.0, "160"
WEST, NORTH = 400_000.0, 5_010_000.0
SITE = """dem = "dem.tif"
altitudes_agl_m = [30.0, 120.0]
fusion_k = 2
[sensors.radar]
x = 407975.0
y = 5002025.0
mast_m = 10.0
elevation_max_deg = 60.0
[sensors.tir]
x = 401200.0
y = 5006000.0
mast_m = 10.0
[sensors.eo]
x = 404100.0
y = 5008100.0
mast_m = 5.0
azimuth_deg = 255.0
sector_deg = 120.0
"""


def _site(folder, site_text=SITE, crs="EPSG:32633"):
    """The site and its DEM: hills with a nodata hole (filled with the lowest valid height in both runs)."""
    import rasterio
    from rasterio.transform import from_origin

    dem = gaussian_hills(max(ROWS, COLS), CELL_M)[:ROWS, :COLS].astype(np.float32)
    dem[40:44, 90:95] = -9999.0
    profile = {"driver": "GTiff", "height": ROWS, "width": COLS, "count": 1, "dtype": "float32"}
    profile.update(crs=crs, transform=from_origin(WEST, NORTH, CELL_M, CELL_M), nodata=-9999.0)
    with rasterio.open(folder / "dem.tif", "w", **profile) as dst:
        dst.write(dem, 1)
    (folder / "site.toml").write_text(site_text)
    return folder / "site.toml"


def _layers(folder) -> dict:
    """Every layer's grid, by file name."""
    import rasterio

    summary = json.loads((folder / "coverage.json").read_text())
    grids = {}
    for layer in summary["layers"]:
        with rasterio.open(folder / layer["path"]) as src:
            grids[layer["path"]] = src.read(1)
    return grids


def _same(tiled, single) -> None:
    """The tiled run's layers, areas and Fresnel shares are the single-process run's, cell for cell."""
    a, b = _layers(tiled), _layers(single)
    assert a.keys() == b.keys() and len(a) == 37
    different = [name for name in a if not np.array_equal(a[name], b[name], equal_nan=True)]
    assert different == []
    layers_a = json.loads((tiled / "coverage.json").read_text())["layers"]
    layers_b = json.loads((single / "coverage.json").read_text())["layers"]
    for x, y in zip(layers_a, layers_b):
        assert x == {key: y[key] for key in x}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The single-process run and the serial run by 4 tiles of the same site."""
    folder = tmp_path_factory.mktemp("tiles")
    site = _site(folder)
    assert cli.main(["coverage", str(site), "--out", str(folder / "single")]) == 0
    assert (
        cli.main(["coverage", str(site), "--out", str(folder / "serial"), "--scheduler", "serial", "--tile", TILE]) == 0
    )
    return folder


def test_tiles_in_this_process_match_the_single_process_run_cell_for_cell(runs):
    summary = json.loads((runs / "serial" / "coverage.json").read_text())
    assert summary["tiles"]["tiles"] == 4 and summary["tiles"]["tiles_run"] == 4
    # the radar (on the corner of 4 tiles, cell 159, 159) is traced on a window of its reach across all
    # four tiles; the EO camera's reach (137 cells) on a window narrower than the DEM across two tiles; the
    # south-east tile's far corner lies beyond every sensor's reach (the cells no sensor reaches)
    radar = summary["sensors"]["radar"]
    assert (radar["row"], radar["col"]) == (159.0, 159.0) and CELL_M < radar["reach_m"] < 4 * CELL_M
    assert 100 * CELL_M < summary["sensors"]["eo"]["reach_m"] < 150 * CELL_M
    assert 10 * CELL_M < summary["sensors"]["tir"]["reach_m"] < 50 * CELL_M
    grids = _layers(runs / "serial")
    assert all(np.isnan(grids[f"{name}_visible_30m.tif"][280, 310]) for name in ("radar", "eo", "tir"))
    _same(runs / "serial", runs / "single")


def test_tiles_on_two_local_workers_match_the_single_process_run_cell_for_cell(runs):
    out = runs / "local"
    args = ["coverage", str(runs / "site.toml"), "--out", str(out), "--scheduler", "local", "--workers", "2"]
    assert cli.main([*args, "--tile", TILE]) == 0
    summary = json.loads((out / "coverage.json").read_text())
    assert summary["tiles"]["workers"] == 2 and summary["tiles"]["tiles_run"] == 4
    _same(out, runs / "single")


def test_a_tiled_run_resumes_only_the_missing_tiles_and_refuses_other_inputs(runs, capsys):
    import shutil

    out = runs / "resumed"
    shutil.copytree(runs / "serial", out)
    for suffix in (".json", ".tif"):
        (out / "tiles" / f"tile-000160-000000{suffix}").unlink()
    args = ["coverage", str(runs / "site.toml"), "--out", str(out), "--scheduler", "serial", "--tile", TILE]
    assert cli.main(args) == 0
    tiles = json.loads((out / "coverage.json").read_text())["tiles"]
    assert (tiles["tiles_run"], tiles["tiles_resumed"]) == (1, 3)
    _same(out, runs / "single")
    capsys.readouterr()
    assert cli.main([*args[:-1], "80"]) == 2  # other tiles: another run's folder
    err = capsys.readouterr().err
    assert "--out" in err and "another run's tiles" in err


def test_tiled_layers_are_cloud_optimised_geotiffs_gdalinfo_reads_without_a_warning(runs):
    out = runs / "serial"
    for name, description, unit in (
        ("fused_pd_30m.tif", "fused: pd at 30 m AGL", "Pd"),
        ("radar_visible_120m.tif", "radar: visible at 120 m AGL", "1 = in sight"),
        ("radar_fresnel_clearance_30m.tif", "radar: fresnel_clearance at 30 m AGL", "clearance / r1"),
    ):
        info = subprocess.run(["gdalinfo", out / name], capture_output=True, text=True, check=True)
        assert info.stderr == "", info.stderr
        expected = (
            "LAYOUT=COG",
            "COMPRESSION=DEFLATE",
            "Block=256x256",
            "Overviews: 160x144",
            f"Description = {description}",
            f"Unit Type: {unit}",
            "NoData Value=nan",
            "Size is 320, 288",
        )
        assert all(text in info.stdout for text in expected), info.stdout


def test_bad_tile_options_are_named_all_at_once(runs, capsys):
    site = str(runs / "site.toml")
    assert cli.main(["coverage", site, "--out", str(runs / "b"), "--scheduler", "udp://x", "--tile", "4"]) == 2
    err = capsys.readouterr().err
    assert "--scheduler" in err and "udp://x" in err and "--tile" in err and ">= 16" in err
    assert cli.main(["coverage", site, "--out", str(runs / "b"), "--workers", "2"]) == 2
    err = capsys.readouterr().err
    assert "--workers" in err and "only with --scheduler" in err
    radio = runs / "radio"
    radio.mkdir()
    _site(radio, SITE + '[sensors.rf]\nx = 401200.0\ny = 5006000.0\n[radio_map]\nsensors = ["rf"]\nstep = 8\n')
    assert cli.main(["coverage", str(radio / "site.toml"), "--out", str(runs / "b"), "--scheduler", "serial"]) == 2
    assert "radio_map" in capsys.readouterr().err
    geographic = runs / "lonlat"
    geographic.mkdir()
    _site(geographic, SITE, crs="EPSG:4326")
    assert cli.main(["coverage", str(geographic / "site.toml"), "--out", str(runs / "b"), "--scheduler", "serial"]) == 2
    err = capsys.readouterr().err
    assert "dem" in err and "north-up GeoTIFF in a projected CRS" in err
    assert not (runs / "b").exists()


def test_a_sensors_reach_window_holds_every_cell_within_its_reach_and_places_it_exactly():
    from csuas.core.coverage import SitedSensor, farthest_ground_m, in_window, reach_window

    sited = SitedSensor("a", 50.5, 10.25, 1.0)
    assert farthest_ground_m((101, 81), sited, 10.0) == pytest.approx(
        np.hypot(50.5, 80 - 10.25) * 10.0, rel=1e-15
    )  # corner (0, 80)
    # 205 m of 10 m cells: 20.5 cells each way, rows 30..71, columns 0 (clipped)..31
    window = reach_window((101, 81), sited, 205.0, 10.0)
    assert (window[0].start, window[0].stop, window[1].start, window[1].stop) == (30, 72, 0, 32)
    rows, cols = np.indices((101, 81))
    within = np.hypot(rows - 50.5, cols - 10.25) * 10.0 <= 205.0
    assert within[window].sum() == within.sum()
    placed = in_window(sited, window)
    assert (placed.row, placed.col, placed.mast_m) == (20.5, 10.25, 1.0)
    assert reach_window((101, 81), sited, float("inf"), 10.0) == (slice(0, 101), slice(0, 81))


def test_the_tiled_estimate_brackets_a_measured_worker_and_does_not_grow_with_the_dem():
    """The 2000^2 coverage_tiles bench (4 sensors, the EO's 1363^2 window over 16 tiles of 500, 25 layers, one
    level) peaked at 480 MiB a worker (the window's bytes a cell were calibrated on it: a factor 2 check only);
    a DEM 100 times larger with the same windows and tiles needs the same memory a worker and more time."""
    from csuas.core.coverage_cost import coverage_tiles_estimate

    windows = [(1363**2, 16, False), (249**2, 1, False), (253**2, 1, False), (41**2, 1, True)]
    small = coverage_tiles_estimate((2000, 2000), windows, (500**2, 2), 1, 25)
    assert 0.5 < small.bytes / (480 * 2**20) < 2.0
    large = coverage_tiles_estimate((20_000, 20_000), windows, (500**2, 2), 1, 25)
    assert large.bytes == small.bytes and large.seconds > 10 * small.seconds
