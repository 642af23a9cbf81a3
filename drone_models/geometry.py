"""View directions, image-plane axes and quasi-uniform direction sets.

Conventions (docs/command-line.md)
--------------------
Body frame: metres, origin at the centre of the drone's bounding box, +x
forward, +y left, +z up. A view direction is given by ``azimuth_deg``
(from +x toward +y) and ``elevation_deg`` (from the xy-plane, +90 = straight
above); the unit vector ``d`` points FROM the target TOWARD the sensor.

Image-plane axes (the "horizontal" and "vertical" of the paper's projected
cross-section, Section 2.3.1): the horizontal axis ``h`` is perpendicular to
``d`` and to world +z, oriented as the sensor's right-hand side,
``h = normalize(z x d)``; the vertical axis is ``v = d x h`` (world "up" as
seen by the sensor). For ``d = +x`` this gives ``h = +y``, ``v = +z``.
When the sensor looks straight down or up (``d = +-z``) ``z x d`` vanishes and
the horizontal axis is taken as the limit of ``h`` for elevations approaching
+-90 deg at the given azimuth, ``h = (-sin az, cos az, 0)`` (so azimuth 0
gives ``h = +y``); this keeps ``h`` continuous in elevation.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError

#: Below this norm of ``z x d`` the view is treated as straight up/down.
_VERTICAL_TOLERANCE = 1e-12


def validate_angles(azimuth_deg, elevation_deg):
    """Check direction angles and return them as float arrays.

    Parameters
    ----------
    azimuth_deg : float or array_like
        Azimuth [deg], finite, -360 <= az <= 360.
    elevation_deg : float or array_like
        Elevation [deg], finite, -90 <= el <= 90.

    Raises
    ------
    ParameterError
        When a value is not finite or outside its range.
    """
    az = np.asarray(azimuth_deg, dtype=float)
    el = np.asarray(elevation_deg, dtype=float)
    bad_az = ~np.isfinite(az) | (np.abs(az) > 360.0)
    if np.any(bad_az):
        raise ParameterError("azimuth_deg", _first(az, bad_az), "finite, -360 <= x <= 360")
    bad_el = ~np.isfinite(el) | (np.abs(el) > 90.0)
    if np.any(bad_el):
        raise ParameterError("elevation_deg", _first(el, bad_el), "finite, -90 <= x <= 90")
    return az, el


def _first(values: np.ndarray, mask: np.ndarray) -> float:
    return float(np.atleast_1d(values)[np.atleast_1d(mask)][0])


def direction_vector(azimuth_deg, elevation_deg) -> np.ndarray:
    """Unit vector from the target toward the sensor.

    Parameters
    ----------
    azimuth_deg, elevation_deg : float or array_like
        Direction angles [deg] (module docstring), broadcast together.

    Returns
    -------
    numpy.ndarray
        Shape ``broadcast_shape + (3,)``:
        ``(cos el cos az, cos el sin az, sin el)``.
    """
    az, el = validate_angles(azimuth_deg, elevation_deg)
    az, el = np.broadcast_arrays(np.radians(az), np.radians(el))
    return np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)


def view_basis(direction, azimuth_deg=None):
    """Image-plane axes ``(h, v)`` for view directions ``direction``.

    Parameters
    ----------
    direction : array_like, shape (..., 3)
        Direction(s) from target toward sensor; normalised here.
    azimuth_deg : float or array_like, optional
        Azimuth [deg] used only for the straight up/down fallback
        ``h = (-sin az, cos az, 0)``; 0 when omitted.

    Returns
    -------
    h, v : numpy.ndarray, shape (..., 3)
        Unit horizontal and vertical image axes (module docstring).
    """
    d = np.asarray(direction, dtype=float)
    norm = np.linalg.norm(d, axis=-1, keepdims=True)
    if np.any(~np.isfinite(norm)) or np.any(norm == 0.0):
        raise ParameterError("direction", d.tolist() if d.size <= 6 else "array", "finite non-zero 3-vectors")
    d = d / norm
    h = np.stack([-d[..., 1], d[..., 0], np.zeros_like(d[..., 0])], axis=-1)  # z x d
    h_norm = np.linalg.norm(h, axis=-1, keepdims=True)
    az = np.radians(np.zeros(d.shape[:-1]) if azimuth_deg is None else np.asarray(azimuth_deg, dtype=float))
    fallback = np.stack(np.broadcast_arrays(-np.sin(az), np.cos(az), np.zeros_like(az)), axis=-1)
    fallback = np.broadcast_to(fallback, h.shape)
    vertical = h_norm < _VERTICAL_TOLERANCE
    h = np.where(vertical, fallback, h / np.where(vertical, 1.0, h_norm))
    v = np.cross(d, h)
    return h, v


def fibonacci_sphere(n: int) -> np.ndarray:
    """Quasi-uniform unit vectors on the sphere (Fibonacci / golden-angle lattice).

    Point ``i`` has ``z_i = 1 - (2 i + 1) / n`` and longitude ``i * pi (3 - sqrt 5)``;
    every point represents an equal area ``4 pi / n`` (Gonzalez, Math. Geosci.
    42, 49-64, 2010).

    Parameters
    ----------
    n : int
        Number of directions, ``n >= 1``.

    Returns
    -------
    numpy.ndarray, shape (n, 3)
    """
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise ParameterError("n_directions", n, "integer >= 1")
    i = np.arange(n, dtype=float)
    z = 1.0 - (2.0 * i + 1.0) / n
    rho = np.sqrt(np.clip(1.0 - z * z, 0.0, None))
    phi = i * np.pi * (3.0 - np.sqrt(5.0))
    return np.stack([rho * np.cos(phi), rho * np.sin(phi), z], axis=-1)


def rotated_lattices(replicates: int, directions_per_replicate: int, seed: int = 0) -> np.ndarray:
    """Randomly rotated Fibonacci lattices, shape ``(replicates, directions_per_replicate, 3)``.

    The randomised quasi-Monte Carlo design of every sphere average in csuas: each replicate is the
    same low-discrepancy lattice (:func:`fibonacci_sphere`) under an independent uniform random
    rotation (:func:`random_rotations`), so replicate means are independent and unbiased and their
    spread gives the standard error.
    """
    rotations = random_rotations(replicates, np.random.default_rng(seed))
    return np.einsum("rij,nj->rni", rotations, fibonacci_sphere(directions_per_replicate))


def random_rotations(count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` uniformly distributed random rotation matrices, shape (count, 3, 3).

    Uses normalised random quaternions (Shoemake, Graphics Gems III, 1992).
    """
    q = rng.normal(size=(count, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], axis=-1),
            np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], axis=-1),
            np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], axis=-1),
        ],
        axis=1,
    )


def direction_angles(direction) -> tuple[np.ndarray, np.ndarray]:
    """Azimuth and elevation [deg] of direction vector(s), inverse of :func:`direction_vector`."""
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d, axis=-1, keepdims=True)
    return np.degrees(np.arctan2(d[..., 1], d[..., 0])), np.degrees(np.arcsin(np.clip(d[..., 2], -1.0, 1.0)))
