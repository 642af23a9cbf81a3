"""RF path gain between the drone's transmitter and the RF sensor with Sionna RT's PathSolver.

The drone transmits from height ``tx_height_m`` above the origin; one RF
sensor (receiver) per requested horizontal distance d stands at (d, 0,
``rx_height_m``). All distances are solved in one ``PathSolver`` call, on
a cached scene (:func:`csuas.render.links.scene.link_scene`) whose devices
are moved into place.
Antennas are isotropic (gain 0 dBi) and vertically polarised, so the path
gain is the link's P_rx / (P_tx G_tx G_rx): in free space it equals
-L_fspl of the paper's Eq. 54 at the slant range, and over a flat ground of
an ITU material it follows the two-ray model
(:mod:`csuas.render.links.two_ray`), lobes and nulls included.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from csuas.base.errors import ParameterError
from csuas.render.links.budget import PRESETS, LinkBudget, resolve_budget
from csuas.render.links.paths import coherent_coefficients
from csuas.render.links.scene import check_frequency, ground_properties, link_scene, path_solver
from csuas.render.links.sionna_backend import active_variant, load_sionna_rt

#: Largest horizontal distance accepted [m].
MAX_DISTANCE_M = 1.0e6


@dataclass
class LinkResult:
    """Path gain of one batch of links.

    Attributes
    ----------
    path_gain_db : numpy.ndarray
        10 log10 |sum of the paths' coefficients|^2 [dB], one per distance.
    coefficients : numpy.ndarray of complex, shape (n, n_paths)
        Each path's coefficient with its float64 phase.
    n_paths : numpy.ndarray of int
        Valid paths found per distance.
    time_s : float
        Wall time of the whole batch: scene set-up (a cache look-up and device
        moves once the scene is cached), solver, post-processing [s].
    budget : LinkBudget
    variant : str
        Mitsuba variant Sionna ran on.
    extra : dict
        Geometry (slant ranges [m]) and the ground's material data.
    """

    path_gain_db: np.ndarray
    coefficients: np.ndarray
    n_paths: np.ndarray
    time_s: float
    budget: LinkBudget
    variant: str
    extra: dict = field(default_factory=dict)


def check_distances(distance_m) -> np.ndarray:
    """1-D float array of horizontal distances, each in (0, MAX_DISTANCE_M] [m]."""
    try:
        d = np.atleast_1d(np.asarray(distance_m, dtype=float))
    except (TypeError, ValueError):
        raise ParameterError("distance_m", distance_m, f"numbers in (0, {MAX_DISTANCE_M:g}] m") from None
    if d.ndim != 1 or d.size == 0 or not np.all(np.isfinite(d)) or np.any(d <= 0) or np.any(d > MAX_DISTANCE_M):
        raise ParameterError("distance_m", distance_m, f"one or more numbers in (0, {MAX_DISTANCE_M:g}] m")
    return d


def check_height(name: str, value, over_ground: bool) -> float:
    """Antenna height [m]: finite, in [0, 1e5], strictly positive over ground."""
    try:
        h = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, "a height in [0, 1e5] m") from None
    low_ok = h > 0 if over_ground else h >= 0
    if not (np.isfinite(h) and low_ok and h <= 1e5):
        raise ParameterError(name, value, "(0, 1e5] m over ground" if over_ground else "[0, 1e5] m")
    return h


def rf_path_gain(
    frequency_ghz,
    distance_m,
    tx_height_m=10.0,
    rx_height_m=10.0,
    ground=None,
    budget="standard",
    polarization="V",
    seed=1,
) -> LinkResult:
    """Path gain [dB] from the drone's transmitter to the RF sensor, by Sionna RT.

    Parameters
    ----------
    frequency_ghz : float
        Carrier frequency [GHz], 0.1 to 100 (an ITU ground narrows it to its
        range of validity, e.g. 1-10 GHz for ``medium_dry_ground``).
    distance_m : float or array_like
        Horizontal distances [m], each in (0, 1e6].
    tx_height_m, rx_height_m : float
        Heights of the drone's transmitter and of the sensor [m].
    ground : str or None
        ITU-R P.2040 material of a flat ground at z = 0 (``"concrete"``,
        ``"medium_dry_ground"``, ...), or None for free space.
    budget : str or LinkBudget
        ``"draft"``, ``"standard"``, ``"reference"``, ``"sionna_default"``
        (see :mod:`csuas.render.links.budget`) or a budget of its own rays per source and
        maximum depth (:func:`csuas.render.links.budget.resolve_budget` makes one from a preset
        and overrides).
    polarization : {"V", "H"}
        Polarisation of both isotropic antennas.
    seed : int
        Seed of Sionna's sampler (results are deterministic for a seed).

    Returns
    -------
    LinkResult
    """
    frequency_ghz = check_frequency(frequency_ghz)
    d = check_distances(distance_m)
    over_ground = ground is not None
    h_tx = check_height("tx_height_m", tx_height_m, over_ground)
    h_rx = check_height("rx_height_m", rx_height_m, over_ground)
    if polarization not in ("V", "H"):
        raise ParameterError("polarization", polarization, "V or H")
    chosen = resolve_budget(budget)
    eps_sigma = ground_properties(ground, frequency_ghz) if over_ground else None
    if not over_ground and chosen.name in PRESETS:
        chosen = LinkBudget(chosen.name, chosen.samples, 0)  # nothing to hit: line of sight only

    load_sionna_rt()  # the first call imports Sionna: not part of the link's time
    start = time.perf_counter()
    link = link_scene(frequency_ghz, ground, float(d.max()), polarization)
    tx_pos = np.array([[0.0, 0.0, h_tx]])
    rx_pos = np.column_stack([d, np.zeros_like(d), np.full_like(d, h_rx)])
    link.place(tx_pos, rx_pos)
    paths = path_solver()(
        link.scene,
        max_depth=chosen.max_depth,
        samples_per_src=chosen.samples,
        max_num_paths_per_src=max(64, 8 * len(d)),
        refraction=False,
        seed=int(seed),
    )
    coefficients, _ = coherent_coefficients(paths, frequency_ghz, tx_pos, rx_pos)
    coefficients = coefficients[:, 0, :]
    elapsed = time.perf_counter() - start
    gain = np.abs(coefficients.sum(-1)) ** 2
    with np.errstate(divide="ignore"):
        gain_db = 10.0 * np.log10(gain)
    extra = {"slant_range_m": np.hypot(d, h_tx - h_rx)}
    if eps_sigma is not None:
        extra.update(relative_permittivity=eps_sigma[0], conductivity_s_m=eps_sigma[1])
    return LinkResult(
        gain_db, coefficients, np.count_nonzero(coefficients, axis=-1), elapsed, chosen, active_variant(), extra
    )
