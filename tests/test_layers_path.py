"""Dataset frames' clutter and confusers take the frame's path at their own ranges when the scenario declares
weather (render/imaging/path.py eo_path_at / tir_path_at; confusers.py, clutter.py, dataset.py).

Closed forms: a confuser's contrast over the horizon sky falls as exp(-beta R) in uniform fog (Koschmieder, beta
= 3.912 / V at 550 nm), its band-radiance excess as 10^(-a R / 10) in rain (Beer-Lambert, a the thermal range's
attenuation), the terrain's light at each pixel as tau(h / -z) L + (1 - tau) L_h.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from csuas.core.scenario import parse_scenario
from csuas.defaults import load_presets

KOSCHMIEDER = -math.log(0.02)
FOG_KM = 0.2


def _gull(range_m: float) -> dict:
    draw = {"class": "gull", "range_m": range_m, "azimuth_deg": 70.0, "elevation_deg": -15.0}
    draw.update(target_offset_px=(3.0, -2.0), wingbeat_phase=0.1, length_m=0.01, confuser_id=1)
    return draw


def _eo_paste(draw: dict, with_path: bool) -> tuple:
    """A gull pasted on a uniform horizon sky of an EO frame, through 200 m fog or without a path; its excess."""
    from csuas.render.imaging.confusers import eo_confusers, eo_render_settings
    from csuas.render.imaging.eo import sun_and_sky
    from csuas.render.imaging.path import eo_path_at
    from csuas.render.imaging.records import Daylight, EoSensor

    light = Daylight(visibility_km=FOG_KM, convention="physical")
    sensor = EoSensor(hfov_deg=4.0, n_h=320, n_v=240, wavelength_nm=550.0)
    render = eo_render_settings(sensor, light, "draft", 1, {"f_number": 2.0, "pixel_pitch_um": 2.9}, 288.15)
    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    horizon = float(sky["sky_radiance"])
    if with_path:
        render["object_path"] = lambda r, up: eo_path_at(r, up, light, 550.0, horizon)
    frame = np.full((sensor.n_v, sensor.n_h), horizon)
    eo_confusers(frame, [draw], math.radians(sensor.hfov_deg) / sensor.n_h, render)
    return frame - horizon


@pytest.mark.parametrize("range_m", [60.0, 120.0, 240.0])
def test_a_birds_contrast_in_uniform_fog_falls_as_koschmieder(range_m):
    clear, fog = _eo_paste(_gull(range_m), False), _eo_paste(_gull(range_m), True)
    assert np.count_nonzero(clear) > 0 and np.array_equal(clear != 0, fog != 0)  # the same pixels
    # same render, same seed: every pixel's contrast over the sky takes tau = exp(-3.912 R / V)
    expected = math.exp(-KOSCHMIEDER / FOG_KM * range_m / 1000.0)
    assert float(np.sum(fog)) / float(np.sum(clear)) == pytest.approx(expected, rel=1e-9)
    covered = clear != 0
    assert fog[covered] == pytest.approx(expected * clear[covered], rel=1e-6, abs=1e-9)


def test_a_birds_thermal_excess_in_rain_falls_by_beer_lambert():
    from csuas.render.imaging.confusers import tir_confusers
    from csuas.render.imaging.path import tir_path_at
    from csuas.render.imaging.records import ThermalScene, ThermalSensor

    attenuation = 13.7  # dB/km: Table 27's 0.2 and 30 mm/h of Marshall-Palmer rain, about
    scene = ThermalScene(extinction_db_km=attenuation, air_temperature_k=288.15, surroundings_k=288.15)
    sensor = ThermalSensor(hfov_deg=4.0, n_h=320, n_v=240)
    render = {"sensor": sensor, "scene": scene, "quality": "draft", "seed": 1, "f_number": 1.0, "pitch_um": 10.0}
    render["ambient_k"] = 288.15
    excess = []
    for path in (None, lambda r, up: tir_path_at(r, up, scene, "lwir")):
        from csuas.core.radiometry import band_radiance

        sky = float(band_radiance(288.15, "lwir"))  # the air's own radiance: the path radiance leaves it as it is
        frame = np.full((sensor.n_v, sensor.n_h), sky)
        tir_confusers(frame, [_gull(150.0)], math.radians(4.0) / 320, {**render, "object_path": path})
        excess.append(float(np.sum(frame - sky)))
    assert excess[0] != 0.0
    assert excess[1] / excess[0] == pytest.approx(10 ** (-attenuation * 0.15 / 10), rel=1e-9)


def test_the_terrain_takes_the_path_at_each_pixels_ground_distance():
    from csuas.render.imaging.background import view_rays
    from csuas.render.imaging.clutter import clutter_layers
    from csuas.render.imaging.dataset_schema import ClutterSchema
    from csuas.render.imaging.path import eo_path_at
    from csuas.render.imaging.records import Daylight

    ifov = math.radians(8.0) / 200
    rays = view_rays(200, 150, ifov, 0.0, 3.0, (0.0, 0.0))  # looking 3 deg down: ground below the horizon
    context = {"band": "eo", "illuminance_lx": 1e4, "ambient_k": 290.0, "ifov_rad": ifov}
    clutter = ClutterSchema(terrain=True)
    (alpha, plain, _), *_ = clutter_layers(rays, clutter, context, 1)[0]
    light, horizon = Daylight(visibility_km=FOG_KM, convention="physical"), 3000.0
    context["path"] = lambda r, up: eo_path_at(r, up, light, 550.0, horizon)
    (alpha_fog, fogged, _), *_ = clutter_layers(rays, clutter, context, 1)[0]
    assert np.array_equal(alpha, alpha_fog)
    ground = alpha > 0
    distance_km = clutter.camera_height_m / -rays[..., 2][ground] / 1000.0  # flat ground: h / (-z) along the ray
    tau = np.exp(-KOSCHMIEDER / FOG_KM * distance_km)
    assert fogged[ground] == pytest.approx(tau * plain[ground] + (1.0 - tau) * horizon, rel=1e-12)
    assert np.array_equal(fogged[~ground], plain[~ground])


def test_the_layers_take_a_path_wherever_range_gives_the_drone_one():
    from csuas.core.ranges import evaluate
    from csuas.render.imaging.dataset import _layers_take_path

    path_terms = {"kruse_extinction", "extinction_db_km"}  # the EO and thermal path terms of csuas range
    sensors = {"eo": {"modality": "eo"}, "tir": {"modality": "tir"}, "mrtd": {"modality": "tir", "model": "mrtd"}}
    for convention in ("paper", "physical"):
        for preset in sorted(load_presets()["environment"]):
            sc = parse_scenario({"convention": convention, "environment": {"preset": preset}, "sensors": sensors})
            ranges = evaluate(sc)
            for name in sensors:
                has_path = bool(path_terms & {t.name for t in ranges[name].terms})
                assert _layers_take_path(sc, sc.sensors[name]) == has_path, (convention, preset, name)
            assert not _layers_take_path(sc, sc.sensors["tir"])  # Johnson: the drone's frame has no path either


def test_no_path_leaves_the_layers_as_they_are():
    from csuas.render.imaging.clutter import _through_path as clutter_path
    from csuas.render.imaging.confusers import _through_path as confuser_path

    light = np.arange(6.0).reshape(2, 3)
    assert clutter_path(np.ones((2, 3)), light, 100.0, np.zeros((2, 3, 3)), None) is light
    assert confuser_path(np.ones((2, 3)), light, _gull(100.0), {}) is light
