"""A Dask worker plugin that readies every worker for a sweep's job once: :class:`WarmUp`.

Without it, each worker's first task pays the job's imports (Mitsuba and Dr.Jit: seconds) and
kernel compilation while its clock runs, and a sweep of a minute loses a large share of it to
start-up. The plugin runs the job's ``warm_up`` (:class:`csuas.sweep.kinds.JobKind`) in the worker's
``setup`` (Dask's ``WorkerPlugin``, docs: https://distributed.dask.org/en/stable/plugins.html), which
Dask calls on every worker when the plugin is registered. The warm-up runs in the worker's own task
thread (its ``default`` executor, the thread that then runs its chunks: Dr.Jit's state stays in the
thread that uses it), so the worker keeps answering its scheduler and nanny meanwhile. The sweep waits
until every worker is warm, then unregisters the plugin (:func:`csuas.sweep.run.run_sweep`): a worker that joins later
(recycled after ``recycle_after`` tasks, or replaced) warms in its first chunk, as without the
plugin, so a recycle costs no more than it did. A process warms once a job (:data:`WARMED`), so a
cluster kept across sweeps (``--scheduler tcp://...``) warms each worker once a job, not once a sweep.
"""

from __future__ import annotations

import threading
from concurrent.futures import Future

from distributed import WorkerPlugin

#: Warm-ups this process has run, per job: at most one (a second registration finds the job warm).
WARMED: dict[str, int] = {}
_WARMING = threading.Lock()


def plugin_name(job: str) -> str:
    """The name a job's plugin is registered under on the scheduler."""
    return f"csuas-warm-{job}"


class WarmUp(WorkerPlugin):
    """Runs ``spec``'s job ``warm_up`` once in each worker process (Dr.Jit set to one thread first for simulators).

    Attributes
    ----------
    spec : SweepSpec
        The sweep whose first warm-up this is (its job's ``warm_up`` reads it: the first point).
    """

    def __init__(self, spec):
        self.spec = spec
        self.name = plugin_name(spec.job)
        self._done: Future | None = None
        self._error: BaseException | None = None

    def setup(self, worker) -> None:
        """Start this worker's warm-up in the thread that runs its tasks."""
        self._done = worker.executors["default"].submit(self._warm)

    def wait(self) -> None:
        """Wait until this worker is warm.

        Raises
        ------
        BaseException
            What the job's warm-up raised (the sweep stops with it, as its first chunk would have).
        """
        if self._done is not None:
            self._done.result()
        if self._error is not None:
            raise self._error

    def _warm(self) -> None:
        from .run import single_drjit_thread

        kind = self.spec.kind
        with _WARMING:
            if self.spec.job in WARMED:
                return
            try:
                if kind.simulator:
                    single_drjit_thread()
                if kind.warm_up is not None:
                    kind.warm_up(self.spec)
            except Exception as exc:  # raised again where the sweep waits for it
                self._error = exc
            else:
                WARMED[self.spec.job] = WARMED.get(self.spec.job, 0) + 1


def wait_warm(job: str, dask_worker=None) -> int:
    """On a Dask worker (``client.run`` passes ``dask_worker``), wait for its warm-up of ``job`` if one is under
    way; the warm-ups of ``job`` this process has run (0 or 1)."""
    plugin = None if dask_worker is None else dask_worker.plugins.get(plugin_name(job))
    if plugin is not None:
        plugin.wait()
    return WARMED.get(job, 0)
