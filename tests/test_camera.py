"""The EO camera chain (core.camera) and the light-limited EO range, against closed forms written here."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from csuas.core import camera

H, C, KB = 6.62607015e-34, 299_792_458.0, 1.380649e-23


def test_photons_per_lumen_against_an_independent_quadrature():
    def planck(lam, t=5900.0):
        return 2 * H * C**2 / lam**5 / math.expm1(H * C / (lam * KB * t))

    def v(lam):  # the Gaussian fit of CIE 1924 V(lambda), lambda in m
        return 1.019 * math.exp(-285.4 * (lam * 1e6 - 0.559) ** 2)

    photons = integrate.quad(lambda lam: planck(lam) * lam / (H * C), 400e-9, 700e-9, epsabs=0, epsrel=1e-10)[0]
    lumens = 683.0 * integrate.quad(lambda lam: planck(lam) * v(lam), 360e-9, 830e-9, epsabs=0, epsrel=1e-10)[0]
    assert camera.photons_per_lumen() == pytest.approx(photons / lumens, rel=1e-4)
    # broadband light needs more photons per lumen than 555 nm light, lambda / (h c 683) = 4.09e15
    assert camera.photons_per_lumen() > 555e-9 / (H * C * 683.0)


def test_michelson_contrast_gives_the_luminance_excess():
    # C = (Lt - Lb)/(Lt + Lb): Lt = 3 Lb at 0.5, Lt = Lb / 3 at -0.5, equal at 0, black background at 1
    assert camera.luminance_excess(0.5) == pytest.approx(2.0)
    assert camera.luminance_excess(-0.5) == pytest.approx(-2.0 / 3.0)
    assert camera.luminance_excess(0.0) == 0.0 and np.isinf(camera.luminance_excess(1.0))


def test_camera_equation_exposure_and_noise():
    assert camera.focal_plane_illuminance_lx(1000.0, 2.0, 1.0) == pytest.approx(math.pi * 1000.0 / 16.0)
    rate = camera.electron_rate(100.0, 2.0, 0.5, 1e16)  # 100 lx on 4 um^2 at QE 0.5
    assert rate == pytest.approx(100.0 * 4e-12 * 0.5 * 1e16)
    assert camera.auto_exposure_s(1e6, 1e4, 0.033) == pytest.approx(0.5 * 1e4 / 1e6)  # bright: half full well
    assert camera.auto_exposure_s(10.0, 1e4, 0.033) == pytest.approx(0.033)  # dark: the frame's longest
    assert camera.auto_exposure_s(0.0, 1e4, 0.033) == pytest.approx(0.033)
    assert camera.pixel_noise_e(100.0, 4.0, 3.0) == pytest.approx(math.sqrt(100 + 4 + 9))


def test_light_limited_range_without_atmosphere_has_its_closed_form():
    chain = camera.CameraChain(
        f_number=2.0,
        optics_transmittance=0.9,
        pixel_pitch_um=2.9,
        quantum_efficiency=0.6,
        max_exposure_ms=33.3,
        full_well_e=1e4,
        read_noise_e=2.0,
        dark_current_e_s=5.0,
        required_snr=4.753424,
    )
    settings = dict(camera=chain, illuminance_lx=0.01, background_reflectance=0.3, projected_area_m2=0.06)
    ifov = math.radians(10.0) / 1920
    r, chain = camera.light_limited_range_m(c_eo=0.5, ifov_rad_=ifov, transmittance_at=lambda rr: 1.0, **settings)
    # by hand: background luminance, focal-plane illuminance, electrons in 33.3 ms, noise
    lum = 0.01 * 0.3 / math.pi
    e_fp = math.pi * lum * 0.9 / 16.0
    s_b = e_fp * (2.9e-6) ** 2 * 0.6 * camera.photons_per_lumen() * 0.0333
    noise = math.sqrt(s_b + 5.0 * 0.0333 + 4.0)
    assert chain["background_e"] == pytest.approx(s_b, rel=1e-12) and chain["noise_e"] == pytest.approx(noise)
    # the paper's Michelson contrast 0.5 (Eq. 3): L_t = L_b (1 + C) / (1 - C) = 3 L_b, an excess of 2 s_b
    excess = (1.5 / 0.5 - 1.0) * s_b
    # resolved at the answer: SNR = excess sqrt(A) / (ifov R noise); sub-pixel would need A / (ifov R)^2 < 1
    expected = excess * math.sqrt(0.06) / (noise * ifov * 4.753424)
    assert 0.06 / (ifov * expected) ** 2 > 1.0
    assert r == pytest.approx(expected, rel=1e-9)
    zero, _ = camera.light_limited_range_m(c_eo=0.0, ifov_rad_=ifov, transmittance_at=lambda rr: 1.0, **settings)
    assert zero == 0.0


def _eo_range(tmp_path, convention, lux):
    from csuas.core.ranges import evaluate
    from csuas.core.scenario import load_scenario

    path = tmp_path / f"{convention}{lux}.toml"
    path.write_text(
        f'name = "eo"\nconvention = "{convention}"\n[target]\n[environment]\nilluminance_lx = {lux}\n'
        '[sensors.eo]\nmodality = "eo"\n'
    )
    return load_scenario(path), evaluate(load_scenario(path), convention)["eo"]


def test_night_shortens_the_physical_eo_range_and_not_the_papers(tmp_path):
    physical = [float(_eo_range(tmp_path, "physical", lux)[1].range_m) for lux in (70000.0, 3.0, 0.01)]
    paper = [float(_eo_range(tmp_path, "paper", lux)[1].range_m) for lux in (70000.0, 3.0, 0.01)]
    assert paper[0] == paper[1] == paper[2]
    assert physical[0] == pytest.approx(paper[0], rel=0.02)  # daylight: the Johnson limit binds
    assert physical[2] < 0.5 * physical[0]  # Table 11's night (10 mlx): light-limited (157 m of 556 m)
    night = _eo_range(tmp_path, "physical", 0.01)[1]
    assert "light-limited" in str(night.reason)


def test_pd_at_the_light_limited_range_is_p_desired(tmp_path):
    from csuas.core.pd_curves import sensor_pd

    scenario, _ = _eo_range(tmp_path, "physical", 0.01)
    curve = sensor_pd(scenario, "eo", np.array([5.0, 400.0]))
    # at 157 m the TTPF is 0.997: Pd there is the camera's 0.5 times it
    assert curve.pd_at_deterministic_range == pytest.approx(0.5, abs=0.01)
    assert curve.pd[0] > 0.99 and curve.pd[1] < 1e-3
