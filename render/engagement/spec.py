"""The ``csuas engage`` spec (docs/engagements.md): one pydantic model per table, every mistake named by its key.

Public keys (issue 24): ``site``, ``sensors``, ``runs``, ``seed``, ``[drone]`` (``target``,
``waypoints``, ``speed_m_s``), ``[looks.NAME]`` (``revisit_s``, ``sigma_range_m``,
``sigma_bearing_deg``), ``[tracker]`` (``confirm``, ``delete_after_misses``), ``[confusers]``
(``birds_per_km2``, ``bird_classes``), ``[classification]`` (``micro_doppler``, ``prf_hz``,
``dwell_s``, ``elevation_deg``: the radars' drone-or-bird decision by blade lines, off by default).
Extensions: ``scenario`` (a scenario name, file or inline
table replacing the site's), the further ``[looks.NAME]`` keys of
:class:`csuas.render.engagement.sensors.LookSettings` and ``confusers.radius_m``.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from csuas.base.errors import ParameterError, raise_all
from csuas.core.m_of_n import MAX_WINDOW
from csuas.defaults import load_birds, load_clutter

Positive = Annotated[float, Field(gt=0)]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=False)


class DroneSpec(_Strict):
    """``[drone]``: the target preset, its waypoints (x, y in the DEM's CRS [m], height above terrain [m]) and speed."""

    target: str = "dji_mini_4_pro"
    waypoints: list[tuple[float, float, Annotated[float, Field(ge=0, le=10_000)]]] = Field(min_length=2)
    speed_m_s: float = Field(gt=0, le=150)

    @field_validator("waypoints")
    @classmethod
    def _legs(cls, waypoints):
        if any(a[:2] == b[:2] for a, b in zip(waypoints, waypoints[1:])):
            raise ValueError("successive waypoints at the same (x, y): every leg needs a ground length")
        return waypoints


class LookSpec(_Strict):
    """``[looks.NAME]``: how a sensor looks and reports; absent keys take its modality's defaults."""

    revisit_s: float | None = Field(None, gt=0, le=3600)
    sigma_range_m: float | None = Field(None, ge=0, le=10_000)
    sigma_range_fraction: float | None = Field(None, ge=0, le=1)
    sigma_bearing_deg: float | None = Field(None, gt=0, le=45)
    pfa: float | None = Field(None, ge=0, le=0.1)
    frames_per_look: int | None = Field(None, ge=1, le=10_000)
    doppler_bins: int | None = Field(None, ge=1, le=65_536)
    elevation_beams: int | None = Field(None, ge=1, le=1000)
    instrumented_range_m: float | None = Field(None, gt=0, le=1e6)
    land_cover: str | None = None
    clutter_rejection_db: float | None = Field(None, ge=0, le=120)
    clutter: bool | None = None
    decorrelation: Literal["aspect", "independent", "correlated"] | None = None
    attitude_jitter_deg: float | None = Field(None, ge=0, le=90)
    frequency_bins: int | None = Field(None, ge=1, le=10_000_000)
    bearing_cells: int | None = Field(None, ge=1, le=100_000)
    range_gate_m: float | None = Field(None, gt=0, le=10_000)
    beam_positions: int | None = Field(None, ge=1, le=100_000_000)

    @field_validator("land_cover")
    @classmethod
    def _land_cover(cls, value):
        covers = load_clutter()["gamma_db"]
        if value is not None and value not in covers:
            raise ValueError("a land cover of defaults/clutter.toml: " + ", ".join(covers))
        return value


class TrackerSpec(_Strict):
    """``[tracker]``: M of N confirmation and deletion after missed looks."""

    confirm: tuple[int, int] = (3, 5)
    delete_after_misses: int = Field(5, ge=1, le=1000)

    @field_validator("confirm")
    @classmethod
    def _m_of_n(cls, value):
        m, n = value
        if not 1 <= m <= n <= MAX_WINDOW:
            raise ValueError(f"[M, N] with 1 <= M <= N <= {MAX_WINDOW}")
        return value


class ConfusersSpec(_Strict):
    """``[confusers]``: birds per km^2 over the square within ``radius_m`` of the sensors, and their classes."""

    birds_per_km2: float = Field(0.0, ge=0, le=1000)
    bird_classes: list[str] = Field(default_factory=lambda: list(load_birds()))
    radius_m: float = Field(2000.0, gt=0, le=50_000)

    @field_validator("bird_classes")
    @classmethod
    def _classes(cls, value):
        unknown = [c for c in value if c not in load_birds()]
        if unknown:
            raise ValueError(f"bird classes of defaults/birds.toml ({', '.join(load_birds())}), not {unknown}")
        return value


class ClassificationSpec(_Strict):
    """``[classification]``: the radars' drone-or-bird decision by blade lines (render/rcs/drone_or_bird.py)."""

    micro_doppler: bool = False
    prf_hz: float = Field(20_000.0, gt=0, le=1e7)
    dwell_s: float = Field(0.05, gt=0, le=1.0)
    elevation_deg: float = Field(10.0, gt=0, lt=90)


class EngageSpec(_Strict):
    """The whole spec (module docstring)."""

    site: str
    scenario: str | dict | None = None
    sensors: list[str] | None = Field(None, min_length=1)
    runs: int = Field(200, ge=1, le=1_000_000)
    seed: int = Field(1, ge=0)
    drone: DroneSpec
    looks: dict[str, LookSpec] = Field(default_factory=dict)
    tracker: TrackerSpec = Field(default_factory=TrackerSpec)
    confusers: ConfusersSpec = Field(default_factory=ConfusersSpec)
    classification: ClassificationSpec = Field(default_factory=ClassificationSpec)

    @model_validator(mode="after")
    def _looks_of_engaged(self):
        if self.sensors is not None:
            extra = [name for name in self.looks if name not in self.sensors]
            if extra:
                raise ValueError(f"looks.{extra[0]}: not one of sensors = {self.sensors}")
        return self


def parse_spec(data: dict) -> EngageSpec:
    """Validate a parsed spec; every mistake at once as ParameterErrors naming the full key path.

    Raises
    ------
    ParameterError
        (several through :func:`csuas.base.errors.raise_all`) with key, value and what is allowed.
    """

    try:
        return EngageSpec.model_validate(data)
    except ValidationError as exc:
        errors = []
        for error in exc.errors():
            key = ".".join(str(part) for part in error["loc"]) or "spec"
            allowed = error["msg"].removeprefix("Value error, ")
            if error["type"] == "extra_forbidden":
                allowed = "a key of the spec (docs/engagements.md)"
            errors.append(ParameterError(key, error.get("input"), allowed))
        raise_all(errors)
        raise  # pragma: no cover (raise_all raised)
