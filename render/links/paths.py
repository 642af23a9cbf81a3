"""Narrow-band channel coefficients of Sionna RT paths, with their phase in float64.

Sionna returns each path's coefficient ``a`` without the propagation phase
and its delay ``tau`` in float32; ``Paths.cir`` then applies
exp(-j 2 pi f tau) in float32. At 50 km, tau = 1.7e-4 s is stored to about
1e-11 s, i.e. 0.15 rad at 2.4 GHz and 1.5 rad at 24 GHz, and the few
millimetres that separate a direct ray from its ground reflection are lost:
the two-ray sum collapses into a spurious null (measured: -180 dB instead
of -152 dB at 50 km, 2.4 GHz). The phase is therefore taken here from the
path length recomputed in float64 from the end points (known exactly) and
the interaction points Sionna found. Those points carry float32 errors, but
a specular path's length is stationary with respect to its reflection point
(Fermat), so the length error is second order in them.
"""

from __future__ import annotations

import numpy as np

from csuas.core.units import wavelength_m

#: Interaction code of "no interaction" (sionna.rt.constants.InteractionType.NONE).
_NONE = 0


def coherent_coefficients(paths, frequency_ghz, tx_positions, rx_positions, sensing_positions=None):
    """Channel coefficients (complex, float64 phase) of every path, per (rx, tx) pair.

    Parameters
    ----------
    paths : sionna.rt.Paths
        Computed with synthetic arrays and single-antenna devices.
    frequency_ghz : float
        Carrier frequency [GHz].
    tx_positions : array_like, shape (n_tx, 3)
        Transmitter positions [m] in float64, in the order added to the scene.
    rx_positions : array_like, shape (n_rx, 3)
        Receiver positions [m] in float64.
    sensing_positions : array_like, shape (n_sp, 3), optional
        Exact positions of the sensing scattering points [m]; interactions of
        type SENSING are replaced by the point of that index.

    Returns
    -------
    coefficients : numpy.ndarray of complex, shape (n_rx, n_tx, n_paths)
        a exp(-j 2 pi L / lambda), 0 for invalid paths.
    lengths : numpy.ndarray, shape (n_rx, n_tx, n_paths)
        Path lengths [m] (float64), NaN for invalid paths.
    """
    from sionna.rt import InteractionType

    wavelength = float(wavelength_m(frequency_ghz))
    a_real, a_imag = paths.a
    a = (np.asarray(a_real.numpy(), np.float64) + 1j * np.asarray(a_imag.numpy(), np.float64))[:, 0, :, 0, :]
    valid = np.asarray(paths.valid.numpy(), bool)
    if valid.ndim == 5:
        valid = valid[:, 0, :, 0, :]
    n_rx, n_tx, n_paths = a.shape
    if n_paths == 0:
        return a, np.zeros(a.shape)
    vertices = np.asarray(paths.vertices.numpy(), np.float64)  # (depth, rx, tx, paths, 3)
    kinds = np.asarray(paths.interactions.numpy())  # (depth, rx, tx, paths)
    if sensing_positions is not None:
        sensing = kinds == InteractionType.SENSING
        if np.any(sensing):
            index = np.asarray(paths.primitives.numpy())  # scattering-point index
            exact = np.asarray(sensing_positions, np.float64)[np.clip(index, 0, len(sensing_positions) - 1)]
            vertices = np.where(sensing[..., None], exact, vertices)
    tx = np.asarray(tx_positions, np.float64)[None, :, None, :]
    rx = np.asarray(rx_positions, np.float64)[:, None, None, :]
    lengths = np.zeros((n_rx, n_tx, n_paths))
    previous = np.broadcast_to(tx, (n_rx, n_tx, n_paths, 3))
    for depth in range(vertices.shape[0]):
        active = kinds[depth] != _NONE
        step = np.linalg.norm(vertices[depth] - previous, axis=-1)
        lengths += np.where(active, step, 0.0)
        previous = np.where(active[..., None], vertices[depth], previous)
    lengths += np.linalg.norm(np.broadcast_to(rx, previous.shape) - previous, axis=-1)
    coefficients = np.where(valid, a * np.exp(-2j * np.pi * lengths / wavelength), 0.0)
    return coefficients, np.where(valid, lengths, np.nan)
