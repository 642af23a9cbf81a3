"""Frame backgrounds (render/imaging/background.py): the CIE clear sky and the horizon."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from csuas.render.imaging.background import clear_sky_frame, relative_sky_luminance, zenith_luminance
from csuas.render.imaging.camera import SensorGeometry
from csuas.render.imaging.records import Daylight, View


def _cie12(z, chi, zs):
    """ISO 15469 type 12 written out: (1 + 10 (e^-3chi - e^-1.5pi) + 0.45 cos^2 chi)(1 - e^(-0.32/cos Z))."""

    def f(x):
        return 1 + 10 * (math.exp(-3 * x) - math.exp(-1.5 * math.pi)) + 0.45 * math.cos(x) ** 2

    def phi(x):
        return 1 - math.exp(-0.32 / math.cos(x))

    return f(chi) * phi(z) / (f(zs) * phi(0.0))


def test_clear_sky_luminance_follows_the_cie_formula():
    zs = math.radians(30.0)
    for z_deg, chi_deg in ((0.0, 30.0), (60.0, 90.0), (85.0, 5.0), (45.0, 150.0)):
        z, chi = math.radians(z_deg), math.radians(chi_deg)
        assert relative_sky_luminance(z, chi, zs) == pytest.approx(_cie12(z, chi, zs), rel=1e-12)
    # brighter toward the sun than away from it, at the same height
    assert relative_sky_luminance(math.radians(60), math.radians(10), zs) > relative_sky_luminance(
        math.radians(60), math.radians(120), zs
    )


def test_zenith_luminance_gives_the_diffuse_illuminance():
    zs = math.radians(45.0)
    lz = zenith_luminance(10500.0, zs)

    def integrand(z, phi):
        chi = math.acos(math.cos(z) * math.cos(zs) + math.sin(z) * math.sin(zs) * math.cos(phi))
        return lz * _cie12(z, chi, zs) * math.cos(z) * math.sin(z)

    e, _ = integrate.dblquad(integrand, 0, 2 * math.pi, 0, math.pi / 2, epsrel=1e-6)
    assert e == pytest.approx(10500.0, rel=1e-4)


def test_the_horizon_lies_where_the_view_ray_turns_level():
    ifov = math.radians(40.0) / 1920
    light = Daylight(illuminance_lx=70000.0, sun_azimuth_deg=100.0, sun_elevation_deg=25.0, ground_reflectance=0.2)
    assert light.diffuse_fraction * light.illuminance_lx == pytest.approx(10500.0)
    frame = clear_sky_frame(SensorGeometry(ifov, 1920, 1080), View(1.0, 30.0, 5.0, (0.0, 300.0)), light)
    ground = 0.2 * 70000.0 / math.pi
    column = frame[:, 960]
    first_ground = int(np.argmax(column == ground))
    # looking down 5 deg at the target (row 840.5): level rays lie tan(5 deg) / ifov rows above it
    expected = 1080 // 2 + 0.5 + 300.0 - math.tan(math.radians(5.0)) / ifov
    assert abs(first_ground - expected) <= 1.0
    assert np.all(column[:first_ground] != ground) and np.all(column[first_ground:] == ground)


def test_clouds_cover_the_share_asked_with_a_fractal_spectrum_and_a_seed():
    from csuas.render.imaging.background import CLOUD_SPECTRUM_EXPONENT, cloud_field, cloud_opacity

    opacity = cloud_opacity(512, 512, 0.4, seed=3, scale_px=512.0)
    assert np.mean(opacity > 0.5) == pytest.approx(0.4, abs=0.01)
    assert np.array_equal(opacity, cloud_opacity(512, 512, 0.4, seed=3, scale_px=512.0))
    assert not np.array_equal(opacity, cloud_opacity(512, 512, 0.4, seed=4, scale_px=512.0))
    # the field's power falls as f^-3 above the largest features: the slope of its radially averaged spectrum
    field = cloud_field(512, 512, seed=7, scale_px=512.0)
    power = np.abs(np.fft.rfft2(field)) ** 2
    radius = np.hypot(np.fft.rfftfreq(512)[None, :], np.fft.fftfreq(512)[:, None])
    bands = np.geomspace(0.01, 0.3, 12)
    mean_power = [power[(radius >= lo) & (radius < hi)].mean() for lo, hi in zip(bands[:-1], bands[1:])]
    centres = np.sqrt(bands[:-1] * bands[1:])
    slope = np.polyfit(np.log(centres), np.log(mean_power), 1)[0]
    assert slope == pytest.approx(-CLOUD_SPECTRUM_EXPONENT, abs=0.15)


def test_clouds_stay_in_the_sky():
    ifov = math.radians(40.0) / 1920
    args = (
        SensorGeometry(ifov, 1920, 1080),
        View(1.0, 30.0, 5.0, (0.0, 300.0)),
        Daylight(illuminance_lx=70000.0, sun_azimuth_deg=100.0, sun_elevation_deg=25.0, ground_reflectance=0.2),
    )
    clear = clear_sky_frame(*args)
    cloudy = clear_sky_frame(*args, cloud_cover=0.5, seed=1)
    ground = clear == 0.2 * 70000.0 / math.pi
    assert np.array_equal(cloudy[ground], clear[ground]) and not np.array_equal(cloudy[~ground], clear[~ground])
    assert cloudy[~ground].max() <= 70000.0 / math.pi + 1e-9


@pytest.mark.slow
def test_the_targets_excess_is_taken_against_the_background_behind_it():
    """Seen from below against the sky: on a uniform sky the excess equals the whole frame's electrons over its
    background; on the clear sky's gradient it stays the target's own (the frame's median would count the
    whole gradient)."""
    from csuas.render.imaging.frame import camera_from_params, eo_frame
    from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
    from csuas.render.imaging.sensor_chain import ChainSettings

    def frame(background):
        return eo_frame(
            "dji_mini_4_pro",
            View(300.0, 30.0, -10.0),
            EoSensor(),
            Daylight(background=background),
            camera_from_params(),
            ChainSettings(stages=()),
            settings=RenderSettings(quality="draft", seed=0),
        )

    uniform = frame("sky")
    electrons = uniform["electrons"]
    assert uniform["target_excess_e"] == pytest.approx(float(np.sum(electrons - np.median(electrons))), rel=1e-6)
    gradient = frame("clear_sky")
    electrons = gradient["electrons"]
    whole_frame = abs(float(np.sum(electrons - np.median(electrons))))
    assert 0.5 < gradient["target_excess_e"] / uniform["target_excess_e"] < 2.0
    assert whole_frame > 100 * abs(gradient["target_excess_e"])


@pytest.mark.slow
@pytest.mark.parametrize("elevation_deg, sky_share", [(-30.0, 1.0), (0.0, 0.5), (30.0, 0.0)])
def test_a_thermal_frame_shows_a_cold_sky_above_the_horizon_and_the_ground_below(elevation_deg, sky_share):
    """Sensor below the drone (it looks up): all sky; level: the upper half (36.7 x 20.6 deg frame); above: ground.

    The target's excess is taken against what lies behind it: a 230 K sky makes the drone stand out more
    than the 298 K ground does.
    """
    from csuas.render.imaging.frame import tir_frame
    from csuas.render.imaging.records import RenderSettings, ThermalScene, ThermalSensor, View
    from csuas.render.imaging.sensor_chain import ChainSettings

    scene = ThermalScene(surroundings_k=288.15)
    view = View(200.0, 40.0, elevation_deg)
    draft = RenderSettings(quality="draft", seed=0)
    frame = tir_frame("dji_mini_4_pro", view, ThermalSensor(), scene, ChainSettings(stages=()), settings=draft)
    sky = tir_frame(
        "dji_mini_4_pro",
        view,
        ThermalSensor(),
        scene,
        ChainSettings(stages=()),
        settings=draft,
        sky_temperature_k=230.0,
    )
    window = sky["result"].window
    outside = np.ones(sky["temperature"].shape, dtype=bool)
    outside[window.y0 : window.y0 + window.height, window.x0 : window.x0 + window.width] = False
    cold = np.isclose(sky["temperature"], 230.0, atol=1e-6)
    assert cold[outside].mean() == pytest.approx(sky_share, abs=0.01)
    assert np.allclose(sky["temperature"][outside & ~cold], frame["background_k"], atol=1e-6)
    assert frame["delta_t_k"] == pytest.approx(frame["result"].values["delta_t_k"], abs=1e-9)  # uniform: the render's
    if sky_share == 1.0:
        assert abs(sky["target_excess_k"]) > abs(frame["target_excess_k"])
        assert sky["delta_t_k"] == pytest.approx(frame["delta_t_k"] + frame["background_k"] - 230.0, abs=1e-6)
    if sky_share == 0.0:
        assert sky["target_excess_k"] == pytest.approx(frame["target_excess_k"], rel=1e-9)
