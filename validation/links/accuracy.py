"""Accuracy against time of the Sionna RT links over their sample budget.

Each row is one budget: its warm wall time (best of ``repeats`` calls on
the cached scene, after one call that builds the scene and compiles
Dr.Jit's kernels), the cold time of that first call (the scene cache is
emptied before it, so it includes building the scene), and the largest
error [dB] against the closed form of the same scene:
Friis (Eq. 54) or the radar equation (Eq. 68) in free space, the two-ray or
four-path model (:mod:`csuas.render.links.two_ray`) over ground.
"""

from __future__ import annotations

import numpy as np

from csuas.core.dielectric import ground_permittivity
from csuas.core.radar import received_power_w
from csuas.core.rf import free_space_path_loss_db
from csuas.core.units import wavelength_m
from csuas.render.links.budget import PRESETS, SIONNA_DEFAULT, LinkBudget
from csuas.render.links.radar import radar_link_gain
from csuas.render.links.rf import rf_path_gain
from csuas.render.links.scene import clear_scene_cache
from csuas.render.links.two_ray import radar_four_paths, two_ray_path_gain_db

#: Budgets swept by default: raw sample counts at depth 1, the presets, Sionna's defaults.
DEFAULT_BUDGETS = (
    LinkBudget("samples_1", 1, 1),
    LinkBudget("samples_4", 4, 1),
    *PRESETS.values(),
    SIONNA_DEFAULT,
)


def closed_form_db(link, frequency_ghz, distance_m, height_a_m, height_b_m, ground_eta=None, sigma_m2=0.01):
    """Closed-form gain [dB] of the link Sionna computes (see module docstring)."""
    d = np.atleast_1d(np.asarray(distance_m, float))
    if link == "rf":
        if ground_eta is None:
            return -free_space_path_loss_db(frequency_ghz, np.hypot(d, height_a_m - height_b_m))
        return two_ray_path_gain_db(frequency_ghz, d, height_a_m, height_b_m, ground_eta)
    radar = np.stack([d, np.zeros_like(d), np.full_like(d, height_a_m)], -1)
    if ground_eta is None:
        r = np.linalg.norm(radar - np.array([0.0, 0.0, height_b_m]), axis=-1)
        return 10 * np.log10(received_power_w(1.0, 0.0, 0.0, wavelength_m(frequency_ghz), sigma_m2, r))
    paths = radar_four_paths(frequency_ghz, radar, np.array([0.0, 0.0, height_b_m]), sigma_m2, ground_eta)
    return 20 * np.log10(np.abs(paths.sum(-1)))


def accuracy_vs_time(
    link="rf",
    frequency_ghz=2.4,
    distance_m=(10.0, 100.0, 1000.0, 10000.0),
    height_a_m=30.0,
    height_b_m=2.0,
    ground="medium_dry_ground",
    budgets=DEFAULT_BUDGETS,
    repeats=2,
):
    """Rows of (budget, time, error) for one link scene.

    Parameters
    ----------
    link : {"rf", "radar"}
        ``rf``: drone transmitter at ``height_a_m`` to sensors at
        ``height_b_m``; ``radar``: radars at ``height_a_m``, drone at
        ``height_b_m`` (0.01 m^2).
    frequency_ghz, distance_m, ground
        Scene; ``ground=None`` for free space.
    budgets : iterable of LinkBudget
    repeats : int
        Warm calls timed per budget (>= 1).

    Returns
    -------
    list of dict
        ``budget``, ``samples``, ``max_depth`` (as run: the presets run at
        depth 0 in free space), ``time_s`` (warm, best of repeats),
        ``cold_time_s`` (first call, scene built anew), ``max_error_db``,
        ``paths_found`` (minimum over the distances).
    """
    rows = []
    for budget in budgets:
        times = []
        clear_scene_cache()
        for _ in range(1 + max(1, int(repeats))):
            if link == "rf":
                result = rf_path_gain(frequency_ghz, distance_m, height_a_m, height_b_m, ground=ground, budget=budget)
            else:
                result = radar_link_gain(
                    frequency_ghz, distance_m, height_a_m, height_b_m, ground=ground, budget=budget
                )
            times.append(result.time_s)
        eta = None
        if ground is not None:
            eta = ground_permittivity(result.extra, frequency_ghz)
        expected = closed_form_db(link, frequency_ghz, distance_m, height_a_m, height_b_m, eta)
        rows.append(
            {
                "budget": budget.name,
                "samples": result.budget.samples,
                "max_depth": result.budget.max_depth,
                "time_s": min(times[1:]),
                "cold_time_s": times[0],
                "max_error_db": float(np.max(np.abs(result.path_gain_db - expected))),
                "paths_found": int(result.n_paths.min()),
            }
        )
    return rows
