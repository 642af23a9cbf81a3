"""Fog in the thermal path (physical convention): LOWTRAN 7's fog models against their printed table, the band
mean by quadrature, the range's terms, and the fog layer's share from the render's own geometry.

The table (Shettle & Fenn 1979, as printed in LOWTRAN 7's BLOCK DATA EXTDTA: VX2, FG1EXT, FG2EXT) is copied
here from the source, not from csuas.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from csuas.base.errors import ParameterError, ScenarioError
from csuas.core import tir
from csuas.core.atmosphere import fog_extinction_ratio, fog_infrared_extinction_per_km
from csuas.core.ranges import evaluate, thermal_fog, thermal_fog_db_km
from csuas.core.scenario import load_scenario, parse_scenario

#: LOWTRAN 7 VX2 [um] from 2.7 to 14.8, and the fog models' extinction over their 0.55 um extinction.
LOWTRAN_UM = [2.7, 3.0, 3.3923, 3.75, 4.5, 5.0, 5.5, 6.0, 6.2, 6.5, 7.2, 7.9, 8.2, 8.7, 9.0, 9.2, 10.0, 10.591, 11.0]
LOWTRAN_UM += [11.5, 12.5, 14.8]
FG1EXT = [1.05886, 1.04899, 1.06823, 1.07804, 1.09272, 1.10367, 1.11684, 1.10430, 1.11367, 1.12899, 1.14987]
FG1EXT += [1.17209, 1.18278, 1.20133, 1.21266, 1.21949, 1.22677, 1.15589, 1.05684, 0.98291, 1.01120, 1.10911]
FG2EXT = [1.04715, 1.10816, 1.43285, 1.45272, 1.18709, 1.04367, 0.82354, 0.71747, 0.92405, 0.79342, 0.60266]
FG2EXT += [0.47677, 0.43171, 0.36734, 0.33259, 0.31184, 0.24139, 0.21601, 0.24006, 0.28816, 0.42671, 0.56861]
DB_PER_NEPER = 10.0 * math.log10(math.e)
KOSCHMIEDER = -math.log(0.02)  # 3.912: Eq. 12, LOWTRAN's visibility scaling at 0.55 um


def band_ratio(table, low_um: float, high_um: float) -> float:
    """Mean of the table's ratio over [low, high] um, linear between its wavelengths, by adaptive quadrature."""
    value, _ = quad(lambda lam: np.interp(lam, LOWTRAN_UM, table), low_um, high_um, points=LOWTRAN_UM, limit=200)
    return value / (high_um - low_um)


def lwir_advection_ratio() -> float:
    """The advection fog's mean ratio over the LWIR 8-12 um."""
    return band_ratio(FG1EXT, 8.0, 12.0)


@pytest.mark.parametrize("fog, table", [("advection", FG1EXT), ("radiation", FG2EXT)])
def test_fog_ratio_is_lowtrans_table_at_its_wavelengths(fog, table):
    for lam, printed in zip(LOWTRAN_UM[1:], table[1:]):
        assert float(fog_extinction_ratio(lam, fog)) == pytest.approx(printed, abs=5e-6)  # printed to 5 decimals


@pytest.mark.parametrize(
    "fog, table, band, limits",
    [
        ("advection", FG1EXT, "lwir", (8.0, 12.0)),
        ("advection", FG1EXT, "mwir", (3.0, 5.0)),
        ("radiation", FG2EXT, "lwir", (8.0, 12.0)),
        ("radiation", FG2EXT, (3.5, 4.2), (3.5, 4.2)),
    ],
)
def test_fog_band_extinction_is_koschmieder_times_the_band_mean(fog, table, band, limits):
    for visibility_km in (0.1, 0.4, 0.8):
        expected = KOSCHMIEDER / visibility_km * band_ratio(table, *limits)
        assert float(fog_infrared_extinction_per_km(visibility_km, band, fog)) == pytest.approx(expected, rel=1e-9)


def test_fog_band_outside_the_table_is_refused_by_name():
    with pytest.raises(ParameterError, match="band"):
        fog_infrared_extinction_per_km(0.4, (1.0, 2.0))
    with pytest.raises(ParameterError, match="fog"):
        fog_extinction_ratio(10.0, "smoke")
    with pytest.raises(ParameterError, match="visibility_km"):
        fog_infrared_extinction_per_km(0.0)


SENSORS = {"mrtd": {"modality": "tir", "model": "mrtd"}, "netd": {"modality": "tir", "model": "netd"}}


def _scenario(environment: dict, convention: str = "physical", altitude_m: float = 0.0, sensors=SENSORS):
    return parse_scenario(
        {"convention": convention, "target": {"altitude_m": altitude_m}, "environment": environment, "sensors": sensors}
    )


@pytest.mark.parametrize("preset, visibility_km", [("fog_light", 0.8), ("fog_moderate", 0.4), ("fog_dense", 0.1)])
def test_fog_presets_add_the_fog_term_in_the_physical_convention_only(preset, visibility_km):
    physical = evaluate(_scenario({"preset": preset}))
    fog_db_km = DB_PER_NEPER * KOSCHMIEDER / visibility_km * lwir_advection_ratio()
    for name in SENSORS:
        terms = {t.name: t for t in physical[name].terms}
        assert float(terms["fog_extinction_db_km"].value) == pytest.approx(fog_db_km, rel=1e-9)
        assert "Shettle & Fenn 1979" in terms["fog_extinction_db_km"].source
        table_27 = _scenario({"preset": preset}).sensors[name].params["extinction_db_km"]
        assert float(terms["extinction_db_km"].value) == pytest.approx(table_27 + fog_db_km, rel=1e-12)
        assert "fog_path_fraction" not in terms
    paper = evaluate(_scenario({"preset": preset}, "paper"))
    clear = evaluate(_scenario({}, "paper"))
    for name in SENSORS:
        assert not {t.name for t in paper[name].terms} & {"fog_extinction_db_km", "fog_path_fraction"}
        assert float(paper[name].range_m) == float(clear[name].range_m)  # Table 27 as printed


def test_fog_type_picks_the_radiation_fogs_table_and_a_bad_one_is_refused_by_key():
    advection = evaluate(_scenario({"preset": "fog_moderate"}))
    radiation = evaluate(_scenario({"preset": "fog_moderate", "fog_type": "radiation"}))
    fog_db_km = DB_PER_NEPER * KOSCHMIEDER / 0.4 * band_ratio(FG2EXT, 8.0, 12.0)  # 0.300 of 3.912/V, in dB
    for name in SENSORS:
        terms = {t.name: float(t.value) for t in radiation[name].terms}
        assert terms["fog_extinction_db_km"] == pytest.approx(fog_db_km, rel=1e-9)
        assert float(radiation[name].range_m) >= float(advection[name].range_m)  # smaller drops: clearer LWIR
    assert float(radiation["netd"].range_m) > 2.0 * float(advection["netd"].range_m)  # 914 against 376 m
    with pytest.raises(ScenarioError, match="environment.fog_type"):
        _scenario({"preset": "fog_moderate", "fog_type": "steam"})


def test_netd_range_in_fog_solves_the_attenuated_snr():
    """In 400 m fog the NETD range R satisfies blob SNR(Delta T(R)) = SNR_req with tau = 10^(-a R / 10), a =
    Table 27 + the fog's: the Delta T there, worked by hand, meets the threshold."""
    from csuas.core.detection import blob_snr, target_pixels
    from csuas.core.radiometry import band_radiance, radiance_temperature

    sc = _scenario({"preset": "fog_moderate"})
    result = evaluate(sc)["netd"]
    r, a = float(result.range_m), float(result.term("extinction_db_km").value)
    terms = {t.name: float(np.asarray(t.value)) for t in result.terms}
    p, env, target = sc.sensors["netd"].params, sc.environment, sc.target
    from csuas.core.radiometry import graybody_apparent_temperature

    t_bg = float(graybody_apparent_temperature(env["emissivity_bg"], env["t_bg_k"], "lwir"))
    tau = 10 ** (-a * r / 1e4)
    path = (1 - tau) * band_radiance(env["temperature_k"], "lwir")
    dt = radiance_temperature(tau * band_radiance(t_bg + terms["delta_t0_k"], "lwir") + path, "lwir")
    dt -= radiance_temperature(tau * band_radiance(t_bg, "lwir") + path, "lwir")
    ifov = math.radians(p["hfov_deg"]) / p["n_h"]
    snr = blob_snr(abs(float(dt)), p["netd_mk"] / 1000.0, target_pixels(target["projected_area_m2"], ifov, r))
    assert float(snr) == pytest.approx(terms["required_snr"], rel=1e-6)
    assert r < 0.2 * float(evaluate(_scenario({}))["netd"].range_m)


def test_a_fog_layer_scales_the_fog_by_its_share_and_lwc_alone_adds_none():
    # a straight path from 2 m to 102 m spends (50 - 2) / 100 of its length below a 50 m top
    sc = _scenario({"fog_visibility_m": 200.0, "fog_top_m": 50.0}, altitude_m=100.0)
    full, layer = thermal_fog(sc, sc.sensors["mrtd"], "physical")
    assert float(full) == pytest.approx(DB_PER_NEPER * KOSCHMIEDER / 0.2 * lwir_advection_ratio(), rel=1e-9)
    fog, share = thermal_fog_db_km(sc, sc.sensors["mrtd"], "physical")
    assert float(share) == pytest.approx(0.48, rel=1e-12) and float(fog) == pytest.approx(0.48 * full, rel=1e-12)
    above = _scenario({"fog_visibility_m": 200.0, "fog_top_m": 1.0}, altitude_m=100.0)
    terms = {t.name: float(t.value) for t in evaluate(above)["mrtd"].terms}
    assert terms["fog_path_fraction"] == 0.0 and terms["fog_extinction_db_km"] == 0.0  # listed: the scene has fog
    radio_fog = _scenario({"lwc_g_m3": 0.2})  # a liquid water content alone: the radio bands' fog
    assert thermal_fog(radio_fog, radio_fog.sensors["mrtd"], "physical") == (0.0, None)


def test_mwir_sensor_takes_the_mwir_band_ratio():
    sc = _scenario({"preset": "fog_moderate"}, sensors={"t": {"modality": "tir", "model": "netd", "band": "mwir"}})
    fog = float(evaluate(sc)["t"].term("fog_extinction_db_km").value)
    assert fog == pytest.approx(DB_PER_NEPER * KOSCHMIEDER / 0.4 * band_ratio(FG1EXT, 3.0, 5.0), rel=1e-9)


def test_fog_terms_list_nothing_without_fog():
    assert tir.fog_terms(0.0) == [] and [t.name for t in tir.fog_terms(1.0)] == ["fog_extinction_db_km"]
    assert [t.name for t in tir.fog_terms(0.5, 0.5)] == ["fog_extinction_db_km", "fog_path_fraction"]


LAYERED = {"fog_visibility_m": 200.0, "fog_top_m": 50.0}
BOTH = {"eo": {"modality": "eo", "height_m": 2.0}, "mrtd": {"modality": "tir", "model": "mrtd"}}


def _render_terms(sc, name: str, view) -> dict:
    """The path terms a render of ``name`` seen from ``view`` lists (no Mitsuba: the render's analytic path)."""
    from csuas.render.imaging.modes import scenario_daylight, scenario_thermal_scene
    from csuas.render.imaging.path import eo_path, fog_layer_at, thermal_fog_at, tir_path

    spec = sc.sensors[name]
    if spec.modality == "eo":
        light = scenario_daylight(sc, spec)
        path = eo_path(
            view.range_m, light.visibility_km, 550.0, 1.0, 0.0, "physical", fog_layer_at(light.fog_layer, view)
        )
    else:
        scene = scenario_thermal_scene(sc, spec)
        fog = thermal_fog_at(scene, view)
        path = tir_path(view.range_m, scene.extinction_db_km + fog[0], 293.15, "lwir", 0.0, "physical", fog)
    return {t["name"]: t["value"] for t in path.terms}


@pytest.mark.parametrize("name", ["eo", "mrtd"])
def test_the_layers_share_follows_the_renders_geometry(name):
    """Sensor at 2 m under a 50 m top: looking up at 30 deg over 300 m the target is 150 m above it, (50 - 2) / 150
    of the path in fog; a level path is all in fog; looking down 10 deg from 2 m the path stays in the fog."""
    from csuas.render.imaging.records import View

    sc = _scenario(LAYERED, altitude_m=100.0, sensors=BOTH)
    full = float(thermal_fog(sc, sc.sensors["mrtd"], "physical")[0])
    for elevation, share in ((-30.0, 48.0 / 150.0), (0.0, 1.0), (10.0, 1.0), (-90.0, 48.0 / 300.0)):
        terms = _render_terms(sc, name, View(300.0, 0.0, elevation))
        assert terms["fog_path_fraction"] == pytest.approx(share, rel=1e-12), elevation
        if name == "mrtd":
            assert terms["fog_extinction_db_km"] == pytest.approx(share * full, rel=1e-12)


@pytest.mark.parametrize("name", ["eo", "mrtd"])
def test_a_render_with_the_scenarios_geometry_lists_the_ranges_terms(name):
    """The target 100 m above the sensor at 300 m: elevation -asin(1/3) gives the share csuas range applies."""
    from csuas.render.imaging.records import View

    sc = _scenario(LAYERED, altitude_m=100.0, sensors=BOTH)
    expected = {t.name: float(np.asarray(t.value)) for t in evaluate(sc)[name].terms}
    rendered = _render_terms(sc, name, View(300.0, 0.0, -math.degrees(math.asin(100.0 / 300.0))))
    assert expected["fog_path_fraction"] == pytest.approx(0.48, rel=1e-12)
    for term in ("fog_path_fraction", "fog_extinction_db_km", "extinction_db_km", "kruse_extinction"):
        if term in expected:
            assert rendered[term] == pytest.approx(expected[term], rel=1e-12), term


@pytest.mark.slow
@pytest.mark.parametrize("mode", ["eo", "tir"])
def test_render_elevation_decides_the_layers_share(mode, tmp_path, capsys):
    """``csuas render --elevation-deg``: at -asin(100/300) the share is the range's 0.48, level it is 1."""
    import json

    from csuas import cli

    scenario = tmp_path / "layer.toml"
    scenario.write_text(
        'name = "layer"\nconvention = "physical"\n[target]\naltitude_m = 100.0\n[environment]\n'
        'fog_visibility_m = 200.0\nfog_top_m = 50.0\n[sensors.eo]\nmodality = "eo"\nheight_m = 2.0\n'
        '[sensors.t]\nmodality = "tir"\nmodel = "mrtd"\n'
    )
    upward = -math.degrees(math.asin(100.0 / 300.0))
    argv = ["render", mode, str(scenario), "--range-m", "300", "--quality", "draft", "--quiet", "--json"]
    assert cli.main([*argv, "--elevation-deg", repr(upward), "0"]) == 0
    rows = json.loads(capsys.readouterr().out)["results"]
    shares = [next(t["value"] for t in row["terms"] if t["name"] == "fog_path_fraction") for row in rows]
    assert shares[0] == pytest.approx(0.48, rel=1e-12) and shares[1] == 1.0
    name = "eo" if mode == "eo" else "t"
    ranged = {t.name: float(np.asarray(t.value)) for t in evaluate(load_scenario(str(scenario)))[name].terms}
    assert shares[0] == pytest.approx(ranged["fog_path_fraction"], rel=1e-12)


def test_the_clear_part_and_the_layers_geometry():
    from csuas.core.ranges import fog_layer_geometry, thermal_extinction_no_fog_db_km

    sc = _scenario({"fog_visibility_m": 200.0, "fog_top_m": 50.0, "rain_rate_mm_h": 6.0}, sensors=BOTH)
    clear, rain = thermal_extinction_no_fog_db_km(sc, sc.sensors["mrtd"], "physical")
    assert float(rain) == pytest.approx(DB_PER_NEPER * math.pi * 8000.0 / (4.1 * 6.0**-0.21) ** 3 * 1e-3, rel=1e-9)
    assert float(clear) == pytest.approx(sc.sensors["mrtd"].params["extinction_db_km"] + float(rain), rel=1e-12)
    assert fog_layer_geometry(sc, sc.sensors["eo"]) == (2.0, 50.0, 10.0)  # height_m, top, Table 24's visibility
    assert fog_layer_geometry(_scenario(LAYERED), _scenario(LAYERED).sensors["mrtd"])[0] == 2.0  # mast-less
    assert fog_layer_geometry(_scenario({}), _scenario({}).sensors["mrtd"]) is None
