"""Band-integrated Planck radiance and radiance temperature (thermal IR, docs/conventions.md point 2).

The paper's Eq. 26 linearises radiance as emissivity x temperature. The
physical convention integrates Planck's law over the sensor band and converts
radiance back into an apparent (radiance) temperature.
"""

from __future__ import annotations

import functools

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require
from csuas.core.units import C_LIGHT, H_PLANCK, K_BOLTZMANN

#: Spectral bands [um] (Section 4.4.1 names them; 3-5 and 8-12 um are the atmospheric windows used).
BANDS_UM = {"mwir": (3.0, 5.0), "lwir": (8.0, 12.0)}
_C1 = 2.0 * H_PLANCK * C_LIGHT**2  # [W m^2 sr^-1]
_C2 = H_PLANCK * C_LIGHT / K_BOLTZMANN  # [m K]
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(96)
#: Temperature span of the radiance-temperature inversion table [K] and its step.
T_TABLE_RANGE_K = (20.0, 2000.0)


def band_limits_um(band):
    """(low, high) wavelength limits [um] of a band name or an explicit pair."""
    if isinstance(band, str):
        if band not in BANDS_UM:
            raise ParameterError("band", band, ", ".join(BANDS_UM) + " or a (low_um, high_um) pair")
        return BANDS_UM[band]
    low, high = (float(b) for b in band)
    if not 0 < low < high:
        raise ParameterError("band", band, "0 < low_um < high_um")
    return low, high


def spectral_radiance(wavelength_um, temperature_k):
    """Planck spectral radiance [W m^-2 sr^-1 um^-1] of a blackbody."""
    lam = np.asarray(wavelength_um, dtype=float) * 1e-6
    t = np.asarray(temperature_k, dtype=float)
    with np.errstate(over="ignore", divide="ignore"):  # T = 0: exp(inf) = inf, radiance 0
        return _C1 / lam**5 / np.expm1(_C2 / (lam * t)) * 1e-6


def band_radiance(temperature_k, band="lwir"):
    """Blackbody radiance integrated over a band [W m^-2 sr^-1].

    Gauss-Legendre quadrature with 96 nodes (relative error < 1e-12 for
    bands within 1-30 um and temperatures above 50 K).

    Parameters
    ----------
    temperature_k : array_like
        Temperature [K], >= 0 (0 K emits nothing: radiance 0).
    band : str or (float, float)
        ``"lwir"`` (8-12 um), ``"mwir"`` (3-5 um) or explicit limits [um].
    """
    t = require("temperature_k", temperature_k, ge=0)
    low, high = band_limits_um(band)
    half = 0.5 * (high - low)
    lam = low + half * (_NODES + 1.0)
    return half * np.sum(_WEIGHTS * spectral_radiance(lam, t[..., None]), axis=-1)


@functools.lru_cache(maxsize=8)
def _inversion_table(band):
    temps = np.linspace(*T_TABLE_RANGE_K, 39601)
    return band_radiance(temps, band), temps


def radiance_temperature(radiance, band="lwir"):
    """Temperature [K] of the blackbody with the given band radiance (inverse of :func:`band_radiance`).

    Linear interpolation of temperature against log-radiance on a 0.05 K
    grid (interpolation error below 1e-5 K between 150 and 1000 K). A zero
    radiance (an emissivity of 0, or a scene so cold that its band radiance
    underflows) is 0 K: nothing in the band is emitted. A radiance between 0
    and that of 20 K, or above that of 2000 K, is refused.
    """
    key = band if isinstance(band, str) else tuple(float(b) for b in band)
    lrad, temps = _inversion_table(key)
    r = require("radiance", radiance, ge=0)
    positive = r > 0
    outside = positive & ((r < lrad[0]) | (r > lrad[-1]))
    if np.any(outside):
        raise ParameterError(
            "radiance",
            float(r[outside].flat[0]),
            f"0, or between the band radiances of {T_TABLE_RANGE_K[0]:g} K and "
            f"{T_TABLE_RANGE_K[1]:g} K (a radiance temperature of 0 or {T_TABLE_RANGE_K[0]:g}-"
            f"{T_TABLE_RANGE_K[1]:g} K)",
        )
    return np.where(positive, np.interp(np.log(np.where(positive, r, lrad[0])), np.log(lrad), temps), 0.0)


def graybody_apparent_temperature(emissivity, temperature_k, band="lwir", surroundings_k=None):
    """Radiance temperature [K] of a graybody: L_bb(T_r) = e L_bb(T) + (1-e) L_bb(T_surr).

    Parameters
    ----------
    emissivity : array_like
        Band emissivity, 0..1.
    temperature_k : array_like
        Physical temperature [K].
    band : str or (float, float)
    surroundings_k : array_like, optional
        Temperature of the reflected surroundings [K]; None reflects nothing.
    """
    e = require("emissivity", emissivity, ge=0, le=1)
    radiance = e * band_radiance(temperature_k, band)
    if surroundings_k is not None:
        radiance = radiance + (1.0 - e) * band_radiance(surroundings_k, band)
    return radiance_temperature(radiance, band)
