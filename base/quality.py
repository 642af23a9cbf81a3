"""The quality ladder: the three rungs every simulator offers, and one record per simulator of what each sets.

Every simulator of csuas trades accuracy for time with the same three rungs, cheapest first:
``draft`` (a quick look, and the sweeps' and datasets' default), ``standard`` (the commands' default) and
``reference`` (the accuracy the oracles are judged with). A simulator declares its ladder once, as one
:class:`QualityLadder` beside the code that reads it: the knobs it sets (:class:`Setting`) and their values on
each rung. The lists of rung names (command-line choices, the sweep and dataset schemas), the presets the
simulators resolve and the table of docs/simulation.md ("Quality ladders", written by
``python -m csuas.schema_docs``) are derived from those records; ``tests/test_quality_ladder.py`` checks that
no other list of rung names is typed.

The ladders of the simulators are listed in :data:`csuas.render.quality.LADDERS`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields

from csuas.base.errors import ParameterError

#: The rungs of every ladder, cheapest first.
RUNGS = ("draft", "standard", "reference")

#: The rungs as an error message and the docs say them.
RUNGS_TEXT = f"{', '.join(RUNGS[:-1])} or {RUNGS[-1]}"


@dataclass(frozen=True)
class Setting:
    """A knob a rung sets.

    Attributes
    ----------
    name : str
        Its name (the keyword or attribute the simulator reads).
    meaning : str
        What it sets, with its unit in brackets where it has one.
    """

    name: str
    meaning: str


@dataclass(frozen=True)
class QualityLadder:
    """The quality ladder of one simulator: the knobs it sets and their values on each rung.

    Attributes
    ----------
    simulator : str
        The simulator, as the docs name it.
    where : str
        The module or function that reads the ladder, and the commands, sweeps and checks that use it.
    settings : tuple of Setting
        The knobs each rung sets, in the order of the rung tuples.
    draft, standard, reference : tuple
        The knobs' values on each rung (one value per setting).
    summary : callable(dict) -> str, optional
        One line of what a rung buys from its knob values (``"32 samples per pixel"``); by default the
        knobs spelled out.
    """

    simulator: str
    where: str
    settings: tuple
    draft: tuple
    standard: tuple
    reference: tuple
    summary: Callable | None = None

    def __post_init__(self):
        names = tuple(f.name for f in fields(self) if f.name in RUNGS)
        if names != RUNGS:  # the rungs are this record's fields; RUNGS names them for everyone else
            raise TypeError(f"QualityLadder's rung fields {names} differ from RUNGS {RUNGS}")
        for rung in RUNGS:
            if len(getattr(self, rung)) != len(self.settings):
                raise TypeError(
                    f"{self.simulator}: rung {rung} has {len(getattr(self, rung))} values for "
                    f"{len(self.settings)} settings ({', '.join(s.name for s in self.settings)})"
                )

    @property
    def names(self) -> tuple:
        """The rung names, cheapest first (:data:`RUNGS`)."""
        return RUNGS

    def values(self, rung: str, parameter: str = "quality") -> dict:
        """``{setting: value}`` of one rung.

        Raises
        ------
        ParameterError
            ``rung`` is not one of :data:`RUNGS` (named ``parameter``).
        """
        check_rung(rung, parameter)
        return dict(zip((s.name for s in self.settings), getattr(self, rung)))

    def presets(self, build: Callable = lambda name, **values: tuple(values.values())) -> dict:
        """``{rung: build(rung, **values)}`` for every rung, cheapest first (by default the tuple of values)."""
        return {rung: build(rung, **self.values(rung)) for rung in RUNGS}

    def describe(self, rung: str) -> str:
        """One line of what ``rung`` sets: its :attr:`summary`, or the knobs spelled out."""
        values = self.values(rung)
        if self.summary is not None:
            return self.summary(values)
        return ", ".join(f"{name} {_number(value)}" for name, value in values.items())

    def help_text(self) -> str:
        """``draft 32 samples per pixel; standard ...``: the rungs for a command's ``--help``."""
        return "; ".join(f"{rung} {self.describe(rung)}" for rung in RUNGS)

    def per_rung(self, **values) -> dict:
        """``{rung: value}`` of a figure measured or chosen per rung (a cost, an error), checked to name every
        rung of the ladder once and nothing else.

        Raises
        ------
        TypeError
            A rung missing or a name that is not a rung (a mistake of the code, found on import).
        """
        if tuple(values) != RUNGS:
            raise TypeError(f"{self.simulator}: per-rung values for {tuple(values)}, not the rungs {RUNGS}")
        return dict(values)

    def rung_cell(self, rung: str) -> str:
        """What ``rung`` sets as the docs table shows it: its summary, then each knob's value."""
        knobs = ", ".join(f"`{name}` {_number(value)}" for name, value in self.values(rung).items())
        return f"{self.describe(rung)} ({knobs})" if self.summary is not None else knobs


def ladders_table(ladders) -> str:
    """The Markdown table of docs/simulation.md "Quality ladders": one row per simulator, what each rung sets.

    Parameters
    ----------
    ladders : iterable of QualityLadder
    """
    lines = ["| simulator | knobs | " + " | ".join(RUNGS) + " | used by |", "|---" * (len(RUNGS) + 3) + "|"]
    for ladder in ladders:
        knobs = "; ".join(f"`{s.name}`: {s.meaning}" for s in ladder.settings)
        cells = " | ".join(ladder.rung_cell(rung) for rung in RUNGS)
        lines.append(f"| {ladder.simulator} | {knobs} | {cells} | {ladder.where} |")
    return "\n".join(lines)


def _number(value) -> str:
    """``16,384`` for a whole number, ``2.5`` for a float."""
    return f"{value:,}" if isinstance(value, int) else f"{value:g}"


def check_rung(rung, parameter: str = "quality") -> str:
    """``rung`` when it is one of :data:`RUNGS`.

    Raises
    ------
    ParameterError
        Otherwise, naming ``parameter`` and the rungs.
    """
    if not isinstance(rung, str) or rung not in RUNGS:
        raise ParameterError(parameter, rung, ", ".join(RUNGS))
    return rung
