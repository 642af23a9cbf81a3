"""The one comparison record of csuas: ``csuas defaults check``, ``csuas report`` and every checker.

A :class:`Check` compares an expected value (an oracle, a value the paper prints, a core
prediction) with a measured one (a simulation, a recomputation) within a tolerance, and says
why when they disagree: a known deviation of the paper, or a documented limit of csuas's own
models. :meth:`Check.of_paper` builds one from the paper's value and relative/absolute
tolerances, the form the defaults checks use.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass
class Check:
    """One compared figure.

    Attributes
    ----------
    name : str
        Stable identifier, e.g. ``"T35.gamma_rain.2.4GHz.6mm_h"`` (the report's baseline
        comparison matches on it).
    expected : float
        Oracle, paper or core value.
    measured : float
        Simulated or recomputed value.
    tolerance : float
        Largest accepted ``|measured - expected|`` in ``unit``; the baseline comparison uses
        it as the largest accepted drift of either value.
    unit : str
        Unit of both values.
    error_estimate : float or None
        Estimated error of ``measured`` (standard error, Richardson estimate, quadrature
        error) in ``unit``; None for exact computations.
    known_deviation : str or None
        Explanation when the figure disagrees because the paper deviates (from itself or from
        physics), so that it is reported, not hidden.
    limitation : str or None
        Explanation when the figure disagrees because of a documented limit of csuas's own
        models (e.g. no edge diffraction in SBR-PO); reported apart from the paper's deviations.
    tolerance_source : str
        Where the tolerance comes from (an error estimate times a factor, a printed precision,
        a derived bound); empty: the report spec's ``tolerance_why``.
    time_s : float
        Wall time of the computation that produced the figure [s]; figures computed together
        share that time equally.
    source, method : str
        Where ``expected`` comes from; how ``measured`` is obtained.
    details : dict
        Further numbers (JSON-ready); :meth:`of_paper` keeps its tolerances here.
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

    @classmethod
    def of_paper(
        cls,
        name: str,
        paper: float,
        computed: float,
        unit: str,
        source: str,
        method: str,
        *,
        rel_tol: float = 0.0,
        abs_tol: float = 0.0,
        known_deviation: str | None = None,
        limitation: str | None = None,
        extra: dict | None = None,
    ) -> Check:
        """A check of a printed value: passes when ``|computed - paper| <= max(abs_tol, rel_tol |paper|)``.

        ``extra`` lands in ``details`` beside the tolerances; its ``stderr`` (or ``stderr_m2``)
        becomes the error estimate and its ``time_s`` the time.
        """
        extra = dict(extra or {})
        tolerance = max(abs_tol, rel_tol * abs(paper)) if math.isfinite(paper) else math.nan
        return cls(
            name,
            paper,
            computed,
            tolerance,
            unit,
            error_estimate=extra.get("stderr", extra.get("stderr_m2")),
            known_deviation=known_deviation,
            limitation=limitation,
            time_s=float(extra.get("time_s", 0.0)),
            source=source,
            method=method,
            details={"rel_tol": rel_tol, "abs_tol": abs_tol, **extra},
        )

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

    def as_dict(self) -> dict:
        """JSON form of ``csuas defaults check`` (docs/command-line.md: ``name``, ``paper``, ``computed``, ``ok``)."""
        details = dict(self.details)
        return {
            "name": self.name,
            "paper": self.expected,
            "computed": self.measured,
            "ok": self.ok,
            "unit": self.unit,
            "source": self.source,
            "method": self.method,
            "rel_tol": details.pop("rel_tol", None),
            "abs_tol": details.pop("abs_tol", None),
            "known_deviation": self.known_deviation,
            "limitation": self.limitation,
            **details,
        }
