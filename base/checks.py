"""Comparison records shared by ``csuas defaults check`` and ``csuas report``."""

from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Check:
    """One comparison of a stated value with an independent computation.

    Attributes
    ----------
    name : str
        Stable identifier, e.g. ``"T35.gamma_rain.2.4GHz.6mm_h"``.
    paper : float
        Value printed in the paper (or the reference value).
    computed : float
        Value recomputed by csuas.
    unit : str
        Unit of both values.
    rel_tol, abs_tol : float
        Tolerances; the check passes when
        ``|computed - paper| <= max(abs_tol, rel_tol * |paper|)``.
    source : str
        Where the paper value comes from (table / equation number).
    method : str
        How the computed value is obtained.
    known_deviation : str or None
        Explanation when the paper disagrees with itself or with physics; a
        failing check with a known deviation is reported, not hidden.
    limitation : str or None
        Explanation when the disagreement comes from a documented limit of
        csuas's own models rather than from the paper.
    """

    name: str
    paper: float
    computed: float
    unit: str
    source: str
    method: str
    rel_tol: float = 0.0
    abs_tol: float = 0.0
    known_deviation: str | None = None
    limitation: str | None = None
    extra: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """True when the computed value agrees with the paper value within tolerance."""
        if not (math.isfinite(self.paper) and math.isfinite(self.computed)):
            return False
        return abs(self.computed - self.paper) <= max(self.abs_tol, self.rel_tol * abs(self.paper))

    def as_dict(self) -> dict:
        """JSON form with the keys of docs/command-line.md (``name``, ``paper``, ``computed``, ``ok``)."""
        return {
            "name": self.name,
            "paper": self.paper,
            "computed": self.computed,
            "ok": self.ok,
            "unit": self.unit,
            "source": self.source,
            "method": self.method,
            "rel_tol": self.rel_tol,
            "abs_tol": self.abs_tol,
            "known_deviation": self.known_deviation,
            "limitation": self.limitation,
            **self.extra,
        }
