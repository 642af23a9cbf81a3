"""ISO 9613-1/-2 outdoor sound propagation and the band-limited acoustic detector (physical convention).

Oracles: ISO 9613-2 Table 2 and IEC 61672-1 Table 3 (printed values), the independent
``sound-propagation`` package (ISO 9613-1 absorption and ISO 9613-2 ground attenuation), Strasberg's
and ISO 9613-2's closed forms by hand.
"""

import math

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core import acoustic, acoustic_spectrum
from csuas.core.ranges import evaluate
from csuas.core.scenario import parse_scenario
from csuas.core.solve import solve_log_linear

sound_propagation = pytest.importorskip("sound_propagation")

OCTAVES_EXACT_HZ = 1000.0 * 10.0 ** (np.arange(-12, 10, 3) / 10.0)


def test_iso_9613_2_table_2_to_its_printed_precision():
    alpha = acoustic.iso9613_absorption_db_km(OCTAVES_EXACT_HZ, 20.0, 70.0, 101.325)
    assert [round(float(a), 1) for a in alpha] == [0.1, 0.3, 1.1, 2.8, 5.0, 9.0, 22.9, 76.6]


@pytest.mark.parametrize("t_c, rh, p_kpa", [(20.0, 70.0, 101.325), (-10.0, 30.0, 95.0), (35.0, 60.0, 90.0)])
def test_absorption_matches_sound_propagation(t_c, rh, p_kpa):
    f = acoustic_spectrum.third_octave_bands_hz()
    ref = sound_propagation.AtmosphericPropagation(t_c, rh, p_kpa).absorption_coefficient(f) * 1000.0
    np.testing.assert_allclose(acoustic.iso9613_absorption_db_km(f, t_c, rh, p_kpa), ref, rtol=1e-12)


@pytest.mark.parametrize(
    "hs, hr, dp, g",
    [(1.0, 2.0, 200.0, (1.0, 0.5, 0.0)), (30.0, 1.5, 150.0, (1.0, 1.0, 1.0)), (0.5, 1.5, 2000.0, (0.3, 0.7, 0.5))],
)
def test_ground_matches_sound_propagation(hs, hr, dp, g):
    g_source, g_middle, g_receiver = g
    ref = sound_propagation.GroundAttenuation(hs, hr, dp, G_source=g_source, G_receiver=g_receiver, G_middle=g_middle)
    nominal = np.array([63, 125, 250, 500, 1000, 2000, 4000, 8000])
    ours = acoustic.iso9613_ground_db(OCTAVES_EXACT_HZ, dp, hs, hr, g_source, g_middle, g_receiver)
    np.testing.assert_allclose(ours, ref.ground_attenuation(nominal), atol=1e-12)
    # a one-third-octave band takes the value of the octave band holding it: 200 Hz and 315 Hz -> 250 Hz
    thirds = acoustic.iso9613_ground_db([199.53, 316.23], dp, hs, hr, g_source, g_middle, g_receiver)
    np.testing.assert_allclose(thirds, ref.ground_attenuation(250), atol=1e-12)


def test_cmet_closed_form():
    # ISO 9613-2 Eqs. 21-22: 0 up to 10 (hs + hr), then C0 (1 - 10 (hs + hr) / dp)
    c = acoustic.iso9613_cmet_db(np.array([100.0, 120.0, 1000.0]), 10.0, 2.0, 2.0)
    np.testing.assert_allclose(c, [0.0, 0.0, 2.0 * (1 - 120 / 1000)], atol=1e-15)


def test_ground_names_a_bad_factor():
    with pytest.raises(ParameterError, match="g_middle"):
        acoustic.iso9613_ground_db(500.0, 100.0, 1.0, 1.0, 0.5, 1.5, 0.5)


def test_a_weighting_matches_iec_61672_table_3():
    nominal = [31.5, 63, 125, 250, 500, 1000, 2000, 4000, 8000, 16000]
    printed = [-39.4, -26.2, -16.1, -8.6, -3.2, 0.0, 1.2, 1.0, -1.1, -6.6]
    exact = 1000.0 * 10.0 ** (np.rint(10 * np.log10(np.array(nominal) / 1000.0)) / 10.0)
    assert [round(float(a), 1) for a in acoustic_spectrum.a_weighting_db(exact)] == printed


def test_bands_are_the_exact_base_10_mid_frequencies():
    bands = acoustic_spectrum.third_octave_bands_hz()
    assert bands.size == 24 and bands[0] == pytest.approx(50.119, abs=1e-3) and bands[-1] == pytest.approx(10000.0)
    np.testing.assert_allclose(bands[1:] / bands[:-1], 10**0.1, rtol=1e-14)


def _a_weighted_total(levels_db):
    a = acoustic_spectrum.a_weighting_db(acoustic_spectrum.third_octave_bands_hz())
    return 10 * np.log10(np.sum(10 ** ((levels_db + a) / 10), axis=-1))


def test_rotor_spectrum_carries_the_source_level_and_its_harmonics():
    spectrum = acoustic_spectrum.rotor_spectrum_db(np.array([80.0, 55.0]), np.array([200.0, 330.0]))
    np.testing.assert_allclose(_a_weighted_total(spectrum), [80.0, 55.0], atol=1e-12)
    bands = acoustic_spectrum.third_octave_bands_hz()
    floor = spectrum[0].min()  # the broadband floor: bands without a tone
    tonal = bands[spectrum[0] > floor + 1e-9]
    expected = {int(b) for b in bands[acoustic_spectrum.band_index(200.0 * np.arange(1, 11))]}
    assert {int(b) for b in tonal} == expected
    # equal A-weighted tonal and broadband power (tonal_to_broadband_db = 0): broadband alone is 3.01 dB down
    floor_total = _a_weighted_total(np.full(24, floor))
    assert 80.0 - floor_total == pytest.approx(10 * math.log10(2), abs=1e-12)


def test_ambient_spectrum_is_pink_at_its_a_weighted_level():
    ambient = acoustic_spectrum.ambient_spectrum_db(35.0)
    assert np.ptp(ambient) == 0.0 and _a_weighted_total(ambient) == pytest.approx(35.0, abs=1e-12)


def test_strasberg_wind_noise_closed_form():
    level = acoustic_spectrum.wind_noise_spectrum_db(10.0, 0.1)
    k0 = int(np.argmin(np.abs(acoustic_spectrum.third_octave_bands_hz() - 1000.0)))
    assert level[k0] == pytest.approx(40 * 1 - 23 * math.log10(1000 * 0.1 / 10) + 15, abs=1e-12)  # 32 dB
    assert np.all(np.isneginf(acoustic_spectrum.wind_noise_spectrum_db(0.5, 0.1)))


def test_band_ranges_with_ground_solve_the_budget():
    budget = np.array([60.0, 45.0, 30.0])
    alpha = acoustic.iso9613_absorption_db_km(np.array([200.0, 1000.0, 4000.0]), 20.0, 70.0, 101.325)
    free = acoustic_spectrum.band_ranges_m(budget, alpha)
    np.testing.assert_allclose(free, solve_log_linear(budget, alpha / 1000.0, n=2.0), rtol=0)
    ground = dict(receiver_height_m=1.5, altitude_m=20.0, g_source=1.0, g_middle=1.0, g_receiver=1.0, c0_db=2.0)
    r = acoustic_spectrum.band_ranges_m(budget[:, None] * np.ones((1, 24)), 0.0, ground)[:, 7]  # 250 Hz band
    hs, hr = 21.5, 1.5
    dp = np.sqrt(r**2 - 20.0**2)
    oracle = np.array([sound_propagation.GroundAttenuation(hs, hr, d).ground_attenuation(250) for d in dp])
    cmet = np.where(dp <= 230, 0.0, 2.0 * (1 - 230 / dp))
    np.testing.assert_allclose(20 * np.log10(r) + oracle + cmet, budget, atol=1e-6)


def _physical(target=None, environment=None, sensor=None):
    sensor = {"modality": "acoustic", **(sensor or {})}
    data = {
        "convention": "physical",
        "target": target or {},
        "environment": environment or {},
        "sensors": {"a": sensor},
    }
    return evaluate(parse_scenario(data))["a"]


def test_detector_reaches_the_required_snr_in_its_band():
    result = _physical()
    r, band = float(result.range_m), float(result.term("detector_band_hz").value)
    snr = (
        float(result.term("band_source_level_db").value)
        - 20 * math.log10(r)
        - float(result.term("absorption_db_km").value) * r / 1000
        - float(result.term("band_ambient_noise_db").value)
        + float(result.term("g_array_db").value)
    )
    assert snr == pytest.approx(10.0, abs=1e-7)  # snr_req_db (Table 28)
    assert acoustic.iso9613_absorption_db_km(band, 20.0, 70.0, 101.325) == pytest.approx(
        float(result.term("absorption_db_km").value), rel=1e-12
    )


def test_windshield_matters_in_wind_only():
    calm = [_physical(sensor={"windshield": w}).range_m for w in ("none", "foam")]
    assert calm[0] == calm[1]
    windy = [
        float(_physical(environment={"preset": "moderate_breeze"}, sensor={"windshield": w}).range_m)
        for w in ("none", "foam")
    ]
    assert windy[1] > windy[0]


def test_ground_only_with_the_sensor_height():
    assert "ground_and_cmet_db" not in {t.name for t in _physical().terms}
    assert "ground_and_cmet_db" in {t.name for t in _physical(sensor={"height_m": 1.5}).terms}


def test_broadband_detector_keeps_the_single_frequency_model():
    result = _physical(sensor={"detector": "broadband"})
    assert result.model.startswith("spherical_spreading+noise") and result.term("absorption_db_m").unit == "dB/m"


def test_vectorised_scenario_matches_point_by_point():
    from dataclasses import replace

    sensors = {
        "a": {"modality": "acoustic", "height_m": 1.5},
        "r": {"modality": "radar", "preset": "paper_section_4_9"},
    }
    base = parse_scenario(
        {"convention": "physical", "environment": {"relative_humidity_pct": 50.0}, "sensors": sensors}
    )
    columns = {"relative_humidity_pct": [10.0, 100.0], "temperature_k": [270.0, 310.0], "wind_speed_m_s": [0.3, 12.0]}
    columns["ground_factor"] = [0.0, 1.0]
    batch = replace(base, environment=dict(base.environment, **{k: np.array(v) for k, v in columns.items()}))
    together = evaluate(batch)
    for i in range(2):
        point = replace(base, environment=dict(base.environment, **{k: v[i] for k, v in columns.items()}))
        for name, result in evaluate(point).items():
            assert float(together[name].range_m[i]) == pytest.approx(float(result.range_m), rel=1e-9)
