"""The registry of validation checks behind ``csuas report`` (docs/validation.md).

A check is a small declared unit, :class:`CheckSpec`: what it compares (an
oracle or a core prediction against a simulation, or the paper against
physics), the tolerance and why, the accuracy knob and its value per report
quality (``quick``, ``full``), and a function ``run(knob_value) -> Section``
that computes the figures. One spec may produce several figures
(:class:`csuas.base.checks.Check`: expected, measured, tolerance, error estimate, time,
known deviation) plus plots, images and a side-by-side table (the
convention differences of docs/conventions.md show paper, physical and simulated values).

:func:`run_spec` never lets a check's exception escape: it becomes a failed
outcome carrying the error text and traceback, so one broken simulator does
not stop the report, and the failure is counted, not hidden.
"""

from __future__ import annotations

import math
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field

from csuas.base.checks import Check

#: Report qualities, cheapest first.
QUALITIES = ("quick", "full")


@dataclass
class Figure:
    """A plot or image of a section, as PNG bytes; ``wide`` ones (two panels) are shown at full size on a row
    of their own, the others at most 620 px wide, two to a row."""

    name: str
    title: str
    png: bytes
    caption: str = ""
    wide: bool = False


@dataclass
class Section:
    """What one spec produced: figures to compare, plots, a side-by-side table, notes."""

    outcomes: list = field(default_factory=list)
    figures: list = field(default_factory=list)
    table: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    time_s: float = 0.0
    error: str | None = None


@dataclass(frozen=True)
class CheckGroup:
    """A section of the report, declared by the check module whose specs fill it (beside its ``SPECS``).

    The report lists exactly the groups of the specs it ran, by ``order``; a spec in a new group gets its
    own section in report.html, report.md and report.json without any other table to edit.

    Attributes
    ----------
    name : str
        Identifier: the ``group`` key of the JSON records and the page's anchor.
    title : str
        Heading of the section.
    order : int
        Place in the report, lowest first (unique among the groups of one report).
    description : str
        One sentence under the heading: what the section checks against what.
    """

    name: str
    title: str
    order: int
    description: str

    def as_dict(self) -> dict:
        """JSON record: ``name``, ``title``, ``order``, ``description``."""
        return {"name": self.name, "title": self.title, "order": self.order, "description": self.description}


def groups_of(specs) -> list:
    """The groups of ``specs``, each once, by ``order``.

    Raises
    ------
    ValueError
        Two different groups share a name or an order (the report could not tell their sections apart).
    """
    groups = []
    for spec in specs:
        if not isinstance(spec.group, CheckGroup):
            raise TypeError(f"check {spec.name}: group {spec.group!r} is not a CheckGroup")
        if spec.group not in groups:
            groups.append(spec.group)
    for key in ("name", "order"):
        values = [getattr(g, key) for g in groups]
        clashes = sorted({str(v) for v in values if values.count(v) > 1})
        if clashes:
            raise ValueError(f"report groups share the {key} {', '.join(clashes)}")
    return sorted(groups, key=lambda g: g.order)


@dataclass(frozen=True)
class CheckSpec:
    """A declared validation check.

    Attributes
    ----------
    name : str
        Identifier, prefix of its outcomes' names.
    title : str
        Heading in the report.
    group : CheckGroup
        Report section, declared beside the module's ``SPECS``.
    compares : str
        What is compared with what.
    tolerance_why : str
        The tolerance and the reason for it.
    run : callable(knob_value) -> Section
    knob : str or None
        The accuracy knob (rays per wavelength, samples per pixel, Sionna
        samples, quality preset); None for exact computations.
    knob_values : dict
        Knob value per report quality (``quick``, ``full``).
    simulated : bool
        Whether it runs a simulator (Mitsuba, Dr.Jit, Sionna RT).
    """

    name: str
    title: str
    group: CheckGroup
    compares: str
    tolerance_why: str
    run: Callable
    knob: str | None = None
    knob_values: dict = field(default_factory=dict)
    simulated: bool = False

    def knob_value(self, quality: str):
        """The knob's value at a report quality (None without a knob)."""
        if self.knob is None:
            return None
        return self.knob_values.get(quality, self.knob_values.get("quick"))


def run_spec(spec: CheckSpec, quality: str) -> Section:
    """Run one spec; an exception becomes a failed outcome with its text (never raised).

    ``KeyboardInterrupt`` and ``SystemExit`` still propagate.
    """
    start = time.perf_counter()
    try:
        section = spec.run(spec.knob_value(quality))
        if not isinstance(section, Section):
            raise TypeError(f"check {spec.name} returned {type(section).__name__}, not a Section")
    except Exception as exc:
        text = f"{type(exc).__name__}: {exc}"
        section = Section(error=text, notes=[traceback.format_exc()])
        section.outcomes.append(
            Check(
                name=f"{spec.name}.error",
                expected=math.nan,
                measured=math.nan,
                tolerance=math.nan,
                method="the check raised an exception",
                details={"error": text},
                ok_override=False,
            )
        )
    section.time_s = time.perf_counter() - start
    for outcome in section.outcomes:
        if not outcome.time_s:
            outcome.time_s = section.time_s / len(section.outcomes)
    return section


def timed(fn, *args, **kwargs):
    """``(result, seconds)`` of ``fn(*args, **kwargs)``."""
    start = time.perf_counter()
    result = fn(*args, **kwargs)
    return result, time.perf_counter() - start
