"""Radio maps over terrain (:mod:`csuas.render.links.terrain_map`) against the two-ray model and the viewshed.

* Flat ground. Over a flat DEM the flight level is a plane and every cell's value must be the
  two-ray model averaged over the cell. Sionna's radio map adds the rays' *powers* (its Eq.
  ``cm_def``), so the oracle is |h_direct|^2 + |h_ground|^2 of :func:`csuas.render.links.two_ray.two_ray_paths`
  (exact Fresnel reflection off the same ITU-R P.2040-3 half-space), averaged over each
  measurement block by Gauss-Legendre quadrature; the coherent |h_direct + h_ground|^2, lobes and
  nulls included, averaged the same way, shows what the radio map leaves out. The replicas' error
  bound is tested for coverage: the fraction of cells whose |error| it bounds must reach its level.
* Accuracy against rays per replica: the same comparison over a range of budgets, with the time.
* Line of sight. With the direct rays only (no reflection, no diffraction) a cell of the map
  receives power exactly when the straight line from the sensor clears the terrain, which is what
  :func:`csuas.core.terrain.viewshed` decides. A cell is compared away from the viewshed's edge: a
  cell that has neighbours of both kinds is partly seen, and the viewshed judges its centre, the
  map its whole area.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.dielectric import ground_permittivity
from csuas.core.terrain import viewshed
from csuas.render.links.terrain_map import (
    DEFAULT_GROUND,
    REPLICAS,
    RadioMapOptions,
    RadioMapSite,
    block_edges,
    blocks_to_grid,
    local_xy,
    measurement_mesh,
    terrain_radio_map,
)
from csuas.render.links.two_ray import two_ray_paths

#: The flat-ground scene: 1 GHz (lobes 11 m apart at 300 m, resolved by 10 m cells beyond), a 10 m
#: mast at the west edge of a 200 m x 600 m strip, flight level 120 m, medium dry ground (eps_r 15),
#: every cell measured. H polarisation: its reflection coefficient goes from -0.66 to -0.89 over the
#: strip, so the lobes are deep, while V passes Brewster's angle (14.5 deg, about 500 m) there.
FLAT = {
    "frequency_ghz": 1.0,
    "shape": (21, 61),
    "cell_m": 10.0,
    "tx_row": 10.0,
    "tx_col": 0.0,
    "mast_m": 10.0,
    "altitude_m": 120.0,
    "ground": DEFAULT_GROUND,
    "polarization": "H",
    "step": 1,
}
#: Gauss-Legendre nodes per axis of a block: 16 and 96 nodes agree to 1e-11 dB on the flat scene for
#: the power sum (smooth on the 110 m scale of the height difference) and for the coherent sum (a few
#: lobes across the blocks nearest the mast).
ORDER = 16
#: The ridge of the line-of-sight check: 1 km x 1.25 km in 25 m cells, a 10 m mast at the west edge,
#: a Gaussian ridge 25 m high, 50 m wide, 250 m east of it; flight level 60 m: seen behind the ridge
#: up to about 830 m, where the line over the crest reaches the flight level, and hidden beyond.
RIDGE = {
    "shape": (41, 51),
    "cell_m": 25.0,
    "tx_row": 20.0,
    "tx_col": 0.0,
    "mast_m": 10.0,
    "altitude_m": 60.0,
    "ridge_col": 10.0,
    "ridge_height_m": 25.0,
    "ridge_width_cells": 2.0,
    "frequency_ghz": 2.4,
}


def block_average_two_ray(site: RadioMapSite, eta, step=1, coherent=False, order=ORDER, polarization="V"):
    """Two-ray path gain over flat ground averaged over each measurement block of the flight level.

    Parameters
    ----------
    site : RadioMapSite
        The map's site: its DEM gives the grid's shape and must be flat (one height everywhere);
        the sensor's fractional cell position, the mast and the flight level above the ground [m]
        and the carrier frequency [GHz].
    eta : complex
        Complex relative permittivity of the ground.
    step : int
        DEM cells per side of a block, as in the radio map.
    coherent : bool
        False: |h_direct|^2 + |h_ground|^2, Sionna's radio map; True: |h_direct + h_ground|^2.
    order : int
        Gauss-Legendre nodes per axis of a block.
    polarization : {"V", "H"}

    Returns
    -------
    numpy.ndarray (rows, cols)
        Path gain averaged over the block of each DEM cell [linear].

    Raises
    ------
    ParameterError
        A DEM that is not flat (the two-ray model knows no terrain).
    """
    dem = np.asarray(site.dem_m, float)
    if dem.ndim != 2 or np.ptp(dem) != 0:
        raise ParameterError("dem_m", f"array of shape {dem.shape}", "a flat 2-D grid (one height everywhere)")
    shape, cell_m, tx_row, tx_col = dem.shape, site.cell_m, site.tx_row, site.tx_col
    nodes, weights = np.polynomial.legendre.leggauss(order)
    u, w = (nodes + 1.0) / 2.0, weights / 2.0
    r_edges, c_edges = block_edges(shape[0], step), block_edges(shape[1], step)
    rows = r_edges[:-1, None] + np.diff(r_edges)[:, None] * u[None, :]  # (blocks, order)
    cols = c_edges[:-1, None] + np.diff(c_edges)[:, None] * u[None, :]
    x, _ = local_xy(0.0, cols, shape, cell_m)
    _, y = local_xy(rows, 0.0, shape, cell_m)
    tx_x, tx_y = local_xy(tx_row, tx_col, shape, cell_m)
    px = np.broadcast_to(x[None, :, None, :], (len(rows), len(cols), order, order))
    py = np.broadcast_to(y[:, None, :, None], px.shape)
    points = np.stack([px, py, np.full(px.shape, float(site.altitude_m))], axis=-1)
    transmitter = np.array([tx_x, tx_y, site.mast_m], float)
    paths = two_ray_paths(site.frequency_ghz, transmitter, points, eta, polarization)
    power = np.abs(paths.sum(-1)) ** 2 if coherent else np.sum(np.abs(paths) ** 2, axis=-1)
    mean = np.einsum("brij,i,j->br", power, w, w)
    return blocks_to_grid(mean, shape, step)


def flat_ground_comparison(samples, replicas=REPLICAS, seed=1, scene=None) -> dict:
    """The radio map of a flat DEM against the two-ray model averaged over its cells.

    Parameters
    ----------
    samples : int
        Rays per replica.
    replicas, seed : int
        As for :func:`csuas.render.links.terrain_map.terrain_radio_map`.
    scene : dict, optional
        Overrides of :data:`FLAT`.

    Returns
    -------
    dict
        ``result`` (TerrainRadioMap), ``distance_m`` (horizontal, per cell), ``power_db`` and
        ``coherent_db`` (the oracles per cell), ``error_db`` (map - power sum, reliable cells, else
        NaN), ``median_abs_error_db``, ``p95_abs_error_db``, ``median_bound_db``, ``coverage``
        (fraction of reliable cells with |error| <= bound), ``reliable_fraction``,
        ``coherent_median_abs_db`` and ``coherent_p95_abs_db`` (map - coherent sum), ``time_s``.
    """
    p = {**FLAT, **(scene or {})}
    shape, cell = p["shape"], p["cell_m"]
    site = RadioMapSite(
        np.zeros(shape), cell, p["tx_row"], p["tx_col"], p["mast_m"], p["altitude_m"], p["frequency_ghz"]
    )
    result = terrain_radio_map(
        site,
        RadioMapOptions(
            ground=p["ground"],
            samples=samples,
            max_depth=1,
            seed=seed,
            replicas=replicas,
            step=p["step"],
            k_factor=None,
            polarization=p["polarization"],
        ),
    )
    eta = ground_permittivity(result.extra, p["frequency_ghz"])
    options = {"step": p["step"], "polarization": p["polarization"]}
    power_db = 10.0 * np.log10(block_average_two_ray(site, eta, **options))
    coherent_db = 10.0 * np.log10(block_average_two_ray(site, eta, coherent=True, **options))
    rows, cols = np.indices(shape)
    distance = np.hypot(rows - p["tx_row"], cols - p["tx_col"]) * cell
    ok = result.reliable
    error = np.where(ok, result.path_gain_db - power_db, np.nan)
    coherent = np.abs(result.path_gain_db - coherent_db)[ok]
    return {
        "result": result,
        "distance_m": distance,
        "power_db": power_db,
        "coherent_db": coherent_db,
        "error_db": error,
        "median_abs_error_db": float(np.median(np.abs(error[ok]))),
        "p95_abs_error_db": float(np.percentile(np.abs(error[ok]), 95)),
        "median_bound_db": float(np.median(result.error_db[ok])),
        "coverage": float(np.mean(np.abs(error[ok]) <= result.error_db[ok])),
        "reliable_fraction": float(ok.mean()),
        "coherent_median_abs_db": float(np.median(coherent)),
        "coherent_p95_abs_db": float(np.percentile(coherent, 95)),
        "time_s": result.time_s,
    }


def accuracy_vs_samples(samples_list, replicas=REPLICAS, seed=1, scene=None) -> list:
    """Rows of :func:`flat_ground_comparison` over rays per replica (its scalar figures, and ``samples``)."""
    rows = []
    for samples in samples_list:
        out = flat_ground_comparison(samples, replicas, seed, scene)
        rows.append({"samples": int(samples), **{k: v for k, v in out.items() if np.isscalar(v)}})
    return rows


def ridge_dem(shape, ridge_col, ridge_height_m, ridge_width_cells) -> np.ndarray:
    """Flat ground with a Gaussian ridge along the rows, crest at column ``ridge_col``: heights [m]."""
    cols = np.arange(shape[1], dtype=float)
    profile = ridge_height_m * np.exp(-0.5 * ((cols - ridge_col) / ridge_width_cells) ** 2)
    return np.broadcast_to(profile, shape).copy()


def edge_cells(visible: np.ndarray) -> np.ndarray:
    """Cells with a neighbour (of the 8) on the other side of the viewshed's edge."""
    padded = np.pad(visible, 1, mode="edge")
    n_r, n_c = visible.shape
    edge = np.zeros_like(visible)
    for dr in (0, 1, 2):
        for dc in (0, 1, 2):
            edge |= padded[dr : dr + n_r, dc : dc + n_c] != visible
    return edge


#: Most seen cells left dark per Poisson-estimated one (:func:`line_of_sight_agreement`): measured
#: 0.80 on the ridge (2^16 rays per replica), 0.97-1.06 on the demo terrain (core.terrain.gaussian_hills,
#: 400 cells of 25 m, 2^20-2^24 rays) and 1.8 on the same terrain in 100 m cells (48 against 26.9, 2^22).
DARK_EXCESS = 2.0


def dark_tolerance(expected_dark: float) -> float:
    """Most seen cells a direct-ray map may leave dark: DARK_EXCESS E + 3 sqrt(DARK_EXCESS E)."""
    excess = DARK_EXCESS * expected_dark
    return excess + 3.0 * np.sqrt(excess)


def triangle_solid_angles_sr(vertices: np.ndarray, faces: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """Solid angles [sr] of triangles seen from ``origin`` (Van Oosterom & Strackee, IEEE TBME 30, 1983, Eq. 8).

    tan(Omega / 2) = |a . (b x c)| / (|a||b||c| + (a . b)|c| + (a . c)|b| + (b . c)|a|), a, b, c the
    corners relative to the origin.
    """
    a, b, c = (vertices[faces[:, i].astype(np.int64)] - origin for i in range(3))
    la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
    numerator = np.abs(np.einsum("ij,ij->i", a, np.cross(b, c)))
    denominator = (
        la * lb * lc
        + np.einsum("ij,ij->i", a, b) * lc
        + np.einsum("ij,ij->i", a, c) * lb
        + np.einsum("ij,ij->i", b, c) * la
    )
    return 2.0 * np.arctan2(numerator, denominator)


def line_of_sight_agreement(site: RadioMapSite, samples, replicas=REPLICAS, seed=1, k_factor=4 / 3) -> dict:
    """A direct-rays-only radio map against the viewshed of the same sensor and flight level.

    A seen cell stays dark when no ray of the lattice falls in its solid angle Omega: with the
    lattice rotated at random, each replica's count of rays in it has mean n = N Omega / (4 pi),
    and a Poisson count would be 0 with probability e^-n, so about the sum of exp(-K n) over the
    seen cells stay dark (``expected_dark``). The lattice's rows leave thin, grazing cells dark more
    often than that: :data:`DARK_EXCESS` (:func:`dark_tolerance`).

    Parameters
    ----------
    site : RadioMapSite
        The DEM, the sensor, the flight level and the carrier.
    samples, replicas, seed : int
        Rays per replica, replicas and seed of the map (:class:`RadioMapOptions`).
    k_factor : float or None
        Effective Earth-radius factor of the map and the viewshed (None: flat Earth).

    Returns
    -------
    dict
        ``result``, ``visible`` (the viewshed), ``edge`` (cells at its edge), ``agreement`` (fraction
        of the cells off the edge where "some power" equals "visible"), ``agreement_all`` (over
        every cell), ``hidden_lit`` and ``visible_dark`` (cells off the edge of each disagreement),
        ``expected_dark`` (the Poisson estimate above), ``cells`` (off the edge), ``time_s``.
    """
    result = terrain_radio_map(
        site,
        RadioMapOptions(
            samples=samples, max_depth=0, seed=seed, replicas=replicas, k_factor=k_factor, reflection=False
        ),
    )
    dem, cell_m, altitude_m = np.asarray(site.dem_m, float), site.cell_m, site.altitude_m
    horizon_k = 1e12 if k_factor is None else k_factor
    visible = viewshed(dem, cell_m, site.tx_row, site.tx_col, site.mast_m, altitude_m, horizon_k)
    edge = edge_cells(visible)
    inner = ~edge
    lit = result.reached
    vertices, faces = measurement_mesh(dem, cell_m, altitude_m, 1, k_factor)
    omega = triangle_solid_angles_sr(vertices, faces, result.extra["tx_position_m"])
    rays = replicas * samples * omega.reshape(dem.shape[0], dem.shape[1], 2).sum(-1) / (4.0 * np.pi)
    return {
        "result": result,
        "visible": visible,
        "edge": edge,
        "agreement": float(np.mean((lit == visible)[inner])),
        "agreement_all": float(np.mean(lit == visible)),
        "hidden_lit": int(np.sum(lit & ~visible & inner)),
        "visible_dark": int(np.sum(~lit & visible & inner)),
        "expected_dark": float(np.sum(np.exp(-rays)[visible & inner])),
        "cells": int(inner.sum()),
        "time_s": result.time_s,
    }


def ridge_line_of_sight(samples, replicas=REPLICAS, seed=1) -> dict:
    """:func:`line_of_sight_agreement` on the ridge of :data:`RIDGE` (radio k-factor 4/3)."""
    p = RIDGE
    dem = ridge_dem(p["shape"], p["ridge_col"], p["ridge_height_m"], p["ridge_width_cells"])
    site = RadioMapSite(dem, p["cell_m"], p["tx_row"], p["tx_col"], p["mast_m"], p["altitude_m"], p["frequency_ghz"])
    return line_of_sight_agreement(site, samples, replicas, seed)
