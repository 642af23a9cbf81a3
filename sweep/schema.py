"""The declared schema of a sweep spec (docs/sweeps.md): its keys, their types, defaults and what is allowed.

The keys every sweep has (:class:`SweepCommon`), each job's ``[options]`` model, and :func:`sweep_schema`,
which makes a job's whole schema; the jobs themselves are declared in :mod:`csuas.sweep.kinds`. What
depends on the base scenario (which parameters and sensors an axis may name, and their ranges from
``defaults/parameters.toml``) is checked by :func:`csuas.sweep.spec.parse_spec` after this schema.
"""

from __future__ import annotations

from math import isfinite
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    Discriminator,
    Field,
    Tag,
    ValidationInfo,
    create_model,
    field_validator,
)

from csuas.base.quality import RUNGS, RUNGS_TEXT
from csuas.base.schema import Schema, key, number, one_of, text, whole

#: Most points one sweep may hold (and so the most samples of one drawn axis).
MAX_POINTS = 100_000_000
CONVENTION = one_of("paper", "physical", allowed="paper or physical")
QUALITY = one_of(*RUNGS, allowed=RUNGS_TEXT)
AZIMUTH = number(-360.0, 360.0, "deg")
ELEVATION = number(-90.0, 90.0, "deg")
AXIS_VALUE_TEXT = "a finite number or a choice (text)"


def _axis_value(value):
    if isinstance(value, str) or (isinstance(value, (int, float)) and not isinstance(value, bool) and isfinite(value)):
        return value
    raise ValueError(AXIS_VALUE_TEXT)


class Draw(Schema):
    """An axis of ``samples`` values drawn uniformly from ``[min, max]`` with the spec's seed."""

    min: number() = key(description="lowest value")
    max: number() = key(description="highest value, >= min")
    samples: whole(1, MAX_POINTS) = key(description="values drawn")

    @field_validator("max")
    @classmethod
    def _not_below_min(cls, value, info: ValidationInfo):
        low = info.data.get("min")
        if low is not None and value < low:
            raise ValueError(f"at least min = {low:g}")
        return value


def _axis_kind(value) -> str | None:
    return "list" if isinstance(value, list) else "draw" if isinstance(value, (dict, BaseModel)) else None


Axis = Annotated[
    Annotated[list[Annotated[Any, BeforeValidator(_axis_value)]], Field(min_length=1), Tag("list")]
    | Annotated[Draw, Tag("draw")],
    Discriminator(
        _axis_kind,
        custom_error_type="csuas",
        custom_error_message="a non-empty list of values, or {min, max, samples}",
    ),
]
#: Tags of the unions above, which pydantic names in its error locations but a spec does not hold.
TAGS = ("list", "draw")


class SweepCommon(Schema):
    """Keys every sweep spec has."""

    scenario: text("an embedded scenario name or a scenario file") = key("default", "the base scenario")
    seed: whole(0) = key(0, "seed of drawn axes and of each point's own seed")
    combine: one_of("grid", "zip", allowed="grid or zip") = key(
        "grid", "grid: every combination of the axes; zip: element by element (axes of equal length)"
    )
    axes: dict[str, Axis] = key(
        {},
        "axis key -> a list (a grid axis) or {min, max, samples} (uniform draws)",
        "target.X, environment.X, sensors.NAME.X (defaults/parameters.toml) or the job's own axes",
    )
    recycle_after: whole(1) = key(50, "tasks a simulator worker runs before a fresh process replaces it")


class RangeOptions(Schema):
    """``[options]`` of the ``range`` job."""

    convention: CONVENTION | None = key(None, "the scenario's convention unless given")


class PdOptions(RangeOptions):
    """``[options]`` of the ``pd`` job."""

    fusion: Annotated[
        str, Field(pattern=r"^(or|k-of-n:[1-9][0-9]*)$", json_schema_extra={"allowed": "or, or k-of-n:K"})
    ] = key("or", "how the sensors' Pd are fused")


class RenderOptions(Schema):
    """``[options]`` of the ``render`` job."""

    mode: one_of("eo", "tir", "lidar", allowed="eo, tir or lidar") = key("eo", "what is rendered")
    quality: QUALITY = key("draft", "render preset")
    range_m: number(1e-3, 1e7, "m") | None = key(None, "range of every point without a range_m axis")
    azimuth_deg: AZIMUTH = key(0.0, "azimuth of every point without an azimuth_deg axis")
    elevation_deg: ELEVATION = key(0.0, "elevation of every point without an elevation_deg axis")


#: The render job's own axes: name -> (lowest, highest) allowed.
RENDER_AXES = {"range_m": (1e-3, 1e7), "azimuth_deg": (-360.0, 360.0), "elevation_deg": (-90.0, 90.0)}
#: The rcs job's own axes.
RCS_AXES = {"frequency_ghz": (1e-3, 1e4), "azimuth_deg": (-360.0, 360.0), "elevation_deg": (-90.0, 90.0)}


class RcsOptions(Schema):
    """``[options]`` of the ``rcs`` job."""

    target: text("a drone preset or a mesh file") | None = key(None, "the drone (the scenario's target unless given)")
    quality: QUALITY = key("draft", "ray density preset")
    rays_per_wavelength: number(1.0, None) | None = key(None, "overrides the quality's ray density")
    azimuth_deg: AZIMUTH = key(0.0, "azimuth of every point without an azimuth_deg axis")
    elevation_deg: ELEVATION = key(0.0, "elevation of every point without an elevation_deg axis")


class EngageOptions(Schema):
    """``[options]`` of the ``engage`` job: whose runs the sweep shares out."""

    engagement: text("an embedded engagement spec or a file (docs/engagements.md)") = key(
        "example", "the engagement spec; its runs are the sweep's points, each seeded by the spec's seed and its index"
    )
    runs: whole(1, MAX_POINTS) | None = key(None, "Monte Carlo runs (the engagement spec's runs unless given)")


def sweep_schema(job: str, options: type[Schema], chunk_points: int) -> type[SweepCommon]:
    """The schema of a sweep of ``job``: the common keys, ``job = "<job>"``, its ``[options]`` and ``chunk_points``."""
    return create_model(
        f"{job.title()}Sweep",
        __base__=SweepCommon,
        __doc__=f"A sweep of the ``{job}`` job.",
        job=(Literal[job], key(description="the job (sweep/kinds.py JOB_KINDS)")),
        options=(options, key(options(), None)),
        chunk_points=(whole(1), key(chunk_points, "points per task")),
    )
