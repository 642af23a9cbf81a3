"""The declared schema of a coverage site (docs/coverage.md): its keys, their types, defaults and what is allowed.

The pointing and dead-zone keys of a sited sensor and their domains come from
:data:`csuas.core.coverage.POINTING`, the record the core checks too. What depends on the scenario (which
sensors it has, which are RF or radar, their carriers against the ground's material) and on the DEM (a
position inside it) is checked beside this schema, in :mod:`csuas.render.site` and
:mod:`csuas.commands.coverage_radio`. It lives below the command line so that what reads a site for a
simulation (``csuas engage``, the ``engage`` sweep job) can use it.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import (
    BaseModel,
    Discriminator,
    Field,
    Tag,
    ValidationInfo,
    create_model,
    field_validator,
    model_validator,
)

from csuas.base.schema import Schema, key, number, text, whole
from csuas.core.coverage import POINTING

#: What each pointing key means (docs/coverage.md).
POINTING_MEANING = {
    "azimuth_deg": "boresight bearing [deg], clockwise from grid north (the DEM's +y)",
    "sector_deg": "full width of the azimuth sector centred on the boresight [deg] (360: all round)",
    "elevation_min_deg": "lowest elevation of the line of sight from the eye to the drone [deg]",
    "elevation_max_deg": "highest elevation [deg], above elevation_min_deg; above it lies the cone of silence",
    "min_range_m": "minimum slant range from the eye to the drone [m]: the near-range dead zone",
}
#: Tags of the unions below, which pydantic names in its error locations but a site does not hold.
TAGS = ("material", "constants")


def _pointing_field(name: str):
    default, bounds = POINTING[name]
    unit = "m" if name.endswith("_m") else "deg"
    low = bounds.get("ge", bounds.get("gt"))
    kind = number(low, bounds.get("le"), unit, low_open="gt" in bounds)
    return kind, key(default, POINTING_MEANING[name])


def _one_position(self):
    """Exactly one complete pair of x, y (the DEM's CRS) or lat, lon (WGS 84)."""
    given = [name for name in ("x", "y", "lat", "lon") if getattr(self, name) is not None]
    if given not in (["x", "y"], ["lat", "lon"]):
        shown = ", ".join(given) or "none"
        raise ValueError(f"exactly one position: x and y, or lat and lon (given: {shown})")
    return self


def _above_elevation_min(cls, value, info: ValidationInfo):
    low = info.data.get("elevation_min_deg")
    if low is not None and not low < value:
        raise ValueError(f"above elevation_min_deg = {low:g}")
    return value


#: A scenario sensor placed on the site.
SitedSensorTable = create_model(
    "SitedSensorTable",
    __base__=Schema,
    __validators__={
        "above_elevation_min": field_validator("elevation_max_deg")(_above_elevation_min),
        "one_position": model_validator(mode="after")(_one_position),
    },
    x=(
        number(allowed="a coordinate in the DEM's CRS [m]") | None,
        key(
            None, "position in the DEM's CRS [m], inside it (or lat and lon)", shown_default="a pair: x, y or lat, lon"
        ),
    ),
    y=(
        number(allowed="a coordinate in the DEM's CRS [m]") | None,
        key(
            None, "position in the DEM's CRS [m], inside it (or lat and lon)", shown_default="a pair: x, y or lat, lon"
        ),
    ),
    lat=(
        number(-90.0, 90.0, "deg") | None,
        key(None, "latitude on WGS 84 [deg] (instead of x and y), with lon", shown_default="a pair: x, y or lat, lon"),
    ),
    lon=(
        number(-180.0, 180.0, "deg") | None,
        key(None, "longitude on WGS 84 [deg] (instead of x and y), with lat", shown_default="a pair: x, y or lat, lon"),
    ),
    mast_m=(number(0.0, 1000.0, "m"), key(10.0, "eye height above the terrain under the sensor")),
    **{name: _pointing_field(name) for name in POINTING},
)


class GroundConstants(Schema):
    """A ground given by its constants, at any frequency."""

    relative_permittivity: number() = key(description="relative permittivity, >= 1")
    conductivity_s_m: number() = key(description="conductivity [S/m], >= 0")


def _ground_kind(value) -> str | None:
    return "material" if isinstance(value, str) else "constants" if isinstance(value, (dict, BaseModel)) else None


Ground = Annotated[
    Annotated[text("an ITU-R P.2040 material of Sionna RT"), Tag("material")]
    | Annotated[GroundConstants, Tag("constants")],
    Discriminator(
        _ground_kind,
        custom_error_type="csuas",
        custom_error_message="an ITU material name or {relative_permittivity, conductivity_s_m}",
    ),
    Field(json_schema_extra={"allowed": "an ITU material name or {relative_permittivity, conductivity_s_m}"}),
]


class RadioMapTable(Schema):
    """``[radio_map]``: Sionna RT radio maps of the site's RF and radar sensors over the terrain."""

    sensors: list[text("a sensor name")] | None = key(None, "RF or radar sensors of the site to map (default: all)")
    ground: Ground = key("medium_dry_ground", "the terrain's material (ITU materials span 1-10 GHz) or its constants")
    step: whole(1, 64, "a whole number of cells 1 to 64") = key(4, "DEM cells per side of a measurement block")
    samples: whole(1000, 100_000_000, "1000 to 1e8 rays per replica") = key(2**20, "rays per replica")
    accuracy_db: number(0.0, 20.0, "dB", low_open=True) | None = key(
        None, "the bound asked of the path gain on 90 % of the visible cells (rays doubled until met)"
    )
    max_depth: whole(0, 10, "0 to 10 reflections") = key(2, "reflections per path")
    seed: whole(0, 2**31 - 1) = key(1, "seed of the replicas")


class SiteSchema(Schema):
    """The keys of a coverage site."""

    dem: text("a GeoTIFF file") | None = key(
        None,
        "terrain heights [m]: a GeoTIFF in a projected CRS, or in lon/lat (reprojected to its UTM zone); "
        "omitted: the demo terrain; relative to the site",
    )
    scenario: text("an embedded scenario name or a scenario file") = key(
        "default", "the sensors' models and the environment"
    )
    altitudes_agl_m: Annotated[list[number(0.0, 10_000.0, "m")], Field(min_length=1)] = key(
        [30.0, 120.0], "flight levels above the terrain of each cell", "heights 0 to 10000 m"
    )
    sensors: Annotated[dict[str, SitedSensorTable], Field(min_length=1)] = key(
        description="sensors of the scenario placed on the site, [sensors.NAME] each",
        allowed="at least one [sensors.NAME] of the scenario",
    )
    fusion_k: whole(1) | None = key(
        None, "k of the k-of-n fused layers (absent: none)", "a whole number 1 to the number of sited sensors"
    )
    radio_map: RadioMapTable | None = key(None, None)

    @field_validator("altitudes_agl_m")
    @classmethod
    def _each_level_once(cls, value):
        if len(set(value)) != len(value):
            raise ValueError("heights 0 to 10000 m, each once (a layer per flight level)")
        return value

    @field_validator("fusion_k")
    @classmethod
    def _at_most_the_sensors(cls, value, info: ValidationInfo):
        sited = info.data.get("sensors") or (info.context or {}).get("sensors")  # the file's, when invalid
        n = len(sited) if isinstance(sited, dict) else 0
        if value is not None and n and value > n:
            allowed = f"a whole number 1 to {n} (the number of sited sensors)"
            raise ValueError(allowed)
        return value
