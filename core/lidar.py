"""Lidar detection range: range equation (Eqs. 87-99) and losses (Eqs. 100-104).

Conventions (docs/conventions.md point 8):

* ``paper``: R = R_max (eta_TL^2 eta_SYS)^(1/4) (Eq. 104) with a given one-way
  transmission factor eta_TL (Table 47: 0.681, from Kruse at V = 3 km over a
  fixed 3 km path in the dB reading of Eq. 10).
* ``physical``: the laser-target interaction I = sigma / max(A_illum, A_p)
  cannot exceed sigma / A_p when the beam footprint is smaller than the target,
  and the two-way transmittance exp(-2 beta R) of the Kruse extinction at the
  actual range is applied; the range is the root of a monotone budget.
"""

from __future__ import annotations

import numpy as np

from csuas.core.atmosphere import extinction_per_km
from csuas.core.checks import require, require_registry_bounds
from csuas.core.result import RangeResult, Term, check_convention, unbounded_reason
from csuas.core.solve import bracketed_root

#: Diffraction factor of a circular aperture (Eq. 87).
AIRY = 1.22


def divergence_rad(wavelength_nm, aperture_mm):
    """Diffraction-limited divergence (Eq. 87) [rad]: 1.22 lambda / d."""
    lam = require("wavelength_nm", wavelength_nm, gt=0) * 1e-9
    d = require("aperture_mm", aperture_mm, gt=0) * 1e-3
    return AIRY * lam / d


def lidar_range_no_loss_m(p_tx_w, p_rx_min_w, sigma_m2, aperture_mm, wavelength_nm):
    """Loss-free lidar range (Eq. 99) [m]."""
    p = require("p_tx_w", p_tx_w, gt=0)
    pmin = require("p_rx_min_w", p_rx_min_w, gt=0)
    s = require("sigma_lidar_m2", sigma_m2, gt=0)
    d = require("aperture_mm", aperture_mm, gt=0) * 1e-3
    lam = require("wavelength_nm", wavelength_nm, gt=0) * 1e-9
    # each factor's fourth root apart: a tiny p_rx_min_w (5e-324 W) gives a large finite range, not p / pmin = inf;
    # what still exceeds float64 is inf, explained by the caller's RangeResult (unbounded_reason)
    with np.errstate(over="ignore", divide="ignore"):
        return (p * s / (AIRY**2 * np.pi)) ** 0.25 * pmin**-0.25 * d / np.sqrt(lam)


def received_power_w(
    p_tx_w,
    sigma_m2,
    aperture_mm,
    wavelength_nm,
    range_m,
    projected_area_m2=None,
    transmittance_two_way=1.0,
    eta_sys=1.0,
):
    """Received power (Eqs. 98, 100, 102) [W].

    With ``projected_area_m2`` the interaction I = sigma / max(A_illum, A_p)
    (physical); without it, I = sigma / A_illum (Eq. 93).
    """
    r = require("range_m", range_m, gt=0)
    d = require("aperture_mm", aperture_mm, gt=0) * 1e-3
    a_illum = np.pi * (r * divergence_rad(wavelength_nm, aperture_mm) / 2.0) ** 2  # Eq. 92
    area = a_illum if projected_area_m2 is None else np.maximum(a_illum, projected_area_m2)
    interaction = np.asarray(sigma_m2, float) / area  # Eq. 89
    efficiency = d**2 / (4.0 * r**2)  # Eq. 97
    return np.asarray(p_tx_w, float) * interaction * efficiency * transmittance_two_way * eta_sys


#: Arguments of :func:`lidar_range` -> their defaults/parameters.toml entries (upper bounds checked).
LIDAR_REGISTRY = {
    "p_tx_w": "lidar.p_tx_w",
    "p_rx_min_w": "lidar.p_rx_min_w",
    "sigma_lidar_m2": "target.sigma_lidar_m2",
    "aperture_mm": "lidar.aperture_mm",
    "wavelength_nm": "lidar.wavelength_nm",
    "eta_sys": "lidar.eta_sys",
    "eta_tl": "lidar.eta_tl",
    "visibility_km": "environment.visibility_km",
    "projected_area_m2": "target.projected_area_m2",
}


def lidar_range(
    *,
    p_tx_w,
    p_rx_min_w,
    sigma_lidar_m2,
    aperture_mm,
    wavelength_nm,
    eta_sys=0.5,
    eta_tl=None,
    visibility_km=None,
    projected_area_m2=None,
    convention="paper",
) -> RangeResult:
    """Lidar detection range [m] with transmission and system losses (Eqs. 99-104).

    Parameters
    ----------
    p_tx_w, p_rx_min_w : array_like
        Transmit power and minimum detectable power [W] (Table 45).
    sigma_lidar_m2 : array_like
        Target LCS [m^2] (Table 8).
    aperture_mm, wavelength_nm : array_like
        Aperture diameter [mm] and wavelength [nm] (Table 45).
    eta_sys : array_like
        System efficiency (Table 47).
    eta_tl : array_like, optional
        One-way transmission factor (paper convention, Table 47); None: no transmission loss.
    visibility_km : array_like, optional
        Visibility for the Kruse extinction (physical convention); None: clear path.
    projected_area_m2 : array_like, optional
        Target projected area A_p [m^2] bounding the interaction (physical convention).
    convention : {"paper", "physical"}
    """
    require_registry_bounds(locals(), LIDAR_REGISTRY, lower=("wavelength_nm",))  # a beam needs a wavelength
    check_convention(convention)
    r0 = lidar_range_no_loss_m(p_tx_w, p_rx_min_w, sigma_lidar_m2, aperture_mm, wavelength_nm)
    e_sys = require("eta_sys", eta_sys, gt=0, le=1)
    terms = [Term("range_no_loss_m", r0, "m", "Eq. 99"), Term("eta_sys", e_sys, "-", "Eq. 103")]
    if convention == "paper":
        factor = e_sys
        if eta_tl is not None:
            e_tl = require("eta_tl", eta_tl, gt=0, le=1)
            factor = factor * e_tl**2
            terms.append(Term("eta_tl", e_tl, "-", "Eq. 101 (Table 47)"))
        r = r0 * factor**0.25  # Eq. 104
        return RangeResult(r, "lidar", "lidar_range_equation (Eqs. 99, 104)", terms, unbounded_reason(r))
    beta = 0.0 if visibility_km is None else extinction_per_km(wavelength_nm, visibility_km, "physical")
    if visibility_km is not None:
        terms.append(
            Term("kruse_extinction_per_km", beta, "1/km", "Eqs. 19-20, continuous (docs/conventions.md point 12)")
        )
    if projected_area_m2 is not None:
        terms.append(Term("projected_area_m2", np.asarray(projected_area_m2, float), "m^2", "Eq. 8"))
    p_min = np.asarray(p_rx_min_w, float)

    def residual(log_r):
        rr = np.exp(log_r)
        tau2 = np.exp(-2.0 * np.asarray(beta) * rr / 1000.0)
        p = received_power_w(p_tx_w, sigma_lidar_m2, aperture_mm, wavelength_nm, rr, projected_area_m2, tau2, e_sys)
        with np.errstate(divide="ignore"):  # far out, the two-way extinction underflows to 0 W: log = -inf
            return np.log(p) - np.log(p_min)

    # The loss-free range with the efficiency bounds the root from above; 1 um from below.
    hi = np.log(np.maximum(r0 * e_sys**0.25, 1e-6) * 1.0000001)
    hi = np.broadcast_to(hi, np.broadcast_shapes(np.shape(hi), np.shape(beta), np.shape(p_min))).copy()
    lo = np.full(hi.shape, np.log(1e-6))
    log_r, found = bracketed_root(residual, lo, hi)
    r = np.where(found, np.exp(log_r), np.where(residual(lo) < 0, 0.0, np.exp(hi)))
    if visibility_km is not None:
        terms.append(Term("eta_tl_at_range", np.exp(-np.asarray(beta) * r / 1000.0), "-", "Beer-Lambert over R"))
    model = "lidar_range_equation (Eq. 98, bounded interaction, two-way Beer-Lambert)"
    return RangeResult(r, "lidar", model, terms, unbounded_reason(r))
