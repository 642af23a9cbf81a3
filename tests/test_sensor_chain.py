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
