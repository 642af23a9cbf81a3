"""Scattering of thin straight PEC wires by the method of moments (the drone's wiring, k a << 1).

Physical optics, which the SBR engine applies to every facet, is an asymptotic theory for bodies
large against the wavelength; a wire of radius ``a`` with ``k a`` of 0.02-0.3 (AWG 20 copper at
2.4-35 GHz) scatters through the current that flows along it, with resonances near half-wave
lengths that PO misses, and PO of its faceted tube is wrong by large factors. This module solves
the electric field integral equation of thin wires instead (Harrington, *Field Computation by
Moment Methods*, 1968, ch. 4; Balanis, *Antenna Theory*, 4th ed., 2016, sec. 8.3-8.4):

    t . E^s(I) = -t . E^i  on each wire axis,
    E^s = -j omega mu int I t' G dl' + 1/(j omega eps) grad int (dI/dl') G dl',

with the *reduced* (thin-wire) kernel ``G = exp(-j k R) / (4 pi R)``, ``R^2 = |r - r'|^2 + a^2``
(the current on the source wire's surface seen from the observation wire's axis; the NEC
convention, Burke and Poggio 1981). The current of each wire is expanded in triangle (piecewise
linear) functions on ``N`` equal segments, zero at the wire's ends, and tested with the same
functions (Galerkin, mixed-potential form after integrating the gradient by parts):

    Z_mn = j k eta [ int int (t_m . t_n) f_m f_n G - k^-2 int int f_m' f_n' G ],   Z I = V,
    V_m  = int f_m t_m . p_t exp(j k d . r) dl,

(time convention ``exp(j omega t)``; the incident wave ``p_t exp(j k d . r)`` comes from the
radar in direction ``d``). The integrals are Gauss-Legendre sums; on the same wire the static part
``1 / (4 pi R)`` of the source integral is done in closed form (``asinh`` and ``R``) so that the
kernel's peak of width ``a`` is exact. The far field in direction ``s`` with receive polarisation
``p_r`` is

    S = -(j k eta / 4 pi) U^T I,    U_m = int f_m t_m . p_r exp(j k s . r) dl,

the scattering amplitude of :mod:`csuas.render.rcs.engine` (``E_s r e^{jkr}`` for a unit incident
field, ``sigma = 4 pi |S|^2``), phase-referenced to the same origin as the engine's target.

Every wire is a separate open wire (no junctions) of one radius, perfectly conducting: AWG 20
copper's surface resistance adds about ``R_s / (2 pi a)`` = 5 ohm/m at 2.4 GHz to a half-wave
dipole's 73 ohm radiation resistance over a few centimetres (< 0.05 dB); insulation is ignored.
All wires of a target are solved together, so their mutual coupling (parallel leads 2 mm apart)
is in the answer; their coupling with the body (the board's ground plane, the shell they sit in)
is not.

Error estimate. The solution on ``N`` segments is compared with the one on ``ceil(N / 2)``. The
amplitude converges about linearly in the segment length (the current's square-root behaviour at
the open ends): each halving shrinks the change by a ratio of 0.5-0.7 on dipoles of 0.1-1.5
wavelengths (measured), so the error left after ``N`` segments, a geometric tail ``d r / (1 - r)``
of the last change ``d``, is below ``d`` for ``r <= 1/2`` and below ``2 d`` for ``r <= 2/3``. The bound
is ``ERROR_FACTOR d`` with :data:`ERROR_FACTOR` = 2, checked against solutions on eight times as
many segments in ``tests/test_thin_wire.py``.

References
----------
- R. F. Harrington, *Field Computation by Moment Methods*, Macmillan, 1968, ch. 4 (wire objects).
- C. A. Balanis, *Antenna Theory: Analysis and Design*, 4th ed., Wiley, 2016, ch. 8.
- G. J. Burke and A. J. Poggio, *Numerical Electromagnetics Code (NEC)*, LLNL, 1981, part I.
- E. F. Knott, J. F. Shaeffer and M. T. Tuley, *Radar Cross Section*, 2nd ed., SciTech, 2004,
  sec. 3 (resonant dipole 0.86 lambda^2); J. H. Van Vleck, F. Bloch and M. Hamermesh, J. Appl.
  Phys. 18, 274 (1947).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.units import wavenumber_rad_m
from csuas.drone_models.geometry import direction_vector

#: Segments per wavelength of the fine solution; a wire gets at least :data:`MIN_SEGMENTS`.
SEGMENTS_PER_WAVELENGTH = 40
#: Fewest segments of a wire on the fine solution (the coarse one of the error estimate has half).
MIN_SEGMENTS = 8
#: Gauss-Legendre points per segment, for both the observation and the source integral (8 points change the
#: Mini 4 Pro wires' amplitude at 9.4 and 24 GHz by at most 7e-4 of itself, a half-wave dipole's by 1.2e-4).
GAUSS_POINTS = 4
#: Bound of the amplitude's discretisation error in units of the change from ceil(N / 2) to N segments.
ERROR_FACTOR = 2.0
#: Largest (segment x segment x point) block held at once [elements] (its temporaries about 64 MB).
BLOCK_ELEMENTS = 1_000_000
#: CPU time of filling and factorising the fine and the coarse system per squared segment count [s]: the DJI
#: Mini 4 Pro's wires at 9.4, 24 and 35 GHz (336, 860 and 1256 segments) took 3.0-3.2e-6 s (one process, 2 shared
#: cores at load 12, 4 Gauss points).
SECONDS_PER_SEGMENT_PAIR = 3.3e-6
#: Memory per squared segment count [B]: four (S, S) complex pair integrals and the matrix.
BYTES_PER_SEGMENT_PAIR = 80.0


@dataclass(frozen=True)
class ThinWires:
    """Straight thin wires: axes from ``start_m`` to ``end_m`` (N, 3) [m] and radii ``radius_m`` (N,) [m]."""

    start_m: np.ndarray
    end_m: np.ndarray
    radius_m: np.ndarray

    def __len__(self) -> int:
        return len(self.radius_m)

    @property
    def length_m(self) -> np.ndarray:
        """Length of each wire (N,) [m]."""
        return np.linalg.norm(self.end_m - self.start_m, axis=1)

    def shifted(self, offset_m) -> ThinWires:
        """The same wires moved by ``offset_m`` (3,) [m]."""
        offset = np.asarray(offset_m, float)
        return ThinWires(self.start_m + offset, self.end_m + offset, self.radius_m)

    @classmethod
    def of(cls, start_m, end_m, radius_m) -> ThinWires:
        """Checked wires: distinct end points, radii > 0 and below a tenth of the length.

        Raises
        ------
        ParameterError
            Coincident end points, a non-positive radius or one too thick for the thin-wire kernel.
        """
        start = np.atleast_2d(np.asarray(start_m, float))
        end = np.atleast_2d(np.asarray(end_m, float))
        radius = np.broadcast_to(np.asarray(radius_m, float), (len(start),)).copy()
        length = np.linalg.norm(end - start, axis=1)
        bad = ~(np.isfinite(length) & (length > 0.0))
        if bad.any():
            raise ParameterError("wire.end_m", end[bad][0].tolist(), "a finite point different from start_m")
        if not (np.isfinite(radius).all() and (radius > 0.0).all() and (radius <= 0.1 * length).all()):
            raise ParameterError("wire.radius_m", radius.tolist(), "0 < radius <= length / 10")
        return cls(start, end, radius)

    @classmethod
    def concatenate(cls, parts: list[ThinWires]) -> ThinWires:
        """All wires of ``parts`` (at least one set) as one set."""
        return cls(*(np.concatenate([getattr(p, n) for p in parts]) for n in ("start_m", "end_m", "radius_m")))


def wire_of_cylinder(vertices) -> ThinWires:
    """The axis and radius of a faceted cylinder's vertices (V, 3) [m] (:func:`drone_models.parts.cylinder_between`).

    The axis is the direction of largest spread (principal axis), its ends the extreme projections;
    the radius is the largest distance of a vertex from the axis (the polygon's circumradius).
    """
    v = np.asarray(vertices, float)
    centre = v.mean(axis=0)
    axis = np.linalg.svd(v - centre, full_matrices=False)[2][0]
    along = (v - centre) @ axis
    radial = np.linalg.norm(v - centre - along[:, None] * axis, axis=1)
    return ThinWires.of(centre + along.min() * axis, centre + along.max() * axis, radial.max())


@dataclass(frozen=True)
class _Segments:
    """Equal segments of every wire, and which segments each triangle function spans."""

    wire: np.ndarray  # (S,) wire index
    start: np.ndarray  # (S, 3) [m]
    tangent: np.ndarray  # (S, 3)
    length: np.ndarray  # (S,) [m]
    offset: np.ndarray  # (S,) position of the segment's start along its wire [m]
    radius: np.ndarray  # (S,) [m]
    rising: np.ndarray  # (B,) segment on which basis b rises (shape u)
    falling: np.ndarray  # (B,) segment on which basis b falls (shape 1 - u)


def _segments(wires: ThinWires, counts: np.ndarray) -> _Segments:
    """Segments of ``counts[w]`` equal pieces on wire ``w``; a triangle function on every inner node."""
    counts = np.asarray(counts, np.int64)
    wire = np.repeat(np.arange(len(wires)), counts)
    first = np.cumsum(counts) - counts
    local = np.arange(int(counts.sum())) - first[wire]
    lengths = wires.length_m
    tangent = (wires.end_m - wires.start_m) / lengths[:, None]
    seg_len = (lengths / counts)[wire]
    offset = local * seg_len
    start = wires.start_m[wire] + tangent[wire] * offset[:, None]
    inner = np.concatenate([first[w] + np.arange(1, counts[w]) for w in range(len(wires))]).astype(np.int64)
    return _Segments(wire, start, tangent[wire], seg_len, offset, wires.radius_m[wire], inner - 1, inner)


def _gauss() -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(GAUSS_POINTS)
    return 0.5 * (x + 1.0), 0.5 * w


#: Points of the azimuthal average of the exact kernel (Gauss-Legendre in t, phi = pi t^2).
RING_POINTS = 16


def _ring() -> tuple[np.ndarray, np.ndarray]:
    """Nodes (2 a sin(phi / 2) / a) and weights of (1 / pi) int_0^pi d phi, clustered at phi = 0 (phi = pi t^2)."""
    x, w = np.polynomial.legendre.leggauss(RING_POINTS)
    t = 0.5 * (x + 1.0)
    return 2.0 * np.sin(0.5 * math.pi * t**2), w * t


def _static_shape_integrals(lo: np.ndarray, length: float, radius: float) -> np.ndarray:
    """(1 / pi) int_0^pi int phi_b(u') / R dl' d phi (2, ...) over a segment, R^2 = x^2 + 4 a^2 sin^2(phi / 2).

    The exact kernel's static part on a wire's own surface, in closed form along the wire (``asinh``,
    ``R``) and by quadrature around it; ``lo`` is the segment's start minus the observation point
    along the axis [m]. ``asinh(x / rho) = sign(x) (ln(|x| + sqrt(x^2 + rho^2)) - ln rho)`` and the
    average of ``ln rho`` is ``ln a``, so the log singularity at ``phi = 0`` is taken out exactly.
    """
    rho, weight = _ring()
    rho = radius * rho
    hi = lo + length

    def mean(values):
        return np.tensordot(values, weight, axes=([-1], [0]))

    def asinh_mean(x):
        return np.sign(x) * (mean(np.log(np.abs(x)[..., None] + np.hypot(x[..., None], rho))) - math.log(radius))

    i0 = asinh_mean(hi) - asinh_mean(lo)
    i1 = mean(np.hypot(hi[..., None], rho) - np.hypot(lo[..., None], rho))
    rise = (i1 - lo * i0) / length
    return np.stack([i0 - rise, rise])


def _pair_integrals(seg: _Segments, k: float) -> np.ndarray:
    """P[a, b, s, s'] = int_s int_s' phi_a phi_b G dl dl' (2, 2, S, S).

    Between wires the reduced kernel; on one wire the exact kernel's static part
    (:func:`_static_shape_integrals`) plus the reduced kernel's smooth rest ``(exp(-j k R) - 1) / (4 pi R)``.
    """
    u, w = _gauss()
    shapes = np.stack([1.0 - u, u])  # (2, q)
    n = len(seg.length)
    src = seg.start[:, None, :] + seg.tangent[:, None, :] * (u[None, :, None] * seg.length[:, None, None])
    src_weights = shapes[:, None, :] * (w * seg.length[:, None])[None]  # (2, S, q)
    out = np.zeros((2, 2, n, n), complex)
    block = max(1, BLOCK_ELEMENTS // (n * GAUSS_POINTS))
    for lo in range(0, n, block):
        rows = np.arange(lo, min(n, lo + block))
        same = seg.wire[rows][:, None] == seg.wire[None, :]
        for i in range(GAUSS_POINTS):
            obs = seg.start[rows] + seg.tangent[rows] * (u[i] * seg.length[rows])[:, None]
            dist = np.sqrt(((obs[:, None, None, :] - src[None]) ** 2).sum(-1) + seg.radius[None, :, None] ** 2)
            kernel = (np.exp(-1j * k * dist) - same[..., None]) / (4.0 * math.pi * dist)
            inner = np.einsum("rsq,bsq->brs", kernel, src_weights)
            out[:, :, rows, :] += (shapes[:, i] * w[i])[:, None, None, None] * (
                seg.length[rows][None, None, :, None] * inner[None]
            )
    for wire in np.unique(seg.wire):
        own = np.flatnonzero(seg.wire == wire)
        length, radius = float(seg.length[own[0]]), float(seg.radius[own[0]])
        z_obs = seg.offset[own][:, None] + u[None, :] * length  # (n, q)
        lo = seg.offset[own][None, None, :] - z_obs[:, :, None]  # (n, q, n)
        static = _static_shape_integrals(lo, length, radius) / (4.0 * math.pi)  # (2, n, q, n)
        out[np.ix_([0, 1], [0, 1], own, own)] += length * np.einsum("aq,q,bnqm->abnm", shapes, w, static)
    return out


def impedance_matrix(seg: _Segments, k: float) -> np.ndarray:
    """Z / (j k eta) (B, B) of the module docstring's Galerkin system [m]."""
    pairs = _pair_integrals(seg, k)
    sides = (seg.falling, seg.rising)  # shape 0 (1 - u) sits on the falling segment, shape 1 (u) on the rising
    slopes = (-1.0, 1.0)
    cosines = seg.tangent @ seg.tangent.T
    charge = pairs.sum(axis=(0, 1)) / np.outer(seg.length, seg.length)
    z = np.zeros((len(seg.rising),) * 2, complex)
    for a in (0, 1):
        for b in (0, 1):
            block = (cosines * pairs[a, b] - slopes[a] * slopes[b] * charge / k**2)[np.ix_(sides[a], sides[b])]
            z += block
    return z


def _moments(seg: _Segments, k: float, directions: np.ndarray, polarisations: np.ndarray) -> np.ndarray:
    """int f_m t_m . p exp(j k d . r) dl (B, D, P) for directions (D, 3) and their polarisations (D, P, 3)."""
    u, w = _gauss()
    points = seg.start[:, None, :] + seg.tangent[:, None, :] * (u[None, :, None] * seg.length[:, None, None])
    phase = np.exp(1j * k * np.einsum("sqc,dc->sqd", points, directions))  # (S, q, D)
    projections = np.einsum("sc,dpc->sdp", seg.tangent, polarisations)  # (S, D, P)
    falling = np.einsum("q,sqd->sd", (1.0 - u) * w, phase) * seg.length[:, None]
    rising = np.einsum("q,sqd->sd", u * w, phase) * seg.length[:, None]
    return (
        falling[seg.falling][..., None] * projections[seg.falling]
        + rising[seg.rising][..., None] * projections[seg.rising]
    )


def segment_counts(wires: ThinWires, frequency_ghz: float, per_wavelength: float = SEGMENTS_PER_WAVELENGTH):
    """Segments of each wire (N,): ``per_wavelength`` per wavelength, at least :data:`MIN_SEGMENTS`."""
    k = float(wavenumber_rad_m(frequency_ghz))
    return np.maximum(MIN_SEGMENTS, np.ceil(wires.length_m * k / (2.0 * math.pi) * per_wavelength)).astype(np.int64)


def estimate_cost(wires: ThinWires, frequency_ghz) -> tuple[float, float]:
    """Time [s] and peak memory [B] of :func:`wire_field` at the given frequencies, before any work.

    The fill of the fine and the coarse system dominates (:data:`SECONDS_PER_SEGMENT_PAIR`); the right-hand
    sides of the aspects cost far less. Memory: the largest frequency's arrays plus one block's temporaries.
    """
    seconds, peak = 0.0, 0.0
    for f in np.unique(np.atleast_1d(np.asarray(frequency_ghz, float))):
        counts = segment_counts(wires, float(f))
        pairs = float(counts.sum()) ** 2 + float(((counts + 1) // 2).sum()) ** 2
        seconds += SECONDS_PER_SEGMENT_PAIR * pairs
        peak = max(peak, BYTES_PER_SEGMENT_PAIR * float(counts.sum()) ** 2 + 64.0 * BLOCK_ELEMENTS)
    return seconds, peak


_FACTORS: dict = {}


def _factorised(wires: ThinWires, k: float, counts) -> tuple[_Segments, tuple]:
    """Segments and the LU factors of their impedance matrix, kept for the last few wire sets and wavenumbers.

    A sphere average calls the solver once per batch of aspects at the same frequency: the matrix is
    filled and factorised once.
    """
    from scipy.linalg import lu_factor

    counts = np.asarray(counts, np.int64)
    key = (wires.start_m.tobytes(), wires.end_m.tobytes(), wires.radius_m.tobytes(), k, counts.tobytes())
    if key not in _FACTORS:
        seg = _segments(wires, counts)
        if len(_FACTORS) >= 8:
            _FACTORS.clear()
        _FACTORS[key] = (seg, lu_factor(impedance_matrix(seg, k)))
    return _FACTORS[key]


def scattering_amplitude(wires: ThinWires, frequency_ghz: float, incidence, observe, counts=None) -> np.ndarray:
    """Scattering amplitude S (J, M, 2, 2) [m] of the wires at one frequency (module docstring).

    Parameters
    ----------
    wires : ThinWires
        Wire axes and radii [m], in the frame (and about the origin) of the field they join.
    frequency_ghz : float
        Frequency [GHz].
    incidence : tuple of ndarray (J,), (J,)
        Azimuth and elevation toward the transmitter [deg].
    observe : tuple of ndarray (J, M), (J, M)
        Azimuth and elevation toward the receivers [deg] (the incidence for monostatic).
    counts : array_like (N,), optional
        Segments of each wire; default :func:`segment_counts`.

    Returns
    -------
    ndarray complex (J, M, 2, 2)
        Receive (V, H) x transmit (V, H), as :class:`csuas.render.rcs.engine.TraceResult` amplitudes.
    """
    from scipy.linalg import lu_solve

    from .geometry import polarisation_basis  # geometry holds the targets' wires: imported here, not at the top

    k = float(wavenumber_rad_m(frequency_ghz))
    seg, factors = _factorised(wires, k, segment_counts(wires, frequency_ghz) if counts is None else counts)
    az, el = (np.asarray(x, float) for x in incidence)
    oaz, oel = (np.asarray(x, float) for x in observe)
    v_hat, h_hat = polarisation_basis(az, el)
    sent = _moments(seg, k, direction_vector(az, el), np.stack([v_hat, h_hat], axis=1))  # (B, J, 2)
    currents = lu_solve(factors, sent.reshape(len(seg.rising), -1)).reshape(sent.shape)
    ov, oh = polarisation_basis(oaz.ravel(), oel.ravel())
    received = _moments(seg, k, direction_vector(oaz.ravel(), oel.ravel()), np.stack([ov, oh], axis=1))
    received = received.reshape(len(seg.rising), *oaz.shape, 2)  # (B, J, M, 2)
    return -np.einsum("bjmr,bjt->jmrt", received, currents) / (4.0 * math.pi)


def wire_field(wires: ThinWires, frequency_ghz, incidence, observe) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude (J, M, 2, 2) of the wires for jobs of any frequency, and its error bound (module docstring).

    Parameters
    ----------
    wires : ThinWires
    frequency_ghz : ndarray (J,)
        Frequency of each job [GHz].
    incidence, observe
        As :func:`scattering_amplitude`, one row per job.

    Returns
    -------
    amplitude : ndarray complex (J, M, 2, 2)
        On :func:`segment_counts` segments.
    error : ndarray (J, M, 2, 2)
        ``ERROR_FACTOR |S_N - S_ceil(N/2)|`` [m], the bound of the amplitude's discretisation error.
    """
    freq = np.asarray(frequency_ghz, float)
    az, el = (np.asarray(x, float) for x in incidence)
    oaz, oel = (np.asarray(x, float) for x in observe)
    amplitude = np.zeros((len(freq), oaz.shape[1], 2, 2), complex)
    error = np.zeros(amplitude.shape)
    for f in np.unique(freq):
        jobs = freq == f
        counts = segment_counts(wires, f)
        args = ((az[jobs], el[jobs]), (oaz[jobs], oel[jobs]))
        fine = scattering_amplitude(wires, f, *args, counts=counts)
        coarse = scattering_amplitude(wires, f, *args, counts=(counts + 1) // 2)
        amplitude[jobs], error[jobs] = fine, ERROR_FACTOR * np.abs(fine - coarse)
    return amplitude, error
