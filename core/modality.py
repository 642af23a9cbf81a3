"""Sensor modalities, each declared once as a :class:`Modality` record; every table keyed by modality derives from them.

A modality is its model (a module of this layer), its parameters (the ``[NAME]`` section of
``defaults/parameters.toml``), its presets (``[sensor.NAME]`` of ``defaults/presets.toml``) and one record
in :data:`RECORDS`. From the records come :data:`csuas.core.ranges.ADAPTERS` (scenario to model),
:data:`csuas.core.ranges.HORIZONS` (the cap of the range), :data:`csuas.core.coverage.K_FACTOR` (the
refraction of the line of sight over terrain), :data:`csuas.core.pd_curves.DETECTORS` (Pd against range)
and the threshold that :func:`csuas.core.pd_curves.margin_db` shifts. The modality names of the scenario
file's schema come from the sections of ``parameters.toml`` (``csuas.defaults.MODALITIES``, the layer
below, which cannot import this one); importing this module checks that they and the records name the
same modalities, and that every record has each part, and fails naming the modality and the part.

Horizons: ITU-R P.834-9 (2017), Section 1 (radio, k = 4/3); Bomford, *Geodesy*, 4th ed., 1980,
Section 3.3 (light, refraction coefficient 0.13), as :mod:`csuas.core.horizon`.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, fields
from typing import Any

from csuas.base.errors import CsuasError, ParameterError, raise_all
from csuas.base.registry import resolve
from csuas.core.horizon import K_OPTICAL, K_RADIO
from csuas.defaults import MODALITIES, load_parameters, load_presets


class ModalityError(CsuasError):
    """A modality declared without one of its parts: the message names the modality and the part."""


@dataclass(frozen=True)
class Horizon:
    """The line of sight of one kind of wave.

    Attributes
    ----------
    k : float
        Effective Earth-radius factor [-] of the line of sight over terrain (:mod:`csuas.core.terrain`).
    label : str or None
        Name of the horizon that caps the predicted range; None: the range is not capped.
    """

    k: float
    label: str | None


class _Missing:
    def __repr__(self) -> str:
        return "MISSING"


#: The value of a part a record does not give (:func:`check_modality` names it).
MISSING: Any = _Missing()

#: Horizon kind -> its line of sight: radio (ITU-R P.834), light (refraction coefficient 0.13), and None
#: for sound, whose refraction the models leave out (straight rays over terrain, range not capped).
HORIZON_KINDS = {
    "radio": Horizon(K_RADIO, "4/3-Earth radio horizon (ITU-R P.834)"),
    "optical": Horizon(K_OPTICAL, "optical horizon, refraction coefficient 0.13"),
    None: Horizon(1.0, None),
}
#: Parameters every sensor has (``csuas pd``'s looks along an approach).
COMMON_PARAMETERS = ("looks", "look_rate_hz")
#: A core function named by a record: ``"csuas.core.module:function"``.
_CORE_FUNCTION = re.compile(r"^csuas\.core\.[a-z_][a-z0-9_]*:[A-Za-z_][A-Za-z0-9_]*$")


@dataclass(frozen=True)
class Modality:
    """One sensor modality: every fact the rest of csuas needs about it, declared once.

    Its parameters are the ``[NAME]`` section of ``defaults/parameters.toml`` and its presets the
    ``[sensor.NAME]`` tables of ``defaults/presets.toml`` (the scenario file's sensor tables are built
    from both, ``csuas.defaults.scenario_schema``). Every part must be given: one left out is
    :data:`MISSING`, which :func:`check_modality` names.

    Attributes
    ----------
    name : str
        The ``modality`` of a scenario's sensor table.
    model : str
        ``"csuas.core.module:function"``: ``function(scenario, sensor, convention) -> RangeResult``, the
        scenario's parameters mapped onto the core model (``csuas range``).
    detector : str
        ``"csuas.core.module:function"``: ``function(scenario, sensor, convention, range_m, result)`` ->
        (Pd at each range, notes), ``result`` the sensor's deterministic range (``csuas pd``).
    horizon : {"radio", "optical", None}
        Kind of its line of sight (:data:`HORIZON_KINDS`): the refraction over terrain and the horizon
        that caps its range (None: straight rays, no cap).
    threshold : str, tuple of (str, str) pairs, or None
        The parameter holding its detection threshold, which ``margin_db`` shifts (added in dB when its
        unit is dB or dBm, else scaled); pairs (value of the sensor's ``model``, parameter) where the
        model chooses it; None for a sensor without one (imaging).
    renderer : str or None
        The ``csuas render --mode`` that simulates it (a key of ``csuas/commands/render.py`` ``MODES``,
        resolved there: the core names no layer above it); None when none does.
    report_group : str
        The report group whose checks compare its simulator with its model (``csuas report``).
    """

    name: str
    model: str = MISSING
    detector: str = MISSING
    horizon: str | None = MISSING
    threshold: str | tuple | None = MISSING
    renderer: str | None = MISSING
    report_group: str = MISSING

    @property
    def line_of_sight(self) -> Horizon:
        """Its :class:`Horizon` (k and the label of the cap)."""
        return HORIZON_KINDS[self.horizon]

    def threshold_key(self, params: dict) -> tuple[str, bool]:
        """The parameter holding a sensor's threshold, and whether it is in dB (unit dB or dBm).

        Raises
        ------
        ParameterError
            The modality has no threshold (an imaging sensor).
        """
        key = self.threshold
        if isinstance(key, tuple):
            key = dict(key)[params["model"]]
        if key is None:
            raise ParameterError("modality", self.name, "a threshold-limited sensor: " + ", ".join(_thresholded()))
        return key, load_parameters()[self.name][key]["unit"].startswith("dB")


#: Every modality, each declared once (docs/scenarios.md).
RECORDS = (
    Modality(
        "eo",
        model="csuas.core.ranges:_eo",
        detector="csuas.core.pd_curves:_eo_pd",
        horizon="optical",
        threshold=None,
        renderer="eo",
        report_group="imaging",
    ),
    Modality(
        "tir",
        model="csuas.core.ranges:_tir",
        detector="csuas.core.pd_curves:_tir_pd",
        horizon="optical",
        threshold=None,
        renderer="tir",
        report_group="imaging",
    ),
    Modality(
        "acoustic",
        model="csuas.core.ranges:_acoustic",
        detector="csuas.core.pd_curves:_acoustic_pd",
        horizon=None,
        threshold="snr_req_db",
        renderer=None,
        report_group="propagation",
    ),
    Modality(
        "rf",
        model="csuas.core.ranges:_rf",
        detector="csuas.core.pd_curves:_rf_pd",
        horizon="radio",
        threshold="s_rx_dbm",
        renderer=None,
        report_group="links",
    ),
    Modality(
        "radar",
        model="csuas.core.ranges:_radar",
        detector="csuas.core.pd_curves:_radar_pd",
        horizon="radio",
        threshold=(("snr", "snr_min_db"), ("range_equation", "p_rx_min_w")),
        renderer=None,
        report_group="links",
    ),
    Modality(
        "lidar",
        model="csuas.core.ranges:_lidar",
        detector="csuas.core.pd_curves:_lidar_pd",
        horizon="optical",
        threshold="p_rx_min_w",
        renderer="lidar",
        report_group="lidar",
    ),
)


def _thresholded() -> list[str]:
    return [m.name for m in RECORDS if m.threshold is not None]


def _threshold_problems(record: Modality, section: dict) -> list[str]:
    """What is wrong with a record's threshold, against its parameters' section."""
    key = record.threshold
    if key is None:
        return []
    if isinstance(key, str):
        names = [key]
    elif all(isinstance(p, tuple) and len(p) == 2 for p in key):
        models, names = [m for m, _ in key], [n for _, n in key]
        choices = section.get("model", {}).get("choices", [])
        if sorted(models) != sorted(choices):
            return [f"threshold: pairs for the models {models}, parameters.toml's are {choices}"]
    else:
        return [f"threshold: {key!r} is neither a parameter nor (model, parameter) pairs"]
    return [
        f"threshold: {name!r} is not a numeric parameter of [{record.name}]"
        for name in names
        if "min" not in section.get(name, {})
    ]


def _part_problems(record: Modality) -> dict:
    """``{part: what is wrong with it, or None}`` of the parts a record gives itself."""
    core = "is not a core function 'csuas.core.module:function'"
    return {
        "model": None if isinstance(record.model, str) and _CORE_FUNCTION.match(record.model) else core,
        "detector": None if isinstance(record.detector, str) and _CORE_FUNCTION.match(record.detector) else core,
        "horizon": None if record.horizon in HORIZON_KINDS else "is not one of " + ", ".join(map(str, HORIZON_KINDS)),
        "renderer": None
        if record.renderer is None or (isinstance(record.renderer, str) and record.renderer)
        else "is neither a render mode nor None",
        "report_group": None
        if isinstance(record.report_group, str) and record.report_group
        else "is not a report group",
    }


def check_modality(record: Modality) -> list[ModalityError]:
    """Every part a record lacks or gets wrong, each as a :class:`ModalityError` naming the modality and part.

    Checked without importing the model: every part given (not :data:`MISSING`), the name's sections in
    ``parameters.toml`` (with :data:`COMMON_PARAMETERS`) and ``presets.toml``, the model and detector as
    core functions, the horizon kind, the threshold parameter, the renderer and the report group.
    :func:`resolve_part` then checks that the model and detector exist.
    """
    missing = {f.name for f in fields(record) if getattr(record, f.name) is MISSING}
    problems = [f"{part}: not given" for part in sorted(missing)]
    section = load_parameters().get(record.name)
    if section is None:
        problems.append(f"parameters: no section [{record.name}] in defaults/parameters.toml")
    else:
        lacking = [p for p in COMMON_PARAMETERS if p not in section]
        problems += [f"parameters: [{record.name}] lacks {', '.join(lacking)}"] if lacking else []
        problems += [] if "threshold" in missing else _threshold_problems(record, section)
    if record.name not in load_presets().get("sensor", {}):
        problems.append(f"presets: no [sensor.{record.name}] tables in defaults/presets.toml")
    problems += [
        f"{part}: {getattr(record, part)!r} {text}"
        for part, text in _part_problems(record).items()
        if text is not None and part not in missing
    ]
    return [ModalityError(f"modality {record.name!r}: {text}") for text in problems]


def check_declared(records=RECORDS, sections=MODALITIES) -> None:
    """Every record complete (:func:`check_modality`), each name once, and one record per modality section.

    Parameters
    ----------
    records : sequence of Modality
    sections : sequence of str
        The modality sections of ``parameters.toml`` (``csuas.defaults.MODALITIES``).

    Raises
    ------
    ModalityError, InputErrors
        Each problem, naming the modality and the part.
    """
    names = [m.name for m in records]
    errors = [e for m in records for e in check_modality(m)]
    errors += [
        ModalityError(f"modality {n!r}: declared twice") for n in sorted({n for n in names if names.count(n) > 1})
    ]
    errors += [
        ModalityError(f"modality {s!r}: a section of defaults/parameters.toml without a Modality record")
        for s in sections
        if s not in names
    ]
    raise_all(errors)


def resolve_part(record: Modality, part: str):
    """The function a record's ``model`` or ``detector`` names, imported.

    Raises
    ------
    ModalityError
        It does not import, or is not a function.
    """
    reference = getattr(record, part)
    try:
        found = resolve(reference)
    except (ImportError, AttributeError) as exc:
        raise ModalityError(f"modality {record.name!r}: {part} {reference!r} does not resolve ({exc})") from exc
    if not callable(found):
        raise ModalityError(f"modality {record.name!r}: {part} {reference!r} is not a function")
    return found


class PartTable(Mapping):
    """``{modality name: the function its record names as part}``, each imported when first used.

    A read-only mapping (iteration in :data:`RECORDS`' order), so that the modules whose functions the
    records name can derive their tables from the records without importing each other in a cycle.
    """

    def __init__(self, part: str, records=RECORDS):
        self._part = part
        self._records = {m.name: m for m in records}
        self._resolved: dict = {}

    def __getitem__(self, name: str):
        if name not in self._resolved:
            self._resolved[name] = resolve_part(self._records[name], self._part)
        return self._resolved[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._records)

    def __len__(self) -> int:
        return len(self._records)


#: Modality name -> its record.
BY_NAME = {m.name: m for m in RECORDS}

check_declared()
