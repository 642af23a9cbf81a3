"""Radar cross-section of the drone as a function of aspect, for Sionna RT sensing targets.

A table sigma(azimuth, elevation) [m^2] (e.g. from the SBR-PO engine of
``csuas.render.rcs``) is interpolated bilinearly in sigma, periodically in
azimuth when the table covers the full circle. Angles follow docs/command-line.md: in
the drone's body frame (+x forward, +y left, +z up), azimuth from +x toward
+y and elevation from the xy-plane, of the direction *from the target toward
the sensor*.

Sionna RT evaluates a target's cross-section for an incident direction of
propagation k_i and a scattered one k_s (target frame). A monostatic table
is used for a bistatic pair through the bisector b = (k_s - k_i)/|k_s - k_i|
(monostatic-bistatic equivalence, Crispin, Goodrich & Siegel 1959; Kell,
Proc. IEEE 53(8), 1965), which is exact for monostatic paths and a fair
approximation for the small bistatic angles of ground-bounce paths.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError

#: Default cross-section [m^2] (the paper's Table 8, sigma_radar).
DEFAULT_SIGMA_M2 = 0.01


class RCSTable:
    """Bilinear interpolation of sigma(azimuth, elevation) [m^2].

    Parameters
    ----------
    azimuth_deg : array_like, shape (n_az,)
        Strictly increasing azimuths [deg] spanning at most 360 deg. When
        they cover the full circle (last - first + step >= 360; a closing
        column at first + 360 is accepted)
        interpolation wraps around; otherwise values are clamped at the ends.
    elevation_deg : array_like, shape (n_el,)
        Strictly increasing elevations [deg] in [-90, 90]; clamped at the ends.
    sigma_m2 : array_like, shape (n_az, n_el)
        Cross-sections [m^2], finite and >= 0.
    """

    def __init__(self, azimuth_deg, elevation_deg, sigma_m2):
        az = np.asarray(azimuth_deg, dtype=float)
        el = np.asarray(elevation_deg, dtype=float)
        sigma = np.asarray(sigma_m2, dtype=float)
        if (
            az.ndim != 1
            or az.size < 1
            or not np.all(np.isfinite(az))
            or np.any(np.diff(az) <= 0)
            or az[-1] - az[0] > 360.0 + 1e-9
        ):
            raise ParameterError("azimuth_deg", azimuth_deg, "a strictly increasing 1-D array spanning <= 360 deg")
        if el.ndim != 1 or el.size < 1 or np.any(np.diff(el) <= 0) or el[0] < -90.0 or el[-1] > 90.0:
            raise ParameterError("elevation_deg", elevation_deg, "a strictly increasing 1-D array in [-90, 90] deg")
        if sigma.shape != (az.size, el.size) or not np.all(np.isfinite(sigma)) or np.any(sigma < 0):
            raise ParameterError(
                "sigma_m2", f"array of shape {sigma.shape}", f"finite values >= 0 of shape ({az.size}, {el.size})"
            )
        step = np.diff(az).min() if az.size > 1 else 360.0
        self.periodic = az.size > 1 and az[-1] - az[0] + step >= 360.0 - 1e-6
        if self.periodic and az[-1] - az[0] < 360.0 - 1e-9:
            az = np.append(az, az[0] + 360.0)
            sigma = np.vstack([sigma, sigma[:1]])
        self.azimuth_deg, self.elevation_deg, self.sigma_m2 = az, el, sigma

    @staticmethod
    def _locate(grid, x):
        """Index of the left node and the weight of the right one, clamped to the grid."""
        if grid.size == 1:
            return np.zeros(x.shape, int), np.zeros(x.shape)
        x = np.clip(x, grid[0], grid[-1])
        i = np.clip(np.searchsorted(grid, x, side="right") - 1, 0, grid.size - 2)
        return i, (x - grid[i]) / (grid[i + 1] - grid[i])

    def __call__(self, azimuth_deg, elevation_deg):
        """Cross-section [m^2] at the given aspects (broadcast)."""
        az, el = np.broadcast_arrays(np.asarray(azimuth_deg, float), np.asarray(elevation_deg, float))
        if self.periodic:
            az = self.azimuth_deg[0] + np.mod(az - self.azimuth_deg[0], 360.0)
        i, wi = self._locate(self.azimuth_deg, az)
        j, wj = self._locate(self.elevation_deg, el)
        s = self.sigma_m2
        i1 = np.minimum(i + 1, s.shape[0] - 1)
        j1 = np.minimum(j + 1, s.shape[1] - 1)
        return (1 - wi) * (1 - wj) * s[i, j] + wi * (1 - wj) * s[i1, j] + (1 - wi) * wj * s[i, j1] + wi * wj * s[i1, j1]


def as_rcs_function(rcs):
    """Turn a constant [m^2], an :class:`RCSTable` or a callable f(az_deg, el_deg) into a callable.

    Raises
    ------
    ParameterError
        For a negative or non-finite constant, or anything else that is not callable.
    """
    if rcs is None:
        rcs = DEFAULT_SIGMA_M2
    if callable(rcs):
        return rcs
    try:
        value = float(rcs)
    except (TypeError, ValueError):
        raise ParameterError(
            "rcs", rcs, "sigma >= 0 [m^2], an RCSTable or a callable f(azimuth_deg, elevation_deg)"
        ) from None
    if not (np.isfinite(value) and value >= 0):
        raise ParameterError("rcs", rcs, "sigma >= 0 [m^2], an RCSTable or a callable f(azimuth_deg, elevation_deg)")
    return lambda azimuth_deg, elevation_deg: np.full(np.broadcast(azimuth_deg, elevation_deg).shape, value)


def bisector_aspect(k_i, k_s):
    """Azimuth and elevation [deg] of the bisector (k_s - k_i) of propagation directions (..., 3)."""
    b = np.asarray(k_s, float) - np.asarray(k_i, float)
    norm = np.linalg.norm(b, axis=-1)
    b = b / np.where(norm > 0, norm, 1.0)[..., None]
    azimuth = np.degrees(np.arctan2(b[..., 1], b[..., 0]))
    elevation = np.degrees(np.arcsin(np.clip(b[..., 2], -1.0, 1.0)))
    return azimuth, elevation
