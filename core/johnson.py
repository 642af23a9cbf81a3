"""Johnson criteria and the target transfer probability function (Eqs. 15-18, 22-23).

Tables 20 and 21 are read from the defaults data (``csuas.defaults``).
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require
from csuas.defaults import load_tables


def _tables():

    return load_tables()


def line_pairs(task):
    """Line pairs across d_crit for a task (Table 20, standard column).

    Parameters
    ----------
    task : str
        ``"detection"`` (1), ``"recognition"`` (4) or ``"identification"`` (8).
    """
    table = _tables()["johnson"]["line_pairs"]
    if task not in table:
        raise ParameterError("task", task, ", ".join(table))
    return float(table[task])


def n_ttpf(p_desired):
    """TTPF multiplier n_TTPF for a desired probability (Table 21).

    Between the tabulated probabilities the multiplier is interpolated
    linearly (the paper gives only the discrete points; linear interpolation
    reproduces them exactly and is monotone).

    Parameters
    ----------
    p_desired : array_like
        Desired probability of task success, 0..1.
    """
    p = require("p_desired", p_desired, ge=0, le=1)
    ttpf = _tables()["johnson"]["ttpf"]
    probs = np.asarray(ttpf["p_desired"], dtype=float)
    mult = np.asarray(ttpf["n_ttpf"], dtype=float)
    order = np.argsort(probs)
    return np.interp(p, probs[order], mult[order])


def ifov_rad(hfov_deg, n_h):
    """Instantaneous field of view of one pixel [rad], Eq. 15: IFOV = HFOV / N_H."""
    h = require("hfov_deg", hfov_deg, gt=0, le=360)
    n = require("n_h", n_h, ge=1)
    return np.deg2rad(h) / n


def ifov_from_pitch_rad(pitch_um, focal_mm):
    """Thermal-camera IFOV [rad] from pixel pitch and focal length, Eq. 22: p / f."""
    p = require("pitch_um", pitch_um, gt=0)
    f = require("focal_mm", focal_mm, gt=0)
    return (p * 1e-6) / (f * 1e-3)


def johnson_range_m(d_crit_m, ifov, lp_task=1.0, n_ttpf=1.0):
    """Johnson / TTPF range [m], Eqs. 17-18 and 23: d_crit / (2 lp n_TTPF IFOV).

    Parameters
    ----------
    d_crit_m : array_like
        Critical dimension [m], >= 0.
    ifov : array_like
        Pixel IFOV [rad] (:func:`ifov_rad` or :func:`ifov_from_pitch_rad`).
    lp_task : array_like
        Line pairs across d_crit (Table 20).
    n_ttpf : array_like
        TTPF multiplier (Table 21); 0 (P_desired = 0) gives an unbounded
        range, returned as +inf.

    Returns
    -------
    ndarray
        Range [m]. The small-angle form of the paper is kept (exact to 1e-6
        relative for targets smaller than 1e-3 rad).
    """
    d = require("d_crit_m", d_crit_m, ge=0)
    i = require("ifov", ifov, gt=0)
    lp = require("lp_task", lp_task, gt=0)
    n = require("n_ttpf", n_ttpf, ge=0)
    denominator = 2.0 * lp * n * i
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(
            denominator == 0, np.where(d > 0, np.inf, 0.0), d / np.where(denominator == 0, 1.0, denominator)
        )
