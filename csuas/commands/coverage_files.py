"""The GIS files of ``csuas coverage``: layers GIS users open as they are (docs/coverage.md).

* GeoTIFF: tiled (256 x 256), DEFLATE-compressed with the floating-point predictor, NaN as nodata,
  the band's description and unit set (GDAL's band metadata, ``gdalinfo`` shows both).
* GeoJSON: RFC 7946 (IETF, 2016): longitude and latitude on WGS 84, no ``crs`` member (Section 4);
  polygons reprojected from the DEM's CRS with rasterio (PROJ), vertex by vertex.
* GeoPackage (OGC 12-128r18): one file holding every vector layer in the DEM's own CRS, written with
  pyogrio (GDAL/OGR); one table per layer.
* KML (OGC 07-147r2): every vector layer as a folder of polygons on WGS 84, for a quick look in a
  virtual globe.
* PNG maps: over the DEM's hillshade, axes in the DEM's CRS [km], a scale bar, a north arrow, the
  sensors, and a legend: a colour bar with its unit, or a patch naming what a yes/no layer marks.
  Each map is drawn once, cropped to its tight bounding box (``savefig(bbox_inches="tight")`` draws it
  twice), and :class:`MapWriter` writes them in worker processes while the caller goes on.
"""

from __future__ import annotations

import json
import os
from collections import namedtuple
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np

from csuas.base.fileio import atomic_path, write_text_atomic
from csuas.base.plots import _pyplot

#: GeoTIFF creation options (GDAL's GTiff driver).
GEOTIFF_OPTIONS = {"compress": "deflate", "predictor": 3, "tiled": True, "blockxsize": 256, "blockysize": 256}
#: Cloud Optimised GeoTIFF creation options (GDAL's COG driver) of the layers written by tiles.
COG_OPTIONS = {"compress": "DEFLATE", "predictor": "YES", "blocksize": 256, "overview_resampling": "NEAREST"}
#: GDAL's block cache while a COG is mosaicked [MB]: bounds the memory of the process that writes them.
COG_CACHE_MB = 256
#: GeoPackage version written: 1.2 opens without a warning in GDAL 3.6 and later, 1.4 warns before 3.12.
GEOPACKAGE_VERSION = "1.2"
#: Geographic CRS of GeoJSON (RFC 7946 Section 4) and KML.
WGS84 = "EPSG:4326"
#: Resolution of the PNG maps [dots per inch] and the margin around their tight bounding box [in]
#: (matplotlib's ``savefig.pad_inches``).
MAP_DPI = 90
MAP_PAD_INCHES = 0.1
#: Most processes writing PNG maps at once.
MAP_WORKERS = 4


def write_geotiff(path: Path, grid: np.ndarray, where: dict, description: str, unit: str) -> None:
    """One float32 band with its description and unit, tiled and compressed; NaN is nodata."""
    import rasterio

    profile = {
        "driver": "GTiff",
        "height": grid.shape[0],
        "width": grid.shape[1],
        "count": 1,
        "dtype": "float32",
        "crs": where["crs"],
        "transform": where["transform"],
        "nodata": float("nan"),
        **GEOTIFF_OPTIONS,
    }
    with atomic_path(path) as tmp:
        with rasterio.open(tmp, "w", **profile) as dst:
            dst.write(grid.astype(np.float32), 1)
            dst.set_band_description(1, description)
            dst.units = (unit,)


def covered_polygons(covered: np.ndarray, transform) -> list[dict]:
    """GeoJSON geometries of the covered cells in the grid's CRS: one polygon per 4-connected patch."""
    from rasterio.features import shapes

    return [geometry for geometry, _ in shapes(covered.astype(np.uint8), mask=covered, transform=transform)]


def to_wgs84(geometries: list[dict], crs: str) -> list[dict]:
    """Geometries reprojected from ``crs`` to longitude and latitude on WGS 84 [deg]."""
    from rasterio.warp import transform_geom

    return [transform_geom(crs, WGS84, geometry) for geometry in geometries]


def write_geojson(path: Path, geometries_wgs84: list[dict], properties: dict) -> None:
    """An RFC 7946 FeatureCollection (no ``crs`` member: WGS 84 longitude and latitude by definition)."""
    features = [{"type": "Feature", "geometry": g, "properties": properties} for g in geometries_wgs84]
    write_text_atomic(path, json.dumps({"type": "FeatureCollection", "features": features}))


def write_geopackage(path: Path, layers: list[tuple[str, list[dict], dict]], crs: str) -> None:
    """Every vector layer, ``(name, geometries in crs, properties)``, as a table of one GeoPackage."""
    import pyogrio.raw
    import shapely.geometry

    with atomic_path(path) as tmp:
        tmp.unlink(missing_ok=True)  # GDAL creates the file itself
        for index, (name, geometries, properties) in enumerate(layers):
            wkb = np.array([shapely.geometry.shape(g).wkb for g in geometries], dtype=object)
            fields = list(properties)
            values = [np.array([properties[k]] * len(geometries), dtype=_field_type(properties[k])) for k in fields]
            pyogrio.raw.write(
                str(tmp),
                wkb,
                values,
                fields,
                layer=name,
                driver="GPKG",
                crs=crs,
                geometry_type="Polygon",
                append=index > 0,
                dataset_options=None if index else {"VERSION": GEOPACKAGE_VERSION},
            )


def _field_type(value) -> type:
    return object if isinstance(value, str) or value is None else float


def write_kml(path: Path, layers: list[tuple[str, list[dict]]]) -> None:
    """Every vector layer, ``(name, geometries on WGS 84)``, as a folder of KML polygons."""
    folders = []
    for name, geometries in layers:
        marks = "".join(f"<Placemark><name>{escape(name)}</name>{_kml_polygon(g)}</Placemark>" for g in geometries)
        folders.append(f"<Folder><name>{escape(name)}</name>{marks}</Folder>")
    text = (
        '<?xml version="1.0" encoding="UTF-8"?>\n<kml xmlns="http://www.opengis.net/kml/2.2"><Document>'
        f"<name>csuas coverage</name>{''.join(folders)}</Document></kml>\n"
    )
    write_text_atomic(path, text)


def _kml_ring(ring) -> str:
    return "<LinearRing><coordinates>" + " ".join(f"{x:.7f},{y:.7f}" for x, y in ring) + "</coordinates></LinearRing>"


def _kml_polygon(geometry: dict) -> str:
    outer, *holes = geometry["coordinates"]
    inner = "".join(f"<innerBoundaryIs>{_kml_ring(h)}</innerBoundaryIs>" for h in holes)
    return f"<Polygon><outerBoundaryIs>{_kml_ring(outer)}</outerBoundaryIs>{inner}</Polygon>"


def _nice_length_m(span_m: float) -> float:
    """A round scale-bar length about a fifth of ``span_m`` [m]: 1, 2 or 5 times a power of ten."""
    target = span_m / 5.0
    power = 10.0 ** np.floor(np.log10(target))
    return float(max(m * power for m in (1.0, 2.0, 5.0) if m * power <= target))


def write_map_png(path: Path, grid: np.ndarray, where: dict, title: str, legend: dict) -> None:
    """A layer over the hillshade with CRS axes [km], a scale bar, a north arrow, the sensors and a legend.

    ``legend`` is ``{"scale": label, "low": v, "high": v}`` (values from ``low`` up on a colour bar; None:
    every finite value) or ``{"patch": what}`` (cells above 0 in one colour, named in the legend).
    """
    from matplotlib.patches import Patch
    from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

    plt = _pyplot()
    transform, rows, cols = where["transform"], grid.shape[0], grid.shape[1]
    west, north = transform @ (0, 0)
    east, south = transform @ (cols, rows)
    extent = (west / 1e3, east / 1e3, south / 1e3, north / 1e3)
    fig, ax = plt.subplots(figsize=(6.4, 5.6), dpi=MAP_DPI)
    ax.imshow(where["hillshade"], cmap="gray", vmin=0, vmax=1, extent=extent)
    finite = np.isfinite(grid)
    if "patch" in legend:
        shown = np.ma.masked_where(~finite | (np.nan_to_num(grid) <= 0), grid)
        ax.imshow(shown, cmap="winter", vmin=0, vmax=1, alpha=0.55, extent=extent)
        ax.legend(
            handles=[Patch(color=plt.get_cmap("winter")(1.0), alpha=0.55, label=legend["patch"])], loc="lower left"
        )
    else:
        low = legend["low"]
        shown = np.ma.masked_where(
            ~finite | (np.nan_to_num(grid, nan=-np.inf) < (low if low is not None else -np.inf)), grid
        )
        image = ax.imshow(shown, cmap="viridis", vmin=low, vmax=legend["high"], alpha=0.7, extent=extent)
        fig.colorbar(image, ax=ax, fraction=0.046, label=legend["scale"])
    for name, sensor in where["sited"].items():
        x, y = transform @ (sensor.col + 0.5, sensor.row + 0.5)
        ax.plot(x / 1e3, y / 1e3, "r^", ms=7)
        ax.annotate(name, (x / 1e3, y / 1e3), color="red", fontsize=8, xytext=(4, 4), textcoords="offset points")
    length = _nice_length_m(abs(east - west))
    label = f"{length / 1e3:g} km" if length >= 1e3 else f"{length:g} m"
    bar = AnchoredSizeBar(
        ax.transData, length / 1e3, label, "lower right", frameon=True, size_vertical=abs(north - south) / 250e3
    )
    ax.add_artist(bar)
    ax.annotate(
        "N",
        xy=(0.95, 0.95),
        xytext=(0.95, 0.82),
        xycoords="axes fraction",
        ha="center",
        fontsize=10,
        arrowprops={"arrowstyle": "-|>", "color": "k"},
    )
    ax.set_xlabel(f"easting [km] ({where['crs']})")
    ax.set_ylabel("northing [km]")
    ax.set_title(title, fontsize=10)
    with atomic_path(path) as tmp:
        _save_tight(fig, tmp)
    plt.close(fig)


def _save_tight(fig, path: Path) -> None:
    """The figure as a PNG cropped to its tight bounding box plus ``MAP_PAD_INCHES``, drawn once.

    ``savefig(bbox_inches="tight")`` draws the figure twice, the first time only to find the box; the box
    is found here from the artists' extents without drawing (the axes' aspect applied as a draw would)
    and handed to ``savefig``, which then draws once.
    """
    box = fig.get_tightbbox(fig.canvas.get_renderer()).padded(MAP_PAD_INCHES)
    fig.savefig(path, dpi=MAP_DPI, bbox_inches=box, format="png")


SensorMark = namedtuple("SensorMark", "row col")
"""A sensor on a map: its fractional cell (row, col)."""


class MapWriter:
    """Writes PNG maps (:func:`write_map_png`) in a pool of spawned processes; :meth:`close` waits for them.

    Spawned, not forked: the caller may hold Dr.Jit's threads (Sionna RT), which a fork would copy
    mid-state. Each worker receives the map's grid and the static parts of ``where`` once (hillshade,
    transform, CRS, sensors). With one worker, or none to spare, maps are written in the caller.

    Parameters
    ----------
    where : dict
        ``transform``, ``crs``, ``hillshade`` and ``sited`` of the maps.
    workers : int, optional
        Processes (default: the CPUs this process may use, at most ``MAP_WORKERS``).
    """

    def __init__(self, where: dict, workers: int | None = None):
        self.where = {key: where[key] for key in ("transform", "crs", "hillshade")}
        # the sensors' cells alone: a worker then imports no more than this module (0.7 CPU-s, not 1.4)
        self.where["sited"] = {name: SensorMark(s.row, s.col) for name, s in where["sited"].items()}
        count = workers if workers is not None else min(len(os.sched_getaffinity(0)), MAP_WORKERS)
        self._pool = None
        if count > 1:
            self._pool = ProcessPoolExecutor(
                count, mp_context=get_context("spawn"), initializer=_set_map_frame, initargs=(self.where,)
            )
        self._futures: list = []

    def write(self, path: Path, grid: np.ndarray, title: str, legend: dict) -> None:
        """Write one map now (no pool) or queue it."""
        if self._pool is None:
            write_map_png(path, grid, self.where, title, legend)
        else:
            self._futures.append(self._pool.submit(_write_queued_map, path, grid, title, legend))

    def close(self) -> None:
        """Wait for every queued map; the first worker's error is raised here."""
        if self._pool is None:
            return
        try:
            for future in self._futures:
                future.result()
        finally:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None

    def __enter__(self) -> MapWriter:
        return self

    def __exit__(self, kind, error, trace) -> None:
        if kind is None:
            self.close()
        elif self._pool is not None:  # the caller failed: drop the maps not started, wait for the rest
            self._pool.shutdown(cancel_futures=True)
            self._pool = None


_map_frame: dict = {}


def _set_map_frame(where: dict) -> None:
    """A map worker's start: keep the maps' static parts."""
    _map_frame.update(where)


def _write_queued_map(path: Path, grid: np.ndarray, title: str, legend: dict) -> None:
    write_map_png(path, grid, _map_frame, title, legend)


def write_cog(path: Path, mosaic: Path, sources: list[tuple[Path, int, tuple]], grid: dict, text: tuple) -> None:
    """One float32 layer mosaicked from tiles' bands into a Cloud Optimised GeoTIFF (GDAL's COG driver).

    Parameters
    ----------
    path : Path
        The COG, written atomically.
    mosaic : Path
        The GDAL VRT mosaic of the tiles written on the way (kept), in the tiles' folder.
    sources : list of (Path, int, (row0, row1, col0, col1))
        Each tile's GeoTIFF (in ``mosaic``'s folder), the layer's band in it, and the tile's cells.
    grid : dict
        ``shape`` (rows, cols), ``transform`` and ``crs`` of the whole layer.
    text : (str, str)
        The band's description and unit.
    """
    import rasterio
    import rasterio.shutil
    from rasterio.crs import CRS

    rows, cols = grid["shape"]
    description, unit = text
    band = [
        f'<SimpleSource><SourceFilename relativeToVRT="1">{escape(tile.name)}'
        f'</SourceFilename><SourceBand>{index}</SourceBand><SrcRect xOff="0" yOff="0" xSize="{c1 - c0}" '
        f'ySize="{r1 - r0}"/><DstRect xOff="{c0}" yOff="{r0}" xSize="{c1 - c0}" ySize="{r1 - r0}"/></SimpleSource>'
        for tile, index, (r0, r1, c0, c1) in sources
    ]
    wkt = escape(CRS.from_user_input(grid["crs"]).to_wkt())
    vrt = (
        f'<VRTDataset rasterXSize="{cols}" rasterYSize="{rows}"><SRS>{wkt}</SRS>'
        f"<GeoTransform>{', '.join(repr(v) for v in grid['transform'].to_gdal())}</GeoTransform>"
        f'<VRTRasterBand dataType="Float32" band="1"><NoDataValue>nan</NoDataValue>'
        f"<Description>{escape(description)}</Description><UnitType>{escape(unit)}</UnitType>"
        + "".join(band)
        + "</VRTRasterBand></VRTDataset>"
    )
    write_text_atomic(mosaic, vrt)
    with atomic_path(path) as tmp:
        with rasterio.Env(GDAL_NUM_THREADS="1", GDAL_CACHEMAX=COG_CACHE_MB):  # GDAL's default: 5 % of the memory
            rasterio.shutil.copy(mosaic, tmp, driver="COG", **COG_OPTIONS)
