"""Sweep specifications (docs/sweeps.md): TOML in, validated axes and the points they span out.

A spec names a job, a base scenario, a seed and axes::

    job = "range"                # range | pd | render | rcs | dataset
    scenario = "default"         # an embedded scenario or a file
    seed = 7
    [axes]
    "target.d_crit_m" = [0.05, 0.101, 0.2]
    "environment.rain_rate_mm_h" = {min = 0.0, max = 50.0, samples = 40}
    "sensors.radar.p_tx_w" = [1.0, 10.0, 100.0]

A list is a grid axis; a table with ``min``, ``max`` and ``samples`` draws that many values
uniformly with the spec's seed (axes drawn in the order written). Axes combine as a full grid,
or element by element with ``combine = "zip"``. Keys are the scenario's canonical names
(``target.X``, ``environment.X``, ``sensors.NAME.X``) or a job's own (``range_m``,
``azimuth_deg``, ``elevation_deg`` for renders; ``frequency_ghz``, ``azimuth_deg``,
``elevation_deg`` for RCS). ``[options]`` holds the job's fixed settings. Every mistake is
reported at once, each naming the key, its value and what is allowed.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from csuas.base.errors import CsuasError, ParameterError, ScenarioError, raise_all
from csuas.base.schema import validate
from csuas.core.scenario import Scenario, load_scenario
from csuas.defaults import load_parameters
from csuas.defaults.scenario_schema import checked_values
from csuas.sweep.schema import CHUNK_POINTS, JOB_AXES, MAX_POINTS, SCHEMAS, TAGS

JOBS = ("range", "pd", "render", "rcs", "dataset")
#: Whether a job takes the scenario's parameters as axes.
TAKES_SCENARIO = {"range": True, "pd": True, "render": True, "rcs": False}
#: Options a job accepts in ``[options]``, with their defaults (from the schema, docs/sweeps.md).
JOB_OPTIONS = {job: model.model_fields["options"].default.model_dump() for job, model in SCHEMAS.items()}
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

    @property
    def n_points(self) -> int:
        """Points of the sweep."""
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


def point_seed(seed: int, index) -> np.ndarray:
    """Seed of each point: from the spec's seed and the point's index alone, so any scheduler agrees."""
    idx = np.atleast_1d(np.asarray(index, dtype=np.int64))
    return np.array([np.random.SeedSequence([seed, int(i)]).generate_state(1)[0] for i in idx], dtype=np.int64)


def _axis_values(axis, rng) -> list:
    """The values of a validated axis: a list as written, or ``samples`` uniform draws."""
    if isinstance(axis, list):
        return list(axis)
    return list(rng.uniform(axis.min, axis.max, axis.samples))


def _own_axis(job: str, key: str, values: list):
    lo, hi = JOB_AXES[job][key]
    for i, v in enumerate(values):
        if isinstance(v, str) or not lo <= v <= hi:
            raise ParameterError(f"axes.{key}.{i}", v, f"a number in [{lo:g}, {hi:g}]")
    return np.asarray(values, dtype=float)


def _parameter_of(job: str, scenario: Scenario, key: str, values: list) -> dict:
    """The parameter spec (defaults/parameters.toml) an axis key names; ParameterError when none."""
    parts = key.split(".")
    spec = None
    if parts[0] in ("target", "environment") and len(parts) == 2:
        spec = load_parameters()[parts[0]].get(parts[1])
    elif parts[0] == "sensors" and len(parts) == 3 and parts[1] in scenario.sensors:
        spec = load_parameters()[scenario.sensors[parts[1]].modality].get(parts[2])
    if spec is None:
        own = ", ".join(JOB_AXES.get(job, {})) or "none"
        raise ParameterError(
            f"axes.{key}",
            values,
            f"target.<param>, environment.<param> or sensors.<name>.<param> (sensors: {', '.join(scenario.sensors)}); "
            f"the job's own axes: {own}",
        )
    if not TAKES_SCENARIO[job]:
        raise ParameterError(f"axes.{key}", values, f"job {job} takes only {', '.join(JOB_AXES[job])}")
    return spec


def _check_axis(job: str, scenario: Scenario, key: str, values: list):
    """Validated values of one axis, as an array (ParameterError naming the first bad value)."""
    if key in JOB_AXES[job]:
        return _own_axis(job, key, values)
    spec = _parameter_of(job, scenario, key, values)
    checked = checked_values(f"axes.{key}", spec, values)
    return np.asarray(checked, dtype=object if "choices" in spec else float)


def _job_of(data) -> str:
    """The spec's job, checked before the schema that depends on it."""
    job = data.get("job") if isinstance(data, dict) else None
    if job == "dataset":
        raise ParameterError(
            "job", job, "range, pd, render or rcs: datasets are made by csuas dataset SPEC --out DIR (one process)"
        )
    if not isinstance(job, str) or job not in SCHEMAS:
        raise ParameterError("job", job, ", ".join(SCHEMAS))
    return job


def _needed_axes(job: str, axes: dict, options: dict, sensors: int) -> list:
    """What the job needs beside its schema: its ranges or frequencies, a k-of-n fusion's k <= the sensors."""
    errors = []
    fusion = options.get("fusion", "or")
    if fusion != "or" and int(fusion.partition(":")[2]) > sensors:
        errors.append(ParameterError("options.fusion", fusion, f"or, or k-of-n:K with K 1 to {sensors} (the sensors)"))
    if job == "render" and "range_m" not in axes and options["range_m"] is None:
        errors.append(ParameterError("axes.range_m", None, "an axis or options.range_m: the render job needs ranges"))
    if job == "rcs" and "frequency_ghz" not in axes:
        errors.append(ParameterError("axes.frequency_ghz", None, "an axis: the rcs job needs frequencies"))
    return errors


def parse_spec(data: dict) -> SweepSpec:
    """Validate a sweep spec's TOML table against its job's schema (:mod:`csuas.sweep.schema`), then its axes
    against the base scenario; every mistake reported at once (exit 2 on the command line)."""
    job = _job_of(data)
    model = validate(SCHEMAS[job], data, tags=TAGS)
    scenario = load_scenario(model.scenario)
    rng = np.random.default_rng(model.seed)
    errors: list[CsuasError] = []
    axes = {}
    for key, axis in model.axes.items():
        try:
            axes[key] = _check_axis(job, scenario, key, _axis_values(axis, rng))
        except (ParameterError, ScenarioError) as exc:
            errors.append(exc)
    if model.combine == "zip" and len({len(v) for v in axes.values()}) > 1:
        lengths = ", ".join(f"{k} {len(v)}" for k, v in axes.items())
        errors.append(ParameterError("combine", "zip", "axes of equal length: " + lengths))
    options = model.options.model_dump()
    raise_all(errors + _needed_axes(job, axes, options, len(scenario.sensors)))
    spec = SweepSpec(
        job, model.scenario, scenario, model.seed, model.combine, axes, options, model.chunk_points, model.recycle_after
    )
    if spec.n_points > MAX_POINTS:
        raise ParameterError("axes", f"{spec.n_points:,} points", f"at most {MAX_POINTS:,} points in one sweep")
    spec.digest = _digest(data, model.scenario)
    return spec


def _digest(data: dict, scenario_source: str) -> str:
    text = json.dumps(data, sort_keys=True, default=str)
    path = Path(scenario_source)
    scenario_text = path.read_bytes() if path.is_file() else scenario_source.encode()
    return hashlib.sha256(text.encode() + b"\0" + scenario_text).hexdigest()


def load_spec(source) -> SweepSpec:
    """Load and validate a sweep spec from a TOML file or an embedded spec name (``defaults/sweeps``)."""
    from csuas.base.fileio import read_spec
    from csuas.defaults import sweep_path

    data = read_spec(source, sweep_path, "sweep spec")
    return parse_spec(data)
