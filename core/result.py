"""Result records of the range models: the range and every term that was applied."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from csuas.base.errors import ParameterError

#: The two conventions of docs/conventions.md.
CONVENTIONS = ("paper", "physical")


def check_convention(convention: str) -> str:
    """Return ``convention`` if it is one of :data:`CONVENTIONS`, else raise."""

    if convention not in CONVENTIONS:
        raise ParameterError("convention", convention, " or ".join(CONVENTIONS))
    return convention


def unbounded_reason(range_m):
    """Per-element reason of an infinite range (a budget beyond float64), or None when every range is finite."""
    r = np.asarray(range_m)
    if np.all(np.isfinite(r)):
        return None
    return np.where(
        np.isinf(r),
        "unbounded: the link budget exceeds anything a finite range can spend "
        "(check the dB inputs: gains, sensitivity, threshold)",
        "",
    )


@dataclass(frozen=True)
class Term:
    """One contribution to a range prediction.

    Attributes
    ----------
    name : str
        Short identifier, e.g. ``"rain_loss_db"``.
    value : float or ndarray
        Value in ``unit``.
    unit : str
        ``"dB"``, ``"m"``, ``"-"`` (factor), ...
    source : str
        Equation or table of the paper, or the reference used.
    """

    name: str
    value: object
    unit: str
    source: str

    def as_dict(self) -> dict:
        """JSON form."""
        return {"value": self.value, "unit": self.unit, "source": self.source}


@dataclass
class RangeResult:
    """A predicted maximum detection range with the terms that produced it.

    Attributes
    ----------
    range_m : ndarray
        Predicted range [m]; 0 where the target is never detectable.
    modality : str
        ``eo``, ``tir``, ``acoustic``, ``rf``, ``radar`` or ``lidar``.
    model : str
        Model name with its equation, e.g. ``"johnson_ttpf+contrast (Eqs. 18, 21)"``.
    terms : list of Term
        Only the terms that were applied (docs/scenarios.md (effects)).
    reason : ndarray of str
        Per element, empty where detectable, else why the range is 0 or which
        limit applies.
    """

    range_m: np.ndarray
    modality: str
    model: str
    terms: list[Term] = field(default_factory=list)
    reason: np.ndarray | None = None

    def term(self, name: str) -> Term:
        """The applied term called ``name`` (KeyError if it was not applied)."""
        for t in self.terms:
            if t.name == name:
                return t
        raise KeyError(name)

    def as_dict(self) -> dict:
        """JSON form with the keys of docs/command-line.md (``range_m``, ``modality``, ``model``, ``terms``)."""
        out = {
            "range_m": self.range_m,
            "modality": self.modality,
            "model": self.model,
            "terms": {t.name: t.as_dict() for t in self.terms},
        }
        if self.reason is not None and np.any(np.asarray(self.reason) != ""):
            out["reason"] = self.reason
        return out
