"""Sample budgets of the Sionna RT link solvers: the accuracy knob and its presets.

Sionna RT finds propagation paths in two steps: rays shot from each source
(Fibonacci lattice, ``samples`` of them) give candidate sequences of hit
primitives, then the image method computes each candidate's exact path on
the planes of those primitives and tests the segments for obstruction; the
line-of-sight path is always tested directly. A budget is therefore exact as
soon as every relevant plane is hit by one ray: over one flat ground, 3 rays
already find every ground reflection (measured; a single ray finds only the
line of sight), and more samples only cost time. ``max_depth`` bounds the
number of interactions; over one flat ground no path has more than one
bounce, so depth 1 is exact there, and in free space the presets run at
depth 0 (line of sight only: there is nothing to hit). The presets keep a
margin of samples for scenes with more than one surface.

Measured accuracy and time of each preset: :func:`csuas.validation.links.accuracy.accuracy_vs_time`.
"""

from __future__ import annotations

from dataclasses import dataclass

from csuas.base.errors import ParameterError
from csuas.render.quality import LINKS


@dataclass(frozen=True)
class LinkBudget:
    """Sample budget of one Sionna RT solver call.

    Attributes
    ----------
    name : str
        Preset name, or ``"custom"``.
    samples : int
        Rays shot per source (``samples_per_src`` of ``PathSolver``,
        ``samples_per_sp`` of ``RCSSolver``).
    max_depth : int
        Maximum number of interactions per path (for ``RCSSolver`` the
        scattering on the target counts as one).
    """

    name: str
    samples: int
    max_depth: int


#: Presets from :data:`csuas.render.quality.LINKS`, cheapest first.
PRESETS = LINKS.presets(LinkBudget)

#: Sionna RT 2.2's own defaults (``PathSolver.__call__``: samples_per_src=1e6, max_depth=3).
SIONNA_DEFAULT = LinkBudget("sionna_default", samples=1_000_000, max_depth=3)


def resolve_budget(budget="standard", samples=None, max_depth=None) -> LinkBudget:
    """Turn a preset name or a :class:`LinkBudget`, with optional overrides, into a budget.

    Parameters
    ----------
    budget : str or LinkBudget
        ``"draft"``, ``"standard"``, ``"reference"``, ``"sionna_default"`` or a budget (its
        samples and depth checked as the overrides are).
    samples : int, optional
        Overrides the rays per source (>= 1).
    max_depth : int, optional
        Overrides the maximum depth (0 to 10; 0 = line of sight only).

    Returns
    -------
    LinkBudget

    Raises
    ------
    ParameterError
        An unknown preset, or samples or a depth out of range, named.
    """
    if isinstance(budget, LinkBudget):
        base = LinkBudget(budget.name, _checked_samples(budget.samples), _checked_depth(budget.max_depth))
    elif budget == SIONNA_DEFAULT.name:
        base = SIONNA_DEFAULT
    elif budget in PRESETS:
        base = PRESETS[budget]
    else:
        raise ParameterError("budget", budget, ", ".join([*PRESETS, SIONNA_DEFAULT.name]) + " or a LinkBudget")
    if samples is not None:
        base = LinkBudget("custom", _checked_samples(samples), base.max_depth)
    if max_depth is not None:
        base = LinkBudget("custom", base.samples, _checked_depth(max_depth))
    return base


def _checked_samples(samples) -> int:
    """Rays per source, an integer from 1 to 1e8."""
    if isinstance(samples, bool) or int(samples) != samples or not 1 <= samples <= 100_000_000:
        raise ParameterError("samples", samples, "an integer from 1 to 1e8")
    return int(samples)


def _checked_depth(max_depth) -> int:
    """Maximum interactions per path, an integer from 0 to 10."""
    if isinstance(max_depth, bool) or int(max_depth) != max_depth or not 0 <= max_depth <= 10:
        raise ParameterError("max_depth", max_depth, "an integer from 0 to 10")
    return int(max_depth)
