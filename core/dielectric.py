"""Complex relative permittivity of a lossy dielectric.

    eta = eps_r - j sigma / (omega eps_0),   omega = 2 pi f

with the time convention exp(+j omega t) of ITU-R P.2040-3 (Eq. 9), where the imaginary part of a
lossy medium is negative.

References
----------
ITU-R P.2040-3 (2023). Effects of building materials and structures on radiowave propagation above
about 100 MHz, Eq. 9.
"""

from __future__ import annotations

import numpy as np

from csuas.core.checks import require

#: Vacuum permittivity [F/m] (CODATA 2018).
EPSILON_0 = 8.8541878128e-12


def complex_permittivity(relative_permittivity, conductivity_s_m, frequency_ghz):
    """Complex relative permittivity eta = eps_r - j sigma / (omega eps_0) [-].

    Parameters
    ----------
    relative_permittivity : array_like
        Relative permittivity eps_r [-]; a complex value keeps its own loss.
    conductivity_s_m : array_like
        Conductivity sigma [S/m], >= 0; infinite (a perfect conductor) gives an imaginary part of -inf.
    frequency_ghz : array_like
        Frequency [GHz], > 0.

    Returns
    -------
    numpy.ndarray of complex
        Broadcast shape of the inputs.
    """
    f = require("frequency_ghz", frequency_ghz, gt=0)
    sigma = require("conductivity_s_m", conductivity_s_m, ge=0, allow_inf=True)
    eps = np.asarray(relative_permittivity, dtype=complex)
    loss = sigma / (2.0 * np.pi * f * 1e9 * EPSILON_0)
    real, imag = np.broadcast_arrays(eps.real, eps.imag - loss)
    out = np.empty(real.shape, dtype=complex)
    out.real, out.imag = real, imag  # assembled part by part: 1j * -inf would turn the real part into NaN
    return out


def ground_permittivity(ground, frequency_ghz):
    """Complex relative permittivity [-] of a ground given by its constants, as the links report them.

    :func:`complex_permittivity` of ``ground["relative_permittivity"]`` and
    ``ground["conductivity_s_m"]`` (the ``extra`` of a Sionna link result, the JSON of
    ``csuas pathloss``, an ITU-R P.2040-3 Table 3 material at that frequency).

    Parameters
    ----------
    ground : mapping
        ``relative_permittivity`` [-] and ``conductivity_s_m`` [S/m] of the ground.
    frequency_ghz : array_like
        Frequency [GHz], > 0.
    """
    return complex_permittivity(ground["relative_permittivity"], ground["conductivity_s_m"], frequency_ghz)
