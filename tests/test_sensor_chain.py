"""The sensor chain (render/imaging/sensor_chain.py) by independent methods: a photon-transfer curve
(EMVA 1288) returns the configured gain and read noise, a slanted edge (ISO 12233) returns the analytic
MTF, flat thermal frames return the NETD (the procedures: validation/imaging/chain_checks.py)."""

from __future__ import annotations

import numpy as np
import pytest

from csuas.base.errors import InputErrors
from csuas.render.imaging.sensor_chain import ChainSettings, apply_chain
from csuas.validation.imaging.chain_checks import flat_field_netd, photon_transfer, slanted_edge_mtf


def test_photon_transfer_curve_returns_the_gain_and_read_noise():
    settings = ChainSettings(stages=("shot_noise", "read_noise", "quantise"), read_noise_e=6.0, bits=12)
    measured = photon_transfer(settings)
    assert measured["gain_e_per_dn"] == pytest.approx(settings.gain_e_per_dn, rel=0.02)
    assert measured["read_noise_e"] == pytest.approx(6.0, rel=0.1)


def test_slanted_edge_mtf_equals_the_chains_analytic_mtf():
    settings = ChainSettings(stages=("psf",), f_number=8.0, wavelength_um=0.55, pixel_pitch_um=2.9, jitter_px=0.3)
    mtf = slanted_edge_mtf(settings)
    assert mtf["max_abs_difference"] < 0.02  # measured 0.012
    assert mtf["analytic"][-1] < 0.1 < mtf["analytic"][len(mtf["analytic"]) // 2]  # a real fall to Nyquist


def test_flat_thermal_frames_show_the_netd():
    settings = ChainSettings(stages=("netd", "quantise"), netd_k=0.05, t_min_k=280.0, t_max_k=320.0, bits=14)
    assert flat_field_netd(settings) == pytest.approx(0.05, rel=0.02)
    out = apply_chain(np.full((256, 256), 300.0), settings, seed=4, thermal=True)
    scale = (settings.t_max_k - settings.t_min_k) / (2**14 - 1)
    assert np.std(out["dn"] * scale) == pytest.approx(0.05, rel=0.03)


def test_the_same_seed_gives_the_same_bytes_and_the_fixed_pattern_stays():
    settings = ChainSettings(stages=("shot_noise", "prnu", "dsnu", "read_noise", "quantise"), prnu=0.01, dsnu_e=3.0)
    flat = np.full((64, 64), 1000.0)
    one, again = apply_chain(flat, settings, seed=9), apply_chain(flat, settings, seed=9)
    assert one["dn"].tobytes() == again["dn"].tobytes()
    frames = [apply_chain(flat, settings, seed=s)["signal"] for s in range(200)]
    pattern = np.mean(frames, axis=0) - 1000.0  # temporal noise averages away (to 2.2 e), the fixed pattern stays
    stream = np.random.default_rng([0, 1])  # camera seed 0: the gain pattern, then the offset pattern
    expected = 1000.0 * 0.01 * stream.standard_normal((64, 64)) + 3.0 * stream.standard_normal((64, 64))
    # correlation of pattern + residual noise with the pattern: sqrt(109 / (109 + 2.2^2)) = 0.98
    assert np.corrcoef(pattern.ravel(), expected.ravel())[0, 1] > 0.95


def test_saturation_zero_light_and_bad_settings():
    settings = ChainSettings(stages=("shot_noise", "read_noise", "quantise"))
    bright = apply_chain(np.full((16, 16), 1e6), settings, seed=0)
    assert bright["saturated"] == 1.0 and bright["dn"].max() == 4095
    dark = apply_chain(np.zeros((16, 16)), settings, seed=0)  # noise only, never negative DN
    assert dark["dn"].min() >= 0 and 0.0 < np.std(dark["signal"]) < 3.0
    with pytest.raises(InputErrors) as caught:
        apply_chain(np.ones((4, 4)), ChainSettings(stages=("blur",), f_number=0.0, bits=9), seed=0)
    text = str(caught.value)
    assert "stages" in text and "f_number" in text and "bits" in text


def _second_moments(image):
    y, x = np.indices(image.shape, dtype=float)
    w = image / image.sum()
    mx, my = (w * x).sum(), (w * y).sum()
    return (w * (x - mx) ** 2).sum(), (w * (y - my) ** 2).sum(), (w * (x - mx) * (y - my)).sum()


def test_defocus_and_motion_blur_spread_a_point_as_a_disk_and_a_line():
    point = np.zeros((256, 256))
    point[128, 128] = 1000.0
    # (as a thermal frame: an EO frame clips the band-limited blur's negative ringing, which moves the moments)
    # a uniform disk of diameter b has the variance b^2 / 16 along each axis
    disk = apply_chain(point, ChainSettings(stages=("defocus",), defocus_px=8.0), seed=0, thermal=True)
    disk = disk["signal"].astype(float)
    vx, vy, cxy = _second_moments(disk)
    assert vx == pytest.approx(64.0 / 16.0, rel=0.002) and vy == pytest.approx(4.0, rel=0.002) and abs(cxy) < 0.01
    # a uniform segment of length L along x has the variance L^2 / 12 along it and none across
    line = apply_chain(point, ChainSettings(stages=("motion",), motion_px=12.0), seed=0, thermal=True)
    line = line["signal"].astype(float)
    vx, vy, _ = _second_moments(line)
    assert vx == pytest.approx(144.0 / 12.0, rel=0.002) and vy < 0.01
    assert disk.sum() == pytest.approx(1000.0, rel=1e-3) and line.sum() == pytest.approx(1000.0, rel=1e-3)


def test_agc_puts_the_chosen_percentile_at_the_chosen_level_and_jpeg_stays_close():
    rng = np.random.default_rng(0)
    scene = 50.0 + 20.0 * rng.random((64, 64))  # a dim frame: 50-70 electrons
    settings = ChainSettings(stages=("agc", "quantise"), agc_percentile=99.0, agc_level=0.8, bits=12)
    out = apply_chain(scene, settings, seed=0)
    assert np.percentile(out["dn"], 99.0) == pytest.approx(0.8 * 4095, abs=2.0)
    smooth = 2000.0 + 1000.0 * np.sin(np.linspace(0, np.pi, 64))[None, :] * np.ones((64, 1))
    eight = ChainSettings(stages=("quantise",), bits=8, full_well_e=4000.0)
    plain = apply_chain(smooth, eight, seed=0)["dn"].astype(float)
    compressed = apply_chain(
        smooth, ChainSettings(stages=("quantise", "jpeg"), bits=8, full_well_e=4000.0, jpeg_quality=85), seed=0
    )["dn"].astype(float)
    psnr = 10 * np.log10(255.0**2 / np.mean((plain - compressed) ** 2 + 1e-12))
    assert 35.0 < psnr < 200.0  # lossy, but close on a smooth frame
    with pytest.raises(InputErrors, match="jpeg"):
        apply_chain(smooth, ChainSettings(stages=("quantise", "jpeg"), bits=12), seed=0)


@pytest.mark.slow
def test_rendered_snr_equals_the_core_camera_model_by_day_twilight_and_night():
    from csuas.validation.imaging.chain_checks import rendered_snr_against_core

    rows = rendered_snr_against_core()
    for row in rows:
        assert row["background_e_rendered"] == pytest.approx(row["background_e_core"], rel=1e-6)
        assert row["snr_rendered"] == pytest.approx(row["snr_core"], rel=0.01)
    assert rows[0]["snr_rendered"] > rows[1]["snr_rendered"] > rows[2]["snr_rendered"]  # light decides


@pytest.mark.slow
def test_rendered_light_limited_range_equals_the_core_camera_model():
    """Day (sub-pixel at 5.4 km), twilight and night (38 m): within 3 standard errors (measured 0.5-2 %)."""
    from csuas.validation.imaging.chain_checks import rendered_light_limited_range

    rows = rendered_light_limited_range(illuminances_lx=(70000.0, 0.01))
    for row in rows:
        assert row["relative_stderr"] < 0.05
        assert row["range_rendered_m"] == pytest.approx(row["range_core_m"], rel=3 * row["relative_stderr"])
    assert rows[0]["range_core_m"] > 100 * rows[1]["range_core_m"]  # light decides


@pytest.mark.slow
def test_a_frame_without_light_is_read_noise_only_and_zero_netd_adds_nothing():
    """0 lx: the longest exposure, no signal, an SNR of 0 and DN of read noise alone; NETD 0: the exact scene."""
    from csuas.render.imaging.frame import camera_from_params, eo_frame, target_snr
    from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View

    camera = camera_from_params()
    stages = ChainSettings(stages=("shot_noise", "read_noise", "quantise"), read_noise_e=2.0)
    frame = eo_frame(
        "dji_mini_4_pro",
        View(300.0, 30.0, 10.0),
        EoSensor(),
        Daylight(0.0, background=0.3),
        camera,
        stages,
        settings=RenderSettings(quality="draft", seed=0),
    )
    assert frame["exposure_s"] == pytest.approx(camera["max_exposure_ms"] / 1000.0)
    assert frame["target_excess_e"] == 0.0 and target_snr(frame, 2.0) == 0.0
    electrons = frame["chain"]["signal"]
    assert np.isfinite(electrons).all() and np.std(electrons) == pytest.approx(2.0, rel=0.01)  # 2 M pixels
    flat = apply_chain(np.full((8, 8), 300.0), ChainSettings(stages=("netd", "quantise"), netd_k=0.0), 0, thermal=True)
    assert np.all(flat["signal"] == 300.0)


def test_a_rolling_shutter_skews_a_moving_edge_by_its_speed_times_the_line_time():
    rows, line_time, vx = 200, 20e-6, 1500.0  # 0.03 px per row
    edge = np.zeros((rows, 120))
    edge[:, 60:] = 1.0  # a dark-to-bright step at the pixel edge x = 60
    settings = ChainSettings(stages=("rolling_shutter",), line_time_s=line_time, velocity_px_s=(vx, 0.0))
    skewed = apply_chain(edge, settings, seed=0)["signal"].astype(float)
    position = 120 - skewed.sum(axis=1)  # a step's position from the light it lets through (any sampling)
    middle = (rows - 1) / 2.0
    expected = 60.0 + vx * line_time * (np.arange(rows) - middle)  # x(r) = x0 + v t_line (r - r_mid)
    assert np.max(np.abs(position - expected)) < 1e-4
    # moving down at vy, row r reads the scene row r - vy tau(r): the step at y0 = 80 lands where
    # r (1 - vy t) + vy t r_mid = y0, a stretch of 1 / (1 - vy t) about the middle row
    vy = 3000.0
    horizontal = np.zeros((rows, 40))
    horizontal[80:, :] = 1.0
    settings = ChainSettings(stages=("rolling_shutter",), line_time_s=line_time, velocity_px_s=(0.0, vy))
    stretched = apply_chain(horizontal, settings, seed=0)["signal"].astype(float)
    r = np.arange(rows, dtype=float)[:, None]
    read = r - vy * line_time * (r - middle)  # the scene row each frame row reads
    assert np.max(np.abs(stretched - np.clip(read - 79.0, 0.0, 1.0))) < 1e-6  # the step's linear ramp, 79 to 80


def test_the_frame_rate_caps_the_exposure_and_the_motion_blur_follows_it():
    flat = np.full((8, 8), 1000.0)
    settings = ChainSettings(stages=("frame_exposure",), exposure_s=0.05, frame_rate_hz=60.0)
    out = apply_chain(flat, settings, seed=0)
    assert out["exposure_s"] == pytest.approx(1 / 60) and out["signal"][0, 0] == pytest.approx(1000.0 * (1 / 60) / 0.05)
    short = ChainSettings(stages=("frame_exposure",), exposure_s=0.004, frame_rate_hz=60.0)
    assert apply_chain(flat, short, seed=0)["signal"][0, 0] == pytest.approx(1000.0)  # shorter than a frame: kept
    # a point moving at 600 px/s for 1/60 s: a 10 px line, its sum kept, along x
    point = np.full((64, 128), 100.0)  # on a pedestal: the band-limited blur's ringing stays above zero
    point[32, 40] += 100.0
    moving = ChainSettings(
        stages=("frame_exposure", "motion"), exposure_s=0.05, frame_rate_hz=60.0, velocity_px_s=(600.0, 0.0)
    )
    smeared = apply_chain(point, moving, seed=0)["signal"].astype(float)
    profile = smeared[32] - 100.0 / 3.0
    assert profile.sum() == pytest.approx(100.0 / 3.0, rel=1e-4)
    centroid = float(np.sum(np.arange(128) * profile) / profile.sum())
    width = 2 * np.sqrt(3 * float(np.sum((np.arange(128) - centroid) ** 2 * profile) / profile.sum()))
    assert centroid == pytest.approx(40.0, abs=0.01) and width == pytest.approx(10.0, rel=0.05)  # sd = L / sqrt 12


def test_the_normal_shot_noise_keeps_the_poisson_mean_and_variance_and_exact_draws_below_its_threshold():
    frame = np.full((400, 500), 2000.0)
    frame[:, :50] = 4.0  # dim pixels stay Poisson
    settings = ChainSettings(stages=("shot_noise",), normal_shot_noise_above_e=1000.0)
    counts = apply_chain(frame, settings, seed=3)["signal"].astype(float)
    bright, dim = counts[:, 50:], counts[:, :50]
    n = (
        bright.size
    )  # 180,000: standard error of the mean sqrt(2000 / n) = 0.105 e, of the variance 2000 sqrt(2 / n) = 6.7 e^2
    assert bright.mean() == pytest.approx(2000.0, abs=4 * 0.105) and bright.var() == pytest.approx(2000.0, abs=4 * 6.7)
    assert np.array_equal(counts, np.rint(counts)) and n == 180_000
    # Poisson(4): P(0) = e^-4 = 0.0183 over 20,000 pixels (standard error 0.00095); a clipped normal: 0.040
    assert np.mean(dim == 0) == pytest.approx(np.exp(-4.0), abs=4 * 0.00095)
    with pytest.raises(InputErrors, match="normal_shot_noise_above_e"):
        apply_chain(frame, ChainSettings(stages=("shot_noise",), normal_shot_noise_above_e=10.0), seed=0)
