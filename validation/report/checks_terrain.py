"""Line of sight over terrain (core/terrain.py) and site coverage (core/coverage.py) against closed forms.

* A smooth Earth: the farthest visible cell from a sensor on a mast against the sum of the two
  horizons, sqrt(2 k R h_s) + sqrt(2 k R h_t) (ITU-R P.834-9 Eq. 1), for radio (k = 4/3) and light.
* A straight wall: the end of its shadow on a target behind it against the straight line through the
  crest, x = D (h_t - h_s) / (H - h_s).
* Coverage on flat ground with the Earth's curvature: a sensor's detected area at a flight level against
  the annular sector pi (min(R_g, d_h)^2 - r^2) w / 360 (R_g the detection range on the ground, d_h the
  two horizons, r the dead zone's radius, w the sector), once limited by the horizon and once by the range
  with the overhead cone of silence, whose radius h / tan(el_max) is checked too.
* A cone-shaped hill: where its shadow starts behind it for a drone at height h, against the straight
  sight line over the apex with the curvature drop d^2 / (2 k R).
* k-of-n fusion: the Poisson-binomial tail against enumeration of all 2^n subsets and the binomial.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from csuas.base.checks import Check
from csuas.core.coverage import SitedSensor, fused_layers, sensor_layers
from csuas.core.horizon import EARTH_RADIUS_M, K_OPTICAL, K_RADIO
from csuas.core.scenario import load_scenario
from csuas.core.terrain import gaussian_hills, viewshed
from csuas.validation.report.registry import CheckGroup, CheckSpec, Section, timed

#: Grid cell of the smooth-Earth check [m] and the tolerance: the method judges cells within 1.5 cells of
#: the horizon on a path up to half a cell off their own line.
SMOOTH_CELL_M = 100.0
WALL_CELL_M = 10.0
#: Cells of the coverage checks [m]: the horizon-limited sector, the range-limited one, the cone-shaped hill.
HORIZON_CELL_M, RANGE_CELL_M, HILL_CELL_M = 100.0, 5.0, 10.0


def _farthest_visible_m(visible: np.ndarray, row: float, col: float, cell: float) -> float:
    rr, cc = np.indices(visible.shape)
    return float(np.hypot(rr - row, cc - col)[visible].max() * cell)


def terrain(_knob=None) -> Section:
    """The viewshed's horizons and shadows against their closed forms."""

    s = Section()
    flat = np.zeros((901, 901))
    for name, k in (("radio", K_RADIO), ("optical", K_OPTICAL)):
        visible, elapsed = timed(viewshed, flat, SMOOTH_CELL_M, 450.0, 450.0, 10.0, 30.0, k)
        horizon = math.sqrt(2 * k * EARTH_RADIUS_M * 10.0) + math.sqrt(2 * k * EARTH_RADIUS_M * 30.0)
        s.outcomes.append(
            Check(
                f"terrain.smooth_earth.{name}.farthest_visible_m",
                horizon,
                _farthest_visible_m(visible, 450.0, 450.0, SMOOTH_CELL_M),
                1.5 * SMOOTH_CELL_M,
                "m",
                time_s=elapsed,
                source="sum of the two horizons sqrt(2 k R h) (ITU-R P.834-9 Eq. 1), k = "
                f"{k:.4g}, 10 m mast, 30 m flight level",
                method=f"R2 viewshed of a flat 90 km square in {SMOOTH_CELL_M:g} m cells",
                tolerance_source="1.5 cells: cells graze the horizon on a path within half a cell of their line",
            )
        )
    wall = np.zeros((101, 401))
    wall[:, 50] = 40.0
    visible, elapsed = timed(viewshed, wall, WALL_CELL_M, 50.0, 0.0, 5.0, 100.0, 1e12)
    behind = np.flatnonzero(~visible[50, 51:]) + 51
    shadow_start = float(behind.min() * WALL_CELL_M) if behind.size else float("inf")
    expected = 50 * WALL_CELL_M * (100.0 - 5.0) / (40.0 - 5.0)
    s.outcomes.append(
        Check(
            "terrain.wall.shadow_start_m",
            expected,
            shadow_start,
            2 * WALL_CELL_M,
            "m",
            time_s=elapsed,
            source="the straight line through the crest: D (h_t - h_s) / (H - h_s)",
            method="a 40 m wall 500 m from a 5 m eye, a 100 m flight level behind it, no curvature",
            tolerance_source="2 cells: the sample nearest the crest and the cell's own half-cell path",
        )
    )
    return s


def _annular_sector_km2(outer_m: float, inner_m: float, sector_deg: float) -> float:
    return math.pi * (outer_m**2 - inner_m**2) * sector_deg / 360.0 / 1e6


def _cell_count_error_km2(outer_m: float, inner_m: float, sector_deg: float, cell_m: float) -> float:
    """Largest error of an annular sector's area counted in whole cells by their centres [km^2].

    A point is classed with its cell's centre, within delta = cell / sqrt(2): a misclassed point lies within
    delta of the boundary, whose band covers at most 2 delta P + 2 pi delta^2 (P the perimeter).
    """
    perimeter = (outer_m + inner_m) * math.radians(sector_deg) + 2 * (outer_m - inner_m)
    delta = cell_m / math.sqrt(2.0)
    return (2 * delta * perimeter + 2 * math.pi * delta**2) / 1e6


def coverage(_knob=None) -> Section:
    """Detected areas, a hill's shadow and k-of-n fusion of the coverage layers against closed forms."""

    s = Section()
    scenario = load_scenario("default")
    s.outcomes += _horizon_sector_checks(scenario)
    s.outcomes += _range_sector_checks(scenario)
    s.outcomes += _hill_shadow_checks(scenario)
    s.outcomes += _k_of_n_checks()
    return s


def _horizon_sector_checks(scenario) -> list:
    """The RF detector's detected area in a flat sector, limited by the radio horizon."""

    out = []
    # (a) horizon-limited: the RF detector (range 125 km) on a 10 m mast, 30 m flight level, 120 degree sector
    # toward 30 degrees, 2 km minimum range
    cell, mast, flight, sector, min_range = HORIZON_CELL_M, 10.0, 30.0, 120.0, 2000.0
    sited = SitedSensor("rf", 370.0, 370.0, mast, azimuth_deg=30.0, sector_deg=sector, min_range_m=min_range)
    layers, elapsed = timed(sensor_layers, np.zeros((741, 741)), cell, scenario, sited, [flight])
    horizon = math.sqrt(2 * K_RADIO * EARTH_RADIUS_M * mast) + math.sqrt(2 * K_RADIO * EARTH_RADIUS_M * flight)
    ground_range = math.sqrt(layers["range_m"] ** 2 - (flight - mast) ** 2)
    outer, inner = min(ground_range, horizon), math.sqrt(min_range**2 - (flight - mast) ** 2)
    band = 2 * 1.5 * cell * outer * math.radians(sector) / 1e6  # the viewshed's 1.5-cell horizon band
    out.append(
        Check(
            "terrain.coverage.flat_horizon_sector.area_km2",
            _annular_sector_km2(outer, inner, sector),
            float(layers["detected"][0].sum()) * cell * cell / 1e6,
            _cell_count_error_km2(outer, inner, sector, cell) + band,
            "km2",
            time_s=elapsed,
            source=f"pi (min(R_g, d_h)^2 - r^2) w / 360: d_h = {horizon / 1000:.4g} km (two horizons, k = 4/3) "
            f"< R_g = {ground_range / 1000:.4g} km, r = sqrt(r_min^2 - h^2), w = {sector:g} deg",
            method=f"coverage of the default RF detector on a flat 74 km square in {cell:g} m cells, "
            f"{mast:g} m mast, {flight:g} m flight level, {min_range / 1000:g} km minimum range",
            tolerance_source="the cell count's error, 2 delta P + 2 pi delta^2 (delta = cell / sqrt 2, P the "
            "perimeter), plus the viewshed's 1.5-cell band either side of the horizon arc",
        )
    )
    return out


def _range_sector_checks(scenario) -> list:
    """The EO camera's detected area in a flat sector, limited by its range, and its cone of silence."""

    out = []
    # (a) range-limited with the overhead cone of silence: the EO camera (range 555.5 m) on a 5 m mast,
    # 120 m flight level, 90 degree sector toward 200 degrees, blind above 45 degrees
    cell, mast, flight, sector, el_max = RANGE_CELL_M, 5.0, 120.0, 90.0, 45.0
    sited = SitedSensor("eo", 120.0, 120.0, mast, azimuth_deg=200.0, sector_deg=sector, elevation_max_deg=el_max)
    layers, elapsed = timed(sensor_layers, np.zeros((241, 241)), cell, scenario, sited, [flight])
    rise = flight - mast
    horizon = math.sqrt(2 * K_OPTICAL * EARTH_RADIUS_M * mast) + math.sqrt(2 * K_OPTICAL * EARTH_RADIUS_M * flight)
    ground_range = math.sqrt(layers["range_m"] ** 2 - rise**2)
    outer, inner = min(ground_range, horizon), rise / math.tan(math.radians(el_max))
    detected = layers["detected"][0]
    rr, cc = np.indices(detected.shape)
    ground = np.hypot(rr - 120.0, cc - 120.0) * cell
    out.append(
        Check(
            "terrain.coverage.flat_range_sector.area_km2",
            _annular_sector_km2(outer, inner, sector),
            float(detected.sum()) * cell * cell / 1e6,
            _cell_count_error_km2(outer, inner, sector, cell),
            "km2",
            time_s=elapsed / 2,
            source=f"pi (min(R_g, d_h)^2 - r^2) w / 360: R_g = sqrt(R^2 - h^2) = {ground_range:.4g} m < d_h, "
            f"r = h / tan(el_max) = {inner:.4g} m, w = {sector:g} deg",
            method=f"coverage of the default EO camera on a flat 1.2 km square in {cell:g} m cells, {mast:g} m "
            f"mast, {flight:g} m flight level, elevation at most {el_max:g} deg",
            tolerance_source="the cell count's error, 2 delta P + 2 pi delta^2 (delta = cell / sqrt 2, P the "
            "perimeter)",
        )
    )
    out.append(
        Check(
            "terrain.coverage.cone_of_silence.radius_m",
            inner,
            float(ground[detected].min()),
            math.sqrt(2.0) * cell,
            "m",
            time_s=elapsed / 2,
            source=f"h / tan(el_max), h = {rise:g} m above the eye, el_max = {el_max:g} deg",
            method="the nearest detected cell centre of the same layer",
            tolerance_source="one cell diagonal: a cell centre lies within cell / sqrt 2 of every point, so the "
            "nearest one outside the circle is at most a diagonal out",
        )
    )
    return out


def _hill_shadow_checks(scenario) -> list:
    """Where a cone-shaped hill's shadow starts at a flight level behind it."""

    out = []
    # (b) a cone-shaped hill (60 m high, 300 m base radius) 1 km east of the RF detector on a 5 m mast, its apex
    # on a cell centre of the sensor's row; a 100 m flight level is hidden from where the sight line over the
    # apex meets it: x^2 / (2 k R) + s_a x - (h - e) = 0, s_a = (H - D^2 / (2 k R) - e) / D
    cell, eye, flight, height, base, apex = HILL_CELL_M, 5.0, 100.0, 60.0, 300.0, 1000.0
    rr, cc = np.indices((101, 301))
    hill = np.clip(height * (1.0 - np.hypot(rr - 50, cc - apex / cell) * cell / base), 0.0, None)
    layers, elapsed = timed(sensor_layers, hill, cell, scenario, SitedSensor("rf", 50.0, 0.0, eye), [flight])
    behind = np.flatnonzero(~layers["detected"][0][50, int(apex / cell) + 1 :]) + int(apex / cell) + 1
    k_r = K_RADIO * EARTH_RADIUS_M
    slope_apex = (height - apex**2 / (2 * k_r) - eye) / apex
    expected = k_r * (-slope_apex + math.sqrt(slope_apex**2 + 2 * (flight - eye) / k_r))
    out.append(
        Check(
            "terrain.coverage.cone_hill.shadow_start_m",
            expected,
            float(behind.min() * cell) if behind.size else float("inf"),
            2 * cell,
            "m",
            time_s=elapsed,
            source="the sight line over the apex with the curvature drop d^2 / (2 k R), k = 4/3: "
            "x = k R (-s_a + sqrt(s_a^2 + 2 (h - e) / (k R)))",
            method=f"coverage of the default RF detector behind a {height:g} m cone of {base:g} m base radius "
            f"{apex:g} m away in {cell:g} m cells, {eye:g} m eye, {flight:g} m flight level",
            tolerance_source="2 cells, as the wall: the first hidden cell centre and the cell's own half-cell path",
        )
    )
    return out


def _k_of_n_checks() -> list:
    """k-of-n fused Pd against the enumeration of subsets and the binomial tail."""

    out = []
    # (c) k-of-n Pd: 5 independent sensors with random Pd, and 5 equal ones (the binomial)
    rng = np.random.default_rng(15)
    n, k = 5, 3
    pd = rng.uniform(0.0, 1.0, (n, 1, 40, 40))
    per_sensor = {f"s{i}": {"detected": pd[i] > 0.5, "pd": pd[i]} for i in range(n)}
    fused, elapsed = timed(fused_layers, per_sensor, k)
    brute = np.zeros(pd.shape[1:])
    for chosen in itertools.product((False, True), repeat=n):
        if sum(chosen) >= k:
            brute += np.prod([p if c else 1.0 - p for p, c in zip(pd, chosen)], axis=0)
    out.append(
        Check(
            "terrain.coverage.k_of_n.max_abs_error_vs_enumeration",
            0.0,
            float(np.abs(fused["pd_k_of_n"] - brute).max()),
            1e-12,
            "",
            time_s=elapsed,
            source=f"sum over all 2^{n} subsets of at least {k} detecting sensors of prod p_i prod (1 - p_j)",
            method=f"fused_layers' {k}-of-{n} Pd on 1600 cells of random Pd",
            tolerance_source="rounding: 2^n products of n factors in double precision, far below 1e-12",
        )
    )
    equal = {f"s{i}": {"detected": np.ones((1, 1, 1), bool), "pd": np.full((1, 1, 1), 0.6)} for i in range(n)}
    fused, elapsed = timed(fused_layers, equal, k)
    binomial = sum(math.comb(n, j) * 0.6**j * 0.4 ** (n - j) for j in range(k, n + 1))
    out.append(
        Check(
            "terrain.coverage.k_of_n.binomial_pd",
            binomial,
            float(fused["pd_k_of_n"][0, 0, 0]),
            1e-12,
            "",
            time_s=elapsed,
            source=f"the binomial tail sum_j>={k} C({n}, j) p^j (1 - p)^({n} - j), p = 0.6",
            method=f"fused_layers' {k}-of-{n} Pd of {n} sensors of equal Pd",
            tolerance_source="rounding of a sum of n + 1 terms, far below 1e-12",
        )
    )
    return out


#: GDAL cross-check cases: (terrain, observer row, observer col, target height [m]).
GDAL_CASES = (("hills", 200, 200, 30.0), ("hills", 120, 300, 2.0), ("hills", 330, 80, 120.0), ("rough", 40, 260, 30.0))


def gdal_cross_check(_knob=None) -> Section:
    """The viewshed against GDAL's gdal_viewshed and the exact sight line (validation/terrain)."""
    from csuas.validation.terrain.viewshed_oracles import ViewshedCase, compare_viewsheds, fractal_dem, gdal_available

    s = Section()
    if not gdal_available():
        s.notes.append("GDAL's gdal_viewshed is not installed (Debian: gdal-bin): the cross-check did not run.")
        return s
    terrains = {
        "hills": (gaussian_hills(400, 25.0), 25.0, K_RADIO),
        "rough": (fractal_dem(300, 300.0, 1.6, seed=1), 30.0, K_OPTICAL),
    }
    for name, row, col, target in GDAL_CASES:
        dem, cell, k = terrains[name]
        problem = ViewshedCase(dem, cell, row, col, 10.0, target, k)
        result, elapsed = timed(compare_viewsheds, problem, exact_samples=1000)
        case = f"terrain.gdal.{name}_r{row}_c{col}_{target:g}m"
        where = f"{dem.shape[0]} x {dem.shape[1]} cells of {cell:g} m, 10 m mast, {target:g} m target"
        s.table.append({"case": case, **result})
        if name == "hills":
            s.outcomes.append(
                Check(
                    f"{case}.agreement_with_gdal",
                    1.0,
                    result["agreement"],
                    0.01,
                    "-",
                    time_s=elapsed,
                    source="GDAL gdal_viewshed (Wang, Robinson & White 2000), same DEM, observer and curvature",
                    method=f"R2 rays on the demo hills ({where}); {result['disagreeing']} cells differ, a share "
                    f"{result['disagreeing_grazing']:.3g} of them grazing",
                    tolerance_source="the issue's criterion: at least 99 % of cells agree",
                )
            )
        s.outcomes.append(
            Check(
                f"{case}.agreement_with_sight_line",
                1.0,
                result["csuas_exact"],
                0.01,
                "-",
                time_s=elapsed,
                source="the exact sight line over the bilinear terrain, sampled every 0.05 cell and at grid lines",
                method=f"R2 rays, 1000 random cells ({where}); GDAL agrees on {result['gdal_exact']:.4f}",
                tolerance_source="99 % of cells: the method judges grazing cells on a path up to half a cell off",
            )
        )
        s.outcomes.append(
            Check(
                f"{case}.disagreements_grazing",
                1.0,
                min(result["disagreeing_grazing"], result["csuas_exact_grazing"]),
                0.0,
                "-",
                time_s=elapsed,
                source="every disagreement grazes: its sight line passes within one cell's relief "
                f"({result['relief_m']:.3g} m) of the terrain",
                method="exact sight-line clearance of each cell where csuas differs from GDAL or the sight line",
                tolerance_source="none: a disagreement away from grazing is an error of one method",
            )
        )
    return s


#: The report section of these checks.
GROUP = CheckGroup(
    "terrain",
    "Line of sight and site coverage over terrain vs closed-form horizons, shadows and areas",
    90,
    "Line of sight over terrain and site coverage against closed-form horizons, wall shadows and covered areas.",
)


SPECS = [
    CheckSpec(
        "terrain.gdal",
        "Line of sight vs GDAL's viewshed and the exact sight line",
        GROUP,
        "the R2 viewshed vs GDAL's gdal_viewshed on the demo hills and on rough fractal terrain, and both vs the "
        "exact sight line on random cells",
        "99 % of cells (the issue's criterion), and every disagreement grazing (clearance within one cell's relief)",
        gdal_cross_check,
        None,
        {},
        False,
    ),
    CheckSpec(
        "terrain.line_of_sight",
        "Line of sight over terrain vs closed-form horizons and shadows",
        GROUP,
        "the R2 viewshed's farthest visible cell and a wall's shadow vs their closed forms",
        "1.5 cells (horizon), 2 cells (shadow)",
        terrain,
        None,
        {},
        False,
    ),
    CheckSpec(
        "terrain.coverage",
        "Site coverage vs closed-form areas, a hill's shadow and k-of-n enumeration",
        GROUP,
        "detected areas of sectors with dead zones on flat ground with curvature vs the annular sector, the "
        "cone of silence's radius, a cone-shaped hill's shadow vs the sight line over its apex, k-of-n Pd vs "
        "enumeration and the binomial",
        "the cell count's boundary band (2 delta P + 2 pi delta^2, delta = cell / sqrt 2) plus the viewshed's "
        "1.5-cell horizon band (areas), one cell diagonal (radius), 2 cells (shadow), 1e-12 (Pd)",
        coverage,
        None,
        {},
        False,
    ),
]
