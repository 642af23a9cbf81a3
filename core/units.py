"""Physical constants and unit conversions used throughout the analytic core.

All functions accept scalars or NumPy arrays and broadcast.
"""

from __future__ import annotations

import numpy as np

#: Speed of light in vacuum [m/s] (exact, SI 2019).
C_LIGHT = 299_792_458.0
#: Speed of light as rounded by the paper (lambda = c/f with c = 3e8 reproduces Section 4.9.3) [m/s].
C_LIGHT_PAPER = 3.0e8
#: Boltzmann constant [J/K] (exact, SI 2019).
K_BOLTZMANN = 1.380649e-23
#: Boltzmann constant as printed in Table 39 [J/K].
K_BOLTZMANN_TABLE_39 = 1.38e-23
#: Boltzmann constant as printed in Section 4.9.3 [J/K].
K_BOLTZMANN_SECTION_4_9 = 1.381e-23
#: Planck constant [J s] (exact, SI 2019).
H_PLANCK = 6.62607015e-34
#: dB/km per km^-1: an extinction coefficient beta [1/km] attenuates 10*log10(e)*beta dB/km.
DB_PER_NEPER = 10.0 / np.log(10.0)


def db_to_linear(value_db):
    """Power ratio from decibels, ``10**(x/10)``; -inf dB gives exactly 0."""
    return np.power(10.0, np.asarray(value_db, dtype=float) / 10.0)


def linear_to_db(value):
    """Decibels of a power ratio, ``10*log10(x)``; 0 gives -inf (no warning)."""
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(np.asarray(value, dtype=float))


def watt_to_dbm(power_w):
    """Power in dBm from watts: ``10*log10(P/1 mW)``."""
    return linear_to_db(np.asarray(power_w, dtype=float) * 1e3)


def wavelength_m(frequency_ghz, c=C_LIGHT):
    """Free-space wavelength [m] of a frequency [GHz]: ``lambda = c/f``.

    ``c`` defaults to the exact speed of light; the paper convention passes
    :data:`C_LIGHT_PAPER`.
    """
    return c / (np.asarray(frequency_ghz, dtype=float) * 1e9)


def wavenumber_rad_m(frequency_ghz):
    """Free-space wavenumber [rad/m] of a frequency [GHz]: ``k = 2 pi f / c``."""
    return 2.0 * np.pi * np.asarray(frequency_ghz, dtype=float) * 1e9 / C_LIGHT


def frequency_ghz(wavelength_m_):
    """Frequency [GHz] of a free-space wavelength [m]."""
    return C_LIGHT / np.asarray(wavelength_m_, dtype=float) / 1e9


def per_km_to_db_per_km(beta_per_km):
    """Attenuation [dB/km] of an extinction coefficient [1/km] (1 km^-1 = 4.343 dB/km)."""
    return DB_PER_NEPER * np.asarray(beta_per_km, dtype=float)


def db_per_km_to_per_km(gamma_db_km):
    """Extinction coefficient [1/km] of an attenuation [dB/km]."""
    return np.asarray(gamma_db_km, dtype=float) / DB_PER_NEPER


def power_sum_db(*levels_db):
    """Incoherent (power) sum of levels in dB: ``10*log10(sum 10**(L/10))`` (Eq. 108).

    Terms at -inf dB contribute nothing; the sum of only -inf terms is -inf.
    """
    total = sum(db_to_linear(level) for level in levels_db)
    return linear_to_db(total)
