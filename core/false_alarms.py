"""False alarms of a sensor per look and per hour: the per-cell false-alarm probability times its cells.

A threshold detector that tests C independent resolution cells per look, each with false-alarm
probability Pfa, raises on average Pfa * C false alarms per look (a binomial count, Poisson for
small Pfa), and Pfa * C * 3600 / T_revisit per hour. The cells per look by modality:

* radar: range bins x Doppler bins x beams inside its sector and reach, with range bins
  (reach - minimum range) / (c / 2B) and azimuth beams sector / theta_3dB, theta_3dB of a pencil beam
  from its gain, G = 4 pi / theta^2 (Skolnik, *Introduction to Radar Systems*, 3rd ed., Eq. 9.2 with
  unit aperture efficiency);
* EO and thermal cameras: pixels x frames per look;
* RF and acoustic energy detectors: their detector's bins per look, frequency bins (an RF
  channeliser's FFT bins, an acoustic array's frequency bands) x bearing cells (a direction-finding
  receiver's or a beamformer's beams across its sector, each sector / theta, theta from the antenna's
  gain or the array's directivity as above);
* lidar: range gates x beam positions per scan, range gates (reach - minimum range) / gate length.

References
----------
M. I. Skolnik, *Introduction to Radar Systems*, 3rd ed., McGraw-Hill, 2001, Sections 2.5 and 9.2.
M. A. Richards, *Fundamentals of Radar Signal Processing*, 2nd ed., 2014, Section 6.2 (false alarms
per unit time: cells tested per second times Pfa).
"""

from __future__ import annotations

import numpy as np

from csuas.core.checks import require, require_all
from csuas.core.units import C_LIGHT

#: Seconds per hour.
SECONDS_PER_HOUR = 3600.0


def range_resolution_m(bandwidth_mhz):
    """Range resolution of a radar, c / (2 B) [m].

    Parameters
    ----------
    bandwidth_mhz : array_like
        Signal bandwidth B [MHz], > 0.
    """
    b = require("bandwidth_mhz", bandwidth_mhz, gt=0)
    return C_LIGHT / (2.0 * b * 1e6)


def beamwidth_deg(gain_db):
    """Half-power beamwidth of a pencil beam from its gain, theta = sqrt(4 pi / G) [deg] (Skolnik Eq. 9.2).

    Parameters
    ----------
    gain_db : array_like
        Antenna gain [dB], >= 11 dB (a beam no wider than about 1 rad).
    """
    g = require("gain_db", gain_db, ge=11.0)
    return np.degrees(np.sqrt(4.0 * np.pi / 10.0 ** (g / 10.0)))


def radar_cells(reach_m, min_range_m, range_resolution, sector_deg, beam_deg, doppler_bins=1, elevation_beams=1):
    """Resolution cells a radar tests per look inside its sector and reach [-].

    Parameters
    ----------
    reach_m, min_range_m : float
        Instrumented range and the start of the range window [m], reach > min >= 0.
    range_resolution : float
        Range bin [m], > 0 (:func:`range_resolution_m`).
    sector_deg, beam_deg : float
        Azimuth sector (0 < sector <= 360) and beamwidth (> 0) [deg].
    doppler_bins, elevation_beams : int
        Doppler filters per range-beam cell and beams stacked in elevation, >= 1.

    Returns
    -------
    float
        ceil((reach - min) / dR) * doppler_bins * ceil(sector / beam) * elevation_beams.
    """
    reach, low, dr, sector, beam, doppler, elevation = require_all(
        ("reach_m", reach_m, {"gt": 0}),
        ("min_range_m", min_range_m, {"ge": 0}),
        ("range_resolution_m", range_resolution, {"gt": 0}),
        ("sector_deg", sector_deg, {"gt": 0, "le": 360}),
        ("beam_deg", beam_deg, {"gt": 0}),
        ("doppler_bins", doppler_bins, {"ge": 1}),
        ("elevation_beams", elevation_beams, {"ge": 1}),
    )
    require("reach_m", reach, gt=float(low), why="beyond min_range_m")
    range_bins = np.ceil((reach - low) / dr)
    return float(range_bins * doppler * np.ceil(sector / beam) * elevation)


def imaging_cells(n_h, n_v, frames_per_look=1):
    """Pixels a camera tests per look: n_h x n_v x frames [-].

    Parameters
    ----------
    n_h, n_v : int
        Detector pixels across and down, >= 1.
    frames_per_look : int
        Frames read in one look (e.g. the steps that cover a sector wider than the field of view), >= 1.
    """
    h, v, f = require_all(
        ("n_h", n_h, {"ge": 1}), ("n_v", n_v, {"ge": 1}), ("frames_per_look", frames_per_look, {"ge": 1})
    )
    return float(h * v * f)


def receiver_cells(frequency_bins, sector_deg, beam_deg):
    """Cells an RF or acoustic detector tests per look: frequency bins x ceil(sector / beam) [-].

    Parameters
    ----------
    frequency_bins : int
        Frequency bins (RF channeliser) or bands (acoustic) tested at each bearing, >= 1.
    sector_deg, beam_deg : float
        Azimuth sector (0 < sector <= 360) and the width of one bearing cell (> 0) [deg].
    """
    bins, sector, beam = require_all(
        ("frequency_bins", frequency_bins, {"ge": 1}),
        ("sector_deg", sector_deg, {"gt": 0, "le": 360}),
        ("beam_deg", beam_deg, {"gt": 0}),
    )
    return float(bins * np.ceil(sector / beam))


def lidar_cells(reach_m, min_range_m, range_gate_m, beam_positions):
    """Cells a scanning lidar tests per look: ceil((reach - min) / gate) x beam positions [-].

    Parameters
    ----------
    reach_m, min_range_m : float
        Instrumented range and the start of the range window [m], reach > min >= 0.
    range_gate_m : float
        Range gate [m], > 0 (c tau / 2 of the gate tau).
    beam_positions : int
        Beam positions of one scan, >= 1.
    """
    reach, low, gate, positions = require_all(
        ("reach_m", reach_m, {"gt": 0}),
        ("min_range_m", min_range_m, {"ge": 0}),
        ("range_gate_m", range_gate_m, {"gt": 0}),
        ("beam_positions", beam_positions, {"ge": 1}),
    )
    require("reach_m", reach, gt=float(low), why="beyond min_range_m")
    return float(np.ceil((reach - low) / gate) * positions)


def false_alarms_per_look(pfa, cells):
    """Mean false alarms per look, Pfa * cells [-].

    Parameters
    ----------
    pfa : array_like
        False-alarm probability of one cell, 0..1.
    cells : array_like
        Independent cells tested per look, >= 0 (:func:`radar_cells`, :func:`imaging_cells`,
        :func:`receiver_cells`, :func:`lidar_cells`).
    """
    p, c = require_all(("pfa", pfa, {"ge": 0, "le": 1}), ("cells", cells, {"ge": 0}))
    return p * c


def per_hour(per_look, revisit_s):
    """A count per look turned into a rate per hour: per_look * 3600 / T_revisit [1/h].

    Parameters
    ----------
    per_look : array_like
        Mean count per look, >= 0.
    revisit_s : array_like
        Time between looks [s], > 0.
    """
    n, t = require_all(("per_look", per_look, {"ge": 0}), ("revisit_s", revisit_s, {"gt": 0}))
    return n * SECONDS_PER_HOUR / t
