"""Cost of ``csuas rcs-statistics`` (time and peak memory): every preset and band at its aspect budget.

The sphere average of a band is adaptive: it stops when its mean reaches the requested accuracy,
at most at ``max_aspects`` aspects. The estimate is that budget's, the longest the command can
run: each aspect costs a fixed part (the batch's rotations, fields and bookkeeping) and its
tubes (:func:`csuas.render.rcs.solver.estimate_tubes` on one grid, traced at
:data:`~csuas.render.rcs.solver.TUBE_BOUNCES_PER_S_CPU`).

Times are for 2 idle CPU cores: the shipped table (standard quality, budget 8192, 256 to 2816
aspects a band, 26880 in all) took 152 s there, 142 s of it the tubes at the engine's measured
rate, leaving 0.36 ms an aspect. Under a load average of 10-20, black_hornet_3 at 2.4 GHz, draft
(16 tubes an aspect), with the accuracy out of reach so the budget is spent, took 9, 21 and 70 s
for 1024, 4096 and 16384 aspects (4 ms an aspect, about 10 times the idle figure) inside a
process of 289-298 MB.
"""

from __future__ import annotations

from csuas.base.cost import Estimate

#: Fixed wall time of one aspect of a sphere average [s] (0.36 ms from the shipped table's run).
ASPECT_SECONDS = 0.4e-3
#: Start: imports and the engines' meshes [s].
START_SECONDS = 2.0
#: Resident memory of the process with an SBR engine [B], and per aspect kept (samples, weights) [B].
PROCESS_BYTES = 300e6
ASPECT_BYTES = 200.0


def statistics_estimate(presets, bands_ghz, quality: str, max_aspects: int) -> Estimate:
    """Longest time and peak memory of :func:`~csuas.validation.rcs.statistics_table.drone_statistics`."""
    from csuas.render.rcs.geometry import load_target
    from csuas.render.rcs.solver import estimate_seconds, estimate_tubes, resolve_quality

    rays, bounces = resolve_quality(quality)
    seconds = START_SECONDS
    for preset in presets:
        radius = load_target(preset).bounding_radius_m
        for f in bands_ghz:
            per_aspect = ASPECT_SECONDS + estimate_seconds(estimate_tubes(radius, float(f), rays), bounces)
            seconds += float(max_aspects) * per_aspect
    peak = PROCESS_BYTES + ASPECT_BYTES * float(max_aspects)
    bands = len(presets) * len(bands_ghz)
    what = (
        f"rcs-statistics of {bands} band(s) at up to --max-aspects {max_aspects:,} each at {quality} quality "
        "(the budget's worst case; a band stops earlier once it reaches --accuracy-db)"
    )
    return Estimate(what, seconds, peak)
