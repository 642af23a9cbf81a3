"""The ``engage`` sweep job: the Monte Carlo runs of an engagement (``csuas engage``), shared out as chunks.

The sweep's points are the runs ``0 .. runs - 1`` of the engagement spec named by ``options.engagement``
(``options.runs`` unless the spec's own count): one chunk is a block of runs, and run ``i`` is
:func:`csuas.render.engagement.simulate.run_once` seeded by the engagement spec's ``seed`` and ``i``
alone, so the table is the same whatever the chunking, the scheduler or the workers, and each row is
the run of the same index in ``csuas engage``'s ``runs_detail``. The engagement (site, scenario, looks)
is built once, when the spec is parsed, and travels with each task. The engagement's modules (Stone
Soup among them, seconds to import) are imported when the job is used, not by every sweep.

Columns per run: ``first_track_time_s`` [s] and ``first_track_range_m`` [m] (NaN when never
confirmed), ``warning_time_s`` [s] (0 when never), ``track_continuity``, ``gospa_mean`` [m],
``false_tracks.CAUSE`` (noise, clutter, birds) and ``false_alarms.SENSOR.noise`` / ``.clutter``.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from csuas.base.cost import Estimate
from csuas.base.fileio import read_spec
from csuas.defaults import engagement_path

if TYPE_CHECKING:
    from .spec import SweepSpec

#: Runs per task: a run of the example takes 3.4 s of CPU, so a task is about half a minute of one core.
CHUNK_RUNS = 8
#: Time of one run on a core of its own [s]: the embedded example (radar and EO, birds at 2 per km^2), CPU
#: time of Dask workers over 16 runs (``csuas bench --only sweep_engage``): 3.39 s a run on one worker,
#: 3.52 s on two. On 2 cores shared with other work (load 13) the wall time was 22 s a run.
SECONDS_PER_RUN = 3.5
#: Resident memory of a process running engage chunks [B]: Stone Soup, SciPy and the engagement (266 MB).
PROCESS_BYTES = 280e6
#: What a run reports once, as the record of ``run_once`` names it.
RUN_VALUES = ("first_track_time_s", "first_track_range_m", "warning_time_s", "track_continuity", "gospa_mean")
#: Kinds of each sensor's false alarms.
ALARM_KINDS = ("noise", "clutter")


def prepare(spec: SweepSpec) -> SweepSpec:
    """The spec with the engagement built (its ``context``), its runs as the points and the engagement spec in
    the digest (a resumed sweep of an edited engagement spec is another sweep)."""
    from csuas.render.engagement.build import load_engagement

    source = spec.options["engagement"]
    engage_spec, engagement = load_engagement(source)
    runs = spec.options["runs"] or engage_spec.runs
    text = json.dumps(read_spec(source, engagement_path, "engagement spec"), sort_keys=True, default=str)
    digest = hashlib.sha256(f"{spec.digest}\0{runs}\0{text}".encode()).hexdigest()
    return replace(spec, count=runs, context=engagement, digest=digest)


def runs_estimate(spec: SweepSpec, base, n_workers: int):
    """``base`` (one point) plus the other runs of the sweep at :data:`SECONDS_PER_RUN`, shared by the workers."""
    parallel = min(n_workers, os.cpu_count() or 1)
    seconds = base.seconds + (spec.n_points - 1) * SECONDS_PER_RUN / parallel
    return Estimate(f"an engage sweep of {spec.n_points:,} runs on {n_workers} worker(s)", seconds, base.bytes)


def warm_up(spec: SweepSpec) -> None:
    """Import the engagement's modules (Stone Soup among them, seconds) once per worker, not a run (3.5 s)."""
    from csuas.render.engagement import simulate  # noqa: F401


def engage_columns(spec: SweepSpec) -> list[str]:
    """Columns of the ``engage`` job (module docstring), the sensors' in the engagement's order."""
    from csuas.render.engagement.simulate import CAUSES

    alarms = [f"false_alarms.{name}.{kind}" for name in spec.context.sensors for kind in ALARM_KINDS]
    return [*RUN_VALUES, *(f"false_tracks.{cause}" for cause in CAUSES), *alarms]


def engage_chunk(spec: SweepSpec, columns: dict, start: int, stop: int) -> dict:
    """Runs ``start .. stop - 1`` of the engagement, one row each."""
    from csuas.render.engagement.simulate import CAUSES, run_once

    out = {column: np.full(stop - start, np.nan) for column in engage_columns(spec)}
    for row, index in enumerate(range(start, stop)):
        record = run_once(spec.context, index)
        for key in RUN_VALUES:
            out[key][row] = np.nan if record[key] is None else record[key]
        for cause in CAUSES:
            out[f"false_tracks.{cause}"][row] = sum(track["cause"] == cause for track in record["false_tracks"])
        for name, counts in record["false_alarms"].items():
            for kind in ALARM_KINDS:
                out[f"false_alarms.{name}.{kind}"][row] = counts[kind]
    return out
