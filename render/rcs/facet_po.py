"""Exact physical optics of a faceted PEC body, the converged reference of the SBR-PO engine.

For a perfectly conducting body the physical-optics monostatic scattering
amplitude is (Knott, Shaeffer & Tuley, *Radar Cross Section*, 2nd ed., 2004,
Eq. 5.8; Gordon, IEEE TAP 23(4), 1975)

    sigma = (4 pi / lambda^2) | sum_F (n_F . d) I_F |^2,    I_F = integral_F exp(2 j k d . r) dS,

over the facets F whose outward normal ``n_F`` faces the radar direction ``d``
(unit vector from the target toward the radar). Each facet integral is
evaluated in closed form: with the phases ``phi_i = 2 k d . r_i`` at its three
vertices, ``a = phi_1 - phi_0`` and ``b = phi_2 - phi_0``,

    I_F = 2 A_F exp(j phi_0) G(a, b),    G(a, b) = -j (E(a) - E(b)) / (a - b),
    E(x) = (exp(j x) - 1) / (j x),

which is the Hermite-Genocchi form of the second divided difference of
``exp(j x)``; its removable singularities (``a``, ``b`` or ``a - b`` near zero)
are evaluated by their Taylor series. Everything runs in float64 with NumPy,
independently of the ray tracer.

Scope: back-face culling is the only shadowing, so the reference holds for
convex bodies (sphere, almond, plate, finite cylinder) and single reflections;
PO, not the exact solution (the exact sphere is the Mie series).

Users: the validation oracles of the SBR engine (validation/rcs, validation/report/checks_rcs.py)
and the rotor micro-Doppler (:mod:`csuas.render.rcs.micro_doppler`), which needs the complex amplitude
of thin blades at thousands of aspects; it lives in render/ so that both layers can import it.
"""

from __future__ import annotations

import numpy as np

from csuas.core.units import wavelength_m, wavenumber_rad_m
from csuas.drone_models.geometry import direction_vector

#: Below this |x| the exponential quotients use their Taylor series [rad].
_SERIES_BELOW = 1e-3

#: Aspects x facets evaluated at once (bounds the memory of the vectorised sum, about 100 MB).
CHUNK_ELEMENTS = 1_000_000


def _e1(x):
    """E(x) = (exp(jx) - 1)/(jx), 1 at x = 0."""
    x = np.asarray(x, float)
    small = np.abs(x) < _SERIES_BELOW
    safe = np.where(small, 1.0, x)
    series = 1 + 1j * x / 2 - x**2 / 6 - 1j * x**3 / 24
    return np.where(small, series, (np.exp(1j * safe) - 1) / (1j * safe))


def _e1_derivative(x):
    """dE/dx = exp(jx)/x - (exp(jx) - 1)/(j x^2), j/2 at x = 0."""
    x = np.asarray(x, float)
    small = np.abs(x) < _SERIES_BELOW
    safe = np.where(small, 1.0, x)
    series = 0.5j - x / 3 - 1j * x**2 / 8
    exact = np.exp(1j * safe) / safe - (np.exp(1j * safe) - 1) / (1j * safe**2)
    return np.where(small, series, exact)


def simplex_phase_integral(a, b):
    """G(a, b) = integral over the unit simplex of exp(j (a u + b v)) du dv (area 1/2 at a = b = 0).

    Parameters
    ----------
    a, b : array_like
        Phase differences along the two edges from the first vertex [rad].

    Returns
    -------
    ndarray complex
    """
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    diff = a - b
    close = np.abs(diff) < _SERIES_BELOW
    safe = np.where(close, 1.0, diff)
    divided = -1j * (_e1(a) - _e1(b)) / safe
    # a close to b: the divided difference becomes the derivative at the midpoint
    return np.where(close, -1j * _e1_derivative(0.5 * (a + b)), divided)


def facet_po_amplitude(vertices, faces, frequency_ghz: float, azimuth_deg, elevation_deg) -> np.ndarray:
    """PO scattering amplitude ``sum_F (n_F . d) I_F`` [m^2] of a PEC mesh for each aspect.

    Parameters
    ----------
    vertices : array_like (V, 3)
        Vertex positions [m].
    faces : array_like (F, 3)
        Triangles with outward (counter-clockwise seen from outside) winding.
    frequency_ghz : float
        Radar frequency [GHz].
    azimuth_deg, elevation_deg : array_like (A,)
        Directions from the target toward the radar [deg].

    Returns
    -------
    ndarray complex (A,)
        ``sigma = 4 pi |amplitude|^2 / lambda^2``.
    """
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    k = wavenumber_rad_m(frequency_ghz)
    r0, r1, r2 = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    cross = np.cross(r1 - r0, r2 - r0)
    area2 = np.linalg.norm(cross, axis=1)  # twice the facet area
    keep = area2 > 0
    r0, r1, r2, cross, area2 = r0[keep], r1[keep], r2[keep], cross[keep], area2[keep]
    normal = cross / area2[:, None]
    d = np.atleast_2d(direction_vector(np.atleast_1d(azimuth_deg), np.atleast_1d(elevation_deg)))
    out = np.empty(len(d), complex)
    chunk = max(1, CHUNK_ELEMENTS // max(len(normal), 1))
    for first in range(0, len(d), chunk):
        dc = d[first : first + chunk]
        cos_i = dc @ normal.T  # (aspects, facets)
        p0, p1, p2 = (2 * k * (dc @ r.T) for r in (r0, r1, r2))
        integral = area2 * np.exp(1j * p0) * simplex_phase_integral(p1 - p0, p2 - p0)
        out[first : first + chunk] = np.sum(np.where(cos_i > 0, cos_i * integral, 0.0), axis=1)
    return out


def facet_po_sigma_m2(vertices, faces, frequency_ghz: float, azimuth_deg, elevation_deg) -> np.ndarray:
    """Monostatic PO RCS [m^2] of a convex PEC mesh (module docstring), one value per aspect."""
    amplitude = facet_po_amplitude(vertices, faces, frequency_ghz, azimuth_deg, elevation_deg)
    return 4 * np.pi * np.abs(amplitude) ** 2 / wavelength_m(frequency_ghz) ** 2
