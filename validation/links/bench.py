"""Benchmark of the Sionna RT links: the chosen budget against Sionna's default sample counts.

For each scene the link is solved with the ``draft`` budget (the one the
accuracy rows show exact over flat ground) and with Sionna RT's defaults
(1e6 rays, depth 3); both run through the same path (the scene cached by
:func:`csuas.render.links.scene.link_scene`, devices moved into place), are
timed warm (best of ``repeats`` after one call that builds the scene and
compiles Dr.Jit's kernels, whose time is kept as the cold time) and are
compared with the same closed form, so the speed-up is at equal accuracy.
Times are end to end: scene look-up and device moves, solver,
post-processing.

Sionna's solvers also cost a fixed time per call, whatever the sample
count: Python tracing of their symbolic loops and some ninety kernel
launches (measured with Dr.Jit's kernel history: the kernels themselves
run for well under a millisecond at the draft budget). The floor row (one
ray, at the depth the chosen budget runs at: 0 in free space, its
``max_depth`` over ground) measures it, and the default's time over it
bounds the speed-up any budget resolving the same bounces can reach.
"""

from __future__ import annotations

from csuas.render.links.budget import PRESETS, SIONNA_DEFAULT, LinkBudget
from csuas.render.links.sionna_backend import active_variant
from csuas.validation.links.accuracy import accuracy_vs_time

#: Scenes timed: (link, frequency [GHz], distances [m], height a [m], height b [m], ground).
SCENES = {
    "rf_free_space": ("rf", 2.4, (10.0, 100.0, 1e3, 1e4, 5e4), 50.0, 50.0, None),
    "rf_over_ground": ("rf", 2.4, (10.0, 100.0, 1e3, 1e4, 5e4), 30.0, 2.0, "medium_dry_ground"),
    "radar_free_space": ("radar", 24.0, (10.0, 100.0, 1e3, 1e4), 5.0, 5.0, None),
    "radar_over_ground": ("radar", 24.0, (10.0, 100.0, 1e3, 1e4), 5.0, 30.0, "concrete"),
}

#: Rays of the floor row: the fewest a solver call can shoot.
FLOOR_SAMPLES = 1

#: Largest error [dB] against the closed form for two budgets to count as equally accurate.
EQUAL_ACCURACY_DB = 1e-3


def bench_links(repeats: int = 3, budget: str = "draft") -> dict:
    """Time each link scene at ``budget`` and at Sionna's defaults.

    Parameters
    ----------
    repeats : int
        Warm calls timed per budget (best of them is kept).
    budget : str
        Preset compared with Sionna's defaults.

    Returns
    -------
    dict
        ``variant`` and, per scene, ``chosen``, ``sionna_default`` and
        ``sionna_floor`` (one ray, same depth as ``chosen``) rows of
        :func:`csuas.validation.links.accuracy.accuracy_vs_time` (warm
        ``time_s`` and ``cold_time_s`` each), ``speedup`` (default time /
        chosen time, warm), ``cold_speedup`` (the same for the cold calls),
        ``speedup_ceiling`` (default time / the cheapest call measured on the
        scene, warm: the most any budget can gain there; the floor, or the
        chosen budget itself when timing noise made it the faster, so the
        ceiling never reads below ``speedup``) and ``equal_accuracy`` (chosen and
        default both within ``EQUAL_ACCURACY_DB`` of the closed form).
    """
    scenes = {}
    for name, (link, f_ghz, distances, h_a, h_b, ground) in SCENES.items():
        depth = PRESETS[budget].max_depth if ground is not None else 0  # as the links run the presets
        floor_budget = LinkBudget("sionna_floor", FLOOR_SAMPLES, depth)
        chosen, default, floor = accuracy_vs_time(
            link,
            f_ghz,
            distances,
            h_a,
            h_b,
            ground,
            budgets=(PRESETS[budget], SIONNA_DEFAULT, floor_budget),
            repeats=repeats,
        )
        scenes[name] = {
            "chosen": chosen,
            "sionna_default": default,
            "sionna_floor": floor,
            "speedup": default["time_s"] / chosen["time_s"],
            "cold_speedup": default["cold_time_s"] / chosen["cold_time_s"],
            "speedup_ceiling": default["time_s"] / min(floor["time_s"], chosen["time_s"]),
            "equal_accuracy": max(chosen["max_error_db"], default["max_error_db"]) <= EQUAL_ACCURACY_DB,
        }
    return {"variant": active_variant(), "budget": budget, "scenes": scenes}
