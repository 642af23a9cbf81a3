"""The declared schema of a dataset spec (docs/datasets.md): its keys, their types, defaults and what is allowed.

A numeric axis (``range_m``, ``azimuth_deg``, ``elevation_deg``) is a list (a grid axis) or ``{min, max}``
(uniform draws), each value within the axis's limits.
"""

from __future__ import annotations

import math
from typing import Annotated, Any

from pydantic import BaseModel, Discriminator, Field, Tag, ValidationInfo, create_model, field_validator

from csuas.base.quality import RUNGS, RUNGS_TEXT
from csuas.base.schema import Schema, key, number, one_of, text, whole
from csuas.defaults import load_birds
from csuas.drone_models.presets import list_presets
from csuas.render.imaging.sensor_chain import STAGES

#: Valid range of each numeric axis and its unit.
AXIS_LIMITS = {"range_m": (1.0, 1e5, "m"), "azimuth_deg": (-360.0, 360.0, "deg"), "elevation_deg": (-90.0, 90.0, "deg")}
#: Tags of the unions below, which pydantic names in its error locations but a spec does not hold.
TAGS = ("list", "span", "name", "reflectance", "number")


def _max_not_below_min(cls, value, info: ValidationInfo):
    low = info.data.get("min")
    if low is not None and value < low:
        raise ValueError(f"at least min = {low:g}")
    return value


def _axis(name: str) -> Any:
    """A list of values or ``{min, max}``, every value within the axis's limits."""
    low, high, unit = AXIS_LIMITS[name]
    value = number(low, high, unit)
    span = create_model(
        f"Span_{name}",
        __base__=Schema,
        __validators__={"max_not_below_min": field_validator("max")(_max_not_below_min)},
        min=(value, key(description="lowest value")),
        max=(value, key(description="highest value")),
    )
    kind = lambda v: "list" if isinstance(v, list) else "span" if isinstance(v, (dict, BaseModel)) else None
    return Annotated[
        Annotated[list[value], Field(min_length=1), Tag("list")] | Annotated[span, Tag("span")],
        Discriminator(kind, custom_error_type="csuas", custom_error_message="a non-empty list, or {min, max}"),
        Field(json_schema_extra={"allowed": f"a list or {{min, max}} of values {low:g} to {high:g} {unit}"}),
    ]


def _background_kind(value) -> str | None:
    return "name" if isinstance(value, str) else "reflectance"


Background = Annotated[
    Annotated[one_of("sky", "clear_sky", allowed="'sky' or 'clear_sky'"), Tag("name")]
    | Annotated[number(0.0, 1.0, allowed="'sky', 'clear_sky' or a reflectance 0..1"), Tag("reflectance")],
    Discriminator(_background_kind),
    Field(json_schema_extra={"allowed": "'sky', 'clear_sky' or a reflectance 0..1"}),
]


def _span(name: str, low: float, high: float, unit: str) -> Any:
    """``{min, max}`` of values within [low, high] (a draw uniform between them)."""
    value = number(low, high, unit)
    return create_model(
        f"Span_{name}",
        __base__=Schema,
        __validators__={"max_not_below_min": field_validator("max")(_max_not_below_min)},
        min=(value, key(description="lowest value")),
        max=(value, key(description="highest value")),
    )


def _count(name: str, high: int) -> Any:
    """A whole number of confusers a frame, or ``{min, max}`` (drawn uniformly, both included)."""
    value = whole(0, high)
    span = create_model(
        f"Count_{name}",
        __base__=Schema,
        __validators__={"max_not_below_min": field_validator("max")(_max_not_below_min)},
        min=(value, key(description="fewest")),
        max=(value, key(description="most")),
    )
    kind = lambda v: "span" if isinstance(v, (dict, BaseModel)) else "number"
    allowed = f"a whole number 0 to {high}, or {{min, max}}"
    return Annotated[
        Annotated[value, Tag("number")] | Annotated[span, Tag("span")],
        Discriminator(kind, custom_error_type="csuas", custom_error_message=allowed),
        Field(json_schema_extra={"allowed": allowed}),
    ]


class ConfusersSchema(Schema):
    """The ``[confusers]`` table: birds, a light aircraft and insects as labelled classes (confusers.py)."""

    birds: _count("birds", 20) = key(0, "birds a frame (a sequence: a video)")
    bird_classes: Annotated[list[one_of(*load_birds())], Field(min_length=1)] = key(
        list(load_birds()), "bird classes drawn from (defaults/birds.toml)", "classes: " + ", ".join(load_birds())
    )
    bird_range_m: _span("bird_range_m", 5.0, 5000.0, "m") = key(
        {"min": 40.0, "max": 400.0}, "range of a bird [m]", "{min, max} of 5 to 5000 m"
    )
    aircraft: _count("aircraft", 3) = key(0, "light aircraft (Cessna 172-like) a frame")
    aircraft_range_m: _span("aircraft_range_m", 200.0, 50000.0, "m") = key(
        {"min": 1500.0, "max": 8000.0}, "range of an aircraft [m]", "{min, max} of 200 to 50000 m"
    )
    insects: _count("insects", 10) = key(0, "insects near the lens a frame (out of focus)")
    insect_range_m: _span("insect_range_m", 0.05, 5.0, "m") = key(
        {"min": 0.5, "max": 3.0}, "distance of an insect from the lens [m]", "{min, max} of 0.05 to 5 m"
    )


class ClutterSchema(Schema):
    """The ``[clutter]`` table: ground and skyline clutter, soft clouds (render/imaging/clutter.py)."""

    terrain: bool = key(False, "land cover (grass, forest, roads, buildings) below the horizon", "true or false")
    camera_height_m: number(0.5, 500.0, "m") = key(10.0, "the camera's height above the ground [m]")
    relief_m: number(0.0, 1000.0, "m") = key(
        0.0, "terrain: heights of a seeded fractal DEM, this times noise (0: flat)"
    )
    skyline: bool = key(False, "hills, trees and buildings along the skyline", "true or false")
    power_lines: whole(0, 5) = key(0, "power lines across the view (catenaries, 50-300 m away)")
    clouds: number(0.0, 1.0) = key(0.0, "share of the sky under soft clouds (thermal too)")
    sun_offset_deg: Annotated[list[number(-90.0, 90.0, "deg")], Field(min_length=2, max_length=2)] | None = key(
        None,
        "EO stills: the sun at [right, up] deg from the frame's centre (lights the drone and the sky)",
        "[x, y], each -90 to 90 deg",
    )
    lens_flare: bool = key(False, "ghost images of the sun along the line through the frame's centre", "true or false")

    @field_validator("lens_flare")
    @classmethod
    def _flare_needs_a_sun(cls, value, info: ValidationInfo):
        if value and info.data.get("sun_offset_deg") is None:
            raise ValueError("true only with sun_offset_deg")
        return value


class DatasetSchema(Schema):
    """The keys of a dataset spec."""

    seed: whole(0) = key(0, "image i draws from the seed [seed, i]")
    count: whole(1, 1_000_000) = key(1, "random draws per point of the list axes")
    scenario: text("an embedded scenario name or a scenario file") = key("default", "environment and sensors")
    sensor: text("an EO or thermal sensor of the scenario") | None = key(
        None, "the sensor that takes the images (the scenario's first EO or thermal one unless given)"
    )
    drones: Annotated[list[one_of(*list_presets())], Field(min_length=1)] = key(
        ["dji_mini_4_pro"], "the drone of each image is drawn from this list", "presets: " + ", ".join(list_presets())
    )
    range_m: _axis("range_m") = key([500.0], "range from the sensor [m]")
    azimuth_deg: _axis("azimuth_deg") = key({"min": -360.0, "max": 360.0}, "aspect azimuth [deg]")
    elevation_deg: _axis("elevation_deg") = key({"min": -90.0, "max": 90.0}, "aspect elevation [deg]")
    background: Background = key("sky", "what lies behind the drone")
    bits: one_of(8, 10, 12, 14, 16, allowed="8, 10, 12, 14 or 16 (whole numbers)") = key(12, "bits per pixel")
    chain: list[one_of(*STAGES)] = key(
        ["psf", "shot_noise", "read_noise", "quantise"], "sensor-chain stages, each a switch", ", ".join(STAGES)
    )
    quality: one_of(*RUNGS, allowed=RUNGS_TEXT) = key("draft", "render preset")
    position: one_of("random", "centre", allowed="random or centre") = key("random", "where the target lies")
    exr: bool = key(False, "also the signal before quantisation as a float32 EXR", "true or false")
    cloud_cover: number(0.0, 1.0, allowed="0..1, with background = 'clear_sky'") = key(
        0.0, "share of a clear_sky background under seeded clouds"
    )
    sky_temperature_k: number(3.0, 400.0, "K") | None = key(
        None, "thermal sensors: a sky of this apparent temperature above the horizon"
    )
    previews: bool = key(True, "also 8-bit sRGB previews (previews/, annotations_previews.json)", "true or false")
    sequence: dict[str, Any] | None = key(
        None,
        "a video along a trajectory instead of drawn views (docs/datasets.md, Sequences: frames, waypoints_m "
        "and speed_m_s or approach, frame_rate_hz, pointing, jitter_urad, line_time_us, rotor_rpm)",
        "a table of the sequence keys",
    )
    normal_shot_noise_above_e: number(100.0, None, "electrons") = key(
        math.inf,
        "shot noise drawn from the normal approximation above this mean (exact Poisson below)",
        shown_default="inf (exact Poisson everywhere)",
    )
    confusers: ConfusersSchema | None = key(None, None)
    clutter: ClutterSchema | None = key(None, None)

    @field_validator("chain")
    @classmethod
    def _jpeg_of_8_bits(cls, value, info: ValidationInfo):
        if "quantise" not in value:
            raise ValueError("stages including 'quantise' (the frames are written as the sensor's DN)")
        if "jpeg" in value and (info.data.get("bits", 8) != 8 or "quantise" not in value[: value.index("jpeg")]):
            raise ValueError("jpeg after quantise, with bits = 8")
        return value

    @field_validator("cloud_cover")
    @classmethod
    def _clouds_need_a_clear_sky(cls, value, info: ValidationInfo):
        if value and info.data.get("background", "clear_sky") != "clear_sky":
            raise ValueError("0..1, with background = 'clear_sky'")
        return value
