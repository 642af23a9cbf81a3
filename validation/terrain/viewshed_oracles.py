"""Independent references for the line of sight over terrain (:func:`csuas.core.terrain.viewshed`).

* :func:`gdal_viewshed`: GDAL's ``gdal_viewshed`` program (GDAL >= 3.1; the algorithm of Wang,
  Robinson & White, *Generating viewsheds without using sightlines*, PE&RS 66(1), 2000), run on the
  same DEM written as a GeoTIFF, with the same observer, target height and curvature. GDAL drops a
  point at distance d by ``cc d^2 / D`` with D the diameter of the CRS's ellipsoid (its semi-major
  axis), so the curvature coefficient that gives csuas's drop d^2 / (2 k R_E) is
  ``cc = a / (k R_E)``.
* :func:`exact_line_of_sight`: the sight line itself, sampled every ``EXACT_STEP_CELLS`` of a cell from
  the sensor's eye to the target, and where it crosses a grid line (the kinks of the bilinear terrain,
  where a crest can stand), over the bilinear terrain and the Earth's curvature; slow, exact up to
  its sampling inside cells, and sharing nothing with the ray method but the bilinear terrain.
* A cell *grazes* when its exact sight line passes within one cell's relief (the largest height step
  between neighbouring cells) of the terrain: two methods that sample the terrain up to a cell apart
  may disagree there, and nowhere else.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from csuas.core.horizon import EARTH_RADIUS_M
from csuas.core.terrain import curvature_drop_m, height_at, viewshed

#: Sampling step of the exact sight line [cells].
EXACT_STEP_CELLS = 0.05
#: Semi-major axis of the WGS 84 ellipsoid [m], the sphere GDAL curves a UTM DEM with.
WGS84_SEMI_MAJOR_M = 6_378_137.0
#: The CRS the DEMs are written in for GDAL (UTM 33N on WGS 84, metres).
TEST_CRS = "EPSG:32633"


def gdal_available() -> bool:
    """Whether GDAL's ``gdal_viewshed`` program is on the PATH."""
    return shutil.which("gdal_viewshed") is not None


def gdal_curvature_coefficient(k_factor: float) -> float:
    """GDAL's ``-cc`` that curves the Earth as csuas does at an effective radius factor k: a / (k R_E)."""
    return WGS84_SEMI_MAJOR_M / (k_factor * EARTH_RADIUS_M)


def gdal_viewshed(dem_m, cell_m, row: int, col: int, mast_m: float, target_m: float, k_factor: float) -> np.ndarray:
    """GDAL's viewshed of the DEM from the centre of cell (row, col): True where the target is visible.

    Parameters
    ----------
    dem_m : ndarray (rows, cols)
        Terrain heights [m]; written as float32, so compare with csuas on the float32-rounded grid.
    cell_m : float
        Cell size [m].
    row, col : int
        The observer's cell.
    mast_m, target_m : float
        Heights of the observer and of the target above the terrain [m].
    k_factor : float
        Effective Earth-radius factor.
    """
    import rasterio
    from rasterio.transform import from_origin

    if not gdal_available():
        raise RuntimeError("GDAL's gdal_viewshed program is not installed (Debian: apt-get install gdal-bin)")
    dem = np.asarray(dem_m, dtype=np.float32)
    transform = from_origin(500_000.0, 5_000_000.0, cell_m, cell_m)
    x, y = transform @ (col + 0.5, row + 0.5)
    with tempfile.TemporaryDirectory() as tmp:
        source, result = Path(tmp) / "dem.tif", Path(tmp) / "viewshed.tif"
        profile = {"driver": "GTiff", "height": dem.shape[0], "width": dem.shape[1], "count": 1, "dtype": "float32"}
        with rasterio.open(source, "w", crs=TEST_CRS, transform=transform, **profile) as dst:
            dst.write(dem, 1)
        command = ["gdal_viewshed", "-q", "-ox", repr(x), "-oy", repr(y), "-oz", repr(float(mast_m))]
        command += ["-tz", repr(float(target_m)), "-cc", repr(gdal_curvature_coefficient(k_factor))]
        command += ["-vv", "1", "-iv", "0", "-ov", "0", str(source), str(result)]
        subprocess.run(command, check=True, capture_output=True, text=True)
        with rasterio.open(result) as src:
            return src.read(1) > 0


def _grid_crossings(start: float, end: float) -> np.ndarray:
    """Fractions t of the way from ``start`` to ``end`` (cell coordinates) where it crosses an integer."""
    if start == end:
        return np.empty(0)
    return (np.arange(np.ceil(min(start, end)), np.floor(max(start, end)) + 1) - start) / (end - start)


def sight_line_clearance_m(dem_m, cell_m, row, col, mast_m, target_m, k_factor, cells) -> np.ndarray:
    """How far the sight line to each of ``cells`` ((n, 2) integer rows and cols) clears the terrain [m].

    The line runs from the eye (terrain at the sensor plus the mast) to the target (the cell's height
    plus ``target_m``), both lowered by the Earth's curvature; its clearance is the least height of
    the line above the bilinear terrain, lowered the same way, over samples ``EXACT_STEP_CELLS``
    apart and every grid-line crossing. Negative: the terrain hides the target by that much.
    """
    dem = np.asarray(dem_m, dtype=float)
    eye = float(height_at(dem, np.array([float(row)]), np.array([float(col)]))[0]) + mast_m
    clearance = np.empty(len(cells))
    for i, (r, c) in enumerate(np.asarray(cells)):
        reach = float(np.hypot(r - row, c - col))
        t = np.concatenate(
            [
                np.linspace(0.0, 1.0, int(reach / EXACT_STEP_CELLS) + 2),
                _grid_crossings(row, r),  # the bilinear terrain's kinks, where sharp crests stand
                _grid_crossings(col, c),
            ]
        )
        t = t[(t > 0.0) & (t < 1.0)]
        if reach < 0.5 or t.size == 0:
            clearance[i] = np.inf
            continue
        ground = height_at(dem, row + (r - row) * t, col + (c - col) * t)
        ground = ground - curvature_drop_m(t * reach * cell_m, k_factor)
        target = dem[r, c] + target_m - curvature_drop_m(reach * cell_m, k_factor)
        clearance[i] = float(np.min(eye + (target - eye) * t - ground))
    return clearance


def exact_line_of_sight(dem_m, cell_m, row, col, mast_m, target_m, k_factor, cells) -> np.ndarray:
    """Whether the sight line to each of ``cells`` clears the terrain (:func:`sight_line_clearance_m` >= 0)."""
    return sight_line_clearance_m(dem_m, cell_m, row, col, mast_m, target_m, k_factor, cells) >= 0.0


def cell_relief_m(dem_m) -> float:
    """The largest height difference between two neighbouring cells of the DEM [m]."""
    dem = np.asarray(dem_m, dtype=float)
    return float(max(np.abs(np.diff(dem, axis=0)).max(), np.abs(np.diff(dem, axis=1)).max()))


def fractal_dem(cells: int, relief_m: float, spectral_slope: float, seed: int) -> np.ndarray:
    """Rough test terrain [m]: Gaussian noise with a power-law amplitude spectrum f^-slope, scaled to 0..relief."""
    rng = np.random.default_rng(seed)
    frequency = np.hypot(*np.meshgrid(np.fft.fftfreq(cells), np.fft.fftfreq(cells)))
    frequency[0, 0] = 1.0
    spectrum = (rng.normal(size=(cells, cells)) + 1j * rng.normal(size=(cells, cells))) * frequency**-spectral_slope
    spectrum[0, 0] = 0.0
    dem = np.real(np.fft.ifft2(spectrum))
    return (dem - dem.min()) / (dem.max() - dem.min()) * relief_m


@dataclass(frozen=True)
class ViewshedCase:
    """A line-of-sight problem over terrain, as :func:`csuas.core.terrain.viewshed` poses it.

    Attributes
    ----------
    dem_m : ndarray (rows, cols)
        Terrain heights [m] on square cells.
    cell_m : float
        Cell size [m].
    row, col : int
        The mast's cell.
    mast_m, target_m : float
        Heights above the terrain of the sensor on its mast and of the target [m].
    k_factor : float
        Effective Earth-radius factor of the refraction.
    """

    dem_m: np.ndarray
    cell_m: float
    row: int
    col: int
    mast_m: float
    target_m: float
    k_factor: float


def compare_viewsheds(case: ViewshedCase, exact_samples: int = 2000, seed: int = 0) -> dict:
    """csuas's viewshed against GDAL's, and both against the exact sight line on random cells.

    A cell *grazes* when its exact sight line passes within one cell's relief (:func:`cell_relief_m`)
    of the terrain: the two methods sample the terrain up to a cell apart, so there they may disagree.

    Returns
    -------
    dict
        ``agreement`` (share of cells where csuas and GDAL agree), ``disagreeing`` (cell count),
        ``disagreeing_grazing`` (share of those that graze), ``worst_clearance_m`` (the largest
        |clearance| of a disagreeing cell), ``csuas_exact`` and ``gdal_exact`` (share of
        ``exact_samples`` random cells where each agrees with the sight line), ``csuas_exact_grazing``
        (share of the cells where csuas and the sight line disagree that graze), ``relief_m`` and
        ``visible`` (share csuas sees).
    """
    dem_m, cell_m, row, col = case.dem_m, case.cell_m, case.row, case.col
    mast_m, target_m, k_factor = case.mast_m, case.target_m, case.k_factor
    dem = np.asarray(dem_m, dtype=np.float32).astype(float)  # the grid GDAL reads
    relief = cell_relief_m(dem)
    ours = viewshed(dem, cell_m, row, col, mast_m, target_m, k_factor)
    theirs = gdal_viewshed(dem, cell_m, row, col, mast_m, target_m, k_factor)
    differ = np.argwhere(ours != theirs)
    clearance = sight_line_clearance_m(dem, cell_m, row, col, mast_m, target_m, k_factor, differ)
    picks = np.random.default_rng(seed).integers(0, dem.shape, size=(exact_samples, 2))
    exact_clearance = sight_line_clearance_m(dem, cell_m, row, col, mast_m, target_m, k_factor, picks)
    exact = exact_clearance >= 0.0
    wrong = ours[picks[:, 0], picks[:, 1]] != exact
    return {
        "agreement": float(1.0 - len(differ) / ours.size),
        "disagreeing": len(differ),
        "disagreeing_grazing": float(np.mean(np.abs(clearance) <= relief)) if len(differ) else 1.0,
        "worst_clearance_m": float(np.max(np.abs(clearance), initial=0.0)),
        "csuas_exact": float(1.0 - wrong.mean()),
        "gdal_exact": float(np.mean(theirs[picks[:, 0], picks[:, 1]] == exact)),
        "csuas_exact_grazing": float(np.mean(np.abs(exact_clearance[wrong]) <= relief)) if wrong.any() else 1.0,
        "relief_m": relief,
        "visible": float(ours.mean()),
    }
