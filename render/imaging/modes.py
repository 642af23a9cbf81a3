"""Scenario-driven EO and thermal renders behind ``csuas render eo|tir`` (docs/command-line.md).

A *render mode* is a callable ``mode(scenario, request) -> list of dict`` returning one JSON-ready
result per range (contract and options: :class:`csuas.render.request.RenderRequest`); the EO mode
also reads the request's ``exposure`` of the preview ("scene": a camera set for clear daylight, so
night looks dark; "auto": the brightest pixel white).
File names and EXR metadata: :mod:`csuas.render.files`.

``atmosphere="auto"`` applies the path wherever ``csuas range`` applies one to the same scenario under
the same convention (the scenario's, or the request's ``convention``; docs/scenarios.md (effects)): for EO
always (the EO range model applies Kruse's extinction at the optical visibility, 10 km clear air by
default); for thermal with the MRTD and NETD models (Table 27's attenuation), never with the Johnson
model (its range has no path, whatever the weather). EO then uses Koschmieder with the optical
visibility (fog visibility in fog), averaged over a fog layer of given top on the render's own slant path
(its range and elevation, the sensor at its ``height_m``), plus the rain's extinction (physical); thermal the
sensor's ``extinction_db_km`` plus the rain's and the fog's (physical, the fog's share of the render's path
alike), with path radiance at the environment's ``temperature_k``. The extinction terms come from
the core functions the range models use (:func:`csuas.core.ranges.eo_path_inputs`,
:func:`csuas.core.eo.path_extinction`, :func:`csuas.core.ranges.thermal_path`), so a scenario's weather
changes both or neither (tests/test_render_weather_terms.py).

The request's ``atmosphere_method`` (EO only; ``csuas render`` asks ``auto``) traces the path through Mitsuba's
participating medium instead where the analytic path is an approximation and the medium the more accurate at the
requested quality (:func:`eo_method`, :mod:`csuas.render.imaging.medium_choice`,
:mod:`csuas.render.imaging.medium_path`); :func:`eo_estimate` is the cost of the renders before any.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from csuas.base.errors import ParameterError
from csuas.core.ranges import (
    eo_path_inputs,
    fog_layer_geometry,
    thermal_extinction_no_fog_db_km,
    thermal_fog,
    thermal_path,
)
from csuas.render.imaging.path import fog_top_above_target_m
from csuas.render.imaging.records import (
    Daylight,
    EoSensor,
    FogLayer,
    RenderSettings,
    ThermalScene,
    ThermalSensor,
    View,
)
from csuas.render.request import ATMOSPHERE_CHOICES, RenderRequest


def _sensor(scenario, modality: str, name):
    if name is not None:
        if name not in scenario.sensors or scenario.sensors[name].modality != modality:
            found = [n for n, s in scenario.sensors.items() if s.modality == modality]
            raise ParameterError("sensor", name, f"a {modality} sensor of the scenario: {', '.join(found) or 'none'}")
        return scenario.sensors[name]
    for spec in scenario.sensors.values():
        if spec.modality == modality:
            return spec
    raise ParameterError("sensor", None, f"a [sensors.NAME] with modality = '{modality}' in scenario {scenario.name!r}")


def atmosphere_on(scenario, atmosphere: str, spec, convention: str | None = None) -> bool:
    """Whether a render applies the path: ``on``, ``off``, or ``auto`` = wherever ``csuas range`` applies one.

    ``auto``: an EO sensor always (its range applies Kruse's extinction at the optical visibility); a thermal
    sensor where its range lists a path (:func:`csuas.core.ranges.thermal_path`: the MRTD and NETD models with an
    attenuation, not the Johnson model, which no weather changes).
    """
    if atmosphere not in ATMOSPHERE_CHOICES:
        raise ParameterError("atmosphere", atmosphere, ", ".join(ATMOSPHERE_CHOICES))
    if atmosphere == "auto":
        if spec.modality == "eo":
            return True
        return thermal_path(scenario, spec, convention or scenario.convention)[0] is not None
    return atmosphere == "on"


def scenario_daylight(scenario, spec, convention: str | None = None) -> Daylight:
    """Light and air of a scenario's EO render: its illuminance and the path ``csuas range`` applies to ``spec``.

    ``convention``: the scenario's unless given. The path's inputs are :func:`csuas.core.ranges.eo_path_inputs`'
    (the optical visibility, the physical convention's rain and layered fog on the sensor's slant path).
    """
    conv = convention or scenario.convention
    path = eo_path_inputs(scenario, spec, conv)
    return Daylight(
        illuminance_lx=scenario.environment["illuminance_lx"],
        visibility_km=path["visibility_km"],
        rain_extinction_per_km=float(path["rain_extinction_per_km"]),
        convention=conv,
        fog_layer=None if path["fog_layer"] is None else scenario_fog_layer(scenario, spec),
    )


def scenario_fog_layer(scenario, spec) -> FogLayer | None:
    """The scenario's fog layer as a render takes it (:func:`csuas.core.ranges.fog_layer_geometry`): the
    render's own range and elevation decide its share of the path (:func:`csuas.render.imaging.path.fog_layer_at`)."""
    geometry = fog_layer_geometry(scenario, spec)
    return None if geometry is None else FogLayer(*(float(v) for v in geometry))


def scenario_thermal_scene(scenario, spec, convention: str | None = None) -> ThermalScene:
    """Background and air of a scenario's thermal render: the path attenuation ``csuas range`` applies.

    ``convention``: the scenario's unless given (the physical convention adds the rain's attenuation, and the
    fog's, :func:`csuas.core.ranges.thermal_fog`, on the render's own path through its layer).
    """

    env, conv = scenario.environment, convention or scenario.convention
    extinction, rain = thermal_extinction_no_fog_db_km(scenario, spec, conv)
    fog, layer = thermal_fog(scenario, spec, conv)
    return ThermalScene(
        t_bg_k=env["t_bg_k"],
        emissivity_bg=env["emissivity_bg"],
        surroundings_k=env["temperature_k"],
        extinction_db_km=float(extinction),
        air_temperature_k=env["temperature_k"],
        rain_db_km=float(rain),
        convention=conv,
        fog_db_km=float(fog),
        fog_layer=None if layer is None else scenario_fog_layer(scenario, spec),
    )


def _files(result, scenario, spec, request: RenderRequest, exposure: str = "scene") -> list:
    """The EXR and PNG of one range's render in the request's ``out_dir`` (none without it)."""
    out_dir, quality, seed = request.out_dir, request.quality, request.seed
    if out_dir is None:
        return []
    from csuas.render.files import file_stem
    from csuas.render.imaging.output import write_images

    stem = file_stem(
        scenario.name,
        spec.name,
        result.modality,
        result.range_m,
        result.azimuth_deg,
        result.elevation_deg,
        quality,
        seed,
    )
    meta = {
        "target": scenario.target_preset,
        "scenario": scenario.name,
        "sensor": spec.name,
        "quality": quality,
        "seed": seed,
        "frame_width_px": spec.params["n_h"],
        "frame_height_px": spec.params["n_v"],
    }
    return write_images(result, Path(out_dir), stem, meta, exposure=exposure)


def _swarm_target(scenario, request: RenderRequest):
    """The target a render traces: the preset, or the swarm's drones (their parts per drone, and all of them)."""
    if scenario.swarm is None:
        return None, scenario.target_preset
    from csuas.render.imaging.swarm import formation_members

    members = formation_members(scenario.target_preset, scenario.swarm, request.azimuth_deg, request.elevation_deg)
    return members, [part for parts in members for part in parts]


def _swarm_row(row: dict, members, view: View, res, spec) -> None:
    """A swarm's drones and blobs in a render's row (:func:`csuas.render.imaging.swarm.swarm_summary`)."""
    if members is not None:
        from csuas.render.imaging.swarm import swarm_summary

        row["swarm"] = swarm_summary(members, view, res, int(spec.params["n_h"]), int(spec.params["n_v"]))


#: Conditions of a scenario that make a path worth a medium (:attr:`csuas.core.scenario.Scenario.effects`).
WEATHER = frozenset({"fog", "fog_layer", "rain", "haze"})


def eo_method(scenario, spec, request: RenderRequest, view: View, light: Daylight, atmosphere: bool):
    """The path of one EO render: :func:`csuas.render.imaging.medium_choice.choose_method` on the request's
    ``atmosphere_method`` (``analytic`` where the request has none), target and quality (``auto`` compares the
    two paths' errors at that quality)."""
    from csuas.render.imaging.medium_choice import choose_method

    air = light if atmosphere else replace(light, visibility_km=None)
    camera = EoSensor.from_params(spec.params)
    top = fog_top_above_target_m(light.fog_layer, view)
    weather = bool(scenario.effects & WEATHER)
    _, target = _swarm_target(scenario, request)
    return choose_method(request.atmosphere_method, air, view, camera, top, weather, target, request.quality)


def eo_scenario(scenario, request: RenderRequest) -> list:
    """Render the scenario's EO sensor at each range of the request (mode ``eo``), through the participating
    medium where :func:`eo_method` chooses it (:func:`csuas.render.imaging.medium_path.render_eo_medium`)."""
    from csuas.render.imaging.eo import render_eo
    from csuas.render.imaging.medium_path import render_eo_medium

    spec = _sensor(scenario, "eo", request.sensor)
    camera = EoSensor.from_params(spec.params)
    light = scenario_daylight(scenario, spec, request.convention)
    settings = RenderSettings(quality=request.quality, seed=request.seed, progress=request.progress)
    members, target = _swarm_target(scenario, request)
    atmosphere = atmosphere_on(scenario, request.atmosphere, spec, request.convention)
    out = []
    for r in request.ranges_m:
        view = View(r, request.azimuth_deg, request.elevation_deg)
        choice = eo_method(scenario, spec, request, view, light, atmosphere)
        if choice.method == "medium":
            res, method = render_eo_medium(target, view, camera, light, choice, settings)
        else:
            res, method = render_eo(target, view, camera, light, atmosphere=atmosphere, settings=settings), None
        row = res.summary()
        row.update(sensor=spec.name, convention=light.convention, atmosphere_method=method or choice.as_dict())
        row.update(files=_files(res, scenario, spec, request, request.exposure))
        _swarm_row(row, members, view, res, spec)
        out.append(row)
    return out


def eo_estimate(scenario, request: RenderRequest):
    """Time and peak memory of :func:`eo_scenario` (a :class:`csuas.base.cost.Estimate`), before any render:
    the analytic windows, and the medium's traces where :func:`eo_method` chooses it
    (:func:`csuas.render.imaging.medium_choice.render_estimate`)."""
    from csuas.render.imaging.medium_choice import render_estimate

    spec = _sensor(scenario, "eo", request.sensor)
    light = scenario_daylight(scenario, spec, request.convention)
    atmosphere = atmosphere_on(scenario, request.atmosphere, spec, request.convention)
    _, target = _swarm_target(scenario, request)
    renders = []
    for r in request.ranges_m:
        view = View(r, request.azimuth_deg, request.elevation_deg)
        renders.append((view, eo_method(scenario, spec, request, view, light, atmosphere)))
    return render_estimate(target, EoSensor.from_params(spec.params), renders, request.quality)


def tir_scenario(scenario, request: RenderRequest) -> list:
    """Render the scenario's thermal sensor at each range of the request (mode ``tir``)."""
    from csuas.render.imaging.tir import render_tir

    spec = _sensor(scenario, "tir", request.sensor)
    target = scenario.target
    camera = ThermalSensor.from_params(spec.params)
    thermal_scene = scenario_thermal_scene(scenario, spec, request.convention)
    settings = RenderSettings(quality=request.quality, seed=request.seed, progress=request.progress)
    members, swarm_target = _swarm_target(scenario, request)
    out = []
    for r in request.ranges_m:
        view = View(r, request.azimuth_deg, request.elevation_deg)
        res = render_tir(
            swarm_target,
            view,
            camera,
            thermal_scene,
            atmosphere=atmosphere_on(scenario, request.atmosphere, spec, request.convention),
            reflected_surroundings=True,
            linear_reference=(target["emissivity_suas"], target["t_suas_k"]),
            settings=settings,
        )
        row = res.summary()
        row.update(sensor=spec.name, convention=thermal_scene.convention, files=_files(res, scenario, spec, request))
        _swarm_row(row, members, view, res, spec)
        out.append(row)
    return out
