"""Cost of a sweep (time and peak memory), from its spec's numbers before any axis is built.

:func:`axis_lengths` reads each axis's length from the TOML table (a list's length, a drawn axis's
``samples``) and refuses a count that is not a finite whole number or exceeds
:data:`~csuas.sweep.spec.MAX_POINTS`, before :func:`~csuas.sweep.spec.parse_spec` draws a single
value. :func:`sweep_estimate` turns the lengths into an :class:`~csuas.base.cost.Estimate` with the
job's cost model (:class:`csuas.sweep.kinds.JobCost`); a job whose cost needs the parsed spec refines
it then (``JobCost.refine``: the ``rcs`` job's tubes, :func:`csuas.sweep.cost_rcs.rcs_estimate`, the
estimate of ``csuas rcs --max-tubes``; the ``engage`` job's runs). Chunks are streamed: a worker
holds one chunk, and the results table is gathered chunk by chunk, so the memory of a sweep does not
grow with its points beyond its axes.

Constants measured with ``csuas sweep --scheduler serial`` on 2 CPU cores of a machine loaded by
other work, the default scenario (6 sensors), ru_maxrss and wall time (each job's own in
:data:`csuas.sweep.kinds.JOB_KINDS`); the ``cost_models`` benchmark compares the model with
measurements on three sizes.
"""

from __future__ import annotations

import math
import os

from csuas.base.cost import BASE_PROCESS_BYTES, Estimate
from csuas.base.errors import ParameterError, raise_all

from .kinds import JOB_KINDS, swarm_pairs
from .schema import MAX_POINTS

#: Drawing and checking one value of an axis in the main process [s] and its memory while the axis
#: is built (the drawn list, its checked copy and the array) [B]; 10^6 to 10^7 samples: 0.75-0.80 us, 84 B.
AXIS_SAMPLE_SECONDS = 0.8e-6
AXIS_SAMPLE_BYTES = 90.0
#: Start of the work [s]: this process's imports and scenario, and a local Dask cluster's start (a job's
#: own libraries add their ``JobCost.start_s``).
START_SECONDS = {"serial": 1.5, "local": 5.0}


def _count(key: str, value) -> int | None:
    """A point count of an axis, or None when it is not a finite whole number from 1 to MAX_POINTS."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    if not (math.isfinite(value) and value == int(value) and 1 <= value <= MAX_POINTS):
        return None
    return int(value)


def axis_lengths(data: dict) -> dict:
    """Length of each axis of a sweep spec's TOML table, read from its numbers (nothing is drawn).

    Raises
    ------
    ParameterError
        ``axes.KEY.samples`` that is not a finite whole number from 1 to MAX_POINTS, or a spec
        whose axes span more than MAX_POINTS points (every such mistake at once).
    """
    axes = data.get("axes", {})
    if not isinstance(axes, dict):
        return {}  # the spec's validator names it
    lengths, errors = {}, []
    for key, raw in axes.items():
        if isinstance(raw, list):
            lengths[key] = len(raw)
        elif isinstance(raw, dict) and "samples" in raw:
            n = _count(key, raw["samples"])
            if n is None:
                errors.append(
                    ParameterError(
                        f"axes.{key}.samples", raw["samples"], f"a finite whole number from 1 to {MAX_POINTS:,}"
                    )
                )
            else:
                lengths[key] = n
    raise_all(errors)
    points = _points(lengths, data.get("combine", "grid"))
    if points > MAX_POINTS:
        raise ParameterError("axes", f"{points:,} points", f"at most {MAX_POINTS:,} points in one sweep")
    return lengths


def _points(lengths: dict, combine) -> int:
    if not lengths:
        return 1
    return max(lengths.values()) if combine == "zip" else math.prod(lengths.values())


def workers_of(scheduler: str, workers: int | None) -> int:
    """Worker processes that run the chunks: 1 serial, ``workers`` (default the CPU count) local, 1 remote.

    A remote (``tcp://``) cluster's size is unknown before connecting: its time is estimated for one worker.
    """
    if scheduler == "local":
        return workers or max(1, os.cpu_count() or 1)
    return 1


def largest_swarm(data: dict, scenario_count: int) -> int:
    """The most drones a point of a sweep has: the scenario's swarm, or the highest value of a
    ``target.swarm.count`` axis (a list or ``{min, max}``; its values are checked when the spec is parsed)."""
    axis = data.get("axes", {}).get("target.swarm.count") if isinstance(data.get("axes"), dict) else None
    values = axis if isinstance(axis, list) else [axis.get("max")] if isinstance(axis, dict) else []
    numbers = [int(v) for v in values if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)]
    return max([scenario_count, *numbers]) if scenario_count else 0


def sweep_estimate(
    data: dict, lengths: dict, n_sensors: int, scheduler: str, workers: int | None, swarm_count: int = 0
) -> Estimate:
    """Time and peak memory of a sweep from its spec table and axis lengths (:func:`axis_lengths`), its scenario's
    ``swarm_count`` drones at most (0 without a swarm; :func:`largest_swarm`).

    Time: the axes drawn (every sample), then every point's job time shared by the workers (at most
    the CPU count of a local cluster run at once), plus the start. Memory: serial, one process with
    the job's libraries, the axes and one chunk; on a cluster, this process with the axes, and per
    worker its process, a copy of the axes (each task carries the spec) and one chunk. What the job
    refines once its spec is parsed (``JobCost.refine``) is not in this estimate.
    """
    job = data.get("job")
    kind = JOB_KINDS[job]
    cost = kind.cost
    points = _points(lengths, data.get("combine", "grid"))
    samples = sum(lengths.values())
    chunk = data.get("chunk_points", kind.chunk_points)
    chunk = chunk if isinstance(chunk, int) and not isinstance(chunk, bool) and chunk >= 1 else kind.chunk_points
    n_workers = workers_of(scheduler, workers)
    parallel = min(n_workers, os.cpu_count() or 1) if scheduler == "local" else 1
    per_point = cost.point_seconds(n_sensors, swarm_pairs(swarm_count))
    seconds = START_SECONDS.get(scheduler, START_SECONDS["local"]) + samples * AXIS_SAMPLE_SECONDS + cost.start_s
    seconds += points * per_point / parallel
    chunk_bytes = cost.chunk_bytes_per_point_sensor * max(n_sensors, 1) * min(chunk, points)
    axes_bytes = samples * AXIS_SAMPLE_BYTES
    if scheduler == "serial":  # one process: the job's libraries, the axes and one chunk
        peak = cost.process_bytes + axes_bytes + chunk_bytes
    else:  # this process with the axes, and every worker with a copy of them (float64) and a chunk
        peak = BASE_PROCESS_BYTES + axes_bytes + n_workers * (cost.process_bytes + 8.0 * samples + chunk_bytes)
    where = {"serial": "in this process"}.get(scheduler, f"on {n_workers} worker(s)")
    return Estimate(f"a {job} sweep of {points:,} points {where}", seconds, peak)
