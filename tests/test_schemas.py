"""Declared schemas of the four input files (issue 22 section 3): every bad file is exit 2 with the key's path.

Table-driven: each case is a file of one kind (scenario, site, dataset spec, sweep spec) that the command line
reads, and the one error line it must give: the full key path and the value as written, with exit code 2 and no
traceback. The cases were measured against the hand-written validators they replace: ``internal`` cases ended in an
internal error (exit 1) or a traceback, ``unclear`` ones in a message without the key's path or with a wrong key,
``silent`` ones were accepted (a TOML ``true`` taken as the number 1), ``clear`` ones were answered well already
(they guard the schema's messages). ``bom`` cases carry a UTF-8 byte-order mark before a mistake, which must be
found past the mark.
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
DEM_SITE = f'dem = "dem.tif"\n{SITE}'.replace("505000.0", "504025.0").replace("5005000.0", "5005975.0")
RADIO_SITE = SITE + "[sensors.rf]\nx = 502500.0\ny = 5007000.0\n"
RADIO = "[radio_map]\nstep = 64\nsamples = 1000\n"
#: The DEM (heights [m], 50 m cells, UTM 33N) a case's site names as dem.tif.
DEMS = {
    "site_dem_one_cell": np.zeros((1, 1)),
    "site_dem_nan_heights": np.full((4, 4), np.nan),
    "site_dem_all_nodata": np.full((4, 4), -9999.0),
}
PD_SWEEP = SWEEP.replace('"range"', '"pd"')
AZIMUTH_SWEEP = 'job = "render"\n[axes]\nazimuth_deg = [0.0]\n'
RCS_SWEEP = 'job = "rcs"\nscenario = "default"\n[axes]\nfrequency_ghz = [10.0]\n'
DATASET = 'scenario = "default"\nsensor = "eo"\ncount = 1\n'

#: (id, kind, what the old validators did, file text, fragments of one error line); kind ``command``: the text is
#: the command line itself. ``clear`` cases were already answered well and guard the schema's messages.
# fmt: off
CASES = [
    ("dataset_range_without_max", "dataset", "internal", DATASET + "range_m = {min = 100.0}\n", ["range_m.max"]),
    ("dataset_sensor_list", "dataset", "internal", 'scenario = "default"\nsensor = ["eo"]\n', ["sensor = ['eo']"]),
    ("dataset_azimuth_without_min", "dataset", "internal", DATASET + "azimuth_deg = {max = 10.0}\n",
     ["azimuth_deg.min"]),
    ("sweep_samples_inf", "sweep", "internal", SWEEP + '"target.x_m" = {min = 0.0, max = 1.0, samples = inf}\n',
     ["axes.target.x_m.samples = inf"]),
    ("sweep_samples_nan", "sweep", "internal", SWEEP + '"target.x_m" = {min = 0.0, max = 1.0, samples = nan}\n',
     ["axes.target.x_m.samples = nan"]),
    ("sweep_render_mode_xray", "sweep", "internal", RENDER_SWEEP + '[options]\nmode = "xray"\n',
     ["options.mode = 'xray'", "eo"]),
    ("sweep_render_xray_without_axes", "sweep", "internal",
     'job = "render"\n[options]\nrange_m = 100.0\nmode = "xray"\n',
     ["options.mode = 'xray'"]),
    ("sweep_scenario_number", "sweep", "internal", 'job = "range"\nscenario = 5\n', ["scenario = 5"]),
    ("sweep_rcs_target_number", "sweep", "unclear", RCS_SWEEP + "[options]\ntarget = 5\n", ["options.target = 5"]),
    ("sweep_rcs_rays_text", "sweep", "unclear", RCS_SWEEP + '[options]\nrays_per_wavelength = "many"\n',
     ["options.rays_per_wavelength = 'many'"]),
    ("sweep_render_range_text", "sweep", "unclear", AZIMUTH_SWEEP + '[options]\nrange_m = "far"\n',
     ["options.range_m = 'far'"]),
    ("sweep_pd_fusion_list", "sweep", "internal", PD_SWEEP + "[options]\nfusion = [1]\n",
     ["options.fusion = [1]"]),
    ("site_sensors_number", "site", "internal", 'scenario = "default"\nsensors = 5\n', ["sensors = 5"]),
    ("site_sensor_not_a_table", "site", "internal", 'scenario = "default"\n[sensors]\neo = 5\n', ["sensors.eo = 5"]),
    ("site_dem_number", "site", "internal", "dem = 5\n" + SITE, ["dem = 5"]),
    ("site_scenario_number", "site", "internal", "scenario = 5\n[sensors.eo]\nx = 1.0\ny = 2.0\n", ["scenario = 5"]),
    ("site_dem_one_cell", "site", "internal", DEM_SITE, ["dem = 'dem.tif'", "2 x 2"]),
    ("site_radio_ground_text", "site", "unclear",
     RADIO_SITE + '[radio_map]\nground = {relative_permittivity = "wet", conductivity_s_m = 0.01}\n',
     ["radio_map.ground.relative_permittivity = 'wet'"]),
    ("site_radio_sensors_table", "site", "clear", RADIO_SITE + "[radio_map]\nsensors = {rf = 1}\n",
     ["radio_map.sensors = {'rf': 1}"]),
    ("site_pointing_table", "site", "clear", SITE + "azimuth_deg = {a = 1}\n",
     ["sensors.eo.azimuth_deg = {'a': 1}"]),
    ("dataset_drones_table", "dataset", "clear", DATASET + "drones = {a = 1}\n", ["drones = {'a': 1}"]),
    ("scenario_bom", "scenario", "unclear", BOM + SCENARIO + "hfov_deg = 500.0\n", ["sensors.eo.hfov_deg = 500.0"]),
    ("sweep_bom", "sweep", "unclear", BOM + 'job = "range"\nseed = -1\n', ["seed = -1"]),
    ("dataset_bom", "dataset", "unclear", BOM + "count = 0\n", ["count = 0"]),
    ("site_bom", "site", "unclear", BOM + "fusion_k = 0\n" + SITE, ["fusion_k = 0"]),
    ("site_dem_not_a_geotiff", "site", "unclear", f'dem = "bad.tif"\n{SITE}', ["dem = 'bad.tif'", "GeoTIFF"]),
    ("site_dem_nan_heights", "site", "unclear", DEM_SITE, ["dem = 'dem.tif'", "finite heights"]),
    ("scenario_rf_rain_path", "scenario", "unclear",
     '[environment]\nrain = "moderate"\n[sensors.rf1]\nmodality = "rf"\nfrequency_ghz = 0.5\n',
     ["sensors.rf1.frequency_ghz = 0.5"]),
    ("pd_radar_pd_zero", "command", "unclear", "pd-radar --pd 0 --pfa 1e-6", ["pd = 0", "Pd = 0 asks for no"]),
    ("sweep_samples_huge", "sweep", "unclear", SWEEP + '"target.x_m" = {min = 0.0, max = 1.0, samples = 1e12}\n',
     ["axes.target.x_m.samples = 1000000000000.0"]),
    ("sweep_render_quality_ultra", "sweep", "unclear", RENDER_SWEEP + '[options]\nquality = "ultra"\n',
     ["options.quality = 'ultra'", "draft"]),
    ("sweep_options_convention", "sweep", "unclear", SWEEP + '[options]\nconvention = "metric"\n',
     ["options.convention = 'metric'", "paper"]),
    ("sweep_pd_fusion_word", "sweep", "unclear", PD_SWEEP + '[options]\nfusion = "and"\n',
     ["options.fusion = 'and'", "k-of-n"]),
    ("sweep_axis_value_out_of_range", "sweep", "unclear", 'job = "render"\n[axes]\nrange_m = [100.0, -5.0]\n',
     ["axes.range_m.1 = -5.0"]),
    ("sweep_draw_min_above_max", "sweep", "unclear", SWEEP + '"target.x_m" = {min = 2.0, max = 1.0, samples = 3}\n',
     ["axes.target.x_m.max = 1.0", "min"]),
    ("sweep_axis_draw_unknown_key", "sweep", "unclear",
     SWEEP + '"target.x_m" = {min = 0.0, max = 1.0, samples = 3, step = 1}\n', ["axes.target.x_m.step = 1"]),
    ("dataset_unknown_stage", "dataset", "unclear", DATASET + 'chain = ["psf", "blur"]\n', ["chain.1 = 'blur'", "psf"]),
    ("dataset_unknown_drone", "dataset", "unclear", DATASET + 'drones = ["dji", "black_hornet_3"]\n',
     ["drones.0 = 'dji'", "dji_mini_4_pro"]),
    ("dataset_range_limits", "dataset", "unclear", DATASET + "range_m = [50.0, 1e9]\n", ["range_m.1 = 1000000000.0"]),
    ("site_x_true", "site", "unclear", SITE.replace("x = 505000.0", "x = true"), ["sensors.eo.x = True"]),
    ("site_x_nan", "site", "unclear", SITE.replace("x = 505000.0", "x = nan"), ["sensors.eo.x = nan"]),
    ("sweep_render_elevation_text", "sweep", "internal", RENDER_SWEEP + '[options]\nelevation_deg = "up"\n',
     ["options.elevation_deg = 'up'"]),
    ("sweep_rcs_azimuth_text", "sweep", "internal", RCS_SWEEP + '[options]\nazimuth_deg = "left"\n',
     ["options.azimuth_deg = 'left'"]),
    ("sweep_options_convention_number", "sweep", "unclear", SWEEP + "[options]\nconvention = 5\n",
     ["options.convention = 5"]),
    ("sweep_render_mode_number", "sweep", "internal", RENDER_SWEEP + "[options]\nmode = 5\n", ["options.mode = 5"]),
    ("sweep_pd_fusion_k_zero", "sweep", "unclear", PD_SWEEP + '[options]\nfusion = "k-of-n:0"\n',
     ["options.fusion = 'k-of-n:0'"]),
    ("site_radio_ground_list", "site", "unclear",
     RADIO_SITE + "[radio_map]\nground = {relative_permittivity = 5.0, conductivity_s_m = [1.0]}\n",
     ["radio_map.ground.conductivity_s_m = [1.0]"]),
    ("scenario_mrtd_scalar_and_list", "scenario", "silent",
     '[sensors.t]\nmodality = "tir"\nmrtd_frequency_cy_mrad = 1.0\nmrtd_k = [0.1, 0.2]\n', ["sensors.t.mrtd_k"]),
    ("scenario_mrtd_empty", "scenario", "silent",
     '[sensors.t]\nmodality = "tir"\nmrtd_frequency_cy_mrad = []\nmrtd_k = []\n',
     ["sensors.t.mrtd_frequency_cy_mrad = []"]),
    ("scenario_mrtd_decreasing", "scenario", "silent",
     '[sensors.t]\nmodality = "tir"\nmrtd_frequency_cy_mrad = [2.0, 1.0]\nmrtd_k = [0.1, 0.2]\n',
     ["sensors.t.mrtd_frequency_cy_mrad = [2.0, 1.0]", "increasing"]),
    ("site_dem_all_nodata", "site", "unclear", DEM_SITE, ["dem = 'dem.tif'", "finite heights"]),
    ("sweep_scenario_list", "sweep", "internal", 'job = "range"\nscenario = ["default"]\n', ["scenario = ['default']"]),
    ("sweep_rcs_quality_number", "sweep", "unclear", RCS_SWEEP + "[options]\nquality = 3\n", ["options.quality = 3"]),
    ("site_min_range_inf", "site", "clear", SITE + "min_range_m = inf\n", ["sensors.eo.min_range_m = inf"]),
    ("site_altitudes_repeated", "site", "silent", SITE.replace("[30.0]", "[30.0, 30.0]"),
     ["altitudes_agl_m = [30.0, 30.0]"]),
    ("sweep_render_range_negative", "sweep", "unclear", AZIMUTH_SWEEP + "[options]\nrange_m = -5.0\n",
     ["options.range_m = -5.0"]),
    ("sweep_render_azimuth_huge", "sweep", "unclear", RENDER_SWEEP + "[options]\nazimuth_deg = 1e9\n",
     ["options.azimuth_deg = 1000000000.0"]),
    ("sweep_pd_fusion_number", "sweep", "internal", PD_SWEEP + "[options]\nfusion = 2\n",
     ["options.fusion = 2"]),
    ("sweep_rcs_elevation_list", "sweep", "silent", RCS_SWEEP + "[options]\nelevation_deg = [1.0]\n",
     ["options.elevation_deg = [1.0]"]),
    ("dataset_elevation_without_max", "dataset", "internal", DATASET + "elevation_deg = {min = 10.0}\n",
     ["elevation_deg.max"]),
    ("dataset_jpeg_of_12_bits", "dataset", "unclear", DATASET + 'chain = ["quantise", "jpeg"]\n',
     ["chain", "bits = 8"]),
    ("sweep_pd_fusion_k_above_n", "sweep", "unclear",
     PD_SWEEP + '[options]\nfusion = "k-of-n:99"\n', ["options.fusion = 'k-of-n:99'"]),
    ("site_mast_true", "site", "silent", SITE + "mast_m = true\n", ["sensors.eo.mast_m = True", "number"]),
    ("site_altitude_true", "site", "silent", SITE.replace("[30.0]", "[true]"), ["altitudes_agl_m.0 = True"]),
    ("site_radio_accuracy_true", "site", "silent", RADIO_SITE + RADIO + "accuracy_db = true\n",
     ["radio_map.accuracy_db = True"]),
    ("dataset_background_true", "dataset", "silent", DATASET + "background = true\n", ["background = True"]),
    ("dataset_cloud_cover_true", "dataset", "silent", DATASET + 'background = "clear_sky"\ncloud_cover = true\n',
     ["cloud_cover = True"]),
    ("sweep_option_azimuth_true", "sweep", "silent", RENDER_SWEEP + "[options]\nazimuth_deg = true\n",
     ["options.azimuth_deg = True"]),
    ("dataset_bits_float", "dataset", "silent", DATASET + "bits = 8.0\n", ["bits = 8.0"]),
    ("scenario_mrtd_lengths", "scenario", "silent",
     '[sensors.t]\nmodality = "tir"\nmrtd_frequency_cy_mrad = [1.0, 2.0]\nmrtd_k = [0.1]\n', ["sensors.t.mrtd_k"]),
    ("scenario_description_number", "scenario", "silent", "description = 5\n" + SCENARIO, ["description = 5"]),
    ("dataset_scenario_table", "dataset", "clear", "scenario = {a = 1}\n", ["scenario = {'a': 1}"]),
    ("sweep_axis_nested_list", "sweep", "unclear", 'job = "render"\n[axes]\nrange_m = [[100.0]]\n',
     ["axes.range_m.0 = [100.0]"]),
    ("site_altitudes_text", "site", "clear", SITE.replace("[30.0]", '"high"'), ["altitudes_agl_m = 'high'"]),
    ("site_radio_map_ground_nan", "site", "unclear",
     RADIO_SITE + "[radio_map]\nground = {relative_permittivity = nan, conductivity_s_m = 0.01}\n",
     ["radio_map.ground.relative_permittivity = nan"]),
    ("site_sensor_unknown_key", "site", "clear", SITE + "mast = 5.0\n", ["sensors.eo.mast = 5.0", "mast_m"]),
    ("site_unknown_key", "site", "clear", SITE.replace("scenario", "scenari"), ["scenari = 'default'", "scenario"]),
    ("sweep_unknown_option", "sweep", "clear", SWEEP + "[options]\nfusoin = 'or'\n",
     ["options.fusoin = 'or'", "convention"]),
    ("site_fusion_k_above_n", "site", "clear", "fusion_k = 3\n" + SITE, ["fusion_k = 3", "1 to 1"]),
    ("site_radio_map_unknown_key", "site", "clear", RADIO_SITE + "[radio_map]\nsteps = 4\n",
     ["radio_map.steps = 4", "step"]),
    ("scenario_sensor_preset_unknown", "scenario", "clear", SCENARIO + 'preset = "nope"\n',
     ["sensors.eo.preset = 'nope'", "default"]),
]
# fmt: on


def _write_dem(path, heights):
    import rasterio
    from rasterio.transform import from_origin

    rows, cols = heights.shape
    profile = {"driver": "GTiff", "height": rows, "width": cols, "count": 1, "dtype": "float32", "nodata": -9999.0}
    transform = from_origin(504_000.0, 5_006_000.0, 50.0, 50.0)
    with rasterio.open(path, "w", crs="EPSG:32633", transform=transform, **profile) as dst:
        dst.write(heights.astype(np.float32), 1)


def _write_file(tmp_path, case_id: str, kind: str, text: str):
    path = tmp_path / f"{kind}.toml"
    path.write_bytes(text.encode("utf-8"))
    (tmp_path / "bad.tif").write_text("not a GeoTIFF\n")
    if case_id in DEMS:
        _write_dem(tmp_path / "dem.tif", DEMS[case_id])
    return path


def _argv(kind: str, path, out) -> list[str]:
    if kind == "command":
        return path.read_text().split()
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
    """What the hand-written validators did with these files (measured on the commit before the schemas):
    the issue's 20 internal errors, 18 unclear messages and 7 silently accepted values, and more found since."""
    counts = {label: sum(c[2] == label for c in CASES) for label in ("internal", "unclear", "silent", "clear")}
    assert counts == {"internal": 20, "unclear": 35, "silent": 14, "clear": 12}, counts


def test_the_docs_key_tables_are_what_the_schemas_generate():
    """docs/ shows the schemas' keys, defaults and allowed values: regenerate with python -m csuas.schema_docs."""
    from csuas.schema_docs import generated_pages

    stale = [str(path) for path, text in generated_pages().items() if path.read_text(encoding="utf-8") != text]
    assert stale == []


def test_every_preset_is_valid_under_its_sections_schema():
    """Presets are applied unchecked by the resolver: each must pass the schema of the table it fills."""
    from csuas.base.schema import validate
    from csuas.defaults import MODALITIES, load_presets
    from csuas.defaults.scenario_schema import TAGS, section_schema

    presets = load_presets()
    tables = [("target", "target", name, table) for name, table in presets["target"].items()]
    tables += [("environment", "environment", name, table) for name, table in presets["environment"].items()]
    tables += [(m, m, name, table) for m in MODALITIES for name, table in presets["sensor"].get(m, {}).items()]
    assert len(tables) > 20
    for section, kind, name, table in tables:
        values = {k: v for k, v in table.items() if k not in ("description", "source")}
        values.update({"modality": kind} if kind in MODALITIES else {})
        validate(section_schema(section, kind, "default" if kind in MODALITIES else name), values, kind, TAGS)


def test_a_byte_order_mark_is_read_past_and_booleans_are_never_numbers(tmp_path):
    from csuas.base.errors import ParameterError
    from csuas.base.schema import Schema, key, number, read_toml, validate

    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbfa = 1.5\n")
    assert read_toml(path, "spec", "spec") == {"a": 1.5}

    class Table(Schema):
        a: number(0.0, 2.0, "m") = key(1.0, "a length")

    assert validate(Table, {"a": 2}).a == 2
    with pytest.raises(ParameterError, match=r"^a = True is invalid; allowed: a number \[0, 2\] m$"):
        validate(Table, {"a": True})


def test_the_generated_markers_are_required():
    from csuas.base.schema import replace_generated

    assert replace_generated("x\n<!-- generated: t -->\nold\n<!-- end generated: t -->\ny", "t", "new") == (
        "x\n<!-- generated: t -->\nnew\n<!-- end generated: t -->\ny"
    )
    with pytest.raises(ValueError, match="lacks the markers"):
        replace_generated("no markers", "t", "new")
