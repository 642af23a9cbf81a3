"""Hostile values into every range model of the core: never a silent 0, inf or NaN.

The core's policy (core/checks.py): NaN, an infinite dB value, or a value outside a parameter's
domain raises ParameterError naming the parameter; a budget beyond float64 gives R = inf with a
``reason``. Every numeric parameter of every range entry point is probed with NaN and +/-inf, and
every loss and power with a negative value.
"""

import math
import re

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core import acoustic, eo, lidar, radar, rf, tir
from csuas.core.mrtd import ParametricMrtd

MODELS = {
    "eo": (
        eo.eo_range,
        dict(
            d_crit_m=0.101,
            hfov_deg=10.0,
            n_h=1920,
            lp_task=1.0,
            n_ttpf=1.0,
            c_eo=0.5,
            c_min=0.05,
            wavelength_nm=550.0,
            visibility_km=10.0,
        ),
    ),
    "tir_johnson": (tir.tir_johnson_range, dict(d_crit_m=0.101, hfov_deg=36.67, n_h=1280, lp_task=1.0, n_ttpf=1.0)),
    "tir_mrtd": (
        tir.tir_mrtd_range,
        dict(
            mrtd=ParametricMrtd(netd_k=0.05, ifov_rad=5e-4, f_number=1.0, pitch_m=10e-6, wavelength_m=10e-6),
            d_crit_m=0.101,
            lp_task=1.0,
            n_ttpf=1.0,
            delta_t0_k=15.0,
            extinction_db_km=0.2,
        ),
    ),
    "acoustic": (
        acoustic.acoustic_range,
        dict(
            sl_db=80.0, snr_req_db=10.0, noise_level_db=35.0, g_array_db=20.0, wind_speed_m_s=6.7, wind_distance_m=50.0
        ),
    ),
    "rf": (
        rf.rf_range,
        dict(
            p_tx_w=0.1,
            g_tx_dbi=8.0,
            g_rx_db=14.0,
            frequency_ghz=2.4,
            s_rx_dbm=-100.0,
            rain_rate_mm_h=6.0,
            lwc_g_m3=0.2,
            d_rain_km=1.0,
            d_fog_km=1.0,
        ),
    ),
    "radar": (
        radar.radar_range,
        dict(
            p_tx_w=10.0,
            g_tx_db=25.0,
            g_rx_db=25.0,
            wavelength_m=0.0125,
            sigma_m2=0.01,
            snr_min_db=10.0,
            t0_k=290.0,
            noise_figure_db=10.0,
            bandwidth_mhz=200.0,
            n_pulses=10,
            integration="coherent",
            l_hardware_db=10.0,
            l_processing_db=3.0,
            rain_rate_mm_h=6.0,
            lwc_g_m3=0.2,
        ),
    ),
    "lidar": (
        lidar.lidar_range,
        dict(
            p_tx_w=1.0,
            p_rx_min_w=1e-10,
            sigma_lidar_m2=0.006,
            aperture_mm=3.0,
            wavelength_nm=1550.0,
            eta_sys=0.5,
            eta_tl=0.681,
        ),
    ),
}
#: Arguments whose error names the scenario's canonical parameter instead.
CANONICAL = {("rf", "p_tx_w"): "rf_power_w"}
#: Parameters where -inf is meaningful (silence), answered by an explained unbounded range.
INF_ALLOWED = {("acoustic", "noise_level_db")}
#: Losses, powers, sizes and rates: a negative value is never physical.
NON_NEGATIVE = (
    "_w",
    "_m2",
    "_m",
    "_mm",
    "_nm",
    "_km",
    "_mm_h",
    "_g_m3",
    "l_hardware_db",
    "l_processing_db",
    "d_crit_m",
    "wind_speed_m_s",
    "extinction_db_km",
    "n_h",
    "n_pulses",
    "eta_",
    "c_min",
    "lp_task",
    "n_ttpf",
    "hfov_deg",
    "visibility_km",
    "t0_k",
    "bandwidth_mhz",
    "frequency_ghz",
)


def _cases():
    for model, (_, kwargs) in MODELS.items():
        for name, value in kwargs.items():
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                continue
            bad = [math.nan, math.inf, -math.inf]
            if name.endswith(NON_NEGATIVE) or name.startswith(NON_NEGATIVE):
                bad.append(-abs(value) - 1.0)
            for v in bad:
                if (model, name) in INF_ALLOWED and v == -math.inf:
                    continue
                yield pytest.param(model, name, v, id=f"{model}.{name}={v}")


def _assert_never_silent(result, name):
    r = np.asarray(result.range_m, float)
    reason = np.broadcast_to(np.asarray(result.reason if result.reason is not None else ""), r.shape)
    silent = (~np.isfinite(r) | (r == 0.0)) & (reason == "")
    assert not np.any(silent), (name, r, reason)


@pytest.mark.parametrize("model, name, value", list(_cases()))
def test_a_hostile_value_is_refused_naming_it_or_explained(model, name, value):
    function, kwargs = MODELS[model]
    try:
        result = function(**{**kwargs, name: value})
    except ParameterError as exc:
        assert CANONICAL.get((model, name), name) in str(exc)
        return
    _assert_never_silent(result, name)


@pytest.mark.parametrize("model", sorted(MODELS))
def test_the_defaults_themselves_give_a_finite_positive_range(model):
    function, kwargs = MODELS[model]
    r = np.asarray(function(**kwargs).range_m)
    assert np.all(np.isfinite(r) & (r > 0))


def test_an_absurd_but_finite_budget_is_an_explained_unbounded_range():
    result = rf.rf_range(p_tx_w=0.1, g_tx_dbi=8.0, g_rx_db=14.0, frequency_ghz=2.4, s_rx_dbm=-7000.0)
    assert np.isinf(result.range_m) and str(result.reason).startswith("unbounded")


#: Every model's arguments with an entry in defaults/parameters.toml, and that entry.
REGISTRY_OF = {
    "eo": eo.EO_REGISTRY,
    "tir_johnson": tir.TIR_JOHNSON_REGISTRY,
    "tir_mrtd": tir.TIR_MRTD_REGISTRY,
    "acoustic": acoustic.ACOUSTIC_REGISTRY,
    "rf": rf.RF_REGISTRY,
    "radar": radar.RADAR_REGISTRY,
    "lidar": lidar.LIDAR_REGISTRY,
}


def _registry_max(key: str) -> float:
    from csuas.defaults import load_parameters

    section, entry = key.split(".")
    return float(load_parameters()[section][entry]["max"])


def _above_cases():
    for model, keys in REGISTRY_OF.items():
        for name, key in keys.items():
            if name not in MODELS[model][1]:
                continue
            high = _registry_max(key)
            yield pytest.param(model, name, high * 10.0 if high > 0 else high + 1.0, key, id=f"{model}.{name}")


@pytest.mark.parametrize("model, name, value, key", list(_above_cases()))
def test_every_parameter_above_its_registry_bound_is_refused_naming_it(model, name, value, key):
    """The upper bound defaults/parameters.toml states holds for the model called directly, not only for scenarios."""
    function, kwargs = MODELS[model]
    bound = re.escape(f"<= {_registry_max(key):g}: {key} in defaults/parameters.toml")
    with pytest.raises(ParameterError, match=rf"^{name} = .*{bound}"):
        function(**{**kwargs, name: value})


#: Finite but absurd inputs that used to overflow into an infinite range with no reason (issue 22):
#: (model, parameter, value). Above the registry they are refused; below, the range is finite or explained.
ABSURD = [
    ("radar", "g_tx_db", 3026.0),
    ("radar", "g_rx_db", 3026.0),
    ("radar", "p_tx_w", 1e300),
    ("radar", "sigma_m2", 1e300),
    ("rf", "g_tx_dbi", 3026.0),
    ("rf", "p_tx_w", 1e300),
    ("tir_johnson", "d_crit_m", 1.7e308),
    ("tir_johnson", "lp_task", 5e-324),
    ("tir_johnson", "n_ttpf", 5e-324),
    ("eo", "d_crit_m", 1.7e308),
    ("lidar", "p_tx_w", 1e300),
    ("lidar", "p_tx_w", 1.7e308),
    ("lidar", "p_rx_min_w", 5e-324),
    ("lidar", "sigma_lidar_m2", 1e300),
    ("lidar", "sigma_lidar_m2", 1.7e308),
    ("lidar", "aperture_mm", 1e100),
    ("lidar", "aperture_mm", 1e300),
    ("lidar", "aperture_mm", 1.7e308),
    ("lidar", "wavelength_nm", 5e-324),
    ("acoustic", "sl_db", 3026.0),
]


@pytest.mark.parametrize("model, name, value", ABSURD, ids=[f"{m}.{n}={v:g}" for m, n, v in ABSURD])
@pytest.mark.parametrize("convention", ["paper", "physical"])
def test_an_absurd_finite_input_is_refused_or_gives_an_explained_range(model, name, value, convention):
    import warnings

    function, kwargs = MODELS[model]
    if model not in ("tir_johnson",):
        kwargs = {**kwargs, "convention": convention}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no overflow on the way either
            result = function(**{**kwargs, name: value})
    except ParameterError as exc:
        assert str(exc).startswith(f"{CANONICAL.get((model, name), name)} = ") or name in str(exc)
        return
    _assert_never_silent(result, name)


#: NaN that a model used to ignore (a weather term skipped when ``NaN > 0`` is False, a term of the
#: other convention never read): (model, parameter). NaN in is an error naming it, in either convention.
NAN_IGNORED = [
    ("radar", "rain_rate_mm_h"),
    ("radar", "lwc_g_m3"),
    ("radar", "temperature_k"),
    ("radar", "d_rain_km"),
    ("radar", "d_fog_km"),
    ("radar", "loss_frequency_ghz"),
    ("lidar", "visibility_km"),
    ("lidar", "eta_tl"),
    ("rf", "temperature_k"),
    ("rf", "d_rain_km"),
    ("rf", "d_fog_km"),
]


@pytest.mark.parametrize("model, name", NAN_IGNORED, ids=[f"{m}.{n}" for m, n in NAN_IGNORED])
@pytest.mark.parametrize("convention", ["paper", "physical"])
def test_nan_is_never_ignored(model, name, convention):
    function, kwargs = MODELS[model]
    with pytest.raises(ParameterError, match=rf"^{name} = nan is invalid"):
        function(**{**kwargs, name: math.nan, "convention": convention})


def test_a_negative_loss_is_refused():
    with pytest.raises(ParameterError, match="l_hardware_db"):
        radar.radar_range(
            p_tx_w=10.0, g_tx_db=25.0, g_rx_db=25.0, wavelength_m=0.0125, sigma_m2=0.01, l_hardware_db=-100.0
        )


def test_require_names_the_offending_element_of_an_array():
    """The mask used to be an integer array (~False == -1), so arr[mask] indexed by position."""
    from csuas.core.checks import require

    with pytest.raises(ParameterError, match="x = -3.0 is invalid"):
        require("x", [1.0, 2.0, -3.0], gt=0)
    with pytest.raises(ParameterError, match="x = 0.0 is invalid"):
        require("x", [0.0], gt=0)


def test_a_zero_emissivity_or_a_frozen_background_is_a_valid_thermal_scene():
    from csuas.core.radiometry import band_radiance, graybody_apparent_temperature, radiance_temperature

    assert radiance_temperature(0.0) == 0.0
    assert band_radiance(0.0) == 0.0
    assert graybody_apparent_temperature(0.0, 288.15) == 0.0
    np.testing.assert_allclose(radiance_temperature(band_radiance(np.array([0.0, 288.15]))), [0.0, 288.15], atol=1e-4)
