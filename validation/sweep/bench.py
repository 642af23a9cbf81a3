"""Benchmarks of ``csuas sweep`` on this machine (docs/performance.md).

* scaling: a CPU-bound simulator sweep (SBR-PO RCS of the default drone) on a LocalCluster of 1
  and of 2 one-thread workers; each cluster is started and warmed (kernels compiled) before the
  timed runs (the best of ``repeats``), so the ratio is the sweep's, not start-up's;
* per-task overhead: tiny range chunks on one worker against the same chunks computed in this
  process, per task;
* memory: the resident memory of one worker rendering the default drone many times (EO, draft),
  read after every block of renders, without recycling, to show whether it stays flat;
* engage: an ``engage`` sweep (Monte Carlo runs of ``csuas engage``) on 1 and 2 workers
  (:func:`bench_engage_sweep`), the speedup with the CPU share the workers got.
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

from csuas.sweep import parse_spec, run_sweep
from csuas.sweep.run import chunk_bounds, run_chunk

RCS_SPEC = {
    "job": "rcs",
    "seed": 1,
    "chunk_points": 12,
    "options": {"target": "dji_mini_4_pro", "quality": "standard"},
    "axes": {
        "frequency_ghz": [9.4, 16.0, 24.0, 35.0],
        "azimuth_deg": {"min": 0.0, "max": 360.0, "samples": 24},
        "elevation_deg": [-20.0, 0.0, 20.0],
    },
}


def _resident_mb() -> float:
    """This process's resident memory [MB] (Linux /proc; the peak from getrusage elsewhere)."""
    status = Path("/proc/self/status")
    if status.exists():
        for line in status.read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _render_block(n: int) -> float:
    """Render the default drone ``n`` times (EO, draft) in this worker; return its resident memory [MB]."""
    from csuas.render.imaging import RenderSettings, View, render_eo
    from csuas.sweep.run import _one_thread_per_worker

    _one_thread_per_worker()
    for i in range(n):
        render_eo("dji_mini_4_pro", View(300.0 + i), settings=RenderSettings(quality="draft", seed=i))
    return _resident_mb()


def _timed_on_cluster(spec, n_workers: int, folder: Path, repeats: int) -> float:
    """Best of ``repeats`` timed runs on a warmed cluster of ``n_workers`` (this machine's timings are noisy)."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=40) as cluster:  # fmt: skip
        run_sweep(spec, folder / f"warm{n_workers}", cluster.scheduler_address, progress=None)
        best = float("inf")
        for r in range(repeats):
            start = time.perf_counter()
            run_sweep(spec, folder / f"timed{n_workers}-{r}", cluster.scheduler_address, progress=None)
            best = min(best, time.perf_counter() - start)
        return best


def task_overhead_s(folder: Path, tasks: int) -> float:
    """Per-task overhead [s]: ``tasks`` one-point range chunks on one warm worker less the same in this process."""
    from distributed import LocalCluster

    tiny = parse_spec({"job": "range", "chunk_points": 1,
                       "axes": {"target.d_crit_m": [0.05 + 0.001 * i for i in range(tasks)]}})  # fmt: skip
    start = time.perf_counter()
    for bounds in chunk_bounds(tiny):
        run_chunk(tiny, *bounds)
    in_process = time.perf_counter() - start
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=40) as cluster:  # fmt: skip
        run_sweep(tiny, folder / "tiny-warm", cluster.scheduler_address, progress=None)
        start = time.perf_counter()
        run_sweep(tiny, folder / "tiny", cluster.scheduler_address, progress=None)
        on_worker = time.perf_counter() - start
    return (on_worker - in_process) / tasks


def bench_sweep(renders: int = 1000, block: int = 100, repeats: int = 2) -> dict:
    """Scaling 1 -> 2 workers, per-task overhead, and one worker's memory over ``renders`` renders."""
    from distributed import Client, LocalCluster

    spec = parse_spec(RCS_SPEC)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        one = _timed_on_cluster(spec, 1, folder, repeats)
        two = _timed_on_cluster(spec, 2, folder, repeats)
        overhead = task_overhead_s(folder, 200)
        with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                          silence_logs=40) as cluster, Client(cluster.scheduler_address) as client:  # fmt: skip
            memory = [client.submit(_render_block, block, pure=False).result() for _ in range(renders // block)]
    return {
        "rcs_points": spec.n_points,
        "rcs_tasks": len(chunk_bounds(spec)),
        "one_worker_s": one,
        "two_workers_s": two,
        "scaling_1_to_2": one / two,
        "task_overhead_s": overhead,
        "renders": renders,
        "worker_rss_mb_first_block": memory[0],
        "worker_rss_mb_last_block": memory[-1],
        "worker_rss_growth_mb_per_1000_renders": (memory[-1] - memory[0]) / max(renders - block, 1) * 1000,
    }


def _worker_cpu_s() -> float:
    """CPU time of this worker process so far [s] (user + system)."""
    import resource

    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _import_engagement() -> None:
    """Import the engagement's modules (Stone Soup among them) on a worker before the timer starts."""
    import csuas.render.engagement.simulate  # noqa: F401


def _engage_on_cluster(spec, n_workers: int, folder: Path) -> dict:
    """Wall time of the engage sweep on a fresh cluster of ``n_workers`` one-thread workers, its modules imported
    first; the workers' CPU time over the run and the machine's load average before and after."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=40) as cluster, Client(cluster.scheduler_address) as client:  # fmt: skip
        client.run(_import_engagement)
        cpu_before = sum(client.run(_worker_cpu_s).values())
        load_before = os.getloadavg()[0]
        start = time.perf_counter()
        run_sweep(spec, folder / f"engage{n_workers}", cluster.scheduler_address, progress=None)
        wall = time.perf_counter() - start
        cpu = sum(client.run(_worker_cpu_s).values()) - cpu_before
    return {"wall_s": wall, "worker_cpu_s": cpu, "load_before": load_before, "load_after": os.getloadavg()[0]}


def bench_engage_sweep(runs: int = 16, chunk_runs: int = 2, engagement: str = "example") -> dict:
    """An ``engage`` sweep of ``runs`` runs of ``engagement`` on a LocalCluster of 1 and of 2 one-thread workers.

    Each cluster is started and its workers import the engagement's modules before the timer; the
    timed run includes the tasks' transfer of the engagement (1.4 MB for the example) and the gathering
    of the results. The speedup is the ratio of the wall times; ``worker_cpu_per_wall`` (the workers' CPU
    seconds over the wall time) says how much of the machine the workers got: 2 on two idle cores, less
    where other work shares them (the load averages are reported beside); ``worker_cpu_s_per_run`` (1 and 2
    workers) is what a run costs the workers whatever the load, so that the two agree shows the sweep
    adds little work for its second worker. Issue 24's target: >= 1.7x on
    2 cores for 10^4 runs (``csuas bench --only sweep_engage --engage-runs 10000``: hours on 2 cores).
    """
    spec = parse_spec(
        {"job": "engage", "chunk_points": chunk_runs, "options": {"engagement": engagement, "runs": runs}}
    )
    with tempfile.TemporaryDirectory() as tmp:
        one = _engage_on_cluster(spec, 1, Path(tmp))
        two = _engage_on_cluster(spec, 2, Path(tmp))
    return {
        "engagement": engagement,
        "runs": runs,
        "tasks": len(chunk_bounds(spec)),
        "cpu_count": os.cpu_count(),
        "one_worker_s": one["wall_s"],
        "two_workers_s": two["wall_s"],
        "speedup_1_to_2": one["wall_s"] / two["wall_s"],
        "one_worker_cpu_per_wall": one["worker_cpu_s"] / one["wall_s"],
        "two_workers_cpu_per_wall": two["worker_cpu_s"] / two["wall_s"],
        "seconds_per_run_one_worker": one["wall_s"] / runs,
        "worker_cpu_s_per_run": [one["worker_cpu_s"] / runs, two["worker_cpu_s"] / runs],
        "load_average_before_after": [one["load_before"], two["load_after"]],
    }
