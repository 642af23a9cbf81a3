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
from pathlib import Path

import numpy as np

from csuas.base.cost import add_limit_arguments
from csuas.base.errors import ParameterError, raise_all
from csuas.base.fileio import atomic_path, prepare_output_dir, read_spec, write_text_atomic
from csuas.commands.coverage_radio import radio_map_layers, radio_map_settings
from csuas.core.coverage import POINTING

#: Keys a site may hold; and of each sensor table.
SITE_KEYS = ("dem", "scenario", "altitudes_agl_m", "fusion_k", "sensors", "radio_map")
SENSOR_KEYS = ("x", "y", "mast_m", *POINTING)
#: Layers of a radio map: (kind, key of :func:`csuas.commands.coverage_radio.radio_map_layers`'s grids).
RADIO_KINDS = (
    ("path_gain", "path_gain_db"),
    ("path_gain_error", "error_db"),
    ("detected_multipath", "detected"),
    ("pd_multipath", "pd"),
)
#: Layers whose every finite value is shown and counted as covered (the others: values above 0).
VALUE_KINDS = ("min_altitude", "path_gain", "path_gain_error")
#: Colour-bar labels of the layers with a scale.
UNITS = {
    "pd": "Pd",
    "pd_multipath": "Pd",
    "min_altitude": "m above the terrain",
    "path_gain": "path gain [dB]",
    "path_gain_error": "bound [dB]",
    "count": "sensors",
}
#: The embedded demo terrain: cells, cell size [m], origin of its transform and CRS.
DEMO = {"cells": 400, "cell_m": 25.0, "origin": (500_000.0, 5_000_000.0), "crs": "EPSG:32633"}


def add_arguments(parser):
    """Declare the options of ``csuas coverage``."""
    parser.add_argument("site", help="site TOML file, or an embedded site (demo)")
    parser.add_argument("--out", required=True, help="output folder (coverage.json, GeoTIFF and PNG layers)")
    add_limit_arguments(parser)


def _load_dem(site: dict, site_path):
    """(heights, transform, crs, cell size) of the site's DEM or the demo terrain."""
    from rasterio.transform import from_origin

    from csuas.core.terrain import gaussian_hills

    if "dem" not in site:
        x0, y0 = DEMO["origin"]
        top = y0 + DEMO["cells"] * DEMO["cell_m"]
        return (
            gaussian_hills(DEMO["cells"], DEMO["cell_m"]),
            from_origin(x0, top, DEMO["cell_m"], DEMO["cell_m"]),
            DEMO["crs"],
            DEMO["cell_m"],
        )
    import rasterio

    with rasterio.open(_dem_path(site, site_path)) as src:
        dem = src.read(1, masked=True).astype(float)
        transform, crs = src.transform, src.crs
    if crs is None or not crs.is_projected:
        raise ParameterError("dem", str(site["dem"]), "a GeoTIFF in a projected CRS (metres)")
    if transform.b or transform.d:
        raise ParameterError("dem", str(site["dem"]), "a GeoTIFF without rotation (rows along the CRS's x axis)")
    if abs(abs(transform.a) - abs(transform.e)) > 1e-6 * abs(transform.a):
        raise ParameterError("dem", str(site["dem"]), "square cells")
    dem, transform = _north_up(dem, transform)
    if np.ma.is_masked(dem):  # nodata holes: the lowest valid height, so they hide nothing
        dem = dem.filled(float(dem.min()))
    return np.asarray(dem), transform, str(crs), abs(transform.a)


def _dem_path(site: dict, site_path) -> Path:
    """The site's DEM file, relative to the site file's folder; a ParameterError naming ``dem`` if it is none."""
    path = Path(site["dem"])
    if not path.is_absolute() and site_path is not None:
        path = Path(site_path).parent / path
    if not path.is_file():
        raise ParameterError("dem", str(site["dem"]), "a GeoTIFF file")
    return path


def _dem_cells(site: dict, site_path) -> tuple[int, int]:
    """Rows and columns of the site's DEM (the demo terrain's without one), read from its header alone."""
    import rasterio
    from rasterio.errors import RasterioIOError

    if "dem" not in site:
        return DEMO["cells"], DEMO["cells"]
    path = _dem_path(site, site_path)
    try:
        with rasterio.open(path) as src:
            return src.height, src.width
    except RasterioIOError:
        raise ParameterError("dem", str(site["dem"]), "a GeoTIFF file that GDAL reads") from None


def _check_cost(site: dict, site_path, radio, args) -> None:
    """Estimate the run from the DEM's header, the sensors and the levels; refuse it above the limits."""
    from csuas.base.cost import check_limits
    from csuas.core.coverage_cost import coverage_estimate

    levels = len(site.get("altitudes_agl_m", [30.0, 120.0]))
    maps = 0 if radio is None else len(radio["sensors"])
    samples = 0 if radio is None else int(radio["samples"])
    cells = _dem_cells(site, site_path)
    estimate = coverage_estimate(cells, len(site["sensors"]), levels, "fusion_k" in site, maps, samples)
    check_limits(estimate, args, "coverage")


def _north_up(dem, transform):
    """The grid flipped, if need be, so that rows run north to south and columns west to east (bearings)."""
    from rasterio.transform import Affine

    if transform.e > 0:  # rows run north: the last row is the northern one
        dem, transform = dem[::-1], transform @ Affine.translation(0, dem.shape[0]) @ Affine.scale(1, -1)
    if transform.a < 0:  # columns run west
        dem, transform = dem[:, ::-1], transform @ Affine.translation(dem.shape[1], 0) @ Affine.scale(-1, 1)
    return dem, transform


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _validate(site: dict, scenario) -> list:
    from csuas.core.checks import require

    errors = [
        ParameterError(key, site[key], "a site key: " + ", ".join(SITE_KEYS)) for key in site if key not in SITE_KEYS
    ]
    altitudes = site.get("altitudes_agl_m", [30.0, 120.0])
    if (
        not isinstance(altitudes, list)
        or not altitudes
        or not all(isinstance(a, (int, float)) and 0.0 <= a <= 10_000.0 for a in altitudes)
    ):
        errors.append(ParameterError("altitudes_agl_m", altitudes, "a list of heights 0 to 10000 m above the terrain"))
    sensors = site.get("sensors", {})
    if not sensors:
        errors.append(ParameterError("sensors", sensors, "at least one [sensors.NAME] of the scenario"))
    for name, table in sensors.items():
        if name not in scenario.sensors:
            errors.append(
                ParameterError(f"sensors.{name}", name, "a sensor of the scenario: " + ", ".join(scenario.sensors))
            )
        for key in table:
            if key not in SENSOR_KEYS:
                errors.append(ParameterError(f"sensors.{name}.{key}", table[key], ", ".join(SENSOR_KEYS)))
        for key in ("x", "y"):
            if not isinstance(table.get(key), (int, float)):
                errors.append(
                    ParameterError(f"sensors.{name}.{key}", table.get(key), "a coordinate in the DEM's CRS [m]")
                )
        mast = table.get("mast_m", 10.0)
        if not (isinstance(mast, (int, float)) and 0.0 <= mast <= 1000.0):
            errors.append(ParameterError(f"sensors.{name}.mast_m", mast, "0 to 1000 m"))
        for key, (_, bounds) in POINTING.items():
            if key not in table:
                continue
            if not _is_number(table[key]):
                errors.append(ParameterError(f"sensors.{name}.{key}", table[key], "a number"))
                continue
            try:
                require(f"sensors.{name}.{key}", table[key], **bounds)
            except ParameterError as exc:
                errors.append(exc)
        low, high = (table.get(key, POINTING[key][0]) for key in ("elevation_min_deg", "elevation_max_deg"))
        if _is_number(low) and _is_number(high) and not low < high:
            errors.append(
                ParameterError(f"sensors.{name}.elevation_max_deg", high, f"above elevation_min_deg = {low:g}")
            )
    if "fusion_k" in site:
        k = site["fusion_k"]
        if not (isinstance(k, int) and not isinstance(k, bool) and 1 <= k <= max(len(sensors), 1)):
            errors.append(
                ParameterError("fusion_k", k, f"a whole number 1 to {len(sensors)} (the number of sited sensors)")
            )
    return errors


def run(args) -> dict:
    """Compute and write every layer of the site."""
    from csuas.core.coverage import SitedSensor, fused_layers, sensor_layers
    from csuas.core.scenario import load_scenario
    from csuas.defaults import site_path

    source = Path(args.site)
    site = read_spec(args.site, site_path, "site")
    scenario = load_scenario(site.get("scenario", "default"))
    radio, radio_errors = radio_map_settings(site, scenario)
    raise_all(_validate(site, scenario) + radio_errors)
    _check_cost(site, source if source.is_file() else None, radio, args)  # before the DEM is read
    dem, transform, crs, cell = _load_dem(site, source if source.is_file() else None)
    inverse = ~transform
    sited, outside = {}, []
    for name, table in site["sensors"].items():
        col, row = inverse @ (float(table["x"]), float(table["y"]))
        col, row = col - 0.5, row - 0.5  # cell centres at half-integers of the transform
        if not (0.0 <= row <= dem.shape[0] - 1 and 0.0 <= col <= dem.shape[1] - 1):
            outside.append(ParameterError(f"sensors.{name}", (table["x"], table["y"]), "a position inside the DEM"))
        pointing = {key: float(table.get(key, default)) for key, (default, _) in POINTING.items()}
        sited[name] = SitedSensor(name, row, col, float(table.get("mast_m", 10.0)), **pointing)
    raise_all(outside)
    altitudes = [float(a) for a in site.get("altitudes_agl_m", [30.0, 120.0])]
    k = site.get("fusion_k")
    out = prepare_output_dir(args.out)
    layers, per_sensor = [], {}
    for name, placed in sited.items():
        print(f"csuas coverage: {name} ...", file=sys.stderr, flush=True)
        per_sensor[name] = sensor_layers(dem, cell, scenario, placed, altitudes)
    fused = fused_layers(per_sensor, k)
    radio_maps = {} if radio is None else radio_map_layers(dem, cell, scenario, sited, altitudes, per_sensor, radio)
    hillshade = _hillshade(dem, cell)
    where = {"transform": transform, "crs": crs, "hillshade": hillshade, "sited": sited, "cell_km2": cell * cell / 1e6}
    for name, grids in per_sensor.items():
        for i, altitude in enumerate(altitudes):
            for kind in ("visible", "detected", "pd"):
                grid = grids[kind][i].astype(np.float32)
                if kind == "visible":
                    grid[~grids["traced"]] = np.nan  # beyond the mapped reach: not traced
                layers.append(_layer(out, name, altitude, kind, grid, where))
        min_alt = grids["min_altitude_m"].astype(np.float32)
        layers.append(_layer(out, name, None, "min_altitude", min_alt, where))
    for name, grids in radio_maps.items():
        for i, altitude in enumerate(altitudes):
            for kind, key in RADIO_KINDS:
                layers.append(_layer(out, name, altitude, kind, grids[key][i].astype(np.float32), where))
    quantities = ("count", "detected", "pd") + (() if k is None else ("k_of_n", "pd_k_of_n"))
    for i, altitude in enumerate(altitudes):
        for quantity in quantities:
            grid = fused[quantity][i].astype(np.float32)
            layer = _layer(out, "fused", altitude, quantity, grid, where)
            extra = {"k": k, "n": len(sited)} if quantity.endswith("k_of_n") else {}
            layers.append({**layer, "kind": "fused", "quantity": quantity, **extra})
    summary = {
        "site": str(args.site),
        "crs": crs,
        "cell_m": cell,
        "altitudes_agl_m": altitudes,
        "fusion_k": k,
        "sensors": {
            n: {
                "range_m": g["range_m"],
                "reach_m": None if math.isinf(g["reach_m"]) else g["reach_m"],
                "row": sited[n].row,
                "col": sited[n].col,
                **{key: getattr(sited[n], key) for key in POINTING},
            }
            for n, g in per_sensor.items()
        },
        "layers": layers,
    }
    if radio is not None:
        settings = {key: radio[key] for key in ("ground", "step", "max_depth", "seed", "accuracy_db")}
        summary["radio_maps"] = {"settings": settings, "maps": {n: g["maps"] for n, g in radio_maps.items()}}
    write_text_atomic(out / "coverage.json", json.dumps(summary, indent=1))
    summary["out"] = str(out)
    return summary


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


def _layer(out: Path, sensor: str, altitude, kind: str, grid, where: dict) -> dict:
    """Write one layer (GeoTIFF, PNG and, for a detected layer, GeoJSON) and describe it for coverage.json."""
    import rasterio

    stem = f"{sensor}_{kind}" + ("" if altitude is None else f"_{altitude:g}m")
    tif, png = out / f"{stem}.tif", out / f"{stem}.png"
    profile = {
        "driver": "GTiff",
        "height": grid.shape[0],
        "width": grid.shape[1],
        "count": 1,
        "dtype": "float32",
        "crs": where["crs"],
        "transform": where["transform"],
        "nodata": float("nan"),
    }
    with atomic_path(tif) as tmp:
        with rasterio.open(tmp, "w", **profile) as dst:
            dst.write(grid, 1)
    title = f"{sensor}: {kind}" + ("" if altitude is None else f" at {altitude:g} m AGL")
    every_value, unit = kind in VALUE_KINDS, UNITS.get(kind, "")
    _map(png, grid, where["hillshade"], title, where["sited"], every_value=every_value, unit=unit)
    covered = np.isfinite(grid) if kind in VALUE_KINDS else np.nan_to_num(grid) > 0
    layer = {
        "sensor": sensor,
        "altitude_m": altitude,
        "kind": kind,
        "path": tif.name,
        "png": png.name,
        "area_km2": float(covered.sum() * where["cell_km2"]),
    }
    if kind in ("detected", "k_of_n", "detected_multipath"):
        geojson = out / f"{stem}.geojson"
        write_text_atomic(
            geojson,
            json.dumps(
                _polygons(
                    covered, where["transform"], where["crs"], {"sensor": sensor, "altitude_m": altitude, "kind": kind}
                )
            ),
        )
        layer["geojson"] = geojson.name
    return layer


def _polygons(covered: np.ndarray, transform, crs: str, properties: dict) -> dict:
    """GeoJSON FeatureCollection of the covered cells: one polygon per 4-connected patch, in the DEM's CRS."""
    from rasterio.features import shapes

    features = [
        {"type": "Feature", "geometry": geometry, "properties": properties}
        for geometry, _ in shapes(covered.astype(np.uint8), mask=covered, transform=transform)
    ]
    return {
        "type": "FeatureCollection",
        "crs": {"type": "name", "properties": {"name": crs}},
        "features": features,
    }


def _map(path: Path, grid, hillshade, title: str, sited, every_value: bool = False, unit: str = "") -> None:
    from csuas.base.plots import _pyplot

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 5.0))
    ax.imshow(hillshade, cmap="gray", vmin=0, vmax=1)
    shown = np.ma.masked_where(~np.isfinite(grid) | (~every_value & (grid <= 0)), grid)
    image = ax.imshow(shown, cmap="viridis", alpha=0.6)
    for name, s in sited.items():
        ax.plot(s.col, s.row, "r^", ms=7)
        ax.annotate(name, (s.col, s.row), color="red", fontsize=8, xytext=(4, 4), textcoords="offset points")
    ax.set_title(title, fontsize=10)
    ax.set_xticks([])
    ax.set_yticks([])
    if np.unique(grid[np.isfinite(grid)]).size > 2:  # yes/no layers need no scale
        fig.colorbar(image, ax=ax, fraction=0.046, label=unit)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=90, bbox_inches="tight", format="png")
    plt.close(fig)


def render_text(result: dict) -> str:
    """Each sensor's range and the area it covers per flight level."""
    lines = [f"coverage of {result['site']} ({result['crs']}, {result['cell_m']:g} m cells): {result['out']}"]
    for layer in result["layers"]:
        if layer["kind"] == "detected" or layer.get("quantity") == "detected":
            lines.append(
                f"  {layer['sensor']:<10} detected at {layer['altitude_m']:g} m AGL: {layer['area_km2']:.2f} km^2"
            )
        elif layer["kind"] == "detected_multipath":
            lines.append(
                f"  {layer['sensor']:<10} detected with multipath at {layer['altitude_m']:g} m AGL: "
                f"{layer['area_km2']:.2f} km^2 (radio map)"
            )
        elif layer.get("quantity") == "k_of_n":
            what = f"{layer['k']} of {layer['n']}"
            lines.append(f"  {what:<10} detected at {layer['altitude_m']:g} m AGL: {layer['area_km2']:.2f} km^2")
    return "\n".join(lines)
