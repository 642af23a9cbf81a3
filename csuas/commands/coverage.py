"""``csuas coverage SITE --out DIR``: where each sensor of a site sees and detects a drone, with terrain.

The site (TOML, public interface; docs/coverage.md) names a DEM (a GeoTIFF in a projected CRS, metres;
omitted: the embedded synthetic demo terrain), a scenario, the flight levels ``altitudes_agl_m``, optionally
``fusion_k`` (the k of the k-of-n fused layers) and, per sensor of the scenario, its position ``x``, ``y``
in the DEM's CRS, ``mast_m`` and optionally its pointing and dead zones (``azimuth_deg``, ``sector_deg``,
``elevation_min_deg``, ``elevation_max_deg``, ``min_range_m``). Writes ``DIR/coverage.json`` (every layer
with ``sensor``, ``altitude_m``, ``kind`` and ``path``, and the area covered), a GeoTIFF per layer in the
DEM's CRS and transform, PNG maps over a hillshade and, for every detected layer, GeoJSON polygons of the
covered cells.
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from csuas.base.cost import add_limit_arguments, check_limits
from csuas.base.errors import ParameterError, raise_all
from csuas.base.fileio import exclusive_lock, prepare_output_dir, read_spec, write_text_atomic
from csuas.base.paths import checked_path, inside, sub_folder
from csuas.commands.coverage_files import (
    MapWriter,
    covered_polygons,
    to_wgs84,
    write_cog,
    write_geojson,
    write_geopackage,
    write_geotiff,
    write_kml,
)
from csuas.commands.coverage_radio import radio_map_errors, radio_map_layers, radio_map_settings
from csuas.commands.coverage_tiles import (
    MIN_TILE_CELLS,
    STATE_NAME,
    TILE_CELLS,
    TILES_DIR,
    TiledSite,
    dem_header,
    inputs_digest,
    nodata_fill_m,
    peak_rss_mib,
    run_tiles,
    window_tiles,
)
from csuas.core.coverage import (
    POINTING,
    SitedSensor,
    farthest_ground_m,
    fresnel_layers,
    fused_layers,
    fused_visibility,
    mapped_reach_m,
    reach_window,
    sensor_layers,
)
from csuas.core.coverage_cost import coverage_estimate, coverage_tiles_estimate
from csuas.core.ranges import evaluate
from csuas.core.scenario import load_scenario
from csuas.defaults import site_path
from csuas.render.site import DEMO, dem_path, load_dem, sensor_xy, validated_site
from csuas.sweep.cluster import DEFAULT_WORKERS, check_scheduler, show_progress

#: Lock file inside the output folder: one coverage run writes into a folder at a time.
LOCK_NAME = ".csuas-coverage.lock"
#: Layers of a radio map: (kind, key of :func:`csuas.commands.coverage_radio.radio_map_layers`'s grids).
RADIO_KINDS = (
    ("path_gain", "path_gain_db"),
    ("path_gain_error", "error_db"),
    ("detected_multipath", "detected"),
    ("pd_multipath", "pd"),
)
#: Layers that also get a GeoJSON of their covered cells.
GEOJSON_KINDS = ("detected", "k_of_n", "detected_multipath")
#: Pd maps show the cells at this Pd or more (a faint wash of low Pd hides where a sensor detects).
PD_SHOWN = 0.5
#: Every vector layer together: a GeoPackage in the DEM's CRS and a KML on WGS 84.
VECTOR_FILES = ("coverage.gpkg", "coverage.kml")
#: Unit of the GeoTIFF band of layers without a physical unit.
BAND_UNITS = {
    "visible": "1 = in sight",
    "detected": "1 = detected",
    "k_of_n": "1 = detected",
    "detected_multipath": "1 = detected",
}
#: Each sensor's layers at every flight level, and the fused layers' quantities (with fusion_k: and k of n).
SENSOR_KINDS = ("visible", "detected", "pd")
FUSED_QUANTITIES = ("count", "detected", "pd", "visible_count")
#: Fused layers over all flight levels: the lowest height any sensor sees, and the lowest level detected.
FUSED_HEIGHTS = ("min_visible_height", "min_detectable_height")
FUSED_K_QUANTITIES = ("k_of_n", "pd_k_of_n")
#: Layers whose every finite value is shown and counted as covered (the others: values above 0).
VALUE_KINDS = (
    "min_altitude",
    "path_gain",
    "path_gain_error",
    "fresnel_clearance",
    "min_visible_height",
    "min_detectable_height",
)
#: Colour-bar labels of the layers with a scale.
UNITS = {
    "pd": "Pd",
    "pd_multipath": "Pd",
    "min_altitude": "m above the terrain",
    "path_gain": "path gain [dB]",
    "path_gain_error": "bound [dB]",
    "count": "sensors",
    "visible_count": "sensors",
    "min_visible_height": "m above the terrain",
    "min_detectable_height": "m above the terrain",
    "fresnel_clearance": "clearance / r1",
}
#: Modalities whose links get a Fresnel clearance layer per flight level.
FRESNEL_MODALITIES = ("rf", "radar")


def add_arguments(parser):
    """Declare the options of ``csuas coverage``."""
    parser.add_argument("site", help="site TOML file, or an embedded site (demo)")
    parser.add_argument("--out", required=True, help="output folder (coverage.json, GeoTIFF and PNG layers)")
    parser.add_argument(
        "--scheduler",
        default=None,
        help="run by tiles on Dask, one Cloud Optimised GeoTIFF a layer (no PNG, GeoJSON or radio map): serial "
        "(this process), local (a LocalCluster), tcp://HOST:PORT or tls://HOST:PORT (docs/coverage.md); "
        "default: the whole DEM in this process",
    )
    parser.add_argument("--workers", type=int, default=None, help="workers of --scheduler local (default: CPU count)")
    parser.add_argument(
        "--tile", type=int, default=None, help=f"tile size with --scheduler [cells a side] (default {TILE_CELLS})"
    )
    add_limit_arguments(parser)


def _dem_cells(dem: str | None, site_path) -> tuple[int, int]:
    """Rows and columns of the site's DEM (the demo terrain's without one), read from its header alone."""
    import rasterio

    if dem is None:
        return DEMO["cells"], DEMO["cells"]
    path = dem_path(dem, site_path)
    try:
        with rasterio.open(path) as src:
            return src.height, src.width
    except rasterio.errors.RasterioError as exc:
        raise ParameterError("dem", dem, f"a GeoTIFF file GDAL can read ({exc})") from None


def _check_cost(site, site_path, radio, args, fresnel_links: int) -> None:
    """Estimate the run from the DEM's header, the sensors and the levels; refuse it above the limits."""

    maps = 0 if radio is None else len(radio["sensors"])
    samples = 0 if radio is None else int(radio["samples"])
    cells = _dem_cells(site.dem, site_path)
    estimate = coverage_estimate(
        cells, len(site.sensors), len(site.altitudes_agl_m), site.fusion_k is not None, maps, samples, fresnel_links
    )
    check_limits(estimate, args, "coverage")


#: Why a scenario with ``target.swarm`` has no coverage map (docs/coverage.md).
SWARM_REFUSED = (
    "a scenario without target.swarm: a coverage map is one drone's Pd per cell, vectorised over the grid, and a "
    "swarm's resolved groups change with each sensor's range and its line of sight to every cell (found range by "
    "range: csuas range and pd report the swarm)"
)


def _checked_site(site: dict):
    """The validated site (:class:`~csuas.render.site_schema.SiteSchema`) and its scenario; every mistake
    of the file, of its sensors and of its radio map against the scenario at once."""

    name = site.get("scenario", "default")
    scenario = load_scenario(name) if isinstance(name, str) else None
    extra = [] if scenario is None else radio_map_errors(site, scenario)
    if scenario is not None and scenario.swarm is not None:
        extra.append(ParameterError("scenario", name, SWARM_REFUSED))
    return validated_site(site, scenario, extra), scenario


def _tile_options(args, radio) -> None:
    """``--scheduler``, ``--workers`` and ``--tile`` in their domains, together (all mistakes at once)."""
    errors = []
    scheduler = getattr(args, "scheduler", None)
    workers, tile = getattr(args, "workers", None), getattr(args, "tile", None)
    if scheduler is None:
        given = (("--workers", workers), ("--tile", tile))
        errors += [ParameterError(o, v, "only with --scheduler") for o, v in given if v is not None]
    else:
        try:
            check_scheduler(scheduler, "--scheduler")
        except ParameterError as exc:
            errors.append(exc)
        if radio is not None:
            why = "no radio map with --scheduler (Sionna traces the whole scene): run without it"
            errors.append(ParameterError("radio_map", radio["sensors"], why))
    if workers is not None and workers < 1:
        errors.append(ParameterError("--workers", workers, "a whole number >= 1"))
    if tile is not None and tile < MIN_TILE_CELLS:
        errors.append(ParameterError("--tile", tile, f"a whole number of cells >= {MIN_TILE_CELLS}"))
    raise_all(errors)


def _site_sensors(site, transform, crs, shape) -> dict:
    """Each sensor of the site placed on the DEM's grid (:class:`SitedSensor`); every one outside it refused."""
    inverse = ~transform
    sited, outside = {}, []
    for name, table in site.sensors.items():
        col, row = inverse @ sensor_xy(table, crs)
        col, row = col - 0.5, row - 0.5  # cell centres at half-integers of the transform
        if not (0.0 <= row <= shape[0] - 1 and 0.0 <= col <= shape[1] - 1):
            given = (table.x, table.y) if table.x is not None else (table.lat, table.lon)
            outside.append(ParameterError(f"sensors.{name}", given, "a position inside the DEM"))
        pointing = {key: float(getattr(table, key)) for key in POINTING}
        sited[name] = SitedSensor(name, row, col, float(table.mast_m), **pointing)
    raise_all(outside)
    return sited


def run(args) -> dict:
    """Compute and write every layer of the site."""

    source = Path(args.site)
    table = read_spec(args.site, site_path, "site")
    site, scenario = _checked_site(table)
    radio = radio_map_settings(site, scenario)
    checked_path(args.out, "--out")  # the folder's name is refused before the estimate is announced
    _tile_options(args, radio)
    if getattr(args, "scheduler", None) is not None:
        return _run_tiled(args, (table, site, scenario), source if source.is_file() else None)
    links = len(_fresnel_sensors(site.sensors, scenario))
    _check_cost(site, source if source.is_file() else None, radio, args, links)  # before the DEM is read
    dem, transform, crs, cell = load_dem(site.dem, source if source.is_file() else None)
    sited = _site_sensors(site, transform, crs, dem.shape)
    altitudes = [float(a) for a in site.altitudes_agl_m]
    k = site.fusion_k
    out = prepare_output_dir(args.out)
    radio_sensors = [] if radio is None else radio["sensors"]
    for name in _layer_files(sited, altitudes, radio_sensors, k, _fresnel_sensors(sited, scenario)):
        inside(out, name)  # outside --out, or a special file there: refused now, not after the work
    frame = {"transform": transform, "crs": crs, "hillshade": _hillshade(dem, cell), "sited": sited}
    with exclusive_lock(out / LOCK_NAME, "--out"), MapWriter(frame) as maps:  # its workers start meanwhile
        layers, per_sensor = [], {}
        for name, placed in sited.items():
            print(f"csuas coverage: {name} ...", file=sys.stderr, flush=True)
            per_sensor[name] = sensor_layers(dem, cell, scenario, placed, altitudes)
        fresnel = {
            name: fresnel_layers(dem, cell, scenario, sited[name], per_sensor[name])
            for name in _fresnel_sensors(sited, scenario)
        }
        fused = {**fused_layers(per_sensor, k), **fused_visibility(dem, cell, scenario, sited, per_sensor)}
        radio_maps = {} if radio is None else radio_map_layers(dem, cell, scenario, sited, altitudes, per_sensor, radio)
        where = {**frame, "cell_km2": cell * cell / 1e6, "vectors": [], "maps": maps}
        for name, grids in per_sensor.items():
            for i, altitude in enumerate(altitudes):
                for kind in SENSOR_KINDS:
                    grid = grids[kind][i].astype(np.float32)
                    if kind == "visible":
                        grid[~grids["traced"]] = np.nan  # beyond the mapped reach: not traced
                    layers.append(_layer(out, name, altitude, kind, grid, where))
            min_alt = grids["min_altitude_m"].astype(np.float32)
            layers.append(_layer(out, name, None, "min_altitude", min_alt, where))
        for name, grids in fresnel.items():
            for i, altitude in enumerate(altitudes):
                layer = _layer(
                    out, name, altitude, "fresnel_clearance", grids["clearance"][i].astype(np.float32), where
                )
                share = float(grids["obstructed"][i])
                layers.append({**layer, "obstructed_fraction": None if math.isnan(share) else share})
        for name, grids in radio_maps.items():
            for i, altitude in enumerate(altitudes):
                for kind, key in RADIO_KINDS:
                    layers.append(_layer(out, name, altitude, kind, grids[key][i].astype(np.float32), where))
        layers += _fused_files(out, fused, altitudes, (k, len(sited)), where)
        summary = {
            **_summary_head(args.site, crs, cell, altitudes, k),
            "sensors": {n: _sensor_summary(sited[n], g["range_m"], g["reach_m"]) for n, g in per_sensor.items()},
            "layers": layers,
            "vectors": _write_vectors(out, where),
        }
        if radio is not None:
            settings = {key: radio[key] for key in ("ground", "step", "max_depth", "seed", "accuracy_db")}
            summary["radio_maps"] = {"settings": settings, "maps": {n: g["maps"] for n, g in radio_maps.items()}}
        maps.close()  # every PNG map written before coverage.json names it
        write_text_atomic(inside(out, "coverage.json"), json.dumps(summary, indent=1))
        summary["out"] = str(out)
        return summary


def _tiled_layers(sensors, altitudes: list, k, fresnel_sensors) -> list[tuple]:
    """``(sensor, altitude or None, kind)`` of every layer a tiled run writes, in the single-process run's order."""
    layers = []
    for name in sensors:
        layers += [(name, a, kind) for a in altitudes for kind in SENSOR_KINDS] + [(name, None, "min_altitude")]
    layers += [(name, a, "fresnel_clearance") for name in fresnel_sensors for a in altitudes]
    fused = FUSED_QUANTITIES + (() if k is None else FUSED_K_QUANTITIES)
    layers += [("fused", a, quantity) for a in altitudes for quantity in fused]
    return layers + [("fused", None, quantity) for quantity in FUSED_HEIGHTS]


def _run_tiled(args, inputs: tuple, source) -> dict:
    """The coverage by tiles on Dask (:mod:`csuas.commands.coverage_tiles`): one COG a layer, and coverage.json."""
    table, site, scenario = inputs
    shape, transform, crs, cell = dem_header(site.dem, source)
    sited = _site_sensors(site, transform, crs, shape)
    altitudes, k = [float(a) for a in site.altitudes_agl_m], site.fusion_k
    fresnel = tuple(_fresnel_sensors(sited, scenario))
    specs = _tiled_layers(sited, altitudes, k, fresnel)
    reach = {n: mapped_reach_m(scenario, n, farthest_ground_m(shape, p, cell)) for n, p in sited.items()}
    tile = args.tile or TILE_CELLS
    windows = [
        (*window_tiles(shape, reach_window(shape, p, reach[n], cell), tile), n in fresnel) for n, p in sited.items()
    ]
    workers = 1 if args.scheduler == "serial" else args.workers or DEFAULT_WORKERS
    estimate = coverage_tiles_estimate(
        shape, windows, (min(tile, shape[0]) * min(tile, shape[1]), workers), len(altitudes), len(specs)
    )
    check_limits(estimate, args, "coverage")  # before the DEM is read
    out = prepare_output_dir(args.out)
    sub_folder(out, TILES_DIR)
    for name in ["coverage.json", STATE_NAME] + [_stem(*spec) + ".tif" for spec in specs]:
        inside(out, name)  # outside --out, or a special file there: refused now, not after the work
    dem = None if site.dem is None else str(dem_path(site.dem, source))
    tiled = TiledSite(
        dem, shape, cell, nodata_fill_m(dem), scenario, sited, reach, tuple(altitudes), k, fresnel, tuple(specs),
        VALUE_KINDS, tile,
    )  # fmt: skip
    where = {"transform": transform, "crs": crs}
    run = {"scheduler": args.scheduler, "workers": args.workers}
    with exclusive_lock(out / LOCK_NAME, "--out"):
        started = time.perf_counter()
        run["digest"] = inputs_digest(table, scenario, dem, tiled.tile)
        ran = run_tiles(tiled, out, run, where)
        layers = _tiled_files(out, tiled, ran["counts"], {**where, "shape": shape, "cell_km2": cell * cell / 1e6})
        ranges = evaluate(scenario)
        summary = {
            **_summary_head(args.site, crs, cell, altitudes, k),
            "sensors": {
                n: _sensor_summary(p, float(np.asarray(ranges[n].range_m)), reach[n]) for n, p in sited.items()
            },
            "layers": layers,
            "vectors": {},
            "tiles": {
                "scheduler": args.scheduler,
                "workers": ran["workers"],
                "tile_cells": tiled.tile,
                "tiles": ran["tiles"],
                "tiles_run": ran["run"],
                "tiles_resumed": ran["tiles"] - ran["run"],
                "peak_rss_mib": ran["peak_rss_mib"],
                "client_peak_rss_mib": peak_rss_mib(),
                "wall_time_s": time.perf_counter() - started,
            },
        }
        write_text_atomic(inside(out, "coverage.json"), json.dumps(summary, indent=1))
        summary["out"] = str(out)
        return summary


def _summary_head(site, crs, cell_m: float, altitudes: list, k) -> dict:
    """The keys of ``coverage.json`` that open it, the same for a single-process and a tiled run."""
    return {"site": str(site), "crs": crs, "cell_m": cell_m, "altitudes_agl_m": altitudes, "fusion_k": k}


def _sensor_summary(placed, range_m: float, reach_m: float) -> dict:
    """``coverage.json``'s ``sensors.<name>``: range and mapped reach [m] (None: unlimited), cell and pointing."""
    return {
        "range_m": range_m,
        "reach_m": None if math.isinf(reach_m) else reach_m,
        "row": placed.row,
        "col": placed.col,
        **{key: getattr(placed, key) for key in POINTING},
    }


def _tiled_files(out: Path, tiled, counts: dict, where: dict) -> list[dict]:
    """Mosaic each layer's tiles into its COG; describe the layers for coverage.json (areas from the tiles' counts)."""
    folder = out / TILES_DIR
    order = sorted(counts)
    n_alt = len(tiled.altitudes)
    started = time.perf_counter()
    layers = []
    for band, (sensor, altitude, kind) in enumerate(tiled.layers):
        stem = _stem(sensor, altitude, kind)
        title = f"{sensor}: {kind}" + ("" if altitude is None else f" at {altitude:g} m AGL")
        sources = [(folder / f"tile-{b[0]:06d}-{b[2]:06d}.tif", band + 1, b) for b in order]
        unit = UNITS.get(kind, "") or BAND_UNITS.get(kind, "")
        write_cog(inside(out, f"{stem}.tif"), folder / f"{stem}.vrt", sources, where, (title, unit))
        area = sum(counts[b]["covered"][band] for b in order) * where["cell_km2"]
        layer = {"sensor": sensor, "altitude_m": altitude, "kind": kind, "path": f"{stem}.tif", "area_km2": float(area)}
        if kind == "fresnel_clearance":
            i = tiled.fresnel.index(sensor) * n_alt + tiled.altitudes.index(altitude)
            obstructed, judged = (sum(counts[b]["fresnel"][i][j] for b in order) for j in (0, 1))
            layer["obstructed_fraction"] = obstructed / judged if judged else None
        if sensor == "fused":
            extra = {"k": tiled.fusion_k, "n": len(tiled.sited)} if kind.endswith("k_of_n") else {}
            layer = {**layer, "kind": "fused", "quantity": kind, **extra}
        layers.append(layer)
        show_progress("coverage: layers", band + 1, len(tiled.layers), started, sys.stderr)
    return layers


def _fused_files(out: Path, fused: dict, altitudes: list, k_of_n: tuple, where: dict) -> list[dict]:
    """Write the fused layers (per flight level, then the lowest heights over all levels); describe them."""
    k, n = k_of_n
    layers = []
    for i, altitude in enumerate(altitudes):
        for quantity in FUSED_QUANTITIES + (() if k is None else FUSED_K_QUANTITIES):
            grid = fused[quantity][i].astype(np.float32)
            layer = _layer(out, "fused", altitude, quantity, grid, where)
            extra = {"k": k, "n": n} if quantity.endswith("k_of_n") else {}
            layers.append({**layer, "kind": "fused", "quantity": quantity, **extra})
    for quantity in FUSED_HEIGHTS:
        layer = _layer(out, "fused", None, quantity, fused[f"{quantity}_m"].astype(np.float32), where)
        layers.append({**layer, "kind": "fused", "quantity": quantity})
    return layers


def _hillshade(dem: np.ndarray, cell: float) -> np.ndarray:
    """Lambertian hillshade (sun from the north-west, 45 degrees up), 0..1."""
    gy, gx = np.gradient(dem, cell)
    normal = np.stack([-gx, gy, np.ones_like(dem)])
    normal /= np.linalg.norm(normal, axis=0)
    sun = np.array(
        [
            -math.cos(math.radians(45)) * math.sin(math.radians(45)),
            math.cos(math.radians(45)) ** 2,
            math.sin(math.radians(45)),
        ]
    )
    return np.clip(np.tensordot(sun, normal, axes=1), 0.0, 1.0)


def _stem(sensor: str, altitude, kind: str) -> str:
    """File name of a layer without suffix: ``<sensor>_<kind>[_<altitude>m]``."""
    return f"{sensor}_{kind}" + ("" if altitude is None else f"_{altitude:g}m")


def _fresnel_sensors(sited: dict, scenario) -> list[str]:
    """The sited sensors whose links get a Fresnel clearance layer (RF and radar)."""
    return [name for name in sited if scenario.sensors[name].modality in FRESNEL_MODALITIES]


def _layer_files(sensors, altitudes, radio_sensors, k, fresnel_sensors=()) -> list[str]:
    """Every file name the layers of a site will have (checked before the work)."""
    layers = [(name, None, "min_altitude") for name in sensors]
    layers += [(name, a, "fresnel_clearance") for name in fresnel_sensors for a in altitudes]
    layers += [(name, a, kind) for name in sensors for a in altitudes for kind in SENSOR_KINDS]
    layers += [(name, a, kind) for name in radio_sensors for a in altitudes for kind, _ in RADIO_KINDS]
    fused = FUSED_QUANTITIES + (() if k is None else FUSED_K_QUANTITIES)
    layers += [("fused", a, quantity) for a in altitudes for quantity in fused]
    layers += [("fused", None, quantity) for quantity in FUSED_HEIGHTS]
    names = ["coverage.json", *VECTOR_FILES]
    for sensor, altitude, kind in layers:
        suffixes = (".tif", ".png") + ((".geojson",) if kind in GEOJSON_KINDS else ())
        names += [_stem(sensor, altitude, kind) + suffix for suffix in suffixes]
    return names


def _layer(out: Path, sensor: str, altitude, kind: str, grid, where: dict) -> dict:
    """Write one layer (GeoTIFF, PNG and, for a detected layer, GeoJSON) and describe it for coverage.json."""
    stem = _stem(sensor, altitude, kind)
    tif, png = inside(out, f"{stem}.tif"), inside(out, f"{stem}.png")
    title = f"{sensor}: {kind}" + ("" if altitude is None else f" at {altitude:g} m AGL")
    every_value, unit = kind in VALUE_KINDS, UNITS.get(kind, "")
    write_geotiff(tif, grid, where, title, unit or BAND_UNITS.get(kind, ""))
    where["maps"].write(png, grid, title, _legend(kind, every_value, unit))
    covered = np.isfinite(grid) if kind in VALUE_KINDS else np.nan_to_num(grid) > 0
    layer = {
        "sensor": sensor,
        "altitude_m": altitude,
        "kind": kind,
        "path": tif.name,
        "png": png.name,
        "area_km2": float(covered.sum() * where["cell_km2"]),
    }
    if kind in GEOJSON_KINDS:
        geojson = inside(out, f"{stem}.geojson")
        native = covered_polygons(covered, where["transform"])
        properties = {"sensor": sensor, "altitude_m": altitude, "kind": kind}
        write_geojson(geojson, to_wgs84(native, where["crs"]), properties)
        where["vectors"].append((stem, native, properties))
        layer["geojson"] = geojson.name
    return layer


def _legend(kind: str, every_value: bool, unit: str) -> dict:
    """How a layer's map shows it: a colour scale with its unit, Pd from PD_SHOWN up, or a yes/no patch."""
    if kind.startswith("pd"):
        return {"scale": f"Pd (cells at {PD_SHOWN:g} or more)", "low": PD_SHOWN, "high": 1.0}
    if kind == "fresnel_clearance":
        return {"scale": "clearance / r1 (0.6 and up: free space)", "low": 0.0, "high": 1.0}
    if every_value or kind.endswith("count"):
        return {"scale": unit, "low": None, "high": None}
    return {"patch": BAND_UNITS.get(kind, "1 = yes").split("= ", 1)[-1]}


def _write_vectors(out: Path, where: dict) -> dict:
    """Every vector layer in one GeoPackage (the DEM's CRS) and one KML (WGS 84); their names."""
    vectors = where["vectors"]
    if not vectors:
        return {}
    write_geopackage(inside(out, VECTOR_FILES[0]), vectors, where["crs"])
    write_kml(inside(out, VECTOR_FILES[1]), [(name, to_wgs84(g, where["crs"])) for name, g, _ in vectors])
    return {"geopackage": VECTOR_FILES[0], "kml": VECTOR_FILES[1]}


def area_text(km2: float) -> str:
    """An area with three significant digits, in m^2 below a hectare and in km^2 above (0 as 0 m^2)."""
    if km2 < 0.01:
        return f"{float(f'{km2 * 1e6:.3g}'):,.0f} m^2"
    return f"{float(f'{km2:.3g}'):,g} km^2"


def render_text(result: dict) -> str:
    """Each sensor's range and the area it covers per flight level."""
    lines = [f"coverage of {result['site']} ({result['crs']}, {result['cell_m']:g} m cells): {result['out']}"]
    for layer in result["layers"]:
        if layer["kind"] == "detected" or layer.get("quantity") == "detected":
            lines.append(
                f"  {layer['sensor']:<10} detected at {layer['altitude_m']:g} m AGL: {area_text(layer['area_km2'])}"
            )
        elif layer["kind"] == "detected_multipath":
            lines.append(
                f"  {layer['sensor']:<10} detected with multipath at {layer['altitude_m']:g} m AGL: "
                f"{area_text(layer['area_km2'])} (radio map)"
            )
        elif layer.get("quantity") == "k_of_n":
            what = f"{layer['k']} of {layer['n']}"
            lines.append(f"  {what:<10} detected at {layer['altitude_m']:g} m AGL: {area_text(layer['area_km2'])}")
    return "\n".join(lines)
