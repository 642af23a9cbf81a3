"""Evaluate a scenario's sensors with the analytic core (the job of ``csuas range``).

Each modality has one adapter (named by its record, :mod:`csuas.core.modality`) that maps the
scenario's canonical parameters (docs/scenarios.md) onto the core model and passes only the effects the
scenario has (docs/scenarios.md (effects)): no rain rate means no rain term, no fog means no fog term.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from csuas.base.errors import CsuasError, InputErrors, ParameterError, raise_all
from csuas.core import acoustic, acoustic_spectrum, detection, eo, itu, johnson, lidar, radar, rf, tir
from csuas.core.atmosphere import (
    fog_infrared_extinction_per_km,
    fog_path_fraction,
    kruse_extinction_per_km,
    rain_extinction_per_km,
    transmittance,
)
from csuas.core.camera import CameraChain
from csuas.core.horizon import line_of_sight_limit_m
from csuas.core.modality import RECORDS, PartTable
from csuas.core.mrtd import sensor_mrtd
from csuas.core.radiometry import graybody_apparent_temperature
from csuas.core.result import RangeResult, Term, check_convention
from csuas.core.scenario import SWARM_KEYS, Scenario, SensorSpec, check_value, johnson_derived, with_swarm_value
from csuas.core.sensitivity import TornadoBar
from csuas.core.units import frequency_ghz
from csuas.defaults import load_parameters


def _eo(sc: Scenario, s: SensorSpec, convention: str) -> RangeResult:
    p = s.params
    camera = None
    if convention == "physical":
        chain = CameraChain(
            f_number=p["f_number"],
            optics_transmittance=p["optics_transmittance"],
            pixel_pitch_um=p["pixel_pitch_um"],
            quantum_efficiency=p["quantum_efficiency"],
            max_exposure_ms=p["max_exposure_ms"],
            full_well_e=p["full_well_e"],
            read_noise_e=p["read_noise_e"],
            dark_current_e_s=p["dark_current_e_s"],
            required_snr=float(detection.gaussian_required_snr(p["p_desired"], p["pfa"])),
        )
        camera = dict(
            camera=chain,
            illuminance_lx=sc.environment["illuminance_lx"],
            background_reflectance=sc.environment["background_reflectance"],
            projected_area_m2=sc.target["projected_area_m2"],
        )
    return eo.eo_range(
        d_crit_m=sc.target["d_crit_m"],
        hfov_deg=p["hfov_deg"],
        n_h=p["n_h"],
        lp_task=p["lp_task"],
        n_ttpf=p["n_ttpf"],
        c_eo=sc.target["c_eo"],
        c_min=p["c_min"],
        wavelength_nm=p["wavelength_nm"],
        convention=convention,
        camera=camera,
        **eo_path_inputs(sc, s, convention),
    )


def eo_path_inputs(sc: Scenario, s: SensorSpec, convention: str) -> dict:
    """What an EO sensor's path takes from the scenario under a convention, for ``range`` and ``render`` alike.

    Returns
    -------
    dict
        ``visibility_km`` (the optical visibility: the fog's in fog), ``rain_extinction_per_km`` (the physical
        convention's Marshall-Palmer rain, else 0) and ``fog_layer`` (the physical convention's layered fog,
        :func:`_fog_layer`, else None): the keywords of :func:`csuas.core.eo.path_extinction`.
    """
    physical = check_convention(convention) == "physical"
    return dict(
        visibility_km=sc.optical_visibility_km,
        rain_extinction_per_km=rain_extinction_per_km(sc.environment["rain_rate_mm_h"]) if physical else 0.0,
        fog_layer=_fog_layer(sc, s) if physical else None,
    )


def _fog_layer(sc: Scenario, s: SensorSpec) -> tuple | None:
    """(L_fog / R, clear visibility [km]) of the scenario's fog layer on an optical sensor's slant path, or None.

    Only with ``environment.fog_top_m`` (docs/scenarios.md): the path runs from the sensor's ``height_m``
    (else REFERENCE_SENSOR_HEIGHT_M, a mast-less sensor) to ``target.altitude_m`` above it
    (:func:`csuas.core.atmosphere.fog_path_fraction`); above the top the air has ``visibility_km``.
    """
    geometry = fog_layer_geometry(sc, s)
    if geometry is None:
        return None
    h_s, top, clear_km = geometry
    return fog_path_fraction(h_s, h_s + sc.target["altitude_m"], top), clear_km


def fog_layer_geometry(sc: Scenario, s: SensorSpec) -> tuple | None:
    """(sensor height [m], fog top [m], clear visibility above it [km]) of the scenario's fog layer, or None.

    The sensor's ``height_m``, else REFERENCE_SENSOR_HEIGHT_M (a mast-less sensor); ``environment.fog_top_m``
    and ``visibility_km``. A render takes the layer's share of its own path from it (its range and elevation).
    """
    top = sc.environment.get("fog_top_m")
    if top is None:
        return None
    h_s = s.params.get("height_m")
    return REFERENCE_SENSOR_HEIGHT_M if h_s is None else h_s, top, sc.environment["visibility_km"]


def thermal_contrast(sc: Scenario, s: SensorSpec, convention: str) -> tuple:
    """Delta T at zero range [K] of a thermal sensor's scenario, and the path inputs of its convention.

    The paper convention takes Eq. 26's linear Delta T; the physical one the difference of the
    radiance temperatures in the sensor's band, with the background's apparent temperature, the
    air temperature and the band kept for the path (:func:`csuas.core.tir.attenuated_delta_t`).

    Returns
    -------
    (ndarray, dict)
        Delta T0 and the keyword arguments of the convention's attenuation.
    """
    t, env, band = sc.target, sc.environment, s.params["band"]
    if convention == "paper":
        return tir.delta_t_linear(t["emissivity_suas"], t["t_suas_k"], env["emissivity_bg"], env["t_bg_k"]), {}
    t_bg_app = graybody_apparent_temperature(env["emissivity_bg"], env["t_bg_k"], band)
    dt0 = graybody_apparent_temperature(t["emissivity_suas"], t["t_suas_k"], band) - t_bg_app
    return dt0, dict(t_bg_app_k=t_bg_app, air_temperature_k=env["temperature_k"], band=band)


def _tir(sc: Scenario, s: SensorSpec, convention: str) -> RangeResult:
    p, t = s.params, sc.target
    if p["model"] == "johnson":
        return tir.tir_johnson_range(
            d_crit_m=t["d_crit_m"], hfov_deg=p["hfov_deg"], n_h=p["n_h"], lp_task=p["lp_task"], n_ttpf=p["n_ttpf"]
        )
    dt0, extra = thermal_contrast(sc, s, convention)
    extinction, rain_db_km = thermal_extinction_db_km(sc, s, convention)
    if p["model"] == "netd":
        result = tir.tir_netd_range(
            projected_area_m2=t["projected_area_m2"],
            ifov_rad_=johnson.ifov_rad(p["hfov_deg"], p["n_h"]),
            netd_mk=p["netd_mk"],
            required_snr=detection.gaussian_required_snr(p["p_desired"], p["pfa"]),
            delta_t0_k=dt0,
            extinction_db_km=extinction,
            convention=convention,
            **extra,
        )
    else:
        result = tir.tir_mrtd_range(
            mrtd=sensor_mrtd(p),
            d_crit_m=t["d_crit_m"],
            lp_task=p["lp_task"],
            n_ttpf=p["n_ttpf"],
            delta_t0_k=dt0,
            extinction_db_km=extinction,
            convention=convention,
            **extra,
        )
    result.terms += tir.rain_terms(rain_db_km) + tir.fog_terms(*thermal_fog_db_km(sc, s, convention))
    return result


def thermal_path(sc: Scenario, s: SensorSpec, convention: str) -> tuple:
    """The path a thermal sensor's range applies, for ``render`` to apply the same: attenuation and its terms.

    Returns
    -------
    (float or None, float, list of Term)
        The attenuation [dB/km] (:func:`thermal_extinction_db_km`), None where the range applies no path (the
        Johnson model, or no attenuation at all); its rain part [dB/km]; the terms ``extinction_db_km`` and
        ``rain_extinction_db_km`` as the MRTD and NETD models list them.
    """
    extinction, rain = thermal_extinction_db_km(sc, s, convention)
    if s.params["model"] == "johnson" or not np.any(extinction > 0):
        return None, 0.0, []
    return extinction, rain, tir.path_terms(extinction, rain, *thermal_fog_db_km(sc, s, convention))


#: dB per neper of power: 10 log10(e), an extinction coefficient [1/km] in dB/km.
DB_PER_NEPER = 10.0 * np.log10(np.e)


def thermal_extinction_db_km(sc: Scenario, s: SensorSpec, convention: str) -> tuple:
    """Path attenuation of a thermal sensor [dB/km], and the part of it that is rain.

    Table 27's ``extinction_db_km`` of the sensor; the physical convention adds the extinction of the
    scenario's rain (Marshall-Palmer, :func:`csuas.core.atmosphere.rain_extinction_per_km`) as
    10 log10(e) beta dB/km, and its fog's on the sensor's path (:func:`thermal_fog_db_km`). The render's
    thermal path takes the same (``csuas render``).
    """
    clear, rain = thermal_extinction_no_fog_db_km(sc, s, convention)
    return clear + thermal_fog_db_km(sc, s, convention)[0], rain


def thermal_extinction_no_fog_db_km(sc: Scenario, s: SensorSpec, convention: str) -> tuple:
    """Table 27's attenuation of a thermal sensor plus the physical convention's rain [dB/km], and the rain's part.

    What :func:`thermal_extinction_db_km` adds its fog to; a render adds the fog on its own path
    (:func:`csuas.render.imaging.path.thermal_fog_at`).
    """
    rain = 0.0
    if convention == "physical":
        rain = DB_PER_NEPER * rain_extinction_per_km(sc.environment["rain_rate_mm_h"])
    return np.asarray(s.params["extinction_db_km"], float) + rain, rain


def thermal_fog(sc: Scenario, s: SensorSpec, convention: str) -> tuple:
    """A thermal sensor's fog: its attenuation where it fills the path [dB/km] (0 without), and its layer.

    Physical convention only, and only where the scenario declares a fog visibility (``fog_visibility_m``, as the
    EO path; a liquid water content alone is the radio bands' fog): 10 log10(e) times
    :func:`csuas.core.atmosphere.fog_infrared_extinction_per_km` in the sensor's band, for the scenario's
    ``environment.fog_type`` (advection or radiation fog). The layer is
    :func:`_fog_layer`'s (L_fog / R, clear visibility), or None where the fog fills the path.
    """
    fog_v = sc.environment.get("fog_visibility_m")
    if check_convention(convention) == "paper" or fog_v is None:
        return 0.0, None
    full = DB_PER_NEPER * fog_infrared_extinction_per_km(fog_v / 1000.0, s.params["band"], sc.environment["fog_type"])
    return full, _fog_layer(sc, s)


def thermal_fog_db_km(sc: Scenario, s: SensorSpec, convention: str) -> tuple:
    """The fog's part of a thermal sensor's attenuation on the scenario's path [dB/km], and the fog layer's share.

    :func:`thermal_fog`'s attenuation times L_fog / R of the layer (the path from the sensor's height to the
    target's altitude above it, as the EO path's); the share is None where the fog fills the path.
    """
    full, layer = thermal_fog(sc, s, convention)
    if layer is None:
        return full, None
    return full * layer[0], layer[0]


def _acoustic(sc: Scenario, s: SensorSpec, convention: str) -> RangeResult:
    p, env = s.params, sc.environment
    gain = p["g_array_db"]
    if convention == "physical" and "g_array_db" not in s.explicit:
        gain = float(acoustic.array_gain_db(p["n_micro"], p["g_micro_db"]))
    if convention == "physical" and p["detector"] == "bands":
        return _acoustic_bands(sc, s, gain)
    absorption = 0.0
    if convention == "physical":
        absorption = acoustic.iso9613_absorption_db_m(
            p["frequency_hz"], env["temperature_k"], env["relative_humidity_pct"], env["pressure_kpa"]
        )
    return acoustic.acoustic_range(
        sl_db=sc.target["sl_db"],
        snr_req_db=p["snr_req_db"],
        noise_level_db=env["noise_level_db"],
        g_array_db=gain,
        wind_speed_m_s=env["wind_speed_m_s"],
        wind_distance_m=p["wind_distance_m"],
        absorption_db_m=absorption,
        convention=convention,
    )


def _acoustic_bands(sc: Scenario, s: SensorSpec, gain) -> RangeResult:
    """Band-limited array detector of the physical convention; ground effect and C_met with the sensor's height."""
    p, env = s.params, sc.environment
    ground = None
    if p.get("height_m") is not None:
        g = env["ground_factor"]
        ground = dict(
            receiver_height_m=p["height_m"],
            altitude_m=sc.target["altitude_m"],
            g_source=g,
            g_middle=g,
            g_receiver=g,
            c0_db=env["c0_met_db"],
        )
    return acoustic_spectrum.spectral_acoustic_range(
        sl_db=sc.target["sl_db"],
        blade_passing_hz=sc.target["blade_passing_hz"],
        snr_req_db=p["snr_req_db"],
        g_array_db=gain,
        noise_level_db=env["noise_level_db"],
        air={k: env[k] for k in ("temperature_k", "relative_humidity_pct", "pressure_kpa")},
        wind=dict(
            wind_speed_m_s=env["wind_speed_m_s"],
            diameter_m=p["windshield_diameter_m"] if p["windshield"] == "foam" else p["microphone_diameter_m"],
        ),
        ground=ground,
    )


def rf_frequency_ghz(sensor_params: dict, target: dict) -> float:
    """Carrier frequency [GHz] an RF sensor listens on: its own ``frequency_ghz``, else the drone's link (Table 33).

    Parameters
    ----------
    sensor_params : dict
        The RF sensor's canonical parameters (``frequency_ghz`` may be absent or None).
    target : dict
        The scenario's target parameters (``rf_frequency_ghz``, the drone's control/video link).
    """
    given = sensor_params.get("frequency_ghz")
    return float(given if given is not None else target["rf_frequency_ghz"])


def _rf(sc: Scenario, s: SensorSpec, convention: str) -> RangeResult:
    p, t, env = s.params, sc.target, sc.environment
    frequency = rf_frequency_ghz(p, t)
    return rf.rf_range(
        p_tx_w=t["rf_power_w"],
        g_tx_dbi=t["rf_gain_dbi"],
        g_rx_db=p["g_rx_db"],
        frequency_ghz=frequency,
        s_rx_dbm=p["s_rx_dbm"],
        rain_rate_mm_h=env["rain_rate_mm_h"],
        lwc_g_m3=env["lwc_g_m3"],
        temperature_k=env["temperature_k"],
        d_rain_km=p["d_rain_km"],
        d_fog_km=p["d_fog_km"],
        gas_db_km=gas_attenuation_db_km(sc, frequency, convention),
        convention=convention,
    )


def gas_atmosphere(sc: Scenario) -> dict:
    """Pressure [hPa], temperature [K] and water vapour density [g/m^3] of the gaseous absorption.

    ITU-R P.835-6's sea-level reference atmosphere (288.15 K, 1013.25 hPa, 7.5 g/m^3), each value
    replaced by the scenario's own when it (or its environment preset) gives ``temperature_k``,
    ``pressure_kpa`` or ``relative_humidity_pct`` (the humidity through ITU-R P.453-14).
    """
    env, given = sc.environment, sc.explicit["environment"]
    atmosphere = itu.standard_atmosphere()
    if "temperature_k" in given:
        atmosphere["temperature_k"] = env["temperature_k"]
    if "pressure_kpa" in given:
        atmosphere["pressure_hpa"] = 10.0 * env["pressure_kpa"]
    if "relative_humidity_pct" in given:
        atmosphere["water_vapour_density_g_m3"] = itu.water_vapour_density_g_m3(
            env["relative_humidity_pct"], atmosphere["temperature_k"], atmosphere["pressure_hpa"]
        )
    return atmosphere


def gas_attenuation_db_km(sc: Scenario, frequency_ghz, convention: str):
    """Gaseous specific attenuation [dB/km] at a sensor's frequency, 0 where no gas term applies.

    The physical convention only, and only within ITU-R P.676's 1-1000 GHz (below 1 GHz the gases
    absorb under 0.006 dB/km; docs/conventions.md).
    """
    f = np.asarray(frequency_ghz, float)
    lo, hi = itu.P676_FREQUENCY_RANGE_GHZ
    inside = (f >= lo) & (f <= hi)
    if convention == "paper" or not np.any(inside):
        return 0.0
    atmosphere = gas_atmosphere(sc)
    gamma = itu.gaseous_attenuation_db_km(
        np.clip(f, lo, hi),
        atmosphere["pressure_hpa"],
        atmosphere["temperature_k"],
        atmosphere["water_vapour_density_g_m3"],
    )
    return np.where(inside, gamma, 0.0)


def _radar(sc: Scenario, s: SensorSpec, convention: str) -> RangeResult:
    p, env = s.params, sc.environment
    wavelength = radar.radar_wavelength_m(p, convention)
    return radar.radar_range(
        p_tx_w=p["p_tx_w"],
        g_tx_db=p["g_tx_db"],
        g_rx_db=p["g_rx_db"],
        wavelength_m=wavelength,
        sigma_m2=sc.target["sigma_radar_m2"],
        model=p["model"],
        p_rx_min_w=p.get("p_rx_min_w"),
        snr_min_db=p["snr_min_db"],
        t0_k=p["t0_k"],
        noise_figure_db=p["noise_figure_db"],
        bandwidth_mhz=p["bandwidth_mhz"],
        n_pulses=p["n_pulses"],
        integration=p["integration"],
        l_hardware_db=p["l_hardware_db"],
        l_processing_db=p["l_processing_db"],
        rain_rate_mm_h=env["rain_rate_mm_h"],
        lwc_g_m3=env["lwc_g_m3"],
        temperature_k=env["temperature_k"],
        loss_frequency_ghz=p["loss_frequency_ghz"],
        d_rain_km=p["d_rain_km"],
        d_fog_km=p["d_fog_km"],
        k_b=p.get("boltzmann_j_k"),
        gas_db_km=gas_attenuation_db_km(sc, frequency_ghz(wavelength), convention),
        convention=convention,
    )


def paper_eta_tl(sc: Scenario, s: SensorSpec) -> float:
    """One-way transmission factor of the paper convention (Table 47).

    Given by the scenario: used as is. Otherwise, when the scenario declares
    fog or a visibility, Table 47's method: Kruse at that visibility over the
    fixed ``tl_path_km`` in the dB reading of Eq. 10. Otherwise Table 47's 0.681.
    """
    p = s.params
    if "eta_tl" in s.explicit or not ({"fog", "haze"} & sc.effects):
        return p["eta_tl"]
    sigma = kruse_extinction_per_km(p["wavelength_nm"], sc.optical_visibility_km)
    return float(transmittance(sigma, p["tl_path_km"] * 1000.0, "paper"))


def _lidar(sc: Scenario, s: SensorSpec, convention: str) -> RangeResult:
    p, t = s.params, sc.target
    common = dict(
        p_tx_w=p["p_tx_w"],
        p_rx_min_w=p["p_rx_min_w"],
        sigma_lidar_m2=t["sigma_lidar_m2"],
        aperture_mm=p["aperture_mm"],
        wavelength_nm=p["wavelength_nm"],
        eta_sys=p["eta_sys"],
    )
    if convention == "paper":
        return lidar.lidar_range(**common, eta_tl=paper_eta_tl(sc, s), convention="paper")
    return lidar.lidar_range(
        **common,
        visibility_km=sc.optical_visibility_km,
        projected_area_m2=t["projected_area_m2"],
        convention="physical",
    )


#: Modality -> its adapter from the scenario to the model (each record's ``model``, csuas.core.modality).
ADAPTERS = PartTable("model")


def _with_key_path(scenario: Scenario, name: str, error):
    """A model's error on a parameter, named by the parameter's key in the scenario (``sensors.rf.frequency_ghz``)."""
    if not isinstance(error, ParameterError) or "." in error.name:
        return error
    for prefix, params in (
        (f"sensors.{name}", scenario.sensors[name].params),
        *((section, getattr(scenario, section)) for section in ("environment", "target")),
    ):
        if error.name in params:
            return ParameterError(f"{prefix}.{error.name}", error.value, error.allowed)
    return error


def evaluate(scenario: Scenario, convention: str | None = None) -> dict:
    """Predicted range of every sensor of the scenario.

    Parameters
    ----------
    scenario : Scenario
    convention : {"paper", "physical"}, optional
        Overrides the scenario's convention.

    Returns
    -------
    dict
        ``{sensor name: RangeResult}``.

    Raises
    ------
    ParameterError
        When a range is unbounded without a model's explanation (P_desired = 0 with nothing else
        limiting the Johnson range); an unbounded range a model explains in ``reason`` (silence
        for the acoustic model) is returned as it is.
    """
    conv = check_convention(convention or scenario.convention)
    results = {}
    for name, sensor in scenario.sensors.items():
        try:
            result = ADAPTERS[sensor.modality](scenario, sensor, conv)
        except (ParameterError, InputErrors) as exc:
            raise_all(_with_key_path(scenario, name, e) for e in getattr(exc, "errors", [exc]))
            raise
        johnson_unbounded = np.any(
            np.asarray(result.reason if result.reason is not None else "") == tir.JOHNSON_UNBOUNDED
        )
        if not np.all(np.isfinite(result.range_m)) and (result.reason is None or johnson_unbounded):
            raise ParameterError(
                f"sensors.{name}.p_desired",
                sensor.params.get("p_desired"),
                "> 0: n_ttpf = 0 gives an unbounded range that nothing else limits",
            )
        _apply_horizon(scenario, sensor, result)
        _explain_short_range(scenario, sensor, result, conv)
        altitude = scenario.target["altitude_m"]
        if altitude != 0.0:
            horizontal = horizontal_range_m(result.range_m, altitude)
            result.terms.append(Term("horizontal_range_m", horizontal, "m", "Eq. 13 (Eq. 14 takes R* for it)"))
            _add_reason(
                result,
                np.isnan(horizontal),
                f"the target flies {abs(altitude):g} m {'above' if altitude > 0 else 'below'} the sensor, "
                f"beyond the slant range: it is never within range at that altitude",
            )
        results[name] = result
    return results


#: Modality -> (effective Earth-radius factor, name) of the horizon that caps its range (each record's
#: ``horizon``); a modality without one (acoustic) is not capped.
HORIZONS = {m.name: (m.line_of_sight.k, m.line_of_sight.label) for m in RECORDS if m.line_of_sight.label is not None}
#: Heights of the flag raised when a scenario gives no sensor height: a mast-less sensor, a drone at
#: the 120 m ceiling of open-category flight [m].
REFERENCE_SENSOR_HEIGHT_M, REFERENCE_TARGET_HEIGHT_M = 2.0, 120.0


def _add_reason(result: RangeResult, mask, text: str) -> None:
    """Append ``text`` to the reason of the elements where ``mask`` holds."""
    mask = np.broadcast_to(np.asarray(mask, bool), np.shape(result.range_m))
    if not np.any(mask):
        return
    old = np.broadcast_to(np.asarray(result.reason if result.reason is not None else "", dtype=object), mask.shape)
    joined = np.where(old != "", old + "; " + text, text)
    result.reason = np.where(mask, joined, old).astype(str)


def _apply_horizon(scenario: Scenario, sensor: SensorSpec, result: RangeResult) -> None:
    """Cap a radio or optical range at the line-of-sight horizon (heights given), or flag it."""
    if sensor.modality not in HORIZONS:
        return
    k, label = HORIZONS[sensor.modality]
    height = sensor.params.get("height_m")
    if height is None:
        limit = line_of_sight_limit_m(REFERENCE_SENSOR_HEIGHT_M, REFERENCE_TARGET_HEIGHT_M, k)
        _add_reason(
            result,
            np.asarray(result.range_m) > limit,
            f"beyond the {label} of a {REFERENCE_SENSOR_HEIGHT_M:g} m sensor and a "
            f"{REFERENCE_TARGET_HEIGHT_M:g} m target ({limit / 1000:.1f} km): set "
            f"sensors.{sensor.name}.height_m and target.altitude_m to cap it",
        )
        return
    target_height = max(height + scenario.target["altitude_m"], 0.0)
    limit = float(line_of_sight_limit_m(height, target_height, k))
    capped = np.asarray(result.range_m) > limit
    result.terms.append(
        Term("horizon_m", limit, "m", f"{label}: sensor {height:g} m, target {target_height:g} m above ground")
    )
    _add_reason(result, capped, f"limited by the {label} ({limit / 1000:.2f} km)")
    result.range_m = np.where(capped, limit, result.range_m)


#: A range below this is reported with its cause [m].
SHORT_RANGE_M = 1.0


def _explain_short_range(scenario: Scenario, sensor: SensorSpec, result: RangeResult, convention: str) -> None:
    """Name the cause of a zero or near-zero range that the model left unexplained."""
    r = np.asarray(result.range_m, float)
    unexplained = (r < SHORT_RANGE_M) & (
        np.broadcast_to(np.asarray(result.reason if result.reason is not None else "", dtype=object), r.shape) == ""
    )
    if not np.any(unexplained):
        return
    if (
        sensor.modality == "lidar"
        and convention == "paper"
        and "eta_tl" not in sensor.explicit
        and {"fog", "haze"} & scenario.effects
    ):
        eta = paper_eta_tl(scenario, sensor)
        text = (
            f"eta_TL = {eta:.3g}: the paper convention applies Kruse extinction at "
            f"{scenario.optical_visibility_km:g} km visibility over Table 47's fixed "
            f"{sensor.params['tl_path_km']:g} km path, whatever the range (docs/conventions.md point 8)"
        )
    else:
        _explain_spent_budget(result, unexplained)
        return
    _add_reason(result, unexplained, f"range below {SHORT_RANGE_M:g} m: {text}")


def _explain_spent_budget(result: RangeResult, unexplained) -> None:
    """Name, per element, the losses that spend the budget before 1 m (each element's own values)."""
    terms = [
        t
        for t in result.terms
        if (t.unit == "dB" and ("loss" in t.name or "budget" in t.name or t.name.startswith("l_")))
        or t.name.startswith("eta_")
        or t.name.endswith("_no_loss_m")
    ]
    shape = np.shape(unexplained)
    values = np.array([np.broadcast_to(np.asarray(t.value, float), shape)[unexplained] for t in terms])
    values = values.reshape(len(terms), int(np.count_nonzero(unexplained)))
    combos, which = np.unique(values, axis=1, return_inverse=True)
    where = np.zeros(shape, dtype=np.int64)
    where[unexplained] = which.reshape(-1)
    for j in range(combos.shape[1]):
        causes = [f"{t.name} = {v:.3g}" + ("" if t.unit == "-" else f" {t.unit}") for t, v in zip(terms, combos[:, j])]
        text = "the budget is spent before 1 m" + (f" ({', '.join(causes)})" if causes else "")
        _add_reason(result, unexplained & (where == j), f"range below {SHORT_RANGE_M:g} m: {text}")


def horizontal_range_m(slant_range_m, altitude_m):
    """Horizontal distance [m] at a slant range and height difference (Eq. 13 with y = 0).

    The models compute the slant (line-of-sight) range R*; the paper's Eq. 14
    approximates the horizontal distance by it. A target higher above the
    sensor than its detection range is never within range: NaN there (the range
    command explains it in ``reason``).
    """
    r = np.asarray(slant_range_m, dtype=float)
    h = float(altitude_m)
    return np.where(r >= abs(h), np.sqrt(np.maximum(r**2 - h**2, 0.0)), np.nan)


def _sensor_range_m(scenario: Scenario, sensor_name: str, convention: str | None) -> float:
    """One sensor's range [m] (:func:`evaluate`), the figure of :func:`scenario_one_at_a_time` by default."""
    return float(evaluate(scenario, convention)[sensor_name].range_m)


def _current_value(scenario: Scenario, sensor_name: str, key: str) -> float:
    """The scenario's value of a varied key (NaN when it has none)."""
    if key == SWARM_KEYS[0]:
        return float(scenario.swarm.count)
    if key == SWARM_KEYS[1]:
        return float(scenario.swarm.spacing_m)
    section, _, name = key.partition(".")
    table = scenario.sensors[sensor_name].params if section == "sensor" else getattr(scenario, section, {})
    current = table.get(name)
    return float(current) if current is not None else float("nan")


def _with_value(scenario: Scenario, sensor_name: str, key: str, value) -> Scenario:
    """A copy of ``scenario`` with one parameter changed (``target.X``, ``environment.X``, ``sensor.X`` or a swarm
    key, :data:`csuas.core.scenario.SWARM_KEYS`)."""
    section, _, name = key.partition(".")
    if key in SWARM_KEYS:
        return with_swarm_value(scenario, key, value, f"vary {key}")
    if section in ("target", "environment"):
        table = dict(getattr(scenario, section))
        if name not in table:
            raise ParameterError("vary", key, f"a parameter of {section}: " + ", ".join(table))
        table[name] = check_value(f"vary {key}", load_parameters()[section][name], value)
        return replace(scenario, **{section: table})
    if section != "sensor":
        raise ParameterError("vary", key, "target.<name>, environment.<name> or sensor.<name>")
    sensor = scenario.sensors[sensor_name]
    if name not in sensor.params:
        raise ParameterError("vary", key, "a parameter of the sensor: " + ", ".join(sensor.params))
    value = check_value(f"vary {key}", load_parameters()[sensor.modality][name], value)
    params = dict(sensor.params, **{name: value})
    if name in ("p_desired", "task"):
        params.update(johnson_derived(params, sensor.explicit))
    sensors = dict(scenario.sensors, **{sensor_name: replace(sensor, params=params)})
    return replace(scenario, sensors=sensors)


def scenario_one_at_a_time(
    scenario: Scenario, sensor_name: str, variations: dict, convention: str | None = None, figure=None
):
    """One-at-a-time sensitivity of one sensor of a scenario (Section 4.9 generalised to any modality).

    Parameters
    ----------
    scenario : Scenario
    sensor_name : str
        Key of the sensor in ``scenario.sensors``.
    variations : dict
        ``{"target.d_crit_m": (low, high), "sensor.hfov_deg": (low, high), ...}``.
    convention : {"paper", "physical"}, optional
    figure : callable, optional
        ``figure(scenario, sensor_name, convention)``: the range analysed [m] (default the sensor's range of
        :func:`evaluate`; a swarm's first detection, :func:`csuas.core.swarm_detection.swarm_first_detection_m`).

    Returns
    -------
    baseline_m : float
    bars : list of csuas.core.sensitivity.TornadoBar
        Sorted by decreasing span.
    """

    if sensor_name not in scenario.sensors:
        raise ParameterError("sensor", sensor_name, ", ".join(scenario.sensors))
    only = replace(scenario, sensors={sensor_name: scenario.sensors[sensor_name]})
    variants, errors = {}, []
    for key, bounds in variations.items():
        for value in bounds:
            try:
                variants[key, value] = _with_value(only, sensor_name, key, value)
            except CsuasError as exc:
                errors.append(exc)
    raise_all({str(e): e for e in errors}.values())  # a wrong key fails both bounds: said once
    figure = figure or _sensor_range_m
    baseline = figure(only, sensor_name, convention)
    bars = []
    for key, (low, high) in variations.items():
        ranges = [figure(variants[key, v], sensor_name, convention) for v in (low, high)]
        bars.append(
            TornadoBar(
                key,
                float(low),
                _current_value(only, sensor_name, key),
                float(high),
                ranges[0],
                ranges[1],
            )
        )
    bars.sort(key=lambda bar: bar.span_m, reverse=True)
    return baseline, bars
