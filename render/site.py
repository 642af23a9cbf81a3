"""A coverage site's terrain and sited sensors, as the simulations read them (docs/coverage.md).

:func:`load_dem` reads the site's DEM (a GeoTIFF in a projected CRS, or in longitude and latitude reprojected
to its centre's UTM zone; turned north-up; nodata holes at the lowest valid height) or builds the embedded
demo terrain; :func:`validated_site` checks a site's table against its schema
(:mod:`csuas.render.site_schema`) and its sensors against the scenario; :func:`sensor_xy` places a sensor
given by ``x``/``y`` or ``lat``/``lon``. ``csuas coverage`` (which adds its radio map's checks), ``csuas
engage`` and the ``engage`` sweep job read sites through here.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from csuas.base.errors import InputErrors, ParameterError, raise_all
from csuas.base.paths import file_name_part
from csuas.base.schema import validate
from csuas.core.terrain import gaussian_hills
from csuas.render.site_schema import TAGS, SiteSchema

#: The embedded demo terrain: cells, cell size [m], origin of its transform and CRS.
DEMO = {"cells": 400, "cell_m": 25.0, "origin": (500_000.0, 5_000_000.0), "crs": "EPSG:32633"}


def load_dem(dem: str | None, site_path):
    """(heights, transform, crs, cell size) of the site's DEM (``dem``, relative to the site) or the demo terrain."""
    from rasterio.transform import from_origin

    if dem is None:
        x0, y0 = DEMO["origin"]
        top = y0 + DEMO["cells"] * DEMO["cell_m"]
        return (
            gaussian_hills(DEMO["cells"], DEMO["cell_m"]),
            from_origin(x0, top, DEMO["cell_m"], DEMO["cell_m"]),
            DEMO["crs"],
            DEMO["cell_m"],
        )
    import rasterio

    path = dem_path(dem, site_path)
    try:
        with rasterio.open(path) as src:
            heights = src.read(1, masked=True).astype(float)
            transform, crs = src.transform, src.crs
    except rasterio.errors.RasterioError as exc:
        raise ParameterError("dem", dem, f"a GeoTIFF file GDAL can read ({exc})") from None
    _check_dem(dem, heights, transform, crs)
    if crs.is_geographic:
        heights, transform, crs = _to_utm(heights, transform, crs)
    heights, transform = _north_up(heights, transform)
    if np.ma.is_masked(heights):  # nodata holes: the lowest valid height, so they hide nothing
        heights = heights.filled(float(heights.min()))
    return np.asarray(heights), transform, str(crs), abs(transform.a)


def _check_dem(dem: str, heights, transform, crs) -> None:
    """A DEM the coverage can use: projected, square cells without rotation, 2 x 2 cells or more, finite heights."""
    if crs is None or not (crs.is_projected or crs.is_geographic):
        raise ParameterError("dem", dem, "a GeoTIFF in a projected CRS (metres) or in longitude and latitude")
    if transform.b or transform.d:
        raise ParameterError("dem", dem, "a GeoTIFF without rotation (rows along the CRS's x axis)")
    if crs.is_projected and abs(abs(transform.a) - abs(transform.e)) > 1e-6 * abs(transform.a):
        raise ParameterError("dem", dem, "square cells")
    if min(heights.shape) < 2:
        rows, cols = heights.shape
        raise ParameterError("dem", dem, f"a grid of at least 2 x 2 cells (this one: {rows} x {cols})")
    valid = heights.compressed() if np.ma.is_masked(heights) else np.asarray(heights).ravel()
    if valid.size == 0 or not np.isfinite(valid).all():
        raise ParameterError("dem", dem, "finite heights [m] (nodata cells marked as the GeoTIFF's nodata)")


def utm_zone_crs(lon_deg: float, lat_deg: float):
    """The WGS 84 / UTM zone CRS of a point: zone floor((lon + 180) / 6) + 1, north (EPSG:326zz) or south (327zz).

    The regular 6-degree zones (the Norway and Svalbard exceptions are not applied; any zone serves a DEM of
    a few degrees). Returns a rasterio CRS.
    """
    from rasterio.crs import CRS

    zone = int((float(lon_deg) + 180.0) // 6.0) % 60 + 1
    return CRS.from_epsg((32600 if lat_deg >= 0 else 32700) + zone)


def _to_utm(heights, transform, crs):
    """A DEM in longitude and latitude reprojected to the UTM zone of its centre (:func:`utm_zone_crs`).

    GDAL's warper (``rasterio.warp.reproject``) with bilinear resampling, onto square cells of the size
    ``rasterio.warp.calculate_default_transform`` picks (about the source's spacing at the centre); cells
    outside the source's footprint (the corners of the rotated frame) and the source's nodata come out masked.
    """
    from rasterio.warp import Resampling, calculate_default_transform, reproject

    rows, cols = heights.shape
    (x0, y0), (x1, y1) = transform @ (0, 0), transform @ (cols, rows)
    west, east, south, north = min(x0, x1), max(x0, x1), min(y0, y1), max(y0, y1)
    utm = utm_zone_crs((west + east) / 2, (south + north) / 2)
    target, width, height = calculate_default_transform(
        crs, utm, cols, rows, left=west, bottom=south, right=east, top=north
    )
    grid = np.full((height, width), np.nan)
    reproject(
        np.ma.filled(heights.astype(float), np.nan),
        grid,
        src_transform=transform,
        src_crs=crs,
        src_nodata=np.nan,
        dst_transform=target,
        dst_crs=utm,
        dst_nodata=np.nan,
        resampling=Resampling.bilinear,
    )
    return np.ma.masked_invalid(grid), target, utm


def sensor_xy(table, crs) -> tuple[float, float]:
    """A sited sensor's position in the DEM's CRS: its ``x``, ``y``, or its ``lat``, ``lon`` (WGS 84) through PROJ."""
    if table.x is not None:
        return float(table.x), float(table.y)
    from pyproj import Transformer

    x, y = Transformer.from_crs("EPSG:4326", str(crs), always_xy=True).transform(float(table.lon), float(table.lat))
    return float(x), float(y)


def dem_path(dem: str, site_path) -> Path:
    """The site's DEM file, relative to the site file's folder; a ParameterError naming ``dem`` if it is none."""
    path = Path(dem)
    if not path.is_absolute() and site_path is not None:
        path = Path(site_path).parent / path
    if not path.is_file():
        raise ParameterError("dem", dem, "a GeoTIFF file")
    return path


def _north_up(dem, transform):
    """The grid flipped, if need be, so that rows run north to south and columns west to east (bearings)."""
    from rasterio.transform import Affine

    if transform.e > 0:  # rows run north: the last row is the northern one
        dem, transform = dem[::-1], transform @ Affine.translation(0, dem.shape[0]) @ Affine.scale(1, -1)
    if transform.a < 0:  # columns run west
        dem, transform = dem[:, ::-1], transform @ Affine.translation(dem.shape[1], 0) @ Affine.scale(-1, 1)
    return dem, transform


def scenario_errors(site: dict, scenario) -> list:
    """Sited sensors the scenario lacks, or whose names cannot name their layer files (the schema checks the types)."""
    sensors = site.get("sensors")
    if not isinstance(sensors, dict):
        return []
    allowed = "a sensor of the scenario: " + ", ".join(scenario.sensors)
    errors = []
    for name in sensors:
        try:
            file_name_part(name, "sensors")  # it names the sensor's layer files
        except ParameterError as exc:
            errors.append(exc)
            continue
        if name == "fused":
            errors.append(ParameterError("sensors", name, "a sensor name other than 'fused' (the fused layers' name)"))
        elif name not in scenario.sensors:
            errors.append(ParameterError(f"sensors.{name}", name, allowed))
    return errors


def validated_site(site: dict, scenario, extra_errors=()):
    """The site's schema model; every mistake of the file, of its sensors against ``scenario`` (None: the
    file alone) and ``extra_errors`` (a caller's checks beside, e.g. ``csuas coverage``'s radio map) at once."""
    errors = ([] if scenario is None else scenario_errors(site, scenario)) + list(extra_errors)
    try:
        model = validate(SiteSchema, site, tags=TAGS, context={"sensors": site.get("sensors")})
    except (ParameterError, InputErrors) as exc:
        raise_all(getattr(exc, "errors", [exc]) + errors)
    raise_all(errors)
    return model
