"""Points per task of a sweep whose spec gives no ``chunk_points``: sized from its points and workers.

Two needs pull apart: load balance wants several tasks a worker (a worker that finishes early takes
another), and the per-task overhead (the client's submission, the scheduler's routing, the task's
transfer with its spec, the chunk file written and the result's return) wants tasks long enough to
hide it. The rule, in closed form (``n`` points, ``w`` workers, ``lowest`` the points that make a task
last :data:`TASK_OVERHEAD_S` / :data:`OVERHEAD_SHARE`, ``highest`` the job's ``chunk_points`` default)::

    tasks = w * clip(floor(n / (w * lowest)), 1, TASKS_PER_WORKER)
    chunk = min(highest, ceil(n / tasks))

so every worker gets between one and :data:`TASKS_PER_WORKER` tasks, as many as keep a task at least
``lowest`` points, and a task never exceeds the job's memory-bounded default. The chunk size is
recorded in the output folder's ``sweep-state.json``, so a resumed sweep keeps its chunks whatever
its workers then (:func:`csuas.sweep.run.run_sweep`).

The overhead was measured by ``csuas bench --only sweep_scaling`` (200 one-point range chunks on one
warm worker against the same chunks in this process, docs/sweeps.md): 14 ms a task at a load average
of about 3 on 2 cores, 37 ms at about 8, 8-25 ms in earlier runs (``sweep_dask``).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .kinds import swarm_pairs

if TYPE_CHECKING:
    from .spec import SweepSpec

#: Wall time a task costs beyond its points' work on a warm local cluster [s] (measured 8-37 ms: module docstring).
TASK_OVERHEAD_S = 0.02
#: Largest share of a task's time the overhead may take when points are plenty.
OVERHEAD_SHARE = 0.05
#: Most tasks a worker gets for load balance.
TASKS_PER_WORKER = 4


def lowest_chunk_points(spec: SweepSpec) -> int:
    """Points that make one task last ``TASK_OVERHEAD_S / OVERHEAD_SHARE`` by the job's cost model (at least 1).

    A job whose time per point is known only once its spec is traced (``rcs``: zero in its
    :class:`~csuas.sweep.kinds.JobCost`) is taken as costly: one point.
    """
    kind = spec.kind
    pairs = swarm_pairs(spec.scenario.swarm.count) if kind.takes_scenario and spec.scenario.swarm is not None else 0
    seconds = kind.cost.point_seconds(len(spec.scenario.sensors) if kind.takes_scenario else 0, pairs)
    if seconds <= 0.0:
        return 1
    return max(1, math.ceil(TASK_OVERHEAD_S / (OVERHEAD_SHARE * seconds)))


def chunk_points_for(n_points: int, n_workers: int, lowest: int, highest: int) -> int:
    """Points per task for ``n_points`` on ``n_workers`` (module docstring's closed form)."""
    n_workers = max(1, n_workers)
    per_worker = min(max(n_points // (n_workers * max(lowest, 1)), 1), TASKS_PER_WORKER)
    return max(1, min(highest, math.ceil(n_points / (n_workers * per_worker))))


def auto_chunk_points(spec: SweepSpec, n_workers: int) -> int:
    """The spec's ``chunk_points`` when it gives one, else sized for ``n_workers`` (:func:`chunk_points_for`)."""
    if not spec.chunk_auto:
        return spec.chunk_points
    return chunk_points_for(spec.n_points, n_workers, lowest_chunk_points(spec), spec.chunk_points)
