"""The paper's default parameters and tables as data (TOML), loaded once and validated.

Files
-----
parameters.toml
    Every canonical parameter (docs/scenarios.md) with value, unit, source and valid range.
tables.toml
    Class tables (Tables 11, 14, 16, 18, 27, 30), lookup tables (Tables 20, 21,
    31, 38, 41) and the printed values that ``csuas defaults check`` recomputes.
sensitivity.toml
    Parameter ranges of Section 4.9 (Tables 48-51) with the paper's quoted ranges.
itu.toml
    Coefficients of ITU-R P.838-3 (rain), P.840 (fog), P.676-12 (gas line tables), P.835-6 (reference
    atmosphere) and P.453-14 (vapour pressure).
presets.toml
    Named targets (Tables 8, 52), sensors (Tables 22-46 system databases) and
    environments (the paper's condition classes).
birds.toml
    Bird classes (the confusers of engagements and datasets): size, wingbeat, airspeed, heights,
    surface temperature, and the wing shape and plumage of their meshes (drone_models/birds.py).
clutter.toml
    Gamma of the constant-gamma land clutter model per land cover (Barton 2013).
drone_rcs_statistics.csv
    The drone presets' RCS over aspects per band and polarisation (``csuas rcs-statistics``).
scenarios/
    Embedded scenario files.
"""

from __future__ import annotations

import csv
import functools
import sys
from importlib import resources

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

from csuas.base.errors import CsuasError

#: Sections of parameters.toml that are not a sensor modality.
SCENE_SECTIONS = ("target", "environment")


def _load(name: str) -> dict:
    with resources.files(__name__).joinpath(name).open("rb") as fh:
        return tomllib.load(fh)


def _validate_parameters(params: dict) -> dict:
    for section, entries in params.items():
        for name, spec in entries.items():
            key = f"{section}.{name}"
            for field in ("unit", "source", "description"):
                if field not in spec:
                    raise CsuasError(f"defaults: {key} lacks '{field}'")
            if "value" not in spec and not spec.get("optional"):
                raise CsuasError(f"defaults: {key} has no value and is not optional")
            value = spec.get("value")
            if "choices" in spec:
                if value is not None and value not in spec["choices"]:
                    raise CsuasError(f"defaults: {key} = {value!r} not in its choices")
            elif value is not None and not (spec["min"] <= value <= spec["max"]):
                raise CsuasError(f"defaults: {key} = {value!r} outside [{spec['min']}, {spec['max']}]")
    return params


@functools.cache
def load_parameters() -> dict:
    """Parameter registry: ``{section: {name: spec}}`` (validated at first load)."""
    return _validate_parameters(_load("parameters.toml"))


@functools.cache
def load_tables() -> dict:
    """Class, lookup and printed-value tables."""
    return _load("tables.toml")


@functools.cache
def load_presets() -> dict:
    """Named target, sensor and environment presets."""
    return _load("presets.toml")


@functools.cache
def load_itu() -> dict:
    """ITU-R coefficient tables (itu.toml): P.838-3, P.840, P.676-12, P.835-6, P.453-14, by recommendation."""
    return _load("itu.toml")


@functools.cache
def load_sensitivity() -> dict:
    """One-at-a-time analyses of Section 4.9 (Tables 48-51) and the platform table (Table 52)."""
    return _load("sensitivity.toml")


#: The sensor modalities: the other sections of parameters.toml, in its order (the paper's). Each has its
#: record in ``csuas.core.modality`` (the layer above), which checks that they agree.
MODALITIES = tuple(section for section in load_parameters() if section not in SCENE_SECTIONS)


def default_values(section: str) -> dict:
    """``{name: default}`` of one section (optional parameters omitted)."""
    return {k: v["value"] for k, v in load_parameters()[section].items() if "value" in v}


def scenario_path(name: str):
    """Path of an embedded scenario file (``default``, ``fog``, ...)."""
    return resources.files(__name__).joinpath("scenarios", f"{name}.toml")


def dataset_path(name: str):
    """Path of an embedded dataset spec (``example``; docs/datasets.md)."""
    return resources.files(__name__).joinpath("datasets", f"{name}.toml")


def site_path(name: str):
    """Path of an embedded coverage site (``demo``; docs/coverage.md)."""
    return resources.files(__name__).joinpath("sites", f"{name}.toml")


def sweep_path(name: str):
    """Path of an embedded sweep spec (``range_rain``, ``rcs_bands``, ...; docs/sweeps.md)."""
    return resources.files(__name__).joinpath("sweeps", f"{name}.toml")


@functools.lru_cache(maxsize=1)
def load_drone_rcs_statistics() -> tuple:
    """Rows of ``drone_rcs_statistics.csv`` as dicts: text columns as read, numbers as float."""
    text = resources.files(__name__).joinpath("drone_rcs_statistics.csv").read_text(encoding="utf-8")
    rows = csv.DictReader(line for line in text.splitlines() if not line.startswith("#"))
    keep_text = ("preset", "polarisation", "quality")
    return tuple({k: (v if k in keep_text else float(v)) for k, v in row.items()} for row in rows)


@functools.cache
def load_birds() -> dict:
    """Bird classes (``birds.toml``): size, wingbeat, airspeed, flight heights, surface temperature, mesh shape."""
    return _load("birds.toml")


@functools.cache
def load_clutter() -> dict:
    """Gamma of the constant-gamma land clutter model per land cover (``clutter.toml``) [dB]."""
    return _load("clutter.toml")


def engagement_path(name: str):
    """Path of an embedded engagement spec (``example``; docs/engagements.md)."""
    return resources.files(__name__).joinpath("engagements", f"{name}.toml")
