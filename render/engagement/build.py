"""An engagement from its spec: the site's terrain and sensors, the scenario's models, the drone's path, the birds.

:func:`build` turns a validated spec (:mod:`csuas.render.engagement.spec`) into the
:class:`~csuas.render.engagement.simulate.Engagement` every run shares; :func:`load_engagement` reads a
spec (an embedded name or a file, its site and scenario files beside it) and builds it. ``csuas engage``,
its benchmark and the ``engage`` sweep job (:mod:`csuas.sweep.job_engage`) read engagements through here.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import tomllib

from csuas.base.errors import ParameterError, raise_all
from csuas.base.fileio import read_spec
from csuas.core.coverage import POINTING, SitedSensor
from csuas.core.scenario import load_scenario, parse_scenario
from csuas.defaults import engagement_path, load_birds, load_clutter, scenario_path, site_path
from csuas.render.engagement.sensors import ENGAGED_MODALITIES, LOOK_DEFAULTS, LookSettings, SensorModel, Terrain
from csuas.render.engagement.simulate import BirdSettings, DronePath, Engagement
from csuas.render.engagement.spec import EngageSpec, parse_spec
from csuas.render.rcs.drone_or_bird import ClassifierSettings
from csuas.render.site import load_dem, sensor_xy, validated_site


def _scenario(spec, site: dict, base: Path | None):
    """The scenario of the engagement: the spec's (name, file beside the spec or inline table) or the site's."""
    source = spec.scenario if spec.scenario is not None else site.get("scenario", "default")
    if isinstance(source, dict):
        data = dict(source)
    else:
        path = Path(source)
        if base is not None and not path.is_absolute() and (base / path).is_file():
            path = base / path
        if not path.is_file():
            path = Path(str(scenario_path(str(source))))
        if not path.is_file():
            return load_scenario(source)  # its own error, naming the scenario
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    data["target"] = {**data.get("target", {}), "preset": spec.drone.target}
    return parse_scenario(data, str(data.get("name", "scenario")))


def build(spec, spec_dir: Path | None):
    """The :class:`csuas.render.engagement.simulate.Engagement` of a validated spec (site, scenario, sensors)."""
    site_source = spec.site
    if spec_dir is not None and (spec_dir / site_source).is_file():
        site_source = str(spec_dir / site_source)
    site = read_spec(site_source, site_path, "site")
    scenario = _scenario(spec, site, spec_dir)
    chosen = spec.sensors or list(site.get("sensors", {}))
    missing = [
        ParameterError("sensors", n, "sensors of the site: " + ", ".join(site.get("sensors", {})))
        for n in chosen
        if n not in site.get("sensors", {})
    ]
    raise_all(missing)
    site = {**site, "sensors": {n: site["sensors"][n] for n in chosen}}
    site.pop("radio_map", None)
    site.pop("fusion_k", None)
    checked = validated_site(site, scenario)
    errors = [
        ParameterError(
            f"sensors.{n}",
            scenario.sensors[n].modality,
            "a modality engage simulates: " + ", ".join(ENGAGED_MODALITIES),
        )
        for n in chosen
        if scenario.sensors[n].modality not in ENGAGED_MODALITIES
    ]
    errors += [
        ParameterError(f"looks.{n}", n, "a sensor taking part: " + ", ".join(chosen))
        for n in spec.looks
        if n not in chosen
    ]
    raise_all(errors)
    site_file = Path(site_source)
    dem, transform, crs, cell = load_dem(checked.dem, site_file if site_file.is_file() else None)
    terrain = Terrain(dem, cell, float(transform.c), float(transform.f))
    waypoints = np.array(spec.drone.waypoints, float)
    rows, cols = terrain.rowcol(waypoints[:, 0], waypoints[:, 1])
    outside = ~((rows >= 0) & (rows <= dem.shape[0] - 1) & (cols >= 0) & (cols <= dem.shape[1] - 1))
    raise_all(
        [
            ParameterError(f"drone.waypoints[{i}]", spec.drone.waypoints[i], "a point inside the DEM")
            for i in np.flatnonzero(outside)
        ]
    )
    gamma = load_clutter()["gamma_db"]
    sensors = {}
    for name in chosen:
        table = checked.sensors[name]
        row, col = terrain.rowcol(*sensor_xy(table, crs))
        pointing = {key: float(getattr(table, key)) for key in POINTING}
        sited = SitedSensor(name, float(row), float(col), float(table.mast_m), **pointing)
        modality = scenario.sensors[name].modality
        given = spec.looks[name].model_dump(exclude_none=True) if name in spec.looks else {}
        settings = LookSettings(**{**LOOK_DEFAULTS[modality], **given})
        sensors[name] = SensorModel(scenario, sited, terrain, settings, gamma[settings.land_cover])
    birds = BirdSettings(spec.confusers.birds_per_km2, tuple(spec.confusers.bird_classes), spec.confusers.radius_m)
    path = DronePath(waypoints, spec.drone.speed_m_s)
    c = spec.classification
    classifier = ClassifierSettings(c.prf_hz, c.dwell_s, c.elevation_deg) if c.micro_doppler else None
    return Engagement(
        terrain,
        sensors,
        path,
        birds,
        tuple(spec.tracker.confirm),
        spec.tracker.delete_after_misses,
        spec.seed,
        load_birds(),
        scenario.swarm,
        classifier.check("classification") if classifier else None,
    )


def load_engagement(source) -> tuple[EngageSpec, Engagement]:
    """The validated spec and the engagement of an engagement spec file or embedded name (``example``).

    Raises
    ------
    ParameterError
        Every mistake of the spec, its site and its scenario at once (exit 2 on the command line).
    """
    spec = parse_spec(read_spec(source, engagement_path, "engagement spec"))
    path = Path(str(source))
    return spec, build(spec, path.parent if path.is_file() else None)
