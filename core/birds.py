"""Radar cross-section of a bird: a prolate spheroid of water in the optical region.

A bird's radar echo comes from its body, a water-filled prolate spheroid of length/width 3 to 10
(Vaughn 1985, after Pollon 1972). Well above the Rayleigh-resonance region (body length >> lambda,
true at 24 GHz for birds of 0.3 m), the echo is the specular return of the body's surface: the
physical-optics RCS of an ellipsoid with semi-axes a (along the body) and b (across),

    sigma(theta) = pi a^2 b^4 / (b^2 sin^2 theta + a^2 cos^2 theta)^2 * |Gamma|^2,

theta the angle between the body's axis and the line of sight (pi b^4 / a^2 nose-on, pi a^2
broadside; Knott, Shaeffer & Tuley, *Radar Cross Section*, 2nd ed., 2004, Table 6.1), times the
power reflectivity |Gamma|^2 = |(1 - sqrt(eps)) / (1 + sqrt(eps))|^2 of water at normal incidence,
with the double-Debye permittivity of liquid water of ITU-R P.840
(:func:`csuas.core.itu.water_permittivity`, Liebe et al. 1991). Over random aspects this spread of about 20 dB is
summarised by a log-normal fit (:func:`csuas.core.rcs_statistics.fit_lognormal`), the form Vaughn
reports for birds. Wingbeat modulation and the wings' own return are left out (a few dB; Vaughn
1985, Section V).

References
----------
C. R. Vaughn, "Birds and insects as radar targets: a review", Proc. IEEE 73(2):205-227, 1985.
F. Pollon, "Distributions of radar angels", IEEE Trans. AES-8(6):721-727, 1972.
H. J. Liebe, G. A. Hufford and T. Manabe, "A model for the complex permittivity of water at
frequencies below 1 THz", Int. J. Infrared Millim. Waves 12(7):659-675, 1991 (ITU-R P.840's model).
M. M. Rahman and D. A. Robertson, "Radar micro-Doppler signatures of drones and birds at K-band
and W-band", Scientific Reports 8:17396, 2018; "In-flight RCS measurements of drones and birds at
K-band and W-band", IET Radar, Sonar & Navigation 13(2):300-309, 2019 (birds and small drones
overlap in RCS at 24 GHz).
"""

from __future__ import annotations

import numpy as np

from csuas.core.checks import require, require_all
from csuas.core.itu import water_permittivity


def normal_reflectivity(permittivity):
    """Power reflection coefficient at normal incidence, |(1 - sqrt(eps)) / (1 + sqrt(eps))|^2 [-]."""
    root = np.sqrt(np.asarray(permittivity, dtype=complex))
    return np.abs((1.0 - root) / (1.0 + root)) ** 2


def spheroid_rcs_m2(theta_rad, semi_axis_m, semi_width_m):
    """Physical-optics RCS of a perfectly conducting prolate spheroid [m^2] (Knott et al., Table 6.1).

    Parameters
    ----------
    theta_rad : array_like
        Angle between the spheroid's axis and the line of sight [rad].
    semi_axis_m, semi_width_m : float
        Semi-axis a along the body and b across it [m], a >= b > 0.
    """
    a, b = require_all(("semi_axis_m", semi_axis_m, {"gt": 0}), ("semi_width_m", semi_width_m, {"gt": 0}))
    theta = require("theta_rad", theta_rad)
    s, c = np.sin(theta), np.cos(theta)
    return np.pi * a**2 * b**4 / (b**2 * s**2 + a**2 * c**2) ** 2


def bird_rcs_m2(theta_rad, body_length_m, body_diameter_m, frequency_ghz, temperature_c=40.0):
    """RCS of a bird's body, a water spheroid of the body's length and diameter [m^2].

    Parameters
    ----------
    theta_rad : array_like
        Angle between the bird's body axis (its heading) and the line of sight [rad].
    body_length_m, body_diameter_m : float
        Body length and diameter [m] (``defaults/birds.toml``); length >= diameter.
    frequency_ghz : float
        Radar frequency [GHz].
    temperature_c : float
        Body temperature [deg C], 0..50 (a bird's body: about 40).
    """
    t_k = require("temperature_c", temperature_c, ge=0, le=50) + 273.15
    eps_real, eps_imag = water_permittivity(frequency_ghz, t_k)
    return spheroid_rcs_m2(theta_rad, body_length_m / 2.0, body_diameter_m / 2.0) * normal_reflectivity(
        eps_real - 1j * eps_imag
    )


def random_aspects_rad(rng: np.random.Generator, count: int) -> np.ndarray:
    """Angles between a randomly oriented axis and a fixed line of sight (uniform on the sphere) [rad]."""
    return np.arccos(rng.uniform(-1.0, 1.0, count))
