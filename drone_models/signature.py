"""Signature figures derived from the projected cross-section: Eqs. 1, 2, 8 and 9."""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError

#: d_crit methods: Eq. 1 ("min") and Eq. 2 ("geometric_mean").
D_CRIT_METHODS = ("min", "geometric_mean")

#: Titterton's rule of thumb k_LCS = 0.1 (paper Section 2.3.6, [48]).
K_LCS_DEFAULT = 0.1


def critical_dimension(d_x_proj_m, d_y_proj_m, method: str = "min"):
    """Critical dimension d_crit [m] of a projected cross-section.

    Parameters
    ----------
    d_x_proj_m, d_y_proj_m : float or array_like
        Horizontal and vertical extents of the projection [m], >= 0.
    method : {"min", "geometric_mean"}
        ``min(d_x, d_y)`` (Eq. 1) or ``sqrt(d_x d_y)`` (Eq. 2).
    """
    dx, dy = np.asarray(d_x_proj_m, dtype=float), np.asarray(d_y_proj_m, dtype=float)
    if np.any(~np.isfinite(dx)) or np.any(dx < 0) or np.any(~np.isfinite(dy)) or np.any(dy < 0):
        raise ParameterError("d_x_proj_m/d_y_proj_m", "negative or non-finite", "finite, >= 0 m")
    if method == "min":
        return np.minimum(dx, dy)
    if method == "geometric_mean":
        return np.sqrt(dx * dy)
    raise ParameterError("d_crit method", method, ", ".join(D_CRIT_METHODS))


def sphere_equivalent_radius(projected_area_m2, t_illum: float = 1.0):
    """Radius r_sphere [m] of the sphere with the same projected area, Eq. 8 solved for r.

    ``A_p = pi r^2 T_illum``  ->  ``r = sqrt(A_p / (pi T_illum))``.
    """
    a = np.asarray(projected_area_m2, dtype=float)
    t = _illumination(t_illum)
    if np.any(~np.isfinite(a)) or np.any(a < 0):
        raise ParameterError("projected_area_m2", "negative or non-finite", "finite, >= 0 m^2")
    return np.sqrt(a / (np.pi * t))


def lcs_estimate(projected_area_m2, k_lcs: float = K_LCS_DEFAULT, t_illum: float = 1.0):
    """Mean lidar cross-section by the projected-area rule, Eqs. 8-9 [m^2].

    ``sigma_lidar = k_LCS * A_p`` with the illuminated area ``A_p = A_geom * T_illum``
    (Eq. 8 with the geometric projected area ``A_geom = pi r_sphere^2``).

    Parameters
    ----------
    projected_area_m2 : float or array_like
        Geometric projected area A_geom [m^2].
    k_lcs : float
        Scaling factor, > 0 (paper: 0.1, Titterton [48]).
    t_illum : float
        Fraction of the target covered by the beam, 0 < T <= 1.
    """
    if not (np.isfinite(k_lcs) and k_lcs > 0):
        raise ParameterError("k_lcs", k_lcs, "finite, > 0")
    a = np.asarray(projected_area_m2, dtype=float)
    if np.any(~np.isfinite(a)) or np.any(a < 0):
        raise ParameterError("projected_area_m2", "negative or non-finite", "finite, >= 0 m^2")
    return k_lcs * a * _illumination(t_illum)


def _illumination(t_illum: float) -> float:
    if not (np.isfinite(t_illum) and 0.0 < t_illum <= 1.0):
        raise ParameterError("t_illum", t_illum, "0 < x <= 1")
    return float(t_illum)
