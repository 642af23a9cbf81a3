"""The ``[radio_map]`` table of a coverage site: RF and radar coverage with multipath over the terrain.

A site that declares it gets, for each RF or radar sensor it names and each flight level, a Sionna RT
radio map over a mesh of the DEM (:func:`csuas.render.links.terrain_map.terrain_radio_map`: path gain
with its error bound) and, from it, where the sensor detects with the terrain's reflections and
shadows (:func:`csuas.core.coverage.multipath_detection`), beside the line-of-sight layers. A site
without the table builds no radio map. Keys (all optional; docs/coverage.md):

``sensors``      RF or radar sensors of the site to map (default: all of them)
``ground``       ITU-R P.2040 material of the terrain (default ``medium_dry_ground``, 1-10 GHz), or a
                 table ``{relative_permittivity, conductivity_s_m}`` of its constants at any frequency
``step``         DEM cells per side of a measurement block (default 4)
``samples``      rays per replica (default 2^20), or
``accuracy_db``  the bound asked of the path gain on 90 % of the visible cells: rays doubled from 2^20
``max_depth``    reflections per path (default 2)
``seed``         seed of the replicas (default 1)
"""

from __future__ import annotations

import sys
import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.coverage import link_frequency_ghz, multipath_detection
from csuas.core.terrain import cells_around
from csuas.render.site_schema import RadioMapTable

#: Keys of a ground given by its constants (instead of an ITU material's name).
GROUND_CONSTANTS = ("relative_permittivity", "conductivity_s_m")
#: The radio map covers the square around the sensor out to this many times its mapped reach
#: (:func:`csuas.core.coverage.mapped_reach_m`): reflections adding up to 4 times the direct power (6 dB)
#: stay inside; cells beyond are not mapped (NaN in the multipath layers).
MAP_REACH_FACTOR = 2.0
#: Share of the visible cells that must meet ``accuracy_db``, and the largest rays per replica tried for it.
ACCURACY_FRACTION = 0.9
ACCURACY_MAX_SAMPLES = 2**23


def radio_map_settings(site, scenario) -> dict | None:
    """The radio-map settings of a validated site (:class:`~csuas.render.site_schema.SiteSchema`);
    None without a ``[radio_map]`` table."""
    if site.radio_map is None:
        return None
    settings = site.radio_map.model_dump()
    if settings["sensors"] is None:
        settings["sensors"] = _radio_sensors(site.sensors, scenario)
    if isinstance(settings["ground"], dict):
        settings["ground"] = tuple(settings["ground"][key] for key in GROUND_CONSTANTS)
    return settings


def _radio_sensors(sited, scenario) -> list:
    return [n for n in sited if n in scenario.sensors and scenario.sensors[n].modality in ("rf", "radar")]


def _ground_errors(ground, names: list, scenario) -> list:
    """The ground against the mapped sensors' carriers (an ITU material) or its constants' domain."""
    from csuas.render.links.scene import ground_properties, itu_materials

    errors = []
    if isinstance(ground, dict) and set(ground) == set(GROUND_CONSTANTS):
        try:
            ground_properties(tuple(ground[key] for key in GROUND_CONSTANTS), 1.0)
        except (ParameterError, TypeError) as exc:
            errors.append(ParameterError("radio_map.ground", ground, getattr(exc, "allowed", "numbers")))
    elif isinstance(ground, str) and ground not in itu_materials():
        allowed = "an ITU material (" + ", ".join(itu_materials()) + ") or {" + ", ".join(GROUND_CONSTANTS) + "}"
        errors.append(ParameterError("radio_map.ground", ground, allowed))
    elif isinstance(ground, str):
        for name in names:  # each sensor's carrier inside the material's frequency ranges
            try:
                ground_properties(ground, link_frequency_ghz(scenario, name))
            except ParameterError as exc:
                errors.append(ParameterError(f"radio_map.ground (for {name})", exc.value, exc.allowed))
    return errors


def _mapped_sensors(table: dict, sited: dict, scenario) -> tuple[list, list]:
    """(the RF and radar sensors the table maps, the errors of its ``sensors``)."""
    radio = _radio_sensors(sited, scenario)
    names = table.get("sensors", radio)
    if not isinstance(names, list):
        return [], []  # the schema names it
    errors = []
    if not names or any(n not in radio for n in names):
        found = ", ".join(radio) or "none on this site"
        errors.append(ParameterError("radio_map.sensors", names, f"RF or radar sensors of the site: {found}"))
    return [n for n in names if n in radio], errors


def _height_errors(site: dict, sited: dict, names: list) -> list:
    """Masts and flight levels above the terrain: a radio map's antennas and measurement surfaces."""
    errors = []
    for name in names:
        mast = sited[name].get("mast_m", 10.0) if isinstance(sited[name], dict) else None
        if isinstance(mast, (int, float)) and mast <= 0:
            errors.append(ParameterError(f"sensors.{name}.mast_m", mast, "above 0 m for a radio map"))
    altitudes = site.get("altitudes_agl_m", [30.0, 120.0])
    if isinstance(altitudes, list) and any(isinstance(a, (int, float)) and a <= 0 for a in altitudes):
        errors.append(ParameterError("altitudes_agl_m", altitudes, "flight levels above 0 m for a radio map"))
    return errors


def sector_window(aimed: np.ndarray, window: tuple[slice, slice], row: float, col: float) -> tuple[slice, slice]:
    """The part of ``window`` bounding the cells of ``aimed`` (the azimuth sector) and the sensor at (row, col).

    A sensor between cell centres keeps the cells around it, where its transmitter stands.
    """
    inside = aimed[window]
    rows = window[0].start + np.nonzero(inside.any(axis=1))[0]
    cols = window[1].start + np.nonzero(inside.any(axis=0))[0]
    low_row, high_row = min(rows.min(), int(np.floor(row))), max(rows.max(), int(np.ceil(row)))
    low_col, high_col = min(cols.min(), int(np.floor(col))), max(cols.max(), int(np.ceil(col)))
    return (
        slice(max(low_row, window[0].start), min(high_row + 1, window[0].stop)),
        slice(max(low_col, window[1].start), min(high_col + 1, window[1].stop)),
    )


def radio_map_errors(site: dict, scenario) -> list:
    """What a site's ``[radio_map]`` asks that its scenario or sensors cannot give (the schema checks types)."""
    table = site.get("radio_map")
    if not isinstance(table, dict):
        return []
    sited = site.get("sensors") if isinstance(site.get("sensors"), dict) else {}
    names, errors = _mapped_sensors(table, sited, scenario)
    ground = table.get("ground", RadioMapTable.model_fields["ground"].default)
    return errors + _ground_errors(ground, names, scenario) + _height_errors(site, sited, names)


def radio_map_layers(dem, cell_m: float, scenario, sited: dict, altitudes, per_sensor: dict, settings: dict) -> dict:
    """Radio maps and multipath detection of each mapped sensor, per flight level.

    Returns
    -------
    dict
        Per sensor: ``path_gain_db``, ``error_db`` (float, (A, rows, cols); NaN where no ray came),
        ``detected`` (1/0) and ``pd`` (:func:`csuas.core.coverage.multipath_detection`; NaN, unknown,
        in the line of sight where some replica got no ray: too few rays to judge, and beyond the
        mapped square, ``MAP_REACH_FACTOR`` times the sensor's mapped reach, or outside the sensor's
        azimuth sector; the map's square is cut to the sector's bounding box, and its rays leave and
        its measurement surface lies only over the sector: :class:`RadioMapSite` ``sector_deg``) and
        ``maps`` (per
        flight level: rays per replica, replicas, time [s], the share of visible cells that are
        reliable, the median bound over them, the unknown cells, and the comparison with the
        line-of-sight layer over the judged cells).
    """
    from csuas.render.links.terrain_map import RadioMapOptions, RadioMapSite, radio_map_budget, terrain_radio_map

    layers = {}
    for name in settings["sensors"]:
        placed, los = sited[name], per_sensor[name]
        frequency = link_frequency_ghz(scenario, name)
        options = RadioMapOptions(
            ground=settings["ground"],
            samples=settings["samples"],
            max_depth=settings["max_depth"],
            seed=settings["seed"],
            step=settings["step"],
        )
        radius = max(MAP_REACH_FACTOR * los["reach_m"] / cell_m, 1.0)  # at least 2 x 2 cells
        square = cells_around(dem.shape, placed.row, placed.col, radius)
        window = sector_window(los["aimed"], square, placed.row, placed.col)
        origin = (window[0].start, window[1].start)
        gains, bounds, detected, pd, maps = [], [], [], [], []
        for i, altitude in enumerate(altitudes):
            print(f"csuas coverage: {name} radio map at {altitude:g} m ...", file=sys.stderr, flush=True)
            start = time.perf_counter()
            row, col = placed.row - origin[0], placed.col - origin[1]
            sector = None if placed.sector_deg >= 360.0 else (placed.azimuth_deg, placed.sector_deg)
            where = RadioMapSite(dem[window], cell_m, row, col, placed.mast_m, altitude, frequency, sector)
            if settings["accuracy_db"] is None:
                result = terrain_radio_map(where, options)
            else:
                _, result = radio_map_budget(
                    settings["accuracy_db"],
                    where,
                    options,
                    fraction=ACCURACY_FRACTION,
                    judged=los["visible"][i][window],
                    start_samples=min(settings["samples"], ACCURACY_MAX_SAMPLES),
                    max_samples=ACCURACY_MAX_SAMPLES,
                )
            mapped = np.zeros(dem.shape, dtype=bool)
            mapped[window] = los["aimed"][window]  # the sensor's sector only, as its line of sight
            gain, error = np.full(dem.shape, -np.inf), np.full(dem.shape, np.inf)
            reached, reliable_map = np.zeros(dem.shape, dtype=bool), np.zeros(dem.shape, dtype=bool)
            measured = result.extra["in_sector"]  # outside it the map is NaN: not traced
            gain[window] = np.where(measured, result.path_gain_db, -np.inf)
            error[window] = np.where(measured, result.error_db, np.inf)
            reached[window], reliable_map[window] = result.reached, result.reliable
            seen, hit = multipath_detection(scenario, name, gain, los["regard"][i] & mapped)
            visible = los["visible"][i]
            reliable = reliable_map & visible
            unknown = visible & ~reliable_map & mapped  # a direct path exists, but too few rays came to judge it
            judged = los["regard"][i] & mapped & ~unknown
            gains.append(np.where(reached & mapped, gain, np.nan))
            bounds.append(np.where(reached & mapped & np.isfinite(error), error, np.nan))
            detected.append(np.where(unknown | ~mapped, np.nan, seen.astype(float)))
            pd.append(np.where(unknown | ~mapped, np.nan, hit))
            maps.append(
                {
                    "altitude_m": altitude,
                    "frequency_ghz": frequency,
                    "samples": result.budget.samples,
                    "replicas": result.replicas,
                    "time_s": time.perf_counter() - start,
                    "reliable_visible_fraction": float(reliable.sum() / max(int(visible.sum()), 1)),
                    "unknown_cells": int(unknown.sum()),
                    "mapped_cells": int(mapped.sum()),
                    "median_bound_db": float(np.median(error[reliable])) if reliable.any() else None,
                    "agreement_with_line_of_sight": float(np.mean((seen == los["detected"][i])[judged]))
                    if judged.any()
                    else None,
                    "detected_only_with_multipath_cells": int((seen & ~los["detected"][i] & ~unknown).sum()),
                    "detected_only_in_line_of_sight_cells": int((~seen & los["detected"][i] & ~unknown).sum()),
                }
            )
        layers[name] = {
            "path_gain_db": np.array(gains),
            "error_db": np.array(bounds),
            "detected": np.array(detected),
            "pd": np.array(pd),
            "maps": maps,
        }
    return layers
