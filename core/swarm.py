"""Swarms: N drones in a formation and what a sensor resolves of them (docs/scenarios.md "Swarms").

A formation is N offsets from the target's position in the frame of the line of sight: x along it (away
from the sensor), y across it horizontally, z up [m]. Two drones share one resolution cell of a sensor when
they are closer than its cell along every axis; the drones a sensor cannot tell apart are the connected
groups of that relation (single linkage), each seen as one merged target.

- Radar: range resolution c / (2 B) along x; cross-range resolution R theta_3 across (y, z), the 3 dB
  beamwidth of a pencil beam from the receive gain, theta_3 = sqrt(4 pi / G) (both
  :mod:`csuas.core.false_alarms`, as the engagement model's cells; theta_az = theta_el). The merged target's RCS is the
  coherent sum of N random-phase returns: mean N sigma, its amplitude Rayleigh for large N (Swerling 1/2,
  Skolnik, *Radar Handbook*, 3rd ed. 2008, sec. 2.4).
- EO and TIR: a drone of size d at range R spans d / (R IFOV) pixels, IFOV = HFOV / N_H; two drones'
  blobs merge when the gap between them is under one pixel, |Delta| < d + R IFOV across the line of sight
  (y and z); the merged blob's critical dimension is the square root of its bounding box's area (the
  NVESD convention of Eq. 1's d_crit).
- Acoustic: N incoherent sources of equal level add 10 log10 N dB (Kinsler et al., *Fundamentals of
  Acoustics*, 4th ed. 2000, sec. 5.12).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components


@dataclass(frozen=True)
class Formation:
    """N drones' offsets from the target [m] (x along the line of sight, y across it, z up).

    Attributes
    ----------
    offsets_m : ndarray, shape (N, 3)
    kind : str
        ``line`` (``count`` and ``spacing_m``) or ``offsets`` (``offsets_m``).
    """

    offsets_m: np.ndarray
    kind: str

    @property
    def count(self) -> int:
        """Number of drones."""
        return int(self.offsets_m.shape[0])

    @property
    def spacing_m(self) -> float | None:
        """Spacing of a ``line`` formation [m] (None for explicit offsets)."""
        return float(self.offsets_m[1, 1] - self.offsets_m[0, 1]) if self.kind == "line" else None


def line_formation(count: int, spacing_m: float) -> Formation:
    """The default formation: ``count`` drones ``spacing_m`` apart on a line along y, centred on the target."""
    y = (np.arange(count) - (count - 1) / 2.0) * spacing_m
    return Formation(np.column_stack([np.zeros(count), y, np.zeros(count)]), "line")


def link_range_m(offsets_m, along_cell_m: float, across_cell_m: float, across_per_m: float) -> np.ndarray:
    """Range beyond which each pair of drones shares one resolution cell [m] (N x N).

    Two drones share a cell at range R when |dx| < ``along_cell_m`` and max(|dy|, |dz|) <
    ``across_cell_m`` + ``across_per_m`` R (radar: 0 + theta_3 R; a camera: d + IFOV R). 0 where they
    share one at every range, inf where at none.
    """
    d = np.abs(np.asarray(offsets_m, float)[:, None, :] - np.asarray(offsets_m, float)[None, :, :])
    across = np.maximum(d[..., 1], d[..., 2])
    with np.errstate(divide="ignore", invalid="ignore"):
        beyond = np.where(across < across_cell_m, 0.0, (across - across_cell_m) / across_per_m)
    return np.where(d[..., 0] < along_cell_m, beyond, np.inf)


def groups_at(link_m: np.ndarray, range_m: float) -> list[np.ndarray]:
    """The groups of drones one sensor sees as one target at ``range_m`` (indices of each group)."""
    linked = csr_matrix(link_m < range_m)
    n, labels = connected_components(linked, directed=False)
    return [np.flatnonzero(labels == k) for k in range(n)]


def first_detection_m(link_m: np.ndarray, group_range_m) -> float:
    """Longest range at which some resolved group of the swarm is detected [m].

    Between two consecutive link ranges the groups do not change; in each such interval (a, b] a group
    whose own detection range R_g (``group_range_m(indices)``) exceeds a is detected out to min(b, R_g).

    Parameters
    ----------
    link_m : ndarray (N, N)
        :func:`link_range_m`.
    group_range_m : callable
        Detection range of one merged group of drones [m], given its indices.
    """
    edges = np.unique(np.concatenate([[0.0], link_m[np.isfinite(link_m)].ravel(), [np.inf]]))
    best, cache = 0.0, {}
    for a, b in zip(edges[:-1], edges[1:]):
        for group in groups_at(link_m, np.nextafter(a, np.inf)):
            members = tuple(group)
            if members not in cache:
                cache[members] = float(group_range_m(group))
            if cache[members] > a:
                best = max(best, min(b, cache[members]))
    return best


def blob_critical_m(offsets_m, d_crit_m: float) -> float:
    """Critical dimension of a merged blob of drones of size d [m]: sqrt((span_y + d)(span_z + d))."""
    o = np.asarray(offsets_m, float)
    span = o.max(axis=0) - o.min(axis=0)
    return float(np.sqrt((span[1] + d_crit_m) * (span[2] + d_crit_m)))


def incoherent_sum_db(count: int) -> float:
    """Level gain of N incoherent equal sources, 10 log10 N [dB] (Kinsler et al. 2000, sec. 5.12)."""
    return float(10.0 * np.log10(count))


def line_of_sight_axes(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """Unit axes (3, 3) of the formation's frame in the target's frame, rows x, y, z: x away from the sensor
    (the sensor seen from the target at ``azimuth_deg``, ``elevation_deg``), y horizontal across the line of
    sight (+y of the target's frame at azimuth 0), z = y cross x (up at elevation 0)."""
    az, el = np.radians(azimuth_deg), np.radians(elevation_deg)
    away = -np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    across = np.array([-np.sin(az), np.cos(az), 0.0])
    return np.stack([away, across, np.cross(across, away)])


def target_frame_offsets_m(offsets_m, azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """The formation's offsets (x along the line of sight, y across, z up) in the target's frame [m]."""
    return np.asarray(offsets_m, float) @ line_of_sight_axes(azimuth_deg, elevation_deg)


def array_factor(offsets_m, toward_transmitter, toward_receiver, wavelength_m: float) -> float:
    """|sum_i exp(j k (u_t + u_r) . r_i)|^2: the RCS of N equal, well-separated point scatterers at
    ``offsets_m`` (target frame) over one's, u_t and u_r the unit vectors toward the transmitter and the
    receiver (monostatic: u_t = u_r, the two-way path 2 u . r), k = 2 pi / lambda (the array factor of
    Balanis, *Antenna Theory*, 4th ed. 2016, Eq. 6.1, with the scatterers' path differences)."""
    u = np.asarray(toward_transmitter, float) + np.asarray(toward_receiver, float)
    phase = 2.0 * np.pi / wavelength_m * (np.asarray(offsets_m, float) @ u)
    return float(np.abs(np.exp(1j * phase).sum()) ** 2)
