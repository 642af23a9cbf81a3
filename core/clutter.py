"""Ground clutter of a radar: the constant-gamma model, and the false alarms it raises at a fixed threshold.

The reflectivity of land per unit ground area at grazing angle psi follows the constant-gamma model

    sigma0 = gamma sin(psi),

with gamma per land cover from the published table in ``defaults/clutter.toml`` (Barton; Nathanson).
A radar resolution cell of range extent dR and beamwidth theta at range R covers the ground area
A = R theta dR / cos(psi) (pulse-limited, Skolnik 3rd ed., Eq. 7.4), so its clutter RCS is
sigma_c = sigma0 A. Only ground the radar sees contributes: cells hidden by the terrain return none.

With a fixed threshold set for Pfa over noise, a cell whose clutter (Rayleigh amplitude, exponential
power, as Swerling 1) has clutter-to-noise ratio CNR exceeds the square-law threshold with
probability Pfa^(1 / (1 + CNR)) for one pulse (the exponential tail with mean 1 + CNR; Richards,
*Fundamentals of Radar Signal Processing*, 2nd ed., Eq. 6.20), after a Doppler (MTI) filter that
attenuates the clutter by its improvement factor.

References
----------
D. K. Barton, *Radar Equations for Modern Radar*, Artech House, 2013, Section 3.4 (constant gamma,
values of gamma for land).
F. E. Nathanson, *Radar Design Principles*, 2nd ed., McGraw-Hill, 1991, ch. 7.
M. I. Skolnik, *Introduction to Radar Systems*, 3rd ed., 2001, Section 7.4.
"""

from __future__ import annotations

import numpy as np

from csuas.core.checks import require, require_all


def sigma0(gamma_db, grazing_rad):
    """Clutter reflectivity per unit ground area, gamma sin(psi) [m^2/m^2].

    Parameters
    ----------
    gamma_db : array_like
        Gamma of the land cover [dB].
    grazing_rad : array_like
        Grazing angle psi [rad], 0..pi/2 (0: no clutter).
    """
    g, psi = require_all(("gamma_db", gamma_db, {}), ("grazing_rad", grazing_rad, {"ge": 0, "le": np.pi / 2}))
    return 10.0 ** (g / 10.0) * np.sin(psi)


def cell_rcs_m2(gamma_db, grazing_rad, range_m, range_resolution_m, beam_rad):
    """Clutter RCS of one resolution cell, sigma0 R theta dR / cos(psi) [m^2].

    Parameters
    ----------
    gamma_db, grazing_rad
        As in :func:`sigma0`.
    range_m : array_like
        Range of the cell [m], >= 0.
    range_resolution_m : float
        Range extent dR of the cell [m], > 0.
    beam_rad : float
        Azimuth beamwidth theta [rad], > 0.
    """
    r, dr, beam = require_all(
        ("range_m", range_m, {"ge": 0}),
        ("range_resolution_m", range_resolution_m, {"gt": 0}),
        ("beam_rad", beam_rad, {"gt": 0}),
    )
    psi = require("grazing_rad", grazing_rad, ge=0, le=np.pi / 2)
    return sigma0(gamma_db, psi) * r * beam * dr / np.maximum(np.cos(psi), 1e-6)


def exceedance(pfa, cnr, rejection_db=0.0):
    """Probability that a cell of exponential clutter plus noise crosses a noise threshold, Pfa^(1/(1+CNR')) [-].

    Parameters
    ----------
    pfa : float
        False-alarm probability of the threshold over noise alone, 0 < Pfa < 1.
    cnr : array_like
        Clutter-to-noise power ratio [linear], >= 0.
    rejection_db : float
        Clutter attenuation of a Doppler (MTI) filter before the threshold [dB], >= 0; CNR' = CNR 10^(-I/10).
    """
    p, c, i = require_all(
        ("pfa", pfa, {"gt": 0, "lt": 1}), ("cnr", cnr, {"ge": 0}), ("rejection_db", rejection_db, {"ge": 0})
    )
    return p ** (1.0 / (1.0 + c * 10.0 ** (-i / 10.0)))
