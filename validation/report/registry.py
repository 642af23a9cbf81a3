"""The registry of validation checks behind ``csuas report`` (docs/validation.md).

A check is a small declared unit, :class:`CheckSpec`: what it compares (an
oracle or a core prediction against a simulation, or the paper against
physics), the tolerance and why, the accuracy knob and its value per report
quality (``quick``, ``full``), and a function ``run(knob_value) -> Section``
that computes the figures. One spec may produce several figures
(:class:`Outcome`: expected, measured, tolerance, error estimate, time,
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

#: Report qualities, cheapest first.
QUALITIES = ("quick", "full")


@dataclass
class Outcome:
    """One compared figure.

    Attributes
    ----------
    name : str
        Stable identifier (the baseline comparison matches on it).
    expected : float
        Oracle, paper or core value.
    measured : float
        Simulated or recomputed value.
    tolerance : float
        Largest accepted ``|measured - expected|`` in ``unit``; the baseline
        comparison uses it as the largest accepted drift of either value.
    unit : str
    error_estimate : float or None
        Estimated error of ``measured`` (standard error, Richardson estimate,
        quadrature error) in ``unit``; None for exact computations.
    known_deviation : str or None
        Explanation when the figure disagrees because the paper deviates (from
        itself or from physics), so that it is reported, not hidden.
    limitation : str or None
        Explanation when the figure disagrees because of a documented limit of
        csuas's own models (e.g. no edge diffraction in SBR-PO); reported apart
        from the paper's deviations.
    tolerance_source : str
        Where the tolerance comes from (an error estimate times a factor, a
        printed precision, a derived bound); empty: the spec's ``tolerance_why``.
    time_s : float
        Wall time of the computation that produced the figure [s]; figures
        computed together share that time equally.
    source, method : str
        Where ``expected`` comes from; how ``measured`` is obtained.
    details : dict
        Further numbers (JSON-ready).
    ok_override : bool or None
        Verdict when it is not ``|measured - expected| <= tolerance`` (an error).
    """

    name: str
    expected: float
    measured: float
    tolerance: float
    unit: str = ""
    error_estimate: float | None = None
    known_deviation: str | None = None
    limitation: str | None = None
    tolerance_source: str = ""
    time_s: float = 0.0
    source: str = ""
    method: str = ""
    details: dict = field(default_factory=dict)
    ok_override: bool | None = None

    @property
    def ok(self) -> bool:
        """True when both values are finite and agree within the tolerance."""
        if self.ok_override is not None:
            return self.ok_override
        try:
            e, m, t = float(self.expected), float(self.measured), float(self.tolerance)
        except (TypeError, ValueError):
            return False
        return all(math.isfinite(v) for v in (e, m, t)) and abs(m - e) <= t

    @property
    def verdict(self) -> str:
        """``ok``, ``known`` (a deviation of the paper), ``limit`` (a limit of csuas's models) or ``FAIL``."""
        if self.ok:
            return "ok"
        if self.known_deviation:
            return "known"
        return "limit" if self.limitation else "FAIL"


@dataclass
class Figure:
    """A plot or image of a section, as PNG bytes."""

    name: str
    title: str
    png: bytes
    caption: str = ""


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
class CheckSpec:
    """A declared validation check.

    Attributes
    ----------
    name : str
        Identifier, prefix of its outcomes' names.
    title : str
        Heading in the report.
    group : str
        Report section: ``defaults``, ``worked_numbers``, ``conventions``,
        ``links``, ``rcs``, ``lidar``, ``imaging``.
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
    group: str
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
            Outcome(
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


def from_check(check, time_s: float = 0.0) -> Outcome:
    """An :class:`Outcome` from a :class:`csuas.base.checks.Check` (``defaults check`` records).

    The tolerance becomes ``max(abs_tol, rel_tol * |paper|)``, the rule of ``Check.ok``.
    """
    tolerance = max(check.abs_tol, check.rel_tol * abs(check.paper)) if math.isfinite(check.paper) else math.nan
    extra = dict(check.extra)
    error = extra.get("stderr", extra.get("stderr_m2"))
    if "time_s" in extra and not time_s:
        time_s = float(extra["time_s"])
    return Outcome(
        name=check.name,
        expected=check.paper,
        measured=check.computed,
        tolerance=tolerance,
        unit=check.unit,
        error_estimate=error,
        known_deviation=check.known_deviation,
        limitation=check.limitation,
        time_s=time_s,
        source=check.source,
        method=check.method,
        details={"rel_tol": check.rel_tol, "abs_tol": check.abs_tol, **extra},
        ok_override=None if check.ok == (abs(check.computed - check.paper) <= tolerance) else check.ok,
    )
