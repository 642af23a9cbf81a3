"""Declared schemas of the four input files (issue 22 section 3): every bad file is exit 2 with the key's path.

Table-driven: each case is a file of one kind (scenario, site, dataset spec, sweep spec) that the command line
reads, and the one error line it must give: the full key path and the value as written, with exit code 2 and no
traceback. The cases were measured against the hand-written validators they replace: ``internal`` cases ended in an
internal error (exit 1) or a traceback, ``unclear`` ones in a message without the key's path or with a wrong key,
``silent`` ones were accepted (a TOML ``true`` taken as the number 1). ``bom`` cases carry a UTF-8 byte-order mark
before a mistake, which must be found past the mark.
"""

from __future__ import annotations

import numpy as np
import pytest

from csuas.cli import main

BOM = "\ufeff"
SCENARIO = '[sensors.eo]\nmodality = "eo"\n'
SITE = 'scenario = "default"\naltitudes_agl_m = [30.0]\n[sensors.eo]\nx = 505000.0\ny = 5005000.0\n'
SWEEP = 'job = "range"\nscenario = "default"\n[axes]\n"target.d_crit_m" = [0.1, 0.2]\n'
RENDER_SWEEP = 'job = "render"\nscenario = "default"\n[axes]\nrange_m = [100.0]\n'
DEM_SITE = f'dem = "dem.tif"\n{SITE}'
#: The DEM (heights [m], 50 m cells, UTM 33N) a case's site names as dem.tif.
DEMS = {"site_dem_one_cell": np.zeros((1, 1)), "site_dem_nan_heights": np.full((4, 4), np.nan)}
DATASET = 'scenario = "default"\nsensor = "eo"\ncount = 1\n'

#: (id, kind, what the old validators did, file text, fragments of one error line)
CASES = [
    # --- internal errors (exit 1 or a traceback) with the old validators
    ("dataset_range_without_max", "dataset", "internal", DATASET + "range_m = {min = 100.0}\n", ["range_m.max"]),
    ("dataset_sensor_list", "dataset", "internal", 'scenario = "default"\nsensor = ["eo"]\n', ["sensor = ['eo']"]),
    (
        "dataset_azimuth_without_min",
        "dataset",
        "internal",
        DATASET + "azimuth_deg = {max = 10.0}\n",
        ["azimuth_deg.min"],
    ),
    ("dataset_scenario_table", "dataset", "internal", "scenario = {a = 1}\n", ["scenario = {'a': 1}"]),
    (
        "sweep_samples_inf",
        "sweep",
        "internal",
        SWEEP + '"target.x_m" = {min = 0.0, max = 1.0, samples = inf}\n',
        ["axes.target.x_m.samples = inf"],
    ),
    (
        "sweep_samples_nan",
        "sweep",
        "internal",
        SWEEP + '"target.x_m" = {min = 0.0, max = 1.0, samples = nan}\n',
        ["axes.target.x_m.samples = nan"],
    ),
    (
        "sweep_render_mode_xray",
        "sweep",
        "internal",
        RENDER_SWEEP + '[options]\nmode = "xray"\n',
        ["options.mode = 'xray'", "eo"],
    ),
    ("sweep_scenario_number", "sweep", "internal", 'job = "range"\nscenario = 5\n', ["scenario = 5"]),
    (
        "sweep_render_quality_ultra",
        "sweep",
        "internal",
        RENDER_SWEEP + '[options]\nquality = "ultra"\n',
        ["options.quality = 'ultra'", "draft"],
    ),
    (
        "sweep_axis_nested_list",
        "sweep",
        "internal",
        'job = "render"\n[axes]\nrange_m = [[100.0]]\n',
        ["axes.range_m.0 = [100.0]"],
    ),
    (
        "sweep_options_convention",
        "sweep",
        "internal",
        SWEEP + '[options]\nconvention = "metric"\n',
        ["options.convention = 'metric'", "paper"],
    ),
    (
        "sweep_samples_huge",
        "sweep",
        "internal",
        SWEEP + '"target.x_m" = {min = 0.0, max = 1.0, samples = 1e12}\n',
        ["axes.target.x_m.samples = 1000000000000.0"],
    ),
    ("site_sensors_number", "site", "internal", 'scenario = "default"\nsensors = 5\n', ["sensors = 5"]),
    ("site_sensor_not_a_table", "site", "internal", 'scenario = "default"\n[sensors]\neo = 5\n', ["sensors.eo = 5"]),
    ("site_dem_number", "site", "internal", "dem = 5\n" + SITE, ["dem = 5"]),
    ("site_scenario_number", "site", "internal", "scenario = 5\n[sensors.eo]\nx = 1.0\ny = 2.0\n", ["scenario = 5"]),
    ("site_altitudes_text", "site", "internal", SITE.replace("[30.0]", '"high"'), ["altitudes_agl_m = 'high'"]),
    ("site_dem_one_cell", "site", "internal", DEM_SITE, ["dem = 'dem.tif'", "2 x 2"]),
    (
        "site_radio_map_ground_nan",
        "site",
        "internal",
        SITE + "[radio_map]\nground = {relative_permittivity = nan, conductivity_s_m = 0.01}\n",
        ["radio_map.ground.relative_permittivity = nan"],
    ),
    (
        "scenario_mrtd_lengths",
        "scenario",
        "internal",
        '[sensors.t]\nmodality = "tir"\nmrtd_frequency_cy_mrad = [1.0, 2.0]\nmrtd_k = [0.1]\n',
        ["sensors.t.mrtd_k"],
    ),
    # --- unclear messages with the old validators
    ("scenario_bom", "scenario", "unclear", BOM + SCENARIO + "hfov_deg = 500.0\n", ["sensors.eo.hfov_deg = 500.0"]),
    ("sweep_bom", "sweep", "unclear", BOM + 'job = "range"\nseed = -1\n', ["seed = -1"]),
    ("dataset_bom", "dataset", "unclear", BOM + "count = 0\n", ["count = 0"]),
    ("site_bom", "site", "unclear", BOM + "fusion_k = 0\n" + SITE, ["fusion_k = 0"]),
    ("site_dem_not_a_geotiff", "site", "unclear", f'dem = "bad.tif"\n{SITE}', ["dem = 'bad.tif'", "GeoTIFF"]),
    (
        "scenario_rf_rain_path",
        "scenario",
        "unclear",
        '[environment]\nrain = "moderate"\n[sensors.rf1]\nmodality = "rf"\nfrequency_ghz = 0.5\n',
        ["sensors.rf1.frequency_ghz = 0.5"],
    ),
    ("site_dem_nan_heights", "site", "unclear", DEM_SITE, ["dem = 'dem.tif'", "finite heights"]),
    ("site_sensor_unknown_key", "site", "unclear", SITE + "mast = 5.0\n", ["sensors.eo.mast = 5.0", "mast_m"]),
    ("site_unknown_key", "site", "unclear", SITE.replace("scenario", "scenari"), ["scenari = 'default'", "scenario"]),
    (
        "sweep_unknown_option",
        "sweep",
        "unclear",
        SWEEP + "[options]\nfusoin = 'or'\n",
        ["options.fusoin = 'or'", "convention"],
    ),
    ("dataset_unknown_stage", "dataset", "unclear", DATASET + 'chain = ["psf", "blur"]\n', ["chain.1 = 'blur'", "psf"]),
    (
        "dataset_unknown_drone",
        "dataset",
        "unclear",
        DATASET + 'drones = ["dji", "black_hornet_3"]\n',
        ["drones.0 = 'dji'", "dji_mini_4_pro"],
    ),
    (
        "sweep_axis_value_out_of_range",
        "sweep",
        "unclear",
        'job = "render"\n[axes]\nrange_m = [100.0, -5.0]\n',
        ["axes.range_m.1 = -5.0"],
    ),
    (
        "sweep_draw_min_above_max",
        "sweep",
        "unclear",
        SWEEP + '"target.x_m" = {min = 2.0, max = 1.0, samples = 3}\n',
        ["axes.target.x_m.max = 1.0", "min"],
    ),
    ("site_fusion_k_above_n", "site", "unclear", "fusion_k = 3\n" + SITE, ["fusion_k = 3", "1 to 1"]),
    (
        "site_radio_map_unknown_key",
        "site",
        "unclear",
        SITE + "[radio_map]\nsteps = 4\n",
        ["radio_map.steps = 4", "step"],
    ),
    ("dataset_range_limits", "dataset", "unclear", DATASET + "range_m = [50.0, 1e9]\n", ["range_m.1 = 1000000000.0"]),
    (
        "scenario_sensor_preset_unknown",
        "scenario",
        "unclear",
        SCENARIO + 'preset = "nope"\n',
        ["sensors.eo.preset = 'nope'", "default"],
    ),
    (
        "sweep_axis_draw_unknown_key",
        "sweep",
        "unclear",
        SWEEP + '"target.x_m" = {min = 0.0, max = 1.0, samples = 3, step = 1}\n',
        ["axes.target.x_m.step = 1"],
    ),
    # --- silently accepted with the old validators
    ("site_mast_true", "site", "silent", SITE + "mast_m = true\n", ["sensors.eo.mast_m = True", "number"]),
    ("site_x_true", "site", "silent", SITE.replace("x = 505000.0", "x = true"), ["sensors.eo.x = True"]),
    ("site_altitude_true", "site", "silent", SITE.replace("[30.0]", "[true]"), ["altitudes_agl_m.0 = True"]),
    ("dataset_background_true", "dataset", "silent", DATASET + "background = true\n", ["background = True"]),
    (
        "dataset_cloud_cover_true",
        "dataset",
        "silent",
        DATASET + 'background = "clear_sky"\ncloud_cover = true\n',
        ["cloud_cover = True"],
    ),
    (
        "sweep_option_azimuth_true",
        "sweep",
        "silent",
        RENDER_SWEEP + "[options]\nazimuth_deg = true\n",
        ["options.azimuth_deg = True"],
    ),
    ("dataset_bits_float", "dataset", "silent", DATASET + "bits = 8.0\n", ["bits = 8.0"]),
]


def _write_dem(path, heights):
    import rasterio
    from rasterio.transform import from_origin

    rows, cols = heights.shape
    transform = from_origin(504_000.0, 5_006_000.0, 50.0, 50.0)
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        height=rows,
        width=cols,
        count=1,
        dtype="float32",
        crs="EPSG:32633",
        transform=transform,
    ) as dst:
        dst.write(heights.astype(np.float32), 1)


def _write_file(tmp_path, case_id: str, kind: str, text: str):
    path = tmp_path / f"{kind}.toml"
    path.write_bytes(text.encode("utf-8"))
    (tmp_path / "bad.tif").write_text("not a GeoTIFF\n")
    if case_id in DEMS:
        _write_dem(tmp_path / "dem.tif", DEMS[case_id])
    return path


def _argv(kind: str, path, out) -> list[str]:
    command = {"scenario": "range", "site": "coverage", "dataset": "dataset", "sweep": "sweep"}[kind]
    extra = ["--scheduler", "serial"] if kind == "sweep" else []
    return [command, str(path)] if kind == "scenario" else [command, str(path), "--out", str(out), *extra]


@pytest.mark.parametrize("case_id, kind, before, text, fragments", CASES, ids=[c[0] for c in CASES])
def test_a_bad_file_is_one_line_with_its_key_path(tmp_path, capsys, case_id, kind, before, text, fragments):
    path = _write_file(tmp_path, case_id, kind, text)
    code = main(_argv(kind, path, tmp_path / "out"))
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and "internal error" not in err
    lines = err.strip().splitlines()
    assert any(all(f in line for f in fragments) for line in lines), lines


def test_the_case_table_holds_the_measured_counts():
    counts = {label: sum(c[2] == label for c in CASES) for label in ("internal", "unclear", "silent")}
    assert counts == {"internal": 20, "unclear": 18, "silent": 7}, counts
