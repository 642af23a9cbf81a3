"""A Dask worker plugin that readies every worker for a sweep's job once: :class:`WarmUp`.

Without it, each worker's first task pays the job's imports (Mitsuba and Dr.Jit: seconds) and
kernel compilation while its clock runs, and a sweep of a minute loses a large share of it to
start-up. The plugin runs the job's ``warm_up`` (:class:`csuas.sweep.kinds.JobKind`) in the worker's
``setup`` (Dask's ``WorkerPlugin``, docs: https://distributed.dask.org/en/stable/plugins.html), which
Dask calls on every worker when the plugin is registered and on every worker that joins later (a
recycled or replaced one). The warm-up runs in a thread of its own, so the worker registers and its
nanny sees it started at once (a warm-up inside ``setup`` delays both, and a worker recycled before
its nanny saw it start is not restarted); each chunk waits for it first (:func:`wait_warm`). The plugin
is registered under one name a job (:func:`plugin_name`) and idempotently, so a cluster kept across
sweeps (``--scheduler tcp://...``) warms each worker once a job, not once a sweep.
"""

from __future__ import annotations

import threading

from distributed import WorkerPlugin


def plugin_name(job: str) -> str:
    """The name a job's plugin is registered under on the scheduler."""
    return f"csuas-warm-{job}"


class WarmUp(WorkerPlugin):
    """Runs ``spec``'s job ``warm_up`` once in each worker (after setting Dr.Jit to one thread for simulators).

    Attributes
    ----------
    spec : SweepSpec
        The sweep whose first warm-up this is (its job's ``warm_up`` reads it: the first point).
    warm_ups : int
        Warm-ups this worker's copy ran (1 once done; read by the tests through ``Worker.plugins``).
    """

    idempotent = True  # registered again by a later sweep of the same job: left as it is

    def __init__(self, spec):
        self.spec = spec
        self.name = plugin_name(spec.job)
        self.warm_ups = 0
        self._thread: threading.Thread | None = None
        self._error: BaseException | None = None

    def setup(self, worker) -> None:
        """Start this worker's warm-up in a thread of its own."""
        self._thread = threading.Thread(target=self._warm, name=self.name, daemon=True)
        self._thread.start()

    def wait(self) -> int:
        """Wait until this worker is warm; its warm-ups (1).

        Raises
        ------
        BaseException
            What the job's warm-up raised (the chunk that waits fails with it, as it would have itself).
        """
        if self._thread is not None:
            self._thread.join()
        if self._error is not None:
            raise self._error
        return self.warm_ups

    def _warm(self) -> None:
        from .run import single_drjit_thread

        kind = self.spec.kind
        try:
            if kind.simulator:
                single_drjit_thread()
            if kind.warm_up is not None:
                kind.warm_up(self.spec)
        except Exception as exc:  # raised again in every chunk that waits for it
            self._error = exc
        else:
            self.warm_ups += 1


def wait_warm(job: str, dask_worker=None) -> int:
    """On a Dask worker, wait for its warm-up of ``job`` (none registered: 0 at once); ``client.run`` passes
    ``dask_worker``, a task finds its worker itself."""
    if dask_worker is None:
        from distributed import get_worker

        dask_worker = get_worker()
    plugin = dask_worker.plugins.get(plugin_name(job))
    return 0 if plugin is None else plugin.wait()
