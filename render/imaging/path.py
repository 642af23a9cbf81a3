"""Path effects of the true range, applied analytically to range-normalised renders.

The render gives the radiance leaving the target and the background toward
the sensor. The atmosphere between them and the sensor is a path of length R
with the extinction ``csuas range`` applies to the same scenario and convention
(the terms come from the same core functions, :func:`csuas.core.eo.path_extinction`
and :func:`csuas.core.tir.path_terms`):

* visible (Koschmieder 1924; docs/validation.md, "Optics and thermal radiometry"):
  L(R) = L0 tau + L_h (1 - tau), tau = exp(-beta R) (physical; the paper's Eq. 10
  reads beta as dB/km, tau = 10^(-beta R/10)), beta Kruse/Kim's (Eqs. 19-20) at the
  sensor's wavelength and visibility (fog visibility in fog), averaged along the
  slant path over a fog layer of given top, plus the rain's (physical), L_h the
  horizon sky luminance;
* thermal infrared: L(R) = L0 tau + L_band(T_air) (1 - tau) with
  tau = 10^(-sigma R / 10) for the band attenuation sigma [dB/km] (Table 27, plus
  the rain's and the fog's, physical; the paper's Eq. 31 as printed: exp(-sigma R)) and
  path radiance of air at T_air (the path emits as a graybody of emissivity 1 - tau; in fog
  the drops scatter a radiation field near the air's Planck radiance, so the same source applies).

A fog layer's share of the path (L_fog / R) comes from the render's own geometry: the sensor at its
height, the target R sin(-elevation) above it (:func:`fog_layer_at`).

Both are the solution of the radiative transfer equation along a
homogeneous path whose source function is uniform: the horizon luminance
(airlight, valid in radiative equilibrium, see
:mod:`csuas.validation.imaging.medium` for the participating-medium check) or the
air's Planck radiance (thermal emission of the path). A disabled atmosphere
(``None``) contributes exactly nothing: tau = 1 and no path radiance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.atmosphere import db_transmittance, fog_path_fraction, transmittance
from csuas.core.eo import path_extinction
from csuas.core.radiometry import band_radiance
from csuas.core.result import Term, check_convention
from csuas.core.tir import path_terms
from csuas.render.imaging.records import FogLayer, ThermalScene, View


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
    convention: str = "physical",
    fog_layer: tuple | None = None,
) -> PathEffect:
    """Koschmieder transmittance and airlight for the visible band, with the extinction ``csuas range`` applies.

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
        aerosol's; the rain scatters the same horizon light, so it adds to the airlight alike (physical only).
    convention : {"paper", "physical"}
        How the extinction enters the transmittance (:func:`csuas.core.atmosphere.transmittance`: the paper
        reads Kruse's coefficient as dB/km, Eq. 10).
    fog_layer : (float, float) or None
        Physical only: (L_fog / R, clear visibility [km]) of a fog layer the slant path crosses
        (:func:`csuas.core.eo.path_extinction`).

    The extinction terms are :func:`csuas.core.eo.path_extinction`'s, as the EO range lists them; then the
    total ``extinction_per_km``, the ``transmittance`` and the ``airlight``.
    """
    if visibility_km is None:
        return NO_PATH
    total, applied = path_extinction(wavelength_nm, visibility_km, convention, rain_extinction_per_km, fog_layer)
    beta = float(total)
    tau = float(transmittance(beta, range_m, convention))
    terms = tuple(term_record(t) for t in applied) + (
        {
            "name": "extinction_per_km",
            "value": beta,
            "unit": applied[0].unit,
            "source": " + ".join(t.name for t in applied if t.name != "fog_path_fraction"),
        },
        {"name": "transmittance", "value": tau, "unit": "-", "source": TRANSMITTANCE_SOURCE[convention]},
        {
            "name": "airlight",
            "value": horizon_radiance * (1.0 - tau),
            "unit": "cd/m^2",
            "source": "Koschmieder L_h (1 - tau)",
        },
    )
    return PathEffect(tau, horizon_radiance * (1.0 - tau), terms)


#: Source of the visible path's transmittance per convention (csuas.core.atmosphere.transmittance).
TRANSMITTANCE_SOURCE = {
    "paper": "Eq. 10 as printed: 10^(-sigma R / 10), sigma read as dB/km",
    "physical": "Beer-Lambert exp(-beta R)",
}
#: Source of the thermal path's transmittance per convention (csuas.core.tir.attenuated_delta_t).
THERMAL_TRANSMITTANCE_SOURCE = {
    "paper": "Eq. 31 as printed: exp(-sigma R), sigma [dB/km] read as 1/km",
    "physical": "10^(-sigma R/10)",
}


def term_record(term: Term) -> dict:
    """A core :class:`~csuas.core.result.Term` as a render's JSON term (name, value, unit, source)."""
    return {"name": term.name, "value": float(np.asarray(term.value)), "unit": term.unit, "source": term.source}


def fog_layer_at(layer, view: View) -> tuple | None:
    """(L_fog / R, clear visibility [km]) of a render's own path through a fog layer, or None without one.

    The path runs straight from the sensor at ``layer.sensor_height_m`` to the target R sin(-elevation) above it
    (``view``: the direction target -> sensor, so a negative elevation looks up at the target;
    :func:`csuas.core.atmosphere.fog_path_fraction`): with R sin(-elevation) equal to the scenario's
    ``target.altitude_m`` it is the share ``csuas range`` applies. A (share, visibility) pair is returned as given.
    """
    if not isinstance(layer, FogLayer):
        return layer
    return float(layer_share(layer, view.range_m, _upward(view))), layer.clear_visibility_km


def fog_top_above_target_m(layer, view: View) -> float | None:
    """A fog layer's top above the drone [m] on a render's own path (placed as :func:`fog_layer_at` places it);
    None without a layer, or with one given as its share alone."""
    if not isinstance(layer, FogLayer):
        return None
    return layer.top_m - layer.sensor_height_m - view.range_m * _upward(view)


def _upward(view: View) -> float:
    """Upward component of the direction sensor -> target of a render's ``view`` (target -> sensor) [-]."""
    return -math.sin(math.radians(view.elevation_deg))


def layer_share(layer: FogLayer, range_m, up):
    """L_fog / R of straight paths [-] from the sensor to points ``range_m`` away along directions whose upward
    component is ``up`` (arrays alike; :func:`csuas.core.atmosphere.fog_path_fraction`)."""
    h_s = layer.sensor_height_m
    return fog_path_fraction(h_s, h_s + np.asarray(range_m, float) * np.asarray(up, float), layer.top_m)


def thermal_fog_at(scene: ThermalScene, view: View) -> tuple:
    """The fog's attenuation on a thermal render's own path [dB/km] and its layer's share (None: no layer).

    ``scene.fog_db_km`` (the fog filling the path) times the layer's share of the render's path
    (:func:`fog_layer_at`); (0, None) without fog.
    """
    if scene.fog_layer is None:
        return scene.fog_db_km, None
    share = fog_layer_at(scene.fog_layer, view)[0]
    return scene.fog_db_km * share, share


def tir_path(
    range_m: float,
    extinction_db_km: float | None,
    air_temperature_k: float,
    band,
    rain_db_km: float = 0.0,
    convention: str = "physical",
    fog: tuple = (0.0, None),
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
    convention : {"paper", "physical"}
        ``physical``: tau = 10^(-sigma R/10); ``paper``: Eq. 31 as printed, exp(-sigma R)
        (:func:`csuas.core.tir.attenuated_delta_t`).
    fog : (float, float or None)
        The part of ``extinction_db_km`` that is fog [dB/km] and the fog layer's share of the path
        (:func:`thermal_fog_at`), listed as their terms; the drops emit and scatter with the rest of the path.

    The terms are :func:`csuas.core.tir.path_terms`' (as the MRTD and NETD ranges list them), then the
    ``transmittance`` and the ``path_radiance``.
    """
    if extinction_db_km is None:
        return NO_PATH
    if not np.isfinite(extinction_db_km) or extinction_db_km < 0:
        raise ParameterError("extinction_db_km", extinction_db_km, ">= 0 dB/km")
    tau = float(thermal_transmittance(extinction_db_km, range_m, convention))
    l_path = float(band_radiance(air_temperature_k, band)) * (1.0 - tau)
    terms = tuple(term_record(t) for t in path_terms(extinction_db_km, rain_db_km, *fog)) + (
        {"name": "transmittance", "value": tau, "unit": "-", "source": THERMAL_TRANSMITTANCE_SOURCE[convention]},
        {
            "name": "path_radiance",
            "value": l_path,
            "unit": "W m^-2 sr^-1",
            "source": "air at T_air emitting (1 - tau) L_band(T_air)",
        },
    )
    return PathEffect(tau, l_path, terms)


def thermal_transmittance(extinction_db_km, range_m, convention: str):
    """Thermal path transmittance [-]: ``physical`` 10^(-sigma R / 10); ``paper`` Eq. 31 as printed, exp(-sigma R)."""
    if check_convention(convention) == "paper":
        return transmittance(extinction_db_km, range_m, "physical")
    return db_transmittance(extinction_db_km, range_m)


def eo_path_at(range_m, up, light, wavelength_nm: float, horizon_radiance: float) -> tuple:
    """Transmittance and airlight [cd/m^2] of a frame's objects at their own ranges (clutter, confusers), arrays alike.

    The path of :func:`eo_path` with ``light``'s visibility, rain, convention and fog layer, the layer's share from
    each object's own range and the upward component ``up`` of its direction (:func:`layer_share`).

    Parameters
    ----------
    range_m, up : array_like
        Distances [m] and upward components of the unit directions toward the objects [-].
    light : Daylight
        The frame's light and air (its ``visibility_km`` not None).
    wavelength_nm, horizon_radiance : float
        The sensor's wavelength [nm] and the horizon sky's luminance L_h [cd/m^2] (the airlight's source).
    """
    layer = light.fog_layer
    if isinstance(layer, FogLayer):
        layer = (layer_share(layer, range_m, up), layer.clear_visibility_km)
    beta, _ = path_extinction(wavelength_nm, light.visibility_km, light.convention, light.rain_extinction_per_km, layer)
    tau = transmittance(beta, range_m, light.convention)
    return tau, horizon_radiance * (1.0 - tau)


def tir_path_at(range_m, up, scene: ThermalScene, band) -> tuple:
    """Transmittance and path radiance [W m^-2 sr^-1] of a frame's objects at their own ranges, arrays alike.

    The path of :func:`tir_path` with ``scene``'s attenuation (its ``extinction_db_km`` not None), its fog on each
    object's path (``fog_db_km`` times :func:`layer_share` of its range and ``up``), convention and air.
    """
    share = 1.0 if scene.fog_layer is None else layer_share(scene.fog_layer, range_m, up)
    tau = thermal_transmittance(scene.extinction_db_km + scene.fog_db_km * share, range_m, scene.convention)
    return tau, band_radiance(scene.air_temperature_k, band) * (1.0 - tau)
