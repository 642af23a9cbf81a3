"""Coverage of a site: where each sensor sees, detects and how likely, per flight level, and fused.

For a sensor on a mast at a DEM cell and a drone at ``altitude`` above the terrain of every cell:

* *visible*: line of sight over the terrain with the Earth's curvature and the modality's refraction
  (:func:`csuas.core.terrain.viewshed`; k = 4/3 for radio and radar, the optical value for EO,
  thermal and lidar, 1 for sound, whose refraction the model leaves out);
* *detected*: visible and within the sensor's predicted detection range (:mod:`csuas.core.ranges`) at
  the slant distance from its eye to the drone;
* *Pd*: the sensor's probability of detection at that slant distance (:mod:`csuas.core.pd_curves`),
  0 where hidden;
* per sensor, the *minimum detectable altitude* of each cell (the lowest flight level detected);
* fused: the number of sensors detecting each cell, their OR, and the OR of their Pd.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csuas.core.horizon import K_OPTICAL, K_RADIO
from csuas.core.pd_curves import sensor_pd
from csuas.core.ranges import evaluate
from csuas.core.scenario import Scenario
from csuas.core.terrain import height_at, viewshed

#: Effective Earth-radius factor of each modality's line of sight.
K_FACTOR = {"rf": K_RADIO, "radar": K_RADIO, "eo": K_OPTICAL, "tir": K_OPTICAL, "lidar": K_OPTICAL, "acoustic": 1.0}


@dataclass(frozen=True)
class SitedSensor:
    """A scenario sensor placed on the site: its cell position and mast height."""

    name: str
    row: float
    col: float
    mast_m: float


def sensor_layers(dem_m: np.ndarray, cell_m: float, scenario: Scenario, sited: SitedSensor, altitudes_m) -> dict:
    """Visible, detected and Pd grids (altitude, rows, cols) of one sensor, and its minimum detectable altitude.

    Returns
    -------
    dict
        ``visible`` and ``detected`` (bool), ``pd`` (float), each (A, rows, cols); ``min_altitude_m``
        (rows, cols; NaN where no flight level is detected); ``range_m`` (the sensor's predicted range).
    """
    spec = scenario.sensors[sited.name]
    reach = float(np.asarray(evaluate(scenario)[sited.name].range_m))
    rows, cols = np.indices(dem_m.shape)
    ground = np.hypot(rows - sited.row, cols - sited.col) * cell_m
    eye = float(height_at(dem_m, np.array([sited.row]), np.array([sited.col]))[0]) + sited.mast_m  # as the viewshed
    visible, detected, pd = [], [], []
    for altitude in altitudes_m:
        seen = viewshed(dem_m, cell_m, sited.row, sited.col, sited.mast_m, altitude, K_FACTOR[spec.modality])
        slant = np.hypot(ground, dem_m + altitude - eye)
        prob = sensor_pd(scenario, sited.name, slant.ravel()).pd.reshape(dem_m.shape)
        visible.append(seen)
        detected.append(seen & (slant <= reach))
        pd.append(np.where(seen, prob, 0.0))
    detected_arr = np.array(detected)
    altitudes = np.asarray(altitudes_m, float)
    first = np.argmax(detected_arr, axis=0)
    min_altitude = np.where(detected_arr.any(axis=0), altitudes[first], np.nan)
    return {
        "visible": np.array(visible),
        "detected": detected_arr,
        "pd": np.array(pd),
        "min_altitude_m": min_altitude,
        "range_m": reach,
    }


def fused_layers(per_sensor: dict) -> dict:
    """Fused grids over sensors (altitude, rows, cols): ``count`` detecting, ``detected`` (OR), ``pd`` (OR of Pd)."""
    detected = np.array([layers["detected"] for layers in per_sensor.values()])
    pd = np.array([layers["pd"] for layers in per_sensor.values()])
    return {
        "count": detected.sum(axis=0),
        "detected": detected.any(axis=0),
        "pd": 1.0 - np.prod(1.0 - pd, axis=0),
    }
