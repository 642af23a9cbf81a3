"""Benchmarks of the analytic core: evaluations per second and exact solves vs the paper's loops.

Targets: docs/performance.md.
"""

from __future__ import annotations

import time

import numpy as np

from csuas.core import acoustic, eo, johnson, lidar, radar, rf, tir
from csuas.core.atmosphere import kruse_extinction_per_km
from csuas.core.mrtd import sensor_mrtd
from csuas.core.terrain import viewshed
from csuas.defaults import default_values
from csuas.validation.core.paper_procedures import eo_step_reduction, tir_step_reduction

#: Scenarios the paper's scalar loops are timed on; their per-scenario time is scaled to all
#: ``n`` (a loop costs the same per scenario, so a couple of hundred measure it well).
LOOP_SCENARIOS_TIMED = 200


def _timed(fn, repeat=3):
    best = np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


def _scenarios(n, rng):
    """``{model: (function, keyword arguments)}``: the random inputs are drawn here, outside any timer."""
    u = lambda lo, hi: rng.uniform(lo, hi, n)
    rf_inputs = dict(
        p_tx_w=u(0.01, 1),
        g_tx_dbi=8.0,
        g_rx_db=14.0,
        frequency_ghz=u(1, 6),
        s_rx_dbm=-100.0,
        rain_rate_mm_h=u(0, 30),
        lwc_g_m3=u(0, 0.5),
    )
    return {
        "eo": (
            eo.eo_range,
            dict(
                d_crit_m=u(0.02, 0.5),
                hfov_deg=u(1, 40),
                n_h=1920.0,
                lp_task=1.0,
                n_ttpf=u(0.5, 2),
                c_eo=u(0.1, 1),
                c_min=0.05,
                wavelength_nm=550.0,
                visibility_km=u(0.2, 60),
            ),
        ),
        "tir_johnson": (
            tir.tir_johnson_range,
            dict(d_crit_m=u(0.02, 0.5), hfov_deg=u(1, 40), n_h=1280.0, lp_task=1.0, n_ttpf=u(0.5, 2)),
        ),
        "acoustic": (
            acoustic.acoustic_range,
            dict(sl_db=u(50, 90), snr_req_db=10.0, noise_level_db=u(25, 60), g_array_db=20.0, wind_speed_m_s=u(0, 12)),
        ),
        "rf": (rf.rf_range, rf_inputs),
        "rf_physical": (rf.rf_range, {**rf_inputs, "convention": "physical"}),
        "radar": (
            radar.radar_range,
            dict(
                p_tx_w=u(1, 1000),
                g_tx_db=25.0,
                g_rx_db=25.0,
                wavelength_m=u(0.008, 0.05),
                sigma_m2=u(0.001, 0.1),
                n_pulses=10.0,
                integration="coherent",
                l_hardware_db=10.0,
                l_processing_db=3.0,
            ),
        ),
        "lidar": (
            lidar.lidar_range,
            dict(
                p_tx_w=u(0.1, 10),
                p_rx_min_w=1e-10,
                sigma_lidar_m2=u(0.001, 0.1),
                aperture_mm=3.0,
                wavelength_nm=1550.0,
                eta_tl=0.681,
            ),
        ),
    }


def bench_models(n: int = 1_000_000, seed: int = 0) -> list[dict]:
    """Evaluations per second of each closed-form model on ``n`` random scenarios (target >= 1e6 /s/core)."""
    rng = np.random.default_rng(seed)
    rows = []
    for name, (model, kwargs) in _scenarios(n, rng).items():
        seconds, result = _timed(lambda model=model, kwargs=kwargs: model(**kwargs), repeat=2)
        assert np.all(np.isfinite(result.range_m))
        rows.append({"model": name, "scenarios": n, "time_s": seconds, "evaluations_per_s": n / seconds})
    return rows


def bench_iterative(n: int = 2000, seed: int = 1) -> list[dict]:
    """Exact vectorised solves vs the paper's scalar step procedures (target speed-up >= 100x).

    Returns rows with the per-scenario time of both, the speed-up, and the
    maximum difference of the loop's answer from the exact one [m].
    """
    rng = np.random.default_rng(seed)
    rows = []
    # EO contrast limit (Section 4.3.3), paper convention, visibility in fog / haze so the limit binds.
    d = rng.uniform(0.05, 0.3, n)
    vis = rng.uniform(0.3, 3.0, n)
    c0 = rng.uniform(0.2, 1.0, n)
    ifov = johnson.ifov_rad(5.0, 1920)
    r_j = johnson.johnson_range_m(d, ifov)

    sigma = kruse_extinction_per_km(550.0, vis)
    t_exact, exact = _timed(lambda: np.minimum(r_j, eo.contrast_limited_range_m(c0, 0.05, sigma, "paper")))
    m = min(n, LOOP_SCENARIOS_TIMED)
    start = time.perf_counter()
    loop = [eo_step_reduction(r_j[i], c0[i], 0.05, sigma[i], step_m=1.0) for i in range(m)]
    t_loop = (time.perf_counter() - start) / m * n
    rows.append(
        {
            "procedure": "eo_contrast_limit (Section 4.3.3)",
            "scenarios": n,
            "exact_time_s": t_exact,
            "loop_time_s": t_loop,
            "speedup": t_loop / t_exact,
            "loop_max_error_m": float(np.max(np.abs(np.asarray(loop) - exact[:m]))),
            "loop_step_m": 1.0,
            "loop_scenarios_timed": m,
        }
    )
    # TIR MRTD with attenuation (Section 4.4.3), paper convention.
    mrtd = sensor_mrtd(default_values("tir"))  # Table 25: 50 mK, 10 um pitch, 20 mm, f/1, LWIR
    dt0 = rng.uniform(0.05, 2.0, n)
    sig = rng.uniform(0.2, 20.0, n)
    t_exact, res = _timed(
        lambda: (
            tir.tir_mrtd_range(
                mrtd=mrtd, d_crit_m=0.101, lp_task=1.0, n_ttpf=1.0, delta_t0_k=dt0, extinction_db_km=sig
            ).range_m
        )
    )
    m = min(n, LOOP_SCENARIOS_TIMED)  # 0.18 s each at a 1 cm step: about 40 s for 200
    start = time.perf_counter()
    loop = [tir_step_reduction(mrtd, 0.101, 1.0, 1.0, dt0[i], sig[i], step_m=0.01) for i in range(m)]
    t_loop = (time.perf_counter() - start) / m * n
    rows.append(
        {
            "procedure": "tir_mrtd_attenuation (Section 4.4.3)",
            "scenarios": n,
            "exact_time_s": t_exact,
            "loop_time_s": t_loop,
            "speedup": t_loop / t_exact,
            "loop_max_error_m": float(np.max(np.abs(np.asarray(loop) - res[:m]))),
            "loop_step_m": 0.01,
            "loop_scenarios_timed": m,
        }
    )
    return rows


def bench_viewshed(size: int = 1000, sensors: int = 6, altitudes=(30.0, 60.0, 120.0, 250.0, 500.0)) -> list[dict]:
    """Line of sight over a ``size`` x ``size`` DEM (30 m cells) for several sensors and flight levels, then
    against GDAL's ``gdal_viewshed`` at four sizes (:func:`csuas.validation.terrain.bench.bench_against_gdal`).

    The DEM is a seeded random surface (integrated Gaussian noise, about 100 m of relief); the sensors
    stand on 10 m masts spread over it. Times only :func:`csuas.core.terrain.viewshed` (issue 15's
    target: 1000 x 1000 cells, 6 sensors, 5 altitudes in under a minute on 2 CPU cores).
    """

    rng = np.random.default_rng(3)
    dem = np.cumsum(np.cumsum(rng.normal(0.0, 1.0, (size, size)), 0), 1)
    dem = 100.0 * (dem - dem.min()) / (dem.max() - dem.min())
    positions = rng.uniform(0.1 * size, 0.9 * size, (sensors, 2))
    start = time.perf_counter()
    visible = 0.0
    for row, col in positions:
        for altitude in altitudes:
            visible += float(viewshed(dem, 30.0, row, col, 10.0, altitude).mean())
    elapsed = time.perf_counter() - start
    runs = sensors * len(altitudes)
    from csuas.validation.terrain.bench import bench_against_gdal

    site = {
        "cells": size * size,
        "viewsheds": runs,
        "time_s": elapsed,
        "s_per_viewshed": elapsed / runs,
        "mean_visible_share": visible / runs,
    }
    return [site, *bench_against_gdal()]
