"""Running a sweep: chunks as tasks on Dask (``dask.distributed``), or in this process.

Schedulers: ``serial`` (this process, no Dask), ``local`` (a ``LocalCluster`` of process workers,
one thread each), ``tcp://HOST:PORT`` (a running Dask scheduler: unencrypted and unauthenticated,
it runs whatever pickled task it is sent) or ``tls://HOST:PORT`` (the same over TLS with Dask's own
security settings, ``distributed.comm.tls.*``). Each chunk's result is
written atomically to ``DIR/chunks/chunk-NNNNNN.parquet`` as it arrives; a sweep started again on
the same folder with the same spec skips the chunks already there (``DIR/sweep-state.json``
holds the spec's digest). When every chunk is done, ``DIR/results.parquet`` gathers them in
point order and ``DIR/sweep.json`` records the provenance. Results depend only on the spec (each
point's seed comes from the spec's seed and its index), so every scheduler gives the same table.

Simulator workers (jobs declared ``simulator``: ``render``, ``rcs``) are restarted by their nanny
after ``recycle_after`` tasks (the client keeps one task a worker in flight, so the worker is idle
then), so memory stays bounded; a worker that dies mid-task is replaced by Dask and its task run again. When the
cluster's workers declare a ``GPU`` resource, simulator tasks ask for one.
"""

from __future__ import annotations

import json
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from csuas.base.errors import CsuasError, ParameterError
from csuas.base.fileio import atomic_path, exclusive_lock, prepare_output_dir, write_text_atomic
from csuas.base.paths import inside, sub_folder

from .chunking import auto_chunk_points
from .cluster import check_scheduler, show_progress
from .cluster import open_client as _client
from .spec import SweepSpec

#: Seconds a cluster may have no worker at all before the sweep stops (``--no-worker-timeout-s``).
NO_WORKER_TIMEOUT_S = 60.0


def chunk_bounds(spec: SweepSpec) -> list[tuple[int, int]]:
    """``(start, stop)`` of every chunk, in point order."""
    n, size = spec.n_points, spec.chunk_points
    return [(start, min(start + size, n)) for start in range(0, n, size)]


def run_chunk(spec: SweepSpec, start: int, stop: int) -> dict:
    """Result columns of points ``start..stop``: ``point``, the axes, the job's declared columns and ``time_s``.

    Raises
    ------
    CsuasError
        A chunk function that returned other columns than its job declares (:class:`csuas.sweep.kinds.JobKind`).
    """
    t0 = time.perf_counter()
    columns = spec.points(start, stop)
    kind = spec.kind
    result = kind.chunk(spec, columns, start, stop)
    declared = list(kind.columns(spec))
    if list(result) != declared:
        raise CsuasError(f"sweep job {kind.name}: its chunk returned columns {list(result)}, not {declared}")
    n = stop - start
    elapsed = time.perf_counter() - t0
    return {"point": np.arange(start, stop), **columns, **result, "time_s": np.full(n, elapsed / max(n, 1))}


def _chunk_path(out: Path, index: int) -> Path:
    return inside(out, "chunks", f"chunk-{index:06d}.parquet")


def _write_table(columns: dict, path: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.table({k: (v.astype(str) if v.dtype == object else v) for k, v in columns.items()})
    with atomic_path(path) as tmp:
        pq.write_table(table, tmp)


def _one_thread_per_worker() -> None:
    """On a Dask worker, Dr.Jit's thread pool shrinks to one thread: the cluster's workers are the parallelism."""
    try:
        from distributed import get_worker

        get_worker()
    except (ImportError, ValueError):
        return  # in this process (serial): Dr.Jit keeps its threads
    single_drjit_thread()


def single_drjit_thread() -> None:
    """Dr.Jit's thread pool set to one thread (a worker process's, whose cluster is the parallelism)."""
    import drjit

    if drjit.thread_count() != 1:
        drjit.set_thread_count(1)


def _task(spec: SweepSpec, index: int, start: int, stop: int, out: str) -> tuple:
    """One chunk on a worker: compute and write its parquet file.

    Returns the process id and the Dask worker address that ran it (None in this process), for
    the provenance and for recycling.
    """
    if spec.kind.simulator:
        _one_thread_per_worker()
    _write_table(run_chunk(spec, start, stop), _chunk_path(Path(out), index))
    try:
        from distributed import get_worker

        address = get_worker().address
    except (ImportError, ValueError):
        address = None
    return os.getpid(), address


def _check_state(spec: SweepSpec, out: Path) -> int | None:
    """Refuse a folder holding another sweep; the points per task of this sweep's earlier run, None in a new folder.

    A state written before chunks were sized (no ``chunk_points``) had the spec's own.
    """
    state = inside(out, "sweep-state.json")
    if not state.exists():
        return None
    recorded = json.loads(state.read_text())
    if recorded.get("digest") != spec.digest:
        raise ParameterError(
            "out", str(out), "a new folder, or the folder of this same sweep (it holds another sweep's chunks)"
        )
    return int(recorded.get("chunk_points", spec.chunk_points))


def _record_state(spec: SweepSpec, out: Path) -> None:
    """Record the sweep's digest and points per task, before its first chunk."""
    write_text_atomic(
        inside(out, "sweep-state.json"), json.dumps({"digest": spec.digest, "chunk_points": spec.chunk_points})
    )


def _unreadable_chunk(out: Path, index: int, rows: int, progress) -> bool:
    """True when chunk ``index`` is on disk but is not ``rows`` readable rows: it is run again, with a warning."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = _chunk_path(out, index)
    if not path.exists():
        return False
    try:
        found = pq.read_metadata(path).num_rows
    except (OSError, ValueError, pa.ArrowException) as exc:
        problem = f"unreadable ({type(exc).__name__})"
    else:
        if found == rows:
            return False
        problem = f"holds {found} rows, not {rows}"
    if progress is not None:
        print(f"sweep: warning: chunks/{path.name} {problem}: chunk {index} redone", file=progress, flush=True)
    return True


def _worker_count(client) -> int:
    """Workers of ``client``'s cluster now (at least one); one in this process (``client`` None)."""
    return 1 if client is None else max(1, len(client.scheduler_info().get("workers", {})))


def _run_on_cluster(client, spec: SweepSpec, todo: list, out: Path, no_worker_timeout_s: float, progress) -> tuple:
    """Run the chunks ``todo`` on ``client``'s cluster; the number of workers at the start and the pids that ran them.

    A window of tasks is in flight: one a worker for simulators (a worker due for recycling is idle
    when its task returns), two a worker otherwise. While none finishes, the cluster's workers are
    counted every poll; none for ``no_worker_timeout_s`` stops the run (:class:`_Watchdog`).
    """
    from distributed import wait

    from .warm import WarmUp, plugin_name, wait_warm

    client.register_plugin(WarmUp(spec))  # every worker warms once a job (csuas.sweep.warm)
    client.run(wait_warm, spec.job)
    client.unregister_worker_plugin(plugin_name(spec.job))  # a recycled worker warms in its first chunk
    bounds, started = chunk_bounds(spec), time.perf_counter()
    info = client.scheduler_info()
    n_workers = len(info.get("workers", {}))
    simulator = spec.kind.simulator
    gpu = simulator and any(w.get("resources", {}).get("GPU") for w in info["workers"].values())

    def submit(i):
        return client.submit(
            _task, spec, i, *bounds[i], str(out), key=f"csuas-{spec.digest[:12]}-{i}", pure=False,
            resources={"GPU": 1} if gpu else None, retries=2,
        )  # fmt: skip

    queue = iter(todo)
    pending = {submit(i) for _, i in zip(range(max(1, n_workers) * (1 if simulator else 2)), queue)}
    pids, tasks_by_worker, done = set(), {}, 0
    watchdog = _Watchdog(client, no_worker_timeout_s, out, progress)
    while pending:
        try:
            finished, pending = wait(pending, timeout=watchdog.poll_s, return_when="FIRST_COMPLETED")
        except TimeoutError:
            watchdog.idle(done)
            continue
        for future in finished:
            pid, address = watchdog.result(future, done)
            watchdog.progressed()
            pids.add(pid)
            done += 1
            tasks_by_worker[address] = tasks_by_worker.get(address, 0) + 1
            if simulator and tasks_by_worker[address] >= spec.recycle_after:
                client.restart_workers([address])  # a fresh process: bounded memory (docs/sweeps.md)
                del tasks_by_worker[address]
            following = next(queue, None)
            if following is not None:
                pending.add(submit(following))
            show_progress("sweep: chunks", done, len(todo), started, progress)
    return n_workers, pids


class _Watchdog:
    """Stops a sweep whose cluster has had no worker for ``timeout_s`` [s], wherever the client waits.

    The client waits in two places: for a task to finish, and for a finished task's result, which
    lives on the worker that ran it (a worker killed after finishing leaves the task to be run again).
    Both wait at most :attr:`poll_s` at a time and then count the cluster's workers (:meth:`idle`).
    """

    def __init__(self, client, timeout_s: float, out: Path, progress):
        self.client, self.timeout_s, self.out, self.progress = client, timeout_s, out, progress
        self.poll_s = min(1.0, timeout_s / 4.0)
        self.alone_since: float | None = None

    def progressed(self) -> None:
        """A task's result arrived: the cluster works."""
        self.alone_since = None

    def result(self, future, done: int):
        """``future.result()``, polling the cluster's workers while it waits."""
        while True:
            try:
                return future.result(timeout=self.poll_s)
            except TimeoutError:
                self.idle(done)

    def idle(self, done: int) -> None:
        """Nothing arrived for :attr:`poll_s`: count the workers; none for ``timeout_s`` stops the sweep.

        Raises
        ------
        CsuasError
            One line: how long, how many chunks are written (they stay) and how to resume.
        """
        if self.client.scheduler_info().get("workers"):
            self.alone_since = None
            return
        now = time.monotonic()
        self.alone_since = now if self.alone_since is None else self.alone_since
        if now - self.alone_since < self.timeout_s:
            return
        if self.progress is not None and done:
            self.progress.write("\n")  # end the progress line before the error's
        written = len(list((self.out / "chunks").glob("chunk-*.parquet")))
        raise CsuasError(
            f"no Dask worker for {self.timeout_s:g} s (--no-worker-timeout-s): stopped; the {written} chunk(s) "
            f"written stay in {self.out / 'chunks'}; start workers and run the same command again to resume"
        )


def run_sweep(
    spec: SweepSpec,
    out,
    scheduler: str = "local",
    workers: int | None = None,
    progress=sys.stderr,
    no_worker_timeout_s: float = NO_WORKER_TIMEOUT_S,
) -> dict:
    """Run every chunk not yet in ``out`` and gather the results.

    On a cluster left without a single worker for ``no_worker_timeout_s`` [s] (every worker killed,
    a scheduler nobody serves), the run stops with :class:`csuas.base.errors.CsuasError` (exit 2);
    the chunks already written stay, and the same command resumes once workers are back.

    Returns
    -------
    dict
        The provenance written to ``sweep.json``: csuas version, spec digest, seed, scheduler,
        workers, the worker processes that ran this run's chunks (recycled workers count anew),
        points, chunks (run now and resumed), wall time, and the results' path.
    """
    check_scheduler(scheduler)
    if not (0.0 < no_worker_timeout_s < float("inf")):
        raise ParameterError("no_worker_timeout_s", no_worker_timeout_s, "> 0 [s], finite")
    out = Path(out)
    prepare_output_dir(out)
    sub_folder(out, "chunks")
    for name in ("sweep-state.json", "results.parquet", "sweep.json"):
        inside(out, name)  # a special file there is refused now, not after the work
    with exclusive_lock(out / LOCK_NAME, "--out"):
        return _run_locked(spec, out, scheduler, workers, no_worker_timeout_s, progress)


#: Lock file inside the output folder: one sweep writes into a folder at a time.
LOCK_NAME = ".csuas-sweep.lock"


def _run_locked(spec: SweepSpec, out: Path, scheduler: str, workers: int | None, no_worker_timeout_s, progress) -> dict:
    """The body of :func:`run_sweep`, holding the folder's lock."""
    recorded = _check_state(spec, out)
    started = time.perf_counter()
    client = cluster = None
    try:
        if recorded is None:  # a new sweep: its chunks sized for the workers there are
            if scheduler != "serial":
                client, cluster = _client(scheduler, workers)
            spec = replace(spec, chunk_points=auto_chunk_points(spec, _worker_count(client)))
            _record_state(spec, out)
        else:  # resumed: the chunks of its first run, whatever the workers now
            spec = replace(spec, chunk_points=recorded)
        bounds = chunk_bounds(spec)
        redone = [i for i, (start, stop) in enumerate(bounds) if _unreadable_chunk(out, i, stop - start, progress)]
        todo = [i for i in range(len(bounds)) if i in redone or not _chunk_path(out, i).exists()]
        n_workers, pids = 1, set()
        if scheduler == "serial" or not todo:
            for done, i in enumerate(todo, 1):
                pids.add(_task(spec, i, *bounds[i], str(out))[0])
                show_progress("sweep: chunks", done, len(todo), started, progress)
        else:
            if client is None:
                client, cluster = _client(scheduler, workers)
            n_workers, pids = _run_on_cluster(client, spec, todo, out, no_worker_timeout_s, progress)
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    results = gather(out, len(bounds))
    provenance = {
        "csuas_version": _version(),
        "spec_digest": spec.digest,
        "job": spec.job,
        "scenario": spec.scenario_source,
        "seed": spec.seed,
        "scheduler": scheduler,
        "workers": n_workers,
        "worker_processes": len(pids),
        "points": spec.n_points,
        "chunks": len(bounds),
        "chunk_points": spec.chunk_points,
        "chunks_run": len(todo),
        "chunks_resumed": len(bounds) - len(todo),
        "chunks_redone": redone,
        "wall_time_s": time.perf_counter() - started,
        "results": str(results),
    }
    write_text_atomic(inside(out, "sweep.json"), json.dumps(provenance, indent=2))
    return provenance


def gather(out: Path, n_chunks: int) -> Path:
    """Append the chunk files in point order to ``results.parquet`` (written atomically).

    One chunk is in memory at a time (a row group each), so gathering 10^8 points needs no more
    memory than one chunk of them.
    """
    import pyarrow.parquet as pq

    missing = [i for i in range(n_chunks) if not _chunk_path(out, i).exists()]
    if missing:
        raise CsuasError(f"sweep: {len(missing)} chunk(s) missing after the run, first {missing[0]}")
    path = inside(out, "results.parquet")
    with atomic_path(path) as tmp:
        first = pq.read_table(_chunk_path(out, 0))
        with pq.ParquetWriter(tmp, first.schema) as writer:
            writer.write_table(first)
            del first
            for i in range(1, n_chunks):
                writer.write_table(pq.read_table(_chunk_path(out, i)))
    return path


def _version() -> str:
    from importlib.metadata import version

    try:
        return version("csuas")
    except Exception:  # pragma: no cover - not installed as a distribution
        return "unknown"


def read_results(path) -> dict:
    """``{column: ndarray}`` of a results table."""
    import pyarrow.parquet as pq

    table = pq.read_table(path)
    return {name: np.asarray(table.column(name).to_numpy(zero_copy_only=False)) for name in table.column_names}
