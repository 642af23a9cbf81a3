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
from dataclasses import dataclass, field
from pathlib import Path
from typing import NoReturn

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

from csuas.base.errors import ScenarioError, plain, raise_all
from csuas.core import johnson
from csuas.core.result import CONVENTIONS
from csuas.defaults import MODALITIES, load_parameters, load_presets, load_tables, scenario_path

#: Aliases of environment parameters that take class names (docs/scenarios.md).
ENVIRONMENT_ALIASES = {
    "illumination": "illuminance_lx",
    "rain": "rain_rate_mm_h",
    "fog": "fog_visibility_m",
    "wind": "wind_speed_m_s",
    "noise": "noise_level_db",
}
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

    @property
    def effects(self) -> frozenset:
        """Conditions present in the scene: subset of {rain, fog, haze, wind, night}.

        ``haze`` means a visibility set by the scenario (not the Table 24
        default); ``wind`` a speed of at least 1 m/s (Table 31's range).
        """
        env = self.environment
        found = set()
        if env["rain_rate_mm_h"] > 0:
            found.add("rain")
        if env.get("fog_visibility_m") is not None or env["lwc_g_m3"] > 0:
            found.add("fog")
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
    """Validate one value against its parameter spec; return it (as float/int/str/list)."""
    if "choices" in spec:
        if not isinstance(value, str) or value not in spec["choices"]:
            _fail(key, value, "one of " + ", ".join(spec["choices"]))
        return value
    if isinstance(value, list):
        if not spec.get("list"):
            _fail(key, value, f"a number [{spec['unit']}]")
        return [check_value(key, {**spec, "list": False}, v) for v in value]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        _fail(key, value, f"a number [{spec['unit']}] in [{spec['min']:g}, {spec['max']:g}]")
    if isinstance(value, float) and math.isnan(value):
        _fail(key, value, "a number, not NaN")
    low_ok = value > spec["min"] if spec.get("min_exclusive") else value >= spec["min"]
    if not (low_ok and value <= spec["max"]):
        bracket = "(" if spec.get("min_exclusive") else "["
        _fail(key, value, f"{bracket}{spec['min']:g}, {spec['max']:g}] {spec['unit']}")
    if isinstance(spec.get("value"), int) and not isinstance(spec.get("value"), bool):
        if value != int(value):
            _fail(key, value, "a whole number")
        return int(value)
    return float(value)


def _class_value(key: str, param: str, value):
    classes = load_tables()["classes"].get(param)
    if classes is None or not isinstance(value, str):
        return value
    names = [k for k in classes if k != "source"]
    if value not in names:
        _fail(key, value, f"a number or one of {', '.join(names)} ({classes['source']})")
    return classes[value]


def _apply_overrides(
    section: str,
    prefix: str,
    registry: dict,
    values: dict,
    overrides: dict,
    explicit: set,
    errors: list,
    origin: dict,
    label: str,
    reserved: tuple = (),
):
    """Validate and apply ``overrides``; each mistake goes to ``errors`` and the others still apply."""
    for key, raw in overrides.items():
        if key in reserved:
            continue
        param = ENVIRONMENT_ALIASES.get(key, key) if section == "environment" else key
        full = f"{prefix}.{key}"
        try:
            if param not in registry:
                allowed = sorted(
                    set(registry) | set(reserved) | (set(ENVIRONMENT_ALIASES) if section == "environment" else set())
                )
                _fail(full, raw, "a known key: " + ", ".join(allowed))
            value = _class_value(full, param, raw)
            if section == "environment" and param == "fog_visibility_m" and isinstance(raw, str):
                # A fog class also sets its liquid water content (Table 16) unless given.
                if "lwc_g_m3" not in overrides:
                    values["lwc_g_m3"] = load_tables()["classes"]["lwc_g_m3"][raw]
                    explicit.add("lwc_g_m3")
                    origin["lwc_g_m3"] = f"{label} (fog class {raw!r}, Table 16)"
            values[param] = check_value(full, registry[param], value)
        except ScenarioError as exc:
            errors.append(exc)
            continue
        explicit.add(param)
        origin[param] = (
            label
            if not isinstance(raw, str) or "choices" in registry[param]
            else f"{label} (class {raw!r}, {load_tables()['classes'][param]['source']})"
        )


def _preset(kind: str, name: str, key: str, modality: str | None = None) -> dict:
    presets = load_presets()[kind]
    if modality is not None:
        presets = presets.get(modality, {})
    if name == "default":
        return {}
    if name not in presets:
        _fail(key, name, "default, " + ", ".join(presets))
    return {k: v for k, v in presets[name].items() if k not in ("description", "source")}


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


def _resolve_sensor(name: str, table: dict, errors: list) -> SensorSpec | None:
    prefix = f"sensors.{name}"
    if not isinstance(table, dict):
        _fail(prefix, table, "a table with modality = ...")
    modality = table.get("modality")
    if not isinstance(modality, str) or modality not in MODALITIES:
        _fail(f"{prefix}.modality", modality, ", ".join(MODALITIES))
    registry = load_parameters()[modality]
    values, explicit, origin = _defaults(modality), set[str](), dict[str, str]()
    preset = table.get("preset", "default")
    if not isinstance(preset, str):
        _fail(f"{prefix}.preset", preset, "a preset name")
    _apply_overrides(
        modality,
        f"{prefix}(preset {preset})",
        registry,
        values,
        _preset("sensor", preset, f"{prefix}.preset", modality),
        explicit,
        errors,
        origin,
        f"preset {preset}",
    )
    _apply_overrides(
        modality, prefix, registry, values, table, explicit, errors, origin, "scenario", reserved=("modality", "preset")
    )
    if errors:
        return None
    if modality in ("eo", "tir"):
        derived = johnson_derived(values, explicit)
        values.update(derived)
        if "lp_task" in derived:
            origin["lp_task"] = f"derived from task = {values['task']!r} (Table 20)"
        if "n_ttpf" in derived:
            origin["n_ttpf"] = f"derived from p_desired = {values['p_desired']:g} (Table 21)"
        curve = [values.get("mrtd_frequency_cy_mrad"), values.get("mrtd_k")]
        if (curve[0] is None) != (curve[1] is None):
            _fail(f"{prefix}.mrtd_k", curve[1], "given together with mrtd_frequency_cy_mrad (same length)")
    if modality == "radar":
        if {"wavelength_m", "frequency_ghz"} <= explicit:
            _fail(f"{prefix}.frequency_ghz", values["frequency_ghz"], "either wavelength_m or frequency_ghz, not both")
        if values["model"] == "range_equation" and values.get("p_rx_min_w") is None:
            _fail(f"{prefix}.p_rx_min_w", None, "a power > 0 [W] when model = range_equation")
    return SensorSpec(name, modality, preset, values, explicit, origin)


def parse_scenario(data: dict, name: str = "scenario") -> Scenario:
    """Resolve a scenario given as a dict (the parsed TOML).

    Raises
    ------
    ScenarioError
        Unknown key, wrong type, out-of-range value, unknown preset or class.
    """
    errors: list = []

    def attempt(step, *args):
        try:
            return step(*args)
        except ScenarioError as exc:
            errors.append(exc)
            return None

    for key in data:
        if key not in TOP_LEVEL_KEYS:
            attempt(_fail, key, data[key], "a known key: " + ", ".join(TOP_LEVEL_KEYS))
    convention = data.get("convention", "paper")
    if convention not in CONVENTIONS:
        attempt(_fail, "convention", convention, " or ".join(CONVENTIONS))
    params = load_parameters()
    sections, explicit, origin = {}, {}, {}
    for section, preset_kind, default_preset in (
        ("target", "target", "dji_mini_4_pro"),
        ("environment", "environment", "clear_day"),
    ):
        table = data.get(section, {})
        if not isinstance(table, dict):
            attempt(_fail, section, table, "a table")
            table = {}
        preset = table.get("preset", default_preset)
        if not isinstance(preset, str) or preset not in load_presets()[preset_kind]:
            attempt(_fail, f"{section}.preset", preset, ", ".join(load_presets()[preset_kind]))
            preset = default_preset
        values, given, where = _defaults(section), set[str](), dict[str, str]()
        _apply_overrides(
            section,
            f"{section}(preset {preset})",
            params[section],
            values,
            _preset(preset_kind, preset, f"{section}.preset"),
            given,
            errors,
            where,
            f"preset {preset}",
        )
        _apply_overrides(
            section, section, params[section], values, table, given, errors, where, "scenario", reserved=("preset",)
        )
        sections[section] = (values, preset)
        explicit[section], origin[section] = given, where
    sensors_table = data.get("sensors", {})
    if not isinstance(sensors_table, dict) or not sensors_table:
        attempt(_fail, "sensors", sensors_table, "at least one [sensors.<name>] table")
        sensors_table = {}
    sensors = {}
    for key, table in sensors_table.items():
        own: list = []
        spec = attempt(_resolve_sensor, key, table, own)
        errors.extend(own)
        sensors[key] = spec
    scenario_name = data.get("name", name)
    if not isinstance(scenario_name, str):
        attempt(_fail, "name", scenario_name, "a string")
    raise_all(errors)
    warnings = [w for spec in sensors.values() for w in plausibility_warnings(spec)]
    return Scenario(
        scenario_name,
        convention,
        sections["target"][0],
        sections["target"][1],
        sections["environment"][0],
        sections["environment"][1],
        sensors,
        explicit,
        origin,
        warnings,
    )


def plausibility_warnings(sensor: SensorSpec) -> list[str]:
    """Likely unit mistakes of an imaging sensor: a field of view that does not fit its detector.

    The fields of view of a pinhole camera with square pixels satisfy
    tan(HFOV/2) / tan(VFOV/2) = N_H / N_V (Eq. 15 per axis). A ratio off by more than a factor of two
    most often means degrees and radians were mixed; a field of view below 0.2 deg beside one above
    2 deg is named as the likely radian. One warning per sensor.
    """
    p = sensor.params
    if sensor.modality not in ("eo", "tir"):
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
        data = tomllib.loads(text.decode("utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"scenario = {str(source)!r} is not valid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise ScenarioError(f"scenario = {str(source)!r} is not UTF-8 text") from None
    except RecursionError:
        raise ScenarioError(f"scenario = {str(source)!r} nests tables or arrays too deeply") from None
    return parse_scenario(data, name=path.stem)
