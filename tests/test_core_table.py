"""Every public function of the core, as a table (in the manner of colour-science's tests).

Each row gives a function, scalar inputs and an independent reference (a closed form written out
here from the paper's equation, or a value the paper prints). For every row the same four checks
run: the reference value; n-dimensional broadcasting (a (2, 3) array equals the function applied
element by element); 0-d in gives 0-d out and float32 in gives float64-close finite out; NaN in
gives NaN out or a ParameterError naming the parameter, never a silent number. Functions whose
references live in a dedicated test file are listed in COVERED_ELSEWHERE with that file; a public
function in neither place fails ``test_every_public_core_function_has_a_row``.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import math
import pkgutil
import re
from pathlib import Path

import numpy as np
import pytest

import csuas.core
from csuas.base.errors import ParameterError
from csuas.core import (
    acoustic,
    atmosphere,
    coverage,
    dielectric,
    eo,
    horizon,
    johnson,
    lidar,
    radar,
    rf,
    terrain,
    tir,
    units,
)

C = 299_792_458.0
A = 6_371_000.0


def _range(result):
    return result.range_m if hasattr(result, "range_m") else result


#: (name, function, scalar keyword arguments, reference, the argument that broadcasts)
ROWS = [
    ("units.db_to_linear", units.db_to_linear, {"value_db": 10.0}, 10.0, "value_db"),
    ("units.linear_to_db", units.linear_to_db, {"value": 100.0}, 20.0, "value"),
    ("units.watt_to_dbm", units.watt_to_dbm, {"power_w": 0.1}, 20.0, "power_w"),
    ("units.wavelength_m", units.wavelength_m, {"frequency_ghz": 24.0}, C / 24e9, "frequency_ghz"),
    ("units.frequency_ghz", units.frequency_ghz, {"wavelength_m_": 0.0125}, C / 0.0125 / 1e9, "wavelength_m_"),
    ("units.wavenumber_rad_m", units.wavenumber_rad_m, {"frequency_ghz": 10.0}, 2e10 * math.pi / C, "frequency_ghz"),
    ("units.per_km_to_db_per_km", units.per_km_to_db_per_km, {"beta_per_km": 1.0}, 10 / math.log(10), "beta_per_km"),
    ("units.db_per_km_to_per_km", units.db_per_km_to_per_km, {"gamma_db_km": 10 / math.log(10)}, 1.0, "gamma_db_km"),
    (
        "atmosphere.koschmieder_extinction_per_km",
        atmosphere.koschmieder_extinction_per_km,
        {"visibility_km": 10.0},
        -math.log(0.02) / 10.0,
        "visibility_km",
    ),
    ("atmosphere.kruse_q", atmosphere.kruse_q, {"visibility_km": 3.0}, 0.16 * 3.0 + 0.34, "visibility_km"),  # Eq. 20
    (
        "atmosphere.kruse_extinction_per_km",
        atmosphere.kruse_extinction_per_km,
        {"wavelength_nm": 850.0, "visibility_km": 10.0},
        -math.log(0.02) / 10.0 * (850 / 550) ** -1.3,
        "visibility_km",
    ),
    (
        "atmosphere.extinction_per_km",
        atmosphere.extinction_per_km,
        {"wavelength_nm": 550.0, "visibility_km": 20.0, "convention": "physical"},
        -math.log(0.02) / 20.0,
        "visibility_km",
    ),
    (
        "atmosphere.transmittance",
        atmosphere.transmittance,
        {"extinction": 1.0, "range_m": 1000.0, "convention": "physical"},
        math.exp(-1.0),
        "range_m",
    ),
    (
        "atmosphere.db_transmittance",
        atmosphere.db_transmittance,
        {"attenuation_db_km": 3.0, "range_m": 1000.0},
        10**-0.3,
        "range_m",
    ),
    (
        "atmosphere.koschmieder_apparent_contrast",
        atmosphere.koschmieder_apparent_contrast,
        {"c0": 0.5, "extinction_per_km": 1.0, "range_m": 1000.0},
        0.5 * math.exp(-1.0),
        "range_m",
    ),
    (
        "atmosphere.range_for_transmittance",
        atmosphere.range_for_transmittance,
        {"extinction": 1.0, "tau": math.exp(-2.0), "convention": "physical"},
        2000.0,
        "tau",
    ),
    (
        "eo.contrast_limited_range_m",
        eo.contrast_limited_range_m,
        {"c0": 0.5, "c_min": 0.05, "extinction": 1.0, "convention": "physical"},
        1000.0 * math.log(10.0),
        "c0",
    ),
    (
        "eo.eo_range",
        eo.eo_range,  # Section 4.9.1: 555.5 m
        {
            "d_crit_m": 0.101,
            "hfov_deg": 10.0,
            "n_h": 1920,
            "lp_task": 1.0,
            "n_ttpf": 1.0,
            "c_eo": 0.5,
            "c_min": 0.05,
            "wavelength_nm": 550.0,
            "visibility_km": 10.0,
        },
        0.101 / (2 * math.radians(10.0) / 1920),
        "d_crit_m",
    ),
    ("johnson.ifov_rad", johnson.ifov_rad, {"hfov_deg": 10.0, "n_h": 1920}, math.radians(10.0) / 1920, "hfov_deg"),
    (
        "johnson.ifov_from_pitch_rad",
        johnson.ifov_from_pitch_rad,
        {"pitch_um": 10.0, "focal_mm": 20.0},
        5e-4,
        "pitch_um",
    ),
    (
        "johnson.johnson_range_m",
        johnson.johnson_range_m,
        {"d_crit_m": 0.101, "ifov": 1e-4, "lp_task": 2.0},
        0.101 / (2 * 2.0 * 1e-4),
        "d_crit_m",
    ),  # Eq. 18
    (
        "tir.tir_johnson_range",
        tir.tir_johnson_range,
        {"d_crit_m": 0.101, "hfov_deg": 36.67, "n_h": 1280, "lp_task": 1.0, "n_ttpf": 1.0},
        0.101 / (2 * math.radians(36.67) / 1280),
        "d_crit_m",
    ),
    (
        "tir.delta_t_linear",
        tir.delta_t_linear,  # Eq. 26: 33.63 K with the defaults
        {"emissivity_suas": 0.68, "t_suas_k": 288.15, "emissivity_bg": 0.77, "t_bg_k": 298.15},
        0.68 * 288.15 - 0.77 * 298.15,
        "t_suas_k",
    ),
    ("acoustic.array_gain_db", acoustic.array_gain_db, {"n_micro": 128}, 10 * math.log10(128), "n_micro"),  # Eq. 42
    (
        "acoustic.acoustic_range",
        acoustic.acoustic_range,  # Eq. 44 without wind
        {"sl_db": 80.0, "snr_req_db": 10.0, "noise_level_db": 35.0, "g_array_db": 20.0},
        10 ** ((80 - 10 - 35 + 20) / 20),
        "sl_db",
    ),
    (
        "rf.free_space_path_loss_db",
        rf.free_space_path_loss_db,
        {"frequency_ghz": 2.4, "distance_m": 1000.0},
        20 * math.log10(4 * math.pi * 1000.0 * 2.4e9 / C),
        "distance_m",
    ),
    (
        "rf.received_power_dbm",
        rf.received_power_dbm,
        {"p_tx_w": 0.1, "g_tx_dbi": 8.0, "g_rx_db": 14.0, "frequency_ghz": 2.4, "distance_m": 1000.0},
        20 + 8 + 14 - 20 * math.log10(4 * math.pi * 1000.0 * 2.4e9 / C),
        "distance_m",
    ),
    (
        "rf.rf_range",
        rf.rf_range,  # Eq. 57 in free space
        {"p_tx_w": 0.1, "g_tx_dbi": 8.0, "g_rx_db": 14.0, "frequency_ghz": 2.4, "s_rx_dbm": -100.0},
        C / 2.4e9 / (4 * math.pi) * 10 ** ((20 + 8 + 14 + 100) / 20),
        "s_rx_dbm",
    ),
    (
        "radar.thermal_noise_power_w",
        radar.thermal_noise_power_w,  # Eq. 73
        {"t0_k": 290.0, "noise_figure_db": 10.0, "bandwidth_mhz": 200.0, "k_b": 1.38e-23},
        1.38e-23 * 290 * 10 * 200e6,
        "bandwidth_mhz",
    ),
    (
        "radar.received_power_w",
        radar.received_power_w,  # Eq. 68
        {"p_tx_w": 10.0, "g_tx_db": 25.0, "g_rx_db": 25.0, "wavelength_m": 0.0125, "sigma_m2": 0.01, "range_m": 100.0},
        10 * 10**5 * 0.0125**2 * 0.01 / ((4 * math.pi) ** 3 * 100.0**4),
        "range_m",
    ),
    (
        "radar.radar_range",
        radar.radar_range,  # Section 4.9.3's radar: 445.3 m (Eq. 109)
        {
            "p_tx_w": 100.0,
            "g_tx_db": 35.0,
            "g_rx_db": 35.0,
            "wavelength_m": 0.0125,
            "sigma_m2": 0.01,
            "bandwidth_mhz": 50.0,
            "k_b": 1.381e-23,
        },
        (100 * 10**7 * 0.0125**2 * 0.01 / ((4 * math.pi) ** 3 * 10 * 1.381e-23 * 290 * 10 * 50e6)) ** 0.25,
        "p_tx_w",
    ),
    (
        "radar.radar_range_of",
        radar.radar_range_of,  # the same radar as a RadarSensor record, against sigma = 0.02 m^2 (Eq. 109)
        {
            "sensor": radar.RadarSensor(
                p_tx_w=100.0, g_tx_db=35.0, g_rx_db=35.0, wavelength_m=0.0125, bandwidth_mhz=50.0, k_b=1.381e-23
            ),
            "sigma_m2": 0.02,
        },
        (100 * 10**7 * 0.0125**2 * 0.02 / ((4 * math.pi) ** 3 * 10 * 1.381e-23 * 290 * 10 * 50e6)) ** 0.25,
        "sigma_m2",
    ),
    (
        "lidar.divergence_rad",
        lidar.divergence_rad,
        {"wavelength_nm": 1550.0, "aperture_mm": 3.0},
        1.22 * 1550e-9 / 3e-3,
        "aperture_mm",
    ),  # Airy divergence
    (
        "lidar.lidar_range",
        lidar.lidar_range,  # Eqs. 99, 104 with Table 47's losses
        {
            "p_tx_w": 1.0,
            "p_rx_min_w": 1e-10,
            "sigma_lidar_m2": 0.006,
            "aperture_mm": 3.0,
            "wavelength_nm": 1550.0,
            "eta_sys": 0.5,
            "eta_tl": 0.681,
        },
        (1.0 / 1e-10 * 0.006 / (1.22**2 * math.pi) * 3e-3**4 / 1550e-9**2) ** 0.25 * (0.5 * 0.681**2) ** 0.25,
        "p_tx_w",
    ),
    (
        "horizon.horizon_distance_m",
        horizon.horizon_distance_m,
        {"height_m": 2.0},
        math.sqrt(2 * 4 / 3 * A * 2.0),
        "height_m",
    ),
    (
        "horizon.line_of_sight_limit_m",
        horizon.line_of_sight_limit_m,
        {"sensor_height_m": 2.0, "target_height_m": 120.0},
        math.sqrt(2 * 4 / 3 * A * 2.0) + math.sqrt(2 * 4 / 3 * A * 120.0),
        "target_height_m",
    ),
    (
        "dielectric.complex_permittivity",
        dielectric.complex_permittivity,
        {"relative_permittivity": 5.0, "conductivity_s_m": 0.01, "frequency_ghz": 1.0},
        5.0 - 1j * 0.01 / (2 * math.pi * 1e9 * 8.8541878128e-12),
        "frequency_ghz",
    ),
    (
        "dielectric.ground_permittivity",
        dielectric.ground_permittivity,
        {"ground": {"relative_permittivity": 15.0, "conductivity_s_m": 0.035}, "frequency_ghz": 2.4},
        15.0 - 1j * 0.035 / (2 * math.pi * 2.4e9 * 8.8541878128e-12),
        "frequency_ghz",
    ),
    # a bearing clockwise from grid north on a north-up grid (rows run south): north-east is 45 degrees
    ("terrain.bearing_deg", terrain.bearing_deg, {"d_row": -1.0, "d_col": 1.0}, 45.0, "d_col"),
    (
        "terrain.off_boresight_deg",
        terrain.off_boresight_deg,
        {"bearing": 350.0, "azimuth_deg": 10.0},
        -20.0,
        "bearing",
    ),
    (
        "coverage.elevation_deg",
        coverage.elevation_deg,
        {"ground_m": 1000.0, "height_m": 100.0, "k_factor": 4.0 / 3.0},
        math.degrees(math.atan((100.0 - 1000.0**2 / (2 * 4 / 3 * A)) / 1000.0)),
        "height_m",
    ),
]

#: Public functions whose references live in a dedicated test file.
COVERED_ELSEWHERE = {
    "micro_doppler.rotor_blade_signal": "tests/test_micro_doppler.py (line integral, PO of flat blades)",
    "micro_doppler.blade_flash_period_s": "tests/test_micro_doppler.py (Chen 2006 Sec. V, 1/(N Omega), 1/(2 N Omega))",
    "micro_doppler.line_spacing_hz": "tests/test_micro_doppler.py (N Omega; spectrum of the closed form)",
    "micro_doppler.max_tip_doppler_hz": "tests/test_micro_doppler.py (2 v_tip cos(beta) / lambda)",
    "micro_doppler.blade_line_rcs_m2": "tests/test_micro_doppler_detection.py (N Omega spacing; Parseval sum)",
    "micro_doppler_detection.line_snr_fractions": "tests/test_micro_doppler_detection.py (shares sum to 1)",
    "micro_doppler_detection.bird_guard_doppler_hz": "tests/test_micro_doppler_detection.py (2 v_w / lambda)",
    "micro_doppler_detection.tested_bins": "tests/test_micro_doppler_detection.py (bins outside the guard)",
    "micro_doppler_detection.blade_feature_pd": "tests/test_micro_doppler_detection.py (Swerling 1, Monte Carlo)",
    "rcs_statistics.fit_chi_square": "tests/test_rcs_statistics.py (gamma samples)",
    "detection.target_pixels": "tests/test_tir_netd.py (closed form)",
    "terrain.curvature_drop_m": "tests/test_terrain.py (closed form)",
    "coverage.link_frequency_ghz": "tests/test_coverage.py (Table 33's link, Table 39's wavelength)",
    "coverage.free_space_equivalent_range_m": "tests/test_coverage.py (round trip through Eq. 54)",
    "coverage.multipath_detection": "tests/test_coverage.py (free-space path gains at known distances)",
    "terrain.fresnel_clearance": "tests/test_terrain.py (flat ground in closed form, a knife edge's crest)",
    "horizon.first_fresnel_radius_m": "tests/test_terrain.py (closed form at 2.4 GHz)",
    "coverage.farthest_ground_m": "tests/test_coverage_tiles.py (the farthest corner of a grid)",
    "coverage.in_window": "tests/test_coverage_tiles.py (a sensor placed in its window, exactly)",
    "coverage.reach_window": "tests/test_coverage_tiles.py (every cell within the reach, clipped at the edge)",
    "coverage.fresnel_layers": "tests/test_coverage.py (a wall's crest ratio read back from the GeoTIFF)",
    "coverage.fused_visibility": "tests/test_coverage.py (two sight lines over a wall, with curvature)",
    "coverage.lowest_detected_level_m": "tests/test_coverage.py (levels out of order, enumerated)",
    "terrain.cells_around": "tests/test_terrain.py (exact index arithmetic)",
    "terrain.gaussian_hills": "tests/test_terrain_gdal.py (the terrain of the GDAL and sight-line cross-checks)",
    "terrain.lowest_visible_height_m": "tests/test_terrain.py (a wall's sight line, the viewshed at 4 levels)",
    "coverage_cost.coverage_estimate": "tests/test_core_direct.py (the measured demo site)",
    "coverage_cost.coverage_tiles_estimate": "tests/test_coverage_tiles.py (a measured worker, bounded in the DEM)",
    "birds.bird_rcs_m2": "tests/test_engagement_core.py (overlaps the drone's 24 GHz distribution)",
    "birds.normal_reflectivity": "tests/test_engagement_core.py (Fresnel at normal incidence)",
    "birds.random_aspects_rad": "tests/test_engagement_core.py (uniform on the sphere)",
    "birds.spheroid_rcs_m2": "tests/test_engagement_core.py (sphere and long-spheroid limits)",
    "clutter.cell_rcs_m2": "tests/test_engagement_core.py (constant-gamma closed form)",
    "clutter.exceedance": "tests/test_engagement_core.py, tests/test_engagement.py (exponential clutter)",
    "clutter.sigma0": "tests/test_engagement_core.py (gamma sin(grazing))",
    "false_alarms.beamwidth_deg": "tests/test_engagement_core.py (from the antenna gain)",
    "false_alarms.false_alarms_per_look": "tests/test_engagement_core.py (Pfa x cells)",
    "false_alarms.imaging_cells": "tests/test_engagement_core.py (pixels x frames)",
    "false_alarms.per_hour": "tests/test_engagement_core.py, tests/test_engagement.py (Monte Carlo within 3 SE)",
    "false_alarms.radar_cells": "tests/test_engagement_core.py (range x Doppler x beam cells)",
    "false_alarms.receiver_cells": "tests/test_core_direct.py (frequency bins x bearing cells, by hand)",
    "false_alarms.lidar_cells": "tests/test_core_direct.py (range gates x beam positions, by hand)",
    "false_alarms.range_resolution_m": "tests/test_engagement_core.py (c / 2B)",
    "m_of_n.first_confirmation": "tests/test_engagement_core.py (brute-force enumeration)",
    "modality.check_declared": "tests/test_modality.py (a section without a record, a record declared twice)",
    "modality.check_modality": "tests/test_modality.py (each missing part named)",
    "modality.resolve_part": "tests/test_modality.py (a detector that does not resolve)",
    "terrain.line_of_sight": "tests/test_engagement.py (agrees with the viewshed)",
    "terrain.height_at": "tests/test_terrain.py and tests/test_coverage.py (flat and ridged DEMs)",
    "coverage.sensor_layers": "tests/test_coverage.py (flat terrain: the slant-range rule cell by cell)",
    "coverage.fused_layers": "tests/test_coverage.py (the OR covers each sensor)",
    "coverage.mapped_reach_m": "tests/test_coverage.py (Pd below 0.001 beyond it; the visible layer's nodata)",
    "terrain.viewshed": "tests/test_terrain.py (smooth-Earth horizons, a ridge's shadow)",
    "camera.luminance_excess": "tests/test_camera.py (Eq. 3 inverted)",
    "camera.photopic_efficiency": "tests/test_core_direct.py (CIE 1924 table)",
    "camera.photons_per_lumen": "tests/test_camera.py (independent quadrature)",
    "camera.focal_plane_illuminance_lx": "tests/test_camera.py (camera equation)",
    "camera.electron_rate": "tests/test_camera.py",
    "camera.auto_exposure_s": "tests/test_camera.py",
    "camera.pixel_noise_e": "tests/test_camera.py",
    "camera.light_limited_range_m": "tests/test_camera.py (closed form without atmosphere)",
    "detection.blob_snr": "tests/test_tir_netd.py (both regimes, continuity)",
    "tir.tir_netd_range": "tests/test_tir_netd.py (closed forms of both regimes, attenuated root)",
    "detection.gaussian_pd": "tests/test_tir_netd.py (normal quantiles, A&S Table 26.5)",
    "detection.gaussian_required_snr": "tests/test_tir_netd.py (normal quantiles)",
    "rcs_statistics.aspect_chi_square_dof": "tests/test_rcs_statistics.py (shipped table, nearest band)",
    "rcs_statistics.pd_chi_square_target": "tests/test_rcs_statistics.py (Swerling 1 and 3 limits)",
    "rcs_statistics.fit_lognormal": "tests/test_rcs_statistics.py (3GPP-like samples)",
    "rcs_statistics.pd_over_rcs_samples": "tests/test_rcs_statistics.py (Swerling 1 limit, steady limit)",
    "rcs_statistics.rcs_summary": "tests/test_rcs_statistics.py",
    "pd_curves.approach": "tests/test_pd_curves.py",
    "pd_curves.default_range_grid": "tests/test_core_direct.py; tests/test_pd_cli.py (grid reaches the longest range)",
    "pd_curves.fuse": "tests/test_pd_curves.py (exact product for n-of-n)",
    "pd_curves.fused_cumulative": "tests/test_pd_curves.py (k-of-n and OR by hand), tests/test_pd_cli.py (enumeration)",
    "pd_curves.fused_first_detection_m": "tests/test_pd_curves.py (a look, by hand)",
    "pd_curves.fused_pd_of_range": "tests/test_pd_curves.py (OR rule on each sensor)",
    "pd_curves.margin_db": "tests/test_pd_curves.py (R^-4 and R^-2 laws, two-way rain attenuation)",
    "pd_curves.range_at_pd": "tests/test_pd_curves.py (closed-form Pd), tests/test_pd_cli.py (Swerling 1, TTPF)",
    "pd_curves.sensor_pd": "tests/test_pd_curves.py (the detectors' closed forms at the deterministic range)",
    "checks.require_all": "tests/test_detection.py",
    "detection.energy_detector_pd": "tests/test_detection.py (Monte Carlo, adaptive quadrature, Swerling 1 identity)",
    "detection.energy_detector_threshold": "tests/test_detection.py (noise-only gamma tail)",
    "detection.imaging_pd": "tests/test_detection.py (Table 21 at Eq. 18 ranges)",
    "detection.lidar_pd_gaussian": "tests/test_detection.py (Monte Carlo)",
    "detection.lidar_pd_poisson": "tests/test_detection.py (exact Poisson sums, Monte Carlo)",
    "detection.photon_counting_threshold": "tests/test_detection.py (exact Poisson sums)",
    "detection.ttpf_cycles_ratio": "tests/test_detection.py (Table 21 multipliers)",
    "detection.ttpf_probability": "tests/test_detection.py (every column of Table 21)",
    "fusion.approach_looks": "tests/test_fusion.py",
    "fusion.cumulative_pd": "tests/test_fusion.py (1 - (1 - p)^n)",
    "fusion.first_detection": "tests/test_fusion.py (Monte Carlo approach)",
    "fusion.fuse_k_of_n": "tests/test_fusion.py (enumeration)",
    "fusion.fuse_or": "tests/test_fusion.py (enumeration)",
    "radar_detection.albersheim_snr_db": "tests/test_radar_detection.py (Richards' 13.1 dB example)",
    "radar_detection.pd_exact": "tests/test_radar_detection.py (closed forms, quadrature, Monte Carlo)",
    "radar_detection.required_snr_db": "tests/test_radar_detection.py (Meyer & Mayer, brentq on quadrature)",
    "radar_detection.shnidman_snr_db": "tests/test_radar_detection.py (against the exact inverse)",
    "radar_detection.threshold": "tests/test_radar_detection.py (noise-only gamma tail)",
    "ranges.thermal_extinction_db_km": "tests/test_core_direct.py",
    "ranges.gas_atmosphere": "tests/test_core_gas.py (P.835 unless the scenario gives T, p, RH)",
    "ranges.gas_attenuation_db_km": "tests/test_core_direct.py",
    "ranges.rf_frequency_ghz": "tests/test_core_direct.py (the sensor's own, else Table 33's link)",
    "ranges.evaluate": "tests/test_scenario.py (every embedded scenario against the core models)",
    "ranges.horizontal_range_m": "tests/test_range_cli.py, tests/test_scenario.py (Eq. 13)",
    "ranges.paper_eta_tl": "tests/test_scenario.py (Table 47)",
    "ranges.thermal_contrast": "tests/test_core_direct.py (Eq. 26), tests/test_scenario.py",
    "ranges.scenario_one_at_a_time": "tests/test_sensitivity.py",
    "scenario.check_value": "tests/test_scenario_errors.py",
    "scenario.embedded_scenarios": "tests/test_scenario.py (every embedded scenario evaluates finite)",
    "scenario.johnson_derived": "tests/test_core_direct.py (Tables 20, 21)",
    "scenario.load_scenario": "tests/test_scenario.py, tests/test_scenario_errors.py",
    "scenario.parse_scenario": "tests/test_scenario.py, tests/test_scenario_errors.py",
    "scenario.plausibility_warnings": "tests/test_core_direct.py; tests/test_range_cli.py (one warning per mistake)",
    "scenario.provenance": "tests/test_core_direct.py; tests/test_range_cli.py (inputs.<p>.source)",
    "sensitivity.table_52_platforms": "tests/test_core_direct.py; tests/test_sensitivity.py (Table 52)",
    "acoustic.iso9613_absorption_db_m": "tests/test_core_acoustic.py (ISO 9613-2 Table 2)",
    "acoustic.wind_noise_db": "tests/test_core_acoustic.py (Table 31)",
    "acoustic.wind_noise_extrapolated": "tests/test_core_acoustic.py",
    "checks.require": "tests/test_core_hostile.py",
    "checks.require_registry_bounds": "tests/test_core_direct.py",
    "itu.fog_coefficient_kl": "tests/test_core_itu.py (ITU-Rpy, Tables 36, 43)",
    "itu.fog_specific_attenuation_db_km": "tests/test_core_itu.py (ITU-Rpy)",
    "itu.rain_coefficients": "tests/test_core_itu.py (ITU-R validation example)",
    "itu.rain_specific_attenuation_db_km": "tests/test_core_itu.py (ITU-Rpy, Tables 35, 42)",
    "itu.water_permittivity": "tests/test_core_itu.py (ITU-Rpy), tests/test_engagement_core.py (static 80.1)",
    "johnson.line_pairs": "tests/test_core_eo.py (Table 20)",
    "johnson.n_ttpf": "tests/test_core_eo.py (Table 21)",
    "lidar.lidar_range_no_loss_m": "tests/test_core_rf_radar_lidar.py (Eq. 99)",
    "lidar.received_power_w": "tests/test_core_rf_radar_lidar.py",
    "mrtd.diffraction_mtf": "tests/test_core_thermal.py",
    "mrtd.sensor_mrtd": "tests/test_core_direct.py; tests/test_core_thermal.py",
    "radar.integration_gain": "tests/test_core_direct.py; tests/test_core_rf_radar_lidar.py (Eqs. 77-82)",
    "radar.radar_wavelength_m": "tests/test_core_direct.py; tests/test_range_cli.py (Section 4.9.3)",
    "radar.radar_frequency_ghz": "tests/test_core_direct.py (given, or exact c over Table 39's wavelength)",
    "radar.total_loss_db": "tests/test_core_rf_radar_lidar.py (Eq. 85: 13.595 dB)",
    "radiometry.band_limits_um": "tests/test_core_direct.py; tests/test_core_thermal.py",
    "radiometry.band_radiance": "tests/test_core_thermal.py (Planck quadrature)",
    "radiometry.graybody_apparent_temperature": "tests/test_core_thermal.py",
    "radiometry.radiance_temperature": "tests/test_core_thermal.py",
    "radiometry.spectral_radiance": "tests/test_core_direct.py; tests/test_core_thermal.py",
    "result.check_convention": "tests/test_core_direct.py; tests/test_core_hostile.py",
    "range_notes.sensor_notes": "tests/test_sweep_scaling.py (Table 39's default radar; none once its budget is set)",
    "result.unbounded_reason": "tests/test_core_direct.py; tests/test_core_hostile.py",
    "sensitivity.acoustic_model": "tests/test_core_direct.py; tests/test_sensitivity.py (Section 4.9.2)",
    "sensitivity.eo_johnson_model": "tests/test_core_direct.py; tests/test_sensitivity.py (Section 4.9.1)",
    "sensitivity.one_at_a_time": "tests/test_sensitivity.py (Tables 48-51)",
    "sensitivity.platform_comparison": "tests/test_core_direct.py; tests/test_sensitivity.py (Table 52)",
    "sensitivity.radar_model": "tests/test_core_direct.py; tests/test_sensitivity.py (Section 4.9.3)",
    "itu.gaseous_attenuation_db_km": "tests/test_core_gas.py (ITU-Rpy P.676-12)",
    "itu.gaseous_attenuation_components_db_km": "tests/test_core_gas.py (ITU-Rpy P.676-12)",
    "itu.gas_loss_matters": "tests/test_core_direct.py",
    "itu.saturation_vapour_pressure_hpa": "tests/test_core_direct.py",
    "itu.standard_atmosphere": "tests/test_core_gas.py (P.835 sea level)",
    "itu.water_vapour_density_g_m3": "tests/test_core_gas.py (ITU-Rpy P.453)",
    "itu.water_vapour_pressure_hpa": "tests/test_core_direct.py",
    "acoustic.iso9613_absorption_db_km": "tests/test_core_acoustic_spectrum.py (ISO 9613-2 Table 2, sound-propagation)",
    "acoustic.iso9613_ground_db": "tests/test_core_acoustic_spectrum.py (sound-propagation)",
    "acoustic.iso9613_cmet_db": "tests/test_core_acoustic_spectrum.py (ISO 9613-2 Eqs. 21-22)",
    "atmosphere.fog_path_fraction": "tests/test_core_atmosphere.py (closed form vs the path's exact geometry)",
    "acoustic.iso9613_barrier_db": "tests/test_core_acoustic.py (ISO 9613-2 Eq. 14 by hand, the 20 and 25 dB caps)",
    "acoustic.iso9613_barrier_c3": "tests/test_core_acoustic.py (ISO 9613-2 Eq. 15 by hand)",
    "acoustic.iso9613_barrier_met_factor": "tests/test_core_acoustic.py (ISO 9613-2 Eq. 18 by hand)",
    "barrier.barrier_frequency_hz": "tests/test_terrain.py (physical acoustic only)",
    "barrier.terrain_barrier_db": "tests/test_terrain.py (ISO 9613-2 Eqs. 14, 18 over a knife edge by hand)",
    "terrain.diffraction_path_difference_m": "tests/test_terrain.py (one and two edges, exact geometry)",
    "pd_curves.acoustic_pd_with_loss": "tests/test_pd_curves.py (R^-2 law: a loss L is the range times 10^(L/20))",
    "acoustic.octave_band_index": "tests/test_core_direct.py",
    "acoustic_spectrum.third_octave_bands_hz": "tests/test_core_acoustic_spectrum.py (IEC 61260-1 base 10)",
    "acoustic_spectrum.band_index": "tests/test_core_acoustic_spectrum.py",
    "acoustic_spectrum.a_weighting_db": "tests/test_core_acoustic_spectrum.py (IEC 61672-1 Table 3)",
    "acoustic_spectrum.rotor_spectrum_db": "tests/test_core_acoustic_spectrum.py (A-weighted total = sl_db)",
    "acoustic_spectrum.ambient_spectrum_db": "tests/test_core_acoustic_spectrum.py",
    "acoustic_spectrum.wind_noise_spectrum_db": "tests/test_core_acoustic_spectrum.py (Strasberg 1988)",
    "acoustic_spectrum.band_ranges_m": "tests/test_core_acoustic_spectrum.py (sound-propagation ground)",
    "acoustic_spectrum.spectral_acoustic_range": "tests/test_core_direct.py",
    "atmosphere.rain_extinction_per_km": "tests/test_render_weather_terms.py (Marshall-Palmer integral)",
    "eo.path_extinction": "tests/test_render_weather_terms.py (Koschmieder by hand, layered fog, rain)",
    "ranges.eo_path_inputs": "tests/test_render_weather_terms.py (the fog layer's share by hand)",
    "ranges.thermal_path": "tests/test_render_weather_terms.py (Table 27, rain by hand)",
    "tir.path_terms": "tests/test_render_weather_terms.py",
    "tir.rain_terms": "tests/test_render_weather_terms.py",
    "tir.fog_terms": "tests/test_thermal_fog.py",
    "atmosphere.fog_extinction_ratio": "tests/test_thermal_fog.py (LOWTRAN 7 FG1EXT/FG2EXT as printed)",
    "atmosphere.fog_infrared_extinction_per_km": "tests/test_thermal_fog.py (3.912/V x band mean by quad)",
    "ranges.thermal_fog": "tests/test_thermal_fog.py (LOWTRAN band mean by quad, in dB)",
    "ranges.thermal_fog_db_km": "tests/test_thermal_fog.py (the layer's share by hand)",
    "ranges.thermal_extinction_no_fog_db_km": "tests/test_thermal_fog.py (Table 27 + rain by hand)",
    "ranges.fog_layer_geometry": "tests/test_thermal_fog.py",
    "solve.bracketed_root": "tests/test_core_solve.py",
    "solve.lambertw_exp": "tests/test_core_solve.py",
    "solve.solve_log_linear": "tests/test_core_solve.py",
    "tir.attenuated_delta_t": "tests/test_core_thermal.py (Eq. 31)",
    "tir.delta_t_radiometric": "tests/test_core_thermal.py (band radiometry)",
    "tir.tir_mrtd_range": "tests/test_core_thermal.py",
    "units.power_sum_db": "tests/test_core_direct.py; tests/test_core_acoustic.py (Eq. 108)",
    "swarm.line_formation": "tests/test_swarm.py (offsets by hand)",
    "swarm.link_range_m": "tests/test_swarm.py (s / theta, c / 2B by hand)",
    "swarm.groups_at": "tests/test_swarm.py (groups either side of s / theta)",
    "swarm.first_detection_m": "tests/test_swarm.py (intervals of constant groups by hand)",
    "swarm.blob_critical_m": "tests/test_swarm.py (bounding box by hand)",
    "swarm.incoherent_sum_db": "tests/test_swarm.py (10 log10 N)",
    "swarm.line_of_sight_axes": "tests/test_swarm_rcs.py (axes at azimuth 90, elevation 30 by hand)",
    "swarm.target_frame_offsets_m": "tests/test_swarm_rcs.py",
    "swarm.array_factor": "tests/test_swarm_rcs.py (N^2 in phase, 0 a quarter wavelength apart; N PEC spheres)",
    "scenario.swarm_formation": "tests/test_swarm.py (the line and offsets by hand)",
    "swarm_detection.sensor_cells": "tests/test_swarm.py (c / 2B, sqrt(4 pi / G))",
    "swarm_detection.group_target": "tests/test_swarm.py (SL + 10 log10 N)",
    "swarm_detection.formation_json": "tests/test_swarm.py (the line's offsets)",
    "swarm_detection.swarm_range": "tests/test_swarm.py (R sigma^(1/4), Johnson R proportional to d_crit)",
    "swarm_detection.swarm_pd": "tests/test_swarm.py (1 - (1 - Pd)^N)",
    "swarm_detection.swarm_first_detection_m": "tests/test_swarm_sweeps.py (R k^(1/4), as csuas range)",
    "swarm_detection.swarm_approach": "tests/test_swarm_approach.py (1 - prod(1 - Pd_any), beam R theta_3)",
    "scenario.with_swarm_value": "tests/test_swarm_sweeps.py (axes and bounds against csuas range)",
    "micro_doppler.rotor_plane_elevation_deg": "tests/test_micro_doppler_axis.py (asin(a . d), |a x d|)",
}


def _public_core_functions():
    found = set()
    for info in pkgutil.iter_modules(csuas.core.__path__):
        module = importlib.import_module(f"csuas.core.{info.name}")
        for name, function in inspect.getmembers(module, inspect.isfunction):
            if function.__module__ == module.__name__ and not name.startswith("_"):
                found.add(f"{info.name}.{name}")
    return found


def test_every_public_core_function_has_a_row():
    rows = {row[0] for row in ROWS}
    assert _public_core_functions() - rows - set(COVERED_ELSEWHERE) == set()
    assert rows & set(COVERED_ELSEWHERE) == set()
    assert (rows | set(COVERED_ELSEWHERE)) - _public_core_functions() == set(), "a row names no function"


def _called_names(path: Path) -> set[str]:
    """Names a test file calls, as ``f(...)`` or ``module.f(...)``."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call):
            func = node.func
            names.add(func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", ""))
    return names


@pytest.mark.parametrize("name", sorted(COVERED_ELSEWHERE))
def test_the_file_named_elsewhere_calls_the_function(name):
    root = Path(__file__).resolve().parents[1]
    paths = [root / rel for rel in re.findall(r"tests/\w+\.py", COVERED_ELSEWHERE[name])]
    assert paths and all(path.is_file() for path in paths), f"{name}: {paths} do not all exist"
    callers = [path.name for path in paths if name.split(".")[-1] in _called_names(path)]
    assert callers, f"none of {[path.name for path in paths]} calls {name}"


IDS = [row[0] for row in ROWS]
#: Arguments whose errors name the canonical (scenario) parameter they stand for.
CANONICAL_NAME = {"c0": "c_eo", "target_height_m": "height_m"}


@pytest.mark.parametrize("name, function, kwargs, reference, _", ROWS, ids=IDS)
def test_reference_value(name, function, kwargs, reference, _):
    np.testing.assert_allclose(_range(function(**kwargs)), reference, rtol=1e-9)


@pytest.mark.parametrize("name, function, kwargs, reference, argument", ROWS, ids=IDS)
def test_broadcasting_matches_element_by_element(name, function, kwargs, reference, argument):
    values = kwargs[argument] * (1.0 + 0.01 * np.arange(6).reshape(2, 3))
    together = np.asarray(_range(function(**{**kwargs, argument: values})))
    one_by_one = np.array([_range(function(**{**kwargs, argument: v})) for v in values.ravel()]).reshape(2, 3)
    assert together.shape == (2, 3)
    np.testing.assert_allclose(together, one_by_one, rtol=1e-12)


@pytest.mark.parametrize("name, function, kwargs, reference, argument", ROWS, ids=IDS)
def test_zero_d_and_float32_inputs(name, function, kwargs, reference, argument):
    zero_d = np.asarray(_range(function(**{**kwargs, argument: np.float64(kwargs[argument])})))
    assert zero_d.ndim == 0
    low = np.asarray(_range(function(**{**kwargs, argument: np.float32(kwargs[argument])})))
    assert np.all(np.isfinite(low))
    # the input's own float32 rounding (6e-8 relative) times the function's sensitivity (<= 4 here)
    np.testing.assert_allclose(low, zero_d, rtol=5e-7)


@pytest.mark.parametrize("name, function, kwargs, reference, argument", ROWS, ids=IDS)
def test_nan_in_is_nan_out_or_an_error_naming_the_parameter(name, function, kwargs, reference, argument):
    try:
        out = np.asarray(_range(function(**{**kwargs, argument: np.nan})))
    except ParameterError as exc:
        assert CANONICAL_NAME.get(argument, argument.rstrip("_")) in str(exc)
        return
    assert np.all(np.isnan(out)), (name, out)
