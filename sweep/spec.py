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
import sys
from dataclasses import dataclass
from pathlib import Path

if sys.version_info >= (3, 11):
    pass
else:  # pragma: no cover
    pass

import numpy as np

from csuas.base.errors import CsuasError, ParameterError, ScenarioError, raise_all
from csuas.core.scenario import Scenario, check_value, load_scenario
from csuas.defaults import load_parameters

JOBS = ("range", "pd", "render", "rcs", "dataset")
#: Axes a job takes besides the scenario's parameters: name -> (lowest, highest) allowed.
JOB_AXES = {
    "range": {},
    "pd": {},
    "render": {"range_m": (1e-3, 1e7), "azimuth_deg": (-360.0, 360.0), "elevation_deg": (-90.0, 90.0)},
    "rcs": {"frequency_ghz": (1e-3, 1e4), "azimuth_deg": (-360.0, 360.0), "elevation_deg": (-90.0, 90.0)},
}
#: Whether a job takes the scenario's parameters as axes.
TAKES_SCENARIO = {"range": True, "pd": True, "render": True, "rcs": False}
#: Options a job accepts in ``[options]``, with their defaults.
JOB_OPTIONS = {
    "range": {"convention": None},
    "pd": {"convention": None, "fusion": "or"},
    "render": {"mode": "eo", "quality": "draft", "range_m": None, "azimuth_deg": 0.0, "elevation_deg": 0.0},
    "rcs": {"target": None, "quality": "draft", "rays_per_wavelength": None, "azimuth_deg": 0.0, "elevation_deg": 0.0},
}
#: Points per task: analytic points go to the core in large NumPy chunks, simulator points in small groups.
CHUNK_POINTS = {"range": 1_000_000, "pd": 32, "render": 4, "rcs": 16}
TOP_KEYS = ("job", "scenario", "seed", "combine", "axes", "options", "chunk_points", "recycle_after")
#: Most points one sweep may hold.
MAX_POINTS = 100_000_000


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


def _axis_values(key: str, raw, seed_rng, errors: list):
    if isinstance(raw, list):
        if not raw:
            errors.append(ParameterError(f"axes.{key}", raw, "a non-empty list, or {min, max, samples}"))
            return None
        return list(raw)
    if isinstance(raw, dict):
        unknown = set(raw) - {"min", "max", "samples"}
        lo, hi, n = raw.get("min"), raw.get("max"), raw.get("samples")
        numbers = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in (lo, hi, n))
        if unknown or not numbers or not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi or n != int(n) or n < 1:
            errors.append(
                ParameterError(
                    f"axes.{key}", raw, "{min = LOW, max = HIGH, samples = N} with LOW <= HIGH finite, N >= 1"
                )
            )
            return None
        return list(seed_rng.uniform(float(lo), float(hi), int(n)))
    errors.append(ParameterError(f"axes.{key}", raw, "a list of values or {min, max, samples}"))
    return None


def _check_axis(job: str, scenario: Scenario, key: str, values: list, errors: list):
    """Validated values of one axis, as an array; None (and an error) when the key or a value is wrong."""
    params = load_parameters()
    if key in JOB_AXES.get(job, {}):
        lo, hi = JOB_AXES[job][key]
        bad = [v for v in values if isinstance(v, bool) or not isinstance(v, (int, float)) or not lo <= v <= hi]
        if bad:
            errors.append(ParameterError(f"axes.{key}", bad[0], f"numbers in [{lo:g}, {hi:g}]"))
            return None
        return np.asarray(values, dtype=float)
    parts = key.split(".")
    spec = None
    if parts[0] in ("target", "environment") and len(parts) == 2:
        spec = params[parts[0]].get(parts[1])
    elif parts[0] == "sensors" and len(parts) == 3 and parts[1] in scenario.sensors:
        spec = params[scenario.sensors[parts[1]].modality].get(parts[2])
    if spec is None:
        own = ", ".join(JOB_AXES.get(job, {})) or "none"
        sensors = ", ".join(scenario.sensors)
        errors.append(
            ParameterError(
                "axes",
                key,
                f"target.<param>, environment.<param> or sensors.<name>.<param> (sensors: {sensors}); "
                f"the job's own axes: {own}",
            )
        )
        return None
    if not TAKES_SCENARIO.get(job, True):
        errors.append(ParameterError("axes", key, f"job {job} takes only {', '.join(JOB_AXES[job])}"))
        return None
    try:
        checked = [check_value(f"axes.{key}", spec, v) for v in values]
    except ScenarioError as exc:
        errors.append(exc)
        return None
    return np.asarray(checked, dtype=object if "choices" in spec else float)


def parse_spec(data: dict) -> SweepSpec:
    """Validate a sweep spec's TOML table; every mistake reported at once (exit 2 on the command line)."""
    errors: list[CsuasError] = []
    for key in sorted(set(data) - set(TOP_KEYS)):
        errors.append(ParameterError(key, data[key], "a key of a sweep spec: " + ", ".join(TOP_KEYS)))
    job = data.get("job")
    if job not in JOBS:
        raise_all([*errors, ParameterError("job", job, ", ".join(JOBS))])
    if job == "dataset":
        raise ParameterError(
            "job", job, "range, pd, render or rcs: datasets are made by csuas dataset SPEC --out DIR (one process)"
        )
    seed = data.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        errors.append(ParameterError("seed", seed, "a whole number >= 0"))
        seed = 0
    combine = data.get("combine", "grid")
    if combine not in ("grid", "zip"):
        errors.append(ParameterError("combine", combine, "grid or zip"))
    source_name = data.get("scenario", "default")
    scenario = load_scenario(source_name)
    options = dict(JOB_OPTIONS[job])
    given = data.get("options", {})
    if not isinstance(given, dict):
        errors.append(ParameterError("options", given, "a table"))
        given = {}
    for key in sorted(set(given) - set(options)):
        errors.append(ParameterError(f"options.{key}", given[key], "one of " + ", ".join(options)))
    options.update({k: v for k, v in given.items() if k in options})
    raw_axes = data.get("axes", {})
    if not isinstance(raw_axes, dict):
        raise_all([*errors, ParameterError("axes", raw_axes, "a table of axes")])
    rng = np.random.default_rng(seed)
    axes = {}
    for key, raw in raw_axes.items():
        values = _axis_values(key, raw, rng, errors)
        if values is not None:
            checked = _check_axis(job, scenario, key, values, errors)
            if checked is not None:
                axes[key] = checked
    if combine == "zip" and len({len(v) for v in axes.values()}) > 1:
        errors.append(
            ParameterError(
                "combine", "zip", "axes of equal length: " + ", ".join(f"{k} {len(v)}" for k, v in axes.items())
            )
        )
    if job == "render" and "range_m" not in axes and options["range_m"] is None:
        errors.append(ParameterError("axes.range_m", None, "an axis or options.range_m: the render job needs ranges"))
    if job == "rcs" and "frequency_ghz" not in axes:
        errors.append(ParameterError("axes.frequency_ghz", None, "an axis: the rcs job needs frequencies"))
    chunk = data.get("chunk_points", CHUNK_POINTS[job])
    recycle = data.get("recycle_after", 50)
    for name, value in (("chunk_points", chunk), ("recycle_after", recycle)):
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            errors.append(ParameterError(name, value, "a whole number >= 1"))
    raise_all(errors)
    spec = SweepSpec(job, str(source_name), scenario, int(seed), combine, axes, options, int(chunk), int(recycle))
    if spec.n_points > MAX_POINTS:
        raise ParameterError("axes", f"{spec.n_points:,} points", f"at most {MAX_POINTS:,} points in one sweep")
    spec.digest = _digest(data, source_name)
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
