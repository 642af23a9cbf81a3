"""Cost of a sweep (time and peak memory), from its spec's numbers before any axis is built.

:func:`axis_lengths` reads each axis's length from the TOML table (a list's length, a drawn axis's
``samples``) and refuses a count that is not a finite whole number or exceeds
:data:`~csuas.sweep.spec.MAX_POINTS`, before :func:`~csuas.sweep.spec.parse_spec` draws a single
value. :func:`sweep_estimate` turns the lengths into an :class:`~csuas.base.cost.Estimate`; for
the ``rcs`` job :func:`rcs_estimate` adds the tube count of every point (the estimate of
``csuas rcs --max-tubes``). Chunks are streamed: a worker holds one chunk, and the results table
is gathered chunk by chunk, so the memory of a sweep does not grow with its points beyond its axes.

Constants measured with ``csuas sweep --scheduler serial`` on 2 CPU cores of a machine loaded by
other work, the default scenario (6 sensors), ru_maxrss and wall time; the ``cost_models``
benchmark compares the model with measurements on three sizes.
"""

from __future__ import annotations

import math
import os

from csuas.base.cost import BASE_PROCESS_BYTES, Estimate
from csuas.base.errors import ParameterError, raise_all

from .spec import CHUNK_POINTS, MAX_POINTS

#: Drawing and checking one value of an axis in the main process [s] and its memory while the axis
#: is built (the drawn list, its checked copy and the array) [B]; 10^6 to 10^7 samples: 0.75-0.80 us, 84 B.
AXIS_SAMPLE_SECONDS = 0.8e-6
AXIS_SAMPLE_BYTES = 90.0
#: Wall time of one point per sensor of the scenario [s]: range (vectorised, 10^5-3x10^6 points:
#: 3-4.6 us a point of 6 sensors) and pd (a Pd curve per sensor: 47 ms a point of 6 sensors).
SECONDS_PER_POINT_SENSOR = {"range": 0.7e-6, "pd": 8e-3}
#: Wall time of one point of the simulator jobs at draft quality [s] (render: 9 EO points in 7.1 s
#: with the start; rcs: from the tubes, :func:`rcs_estimate`).
SECONDS_PER_POINT = {"render": 0.3}
#: Working memory of one point of a chunk per sensor [B] (range: 840 MB for 10^6 points of 6 sensors).
CHUNK_BYTES_PER_POINT_SENSOR = {"range": 140.0, "pd": 2e4}
#: Resident memory of a process running the job's chunks, before its points [B]: the interpreter
#: with the job's libraries (pd: 180 MB a Dask worker; render 290 MB and rcs 365 MB serial runs;
#: rcs: :data:`~csuas.render.rcs.solver.ENGINE_PROCESS_BYTES`, its tubes added by :func:`rcs_estimate`).
PROCESS_BYTES = {"range": 180e6, "pd": 180e6, "render": 300e6, "rcs": 370e6}
#: Start of the work [s]: this process's imports and scenario, and a local Dask cluster's start; the
#: simulator jobs add Dr.Jit's and Mitsuba's imports, the target's engine and their first kernels
#: (rcs: 1 to 6 frequencies of 7 aspects at draft, 10^4-10^6 tubes, took 7.5-9.5 s in all).
START_SECONDS = {"serial": 1.5, "local": 5.0}
SIMULATOR_START_SECONDS = 6.0


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


def sweep_estimate(data: dict, lengths: dict, n_sensors: int, scheduler: str, workers: int | None) -> Estimate:
    """Time and peak memory of a sweep from its spec table and axis lengths (:func:`axis_lengths`).

    Time: the axes drawn (every sample), then every point's job time shared by the workers (at most
    the CPU count of a local cluster run at once), plus the start. Memory: serial, one process with
    the job's libraries, the axes and one chunk; on a cluster, this process with the axes, and per
    worker its process, a copy of the axes (each task carries the spec) and one chunk. The ``rcs``
    job's tubes are added by :func:`rcs_estimate`.
    """
    job = data.get("job")
    combine = data.get("combine", "grid")
    points = _points(lengths, combine)
    samples = sum(lengths.values())
    chunk = data.get("chunk_points", CHUNK_POINTS.get(job, 1))
    chunk = chunk if isinstance(chunk, int) and not isinstance(chunk, bool) and chunk >= 1 else CHUNK_POINTS[job]
    n_workers = workers_of(scheduler, workers)
    parallel = min(n_workers, os.cpu_count() or 1) if scheduler == "local" else 1
    per_point = SECONDS_PER_POINT_SENSOR[job] * max(n_sensors, 1) if job in SECONDS_PER_POINT_SENSOR else 0.0
    per_point = SECONDS_PER_POINT.get(job, per_point)
    seconds = START_SECONDS.get(scheduler, START_SECONDS["local"]) + samples * AXIS_SAMPLE_SECONDS
    seconds += SIMULATOR_START_SECONDS if job in ("render", "rcs") else 0.0
    seconds += points * per_point / parallel
    chunk_bytes = CHUNK_BYTES_PER_POINT_SENSOR.get(job, 0.0) * max(n_sensors, 1) * min(chunk, points)
    axes_bytes = samples * AXIS_SAMPLE_BYTES
    if scheduler == "serial":  # one process: the job's libraries, the axes and one chunk
        peak = PROCESS_BYTES[job] + axes_bytes + chunk_bytes
    else:  # this process with the axes, and every worker with a copy of them (float64) and a chunk
        peak = BASE_PROCESS_BYTES + axes_bytes + n_workers * (PROCESS_BYTES[job] + 8.0 * samples + chunk_bytes)
    where = {"serial": "in this process"}.get(scheduler, f"on {n_workers} worker(s)")
    return Estimate(f"a {job} sweep of {points:,} points {where}", seconds, peak)


def rcs_estimate(spec, base: Estimate, n_workers: int) -> Estimate:
    """``base`` plus the SBR tracing of every point of an ``rcs`` sweep (as ``csuas rcs`` estimates it).

    Each point traces the grid of :func:`~csuas.render.rcs.solver.estimate_tubes` at its frequency on
    ``REPLICAS`` shifted grids (the error estimate); the time is
    :func:`~csuas.render.rcs.solver.estimate_seconds`, shared by the workers.
    """
    import numpy as np

    from csuas.render.rcs.geometry import load_target
    from csuas.render.rcs.solver import (
        REPLICAS,
        estimate_peak_bytes,
        estimate_seconds,
        estimate_tubes,
        resolve_quality,
    )

    rays, bounces = resolve_quality(spec.options["quality"], spec.options["rays_per_wavelength"])
    radius = load_target(str(spec.options["target"] or spec.scenario.target_preset)).bounding_radius_m
    axis = spec.axes["frequency_ghz"]
    frequencies, counts = np.unique(axis, return_counts=True)
    if spec.combine == "grid":
        counts = counts * (spec.n_points // len(axis))  # every frequency meets every other axis's values
    per_point = [float(estimate_tubes(radius, float(f), rays)) * REPLICAS for f in frequencies]
    tubes = sum(t * int(c) for t, c in zip(per_point, counts))
    seconds = estimate_seconds(tubes, bounces) / min(n_workers, os.cpu_count() or 1)
    # each worker holds the tubes of one grid (an aspect's replica) in flight at a time
    batch = estimate_peak_bytes(max(per_point) / REPLICAS) - PROCESS_BYTES["rcs"]
    what = f"{base.what} ({tubes:.3g} tubes at {rays:g} rays per wavelength)"
    return Estimate(what, base.seconds + seconds, base.bytes + n_workers * max(batch, 0.0))
