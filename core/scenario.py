"""Scenario files (docs/scenarios.md): TOML in, validated and fully resolved parameters out.

A scenario names a target, an environment and any number of sensors. Each
section may start from a preset and override any canonical parameter
(docs/scenarios.md). Environment class names of Tables 11, 14, 16, 18, 27 and 30 are
accepted in place of numbers, either under the parameter's own name
(``rain_rate_mm_h = "moderate"``) or under a short alias (``rain = "moderate"``).

Every error names the key, the value and what is allowed.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import NoReturn

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

import numpy as np

from csuas.base.errors import InputErrors, ParameterError, ScenarioError, plain, raise_all
from csuas.base.schema import validate
from csuas.core import johnson
from csuas.core.result import CONVENTIONS
from csuas.core.swarm import Formation, line_formation
from csuas.defaults import load_parameters, load_presets, load_tables, scenario_path
from csuas.defaults.scenario_schema import ENVIRONMENT_ALIASES, MAX_SWARM, checked_values, scenario_schema
from csuas.defaults.scenario_schema import TAGS as SCHEMA_TAGS

#: Keys of a scenario file (its schema: :func:`csuas.defaults.scenario_schema.scenario_schema`).
TOP_LEVEL_KEYS = ("name", "description", "convention", "target", "environment", "sensors")


@dataclass
class SensorSpec:
    """One sensor of a scenario with its resolved parameters.

    Attributes
    ----------
    name : str
        The sensor's key in the scenario (``[sensors.<name>]``).
    modality : str
        ``eo``, ``tir``, ``acoustic``, ``rf``, ``radar`` or ``lidar``.
    preset : str
        ``default`` or a named system of Tables 23, 26, 29, 34, 40, 46.
    params : dict
        Every parameter of the modality (defaults, preset, overrides, derived).
    explicit : set of str
        Parameters given by the scenario or the preset (not defaults).
    origin : dict
        ``{parameter: "scenario" | "preset NAME" | "derived (...)"}`` for every parameter not
        at its default; the others come from ``defaults/parameters.toml`` (:func:`provenance`).
    """

    name: str
    modality: str
    preset: str
    params: dict
    explicit: set = field(default_factory=set)
    origin: dict = field(default_factory=dict)


@dataclass
class Scenario:
    """A resolved scenario.

    Attributes
    ----------
    name, convention : str
    target, environment : dict
        Resolved canonical parameters.
    target_preset, environment_preset : str
    sensors : dict of SensorSpec
    explicit : dict
        ``{"target": set, "environment": set}`` of parameters set explicitly.
    origin : dict
        ``{"target": {...}, "environment": {...}}``, as :attr:`SensorSpec.origin`.
    warnings : list of str
        Plausibility warnings (likely unit mistakes); not errors.
    """

    name: str
    convention: str
    target: dict
    target_preset: str
    environment: dict
    environment_preset: str
    sensors: dict
    explicit: dict
    origin: dict = field(default_factory=lambda: {"target": {}, "environment": {}})
    warnings: list = field(default_factory=list)
    swarm: Formation | None = None

    @property
    def effects(self) -> frozenset:
        """Conditions present in the scene: subset of {rain, fog, fog_layer, haze, wind, night}.

        ``haze`` means a visibility set by the scenario (not the Table 24
        default); ``wind`` a speed of at least 1 m/s (Table 31's range).
        """
        env = self.environment
        found = set()
        if env["rain_rate_mm_h"] > 0:
            found.add("rain")
        if env.get("fog_visibility_m") is not None or env["lwc_g_m3"] > 0:
            found.add("fog")
        if env.get("fog_top_m") is not None:
            found.add("fog_layer")
        if "visibility_km" in self.explicit["environment"]:
            found.add("haze")
        if env["wind_speed_m_s"] >= 1.0:
            found.add("wind")
        if env["illuminance_lx"] < 400.0:
            found.add("night")
        return frozenset(found)

    @property
    def optical_visibility_km(self) -> float:
        """Visibility for optical extinction [km]: the fog visibility in fog, else ``visibility_km``."""
        fog_v = self.environment.get("fog_visibility_m")
        return fog_v / 1000.0 if fog_v is not None else self.environment["visibility_km"]


def _fail(key: str, value, allowed: str) -> NoReturn:
    raise ScenarioError(f"{key} = {plain(value)} is invalid; allowed: {allowed}")


def check_value(key: str, spec: dict, value):
    """Validate one value against its parameter spec (its schema field,
    :func:`csuas.defaults.scenario_schema.parameter_type`); return it (as float/int/str/list)."""
    try:
        return checked_values(key, spec, [value], indexed=False)[0]
    except ParameterError as exc:
        raise ScenarioError(str(exc)) from None


def _class_value(param: str, value):
    """A class name's value (Tables 11, 14, 16, 18, 27, 30); a number as it is."""
    classes = load_tables()["classes"].get(param)
    return classes[value] if classes is not None and isinstance(value, str) else value


def _apply(section: str, values: dict, given: dict, explicit: set, origin: dict, label: str) -> None:
    """Apply validated ``given`` values (aliases and class names resolved), noting where each came from."""
    registry = load_parameters()[section]
    for key, raw in given.items():
        param = ENVIRONMENT_ALIASES.get(key, key) if section == "environment" else key
        if (
            section == "environment"
            and param == "fog_visibility_m"
            and isinstance(raw, str)
            and "lwc_g_m3" not in given
        ):
            # A fog class also sets its liquid water content (Table 16) unless given.
            values["lwc_g_m3"] = load_tables()["classes"]["lwc_g_m3"][raw]
            explicit.add("lwc_g_m3")
            origin["lwc_g_m3"] = f"{label} (fog class {raw!r}, Table 16)"
        values[param] = _class_value(param, raw)
        explicit.add(param)
        origin[param] = (
            label
            if not isinstance(raw, str) or "choices" in registry[param]
            else f"{label} (class {raw!r}, {load_tables()['classes'][param]['source']})"
        )


def _given(table) -> dict:
    """The values a validated table gives, in the file's order (``preset`` and ``modality`` aside)."""
    return {k: getattr(table, k) for k in table.model_fields_set if k not in ("preset", "modality", "swarm")}


def swarm_formation(swarm, key: str = "target.swarm") -> Formation | None:
    """A validated swarm table (:class:`csuas.defaults.scenario_schema.SwarmTable`, or None) resolved: a line
    of ``count`` drones ``spacing_m`` apart, or ``offsets_m``; ``key`` names it in the error."""
    if swarm is None:
        return None
    line = (swarm.count, swarm.spacing_m)
    if swarm.offsets_m is not None and line == (None, None):
        return Formation(np.asarray(swarm.offsets_m, dtype=float), "offsets")
    if swarm.offsets_m is None and None not in line:
        return line_formation(swarm.count, swarm.spacing_m)
    given = {k: v for k, v in zip(("count", "spacing_m", "offsets_m"), (*line, swarm.offsets_m)) if v is not None}
    raise ScenarioError(f"{key} = {plain(given)} is invalid; allowed: count and spacing_m together, or offsets_m alone")


#: The swarm keys a sweep axis or a sensitivity bound may vary (a line formation's, docs/scenarios.md "Swarms").
SWARM_KEYS = ("target.swarm.count", "target.swarm.spacing_m")


def with_swarm_value(scenario: Scenario, key: str, value, label: str | None = None) -> Scenario:
    """A copy of ``scenario`` whose line formation has ``target.swarm.count`` or ``target.swarm.spacing_m`` set
    to ``value`` (the other kept); ``label`` names the value in the error (default ``key``).

    Raises
    ------
    ParameterError
        When ``key`` is not one of :data:`SWARM_KEYS`, the scenario has no ``target.swarm`` of ``count`` and
        ``spacing_m`` (none, or ``offsets_m``: no count or spacing to vary), or the value is out of range
        (a whole number 2 to MAX_SWARM drones; a spacing > 0 and <= 1e5 m, finite).
    """
    label = label or key
    formation = scenario.swarm
    if key not in SWARM_KEYS:
        raise ParameterError(label, value, "one of " + ", ".join(SWARM_KEYS))
    if formation is None or formation.kind != "line":
        has = "no target.swarm" if formation is None else "target.swarm.offsets_m"
        allowed = f"a scenario whose target.swarm is {{count, spacing_m}} (this one has {has})"
        raise ParameterError(label, value, allowed)
    count = formation.count
    spacing = formation.spacing_m
    number = float(value) if isinstance(value, (int, float, np.number)) and not isinstance(value, bool) else None
    if key == SWARM_KEYS[0]:
        if number is None or not number.is_integer() or not 2 <= number <= MAX_SWARM:
            raise ParameterError(label, value, f"a whole number of drones, 2 to {MAX_SWARM}")
        count = int(number)
    else:
        if number is None or not (math.isfinite(number) and 0.0 < number <= 1e5):
            raise ParameterError(label, value, "a spacing > 0 and <= 100000 [m]")
        spacing = number
    return replace(scenario, swarm=line_formation(count, spacing))


def _preset(kind: str, name: str, modality: str | None = None) -> dict:
    """The values a preset sets (``default``: none); names are checked by the schema."""
    if name == "default":
        return {}
    presets = load_presets()[kind]
    table = presets[modality][name] if modality is not None else presets[name]
    return {k: v for k, v in table.items() if k not in ("description", "source")}


def _defaults(section: str) -> dict:
    return {k: v.get("value") for k, v in load_parameters()[section].items()}


def johnson_derived(params: dict, explicit) -> dict:
    """An imaging sensor's values derived from others unless given: lp_task from task (Table 20),
    n_TTPF from p_desired (Table 21).

    Parameters
    ----------
    params : dict
        The sensor's resolved parameters (``task`` and ``p_desired`` read).
    explicit : set of str
        Parameters the scenario gives; those are never derived.
    """
    derived = {}
    if "lp_task" not in explicit:
        derived["lp_task"] = johnson.line_pairs(params["task"])
    if "n_ttpf" not in explicit:
        derived["n_ttpf"] = float(johnson.n_ttpf(params["p_desired"]))
    return derived


def _resolve_sensor(name: str, table) -> SensorSpec:
    """A validated sensor table resolved: defaults, then its preset, then the file's values, then derived ones."""
    modality, preset = table.modality, table.preset
    values, explicit, origin = _defaults(modality), set[str](), dict[str, str]()
    _apply(modality, values, _preset("sensor", preset, modality), explicit, origin, f"preset {preset}")
    _apply(modality, values, _given(table), explicit, origin, "scenario")
    if "lp_task" in values:  # an imaging sensor, ranged by the Johnson criteria (eo, tir)
        _derive_imaging(name, values, explicit, origin)
    if modality == "radar":
        _check_radar(name, values, explicit)
    return SensorSpec(name, modality, preset, values, explicit, origin)


def _derive_imaging(name: str, values: dict, explicit: set, origin: dict) -> None:
    derived = johnson_derived(values, explicit)
    values.update(derived)
    if "lp_task" in derived:
        origin["lp_task"] = f"derived from task = {values['task']!r} (Table 20)"
    if "n_ttpf" in derived:
        origin["n_ttpf"] = f"derived from p_desired = {values['p_desired']:g} (Table 21)"
    frequencies, k = values.get("mrtd_frequency_cy_mrad"), values.get("mrtd_k")
    if frequencies is not None and not np.all(np.diff(np.atleast_1d(frequencies)) > 0):
        _fail(f"sensors.{name}.mrtd_frequency_cy_mrad", frequencies, "strictly increasing frequencies [cy/mrad]")
    lengths = {len(np.atleast_1d(v)) for v in (frequencies, k) if v is not None}
    if (frequencies is None) != (k is None) or len(lengths) > 1:
        _fail(f"sensors.{name}.mrtd_k", k, "given together with mrtd_frequency_cy_mrad (same length)")


def _check_radar(name: str, values: dict, explicit: set) -> None:
    if {"wavelength_m", "frequency_ghz"} <= explicit:
        _fail(
            f"sensors.{name}.frequency_ghz", values["frequency_ghz"], "either wavelength_m or frequency_ghz, not both"
        )
    if values["model"] == "range_equation" and values.get("p_rx_min_w") is None:
        _fail(f"sensors.{name}.p_rx_min_w", None, "a power > 0 [W] when model = range_equation")


def _validated(data: dict):
    """The scenario's schema validated; every mistake as a :class:`ScenarioError`, all at once."""
    try:
        return validate(scenario_schema(CONVENTIONS), data, tags=SCHEMA_TAGS)
    except (ParameterError, InputErrors) as exc:
        raise_all(ScenarioError(str(e)) for e in getattr(exc, "errors", [exc]))
        raise  # pragma: no cover (raise_all raised)


def parse_scenario(data: dict, name: str = "scenario") -> Scenario:
    """Resolve a scenario given as a dict (the parsed TOML), after its schema
    (:func:`csuas.defaults.scenario_schema.scenario_schema`).

    Raises
    ------
    ScenarioError
        Unknown key, wrong type, out-of-range value, unknown preset or class (:class:`InputErrors` of them
        when several), or values that do not go together.
    """
    model = _validated(data)
    sections, explicit, origin = {}, {}, {}
    for section in ("target", "environment"):
        table = getattr(model, section)
        preset = table.preset
        values, given, where = _defaults(section), set[str](), dict[str, str]()
        _apply(section, values, _preset(section, preset), given, where, f"preset {preset}")
        _apply(section, values, _given(table), given, where, "scenario")
        sections[section], explicit[section], origin[section] = (values, preset), given, where
    sensors, errors = {}, []
    environment = sections["environment"][0]
    if environment.get("fog_top_m") is not None and environment.get("fog_visibility_m") is None:
        errors.append(
            ScenarioError(
                f"environment.fog_top_m = {plain(environment['fog_top_m'])} is invalid; allowed: "
                "given with environment.fog_visibility_m (the fog it tops)"
            )
        )
    for key, table in model.sensors.items():
        try:
            sensors[key] = _resolve_sensor(key, table)
        except ScenarioError as exc:
            errors.append(exc)
    formation = None
    try:
        formation = swarm_formation(model.target.swarm)
    except ScenarioError as exc:
        errors.append(exc)
    raise_all(errors)
    warnings = [w for spec in sensors.values() for w in plausibility_warnings(spec)]
    return Scenario(
        model.name if model.name is not None else name,
        model.convention,
        sections["target"][0],
        sections["target"][1],
        sections["environment"][0],
        sections["environment"][1],
        sensors,
        explicit,
        origin,
        warnings,
        formation,
    )


def plausibility_warnings(sensor: SensorSpec) -> list[str]:
    """Likely unit mistakes of an imaging sensor: a field of view that does not fit its detector.

    The fields of view of a pinhole camera with square pixels satisfy
    tan(HFOV/2) / tan(VFOV/2) = N_H / N_V (Eq. 15 per axis). A ratio off by more than a factor of two
    most often means degrees and radians were mixed; a field of view below 0.2 deg beside one above
    2 deg is named as the likely radian. One warning per sensor.
    """
    p = sensor.params
    if not {"hfov_deg", "vfov_deg", "n_h", "n_v"} <= p.keys():  # not an imaging sensor
        return []
    h, v = p["hfov_deg"], p["vfov_deg"]
    optical = math.tan(math.radians(min(h, 179.0)) / 2) / math.tan(math.radians(min(v, 179.0)) / 2)
    pixels = p["n_h"] / p["n_v"]
    if 0.5 <= optical / pixels <= 2.0:
        return []
    suspects = [
        f" {key} = {value:g} looks like radians ({value:g} rad = {math.degrees(value):.3g} deg)"
        for key, value, other in (("hfov_deg", h, v), ("vfov_deg", v, h))
        if value < 0.2 and other > 2.0
    ]
    return [
        f"sensors.{sensor.name}: hfov_deg = {h:g} and vfov_deg = {v:g} give a field-of-view aspect ratio "
        f"tan(hfov/2) / tan(vfov/2) = {optical:.3g}, but the detector's n_h / n_v = {p['n_h']:g} / "
        f"{p['n_v']:g} = {pixels:.3g};" + (";".join(suspects) or " is a field of view in radians?")
    ]


def provenance(section: str, params: dict, origin: dict) -> dict:
    """``{parameter: {value, unit, source}}`` of every parameter used: scenario, preset or default.

    ``source`` is ``"scenario"``, ``"preset NAME"``, ``"derived from ..."`` or ``"default (TABLE)"``
    with the table of ``defaults/parameters.toml``; optional parameters left unset are omitted.
    """
    registry = load_parameters()[section]
    out = {}
    for key, value in params.items():
        if value is None:
            continue
        spec = registry.get(key, {})
        source = origin.get(key) or f"default ({spec.get('source', 'parameters.toml')})"
        out[key] = {"value": value, "unit": spec.get("unit", "-"), "source": source}
    return out


#: Largest scenario file read [bytes]; a scenario is a few hundred bytes.
MAX_SCENARIO_BYTES = 1024 * 1024


def embedded_scenarios() -> list[str]:
    """Names of the embedded scenarios (``defaults/scenarios/*.toml``)."""
    folder = scenario_path("default").parent
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def load_scenario(source) -> Scenario:
    """Load and resolve a scenario from a TOML file or an embedded scenario name.

    Parameters
    ----------
    source : str or Path
        A path to a ``.toml`` file, or the name of an embedded scenario
        (``default``, ...; see ``defaults/scenarios/``).
    """
    path = Path(source)
    if not path.exists() and not str(source).endswith(".toml"):
        embedded = scenario_path(str(source))
        if not embedded.is_file():
            raise ScenarioError(
                f"scenario = {str(source)!r} is neither a file nor an embedded scenario; "
                f"embedded scenarios: {', '.join(embedded_scenarios())}"
            )
        path = embedded
    if not path.exists():
        raise ScenarioError(f"scenario = {str(source)!r}: no such file")
    if path.is_dir():
        raise ScenarioError(f"scenario = {str(source)!r} is a directory, not a TOML file")
    if not path.is_file():
        raise ScenarioError(f"scenario = {str(source)!r} is not a regular file (a device or a pipe)")
    try:
        with path.open("rb") as stream:
            text = stream.read(MAX_SCENARIO_BYTES + 1)
    except OSError as exc:
        raise ScenarioError(f"scenario = {str(source)!r} cannot be read: {exc.strerror or exc}") from None
    if len(text) > MAX_SCENARIO_BYTES:
        raise ScenarioError(f"scenario = {str(source)!r} is larger than {MAX_SCENARIO_BYTES // 1024} KiB")
    try:
        data = tomllib.loads(text.decode("utf-8").removeprefix("\ufeff"))  # a byte-order mark is no key
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"scenario = {str(source)!r} is not valid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise ScenarioError(f"scenario = {str(source)!r} is not UTF-8 text") from None
    except RecursionError:
        raise ScenarioError(f"scenario = {str(source)!r} nests tables or arrays too deeply") from None
    return parse_scenario(data, name=path.stem)
