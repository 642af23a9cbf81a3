"""A Dask client for ``csuas sweep`` and ``csuas coverage --scheduler``, and their progress line with an ETA.

Schedulers: ``local`` (a ``LocalCluster`` of process workers, one thread each), ``tcp://HOST:PORT`` (a
running Dask scheduler: unencrypted and unauthenticated, it runs whatever pickled task it is sent) or
``tls://HOST:PORT`` (the same over TLS with Dask's own security settings, ``distributed.comm.tls.*``;
docs/sweeps.md). ``serial`` (this process, no Dask) is the callers' own.
"""

from __future__ import annotations

import os
import time

from csuas.base.errors import ParameterError

#: Seconds to wait for a ``tcp://`` scheduler before giving up.
CONNECT_TIMEOUT_S = 10.0
#: Workers of a local cluster by default: one a CPU core.
DEFAULT_WORKERS = max(1, os.cpu_count() or 1)
#: The schedulers the commands accept (a prefix for the remote ones).
SCHEDULERS = "serial, local, tcp://HOST:PORT or tls://HOST:PORT"


def check_scheduler(scheduler: str, name: str = "scheduler") -> None:
    """Refuse a scheduler that is none of :data:`SCHEDULERS`, naming the option ``name``."""
    if scheduler not in ("serial", "local") and not scheduler.startswith(("tcp://", "tls://")):
        raise ParameterError(name, scheduler, SCHEDULERS)


def open_client(scheduler: str, workers: int | None):
    """``(client, cluster)``: a new ``LocalCluster`` of ``workers`` processes (default: the CPU count) and its
    client for ``local``, else a client of the running scheduler and None. A ParameterError naming
    ``scheduler`` when it cannot be reached or TLS is asked for without Dask's TLS settings."""
    from distributed import Client, LocalCluster

    if scheduler == "local":
        cluster = LocalCluster(
            n_workers=workers or DEFAULT_WORKERS,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=40,
        )
        return Client(cluster), cluster
    security = None
    if scheduler.startswith("tls://"):
        from distributed.security import Security

        security = Security()  # Dask's own settings: distributed.comm.tls.* (docs/sweeps.md)
        if not (security.tls_ca_file and security.tls_client_cert):
            raise ParameterError(
                "scheduler",
                scheduler,
                "a tls:// scheduler with Dask's TLS settings in place (distributed.comm.tls.ca-file and "
                "distributed.comm.tls.client.cert/key, e.g. DASK_DISTRIBUTED__COMM__TLS__CA_FILE; docs/sweeps.md)",
            )
    try:
        return Client(scheduler, timeout=CONNECT_TIMEOUT_S, security=security), None
    except (OSError, TimeoutError) as exc:
        raise ParameterError("scheduler", scheduler, f"a reachable Dask scheduler ({type(exc).__name__})") from None


def show_progress(what: str, done: int, total: int, started: float, stream) -> None:
    """Rewrite the progress line ``<what>: done/total, elapsed, ETA`` on ``stream`` (None: silent).

    ``what`` is ``"<command>: <units>"`` (e.g. ``"sweep: chunks"``); the ETA is the mean time per unit so far
    times the units left [s]; a newline ends the line when the last unit is done.
    """
    if stream is None:
        return
    command, units = what.split(": ", 1)
    elapsed = time.perf_counter() - started
    eta = elapsed / done * (total - done) if done else float("nan")
    stream.write(f"\r{command}: {done}/{total} {units}, {elapsed:.0f} s, ETA {eta:.0f} s   ")
    stream.flush()
    if done == total:
        stream.write("\n")
