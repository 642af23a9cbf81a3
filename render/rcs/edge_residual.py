"""What first-order PTD still misses at edges, as a term of the RCS bound.

PO + PTD (:mod:`csuas.render.rcs.edges`) adds the fringe currents of each edge once; it has no
double diffraction (a wave diffracted by one edge that grazes the face to another edge and is
diffracted again), no corner diffraction and no surface waves along the faces. The doubly
diffracted wave is strong where the magnetic field lies along the edges (the *hard*
polarisation: the grazing field on the face does not vanish there; R. A. Ross, "Radar cross
section of rectangular flat plates as a function of aspect angle", IEEE TAP 14(3), 1966) and
weak for the *soft* one (electric field along the edges); P. Ya. Ufimtsev, *Fundamentals of the
Physical Theory of Diffraction*, Wiley 2007, ch. 8 (multiple diffraction). A corner diffracts an
amplitude of order 1/k whatever the edges' lengths (F. A. Sikta, W. D. Burnside, T.-T. Chu and
L. Peters, "First-order equivalent current and corner diffraction scattering from flat plate
structures", IEEE TAP 31(4), 1983). This module does not model those waves; it bounds what they
can add, from what the engine knows of each edge:

    R_rt = sum over straight edge lines L of |sum_{e in L} g_e| (C_HARD w_h + C_SOFT w_s)
           + C_CORNER N_corners / (4 pi k),
    g_e = l_e sinc(k (s + d_i) . t l_e / 2) e^{j k (s + d_i) . m_e} / (4 pi),
    w_h = |(h_r . t)(h_t . t)| / sin^2 beta',      w_s = |(e_r . t)(e_t . t)| / sin^2 beta',

with ``l_e``, ``t``, ``m_e`` a visible edge segment's length, tangent and midpoint, ``beta'`` the
angle between the incidence ``d_i`` and the edge, ``s`` the direction toward the receiver,
``e_t``/``h_t`` the transmitted electric/magnetic field directions and ``e_r``/``h_r`` the
received ones (V: theta-hat/phi-hat, H: phi-hat/theta-hat), and ``N_corners`` the lit corners
(end points where an edge ends, three or more meet, or two meet turning by at least
:data:`CORNER_TURN_DEG`; a faceted curved rim has none). ``g_e`` radiates a unit line current
along the segment, as the fringe currents of :mod:`csuas.render.rcs.edges` do (its sinc is the
phase progression along the edge that a diffracted wave keeps, Keller's cone): summed coherently
along each straight line, in magnitude across lines and corners (the missing waves of different
edges may add in phase). The weights split the edge's coupling into its hard and soft parts
(``w_h + w_s <= 1``). The term of a figure of amplitude ``|A_rt|`` is the relative amplitude
``R_rt / |A_rt|`` (:func:`residual_relative`), ``-20 log10(1 - R/|A|)`` in dB, added to the
other terms by :func:`csuas.render.rcs.model_error.total_bound_db`; it is infinite (no bound)
where the missing waves could outweigh the result. Near a face's specular flash ``|A|`` is large
and the term small (0.6 dB on a plate of side two wavelengths at normal incidence; 4-6 dB in VV and
2.7-4 dB in HH at 40-80 deg from the normal in its principal plane).

Calibration (:mod:`csuas.validation.rcs.edge_residual_cases`): the bempp-cl EFIE of square PEC
plates of side 1 and 2 wavelengths at 10 GHz (10 mesh edges per wavelength), 0-80 deg from the
normal (elevations 90-10 deg at azimuths 0 and 45 deg), VV and HH, against SBR-PO + PTD at
reference quality, 72 figures. The coefficients are the least (by a linear programme) for which
the whole bound (discretisation, PO's model term, truncation and this term) covers every
calibration figure (0.482, 0.336, 0.118), rounded up to 0.01. Hard exceeds soft, as the missing
double diffraction predicts. Coverage is tested on other plates (side 1.5, 2.5 and 3 wavelengths,
1 x 1.5, 1 x 2, 2 x 1.5 and 1.5 x 2.5 rectangles, other azimuths; 162 figures per polarisation):
VV 97.5 %, HH 98.8 % (40.7 % and 49.4 % without this term; ``tests/test_rcs_edge_residual.py``). The doubly
diffracted wave decays as ``(k w)^(-1/2)`` with the distance ``w`` across the face (Ross), so on
faces larger than the calibration's the term is conservative; below one wavelength it is not
claimed, nor for curved edges, dielectric edges or wedges other than thin plates (not calibrated).
"""

from __future__ import annotations

import numpy as np
from scipy import sparse

from csuas.core.units import wavenumber_rad_m
from csuas.drone_models.geometry import direction_vector

from .edges import CHUNK_ELEMENTS, SIN_BETA_FLOOR, Edges
from .geometry import polarisation_basis

#: C_HARD of the module docstring: the missing waves' amplitude per unit of a hard edge line's amplitude.
C_HARD = 0.49
#: C_SOFT of the module docstring: the same for the soft part (electric field along the edge).
C_SOFT = 0.34
#: C_CORNER of the module docstring: a lit corner's amplitude in units of 1 / (4 pi k).
C_CORNER = 0.12

#: Rounding of edge directions, offsets and end points when segments are grouped into straight lines and
#: corners [fraction of the largest coordinate].
LINE_TOLERANCE = 1e-6

#: Smallest turn between two edges meeting at a point for the point to be a corner [deg]: a faceted curved
#: rim turns by less at each vertex and has no corners.
CORNER_TURN_DEG = 30.0


def _keys(rows: np.ndarray, scale: float) -> np.ndarray:
    """Index of each row among the distinct rows, after rounding to :data:`LINE_TOLERANCE` of ``scale``."""
    return np.unique(np.round(rows / (LINE_TOLERANCE * scale)).astype(np.int64), axis=0, return_inverse=True)[1].ravel()


def _scale(edges: Edges) -> float:
    return max(float(np.abs(np.concatenate([edges.start, edges.end])).max()), 1e-12)


def edge_lines(edges: Edges) -> np.ndarray:
    """Index (E,) of the straight line each edge segment lies on (same direction and offset)."""
    if len(edges) == 0:
        return np.zeros(0, int)
    t = edges.tangent * np.where(_first_nonzero(edges.tangent) < 0, -1.0, 1.0)[:, None]
    mid = edges.midpoint
    offset = mid - np.sum(mid * t, axis=1)[:, None] * t
    return _keys(np.hstack([t * _scale(edges), offset]), _scale(edges))


def _first_nonzero(vectors: np.ndarray) -> np.ndarray:
    """The first component of each row whose magnitude exceeds 1e-9 (the sign that fixes a direction)."""
    big = np.abs(vectors) > 1e-9
    return vectors[np.arange(len(vectors)), np.argmax(big, axis=1)]


def edge_corners(edges: Edges) -> sparse.csr_matrix:
    """Incidence (E, C) of the edge segments on the corners: end points where one edge ends, three or more
    meet, or two meet turning by at least :data:`CORNER_TURN_DEG`."""
    n = len(edges)
    point = _keys(np.concatenate([edges.start, edges.end]), _scale(edges))  # (2E,) start points, then ends
    outward = np.concatenate([edges.tangent, -edges.tangent])  # from each end point along its edge
    degree = np.bincount(point)
    turn = np.linalg.norm(np.stack([np.bincount(point, outward[:, c]) for c in range(3)], -1), axis=1)
    corner = (degree != 2) | (turn >= 2.0 * np.sin(np.radians(0.5 * CORNER_TURN_DEG)))
    at = corner[point]
    ids = np.cumsum(corner) - 1
    return sparse.csr_matrix(
        (np.ones(int(at.sum())), (np.tile(np.arange(n), 2)[at], ids[point][at])), shape=(n, int(corner.sum()))
    )


def residual_amplitude(
    edges: Edges,
    incident_az_deg,
    incident_el_deg,
    frequency_ghz,
    observe_az_deg,
    observe_el_deg,
    visible=None,
    coefficients: tuple[float, float, float] = (C_HARD, C_SOFT, C_CORNER),
):
    """R_rt of the module docstring (J, M, 2, 2) [m]: the bound of the waves PTD misses, per channel.

    Parameters
    ----------
    edges : Edges
        :func:`csuas.render.rcs.edges.find_edges` of the target.
    incident_az_deg, incident_el_deg, frequency_ghz : array_like (J,)
        Directions toward the transmitter [deg] and frequency [GHz] of each job.
    observe_az_deg, observe_el_deg : array_like (J, M)
        Receiver directions [deg].
    visible : array_like bool (J, M, E), optional
        Edges lit and seen (:func:`csuas.render.rcs.edges.edge_visibility`); default all.
    coefficients : (float, float, float)
        (C_HARD, C_SOFT, C_CORNER); the calibration passes unit vectors to get the three parts apart.

    Returns
    -------
    ndarray (J, M, 2, 2)
        Receive (V, H) x transmit (V, H), the convention of
        :attr:`csuas.render.rcs.solver.RcsResult.sigma_m2`; zero without edges.
    """
    az, el, f = (np.atleast_1d(np.asarray(x, float)) for x in (incident_az_deg, incident_el_deg, frequency_ghz))
    oaz, oel = np.asarray(observe_az_deg, float), np.asarray(observe_el_deg, float)
    out = np.zeros((len(az), oaz.shape[1], 2, 2))
    if len(edges) == 0:
        return out
    lines = edge_lines(edges)
    groups = (sparse.csr_matrix((np.ones(len(edges)), (np.arange(len(edges)), lines))), edge_corners(edges))
    step = max(1, CHUNK_ELEMENTS // (oaz.shape[1] * len(edges)))
    for j0 in range(0, len(az), step):
        js = slice(j0, j0 + step)
        vis = np.ones((1, 1, len(edges)), bool) if visible is None else np.asarray(visible, bool)[js]
        out[js] = _residual_chunk(edges, groups, (az[js], el[js], f[js], oaz[js], oel[js]), vis, coefficients)
    return out


def _residual_chunk(edges: Edges, groups, waves, visible, coefficients) -> np.ndarray:
    """R_rt (J, M, 2, 2) of some jobs: line sums weighted by their couplings, plus the lit corners."""
    az, el, f, oaz, oel = waves
    lines, corners = groups
    k = wavenumber_rad_m(f)[:, None, None]
    d_i, s = direction_vector(az, el), direction_vector(oaz, oel)  # (J, 3), (J, M, 3)
    q = s + d_i[:, None, :]
    g = np.where(
        visible,
        edges.length_m
        * np.sinc(0.5 * k * (q @ edges.tangent.T) * edges.length_m / np.pi)
        * np.exp(1j * k * (q @ edges.midpoint.T))
        / (4 * np.pi),
        0.0,
    )  # (J, M, E): a unit line current on each visible segment
    n_j, n_m, n_e = g.shape
    line_sum = np.abs((lines.T @ g.reshape(-1, n_e).T).T).reshape(n_j, n_m, -1)  # (J, M, lines)
    lit_corners = (corners.T @ np.broadcast_to(visible, g.shape).reshape(-1, n_e).T.astype(float)).T > 0
    corner_term = lit_corners.reshape(n_j, n_m, -1).sum(-1) / (4 * np.pi * k[..., 0])  # (J, M)
    t = edges.tangent[np.unique(lines.indices, return_index=True)[1]]  # each line's direction (lines, 3)
    sin2 = np.maximum(1.0 - (d_i @ t.T) ** 2, SIN_BETA_FLOOR**2)[:, None, :]  # (J, 1, lines)
    th_i, ph_i = polarisation_basis(az, el)
    th_s, ph_s = polarisation_basis(oaz, oel)
    # electric and magnetic field directions along the line: transmit (J, 1, lines, pol), receive (J, M, lines, pol)
    e_t = np.stack([th_i @ t.T, ph_i @ t.T], -1)[:, None]
    h_t = e_t[..., ::-1]
    e_r = np.stack([np.einsum("jmc,lc->jml", th_s, t), np.einsum("jmc,lc->jml", ph_s, t)], -1)
    h_r = e_r[..., ::-1]
    c_hard, c_soft, c_corner = coefficients
    weight = (
        c_hard * np.abs(h_r[..., :, None] * h_t[..., None, :]) + c_soft * np.abs(e_r[..., :, None] * e_t[..., None, :])
    ) / sin2[..., None, None]  # (J, M, lines, 2, 2)
    return np.einsum("jml,jmlrt->jmrt", line_sum, weight) + c_corner * corner_term[..., None, None]


def residual_relative(residual_m, sigma_m2) -> np.ndarray:
    """Relative amplitude ``R / |A|`` of the bound term, ``|A| = sqrt(sigma / 4 pi)``.

    0 where R = 0; ``inf`` where A = 0 and R > 0.
    """
    r = np.asarray(residual_m, float)
    amplitude = np.sqrt(np.asarray(sigma_m2, float) / (4 * np.pi))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(r > 0.0, np.where(amplitude > 0.0, r / amplitude, np.inf), 0.0)
