"""The declared schema of a scenario file (docs/scenarios.md), built from the tables of this layer.

``parameters.toml`` stays the single source of every parameter's type, unit and valid range: each section
(``target``, ``environment``, one per modality) becomes a model whose fields are built from its entries
(:func:`parameter_type`), with the presets of ``presets.toml`` as the allowed ``preset`` names and the class
names of ``tables.toml`` (Tables 11, 14, 16, 18, 27, 30) accepted beside numbers. A sensor table's model is
chosen by its ``modality``. What needs the resolved values (a preset's values under the file's, a radar given
both a wavelength and a frequency, a measured MRTD curve of two lists of one length) is checked by the
resolver, :func:`csuas.core.scenario.parse_scenario`.
"""

from __future__ import annotations

import functools
import json
from typing import Annotated, Any

from pydantic import BaseModel, Discriminator, Field, Tag, TypeAdapter, ValidationError, create_model

from csuas.base.errors import ParameterError
from csuas.base.schema import Schema, key, number, one_of, text, toml_text, whole
from csuas.defaults import MODALITIES, load_parameters, load_presets, load_tables

#: Aliases of environment parameters that take class names (docs/scenarios.md).
ENVIRONMENT_ALIASES = {
    "illumination": "illuminance_lx",
    "rain": "rain_rate_mm_h",
    "fog": "fog_visibility_m",
    "wind": "wind_speed_m_s",
    "noise": "noise_level_db",
}
#: The tag of a sensor table whose modality is missing or unknown.
UNKNOWN = "unknown modality"
#: Tags of the unions below, which pydantic names in its error locations but a scenario does not hold.
TAGS = (*MODALITIES, UNKNOWN, "list", "number", "class")


def allowed_range(spec: dict) -> str:
    """What a numeric parameter allows, as the error lines and ``csuas defaults list`` say it: ``[0, 180] deg``."""
    bracket = "(" if spec.get("min_exclusive") else "["
    return f"{bracket}{spec['min']:g}, {spec['max']:g}] {spec['unit']}"


def parameter_allowed(spec: dict) -> str:
    """What one parameter of ``parameters.toml`` allows, as its errors and the docs say it."""
    if "choices" in spec:
        return "one of " + ", ".join(spec["choices"])
    if spec.get("list"):
        return "a number or a list of numbers in " + allowed_range(spec)
    default = spec.get("value")
    if isinstance(default, int) and not isinstance(default, bool):
        return "a whole number in " + allowed_range(spec)
    return allowed_range(spec)


def _scalar_type(spec: dict) -> Any:
    scalar = {**spec, "list": False}
    if "choices" in spec:
        return one_of(*spec["choices"], allowed=parameter_allowed(scalar))
    default = spec.get("value")
    if isinstance(default, int) and not isinstance(default, bool):
        return whole(spec["min"], spec["max"], allowed=parameter_allowed(scalar), lenient=True)
    low_open = bool(spec.get("min_exclusive"))
    return number(spec["min"], spec["max"], spec["unit"], low_open=low_open, allowed=parameter_allowed(scalar))


def _kind(value) -> str:
    return "class" if isinstance(value, str) else "list" if isinstance(value, list) else "number"


def parameter_type(spec: dict, classes: dict | None = None) -> Any:
    """The field type of one parameter of ``parameters.toml``: its unit, range, choices; a list where the
    parameter takes one; a class name of ``classes`` (a table of ``tables.toml``) beside a number."""
    scalar = _scalar_type(spec)
    if spec.get("list"):
        return Annotated[
            Annotated[list[scalar], Field(min_length=1), Tag("list")] | Annotated[scalar, Tag("number")],
            Discriminator(_kind),
            Field(json_schema_extra={"allowed": parameter_allowed(spec)}),
        ]
    if classes is None:
        return scalar
    names = [k for k in classes if k != "source"]
    text_ = f"{allowed_range(spec)} or one of {', '.join(names)} ({classes['source']})"
    return Annotated[
        Annotated[one_of(*names, allowed=text_), Tag("class")] | Annotated[scalar, Tag("number")],
        Discriminator(_kind),
        Field(json_schema_extra={"allowed": text_}),
    ]


@functools.lru_cache(maxsize=256)
def _values_adapter(spec_json: str) -> TypeAdapter:
    return TypeAdapter(list[parameter_type(json.loads(spec_json))])


def checked_values(key: str, spec: dict, values: list, indexed: bool = True) -> list:
    """``values`` of one parameter (a sweep's axis, a sensitivity's bounds), each checked by the parameter's
    schema field (:func:`parameter_type`) in one call.

    Raises
    ------
    ParameterError
        The first bad value, named ``key.INDEX`` (``key`` with ``indexed=False``).
    """
    try:
        return _values_adapter(json.dumps(spec, sort_keys=True)).validate_python(values)
    except ValidationError as exc:
        index = exc.errors()[0]["loc"][0]
        value = values[index] if isinstance(index, int) else values
        raise ParameterError(f"{key}.{index}" if indexed else key, value, parameter_allowed(spec)) from None


def _shown(spec: dict) -> str:
    """A parameter's default as docs/scenarios.md shows it (``parameters.toml``'s value; optional: unset)."""
    return "unset" if spec.get("value") is None else f"`{toml_text(spec['value'])}`"


def _parameter_fields(section: str) -> dict:
    classes = load_tables()["classes"]
    fields = {
        name: (
            parameter_type(spec, classes.get(name)) | None,
            key(None, spec["description"], shown_default=_shown(spec)),
        )
        for name, spec in load_parameters()[section].items()
    }
    if section == "environment":
        for alias, name in ENVIRONMENT_ALIASES.items():
            fields[alias] = (fields[name][0], key(None, f"a class name or value of {name}", shown_default="-"))
    return fields


#: Most drones a swarm declares (the pairwise resolution test grows as N^2, its intervals as N^2 too).
MAX_SWARM = 100


class SwarmTable(Schema):
    """``target.swarm``: N copies of the target in a formation (docs/scenarios.md "Swarms"). Offsets are in the
    frame of the line of sight: x along it (away from the sensor), y across it horizontally, z up [m]."""

    count: whole(2, MAX_SWARM) | None = key(None, "number of drones (with spacing_m: a line across the line of sight)")
    spacing_m: number(0.0, 1e5, "m", low_open=True) | None = key(
        None, "spacing of the default formation: a line along y (across the line of sight), centred on the target"
    )
    offsets_m: (
        Annotated[
            list[Annotated[list[number(-1e5, 1e5, "m")], Field(min_length=3, max_length=3)]],
            Field(min_length=2, max_length=MAX_SWARM),
        ]
        | None
    ) = key(
        None,
        "explicit offsets [[x, y, z], ...] of each drone from the target [m] (instead of count, spacing_m)",
        allowed=f"2 to {MAX_SWARM} offsets [x, y, z], each in [-100000, 100000] m",
    )


@functools.cache
def section_schema(section: str, kind: str, default_preset: str):
    """The model of a ``[target]``, ``[environment]`` or sensor table (``kind``: ``target``, ``environment``
    or a modality); a sensor's model holds its ``modality`` too."""
    presets = load_presets()["sensor"].get(kind, {}) if kind in MODALITIES else load_presets()[kind]
    names = (["default"] if kind in MODALITIES else []) + list(presets)
    fields: dict = {}
    if kind in MODALITIES:
        fields["modality"] = (one_of(kind), key(description="the sensor's modality"))
    fields["preset"] = (one_of(*names, allowed=", ".join(names)), key(default_preset, "values to start from"))
    fields.update(_parameter_fields(section))
    if kind == "target":
        fields["swarm"] = (SwarmTable | None, key(None, None))
    return create_model(f"{kind.title()}Table", __base__=Schema, **fields)


class UnknownModality(Schema, extra="allow"):
    """A sensor table whose modality is missing or unknown: only that is said."""

    modality: one_of(*MODALITIES, allowed=", ".join(MODALITIES)) = key(description="the sensor's modality")


def _modality(table) -> str | None:
    if isinstance(table, BaseModel):  # a validated table, when dumped
        return table.modality if table.modality in MODALITIES else UNKNOWN
    if not isinstance(table, dict):
        return None
    return table["modality"] if table.get("modality") in MODALITIES else UNKNOWN


def sensor_type() -> Any:
    """A ``[sensors.NAME]`` table: the model of its modality."""
    choices = [Annotated[section_schema(m, m, "default"), Tag(m)] for m in MODALITIES]
    union = functools.reduce(lambda a, b: a | b, choices) | Annotated[UnknownModality, Tag(UNKNOWN)]
    return Annotated[
        union,
        Discriminator(
            _modality, custom_error_type="csuas", custom_error_message="a table [sensors.NAME] with modality = ..."
        ),
    ]


@functools.cache
def scenario_schema(conventions: tuple[str, ...]):
    """The model of a scenario file; ``conventions`` are the core's (:data:`csuas.core.result.CONVENTIONS`)."""
    target = section_schema("target", "target", "dji_mini_4_pro")
    environment = section_schema("environment", "environment", "clear_day")
    return create_model(
        "ScenarioSchema",
        __base__=Schema,
        name=(text("a string") | None, key(None, "the scenario's name (default: the file's name)")),
        description=(text("a string") | None, key(None, "free text")),
        convention=(one_of(*conventions, allowed=" or ".join(conventions)), key(conventions[0], "docs/conventions.md")),
        target=(target, key(target(), None)),
        environment=(environment, key(environment(), None)),
        sensors=(
            Annotated[dict[str, sensor_type()], Field(min_length=1)],
            key(
                description="the sensors, [sensors.NAME] each with its modality",
                allowed="at least one [sensors.<name>] table",
            ),
        ),
    )
