"""Sionna RT links against their closed forms: Friis and two-ray (RF), Eq. 68 and four-path (radar).

Knob: Sionna's sample budget (rays per source, maximum depth,
:mod:`csuas.render.links.budget`). In free space the line of sight is
tested directly and a link is exact to float precision whatever the budget;
over a flat ground 3 rays already find every reflection, so the presets are
exact there too. The accuracy-vs-time curves (:func:`csuas.validation.links.accuracy.accuracy_vs_time`)
show this: error against wall time over the budgets, Sionna's own default
(10^6 rays, depth 3) included in the full report.

Radio maps over terrain (:mod:`csuas.render.links.terrain_map`) have a knob that matters: the
rays per replica, whose error the replicas' own bound estimates; their checks
(:mod:`csuas.validation.links.terrain_map`) test that bound's coverage against the two-ray power
sum over a flat DEM, and a direct-ray map against the viewshed of a ridge.
"""

from __future__ import annotations

import numpy as np

from csuas.base.checks import Check
from csuas.core.dielectric import ground_permittivity
from csuas.render.quality import LINKS
from csuas.validation.report.figures import AccuracyColumns, PlotAxes, curves
from csuas.validation.report.figures import accuracy_vs_time as plot_accuracy
from csuas.validation.report.registry import CheckGroup, CheckSpec, Section, timed

#: Sample budget of the link checks per report quality.
BUDGETS = {"quick": "draft", "full": "standard"}
#: Accuracy-vs-time budgets per report quality (names of csuas.render.links.budget presets or (samples, depth)).
SWEEPS = {
    "quick": ((1, 1), (4, 1), "draft", "standard"),
    "full": ((1, 1), (4, 1), *LINKS.names, "sionna_default"),
}
#: Largest accepted difference to the closed form [dB]: float32 geometry in Sionna, float64 phases here.
TOLERANCE_DB = 0.05
#: Distances of the range curves [m].
DISTANCES_M = (10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0)
GROUND = "medium_dry_ground"


def _budgets(names):
    from csuas.render.links.budget import PRESETS, SIONNA_DEFAULT, LinkBudget

    out = []
    for b in names:
        if isinstance(b, tuple):
            out.append(LinkBudget(f"samples_{b[0]}", b[0], b[1]))
        else:
            out.append(SIONNA_DEFAULT if b == "sionna_default" else PRESETS[b])
    return tuple(out)


def rf_links(budget: str) -> Section:
    """RF path gain drone -> sensor, 2.4 GHz, free space (Friis) and over medium dry ground (two-ray)."""
    from csuas.render.links.rf import rf_path_gain
    from csuas.validation.links.accuracy import closed_form_db

    s = Section()
    d = np.array(DISTANCES_M)
    f = 2.4
    free, t_free = timed(rf_path_gain, f, d, 30.0, 2.0, budget=budget)
    ground, t_ground = timed(rf_path_gain, f, d, 30.0, 2.0, ground=GROUND, budget=budget)
    friis = closed_form_db("rf", f, d, 30.0, 2.0)
    eta = ground_permittivity(ground.extra, f)
    two_ray = closed_form_db("rf", f, d, 30.0, 2.0, eta)
    err_free = float(np.max(np.abs(free.path_gain_db - friis)))
    err_ground = float(np.max(np.abs(ground.path_gain_db - two_ray)))
    s.outcomes.append(
        Check(
            "links.rf.free_space.max_error_db",
            0.0,
            err_free,
            TOLERANCE_DB,
            "dB",
            time_s=t_free,
            source="Friis, Eq. 54 (csuas.core.rf)",
            method=f"Sionna RT PathSolver, {len(d)} distances 10 m-10 km, budget {budget}",
            details={"distance_m": d, "sionna_db": free.path_gain_db, "friis_db": friis},
        )
    )
    s.outcomes.append(
        Check(
            "links.rf.ground.max_error_db",
            0.0,
            err_ground,
            TOLERANCE_DB,
            "dB",
            time_s=t_ground,
            source="two-ray model with Fresnel reflection (csuas.render.links.two_ray)",
            method=f"Sionna RT PathSolver over {GROUND}, budget {budget}",
            details={"distance_m": d, "sionna_db": ground.path_gain_db, "two_ray_db": two_ray},
        )
    )
    dd = np.geomspace(d[0], d[-1], 400)
    s.figures.append(
        curves(
            "links_rf_range_curve",
            "RF path gain drone (30 m) -> sensor (2 m), 2.4 GHz",
            axes=PlotAxes("distance [m]", "path gain [dB]", log_x=True),
            lines=[
                ("Friis (Eq. 54)", dd, closed_form_db("rf", f, dd, 30.0, 2.0)),
                (f"two-ray over {GROUND}", dd, closed_form_db("rf", f, dd, 30.0, 2.0, eta)),
            ],
            points=[
                ("Sionna RT, free space", d, free.path_gain_db, None),
                (f"Sionna RT, {GROUND}", d, ground.path_gain_db, None),
            ],
        )
    )
    return s


def radar_links(budget: str) -> Section:
    """Monostatic radar link to a 0.01 m^2 drone: 24 GHz free space (Eq. 68), 10 GHz over ground (four paths)."""
    from csuas.render.links.radar import radar_link_gain
    from csuas.validation.links.accuracy import closed_form_db

    s = Section()
    d = np.array(DISTANCES_M)
    free, t_free = timed(radar_link_gain, 23.98, d, 5.0, 5.0, budget=budget)
    eq68 = closed_form_db("radar", 23.98, d, 5.0, 5.0)
    ground, t_ground = timed(radar_link_gain, 10.0, d, 5.0, 10.0, ground=GROUND, budget=budget)
    eta = ground_permittivity(ground.extra, 10.0)
    four = closed_form_db("radar", 10.0, d, 5.0, 10.0, eta)
    s.outcomes.append(
        Check(
            "links.radar.free_space.max_error_db",
            0.0,
            float(np.max(np.abs(free.path_gain_db - eq68))),
            TOLERANCE_DB,
            "dB",
            time_s=t_free,
            source="radar equation, Eq. 68 (csuas.core.radar)",
            method=f"Sionna RT RCSSolver, 23.98 GHz, sigma 0.01 m^2, budget {budget}",
            details={"range_m": d, "sionna_db": free.path_gain_db, "eq68_db": eq68},
        )
    )
    s.outcomes.append(
        Check(
            "links.radar.ground.max_error_db",
            0.0,
            float(np.max(np.abs(ground.path_gain_db - four))),
            TOLERANCE_DB,
            "dB",
            time_s=t_ground,
            source="four-path model (direct/reflected legs, csuas.render.links.two_ray)",
            method=f"Sionna RT RCSSolver over {GROUND}, 10 GHz, budget {budget}",
            details={"range_m": d, "sionna_db": ground.path_gain_db, "four_path_db": four},
        )
    )
    dd = np.geomspace(d[0], d[-1], 400)
    s.figures.append(
        curves(
            "links_radar_range_curve",
            "Radar two-way gain, drone 0.01 m^2",
            axes=PlotAxes("range [m]", "P_rx / (P_tx G_tx G_rx) [dB]", log_x=True),
            lines=[
                ("Eq. 68, 23.98 GHz", dd, closed_form_db("radar", 23.98, dd, 5.0, 5.0)),
                (f"four-path, 10 GHz over {GROUND}", dd, closed_form_db("radar", 10.0, dd, 5.0, 10.0, eta)),
            ],
            points=[
                ("Sionna RT, free space", d, free.path_gain_db, None),
                ("Sionna RT, over ground", d, ground.path_gain_db, None),
            ],
        )
    )
    return s


#: SBR-PO drone table of the radar link: rays per wavelength per report quality, and the aspect grid.
SBR_RAYS_PER_WAVELENGTH = {"quick": 3.0, "full": 6.0}
SBR_AZIMUTHS_DEG = tuple(np.arange(0.0, 360.0, 30.0))
SBR_ELEVATIONS_DEG = (-30.0, 0.0, 30.0)


def radar_sbr_link(rays_per_wavelength: float) -> Section:
    """Radar link to the DJI Mini 4 Pro whose Sionna RCS function interpolates the SBR-PO table (24 GHz).

    The radar and the drone are at the same height, so the link looks at
    elevation 0; at table nodes the interpolated cross-section is the SBR
    value itself and Eq. 68 with that sigma is the closed form.
    """
    from csuas.render.links.radar import RadarTarget, radar_link_gain
    from csuas.render.links.rcs_table import RCSTable
    from csuas.render.rcs.sweep import rcs_table
    from csuas.validation.links.accuracy import closed_form_db

    s = Section()
    f = 23.98
    table, t_table = timed(
        rcs_table,
        "dji_mini_4_pro",
        f,
        SBR_AZIMUTHS_DEG,
        SBR_ELEVATIONS_DEG,
        rays_per_wavelength=rays_per_wavelength,
        max_bounces=3,
        error_estimate=False,
    )
    rcs = RCSTable(table["azimuth_deg"], table["elevation_deg"], table["rcs_m2"])
    s.notes.append(
        f"SBR-PO table {len(SBR_AZIMUTHS_DEG)} x {len(SBR_ELEVATIONS_DEG)} aspects, "
        f"{rays_per_wavelength:g} rays per wavelength: {t_table:.1f} s"
    )
    d = np.array(DISTANCES_M)
    lines, points = [], []
    for aspect in (0.0, 90.0):
        link, t_link = timed(radar_link_gain, f, d, 5.0, 5.0, RadarTarget(rcs, azimuth_deg=aspect), budget="draft")
        sigma = float(table["rcs_m2"][SBR_AZIMUTHS_DEG.index(aspect), SBR_ELEVATIONS_DEG.index(0.0)])
        eq68 = closed_form_db("radar", f, d, 5.0, 5.0, sigma_m2=sigma)
        s.outcomes.append(
            Check(
                f"links.radar_sbr.azimuth_{aspect:g}.max_error_db",
                0.0,
                float(np.max(np.abs(link.path_gain_db - eq68))),
                TOLERANCE_DB,
                "dB",
                time_s=t_link,
                source="radar equation, Eq. 68, with the SBR-PO sigma at that aspect",
                method=f"Sionna RT RCSSolver, drone as sensing target with the SBR-PO table "
                f"(sigma = {sigma:.3g} m^2 at azimuth {aspect:g} deg)",
                details={"range_m": d, "sionna_db": link.path_gain_db, "eq68_db": eq68, "sigma_m2": sigma},
            )
        )
        lines.append((f"Eq. 68, SBR sigma at {aspect:g} deg ({10 * np.log10(sigma):.1f} dBsm)", d, eq68))
        points.append((f"Sionna RT, azimuth {aspect:g} deg", d, link.path_gain_db, None))
    s.figures.append(
        curves(
            "links_radar_sbr_range_curve",
            f"Radar link to the SBR-PO drone, {f:g} GHz",
            axes=PlotAxes("range [m]", "P_rx / (P_tx G_tx G_rx) [dB]", log_x=True),
            lines=lines,
            points=points,
        )
    )
    s.table += [
        {"azimuth_deg": a, "elevation_deg": e, "rcs_dbsm": 10 * np.log10(table["rcs_m2"][i, j])}
        for i, a in enumerate(SBR_AZIMUTHS_DEG)
        for j, e in enumerate(SBR_ELEVATIONS_DEG)
    ]
    return s


def link_accuracy(budgets) -> Section:
    """Accuracy against time of the RF link over ground and the radar link in free space."""
    from csuas.render.links.budget import PRESETS
    from csuas.validation.links.accuracy import accuracy_vs_time

    s = Section()
    chosen = _budgets(budgets)
    for link, kwargs in (
        ("rf", {"frequency_ghz": 2.4}),
        ("radar", {"frequency_ghz": 10.0, "height_a_m": 5.0, "height_b_m": 10.0}),
    ):
        rows, elapsed = timed(accuracy_vs_time, link, budgets=chosen, repeats=1, **kwargs)
        for r in rows:
            r["samples_label"] = r["samples"]
        s.figures.append(
            plot_accuracy(
                f"links_{link}_accuracy_vs_time",
                f"Sionna RT {link} link over {GROUND}: error vs time",
                rows,
                columns=AccuracyColumns("samples", "max_error_db", error_label="largest |error| vs closed form [dB]"),
                caption="Warm wall time per solve; labels: rays per source.",
                presets={name: b.samples for name, b in PRESETS.items()},
            )
        )
        best = [r for r in rows if r["budget"] in ("draft", "standard")]
        for r in best:
            s.outcomes.append(
                Check(
                    f"links.{link}.accuracy.{r['budget']}.max_error_db",
                    0.0,
                    r["max_error_db"],
                    TOLERANCE_DB,
                    "dB",
                    time_s=r["time_s"],
                    source="two-ray / four-path closed form",
                    method=f"budget {r['budget']}: {r['samples']} rays, depth {r['max_depth']}",
                    details={"cold_time_s": r["cold_time_s"], "paths_found": r["paths_found"]},
                )
            )
        s.table += [{"link": link, **r} for r in rows]
        s.notes.append(f"{link}: accuracy sweep {elapsed:.1f} s")
    return s


#: Rays per replica of the terrain radio maps per report quality; the accuracy sweep runs up to it.
TERRAIN_MAP_SAMPLES = {"quick": 2**18, "full": 2**22}


def _map_accuracy_figure(rows: list, replicas: int):
    """The flat-ground radio map's median error and bound against rays per replica and wall time."""
    from csuas.render.links.terrain_map import BOUND_LEVEL

    return plot_accuracy(
        "links_terrain_map_accuracy_vs_time",
        "Radio map over flat ground: error vs rays per replica",
        rows,
        columns=AccuracyColumns(
            "samples",
            "median_abs_error_db",
            error_label="median |error| vs two-ray power sum [dB]",
            stderr_key="median_bound_db",
            stderr_label=f"median {BOUND_LEVEL:.0%} bound [dB]",
        ),
        caption=f"{replicas} replicas per map; wall time of the whole map.",
    )


def terrain_radio_maps(samples: int) -> Section:
    """Sionna radio maps over a flat DEM (two-ray model, power sum) and over a ridge (viewshed), with their cost."""
    from csuas.validation.links.terrain_map import accuracy_vs_samples, flat_ground_comparison, ridge_line_of_sight

    s = Section()
    flat = flat_ground_comparison(samples)
    result = flat["result"]
    s.outcomes += _flat_map_checks(flat, samples)
    s.outcomes += _ridge_checks(ridge_line_of_sight(samples), samples)
    s.figures.append(_flat_profile_figure(flat))
    exponents = range(14, int(np.log2(samples)) + 1, 2)
    rows, elapsed = timed(accuracy_vs_samples, [2**e for e in exponents])
    s.figures.append(_map_accuracy_figure(rows, result.replicas))
    s.table += [{"map": "flat", **r} for r in rows]
    s.notes.append(
        f"map vs coherent two-ray (lobes): median |difference| {flat['coherent_median_abs_db']:.2f} dB, "
        f"95th percentile {flat['coherent_p95_abs_db']:.2f} dB; accuracy sweep {elapsed:.1f} s"
    )
    return s


def _flat_map_checks(flat: dict, samples: int) -> list:
    """The flat DEM's map against the two-ray power sum: its median error within the median bound, and the
    fraction of cells the bound misses within the stated coverage."""
    from csuas.render.links.terrain_map import BOUND_LEVEL, STATED_COVERAGE
    from csuas.validation.links.terrain_map import FLAT

    result = flat["result"]
    scene = (
        f"{FLAT['frequency_ghz']:g} GHz, {FLAT['polarization']} polarisation, {FLAT['mast_m']:g} m mast, "
        f"flight level {FLAT['altitude_m']:g} m, {FLAT['shape'][0]} x {FLAT['shape'][1]} cells of "
        f"{FLAT['cell_m']:g} m over {FLAT['ground']}"
    )
    method = f"Sionna RT RadioMapSolver, {result.replicas} rotated replicas of {samples} rays, {scene}"
    common = {
        "median_bound_db": flat["median_bound_db"],
        "p95_abs_error_db": flat["p95_abs_error_db"],
        "reliable_fraction": flat["reliable_fraction"],
        "coherent_median_abs_db": flat["coherent_median_abs_db"],
        "coherent_p95_abs_db": flat["coherent_p95_abs_db"],
    }
    return [
        Check(
            "links.terrain_map.flat.median_abs_error_db",
            0.0,
            flat["median_abs_error_db"],
            flat["median_bound_db"],
            "dB",
            error_estimate=flat["median_bound_db"],
            time_s=result.time_s,
            source="two-ray model, power sum |h_direct|^2 + |h_ground|^2 averaged over each cell "
            "(csuas.render.links.two_ray, Gauss-Legendre)",
            method=method,
            tolerance_source=f"the median of the replicas' {BOUND_LEVEL:.0%} bound over the same cells",
            details=common,
        ),
        Check(
            "links.terrain_map.flat.bound_miss_fraction",
            0.0,
            1.0 - flat["coverage"],
            1.0 - STATED_COVERAGE,
            "-",
            time_s=result.time_s,
            source="two-ray model, power sum averaged over each cell",
            method=f"fraction of the reliable cells whose |error| exceeds the error bound; {method}",
            tolerance_source=f"the bound is stated to cover {STATED_COVERAGE:.0%} of the cells",
            details={"coverage": flat["coverage"], **common},
        ),
    ]


def _ridge_checks(ridge: dict, samples: int) -> list:
    """The ridge's direct-ray map against the viewshed: no hidden cell lit (exact), few seen cells dark (Poisson)."""
    from csuas.validation.links.terrain_map import RIDGE, dark_tolerance

    ridge_method = (
        f"direct rays only, {RIDGE['ridge_height_m']:g} m ridge {RIDGE['ridge_col'] * RIDGE['cell_m']:g} m from a "
        f"{RIDGE['mast_m']:g} m mast, flight level {RIDGE['altitude_m']:g} m, {ridge['cells']} cells off the "
        f"viewshed's edge; {samples} rays x {ridge['result'].replicas} replicas"
    )
    ridge_details = {
        "agreement": ridge["agreement"],
        "agreement_all_cells": ridge["agreement_all"],
        "edge_cells": int(ridge["edge"].sum()),
        "expected_dark": ridge["expected_dark"],
    }
    return [
        Check(
            "links.terrain_map.ridge.hidden_cells_lit",
            0.0,
            float(ridge["hidden_lit"]),
            0.0,
            "cells",
            time_s=ridge["time_s"],
            source="R2 viewshed (csuas.core.terrain.viewshed), radio k = 4/3",
            method=ridge_method,
            tolerance_source="exact: no straight ray crosses the terrain",
            details=ridge_details,
        ),
        Check(
            "links.terrain_map.ridge.visible_cells_dark",
            0.0,
            float(ridge["visible_dark"]),
            dark_tolerance(ridge["expected_dark"]),
            "cells",
            time_s=ridge["time_s"],
            source="R2 viewshed (csuas.core.terrain.viewshed), radio k = 4/3",
            method=ridge_method,
            tolerance_source="seen cells whose solid angle Omega catches no ray: the Poisson estimate "
            "sum exp(-K N Omega / 4 pi) times DARK_EXCESS (the lattice's measured excess), plus 3 standard deviations",
            details=ridge_details,
        ),
    ]


def _flat_profile_figure(flat: dict):
    """The flat map along the transmitter's row against the two-ray model: coherent at points and per cell,
    power sum per cell, and every third cell of the map with its bound."""
    from csuas.render.links.terrain_map import BOUND_LEVEL
    from csuas.render.links.two_ray import two_ray_path_gain_db
    from csuas.validation.links.terrain_map import FLAT

    result = flat["result"]
    row = int(FLAT["tx_row"])
    d = flat["distance_m"][row]
    fine = np.linspace(50.0, d[-1], 8000)  # 4 points or more per lobe of the coherent sum beyond 50 m
    f = FLAT["frequency_ghz"]
    eta = ground_permittivity(result.extra, f)
    points = two_ray_path_gain_db(f, fine, FLAT["mast_m"], FLAT["altitude_m"], eta, FLAT["polarization"])
    return curves(
        "links_terrain_map_flat_profile",
        f"Radio map over flat ground vs two-ray, {f:g} GHz {FLAT['polarization']}",
        axes=PlotAxes("distance from the mast [m]", "path gain [dB]"),
        lines=[
            ("two-ray, coherent, at points", fine, points),
            ("two-ray, coherent, cell average", d, flat["coherent_db"][row]),
            ("two-ray, power sum, cell average", d, flat["power_db"][row]),
        ],
        points=[  # every third cell, so the power-sum line shows between them
            (
                f"Sionna radio map, {BOUND_LEVEL:.0%} bound",
                d[::3],
                result.path_gain_db[row][::3],
                result.error_db[row][::3],
            )
        ],
        caption="Sionna's radio map adds the rays' powers: it follows the power sum, not the lobes and nulls "
        "(every third cell shown).",
    )


#: The report section of these checks.
GROUP = CheckGroup(
    "links",
    "Sionna RT links vs Friis and the radar equation",
    40,
    "Sionna RT path gains and radar links against Friis, two-ray, Eq. 68 and four-path closed forms, and "
    "their accuracy against the sample budget.",
)


SPECS = [
    CheckSpec(
        "links.rf",
        "Friis and two-ray vs Sionna RT path gain",
        GROUP,
        "closed-form RF path gain vs Sionna RT PathSolver (free space and flat ITU ground)",
        f"{TOLERANCE_DB} dB: both are exact for these scenes; float32 geometry limits the agreement",
        rf_links,
        "Sionna sample budget",
        BUDGETS,
        True,
    ),
    CheckSpec(
        "links.radar",
        "Radar equation and four-path model vs Sionna RT radar link",
        GROUP,
        "Eq. 68 and the four-path ground model vs Sionna RT RCSSolver with the drone as sensing target",
        f"{TOLERANCE_DB} dB (exact scenes)",
        radar_links,
        "Sionna sample budget",
        BUDGETS,
        True,
    ),
    CheckSpec(
        "links.radar_sbr",
        "Radar link with the SBR-PO drone as Sionna sensing target",
        GROUP,
        "Sionna RT radar link whose RCS function interpolates the drone's SBR-PO table vs Eq. 68 with "
        "the SBR sigma at that aspect",
        f"{TOLERANCE_DB} dB (table nodes are exact)",
        radar_sbr_link,
        "SBR rays per wavelength",
        SBR_RAYS_PER_WAVELENGTH,
        True,
    ),
    CheckSpec(
        "links.accuracy",
        "Sionna RT accuracy vs time over the sample budget",
        GROUP,
        "error against the closed form per sample budget, with its wall time",
        f"presets draft and standard within {TOLERANCE_DB} dB",
        link_accuracy,
        "budgets swept",
        SWEEPS,
        True,
    ),
    CheckSpec(
        "links.terrain_map",
        "Sionna RT radio maps over terrain vs the two-ray model and the viewshed",
        GROUP,
        "RadioMapSolver on a DEM mesh: a flat DEM against the two-ray power sum averaged per cell (error and "
        "coverage of the replicas' bound), a ridge's direct-ray map against the viewshed",
        "flat: the replicas' own bound (median and coverage); ridge: exact for lit hidden cells, a Poisson bound "
        "for dark seen cells",
        terrain_radio_maps,
        "Sionna rays per replica",
        TERRAIN_MAP_SAMPLES,
        True,
    ),
]
