"""Radar detection range: range equation, SNR model, pulse integration and losses (Eqs. 62-86).

Conventions:

* ``paper``: non-coherent integration gain n_p^(1/n_p) (Eqs. 78, 81-82, as
  printed); rain and fog losses at ``loss_frequency_ghz`` (Table 44: 12 GHz)
  over the fixed paths d_rain, d_fog (Table 44: 1 km); the total loss scales the
  range by 10^(-L/40) (Eq. 86).
* ``physical`` (docs/conventions.md points 4-6): non-coherent gain sqrt(n_p); weather
  losses at the radar's own frequency over the actual two-way path, solved
  exactly from 40 log10 R + 2 gamma R = budget, with the gases (oxygen and water vapour,
  ITU-R P.676) in gamma where they cost more than 0.01 dB over the two-way path.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require, require_registry_bounds
from csuas.core.itu import fog_specific_attenuation_db_km, gas_loss_matters, rain_specific_attenuation_db_km
from csuas.core.result import RangeResult, Term, check_convention, unbounded_reason
from csuas.core.solve import solve_log_linear
from csuas.core.units import (
    C_LIGHT,
    C_LIGHT_PAPER,
    K_BOLTZMANN,
    K_BOLTZMANN_TABLE_39,
    db_to_linear,
    frequency_ghz,
    linear_to_db,
)
from csuas.core.units import wavelength_m as carrier_wavelength_m

INTEGRATIONS = ("coherent", "noncoherent", "none")


def received_power_w(p_tx_w, g_tx_db, g_rx_db, wavelength_m, sigma_m2, range_m):
    """Monostatic received power (Eq. 68) [W]: P G_t G_r lambda^2 sigma / ((4 pi)^3 R^4)."""
    p = require("p_tx_w", p_tx_w, ge=0)
    lam = require("wavelength_m", wavelength_m, gt=0)
    s = require("sigma_m2", sigma_m2, ge=0)
    r = require("range_m", range_m, gt=0)
    return p * db_to_linear(g_tx_db) * db_to_linear(g_rx_db) * lam**2 * s / ((4 * np.pi) ** 3 * r**4)


def thermal_noise_power_w(t0_k, noise_figure_db, bandwidth_mhz, k_b=K_BOLTZMANN):
    """Receiver noise power (Eq. 73) [W]: k_B T0 F B."""
    t0 = require("t0_k", t0_k, gt=0)
    b = require("bandwidth_mhz", bandwidth_mhz, gt=0)
    return k_b * t0 * db_to_linear(noise_figure_db) * b * 1e6


def integration_gain(n_pulses, integration="coherent", convention="paper"):
    """SNR gain of pulse integration (Eqs. 77-78).

    ``coherent``: n_p (Eq. 77). ``noncoherent``: the paper's lower bound
    n_p^(1/n_p) (Eq. 78) or, in the physical convention, sqrt(n_p) (the usual
    approximation of non-coherent integration efficiency). ``none``: 1.
    """
    if integration not in INTEGRATIONS:
        raise ParameterError("radar.integration", integration, ", ".join(INTEGRATIONS))
    n = require("n_pulses", n_pulses, ge=1)
    if integration == "coherent":
        return n
    if integration == "noncoherent":
        return n ** (1.0 / n) if convention == "paper" else np.sqrt(n)
    return np.ones_like(n)


def total_loss_db(
    l_hardware_db, l_processing_db, gamma_rain_db_km=0.0, gamma_fog_db_km=0.0, d_rain_km=1.0, d_fog_km=1.0
):
    """Total radar loss (Eqs. 83-84) [dB]: L_hw + L_proc + d_rain gamma_rain + d_fog gamma_fog."""
    return (
        np.asarray(l_hardware_db, float)
        + np.asarray(l_processing_db, float)
        + np.asarray(d_rain_km, float) * gamma_rain_db_km
        + np.asarray(d_fog_km, float) * gamma_fog_db_km
    )


def radar_wavelength_m(params: dict, convention: str) -> float:
    """Carrier wavelength [m] of a radar's canonical parameters: ``wavelength_m``, or c/f.

    With ``frequency_ghz`` the paper convention uses c = 3e8 m/s, as Section 4.9.3 does (it alone
    reproduces 445.3 m); the physical convention the exact speed of light (docs/conventions.md
    point 11).
    """
    if params.get("frequency_ghz") is not None:
        c = C_LIGHT_PAPER if convention == "paper" else C_LIGHT
        return float(carrier_wavelength_m(params["frequency_ghz"], c))
    return params["wavelength_m"]


@dataclass(frozen=True)
class RadarSensor:
    """A radar's own parameters (Tables 39, 41, 44), as :func:`radar_range` takes them.

    Attributes
    ----------
    p_tx_w, g_tx_db, g_rx_db, wavelength_m : array_like
        Transmit power [W], antenna gains [dB], wavelength [m] (Table 39).
    model : {"snr", "range_equation"}
        SNR model (Eq. 75 with integration, Eqs. 80/82) or the range equation with a minimum
        received power ``p_rx_min_w`` [W] (Eq. 69).
    snr_min_db, t0_k, noise_figure_db, bandwidth_mhz : array_like
        Detection threshold [dB] and noise parameters [K, dB, MHz] (Table 39).
    n_pulses, integration : array_like, str
        Pulses integrated and how (Table 39, Eqs. 77-82).
    l_hardware_db, l_processing_db : array_like
        Loss budget terms [dB] (Tables 41, 44).
    loss_frequency_ghz, d_rain_km, d_fog_km : array_like
        Paper convention: frequency [GHz] and fixed paths [km] of the weather losses (Table 44).
    k_b : float, optional
        Boltzmann constant [J/K]; None: Table 39's 1.38e-23 (paper) or the exact SI value (physical).
    """

    p_tx_w: Any
    g_tx_db: Any
    g_rx_db: Any
    wavelength_m: Any
    model: str = "snr"
    p_rx_min_w: Any = None
    snr_min_db: Any = 10.0
    t0_k: Any = 290.0
    noise_figure_db: Any = 10.0
    bandwidth_mhz: Any = 200.0
    n_pulses: Any = 1
    integration: str = "none"
    l_hardware_db: Any = 0.0
    l_processing_db: Any = 0.0
    loss_frequency_ghz: Any = 12.0
    d_rain_km: Any = 1.0
    d_fog_km: Any = 1.0
    k_b: Any = None


@dataclass(frozen=True)
class RadarWeather:
    """The propagation terms of a radar's path (Eqs. 58-61, ITU-R P.676).

    Attributes
    ----------
    rain_rate_mm_h, lwc_g_m3, temperature_k : array_like
        Rain rate [mm/h], fog liquid water content [g/m^3] and temperature [K]; zero rain or LWC
        adds no term.
    gas_db_km : array_like
        Gaseous specific attenuation at the radar's frequency [dB/km], physical convention only.
    """

    rain_rate_mm_h: Any = 0.0
    lwc_g_m3: Any = 0.0
    temperature_k: Any = 293.15
    gas_db_km: Any = 0.0


def radar_frequency_ghz(params: dict) -> float:
    """Carrier frequency [GHz] of a radar's canonical parameters: ``frequency_ghz``, or c/``wavelength_m``.

    A wavelength converts with the exact speed of light in both conventions (the paper gives Table 39's
    radar by its wavelength and converts only a frequency, Section 4.9.3).
    """
    if params.get("frequency_ghz") is not None:
        return float(params["frequency_ghz"])
    return float(frequency_ghz(params["wavelength_m"]))


#: Arguments of :func:`radar_range` -> their defaults/parameters.toml entries (upper bounds checked).
RADAR_REGISTRY = {
    "p_tx_w": "radar.p_tx_w",
    "g_tx_db": "radar.g_tx_db",
    "g_rx_db": "radar.g_rx_db",
    "wavelength_m": "radar.wavelength_m",
    "sigma_m2": "target.sigma_radar_m2",
    "p_rx_min_w": "radar.p_rx_min_w",
    "snr_min_db": "radar.snr_min_db",
    "t0_k": "radar.t0_k",
    "noise_figure_db": "radar.noise_figure_db",
    "bandwidth_mhz": "radar.bandwidth_mhz",
    "n_pulses": "radar.n_pulses",
    "l_hardware_db": "radar.l_hardware_db",
    "l_processing_db": "radar.l_processing_db",
    "rain_rate_mm_h": "environment.rain_rate_mm_h",
    "lwc_g_m3": "environment.lwc_g_m3",
    "temperature_k": "environment.temperature_k",
    "loss_frequency_ghz": "radar.loss_frequency_ghz",
    "d_rain_km": "radar.d_rain_km",
    "d_fog_km": "radar.d_fog_km",
    "k_b": "radar.boltzmann_j_k",
}


def radar_range(
    *,
    p_tx_w,
    g_tx_db,
    g_rx_db,
    wavelength_m,
    sigma_m2,
    model="snr",
    p_rx_min_w=None,
    snr_min_db=10.0,
    t0_k=290.0,
    noise_figure_db=10.0,
    bandwidth_mhz=200.0,
    n_pulses=1,
    integration="none",
    l_hardware_db=0.0,
    l_processing_db=0.0,
    rain_rate_mm_h=0.0,
    lwc_g_m3=0.0,
    temperature_k=293.15,
    loss_frequency_ghz=12.0,
    d_rain_km=1.0,
    d_fog_km=1.0,
    k_b=None,
    gas_db_km=0.0,
    convention="paper",
) -> RangeResult:
    """Radar detection range [m] (Eqs. 69, 75, 80, 82, 86): the keyword form of :func:`radar_range_of`.

    Parameters
    ----------
    p_tx_w, g_tx_db, g_rx_db, wavelength_m : array_like
        Transmit power [W], antenna gains [dB], wavelength [m] (Table 39).
    sigma_m2 : array_like
        Target RCS [m^2] (Table 8).
    model : {"snr", "range_equation"}
        SNR model (Eq. 75 with integration, Eqs. 80/82) or the range equation
        with a minimum received power ``p_rx_min_w`` (Eq. 69).
    snr_min_db, t0_k, noise_figure_db, bandwidth_mhz : array_like
        Detection threshold and noise parameters (Table 39); every dB value finite.
    n_pulses, integration : array_like, str
        Pulses integrated and how (Table 39, Eqs. 77-82).
    l_hardware_db, l_processing_db : array_like
        Loss budget terms (Tables 41, 44), >= 0 dB; zero adds no term.
    rain_rate_mm_h, lwc_g_m3, temperature_k : array_like
        Weather; zero rain or LWC adds no term.
    loss_frequency_ghz, d_rain_km, d_fog_km : array_like
        Paper convention: frequency and fixed paths of the weather losses (Table 44).
    k_b : float, optional
        Boltzmann constant [J/K]; default Table 39's 1.38e-23 (paper) or the
        exact SI value (physical).
    gas_db_km : array_like
        Gaseous specific attenuation at the radar's frequency [dB/km] (ITU-R P.676), physical
        convention only; applied where it costs more than 0.01 dB over the two-way path.
    convention : {"paper", "physical"}

    Returns
    -------
    RangeResult
        A budget too large for a float64 range (e.g. absurd gains) gives R = inf with ``reason``.

    Raises
    ------
    ParameterError
        NaN, an infinite dB value or a negative loss, naming the parameter.
    """
    sensor = RadarSensor(
        p_tx_w=p_tx_w,
        g_tx_db=g_tx_db,
        g_rx_db=g_rx_db,
        wavelength_m=wavelength_m,
        model=model,
        p_rx_min_w=p_rx_min_w,
        snr_min_db=snr_min_db,
        t0_k=t0_k,
        noise_figure_db=noise_figure_db,
        bandwidth_mhz=bandwidth_mhz,
        n_pulses=n_pulses,
        integration=integration,
        l_hardware_db=l_hardware_db,
        l_processing_db=l_processing_db,
        loss_frequency_ghz=loss_frequency_ghz,
        d_rain_km=d_rain_km,
        d_fog_km=d_fog_km,
        k_b=k_b,
    )
    weather = RadarWeather(
        rain_rate_mm_h=rain_rate_mm_h, lwc_g_m3=lwc_g_m3, temperature_k=temperature_k, gas_db_km=gas_db_km
    )
    return radar_range_of(sensor, sigma_m2, weather, convention)


def radar_range_of(
    sensor: RadarSensor, sigma_m2, weather: RadarWeather = RadarWeather(), convention: str = "paper"
) -> RangeResult:
    """Radar detection range [m] (Eqs. 69, 75, 80, 82, 86) of a :class:`RadarSensor` against an RCS.

    Parameters
    ----------
    sensor : RadarSensor
        The radar (Tables 39, 41, 44); every dB value finite, losses >= 0 dB.
    sigma_m2 : array_like
        Target RCS [m^2] (Table 8).
    weather : RadarWeather
        Rain, fog and gas terms of the path.
    convention : {"paper", "physical"}

    Returns
    -------
    RangeResult
        A budget too large for a float64 range (e.g. absurd gains) gives R = inf with ``reason``.

    Raises
    ------
    ParameterError
        NaN, an infinite dB value or a negative loss, naming the parameter.
    """
    require_registry_bounds({**vars(sensor), **vars(weather), "sigma_m2": sigma_m2}, RADAR_REGISTRY)
    check_convention(convention)
    if sensor.model not in ("snr", "range_equation"):
        raise ParameterError("radar.model", sensor.model, "snr, range_equation")
    lam = require("wavelength_m", sensor.wavelength_m, gt=0)
    g_tx_db, g_rx_db = require("g_tx_db", sensor.g_tx_db), require("g_rx_db", sensor.g_rx_db)
    snr_min_db = require("snr_min_db", sensor.snr_min_db)
    noise_figure_db = require("noise_figure_db", sensor.noise_figure_db)
    l_hardware_db = require("l_hardware_db", sensor.l_hardware_db, ge=0)
    l_processing_db = require("l_processing_db", sensor.l_processing_db, ge=0)
    numerator = (
        require("p_tx_w", sensor.p_tx_w, gt=0)
        * db_to_linear(g_tx_db)
        * db_to_linear(g_rx_db)
        * lam**2
        * require("sigma_m2", sigma_m2, gt=0)
        / (4 * np.pi) ** 3
    )
    terms: list = []
    p_min, name = _detection_threshold_w(sensor, snr_min_db, noise_figure_db, convention, terms)
    budget_db = linear_to_db(numerator / p_min)  # 40 log10 R at the threshold, before losses
    fixed_loss = np.asarray(l_hardware_db, float) + np.asarray(l_processing_db, float)
    if np.any(fixed_loss != 0):
        terms.append(Term("l_hardware_db", np.asarray(l_hardware_db, float), "dB", "Table 41"))
        terms.append(Term("l_processing_db", np.asarray(l_processing_db, float), "dB", "Table 44"))
    f_loss = sensor.loss_frequency_ghz if convention == "paper" else frequency_ghz(lam)
    gamma_rain, gamma_fog = _weather_gammas_db_km(f_loss, weather, terms)
    if convention == "paper":
        r, loss = _range_over_fixed_paths(budget_db, sensor, weather, (gamma_rain, gamma_fog), terms)
    else:
        r, propagation = _two_way_over_range(budget_db - fixed_loss, gamma_rain + gamma_fog, weather.gas_db_km, terms)
        loss = fixed_loss + propagation
        if _raining(weather) or _foggy(weather):
            weather_loss = 2.0 * (np.asarray(gamma_rain) + np.asarray(gamma_fog)) * r / 1000.0
            terms.append(Term("l_propagation_db", weather_loss, "dB", "Eqs. 59, 61 over the two-way path"))
    if np.any(loss != 0):
        terms.append(Term("l_total_db", loss, "dB", "Eqs. 84-86"))
    return RangeResult(r, "radar", name, terms, unbounded_reason(r))


def _detection_threshold_w(sensor: RadarSensor, snr_min_db, noise_figure_db, convention: str, terms: list):
    """Minimum detectable received power [W] and the model's name (Eqs. 69, 73, 75, 77-82).

    ``range_equation``: the given ``p_rx_min_w`` (Eq. 69); ``snr``: SNR_min k_B T0 F B / G_int.
    The terms of the threshold are appended to ``terms``.
    """
    if sensor.model == "range_equation":
        if sensor.p_rx_min_w is None:
            raise ParameterError("radar.p_rx_min_w", None, "a power > 0 [W] with model = range_equation")
        p_min = require("p_rx_min_w", sensor.p_rx_min_w, gt=0)
        terms.append(Term("p_rx_min_w", p_min, "W", "Eq. 69"))
        return p_min, "range_equation (Eq. 69)"
    integration = sensor.integration
    kb = sensor.k_b
    if kb is None:
        kb = K_BOLTZMANN_TABLE_39 if convention == "paper" else K_BOLTZMANN
    noise = thermal_noise_power_w(sensor.t0_k, noise_figure_db, sensor.bandwidth_mhz, kb)
    gain = integration_gain(sensor.n_pulses, integration, convention)
    terms += [
        Term("noise_power_w", noise, "W", "Eq. 73"),
        Term(
            "integration_gain_db",
            linear_to_db(gain),
            "dB",
            {"coherent": "Eq. 77", "noncoherent": "Eq. 78", "none": "Eq. 75"}[integration],
        ),
    ]
    name = {"coherent": "snr_coherent (Eq. 80)", "noncoherent": "snr_noncoherent (Eq. 82)", "none": "snr (Eq. 75)"}
    return db_to_linear(snr_min_db) * noise / gain, name[integration]


def _raining(weather: RadarWeather) -> bool:
    return bool(np.any(np.asarray(weather.rain_rate_mm_h) > 0))


def _foggy(weather: RadarWeather) -> bool:
    return bool(np.any(np.asarray(weather.lwc_g_m3) > 0))


def _weather_gammas_db_km(f_loss_ghz, weather: RadarWeather, terms: list):
    """Rain and fog specific attenuations [dB/km] at ``f_loss_ghz`` (Eqs. 58, 60), 0.0 where absent.

    Their terms are appended to ``terms``.
    """
    rain, fog = _raining(weather), _foggy(weather)
    gamma_rain = rain_specific_attenuation_db_km(f_loss_ghz, weather.rain_rate_mm_h) if rain else 0.0
    gamma_fog = fog_specific_attenuation_db_km(f_loss_ghz, weather.lwc_g_m3, weather.temperature_k) if fog else 0.0
    if rain:
        terms.append(Term("gamma_rain_db_km", gamma_rain, "dB/km", "Eq. 58 (ITU-R P.838-3)"))
    if fog:
        terms.append(Term("gamma_fog_db_km", gamma_fog, "dB/km", "Eq. 60 (ITU-R P.840)"))
    return gamma_rain, gamma_fog


def _range_over_fixed_paths(budget_db, sensor: RadarSensor, weather: RadarWeather, gammas, terms: list):
    """Range [m] and total loss [dB] of the paper convention: weather over d_rain, d_fog (Eqs. 83-86).

    The total loss scales the range by 10^(-L/40); a gas term is refused (the paper has none).
    """
    gamma_rain, gamma_fog = gammas
    rain, fog = _raining(weather), _foggy(weather)
    if np.any(np.asarray(weather.gas_db_km) != 0):
        raise ParameterError("gas_db_km", float(np.max(weather.gas_db_km)), "0 in the paper convention (no gas term)")
    propagation = (np.asarray(sensor.d_rain_km, float) * gamma_rain if rain else 0.0) + (
        np.asarray(sensor.d_fog_km, float) * gamma_fog if fog else 0.0
    )
    loss = total_loss_db(sensor.l_hardware_db, sensor.l_processing_db) + propagation
    if rain or fog:
        terms.append(Term("l_propagation_db", propagation, "dB", "Eq. 83"))
    return solve_log_linear(budget_db - loss, 0.0, n=4.0), loss


def _two_way_over_range(budget_db, gamma_weather_db_km, gas_db_km, terms):
    """Range and two-way propagation loss [dB] with the losses over the actual path (physical convention).

    Solves 40 log10 R + 2 (gamma_weather + gamma_gas) R = budget, with the gases only where they
    cost more than 0.01 dB over the path found without them (their terms appended to ``terms``).
    """
    weather = 2.0 * np.asarray(gamma_weather_db_km, float) / 1000.0
    r = solve_log_linear(budget_db, weather, n=4.0)
    gas = require("gas_db_km", gas_db_km, ge=0)
    matters = gas_loss_matters(gas, r, ways=2)
    if not np.any(matters):
        return r, weather * r
    gas = np.where(matters, gas, 0.0)
    r = solve_log_linear(budget_db, weather + 2.0 * gas / 1000.0, n=4.0)
    terms.append(Term("gamma_gas_db_km", gas, "dB/km", "ITU-R P.676-12 Annex 1 (oxygen and water vapour)"))
    terms.append(Term("l_gas_db", 2.0 * gas * r / 1000.0, "dB", "ITU-R P.676-12 over the two-way path"))
    return r, (weather + 2.0 * gas / 1000.0) * r
