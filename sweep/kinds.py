"""The sweep jobs, each declared once: its spec schema, chunk function, output columns and cost model.

Every place that depends on the job (the spec's validation and error texts, the chunks, the columns
written, the cost estimate, the simulator workers' handling, the command line and the docs tables)
reads :data:`JOB_KINDS`. Adding a job is its ``[options]`` model (:mod:`csuas.sweep.schema`), its chunk
function and one :class:`JobKind` appended here (ARCHITECTURE.md "Where to make a change"); a spec
naming a job not here is refused, naming the jobs that are (:func:`kind_of`).

The cost constants were measured with ``csuas sweep --scheduler serial`` on 2 CPU cores of a machine
loaded by other work, the default scenario (6 sensors), ru_maxrss and wall time; the ``cost_models``
benchmark compares the model with measurements on three sizes (:mod:`csuas.sweep.cost`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from csuas.base.errors import ParameterError

from . import job_engage, jobs
from .cost_rcs import rcs_estimate
from .schema import (
    RCS_AXES,
    RENDER_AXES,
    EngageOptions,
    PdOptions,
    RangeOptions,
    RcsOptions,
    RenderOptions,
    SweepCommon,
    sweep_schema,
)

#: Resident memory of an rcs process before its tubes [B]: :data:`csuas.render.rcs.solver.ENGINE_PROCESS_BYTES`
#: (not imported here: that module brings Dr.Jit, seconds to import, into every sweep).
RCS_PROCESS_BYTES = 370e6


@dataclass(frozen=True)
class JobCost:
    """What one point of a job costs (:func:`csuas.sweep.cost.sweep_estimate`).

    Attributes
    ----------
    process_bytes : float
        Resident memory of a process running the job's chunks, before its points [B].
    seconds_per_point_sensor, seconds_per_point : float
        Wall time of one point [s], per sensor of the scenario and in all (added).
    chunk_bytes_per_point_sensor : float
        Working memory of one point of a chunk per sensor [B].
    start_s : float
        Start of the job's libraries on top of the scheduler's (a simulator's imports and first kernels) [s].
    refine : callable or None
        ``refine(spec, estimate, n_workers) -> Estimate``: the estimate once the spec is parsed (rcs: its tubes).
    swarm_seconds_per_pair_sensor : float
        Wall time a point adds per sensor and per pair of drones of a ``target.swarm`` (its groups are found
        point by point over the intervals where pairs merge, :func:`csuas.core.swarm_detection.swarm_range`) [s].
    """

    process_bytes: float
    seconds_per_point_sensor: float = 0.0
    seconds_per_point: float = 0.0
    chunk_bytes_per_point_sensor: float = 0.0
    start_s: float = 0.0
    refine: Callable[[Any, Any, int], Any] | None = None
    swarm_seconds_per_pair_sensor: float = 0.0

    def point_seconds(self, n_sensors: int, swarm_pairs: int = 0) -> float:
        """Wall time of one point [s] on a scenario of ``n_sensors`` sensors (at least one counted) and a swarm of
        ``swarm_pairs`` pairs of drones (0: none)."""
        per_sensor = self.seconds_per_point_sensor + self.swarm_seconds_per_pair_sensor * swarm_pairs
        return per_sensor * max(n_sensors, 1) + self.seconds_per_point


#: What a swarm adds to a range or pd point, per sensor and pair of drones [s]: 7.0 ms a point-sensor measured
#: for the embedded ``swarm`` (4 drones, 6 pairs, 6 sensors; 20 points of a spacing axis, ``range_chunk``, on the
#: shared 2 cores at load 12): 1.2 ms a pair.
SWARM_SECONDS_PER_PAIR_SENSOR = 1.2e-3


def swarm_pairs(count: int) -> int:
    """Pairs of drones of a swarm of ``count`` (0 without one)."""
    return count * (count - 1) // 2


def no_needs(axes: dict, options: dict, n_sensors: int) -> list:
    """A job that needs nothing beside its schema."""
    return []


@dataclass(frozen=True)
class JobKind:
    """One sweep job.

    Attributes
    ----------
    name : str
        The spec's ``job``.
    options : type
        The ``[options]`` model (:mod:`csuas.sweep.schema`).
    chunk_points : int
        Default points per task.
    chunk : callable
        ``chunk(spec, columns, start, stop) -> {column: array}`` for points ``start..stop``.
    columns : callable
        ``columns(spec) -> [column, ...]``: what ``chunk`` returns, in order (checked on every chunk).
    cost : JobCost
    own_axes : dict
        Axes the job takes besides the scenario's parameters: name -> (lowest, highest) allowed.
    takes_scenario : bool
        Whether the scenario's parameters may be axes.
    simulator : bool
        One thread a worker, recycled after ``recycle_after`` tasks, a ``GPU`` resource when the cluster has one.
    needs : callable
        ``needs(axes, options, n_sensors) -> [ParameterError, ...]``: what the job needs beside its schema.
    prepare : callable or None
        ``prepare(spec) -> spec``: what the job adds to a validated spec (engage: its runs as the points).
    warm_up : callable or None
        ``warm_up(spec)``: what a Dask worker does once, before its first chunk of this job (imports the
        job's modules, compiles its kernels; :class:`csuas.sweep.warm.WarmUp`).
    schema : type
        The job's whole spec schema (:func:`csuas.sweep.schema.sweep_schema`), made from the fields above.
    """

    name: str
    options: type
    chunk_points: int
    chunk: Callable[[Any, dict, int, int], dict]
    columns: Callable[[Any], list]
    cost: JobCost
    own_axes: dict = field(default_factory=dict)
    takes_scenario: bool = True
    simulator: bool = False
    needs: Callable[[dict, dict, int], list] = no_needs
    prepare: Callable[[Any], Any] | None = None
    warm_up: Callable[[Any], None] | None = jobs.warm_first_point
    schema: type[SweepCommon] = field(init=False)

    def __post_init__(self):
        # the job's whole spec schema, made once (pydantic builds its validator when the class is made)
        object.__setattr__(self, "schema", sweep_schema(self.name, self.options, self.chunk_points))


def _fusion_needs(axes: dict, options: dict, n_sensors: int) -> list:
    """A k-of-n fusion's k is at most the sensors."""
    fusion = options["fusion"]
    if fusion != "or" and int(fusion.partition(":")[2]) > n_sensors:
        return [ParameterError("options.fusion", fusion, f"or, or k-of-n:K with K 1 to {n_sensors} (the sensors)")]
    return []


def _range_needs(axes: dict, options: dict, n_sensors: int) -> list:
    if "range_m" not in axes and options["range_m"] is None:
        return [ParameterError("axes.range_m", None, "an axis or options.range_m: the render job needs ranges")]
    return []


def _frequency_needs(axes: dict, options: dict, n_sensors: int) -> list:
    if "frequency_ghz" not in axes:
        return [ParameterError("axes.frequency_ghz", None, "an axis: the rcs job needs frequencies")]
    return []


#: Every sweep job, in the order the docs list them. Points per task: analytic points go to the core in
#: large NumPy chunks, simulator points in small groups. Costs: range is vectorised (10^5-3x10^6 points:
#: 3-4.6 us a point of 6 sensors; 840 MB for 10^6 points of 6 sensors); pd computes a Pd curve per sensor and
#: solves its ranges at Pd 0.5 and 0.9 on the model (0.27-0.28 s a point of 6 sensors and their fusion,
#: serial at load 0.9, 2026-11-27; 180 MB a Dask worker); render takes 9 EO points in 7.1 s with the start
#: (290 MB serial); rcs from its tubes (:func:`~csuas.sweep.cost_rcs.rcs_estimate`; 1 to 6 frequencies of
#: 7 aspects at draft, 10^4-10^6 tubes, took 7.5-9.5 s in all); engage from the example's runs
#: (:mod:`csuas.sweep.job_engage`).
JOB_KINDS: dict[str, JobKind] = {
    kind.name: kind
    for kind in (
        JobKind(
            "range",
            RangeOptions,
            1_000_000,
            lambda spec, columns, start, stop: jobs.range_chunk(spec, columns),
            jobs.range_columns,
            JobCost(
                180e6,
                seconds_per_point_sensor=0.7e-6,
                chunk_bytes_per_point_sensor=140.0,
                swarm_seconds_per_pair_sensor=SWARM_SECONDS_PER_PAIR_SENSOR,
            ),
        ),
        JobKind(
            "pd",
            PdOptions,
            32,
            lambda spec, columns, start, stop: jobs.pd_chunk(spec, columns),
            jobs.pd_columns,
            JobCost(
                180e6,
                seconds_per_point_sensor=46e-3,
                chunk_bytes_per_point_sensor=2e4,
                swarm_seconds_per_pair_sensor=SWARM_SECONDS_PER_PAIR_SENSOR,
            ),
            needs=_fusion_needs,
        ),
        JobKind(
            "render",
            RenderOptions,
            4,
            lambda spec, columns, start, stop: jobs.render_chunk(spec, columns, start),
            jobs.render_columns,
            JobCost(300e6, seconds_per_point=0.3, start_s=6.0),
            own_axes=RENDER_AXES,
            simulator=True,
            needs=_range_needs,
        ),
        JobKind(
            "rcs",
            RcsOptions,
            16,
            lambda spec, columns, start, stop: jobs.rcs_chunk(spec, columns),
            jobs.rcs_columns,
            JobCost(RCS_PROCESS_BYTES, start_s=6.0, refine=rcs_estimate),
            own_axes=RCS_AXES,
            takes_scenario=False,
            simulator=True,
            needs=_frequency_needs,
        ),
        JobKind(
            "engage",
            EngageOptions,
            job_engage.CHUNK_RUNS,
            job_engage.engage_chunk,
            job_engage.engage_columns,
            JobCost(
                job_engage.PROCESS_BYTES, seconds_per_point=job_engage.SECONDS_PER_RUN, refine=job_engage.runs_estimate
            ),
            takes_scenario=False,
            prepare=job_engage.prepare,
            warm_up=job_engage.warm_up,
        ),
    )
}


def jobs_text(final: str = "or") -> str:
    """The jobs, for messages: ``range, pd, render or rcs``."""
    names = list(JOB_KINDS)
    return ", ".join(names[:-1]) + f" {final} {names[-1]}" if len(names) > 1 else names[0]


def kind_of(job) -> JobKind:
    """The declared job a spec names.

    Raises
    ------
    ParameterError
        ``job`` naming no declared job, with the jobs there are (``dataset`` pointed to ``csuas dataset``).
    """
    if isinstance(job, str) and job in JOB_KINDS:
        return JOB_KINDS[job]
    if job == "dataset":
        raise ParameterError(
            "job", job, f"{jobs_text()}: datasets are made by csuas dataset SPEC --out DIR (one process)"
        )
    raise ParameterError("job", job, ", ".join(JOB_KINDS))
