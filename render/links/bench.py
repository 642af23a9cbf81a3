"""Benchmark of the Sionna RT links: the chosen budget against Sionna's default sample counts.

For each scene the link is solved with the ``draft`` budget (the one the
accuracy rows show exact over flat ground) and with Sionna RT's defaults
(1e6 rays, depth 3); both are timed warm (best of ``repeats`` after one
compiling call) and compared with the same closed form, so the speed-up is
at equal accuracy. Times are end to end: scene set-up, solver, post-processing.
"""

from __future__ import annotations

from csuas.render.links.accuracy import accuracy_vs_time
from csuas.render.links.budget import PRESETS, SIONNA_DEFAULT
from csuas.render.links.sionna_backend import active_variant

#: Scenes timed: (link, frequency [GHz], distances [m], height a [m], height b [m], ground).
SCENES = {
    "rf_free_space": ("rf", 2.4, (10.0, 100.0, 1e3, 1e4, 5e4), 50.0, 50.0, None),
    "rf_over_ground": ("rf", 2.4, (10.0, 100.0, 1e3, 1e4, 5e4), 30.0, 2.0, "medium_dry_ground"),
    "radar_free_space": ("radar", 24.0, (10.0, 100.0, 1e3, 1e4), 5.0, 5.0, None),
    "radar_over_ground": ("radar", 24.0, (10.0, 100.0, 1e3, 1e4), 5.0, 30.0, "concrete"),
}

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
        ``variant`` and, per scene, ``chosen`` and ``sionna_default`` rows of
        :func:`csuas.render.links.accuracy.accuracy_vs_time`, ``speedup``
        (default time / chosen time) and ``equal_accuracy`` (both within
        ``EQUAL_ACCURACY_DB`` of the closed form).
    """
    scenes = {}
    for name, (link, f_ghz, distances, h_a, h_b, ground) in SCENES.items():
        chosen, default = accuracy_vs_time(link, f_ghz, distances, h_a, h_b, ground,
                                           budgets=(PRESETS[budget], SIONNA_DEFAULT), repeats=repeats)
        scenes[name] = {
            "chosen": chosen,
            "sionna_default": default,
            "speedup": default["time_s"] / chosen["time_s"],
            "equal_accuracy": max(chosen["max_error_db"], default["max_error_db"]) <= EQUAL_ACCURACY_DB,
        }
    return {"variant": active_variant(), "budget": budget, "scenes": scenes}
