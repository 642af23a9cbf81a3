"""ITU-R P.676 gaseous attenuation against ITU-Rpy (itur), and its place in the physical RF and radar ranges.

The ``p676`` package, the second cross-check the issue names, does not install here (its
dependency ``p835`` is not on the package index this project uses): itur alone is the oracle.
ITU-Rpy's P.676-12 takes the dry-air pressure p of Annex 1 Eq. 3; csuas takes the total
barometric pressure p + e, so the oracle is given p = P - rho T / 216.7.
"""

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.core import itu, radar, rf
from csuas.core.ranges import evaluate, gas_atmosphere
from csuas.core.scenario import parse_scenario
from csuas.core.units import wavelength_m

itur676 = pytest.importorskip("itur.models.itu676")
itur453 = pytest.importorskip("itur.models.itu453")

FREQUENCIES_GHZ = [10.0, 22.235, 24.0, 35.0, 60.0, 94.0]


def _itur_gamma(f, p_total, t, rho):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p_dry = p_total - rho * t / 216.7
        return float(itur676.gamma_exact(f, p_dry, rho, t).value)


@pytest.mark.parametrize("f", FREQUENCIES_GHZ)
@pytest.mark.parametrize("p, t, rho", [(1013.25, 288.15, 7.5), (950.0, 303.15, 20.0), (1030.0, 263.15, 1.0)])
def test_gaseous_attenuation_matches_itur(f, p, t, rho):
    assert itur676.get_version() == 12
    assert itu.gaseous_attenuation_db_km(f, p, t, rho) == pytest.approx(_itur_gamma(f, p, t, rho), abs=1e-6)


def test_issue_figures_in_the_reference_atmosphere():
    # Issue 27 quotes 0.17 (24 GHz), 0.10 (35 GHz) and 14.8 dB/km (60 GHz) for the P.835 sea level
    # atmosphere read with 1013.25 hPa as the dry-air pressure; total pressure 1013.25 gives 14.7 at 60 GHz.
    e = 7.5 * 288.15 / 216.7
    gamma = itu.gaseous_attenuation_db_km(np.array([24.0, 35.0, 60.0]), 1013.25 + e, 288.15, 7.5)
    assert [round(float(g), d) for g, d in zip(gamma, (2, 2, 1))] == [0.17, 0.10, 14.8]
    assert float(itu.gaseous_attenuation_db_km(60.0, 1013.25, 288.15, 7.5)) == pytest.approx(14.66, abs=0.005)


def test_dry_air_alone_has_no_water_line():
    oxygen, water = itu.gaseous_attenuation_components_db_km(22.235, 1013.25, 288.15, 0.0)
    assert float(water) == 0.0 and 0.0 < float(oxygen) < 0.02


def test_vectorised_broadcast():
    f = np.array([[24.0], [35.0]])
    rho = np.array([0.0, 7.5, 15.0])
    gamma = itu.gaseous_attenuation_db_km(f, 1013.25, 288.15, rho)
    assert gamma.shape == (2, 3)
    assert gamma[1, 2] == pytest.approx(_itur_gamma(35.0, 1013.25, 288.15, 15.0), abs=1e-6)


def test_vapour_density_from_humidity_matches_itur_p453():
    rho = itu.water_vapour_density_g_m3(70.0, 293.15, 1013.25)
    e_ref = float(itur453.water_vapour_pressure(20.0, 1013.25, 70.0).value)
    assert float(rho) == pytest.approx(216.7 * e_ref / 293.15, rel=1e-10)


@pytest.mark.parametrize(
    "kwargs, name", [({"frequency_ghz": 0.5}, "frequency_ghz"), ({"water_vapour_density_g_m3": 1e5}, "water_vapour")]
)
def test_bad_input_names_parameter(kwargs, name):
    args = dict(frequency_ghz=24.0, pressure_hpa=1013.25, temperature_k=288.15, water_vapour_density_g_m3=7.5)
    with pytest.raises(ParameterError, match=name):
        itu.gaseous_attenuation_db_km(**(args | kwargs))


RF = dict(p_tx_w=0.1, g_tx_dbi=8.0, g_rx_db=14.0, frequency_ghz=2.4, s_rx_dbm=-100.0)


def test_rf_physical_solves_the_gas_over_the_range():
    gamma = float(itu.gaseous_attenuation_db_km(2.4, 1013.25, 288.15, 7.5))
    result = rf.rf_range(**RF, gas_db_km=gamma, convention="physical")
    r = float(result.range_m)
    fspl = 20 * np.log10(4 * np.pi * r / wavelength_m(2.4))
    assert fspl + gamma * r / 1000 == pytest.approx(142.0, abs=1e-9)  # Eq. 57's budget, spent exactly
    assert float(result.term("gas_loss_db").value) == pytest.approx(gamma * r / 1000, rel=1e-12)


def test_negligible_gas_adds_no_term():
    gamma = float(itu.gaseous_attenuation_db_km(2.4, 1013.25, 288.15, 7.5))
    short = rf.rf_range(**(RF | {"s_rx_dbm": -40.0}), gas_db_km=gamma, convention="physical")  # 125 m: 0.9 mdB
    assert "gas_loss_db" not in {t.name for t in short.terms}
    assert float(short.range_m) == pytest.approx(
        float(rf.rf_range(**(RF | {"s_rx_dbm": -40.0}), convention="physical").range_m), rel=0
    )


def test_paper_convention_refuses_a_gas_term():
    with pytest.raises(ParameterError, match="gas_db_km"):
        rf.rf_range(**RF, gas_db_km=0.1)
    with pytest.raises(ParameterError, match="gas_db_km"):
        radar.radar_range(p_tx_w=10, g_tx_db=25, g_rx_db=25, wavelength_m=0.0125, sigma_m2=0.01, gas_db_km=0.1)


def test_radar_two_way_gas_closed_form():
    kw = dict(p_tx_w=1000.0, g_tx_db=35.0, g_rx_db=35.0, wavelength_m=wavelength_m(35.0), sigma_m2=0.01)
    gamma = float(itu.gaseous_attenuation_db_km(35.0, 1013.25, 288.15, 7.5))
    without = float(radar.radar_range(**kw, convention="physical").range_m)
    result = radar.radar_range(**kw, gas_db_km=gamma, convention="physical")
    r = float(result.range_m)
    assert 40 * np.log10(without) == pytest.approx(40 * np.log10(r) + 2 * gamma * r / 1000, abs=1e-9)
    assert float(result.term("l_gas_db").value) == pytest.approx(2 * gamma * r / 1000, rel=1e-12)


def _scenario(env: dict, convention="physical"):
    sensors = {"radar": {"modality": "radar"}, "rf": {"modality": "rf"}}
    return parse_scenario({"convention": convention, "environment": env, "sensors": sensors})


def test_scenario_gas_term_only_under_physical_and_paper_unchanged():
    physical = evaluate(_scenario({}))
    assert float(physical["radar"].term("gamma_gas_db_km").value) == pytest.approx(
        _itur_gamma(299792458.0 / 0.0125 / 1e9, 1013.25, 288.15, 7.5), abs=1e-6
    )
    paper = evaluate(_scenario({}, "paper"))
    for result in paper.values():
        assert not {"gamma_gas_db_km", "gas_loss_db", "l_gas_db"} & {t.name for t in result.terms}


def test_scenario_atmosphere_replaces_the_reference_values():
    assert gas_atmosphere(_scenario({})) == itu.standard_atmosphere()
    given = gas_atmosphere(_scenario({"temperature_k": 303.15, "relative_humidity_pct": 90.0, "pressure_kpa": 95.0}))
    assert given["temperature_k"] == 303.15 and given["pressure_hpa"] == pytest.approx(950.0)
    e_ref = float(itur453.water_vapour_pressure(30.0, 950.0, 90.0).value)
    assert given["water_vapour_density_g_m3"] == pytest.approx(216.7 * e_ref / 303.15, rel=1e-10)
