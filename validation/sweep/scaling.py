"""``csuas bench --only sweep_scaling``: one against two workers on a warm cluster (issue 25, section 4).

For each of two sweeps, an RCS sweep (SBR-PO of the default drone, CPU-bound, about a minute of one
core at standard quality) and a ``pd`` sweep (Pd curves of every sensor over radar power and
Swerling case, about half a minute of one core), a ``LocalCluster`` of 1 and then of 2 one-thread
process workers is started and warmed first (the job's :class:`~csuas.sweep.warm.WarmUp` registered
and waited for), and only the sweep is timed. The specs give no ``chunk_points``, so the chunks are
sized for the workers (:mod:`csuas.sweep.chunking`). Targets: >= 1.7x for the RCS sweep and >= 1.5x
for the pd sweep on 2 idle cores.

On a machine shared with other work the wall-time ratio measures the load as much as the sweep, so
beside it: the load average before and after each run, each worker's CPU seconds, and the speed-up
the CPU seconds imply on idle cores (one worker's CPU time over the busiest of the two workers'),
which counts what the second worker adds in overhead and in load imbalance but not what other
processes take. The per-task overhead: tiny range chunks (one point each) on one warm worker against
the same chunks computed in this process, per task (:data:`csuas.sweep.chunking.TASK_OVERHEAD_S`).
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

from csuas.sweep import parse_spec, run_sweep
from csuas.sweep.warm import WarmUp, plugin_name, wait_warm

from .bench import _worker_cpu_s, task_overhead_s


def _rcs_spec(azimuths: int) -> dict:
    """The RCS sweep: 4 bands x ``azimuths`` drawn azimuths x 3 elevations of the default drone, standard quality."""
    return {
        "job": "rcs",
        "seed": 1,
        "options": {"target": "dji_mini_4_pro", "quality": "standard"},
        "axes": {
            "frequency_ghz": [9.4, 16.0, 24.0, 35.0],
            "azimuth_deg": {"min": 0.0, "max": 360.0, "samples": azimuths},
            "elevation_deg": [-20.0, 0.0, 20.0],
        },
    }


def _pd_spec(powers: int) -> dict:
    """The pd sweep: ``powers`` radar powers (log-spaced 1 W to 1 kW) x Swerling 0, 1 and 3 of the default scenario."""
    return {
        "job": "pd",
        "seed": 1,
        "axes": {
            "sensors.radar.p_tx_w": [float(10 ** (3.0 * i / max(powers - 1, 1))) for i in range(powers)],
            "sensors.radar.swerling": [0, 1, 3],
        },
    }


def _timed(spec, n_workers: int, folder: Path) -> dict:
    """Wall time of ``spec`` on a fresh, warmed cluster of ``n_workers``; its workers' CPU seconds and the load."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=40) as cluster, Client(cluster.scheduler_address) as client:  # fmt: skip
        client.register_plugin(WarmUp(spec))
        client.run(wait_warm, spec.job)  # every worker warm before the clock starts
        client.unregister_worker_plugin(plugin_name(spec.job))
        cpu_before = client.run(_worker_cpu_s)
        load_before = os.getloadavg()[0]
        start = time.perf_counter()
        out = run_sweep(spec, folder / f"{spec.job}-{n_workers}", cluster.scheduler_address, progress=None)
        wall = time.perf_counter() - start
        cpu = {w: s - cpu_before[w] for w, s in client.run(_worker_cpu_s).items() if w in cpu_before}
    return {
        "wall_s": wall,
        "chunks": out["chunks"],
        "chunk_points": out["chunk_points"],
        "worker_cpu_s": sorted(cpu.values(), reverse=True),
        "load": [load_before, os.getloadavg()[0]],
    }


def _scaling(spec, folder: Path) -> dict:
    """One and two workers on ``spec``: the wall times, their ratio and the ratio the CPU seconds imply."""
    one, two = _timed(spec, 1, folder), _timed(spec, 2, folder)
    return {
        "points": spec.n_points,
        "chunks_one_two": [one["chunks"], two["chunks"]],
        "chunk_points_one_two": [one["chunk_points"], two["chunk_points"]],
        "one_worker_s": one["wall_s"],
        "two_workers_s": two["wall_s"],
        "speedup": one["wall_s"] / two["wall_s"],
        "one_worker_cpu_s": one["worker_cpu_s"][0],
        "two_workers_cpu_s": two["worker_cpu_s"],
        "speedup_from_worker_cpu": one["worker_cpu_s"][0] / max(two["worker_cpu_s"][0], 1e-9),
        "worker_cpu_per_wall_one_two": [
            one["worker_cpu_s"][0] / one["wall_s"],
            sum(two["worker_cpu_s"]) / two["wall_s"],
        ],
        "load_average_one": one["load"],
        "load_average_two": two["load"],
    }


def bench_sweep_scaling(rcs_azimuths: int = 48, pd_powers: int = 200, overhead_tasks: int = 200) -> dict:
    """One against two warm workers on an RCS sweep and a pd sweep, and the per-task overhead (module docstring)."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        rcs = _scaling(parse_spec(_rcs_spec(rcs_azimuths)), folder)
        pd = _scaling(parse_spec(_pd_spec(pd_powers)), folder)
        overhead = task_overhead_s(folder, overhead_tasks)
    return {
        "cpu_count": os.cpu_count(),
        "rcs": rcs,
        "pd": pd,
        "task_overhead_s": overhead,
        "targets": {"rcs_speedup": 1.7, "pd_speedup": 1.5},
    }
