"""Direct references for the public core functions that other tests only reached through a caller.

``tests/test_core_table.py`` lists functions covered outside its table with the file that covers
them, and checks that the file really calls each one. These did not: each is called here on its own
against a reference written out independently (a closed form, a published table, the paper's
printed value or ITU-Rpy).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from csuas.base.errors import CsuasError, ParameterError
from csuas.core import (
    acoustic,
    camera,
    checks,
    itu,
    mrtd,
    pd_curves,
    radar,
    radiometry,
    ranges,
    result,
    scenario,
    sensitivity,
    units,
)

H, C, K_B = 6.62607015e-34, 299_792_458.0, 1.380649e-23


@pytest.mark.parametrize("wavelength_um, cie", [(0.510, 0.503), (0.555, 1.000), (0.610, 0.503), (0.650, 0.107)])
def test_photopic_efficiency_follows_the_cie_1924_table(wavelength_um, cie):
    # CIE 1924 V(lambda); the Gaussian fit departs from the table by at most 0.018 in 510-650 nm
    assert camera.photopic_efficiency(wavelength_um) == pytest.approx(cie, abs=0.02)


@pytest.mark.parametrize("frequency_ghz, temperature_c", [(10.0, 0.0), (24.0, 15.0), (94.0, 20.0)])
def test_water_permittivity_gives_itu_rpy_specific_attenuation_coefficient(frequency_ghz, temperature_c):
    itu840 = pytest.importorskip("itur.models.itu840")
    eps_re, eps_im = itu.water_permittivity(frequency_ghz, temperature_c + 273.15)
    eta = (2.0 + eps_re) / eps_im
    k_l = 0.819 * frequency_ghz / (eps_im * (1.0 + eta**2))  # ITU-R P.840 Eq. 2
    reference = np.asarray(itu840.specific_attenuation_coefficients(frequency_ghz, temperature_c))
    assert k_l == pytest.approx(float(reference), rel=1e-6)


def test_parametric_mrtd_from_a_datasheet_takes_the_band_centre():
    curve = mrtd.ParametricMrtd.from_datasheet(netd_mk=40.0, ifov_rad=6e-4, f_number=1.2, pitch_um=12.0, band="mwir")
    expected = mrtd.ParametricMrtd(netd_k=0.04, ifov_rad=6e-4, f_number=1.2, pitch_m=12e-6, wavelength_m=4e-6)
    assert dataclasses.astuple(curve) == pytest.approx(dataclasses.astuple(expected), rel=1e-12)
    # the scenario's sensor builds the same curve, IFOV = pitch / focal (Eq. 22)
    params = {"netd_mk": 40.0, "pitch_um": 12.0, "focal_mm": 20.0, "f_number": 1.2, "band": "mwir", "mrtd_k": None}
    expected = mrtd.ParametricMrtd(netd_k=0.04, ifov_rad=12e-6 / 20e-3, f_number=1.2, pitch_m=12e-6, wavelength_m=4e-6)
    assert dataclasses.astuple(mrtd.sensor_mrtd(params)) == pytest.approx(dataclasses.astuple(expected), rel=1e-12)


def test_sensor_mrtd_reaches_netd_scaled_shape_and_takes_a_user_table():
    params = {"netd_mk": 50.0, "pitch_um": 10.0, "focal_mm": 20.0, "f_number": 1.0, "band": "lwir", "mrtd_k": None}
    curve = mrtd.sensor_mrtd(params)
    nyquist = 0.5 / (10e-6 / 20e-3)  # 1 / (2 IFOV) with IFOV = pitch / focal [cy/rad]
    assert curve.nyquist_cy_rad == pytest.approx(nyquist, rel=1e-12)
    assert curve(2.0 * nyquist) == math.inf  # beyond Nyquist nothing is resolved
    assert float(curve(0.5 * nyquist)) == pytest.approx(0.050 * float(curve.shape(0.5)), rel=1e-12)
    table = {**params, "mrtd_frequency_cy_mrad": [0.5, 1.0, 2.0], "mrtd_k": [0.1, 0.2, 0.8]}
    tabulated = mrtd.sensor_mrtd(table)
    assert float(tabulated(1000.0)) == pytest.approx(0.2, rel=1e-9)  # 1 cy/mrad = 1000 cy/rad


@pytest.mark.parametrize(
    "integration, convention, expected",
    [
        ("coherent", "paper", 16.0),
        ("noncoherent", "paper", 16.0 ** (1 / 16)),
        ("noncoherent", "physical", 4.0),
        ("none", "paper", 1.0),
    ],
)
def test_integration_gain_eqs_77_78(integration, convention, expected):
    assert float(radar.integration_gain(16.0, integration, convention)) == pytest.approx(expected, rel=1e-12)


def test_radar_wavelength_uses_the_papers_c_or_the_exact_one():
    assert radar.radar_wavelength_m({"frequency_ghz": 24.0, "wavelength_m": None}, "paper") == pytest.approx(
        3e8 / 24e9, rel=1e-12
    )
    assert radar.radar_wavelength_m({"frequency_ghz": 24.0, "wavelength_m": None}, "physical") == pytest.approx(
        C / 24e9, rel=1e-12
    )
    assert radar.radar_wavelength_m({"frequency_ghz": None, "wavelength_m": 0.0125}, "paper") == 0.0125


def test_radar_frequency_is_the_given_one_or_exact_c_over_the_wavelength():
    # A given frequency is returned as given in both conventions (not c_exact / (3e8 / f)).
    assert radar.radar_frequency_ghz({"frequency_ghz": 24.0, "wavelength_m": None}) == 24.0
    assert radar.radar_frequency_ghz({"frequency_ghz": None, "wavelength_m": 0.0125}) == pytest.approx(
        C / 0.0125 / 1e9, rel=1e-12
    )


def test_rf_frequency_is_the_sensors_own_or_the_drones_link():
    target = {"rf_frequency_ghz": 2.4}  # Table 33's control link
    assert ranges.rf_frequency_ghz({"frequency_ghz": 5.8}, target) == 5.8
    assert ranges.rf_frequency_ghz({"frequency_ghz": None}, target) == 2.4
    assert ranges.rf_frequency_ghz({}, target) == 2.4


def test_band_limits_and_planck_spectral_radiance():
    assert radiometry.band_limits_um("lwir") == (8.0, 12.0)
    assert radiometry.band_limits_um("mwir") == (3.0, 5.0)
    assert radiometry.band_limits_um((1.0, 2.0)) == (1.0, 2.0)
    lam = 10e-6
    planck = 2 * H * C**2 / lam**5 / (math.exp(H * C / (lam * K_B * 300.0)) - 1) * 1e-6  # per um
    assert float(radiometry.spectral_radiance(10.0, 300.0)) == pytest.approx(planck, rel=1e-6)
    peak = 2897.771955 / 300.0  # Wien's displacement law [um]
    grid = np.linspace(peak - 0.5, peak + 0.5, 10001)
    assert grid[np.argmax(radiometry.spectral_radiance(grid, 300.0))] == pytest.approx(peak, abs=1e-3)


def test_thermal_contrast_is_eq_26_in_the_paper_convention():
    sc = scenario.load_scenario("default")
    dt0, path = ranges.thermal_contrast(sc, sc.sensors["tir"], "paper")
    t, env = sc.target, sc.environment
    linear = t["emissivity_suas"] * t["t_suas_k"] - env["emissivity_bg"] * env["t_bg_k"]
    assert abs(float(dt0)) == pytest.approx(abs(linear), rel=1e-12) and path == {}
    assert abs(linear) == pytest.approx(33.6, abs=0.05)  # README and docs/conventions.md


def test_check_convention_and_unbounded_reason():
    assert result.check_convention("physical") == "physical"
    with pytest.raises(ParameterError, match="convention"):
        result.check_convention("xray")
    assert result.unbounded_reason(np.array([1.0, 2.0])) is None
    reasons = result.unbounded_reason(np.array([1.0, np.inf]))
    assert reasons[0] == "" and reasons[1].startswith("unbounded")


@pytest.mark.parametrize("task, lp", [("detection", 1.0), ("recognition", 4.0), ("identification", 8.0)])
def test_johnson_derived_tables_20_and_21(task, lp):
    derived = scenario.johnson_derived({"task": task, "p_desired": 0.5}, explicit=set())
    assert derived == {"lp_task": lp, "n_ttpf": 1.0}  # Table 20; Table 21: P = 0.50 -> n_TTPF = 1.00
    assert scenario.johnson_derived({"task": task, "p_desired": 0.5}, explicit={"lp_task", "n_ttpf"}) == {}


def test_plausibility_warnings_flag_a_field_of_view_in_radians():
    eo = scenario.load_scenario("default").sensors["eo"]
    assert scenario.plausibility_warnings(eo) == []
    radians = dataclasses.replace(eo, params={**eo.params, "vfov_deg": math.radians(eo.params["vfov_deg"])})
    (warning,) = scenario.plausibility_warnings(radians)
    assert "vfov_deg" in warning and "radians" in warning


def test_provenance_names_scenario_preset_and_default_sources():
    found = scenario.provenance("eo", {"hfov_deg": 10.0, "n_h": 1920, "c_min": None}, {"hfov_deg": "scenario"})
    assert found["hfov_deg"] == {"value": 10.0, "unit": "deg", "source": "scenario"}
    assert found["n_h"]["source"].startswith("default (") and "c_min" not in found


def test_section_4_9_models_reproduce_the_papers_printed_ranges():
    eo = sensitivity.eo_johnson_model(0.101, 1.0, 1920, 10.0)
    assert eo == pytest.approx(0.101 / 2 * 1920 / math.radians(10.0), rel=1e-12)
    assert eo == pytest.approx(555.5, abs=0.05)  # Table 52
    assert sensitivity.acoustic_model(80.0, 10.0, 40.0) == pytest.approx(10**1.5, rel=1e-12)  # Eq. 106
    windy = sensitivity.acoustic_model(80.0, 10.0, 40.0, wind_noise_level_db=80.0, wind_distance_m=50.0)
    noise = 10 * math.log10(10**4.0 + 10 ** ((80.0 - 20 * math.log10(50.0)) / 10))  # Eqs. 107-108
    assert windy == pytest.approx(10 ** ((80.0 - 10.0 - noise) / 20), rel=1e-12)
    lam = 3e8 / 24e9
    budget = 100.0 * 10**7.0 * lam**2 * 0.01 / ((4 * math.pi) ** 3 * 10.0 * 1.381e-23 * 290.0 * 10.0 * 50e6)
    assert sensitivity.radar_model(100.0, 35.0, 24.0, 0.01, 10.0, 10.0, 50.0) == pytest.approx(budget**0.25)
    assert budget**0.25 == pytest.approx(445.3, abs=0.05)  # Section 4.9.3, Table 52


def test_table_52_platforms_match_the_printed_table():
    table = sensitivity.table_52_platforms()
    printed = {"dji_mini_4_pro": (555.5, 445.3, 100.0), "black_hornet_3": (137.4, 250.4, 5.6)}
    for name, (eo, radar_m, acoustic_m) in printed.items():
        computed = table[name]["computed_m"]
        assert computed["eo"] == pytest.approx(eo, abs=0.12)  # the paper rounds d_crit x N_H / HFOV
        assert computed["radar"] == pytest.approx(radar_m, abs=0.05)
        assert computed["acoustic"] == pytest.approx(acoustic_m, abs=0.05)
    target_terms = ("d_crit_m", "sigma_radar_m2", "sl_db")
    sensors = [
        {k: v for k, v in sensitivity._section_defaults(section).items() if k not in target_terms}
        for section in ("eo", "acoustic_calm", "radar")
    ]
    direct = sensitivity.platform_comparison(
        {"x": {"d_crit_m": 0.101, "sigma_radar_m2": 0.01, "sl_db": 80.0}}, *sensors
    )
    assert direct["x"] == pytest.approx(table["dji_mini_4_pro"]["computed_m"], rel=1e-12)


def test_power_sum_eq_108():
    assert float(units.power_sum_db(30.0, 30.0)) == pytest.approx(30.0 + 10 * math.log10(2.0), rel=1e-12)
    assert float(units.power_sum_db(42.0, -np.inf)) == pytest.approx(42.0, rel=1e-12)


def test_default_range_grid_spans_one_metre_to_three_times_the_longest_reach():
    """The longest reach: each sensor's deterministic range, or its line-of-sight horizon where nearer (the
    reference 2 m sensor and 120 m drone of csuas range, 4/3 Earth for radio, refraction 0.13 for light)."""
    from csuas.core.horizon import K_OPTICAL, K_RADIO, line_of_sight_limit_m

    sc = scenario.load_scenario("default")
    horizon = {"rf": K_RADIO, "radar": K_RADIO, "eo": K_OPTICAL, "tir": K_OPTICAL, "lidar": K_OPTICAL}
    reach = []
    for name, prediction in ranges.evaluate(sc).items():
        k = horizon.get(sc.sensors[name].modality)
        limit = math.inf if k is None else float(line_of_sight_limit_m(2.0, 120.0, k))
        reach.append(min(float(np.max(prediction.range_m)), limit))
    grid = pd_curves.default_range_grid(sc)
    assert grid[0] == 1.0 and grid[-1] == pytest.approx(3.0 * max(reach), rel=1e-12)
    assert np.allclose(np.diff(np.log(grid)), np.log(grid[1] / grid[0]))


def test_errors_are_csuas_errors():
    with pytest.raises(CsuasError):
        radiometry.band_limits_um("uv")


@pytest.mark.parametrize(
    "frequency_hz, index", [(20.0, 0), (63.0, 0), (800.0, 4), (1000.0, 4), (1250.0, 4), (20000.0, 7)]
)
def test_octave_band_index_holds_each_third_octave_in_its_octave(frequency_hz, index):
    # ISO 9613-2 Table 3's octaves 63 Hz to 8 kHz: 800 and 1250 Hz lie in the 1 kHz octave's thirds
    assert int(acoustic.octave_band_index(frequency_hz)) == index


def test_vapour_pressures_itu_r_p453_and_p676():
    itu453 = pytest.importorskip("itur.models.itu453")
    reference = float(np.asarray(itu453.saturation_vapour_pressure(20.0, 1013.25, "water")))
    assert float(itu.saturation_vapour_pressure_hpa(293.15, 1013.25)) == pytest.approx(reference, rel=1e-6)
    assert float(itu.water_vapour_pressure_hpa(7.5, 288.15)) == pytest.approx(7.5 * 288.15 / 216.7, rel=1e-12)


def test_gas_loss_matters_only_above_a_hundredth_of_a_db():
    # 0.17 dB/km: one way over 50 m is 0.0085 dB (no term), two ways 0.017 dB (a term)
    assert not bool(itu.gas_loss_matters(0.17, 50.0, ways=1))
    assert bool(itu.gas_loss_matters(0.17, 50.0, ways=2))


def test_scenario_gas_attenuation_is_p676_in_the_physical_convention_only():
    itu676 = pytest.importorskip("itur.models.itu676")
    sc = scenario.load_scenario("default")
    assert float(ranges.gas_attenuation_db_km(sc, 24.0, "paper")) == 0.0
    t_k, p_hpa, rho = 288.15, 1013.25, 7.5  # ITU-R P.835 sea level
    dry = p_hpa - rho * t_k / 216.7  # ITU-Rpy takes the dry-air pressure
    expected = float(np.asarray(itu676.gamma_exact(24.0, dry, rho, t_k)))
    assert float(ranges.gas_attenuation_db_km(sc, 24.0, "physical")) == pytest.approx(expected, rel=1e-6)


def test_thermal_extinction_adds_marshall_palmer_rain_in_the_physical_convention():
    sc = scenario.load_scenario("default")
    sensor = sc.sensors["tir"]
    table_27 = sensor.params["extinction_db_km"]
    assert [float(v) for v in ranges.thermal_extinction_db_km(sc, sensor, "paper")] == [table_27, 0.0]
    rainy = dataclasses.replace(sc, environment={**sc.environment, "rain_rate_mm_h": 30.0})
    total, rain = (float(v) for v in ranges.thermal_extinction_db_km(rainy, sensor, "physical"))
    # Marshall-Palmer N(D) = N0 exp(-Lambda D), N0 = 8000 m^-3 mm^-1, Lambda = 4.1 R^-0.21 mm^-1, extinction
    # efficiency 2: beta = 2 (pi / 4) N0 int D^2 exp(-Lambda D) dD = pi N0 / Lambda^3 [1/km after 1e-6 * 1e3]
    beta = math.pi * 8000.0 / (4.1 * 30.0**-0.21) ** 3 * 1e-3
    expected_rain = 10 * math.log10(math.e) * beta
    assert rain == pytest.approx(expected_rain, rel=1e-9) and total == pytest.approx(table_27 + expected_rain)


def test_registry_bounds_refuse_nan_and_values_above_parameters_toml():
    keys = {"g_tx_db": "radar.g_tx_db"}
    checks.require_registry_bounds({"g_tx_db": 25.0}, keys)
    for bad in (3026.0, float("nan")):
        with pytest.raises(ParameterError, match="g_tx_db"):
            checks.require_registry_bounds({"g_tx_db": bad}, keys)


def test_spectral_acoustic_range_meets_the_budget_in_the_band_that_reaches_farthest():
    """Every band solved apart by Brent's method: the returned range is the largest band's root of
    budget_b - 20 log10 R - alpha_b R / 1000 = 0 (no ground)."""
    from scipy.optimize import brentq

    from csuas.core import acoustic_spectrum as spectrum

    air = {"temperature_k": 293.15, "relative_humidity_pct": 70.0, "pressure_kpa": 101.325}
    wind = {"wind_speed_m_s": 0.3, "diameter_m": 0.01}
    kwargs = {"sl_db": 80.0, "blade_passing_hz": 200.0, "snr_req_db": 10.0, "g_array_db": 6.0, "noise_level_db": 35.0}
    result = spectrum.spectral_acoustic_range(**kwargs, air=air, wind=wind)
    bands = spectrum.third_octave_bands_hz()
    noise = 10 * np.log10(
        10 ** (spectrum.ambient_spectrum_db(35.0) / 10) + 10 ** (spectrum.wind_noise_spectrum_db(0.3, 0.01) / 10)
    )
    budget = spectrum.rotor_spectrum_db(80.0, 200.0) - noise + 6.0 - 10.0
    alpha = acoustic.iso9613_absorption_db_km(bands, 20.0, 70.0, 101.325)
    roots = [
        brentq(lambda r, b=b, a=a: b - 20 * math.log10(r) - a * r / 1000.0, 1e-6, 1e8) if b > 0 else 0.0
        for b, a in zip(budget, alpha)
    ]
    assert float(result.range_m) == pytest.approx(max(roots), rel=1e-6)


def test_coverage_estimate_brackets_the_measured_demo_site_and_grows_with_the_dem():
    """The demo site (400^2 cells, 3 sensors, 2 levels, 2-of-3 layers, one radio map at the default 10^6
    rays) took 14.7 s on 2 CPU cores at load 1.3 (README, measured): the estimate lies within a factor 2; a
    DEM 4 times larger costs more time and memory, a DEM of 20 000^2 cells more than any machine of ours has."""
    from csuas.core.coverage_cost import coverage_estimate

    demo = coverage_estimate((400, 400), 3, 2, True, radio_maps=1, radio_samples=1_000_000, fresnel_links=2)
    assert 14.7 / 2 <= demo.seconds <= 14.7 * 2
    bigger = coverage_estimate((800, 800), 3, 2, True, radio_maps=1, radio_samples=1_000_000)
    assert bigger.seconds > demo.seconds and bigger.bytes > demo.bytes
    assert coverage_estimate((20_000, 20_000), 3, 2, False).bytes > 24 * 2**30


def test_receiver_and_lidar_cells_count_by_hand():
    """RF: 1024 bins x ceil(120 deg / 25 deg) = 5120 cells; lidar: ceil((2000 - 50) m / 1.5 m) x 10^4 beams."""
    from csuas.core import false_alarms

    assert false_alarms.receiver_cells(1024, 120.0, 25.0) == 1024 * 5
    assert false_alarms.receiver_cells(24, 360.0, 20.0) == 24 * 18
    assert false_alarms.lidar_cells(2000.0, 50.0, 1.5, 10_000) == 1300 * 10_000
    with pytest.raises(ParameterError, match="reach_m"):
        false_alarms.lidar_cells(40.0, 50.0, 1.5, 10)
