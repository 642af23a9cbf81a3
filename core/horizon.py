"""Line-of-sight horizons over a smooth spherical Earth with standard refraction.

A sensor at height h1 and a target at height h2 above a smooth Earth of radius a see each other up
to the distance

    d = sqrt(2 k a h1) + sqrt(2 k a h2)        (h << a)

where k is the effective Earth-radius factor that folds the downward bending of the ray by the
vertical gradient of the refractive index into a larger Earth. Two standard atmospheres:

* radio (RF, radar): k = 4/3, the median of temperate climates, ITU-R P.834-9 (2017), Section 1,
  and ITU-R P.453; the "4/3 Earth" of radar engineering (Skolnik, *Introduction to Radar Systems*,
  3rd ed., 2001, Section 8.2);
* visible and infrared light: refraction coefficient 0.13 (Gauss; Bomford, *Geodesy*, 4th ed.,
  1980, Section 3.3), i.e. k = 1 / (1 - 0.13) = 1.149.

The models of the paper give a slant range without the Earth (Eq. 14); these horizons bound it.
"""

from __future__ import annotations

import numba
import numpy as np

from csuas.core.checks import require

#: Mean Earth radius [m] (IUGG).
EARTH_RADIUS_M = 6_371_000.0
#: Effective Earth-radius factor of radio waves in the standard atmosphere (ITU-R P.834).
K_RADIO = 4.0 / 3.0
#: Terrestrial refraction coefficient of light (Gauss, 0.13) and its Earth-radius factor.
REFRACTION_COEFFICIENT_OPTICAL = 0.13
K_OPTICAL = 1.0 / (1.0 - REFRACTION_COEFFICIENT_OPTICAL)


def horizon_distance_m(height_m, k=K_RADIO, earth_radius_m=EARTH_RADIUS_M):
    """Distance to the horizon of one end [m]: sqrt(2 k a h).

    Parameters
    ----------
    height_m : float or array_like
        Height above the smooth Earth [m], >= 0.
    k : float
        Effective Earth-radius factor [-] (:data:`K_RADIO`, :data:`K_OPTICAL`, 1 for geometry).
    earth_radius_m : float
        Earth radius [m].
    """
    h = require("height_m", height_m, ge=0.0)
    kk = require("k", k, gt=0.0)
    return np.sqrt(2.0 * kk * earth_radius_m * h)


def line_of_sight_limit_m(sensor_height_m, target_height_m, k=K_RADIO, earth_radius_m=EARTH_RADIUS_M):
    """Longest distance at which two ends still see each other [m]: the sum of both horizons.

    Parameters
    ----------
    sensor_height_m, target_height_m : float or array_like
        Heights above the smooth Earth [m], >= 0.
    k : float
        Effective Earth-radius factor [-].
    """
    return horizon_distance_m(sensor_height_m, k, earth_radius_m) + horizon_distance_m(
        target_height_m, k, earth_radius_m
    )


def first_fresnel_radius_m(wavelength_m, d1_m, d2_m):
    """Radius of the first Fresnel zone at a point of a link [m]: r1 = sqrt(lambda d1 d2 / (d1 + d2)).

    ITU-R P.530-18 (2021), Eq. 2 (and ITU-R P.526-15, Eq. 2, with n = 1); d1 and d2 the distances from
    the point to the two ends (their sum the link's length), all much longer than the wavelength.

    Parameters
    ----------
    wavelength_m : float or array_like
        Wavelength [m], > 0.
    d1_m, d2_m : float or array_like
        Distances from the point to each end of the link [m], >= 0, not both 0.
    """
    lam = require("wavelength_m", wavelength_m, gt=0.0)
    d1 = require("d1_m", d1_m, ge=0.0)
    d2 = require("d2_m", d2_m, ge=0.0)
    return fresnel_radius(lam, d1, d2)


@numba.vectorize(["float64(float64, float64, float64)"], cache=True)
def fresnel_radius(wavelength, d1, d2):
    """:func:`first_fresnel_radius_m` unchecked, as a ufunc that compiled kernels call too [m]."""
    return np.sqrt(wavelength * d1 * d2 / (d1 + d2))
