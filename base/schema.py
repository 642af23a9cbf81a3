"""Declared schemas of input files (pydantic v2): strict values, one error line per mistake, key tables for docs/.

The four kinds of input file (scenario, coverage site, dataset spec, sweep spec) are each declared once as a
pydantic model; this module holds what they share:

* :class:`Schema`, the base model: unknown keys are errors, values are never coerced (a TOML ``true`` is not
  the number 1, ``"5"`` is not 5), numbers are finite unless a field says otherwise;
* field helpers (:func:`number`, :func:`whole`, :func:`one_of`, :func:`key`) that carry the text of what is
  allowed, so that the error line and the docs table say the same;
* :func:`validate`: a model's validation errors as :class:`csuas.base.errors.ParameterError`, one per
  mistake, each with the full key path (``sensors.radar.frequency_ghz``), the value as written and what is
  allowed, all raised at once;
* :func:`read_toml`: a TOML file as a table, a UTF-8 byte-order mark accepted;
* :func:`key_table` and :func:`replace_generated`: the Markdown key table of a schema, and its place
  between marker comments in a docs page (``tools/docs_tables.py`` regenerates them; a test compares).

Why pydantic: the project's declared validation library (pyproject.toml); its errors carry the location of
every mistake, which is what the one-line messages need.
"""

from __future__ import annotations

import math
import re
import sys
import typing
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Annotated, Any

from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, Field, ValidationError

from csuas.base.errors import ParameterError, raise_all

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


class Missing:
    """The value of a required key the file lacks (shown as ``(missing)``)."""

    def __repr__(self) -> str:
        return "(missing)"


MISSING = Missing()


class Schema(BaseModel):
    """Base of the input-file schemas: unknown keys refused, no coercion, frozen."""

    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)


def _refuse(allowed: str):
    raise ValueError(allowed)  # pydantic reports it as a value_error with these words


def _finite(allowed: str) -> Callable[[Any], Any]:
    def check(value):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            _refuse(allowed)
        return value

    return check


def _bounded(low, high, allowed: str, low_open: bool = False, high_open: bool = False) -> Callable[[Any], Any]:
    def check(value):
        below = low is not None and (value <= low if low_open else value < low)
        above = high is not None and (value >= high if high_open else value > high)
        if below or above:
            _refuse(allowed)
        return value

    return check


def _plain_number(x: float) -> str:
    """``2147483647`` and ``1000000`` written out, ``0.001`` and ``1e+30`` as :g writes them."""
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e10 else f"{x:g}"


def _range_text(low, high, unit: str, low_open: bool, high_open: bool) -> str:
    low_text, high_text = (None if x is None else _plain_number(x) for x in (low, high))
    if low is not None and high is not None:
        text = f"{'(' if low_open else '['}{low_text}, {high_text}{')' if high_open else ']'}"
    elif low is not None:
        text = f"{'>' if low_open else '>='} {low_text}"
    elif high is not None:
        text = f"{'<' if high_open else '<='} {high_text}"
    else:
        text = "any finite number"
    return f"{text} {unit}".rstrip()


def number(
    low: float | None = None,
    high: float | None = None,
    unit: str = "",
    *,
    low_open: bool = False,
    high_open: bool = False,
    allowed: str | None = None,
) -> Any:
    """A finite number (int or float, never a boolean) within ``[low, high]`` (open ends on request).

    ``allowed`` replaces the generated text (``[0, 360] deg``) in errors and docs.
    """
    words = allowed or "a number " + _range_text(low, high, unit, low_open, high_open)
    return Annotated[
        float,
        BeforeValidator(_finite(words)),
        AfterValidator(_bounded(low, high, words, low_open, high_open)),
        Field(json_schema_extra={"allowed": words}),
    ]


def whole(low: int | None = None, high: int | None = None, allowed: str | None = None, lenient: bool = False) -> Any:
    """A whole number (never a boolean) within ``[low, high]``; ``lenient``: also a float without fraction."""
    words = allowed or "a whole number " + _range_text(low, high, "", False, False)

    def check(value):
        if lenient and isinstance(value, float) and math.isfinite(value) and value == int(value):
            value = int(value)
        if isinstance(value, bool) or not isinstance(value, int):
            _refuse(words)
        return value

    return Annotated[
        int,
        BeforeValidator(check),
        AfterValidator(_bounded(low, high, words)),
        Field(json_schema_extra={"allowed": words}),
    ]


def one_of(*choices, allowed: str | None = None) -> Any:
    """One of ``choices`` exactly (``8`` is not ``8.0``, ``1`` is not ``true``)."""
    words = allowed or ", ".join(str(c) for c in choices)

    def check(value):
        if not any(type(value) is type(c) and value == c for c in choices):
            _refuse(words)
        return value

    return Annotated[Any, BeforeValidator(check), Field(json_schema_extra={"allowed": words})]


def text(allowed: str) -> Any:
    """A string (what it names said by ``allowed``)."""

    def check(value):
        if not isinstance(value, str):
            _refuse(allowed)
        return value

    return Annotated[str, BeforeValidator(check), Field(json_schema_extra={"allowed": allowed})]


def key(default=..., description: str | None = "", allowed: str | None = None, shown_default: str | None = None) -> Any:
    """A schema field: its default (``...``: required), what it means and, optionally, what is allowed and the
    default as the docs show it (where absent means another table's value). ``description=None`` marks a
    nested table, whose keys the docs list one by one."""
    extra: dict[str, Any] = {k: v for k, v in (("allowed", allowed), ("shown_default", shown_default)) if v}
    if extra:  # a None would replace what the field's type declares
        return Field(default, description=description, json_schema_extra=extra)
    return Field(default, description=description)


# ---------------------------------------------------------------------------------------------------------
# errors


def _annotation_allowed(annotation) -> str | None:
    """The ``allowed`` text declared inside an annotation (``number(...) | None``)."""
    for meta in getattr(annotation, "__metadata__", ()):
        extra = getattr(meta, "json_schema_extra", None)
        if isinstance(extra, dict) and "allowed" in extra:
            return str(extra["allowed"])
    for arg in typing.get_args(annotation):
        found = _annotation_allowed(arg)
        if found is not None:
            return found
    return None


def _field_allowed(field) -> str | None:
    extra = field.json_schema_extra if isinstance(field.json_schema_extra, dict) else {}
    if "allowed" in extra:
        return str(extra["allowed"])
    return _annotation_allowed(field.annotation)


def _models_in(annotation) -> list[type[BaseModel]]:
    """The schema models an annotation may hold (through Annotated, unions, lists and dicts)."""
    return [model for model, _ in _tagged_models(annotation)]


def _tagged_models(annotation, tag: str | None = None) -> list[tuple[type[BaseModel], str | None]]:
    """(model, the union tag that chooses it) of every model an annotation may hold."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [(annotation, tag)]
    for meta in getattr(annotation, "__metadata__", ()):
        tag = getattr(meta, "tag", tag)
    found = []
    for arg in typing.get_args(annotation):
        found.extend(_tagged_models(arg, tag))
    return found


def _path(data, loc: tuple, tags: Iterable[str]) -> list:
    """The key path of ``loc`` in ``data``: pydantic's union tags (not keys of the file) left out."""
    path, here = [], data
    for part in loc:
        if isinstance(part, int):
            path.append(part)
            here = here[part] if isinstance(here, list) and 0 <= part < len(here) else None
        elif isinstance(here, dict) and part in here:
            path.append(part)
            here = here[part]
        elif part in tags:
            continue
        else:
            path.append(part)
            here = None
    return path


def _value_at(data, path: list):
    here = data
    for part in path:
        if isinstance(here, dict) and part in here:
            here = here[part]
        elif isinstance(here, list) and isinstance(part, int) and 0 <= part < len(here):
            here = here[part]
        else:
            return MISSING
    return here


def _describe(root, loc: tuple, tags: set) -> tuple[str | None, list[str]]:
    """(what the schema allows at pydantic's location ``loc``, the keys allowed beside it), by walking the
    models along it: a union tag in ``loc`` picks its member."""
    models, allowed, keys = _tagged_models(root), None, []
    for part in loc:
        chosen = [(m, t) for m, t in models if t == part]
        if part in tags and chosen:
            models = chosen
            continue
        keys = [name for m, _ in models for name in m.model_fields]
        fields = [m.model_fields[part] for m, _ in models if isinstance(part, str) and part in m.model_fields]
        if fields:
            allowed = _field_allowed(fields[0])
            models = [pair for f in fields for pair in _tagged_models(f.annotation)]
        # else: a name in a table of tables (sensors.NAME) or a list index: the same models below
    return allowed, keys


def _allowed_text(error: Any, allowed: str | None, keys: list[str]) -> str:
    kind = error["type"]
    if kind == "extra_forbidden":
        return "a known key: " + ", ".join(keys)
    if kind in ("value_error", "csuas"):  # a validator's or a discriminator's own words
        return re.sub(r"^Value error, ", "", error["msg"])
    message = re.sub(r"^Input should be ", "", error["msg"])
    if kind == "missing":
        return "required: " + (allowed or message)
    return allowed or message


def parameter_errors(error: ValidationError, data, root, prefix: str = "", tags: Iterable[str] = ()) -> list:
    """One :class:`ParameterError` per mistake of ``error``, named by its full key path.

    Parameters
    ----------
    error : pydantic.ValidationError
        From validating ``data`` against ``root``.
    data : dict
        The file's table as read.
    root : type
        The schema (a model, or an annotation holding models).
    prefix : str
        Prepended to every key path (``"sensors.eo(preset x)"``).
    tags : iterable of str
        Tags of discriminated unions, which pydantic puts in its locations but the file does not hold.
    """
    tags = set(tags)
    found = []
    for item in error.errors(include_url=False):
        path = _path(data, tuple(item["loc"]), tags)
        value = _value_at(data, path) if path else data
        allowed, keys = _describe(root, tuple(item["loc"]), tags)
        name = ".".join(str(p) for p in ([prefix] if prefix else []) + path) or "file"
        found.append(ParameterError(name, value, _allowed_text(item, allowed, keys)))
    return found


def validate(model: type[BaseModel], data, prefix: str = "", tags: Iterable[str] = (), context=None):
    """``model`` validated from ``data``; every mistake raised at once (exit 2 on the command line)."""
    try:
        return model.model_validate(data, context=context)
    except ValidationError as exc:
        raise_all(parameter_errors(exc, data, model, prefix, tags))
        raise  # pragma: no cover (raise_all raised)


# ---------------------------------------------------------------------------------------------------------
# files


def read_toml(path: str | Path, name: str, what: str, max_bytes: int | None = None) -> dict:
    """The table of a TOML file; a UTF-8 byte-order mark (as some editors write) is accepted.

    Raises
    ------
    ParameterError
        Named ``name``: not UTF-8, not TOML (with the parser's line and column), nested too deeply,
        or larger than ``max_bytes``.
    """
    with open(path, "rb") as stream:
        raw = stream.read() if max_bytes is None else stream.read(max_bytes + 1)
    if max_bytes is not None and len(raw) > max_bytes:
        raise ParameterError(name, str(path), f"a {what} of at most {max_bytes // 1024} KiB")
    try:
        return tomllib.loads(raw.decode("utf-8").removeprefix("\ufeff"))
    except UnicodeDecodeError:
        raise ParameterError(name, str(path), f"a {what} in UTF-8 text") from None
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(name, str(path), f"a {what} in valid TOML ({exc})") from None
    except RecursionError:
        raise ParameterError(name, str(path), f"a {what} without tables or arrays nested this deeply") from None


# ---------------------------------------------------------------------------------------------------------
# docs


def toml_text(value) -> str:
    """A value as TOML writes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, list):
        return "[" + ", ".join(toml_text(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {toml_text(v)}" for k, v in value.items()) + "}"
    return _plain_number(value) if isinstance(value, float) else str(value)


def _extra(field) -> dict:
    return field.json_schema_extra if isinstance(field.json_schema_extra, dict) else {}


def _default_text(field) -> str:
    if "shown_default" in _extra(field):
        return str(_extra(field)["shown_default"])
    if field.is_required():
        return "required"
    default = field.get_default(call_default_factory=True)
    return "absent" if default is None else f"`{toml_text(default)}`"


def _table_of_tables(annotation) -> type[BaseModel] | None:
    """The model of a ``dict[str, Model]`` (``[sensors.NAME]`` tables), else None."""
    if typing.get_origin(annotation) is dict:
        value = typing.get_args(annotation)[1]
        if isinstance(value, type) and issubclass(value, BaseModel):
            return value
    return None


def key_rows(model: type[BaseModel], prefix: str = "") -> list[tuple[str, str, str, str]]:
    """(key, default, allowed, meaning) of every key of ``model``: a nested table's keys with dots
    (``radio_map.step``), a table of tables' with ``NAME`` (``sensors.NAME.x``)."""
    rows = []
    for name, field in model.model_fields.items():
        full = f"{prefix}{name}"
        tables = _table_of_tables(field.annotation)
        nested = _models_in(field.annotation)
        if tables is not None:
            rows.extend(key_rows(tables, f"{full}.NAME."))
        elif nested and field.description is None:
            for sub in nested:
                rows.extend(key_rows(sub, f"{full}."))
        else:
            rows.append((full, _default_text(field), _field_allowed(field) or "", field.description or ""))
    return rows


def key_table(rows: Iterable[tuple[str, str, str, str]]) -> str:
    """The Markdown table of key rows (:func:`key_rows`; what docs/ shows between the generated markers)."""
    lines = ["| key | default | allowed | meaning |", "|---|---|---|---|"]
    for name, default, allowed, meaning in rows:
        cell = allowed.replace("|", "\\|")
        lines.append(f"| `{name}` | {default} | {cell} | {meaning} |")
    return "\n".join(lines)


def replace_generated(page: str, name: str, table: str) -> str:
    """``page`` with the text between ``<!-- generated: NAME -->`` and ``<!-- end generated: NAME -->`` replaced.

    Raises
    ------
    ValueError
        The page lacks the markers.
    """
    start, end = f"<!-- generated: {name} -->", f"<!-- end generated: {name} -->"
    head, found, rest = page.partition(start)
    _, found_end, tail = rest.partition(end)
    if not (found and found_end):
        raise ValueError(f"the page lacks the markers {start} ... {end}")
    return f"{head}{start}\n{table}\n{end}{tail}"
