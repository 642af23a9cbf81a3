"""Sweep specifications (docs/sweeps.md): TOML in, validated axes and the points they span out.

A spec names a job, a base scenario, a seed and axes::

    job = "range"                # a job of csuas.sweep.kinds.JOB_KINDS: range | pd | render | rcs | engage
    scenario = "default"         # an embedded scenario or a file
    seed = 7
    [axes]
    "target.d_crit_m" = [0.05, 0.101, 0.2]
    "environment.rain_rate_mm_h" = {min = 0.0, max = 50.0, samples = 40}
    "sensors.radar.p_tx_w" = [1.0, 10.0, 100.0]

A list is a grid axis; a table with ``min``, ``max`` and ``samples`` draws that many values
uniformly with the spec's seed (axes drawn in the order written). Axes combine as a full grid,
or element by element with ``combine = "zip"``. Keys are the scenario's canonical names
(``target.X``, ``environment.X``, ``sensors.NAME.X``; ``target.swarm.count`` and ``target.swarm.spacing_m``
of a scenario whose swarm is a line) or a job's own (``range_m``,
``azimuth_deg``, ``elevation_deg`` for renders; ``frequency_ghz``, ``azimuth_deg``,
``elevation_deg`` for RCS). ``[options]`` holds the job's fixed settings. What each job takes and
needs is its :class:`~csuas.sweep.kinds.JobKind`. Every mistake is reported at once, each naming
the key, its value and what is allowed.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from csuas.base.errors import CsuasError, ParameterError, ScenarioError, raise_all
from csuas.base.fileio import read_spec
from csuas.base.schema import validate
from csuas.core.scenario import SWARM_KEYS, Scenario, load_scenario, with_swarm_value
from csuas.defaults import load_parameters, sweep_path
from csuas.defaults.scenario_schema import checked_values
from csuas.sweep.kinds import JOB_KINDS, JobKind, kind_of
from csuas.sweep.schema import MAX_POINTS, TAGS

#: Read from :data:`~csuas.sweep.kinds.JOB_KINDS`: the jobs (``dataset`` is refused, naming ``csuas dataset``),
#: each job's default points per task, own axes, and ``[options]`` with their defaults (docs/sweeps.md).
JOBS = (*JOB_KINDS, "dataset")
CHUNK_POINTS = {job: kind.chunk_points for job, kind in JOB_KINDS.items()}
JOB_AXES = {job: kind.own_axes for job, kind in JOB_KINDS.items()}
JOB_OPTIONS = {job: kind.options().model_dump() for job, kind in JOB_KINDS.items()}
__all__ = ["CHUNK_POINTS", "JOBS", "JOB_AXES", "JOB_OPTIONS", "MAX_POINTS", "SweepSpec", "load_spec", "parse_spec"]


@dataclass
class SweepSpec:
    """A validated sweep.

    Attributes
    ----------
    job : str
    scenario_source : str
        Embedded scenario name or file path.
    scenario : Scenario
        The resolved base scenario.
    seed : int
    combine : {"grid", "zip"}
    axes : dict
        ``{key: ndarray of values}`` (numbers as float, choices as str), in the order written.
    options : dict
        The job's options with defaults filled in.
    chunk_points, recycle_after : int
        Points per task; tasks a simulator worker runs before it is recycled.
    digest : str
        SHA-256 of the spec's content and the scenario's, to tell a resumed sweep from another.
    count : int or None
        The points of a job whose points are not a grid of axes (engage: its runs); None: the axes'.
    context : object
        What the job built from its options before the chunks (engage: the engagement), sent with each task.
    chunk_auto : bool
        The spec gave no ``chunk_points``: the run sizes its chunks from the points and workers, at most
        ``chunk_points`` (:mod:`csuas.sweep.chunking`).
    """

    job: str
    scenario_source: str
    scenario: Scenario
    seed: int
    combine: str
    axes: dict
    options: dict
    chunk_points: int
    recycle_after: int
    digest: str = ""
    count: int | None = None
    context: Any = None
    chunk_auto: bool = False

    @property
    def kind(self) -> JobKind:
        """The job's declaration."""
        return JOB_KINDS[self.job]

    @property
    def n_points(self) -> int:
        """Points of the sweep."""
        if self.count is not None:
            return self.count
        sizes = [len(v) for v in self.axes.values()]
        if not sizes:
            return 1
        return sizes[0] if self.combine == "zip" else math.prod(sizes)

    def points(self, start: int = 0, stop: int | None = None) -> dict:
        """Columns ``{key: values}`` of points ``start..stop`` (grid: last axis fastest)."""
        stop = self.n_points if stop is None else min(stop, self.n_points)
        index = np.arange(start, stop)
        if self.combine == "zip" or not self.axes:
            return {k: v[index] if len(v) else v for k, v in self.axes.items()}
        sizes = [len(v) for v in self.axes.values()]
        positions = np.unravel_index(index, sizes)
        return {k: v[i] for (k, v), i in zip(self.axes.items(), positions)}


def _axis_values(axis, rng) -> list:
    """The values of a validated axis: a list as written, or ``samples`` uniform draws."""
    if isinstance(axis, list):
        return list(axis)
    return list(rng.uniform(axis.min, axis.max, axis.samples))


def _own_axis(kind: JobKind, key: str, values: list):
    lo, hi = kind.own_axes[key]
    for i, v in enumerate(values):
        if isinstance(v, str) or not lo <= v <= hi:
            raise ParameterError(f"axes.{key}.{i}", v, f"a number in [{lo:g}, {hi:g}]")
    return np.asarray(values, dtype=float)


def _parameter_of(kind: JobKind, scenario: Scenario, key: str, values: list) -> dict:
    """The parameter spec (defaults/parameters.toml) an axis key names; ParameterError when none."""
    parts = key.split(".")
    spec = None
    if parts[0] in ("target", "environment") and len(parts) == 2:
        spec = load_parameters()[parts[0]].get(parts[1])
    elif parts[0] == "sensors" and len(parts) == 3 and parts[1] in scenario.sensors:
        spec = load_parameters()[scenario.sensors[parts[1]].modality].get(parts[2])
    if spec is None:
        own = ", ".join(kind.own_axes) or "none"
        raise ParameterError(
            f"axes.{key}",
            values,
            f"target.<param>, environment.<param> or sensors.<name>.<param> (sensors: {', '.join(scenario.sensors)}), "
            f"{' or '.join(SWARM_KEYS)}; "
            f"the job's own axes: {own}",
        )
    if not kind.takes_scenario:
        takes = f"only {', '.join(kind.own_axes)}" if kind.own_axes else "no axes"
        raise ParameterError(f"axes.{key}", values, f"job {kind.name} takes {takes}")
    return spec


def _swarm_axis(kind: JobKind, scenario: Scenario, key: str, values: list):
    """A ``target.swarm.count`` or ``target.swarm.spacing_m`` axis: jobs that take the scenario only, its swarm
    a line of ``count`` drones ``spacing_m`` apart (:func:`csuas.core.scenario.with_swarm_value`)."""
    if not kind.takes_scenario:
        raise ParameterError(f"axes.{key}", values, f"job {kind.name} takes no scenario keys")
    for i, v in enumerate(values):
        with_swarm_value(scenario, key, v, f"axes.{key}.{i}")
    return np.asarray(values, dtype=float)


def _check_axis(kind: JobKind, scenario: Scenario, key: str, values: list):
    """Validated values of one axis, as an array (ParameterError naming the first bad value)."""
    if key in kind.own_axes:
        return _own_axis(kind, key, values)
    if key in SWARM_KEYS:
        return _swarm_axis(kind, scenario, key, values)
    spec = _parameter_of(kind, scenario, key, values)
    checked = checked_values(f"axes.{key}", spec, values)
    return np.asarray(checked, dtype=object if "choices" in spec else float)


def parse_spec(data: dict) -> SweepSpec:
    """Validate a sweep spec's TOML table against its job's schema (:mod:`csuas.sweep.schema`), then its axes
    against the base scenario; every mistake reported at once (exit 2 on the command line)."""
    kind = kind_of(data.get("job") if isinstance(data, dict) else None)
    model = validate(kind.schema, data, tags=TAGS)
    scenario = load_scenario(model.scenario)
    rng = np.random.default_rng(model.seed)
    errors: list[CsuasError] = []
    axes = {}
    for key, axis in model.axes.items():
        try:
            axes[key] = _check_axis(kind, scenario, key, _axis_values(axis, rng))
        except (ParameterError, ScenarioError) as exc:
            errors.append(exc)
    if model.combine == "zip" and len({len(v) for v in axes.values()}) > 1:
        lengths = ", ".join(f"{k} {len(v)}" for k, v in axes.items())
        errors.append(ParameterError("combine", "zip", "axes of equal length: " + lengths))
    options = model.options.model_dump()
    if kind.name == "rcs" and scenario.swarm is not None and options["target"] is None:
        why = "a drone preset: the rcs job traces one drone, and the scenario's target.swarm is a formation"
        errors.append(ParameterError("options.target", None, why + " (csuas rcs --swarm-count N traces one)"))
    raise_all(errors + kind.needs(axes, options, len(scenario.sensors)))
    spec = SweepSpec(
        kind.name,
        model.scenario,
        scenario,
        model.seed,
        model.combine,
        axes,
        options,
        model.chunk_points,
        model.recycle_after,
        chunk_auto="chunk_points" not in data,
    )
    if spec.n_points > MAX_POINTS:
        raise ParameterError("axes", f"{spec.n_points:,} points", f"at most {MAX_POINTS:,} points in one sweep")
    spec.digest = _digest(data, model.scenario)
    return spec if kind.prepare is None else kind.prepare(spec)


def _digest(data: dict, scenario_source: str) -> str:
    text = json.dumps(data, sort_keys=True, default=str)
    path = Path(scenario_source)
    scenario_text = path.read_bytes() if path.is_file() else scenario_source.encode()
    return hashlib.sha256(text.encode() + b"\0" + scenario_text).hexdigest()


def load_spec(source) -> SweepSpec:
    """Load and validate a sweep spec from a TOML file or an embedded spec name (``defaults/sweeps``)."""

    data = read_spec(source, sweep_path, "sweep spec")
    return parse_spec(data)
