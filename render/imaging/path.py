"""Path effects of the true range, applied analytically to range-normalised renders.

The render gives the radiance leaving the target and the background toward
the sensor. The atmosphere between them and the sensor is a homogeneous
horizontal path of length R:

* visible (Koschmieder 1924; docs/validation.md, "Optics and thermal radiometry"):
  L(R) = L0 tau + L_h (1 - tau), tau = exp(-beta R), beta from Kruse/Kim
  (Eqs. 19-20, physical convention: km^-1) at the sensor's wavelength and
  visibility (fog visibility in fog), L_h the horizon sky luminance;
* thermal infrared: L(R) = L0 tau + L_band(T_air) (1 - tau) with
  tau = 10^(-sigma R / 10) for the band attenuation sigma [dB/km] (Table 27)
  and path radiance of air at T_air (the path emits as a graybody of
  emissivity 1 - tau).

Both are the solution of the radiative transfer equation along a
homogeneous path whose source function is uniform: the horizon luminance
(airlight, valid in radiative equilibrium, see
:mod:`csuas.validation.imaging.medium` for the participating-medium check) or the
air's Planck radiance (thermal emission of the path). A disabled atmosphere
(``None``) contributes exactly nothing: tau = 1 and no path radiance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.atmosphere import RAIN_EXTINCTION_SOURCE, db_transmittance, extinction_per_km, transmittance
from csuas.core.radiometry import band_radiance


@dataclass(frozen=True)
class PathEffect:
    """Transmittance and additive path radiance of one range.

    Attributes
    ----------
    transmittance : float
        tau(R), 0..1.
    path_radiance : float
        Radiance added by the path [same unit as the image].
    terms : list of dict
        The applied terms (name, value, unit, source) for reports (docs/scenarios.md (effects)).
    """

    transmittance: float
    path_radiance: float
    terms: tuple = ()

    def apply(self, radiance):
        """Apparent radiance at the sensor: L0 tau + L_path."""
        return np.asarray(radiance, dtype=float) * self.transmittance + self.path_radiance


#: The vacuum: nothing applied.
NO_PATH = PathEffect(1.0, 0.0, ())


def eo_path(
    range_m: float,
    visibility_km: float | None,
    wavelength_nm: float,
    horizon_radiance: float,
    rain_extinction_per_km: float = 0.0,
) -> PathEffect:
    """Koschmieder transmittance and airlight for the visible band.

    Parameters
    ----------
    range_m : float
        Slant range [m].
    visibility_km : float or None
        Meteorological (or fog) visibility [km]; None disables the atmosphere.
    wavelength_nm : float
        Sensor wavelength for Kruse's q (Eq. 20) [nm].
    horizon_radiance : float
        Horizon sky luminance L_h [cd m^-2] (the airlight source).
    rain_extinction_per_km : float
        Extinction of rain [1/km] (:func:`csuas.core.atmosphere.rain_extinction_per_km`), added to the
        aerosol's; the rain scatters the same horizon light, so it adds to the airlight alike.
    """
    if visibility_km is None:
        return NO_PATH
    aerosol = float(extinction_per_km(wavelength_nm, visibility_km, "physical"))
    beta = aerosol + float(rain_extinction_per_km)
    tau = float(transmittance(beta, range_m, "physical"))
    rain_terms = _rain_term("rain_extinction_per_km", rain_extinction_per_km, "1/km")
    terms = rain_terms + (
        {
            "name": "extinction_per_km",
            "value": beta,
            "unit": "1/km",
            "source": "Kruse/Kim Eqs. 19-20 (physical)" + (" + rain" if rain_terms else ""),
        },
        {"name": "transmittance", "value": tau, "unit": "-", "source": "Beer-Lambert exp(-beta R)"},
        {
            "name": "airlight",
            "value": horizon_radiance * (1.0 - tau),
            "unit": "cd/m^2",
            "source": "Koschmieder L_h (1 - tau)",
        },
    )
    return PathEffect(tau, horizon_radiance * (1.0 - tau), terms)


def tir_path(
    range_m: float, extinction_db_km: float | None, air_temperature_k: float, band, rain_db_km: float = 0.0
) -> PathEffect:
    """Band transmittance and path radiance for the thermal infrared.

    Parameters
    ----------
    range_m : float
        Slant range [m].
    extinction_db_km : float or None
        Path attenuation sigma [dB/km] (Table 27); None disables the atmosphere.
    air_temperature_k : float
        Temperature of the air along the path [K].
    band : str or (float, float)
    rain_db_km : float
        The part of ``extinction_db_km`` that is rain [dB/km], listed as its own term; the drops, near
        the air's temperature, emit with the rest of the path.
    """
    if extinction_db_km is None:
        return NO_PATH
    if not np.isfinite(extinction_db_km) or extinction_db_km < 0:
        raise ParameterError("extinction_db_km", extinction_db_km, ">= 0 dB/km")
    tau = float(db_transmittance(extinction_db_km, range_m))
    l_path = float(band_radiance(air_temperature_k, band)) * (1.0 - tau)
    rain_terms = _rain_term("rain_extinction_db_km", rain_db_km, "dB/km")
    terms = rain_terms + (
        {
            "name": "extinction_db_km",
            "value": float(extinction_db_km),
            "unit": "dB/km",
            "source": "Table 27" + (" + rain" if rain_terms else ""),
        },
        {"name": "transmittance", "value": tau, "unit": "-", "source": "10^(-sigma R/10)"},
        {
            "name": "path_radiance",
            "value": l_path,
            "unit": "W m^-2 sr^-1",
            "source": "air at T_air emitting (1 - tau) L_band(T_air)",
        },
    )
    return PathEffect(tau, l_path, terms)


def _rain_term(name: str, value: float, unit: str) -> tuple:
    """The path's rain term (Marshall-Palmer extinction), or none when no rain is declared."""
    if not value > 0:
        return ()
    return ({"name": name, "value": float(value), "unit": unit, "source": RAIN_EXTINCTION_SOURCE},)
