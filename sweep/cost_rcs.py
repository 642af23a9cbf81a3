"""The cost of an ``rcs`` sweep's SBR tracing, added once its spec is parsed (the ``rcs`` job's ``JobCost.refine``).

The simulator's modules are imported when an estimate is made: they bring Dr.Jit (seconds to import).
"""

from __future__ import annotations

import os

import numpy as np

from csuas.base.cost import Estimate


def rcs_estimate(spec, base: Estimate, n_workers: int) -> Estimate:
    """``base`` plus the SBR tracing of every point of an ``rcs`` sweep (as ``csuas rcs`` estimates it).

    Each point traces the grid of :func:`~csuas.render.rcs.solver.estimate_tubes` at its frequency on
    ``REPLICAS`` shifted grids (the error estimate); the time is
    :func:`~csuas.render.rcs.solver.estimate_seconds`, shared by the workers.
    """
    from csuas.render.rcs.geometry import load_target
    from csuas.render.rcs.solver import (
        ENGINE_PROCESS_BYTES,
        REPLICAS,
        estimate_peak_bytes,
        estimate_seconds,
        estimate_tubes,
        resolve_quality,
    )

    rays, bounces = resolve_quality(spec.options["quality"], spec.options["rays_per_wavelength"])
    radius = load_target(str(spec.options["target"] or spec.scenario.target_preset)).bounding_radius_m
    axis = spec.axes["frequency_ghz"]
    frequencies, counts = np.unique(axis, return_counts=True)
    if spec.combine == "grid":
        counts = counts * (spec.n_points // len(axis))  # every frequency meets every other axis's values
    per_point = [float(estimate_tubes(radius, float(f), rays)) * REPLICAS for f in frequencies]
    tubes = sum(t * int(c) for t, c in zip(per_point, counts))
    seconds = estimate_seconds(tubes, bounces) / min(n_workers, os.cpu_count() or 1)
    # each worker holds the tubes of one grid (an aspect's replica) in flight at a time
    batch = estimate_peak_bytes(max(per_point) / REPLICAS) - ENGINE_PROCESS_BYTES
    what = f"{base.what} ({tubes:.3g} tubes at {rays:g} rays per wavelength)"
    return Estimate(what, base.seconds + seconds, base.bytes + n_workers * max(batch, 0.0))
