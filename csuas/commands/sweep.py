"""``csuas sweep SPEC --out DIR``: a sweep over scenario parameters, in one process or on Dask (docs/sweeps.md).

JSON (``--json``): the provenance of ``DIR/sweep.json`` (``csuas_version``, ``spec_digest``,
``job``, ``scenario``, ``seed``, ``scheduler``, ``workers``, ``worker_processes``, ``points``,
``chunks``, ``chunks_run``, ``chunks_resumed``, ``chunks_redone``, ``wall_time_s``, ``results``), plus ``columns`` of
``DIR/results.parquet`` and ``cost_estimate`` (:mod:`csuas.sweep.cost`, checked before any axis is drawn).
"""

from __future__ import annotations

import sys

from csuas.base.cost import add_limit_arguments, check_limits
from csuas.base.errors import ParameterError
from csuas.base.fileio import read_spec
from csuas.core.scenario import load_scenario
from csuas.defaults import sweep_path


def add_arguments(parser):
    """Declare the options of ``csuas sweep``."""
    from csuas.sweep.run import NO_WORKER_TIMEOUT_S

    parser.add_argument("spec", help="sweep spec TOML file, or an embedded spec (range_rain, pd_radar_power, ...)")
    parser.add_argument("--out", required=True, help="output folder (results.parquet, sweep.json, chunks/)")
    parser.add_argument(
        "--scheduler",
        default="local",
        help="serial (this process), local (default: a LocalCluster of process workers), tcp://HOST:PORT (a Dask "
        "scheduler: unencrypted, trusted networks only) or tls://HOST:PORT (Dask's TLS settings, docs/sweeps.md)",
    )
    parser.add_argument("--workers", type=int, default=None, help="workers of the local cluster (default: CPU count)")
    parser.add_argument(
        "--no-worker-timeout-s",
        type=float,
        default=NO_WORKER_TIMEOUT_S,
        metavar="S",
        help=f"stop (exit 2) when the cluster has had no worker for S seconds; written chunks stay and the same "
        f"command resumes (default {NO_WORKER_TIMEOUT_S:g})",
    )
    add_limit_arguments(parser)


def run(args) -> dict:
    """Validate the spec, run or resume the sweep, and return its provenance."""
    from csuas.sweep import parse_spec, read_results, run_sweep
    from csuas.sweep.cost import axis_lengths, largest_swarm, sweep_estimate, workers_of
    from csuas.sweep.kinds import JOB_KINDS

    if args.workers is not None and args.workers < 1:
        raise ParameterError("workers", args.workers, "a whole number >= 1")
    data = read_spec(args.spec, sweep_path, "sweep spec")
    lengths = axis_lengths(data)  # before any axis is drawn
    if data.get("job") not in JOB_KINDS or not isinstance(data.get("scenario", "default"), str):
        parse_spec(data)  # refuses the job or the scenario, with every other mistake of the spec
    kind = JOB_KINDS[data["job"]]
    scenario = load_scenario(data.get("scenario", "default")) if kind.takes_scenario else None
    sensors = len(scenario.sensors) if scenario is not None else 0
    drones = largest_swarm(data, scenario.swarm.count) if scenario is not None and scenario.swarm is not None else 0
    estimate = sweep_estimate(data, lengths, sensors, args.scheduler, args.workers, drones)
    refine = kind.cost.refine  # a cost that needs the parsed spec (rcs: the tubes, from the target and frequencies)
    check_limits(estimate, args, "sweep", announce=refine is None)
    spec = parse_spec(data)
    if refine is not None:
        estimate = refine(spec, estimate, workers_of(args.scheduler, args.workers))
        check_limits(estimate, args, "sweep")
    provenance = run_sweep(
        spec, args.out, args.scheduler, args.workers, progress=sys.stderr, no_worker_timeout_s=args.no_worker_timeout_s
    )
    provenance["cost_estimate"] = estimate.as_dict()
    provenance["columns"] = list(read_results(provenance["results"]))
    return provenance


def render_text(result: dict) -> str:
    """Where the results are and what the run took."""
    return (
        f"sweep {result['job']} of {result['scenario']}: {result['points']:,} points in {result['chunks']} chunk(s) "
        f"({result['chunks_resumed']} resumed) on {result['scheduler']} with {result['workers']} worker(s), "
        f"{result['wall_time_s']:.1f} s\nresults: {result['results']}\ncolumns: {', '.join(result['columns'])}"
    )
