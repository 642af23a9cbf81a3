"""What one task of a sweep computes: a chunk of points of one job, as result columns.

* ``range``: vectorised. The chunk's points are grouped by the values the models branch on
  (which effects are present, heights and altitudes, text choices, derived Johnson values); each
  group goes to :func:`csuas.core.ranges.evaluate` once with its other axes as arrays, so 10^6
  points are a few NumPy calls, not 10^6 evaluations.
* ``pd``: per point, :func:`csuas.core.pd_curves.sensor_pd` on the scenario's default grid.
* ``render``: per point, the scenario render modes (Mitsuba), kernels kept warm by the worker.
* ``rcs``: SBR-PO, one call per frequency for all the chunk's aspects (the engine is cached by
  the worker process).

Every chunk function returns ``{column: array}`` aligned with the chunk's points, its columns
those its job declares (the ``*_columns`` function beside it); :func:`csuas.sweep.run.run_chunk`
adds the points, their axes and ``time_s`` (the chunk's wall time shared equally). The jobs are
declared, each once, in :mod:`csuas.sweep.kinds`.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from csuas.core.pd_curves import REPORTED_PD, default_range_grid, fused_pd_of_range, range_at_pd, sensor_pd
from csuas.core.range_notes import sensor_notes
from csuas.core.ranges import evaluate
from csuas.core.scenario import SWARM_KEYS, Scenario, johnson_derived, with_swarm_value
from csuas.core.swarm_detection import swarm_range
from csuas.defaults import load_parameters

from .schema import RENDER_AXES

if TYPE_CHECKING:
    from .spec import SweepSpec

#: Environment parameters the models branch on, with the predicate that decides the branch.
EFFECT_PREDICATES = {
    "environment.rain_rate_mm_h": lambda v: v > 0,
    "environment.lwc_g_m3": lambda v: v > 0,
    "environment.wind_speed_m_s": lambda v: v >= 1.0,
    "environment.illuminance_lx": lambda v: v < 400.0,
}
#: Parameters read as scalars (by a branch or a derivation): points are grouped by their value.
SCALAR_NAMES = ("altitude_m", "height_m", "p_desired", "task", "fog_visibility_m")


@dataclass
class _FixedEffects(Scenario):
    """A scenario whose parameters may be arrays; its effects are those of the group's points."""

    group_effects: frozenset = frozenset()

    @property
    def effects(self) -> frozenset:  # type: ignore[override]
        return self.group_effects


def point_seed(seed: int, index) -> np.ndarray:
    """Seed of each point: from the spec's seed and the point's index alone, so any scheduler agrees."""
    idx = np.atleast_1d(np.asarray(index, dtype=np.int64))
    return np.array([np.random.SeedSequence([seed, int(i)]).generate_state(1)[0] for i in idx], dtype=np.int64)


def with_values(scenario: Scenario, values: dict) -> Scenario:
    """A copy of ``scenario`` with canonical parameters set (scalars or arrays), marked explicit; the swarm keys
    (:data:`csuas.core.scenario.SWARM_KEYS`, scalars) set its line formation.

    Derived values follow as the scenario loader derives them: ``n_ttpf`` from ``p_desired``
    (Table 21) and ``lp_task`` from ``task`` (Table 20) unless given.
    """
    target, environment = dict(scenario.target), dict(scenario.environment)
    explicit = {k: set(v) for k, v in scenario.explicit.items()}
    sensors = dict(scenario.sensors)
    swarm = {key: values[key] for key in SWARM_KEYS if key in values}
    for key, value in values.items():
        parts = key.split(".")
        if key in swarm:
            continue
        if parts[0] == "target":
            target[parts[1]] = value
            explicit["target"].add(parts[1])
        elif parts[0] == "environment":
            environment[parts[1]] = value
            explicit["environment"].add(parts[1])
        else:
            sensor = sensors[parts[1]]
            params = dict(sensor.params, **{parts[2]: value})
            if parts[2] in ("p_desired", "task"):
                params.update(johnson_derived(params, sensor.explicit))
            sensors[parts[1]] = replace(sensor, params=params, explicit=sensor.explicit | {parts[2]})
    out = replace(scenario, target=target, environment=environment, sensors=sensors, explicit=explicit)
    for key, value in swarm.items():  # a line formation's count or spacing, one value a point (scalar)
        out = with_swarm_value(out, key, value)
    return out


def _is_scalar(scenario: Scenario, key: str) -> bool:
    """Whether the models read this parameter as a scalar: text choices, whole numbers, SCALAR_NAMES."""
    if key in SWARM_KEYS:
        return True
    parts = key.split(".")
    section = scenario.sensors[parts[1]].modality if parts[0] == "sensors" else parts[0]
    spec = load_parameters()[section][parts[-1]]
    return "choices" in spec or parts[-1] in SCALAR_NAMES or isinstance(spec.get("value"), int)


def warm_first_point(spec: SweepSpec) -> None:
    """Compute the sweep's first point and drop it: a worker imports the job's modules and compiles its
    kernels (Dr.Jit's, the SBR engine of the target) before its first chunk (:class:`csuas.sweep.warm.WarmUp`)."""
    spec.kind.chunk(spec, spec.points(0, 1), 0, 1)


def range_columns(spec: SweepSpec) -> list[str]:
    """Columns of the ``range`` job: ``range_m.SENSOR`` [m] of every sensor of the scenario (one drone's), then
    its :func:`swarm_columns` and :func:`explanation_columns`."""
    return [f"range_m.{name}" for name in spec.scenario.sensors] + swarm_columns(spec) + explanation_columns(spec)


def swarm_columns(spec: SweepSpec) -> list[str]:
    """With the scenario's ``target.swarm``: ``swarm_first_detection_m.SENSOR`` [m] (the longest range at which
    any resolved group is detected) and ``swarm_resolved_count.SENSOR`` (the groups there) of every sensor, as
    ``csuas range --json``'s ``sensors.SENSOR.swarm`` reports them; none without a swarm."""
    if spec.scenario.swarm is None:
        return []
    names = list(spec.scenario.sensors)
    return [f"swarm_first_detection_m.{n}" for n in names] + [f"swarm_resolved_count.{n}" for n in names]


def _swarm_point(out: dict, i: int, scenario: Scenario, convention) -> None:
    """Write point ``i``'s :func:`swarm_columns` from ``scenario`` (that point's scalar values)."""
    if scenario.swarm is None:
        return
    for name in scenario.sensors:
        figures = swarm_range(scenario, name, convention or scenario.convention)
        out[f"swarm_first_detection_m.{name}"][i] = figures["first_detection_m"]
        out[f"swarm_resolved_count.{name}"][i] = figures["resolved_count"]


def explanation_columns(spec: SweepSpec) -> list[str]:
    """``reason.SENSOR`` (why a range is zero, short, unbounded or capped; empty when none) and ``notes.SENSOR``
    (the sensor's notes, one a line; empty when none) of every sensor, as ``csuas range`` reports them."""
    names = list(spec.scenario.sensors)
    return [f"reason.{name}" for name in names] + [f"notes.{name}" for name in names]


def _explain(out: dict, idx, scenario: Scenario, results: dict) -> None:
    """Write the ``reason.SENSOR`` and ``notes.SENSOR`` of points ``idx`` from their range results."""
    for name, result in results.items():
        reason = "" if result.reason is None else result.reason
        out[f"reason.{name}"][idx] = np.broadcast_to(np.asarray(reason, dtype=object), np.shape(idx))
        sensor = scenario.sensors[name]
        out[f"notes.{name}"][idx] = "\n".join(sensor_notes(sensor.modality, sensor.preset, sensor.explicit))


def _empty_columns(names: list[str], n: int) -> dict:
    """NaN columns of ``n`` points, text (empty) for the reason and notes columns."""
    text = ("reason.", "notes.")
    return {c: np.full(n, "", dtype=object) if c.startswith(text) else np.full(n, np.nan) for c in names}


def range_chunk(spec: SweepSpec, columns: dict) -> dict:
    """Range of every sensor at each point of the chunk (vectorised by groups)."""
    scenario = spec.scenario
    n = len(next(iter(columns.values()))) if columns else 1
    codes = []
    for key, values in columns.items():
        if key in EFFECT_PREDICATES:
            codes.append(EFFECT_PREDICATES[key](np.asarray(values, float)).astype(np.int64))
        elif _is_scalar(scenario, key):
            codes.append(np.unique(values, return_inverse=True)[1].astype(np.int64))
    if codes:
        group = np.unique(np.stack(codes), axis=1, return_inverse=True)[1].reshape(-1)
    else:
        group = np.zeros(n, dtype=np.int64)
    out = _empty_columns(range_columns(spec), n)
    for g in np.unique(group):
        idx = np.nonzero(group == g)[0]
        first = with_values(scenario, {k: v[idx[0]] for k, v in columns.items()})
        values = {k: v[idx[0]] if _is_scalar(scenario, k) else np.asarray(v[idx], float) for k, v in columns.items()}
        batch = with_values(scenario, values)
        batch = _FixedEffects(**{f: getattr(batch, f) for f in batch.__dataclass_fields__}, group_effects=first.effects)
        results = evaluate(batch, spec.options.get("convention"))
        for name, result in results.items():
            out[f"range_m.{name}"][idx] = np.broadcast_to(np.asarray(result.range_m, float), idx.shape)
        _explain(out, idx, batch, results)
    for i in range(n) if scenario.swarm is not None else ():  # the swarm's groups are found point by point
        point = with_values(scenario, {k: v[i] for k, v in columns.items()})
        _swarm_point(out, i, point, spec.options.get("convention"))
    return out


def _sensor_pd_of_range(scenario, name: str, convention):
    return lambda r: sensor_pd(scenario, name, r, convention).pd


def pd_columns(spec: SweepSpec) -> list[str]:
    """Columns of the ``pd`` job: ranges at each reported Pd of every sensor and fused [m], then each sensor's Pd
    at its deterministic range."""
    names = list(spec.scenario.sensors)
    ranges = [f"range_at_pd_{p:g}.{name}" for name in [*names, "fused"] for p in REPORTED_PD]
    at_range = [f"pd_at_deterministic_range.{name}" for name in names]
    return ranges + at_range + swarm_columns(spec) + explanation_columns(spec)


def pd_chunk(spec: SweepSpec, columns: dict) -> dict:
    """Per point: each sensor's Pd at its deterministic range and its ranges at Pd 0.5 and 0.9, and fused; the
    reason and notes of each sensor's deterministic range (:func:`explanation_columns`)."""
    n = len(next(iter(columns.values()))) if columns else 1
    names = list(spec.scenario.sensors)
    out = _empty_columns(pd_columns(spec), n)
    convention = spec.options.get("convention")
    for i in range(n):
        scenario = with_values(spec.scenario, {k: v[i] for k, v in columns.items()})
        _explain(out, np.array([i]), scenario, evaluate(scenario, convention))
        _swarm_point(out, i, scenario, convention)
        grid = default_range_grid(scenario, convention)
        curves = [sensor_pd(scenario, name, grid, convention) for name in names]
        for c in curves:
            out[f"pd_at_deterministic_range.{c.sensor}"][i] = (
                np.nan if c.pd_at_deterministic_range is None else c.pd_at_deterministic_range
            )
        models = {name: _sensor_pd_of_range(scenario, name, convention) for name in names}
        models["fused"] = fused_pd_of_range(scenario, spec.options["fusion"], convention)
        for name, model in models.items():  # solved on the model, bracketed by the grid
            for p, r in zip(REPORTED_PD, range_at_pd(model, grid, REPORTED_PD)):
                out[f"range_at_pd_{p:g}.{name}"][i] = np.nan if r is None else r
    return out


#: What a render reports per point (the ``stderr`` of pixels_on_target follows them).
RENDER_VALUES = ("pixels_on_target", "pixels_across_dcrit", "contrast", "delta_t_k", "lcs_m2")


def render_columns(spec: SweepSpec) -> list[str]:
    """Columns of the ``render`` job: :data:`RENDER_VALUES` and ``pixels_on_target_stderr``."""
    return [*RENDER_VALUES, "pixels_on_target_stderr"]


def render_chunk(spec: SweepSpec, columns: dict, start: int) -> dict:
    """Per point: the scenario's render mode at the point's range and aspect, seeded by the point."""
    from csuas.render.imaging.modes import eo_scenario, tir_scenario
    from csuas.render.lidar.runner import render_lidar
    from csuas.render.request import RenderRequest

    mode = {"eo": eo_scenario, "tir": tir_scenario, "lidar": render_lidar}[spec.options["mode"]]
    n = len(next(iter(columns.values()), [None]))  # no axes: the one point of the options
    seeds = point_seed(spec.seed, np.arange(start, start + n))
    out = {k: np.full(n, np.nan) for k in render_columns(spec)}
    own = {k: v for k, v in columns.items() if k in RENDER_AXES}
    for i in range(n):
        scenario = with_values(spec.scenario, {k: v[i] for k, v in columns.items() if k not in own})
        at = {k: float(own[k][i]) if k in own else spec.options[k] for k in RENDER_AXES}
        request = RenderRequest(
            ranges_m=[at["range_m"]],
            quality=spec.options["quality"],
            azimuth_deg=at["azimuth_deg"],
            elevation_deg=at["elevation_deg"],
            seed=int(seeds[i] % (2**31)),
        )
        (row,) = mode(scenario, request)
        for k in RENDER_VALUES:
            value = row.get(k)
            if isinstance(value, (int, float)):
                out[k][i] = value
        out["pixels_on_target_stderr"][i] = row.get("stderr", {}).get("pixels_on_target", np.nan)
    return out


def rcs_columns(spec: SweepSpec) -> list[str]:
    """Columns of the ``rcs`` job: RCS [dBsm] and its error estimate [dB], VV and HH."""
    return ["rcs_dbsm.VV", "rcs_dbsm.HH", "error_db.VV", "error_db.HH"]


def rcs_chunk(spec: SweepSpec, columns: dict) -> dict:
    """RCS [dBsm] VV and HH at each point, one SBR-PO call per frequency for the chunk's aspects."""
    from csuas.render.rcs import compute_rcs

    # interned: the SBR engine cache keys on the target object, and each task unpickles its own string
    target = sys.intern(str(spec.options["target"] or spec.scenario.target_preset))
    n = len(columns["frequency_ghz"])
    az = np.asarray(columns.get("azimuth_deg", np.full(n, spec.options["azimuth_deg"])), float)
    el = np.asarray(columns.get("elevation_deg", np.full(n, spec.options["elevation_deg"])), float)
    out = {k: np.full(n, np.nan) for k in rcs_columns(spec)}
    for f in np.unique(columns["frequency_ghz"]):
        idx = np.nonzero(columns["frequency_ghz"] == f)[0]
        res = compute_rcs(
            target,
            float(f),
            az[idx],
            el[idx],
            quality=spec.options["quality"],
            rays_per_wavelength=spec.options["rays_per_wavelength"],
        )
        for name, (rx, tx) in (("VV", (0, 0)), ("HH", (1, 1))):
            sigma = res.sigma_m2[0, :, 0, rx, tx]
            with np.errstate(divide="ignore"):
                out[f"rcs_dbsm.{name}"][idx] = np.where(sigma > 0, 10 * np.log10(np.maximum(sigma, 1e-300)), np.nan)
            if res.error_db is not None:
                out[f"error_db.{name}"][idx] = res.error_db[0, :, 0, rx, tx]
    return out
