"""Thermal-IR rendering against band-Planck oracles (docs/validation.md), the paper's linear Delta T (Eq. 26)
and the MRTD range of core/ (docs/simulation.md, docs/validation.md).

Reference values: tests/reference/render_tir_oracles.csv (from docs/validation.md "Thermal IR radiometry").
"""

from __future__ import annotations

import csv
import math
from dataclasses import astuple
from pathlib import Path

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core.mrtd import ParametricMrtd
from csuas.core.radiometry import band_radiance, radiance_temperature
from csuas.core.tir import tir_mrtd_range
from csuas.render.imaging import Quality, render_tir
from csuas.render.imaging.records import RenderSettings, ThermalScene, ThermalSensor, View
from csuas.render.imaging.targets import plate
from csuas.render.imaging.tir import default_mrtd

pytestmark = pytest.mark.slow

Q = Quality("test", 2, 8)
IFOV = math.radians(36.67) / 1280


def oracle_rows():
    path = Path(__file__).parent / "reference" / "render_tir_oracles.csv"
    lines = [ln for ln in path.read_text().splitlines() if not ln.startswith("#")]
    rows = list(csv.DictReader(lines))
    return [r for r in rows if r["band"] != "-"]  # skip the units row


@pytest.mark.parametrize("row", oracle_rows(), ids=lambda r: f"{r['band']}-{r['surroundings_k']}")
def test_graybody_plate_delta_t_matches_band_planck_oracle(row):
    surroundings = None if row["surroundings_k"] == "none" else float(row["surroundings_k"])
    res = render_tir(
        plate(emissivity=0.68, temperature_k=288.15),
        View(range_m=100.0),
        sensor=ThermalSensor(band=row["band"]),
        scene=ThermalScene(t_bg_k=298.15, emissivity_bg=0.77, surroundings_k=surroundings),
        settings=RenderSettings(quality=Q),
        linear_reference=(0.68, 288.15),
        reflected_surroundings=surroundings is not None,
    )
    dt, se = res.values["delta_t_k"], res.stderr["delta_t_k"]
    assert dt < 0  # the plate is colder than the background
    assert abs(dt) == pytest.approx(float(row["delta_t_abs_k"]), abs=0.006 + 4 * se)
    if surroundings is None:
        assert se == 0.0  # pure emission: no Monte Carlo noise
    # The paper's linear Delta T (Eq. 26) beside it: 0.68 * 288.15 - 0.77 * 298.15.
    assert res.values["delta_t_linear_k"] == pytest.approx(0.68 * 288.15 - 0.77 * 298.15, rel=1e-12)
    assert res.values["delta_t_linear_k"] == pytest.approx(-33.6335, abs=1e-4)
    assert abs(res.values["delta_t_linear_k"]) > 2 * abs(
        dt
    )  # the linear rule overstates it (docs/conventions.md point 2)


def test_plate_delta_t_same_at_10_m_and_20_km():
    kw = dict(
        sensor=ThermalSensor(band="lwir", hfov_deg=57.29577951308232, n_h=1000, n_v=1000),
        settings=RenderSettings(quality=Q),
    )
    near = render_tir(plate(), View(range_m=10.0), **kw)
    far = render_tir(plate(), View(range_m=20000.0), **kw)
    assert near.values["delta_t_k"] == pytest.approx(-15.33, abs=0.006)
    assert far.values["delta_t_k"] == pytest.approx(near.values["delta_t_k"], abs=1e-6)
    tolerance = 4 * far.stderr["pixels_on_target"] + 1e-3 * 0.0025
    assert far.values["pixels_on_target"] == pytest.approx(0.0025, abs=tolerance)
    se_far = far.stderr["pixels_on_target"] * 20000.0**2
    assert near.values["pixels_on_target"] * 10.0**2 == pytest.approx(
        far.values["pixels_on_target"] * 20000.0**2, abs=4 * se_far + 2e-3 * 1e6
    )


def test_path_transmittance_and_radiance():
    """Apparent Delta T after 5 km at 1 dB/km with air at 293.15 K, against the closed form inline."""
    sigma, r, t_air = 1.0, 5000.0, 293.15
    res = render_tir(
        plate(),
        View(range_m=r),
        sensor=ThermalSensor(band="lwir"),
        scene=ThermalScene(extinction_db_km=sigma, air_temperature_k=t_air),
        settings=RenderSettings(quality=Q),
        atmosphere=True,
    )
    tau = 10 ** (-sigma * r / 1000 / 10)
    l_air = float(band_radiance(t_air, "lwir"))
    l_t = 0.68 * float(band_radiance(288.15, "lwir"))
    l_b = 0.77 * float(band_radiance(298.15, "lwir"))
    expected = float(
        radiance_temperature(l_t * tau + l_air * (1 - tau), "lwir")
        - radiance_temperature(l_b * tau + l_air * (1 - tau), "lwir")
    )
    assert res.values["delta_t_k"] == pytest.approx(expected, abs=1e-4)
    assert res.values["delta_t_inherent_k"] == pytest.approx(-15.33, abs=0.006)
    assert [t["name"] for t in res.terms] == ["extinction_db_km", "transmittance", "path_radiance"]
    assert res.terms[1]["value"] == pytest.approx(tau, rel=1e-12)


def test_default_mrtd_is_the_datasheet_curve_of_table_25_defaults():
    # 50 mK, f/1, 10 um pitch (defaults/parameters.toml [tir]), LWIR centre 10 um
    expected = ParametricMrtd(netd_k=0.05, ifov_rad=IFOV, f_number=1.0, pitch_m=10e-6, wavelength_m=10e-6)
    assert astuple(default_mrtd(IFOV, "lwir")) == pytest.approx(astuple(expected), rel=1e-12)


def test_mrtd_range_matches_core_with_oracle_delta_t():
    """Range where the rendered Delta T meets the MRTD at f = lp n R / d_crit, against core with exact inputs."""
    width = 0.3
    target = plate(width_m=width, height_m=width)
    res = render_tir(
        target,
        View(range_m=200.0),
        sensor=ThermalSensor(band="lwir"),
        scene=ThermalScene(extinction_db_km=1.0, air_temperature_k=293.15),
        settings=RenderSettings(quality=Quality("t", 4, 8)),
        atmosphere=True,
    )
    t_bg_app = float(radiance_temperature(0.77 * band_radiance(298.15, "lwir"), "lwir"))
    expected = tir_mrtd_range(
        mrtd=default_mrtd(IFOV, "lwir"),
        d_crit_m=width,
        lp_task=1.0,
        n_ttpf=1.0,
        delta_t0_k=-15.334,
        extinction_db_km=1.0,
        convention="physical",
        t_bg_app_k=t_bg_app,
        air_temperature_k=293.15,
        band="lwir",
    )
    assert res.values["d_crit_rendered_m"] == pytest.approx(width, rel=0.005)
    assert res.values["mrtd_range_m"] == pytest.approx(float(expected.range_m), rel=0.005)
    assert res.stderr["mrtd_range_m"] < 0.01 * res.values["mrtd_range_m"]
    # At the render range the target's Delta T exceeds the MRTD at its spatial frequency.
    assert abs(res.values["delta_t_k"]) > res.values["mrtd_at_range_k"]


def test_drone_lwir_and_mwir_are_finite_and_bounded():
    for band in ("lwir", "mwir"):
        res = render_tir(
            "dji_mini_4_pro",
            View(range_m=150.0, azimuth_deg=30.0, elevation_deg=15.0),
            sensor=ThermalSensor(band=band),
            scene=ThermalScene(surroundings_k=293.15),
            settings=RenderSettings(quality=Quality("t", 2, 4)),
            reflected_surroundings=True,
        )
        assert all(np.isfinite(v) for v in res.values.values() if isinstance(v, float) and v != float("inf"))
        # Every part is at 288.15 K reflecting 293.15 K surroundings: the radiance temperature lies in between.
        t_target = res.values["background_temperature_apparent_k"] + res.values["delta_t_inherent_k"]
        assert 288.15 - 0.05 <= t_target <= 293.15 + 0.05
        assert res.values["pixels_on_target"] > 0 and res.image.shape[0] == 1


def test_bad_input():
    with pytest.raises(ParameterError, match="band"):
        render_tir(
            plate(), View(range_m=100.0), sensor=ThermalSensor(band="swir"), settings=RenderSettings(quality="draft")
        )
    with pytest.raises(ParameterError, match="emissivity_bg"):
        render_tir(
            plate(),
            View(range_m=100.0),
            scene=ThermalScene(emissivity_bg=1.5),
            settings=RenderSettings(quality="draft"),
        )
    with pytest.raises(ParameterError, match="extinction_db_km"):
        render_tir(
            plate(),
            View(range_m=100.0),
            scene=ThermalScene(extinction_db_km=-1.0),
            settings=RenderSettings(quality="draft"),
            atmosphere=True,
        )
    with pytest.raises(ParameterError, match="extinction_db_km"):
        render_tir(plate(), View(range_m=100.0), settings=RenderSettings(quality="draft"), atmosphere=True)
    with pytest.raises(ParameterError, match="surroundings_k"):
        render_tir(plate(), View(range_m=100.0), settings=RenderSettings(quality="draft"), reflected_surroundings=True)


def test_an_effect_switched_off_is_not_simulated_even_when_its_parameter_is_given():
    """The records may carry every parameter; only the switches decide what is built (docs/scenarios.md (effects))."""
    scene = ThermalScene(surroundings_k=293.15, extinction_db_km=1.0)
    off = render_tir(plate(), View(range_m=500.0), scene=scene, settings=RenderSettings(quality=Q))
    assert off.terms == [] and off.stderr["delta_t_k"] == 0.0  # no path, pure emission
    assert off.values["delta_t_k"] == pytest.approx(-15.33, abs=0.006)  # the oracle without surroundings
