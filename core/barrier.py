"""Terrain barrier on an acoustic sensor's path: ISO 9613-2 top-edge diffraction (physical convention).

Where the terrain hides the drone from an acoustic array, the sound still reaches it over the terrain's
top edge, or its first and last edges where it has two (double diffraction), attenuated by A_bar =
D_z - A_gr (ISO 9613-2:1996, Section 7.4, Eqs. 12, 14-18;
:func:`csuas.core.acoustic.iso9613_barrier_db`), z from the terrain profile
(:func:`csuas.core.terrain.diffraction_path_difference_m`). The paper's convention has no diffraction:
a hidden drone is not heard (docs/conventions.md, Point 7).

References
----------
ISO 9613-2:1996 Acoustics - Attenuation of sound during propagation outdoors - Part 2: General method
of calculation.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.acoustic import iso9613_barrier_db, iso9613_barrier_met_factor, iso9613_ground_db
from csuas.core.modality import BY_NAME
from csuas.core.ranges import evaluate
from csuas.core.scenario import Scenario
from csuas.core.terrain import diffraction_path_difference_m


def barrier_frequency_hz(scenario: Scenario, sensor_name: str) -> float | None:
    """Frequency of a sensor's barrier attenuation [Hz]; None where no barrier is simulated.

    An acoustic sensor of the physical convention only: the band detector's band of highest SNR in free
    field (its ``detector_band_hz`` term), the broadband detector's ``frequency_hz``. The band is kept
    behind the barrier (a lower one, which diffracts better, may do better there: the figure errs deaf).
    """
    spec = scenario.sensors[sensor_name]
    if spec.modality != "acoustic" or scenario.convention != "physical":
        return None
    if spec.params["detector"] == "bands":
        return float(np.asarray(evaluate(scenario)[sensor_name].term("detector_band_hz").value))
    return float(spec.params["frequency_hz"])


def terrain_barrier_db(scenario: Scenario, sensor_name: str, dem_m, cell_m: float, eye, targets, slant_m):
    """A_bar = D_z - A_gr [dB] of drones the terrain hides from an acoustic sensor (ISO 9613-2, one or two edges).

    Parameters
    ----------
    scenario, sensor_name
        The scenario and its acoustic sensor (physical convention: :func:`barrier_frequency_hz`).
    dem_m, cell_m, eye, targets
        As :func:`csuas.core.terrain.line_of_sight`: heights [m], cell [m], the sensor's (row, col,
        height [m]) and the drones' (n, 3) (row, col, height [m]).
    slant_m : array_like
        Slant range of each drone [m] (d of K_met, Eq. 18).

    Returns
    -------
    ndarray (n,)
        A_bar [dB]: z and the edge separation e from the profile, K_met from its edge distances; A_gr
        the ground attenuation the free-field model holds at that range (band detector with the
        sensor's ``height_m``), else 0.
    """
    frequency = barrier_frequency_hz(scenario, sensor_name)
    if frequency is None:
        spec = scenario.sensors[sensor_name]
        raise ParameterError(
            f"sensors.{sensor_name}",
            f"{spec.modality} ({scenario.convention})",
            "an acoustic sensor, physical convention",
        )
    k = BY_NAME["acoustic"].line_of_sight.k
    slant = np.asarray(slant_m, float)
    path, d_ss, d_sr, separation = diffraction_path_difference_m(dem_m, cell_m, eye, targets, k)
    k_met = iso9613_barrier_met_factor(path, d_ss, d_sr, slant)
    a_gr = 0.0
    p = scenario.sensors[sensor_name].params
    if p["detector"] == "bands" and p.get("height_m") is not None:
        altitude, g = scenario.target["altitude_m"], scenario.environment["ground_factor"]
        dp = np.sqrt(np.maximum(slant**2 - altitude**2, 1e-4))
        hr = p["height_m"]
        a_gr = iso9613_ground_db(frequency, dp, max(hr + altitude, 0.0), hr, g, g, g)
    return iso9613_barrier_db(frequency, path, k_met, a_gr, separation)
