"""Monostatic radar link with the drone as a Sionna RT sensing target (``sionna.rt.rcs.RCSSolver``).

The drone is a :class:`sionna.rt.rcs.SensingTarget` at (0, 0,
``target_height_m``): a cuboid of its size (an absorber, so it casts a
radio shadow) with one scattering point at its centre whose cross-section
is the given table, callable or constant (default 0.01 m^2, Table 8) and
whose polarisation matrix is the identity (``ConstantCPM``). One radar
(a transmitter and a receiver at the same point, isotropic antennas,
vertical polarisation) stands at each requested horizontal range, at
``radar_height_m``, in the direction ``azimuth_deg`` of the drone's body
frame (the drone's nose points along +x). All ranges are solved in one
``RCSSolver`` call, on a cached scene
(:func:`csuas.render.links.scene.link_scene`) whose radars are moved into
place, and each radar keeps its own echo.

The result is the link's two-way gain P_rx / (P_tx G_tx G_rx) [dB]; in
free space it equals lambda^2 sigma / ((4 pi)^3 R^4) of the paper's Eq. 68
at the slant range R, and over a flat ground the four direct/reflected leg
combinations interfere (:func:`csuas.render.links.two_ray.radar_four_paths`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from csuas.base.errors import ParameterError
from csuas.render.links.budget import PRESETS, LinkBudget, resolve_budget
from csuas.render.links.paths import coherent_coefficients
from csuas.render.links.rcs_table import as_rcs_function, bisector_aspect
from csuas.render.links.rf import LinkResult, check_distances, check_height
from csuas.render.links.scene import TargetSpec, check_frequency, ground_properties, link_scene, rcs_solver
from csuas.render.links.sionna_backend import active_variant, load_sionna_rt

#: Size of the target's cuboid [m] (DJI Mini 4 Pro unfolded, 298 x 373 x 101 mm, docs/simulation.md).
DEFAULT_TARGET_SIZE_M = (0.298, 0.373, 0.101)


def sionna_rcs_callable(rcs_function, constant_sigma=None):
    """Wrap f(azimuth_deg, elevation_deg) -> sigma [m^2] (NumPy) as a Sionna RCS callable.

    Sionna calls it with the incident and scattered directions of
    propagation in the target's frame; the aspect is their bisector (see
    :mod:`csuas.render.links.rcs_table`). The solver calls it outside its
    symbolic loops, so the directions can be read back to NumPy. With
    ``constant_sigma`` [m^2] the callable returns that value (in float32,
    as the NumPy path does) without reading anything back to the host.
    """
    import drjit as dr
    import mitsuba as mi

    if constant_sigma is not None:
        sigma32 = float(np.float32(constant_sigma))
        return lambda k_i, k_s, seed: dr.full(mi.Float, sigma32, dr.width(k_i))

    def rcs(k_i, k_s, seed):
        if dr.width(k_i) == 0:
            return mi.Float()
        ki = np.stack([np.asarray(c.numpy(), float) for c in (k_i.x, k_i.y, k_i.z)], -1)
        ks = np.stack([np.asarray(c.numpy(), float) for c in (k_s.x, k_s.y, k_s.z)], -1)
        sigma = np.asarray(rcs_function(*bisector_aspect(ki, ks)), float)
        if sigma.shape != ki.shape[:1] or not np.all(np.isfinite(sigma)) or np.any(sigma < 0):
            raise ParameterError("rcs", "returned values", "finite sigma >= 0 [m^2], one per direction")
        return mi.Float(sigma.astype(np.float32))

    return rcs


@dataclass(frozen=True)
class RadarTarget:
    """The drone as a radar link's sensing target (module docstring).

    Attributes
    ----------
    rcs : float, RCSTable or callable, optional
        Cross-section [m^2]: a constant, a table, or any vectorised f(azimuth_deg, elevation_deg);
        None: 0.01 m^2 (Table 8).
    azimuth_deg : float
        Direction of the radars seen from the drone, in its body frame [deg].
    size_m : tuple of 3 floats
        Size of the drone's cuboid [m] (the error names it ``target_size_m``).
    """

    rcs: Any = None
    azimuth_deg: float = 0.0
    size_m: tuple = DEFAULT_TARGET_SIZE_M


def radar_link_gain(
    frequency_ghz,
    range_m,
    radar_height_m=5.0,
    target_height_m=5.0,
    target: RadarTarget = RadarTarget(),
    ground=None,
    budget="standard",
    seed=1,
) -> LinkResult:
    """Two-way gain [dB] of a monostatic radar link to the drone, by Sionna RT.

    Parameters
    ----------
    frequency_ghz : float
        Radar frequency [GHz], 0.1 to 100 (narrower with an ITU ground).
    range_m : float or array_like
        Horizontal ranges from the drone to the radar [m], each in (0, 1e6].
    radar_height_m, target_height_m : float
        Heights [m] of the radar and of the drone's centre.
    target : RadarTarget
        The drone's cross-section, the radars' direction in its body frame and its cuboid.
    ground : str or None
        ITU material of a flat ground at z = 0, or None for free space.
    budget : str or LinkBudget
        Sample budget (see :mod:`csuas.render.links.budget`); here its ``samples`` are rays per
        scattering point and its ``max_depth`` bounds the scene interactions of each leg, so
        RCSSolver runs with depth 2 max_depth + 1 (the scattering on the target counts as one).
    seed : int
        Seed of Sionna's sampler.

    Returns
    -------
    LinkResult
        ``path_gain_db`` is 10 log10 P_rx/(P_tx G_tx G_rx), one per range;
        ``extra`` holds the slant ranges and the cross-section [m^2] seen on
        the direct path.
    """
    frequency_ghz = check_frequency(frequency_ghz)
    r = check_distances(range_m)
    over_ground = ground is not None
    h_radar = check_height("radar_height_m", radar_height_m, over_ground)
    h_target = check_height("target_height_m", target_height_m, over_ground)
    size = _checked_size(target.size_m, target_height_m, h_target, over_ground)
    rcs_function = as_rcs_function(target.rcs)
    constant_sigma = None if callable(target.rcs) else float(rcs_function(0.0, 0.0))
    chosen = resolve_budget(budget)
    if not over_ground and chosen.name in PRESETS:
        chosen = LinkBudget(chosen.name, chosen.samples, 0)  # nothing to hit: direct legs only
    eps_sigma = ground_properties(ground, frequency_ghz) if over_ground else None

    load_sionna_rt()  # the first call imports Sionna: not part of the link's time
    start = time.perf_counter()
    target_pos = np.array([0.0, 0.0, h_target])
    link = link_scene(
        frequency_ghz,
        ground,
        float(r.max()),
        "V",
        TargetSpec(tuple(float(v) for v in size), tuple(float(v) for v in target_pos)),
    )
    link.rcs.function = sionna_rcs_callable(rcs_function, constant_sigma)
    az = np.radians(float(target.azimuth_deg))
    radar_pos = np.column_stack([r * np.cos(az), r * np.sin(az), np.full_like(r, h_radar)])
    link.place(radar_pos, radar_pos)
    paths = rcs_solver()(
        link.scene,
        max_depth=2 * chosen.max_depth + 1,
        samples_per_sp=chosen.samples,
        buffer_size_per_sp=max(64, 16 * len(r)),
        refraction=False,
        seed=int(seed),
    )
    coefficients, _ = coherent_coefficients(paths, frequency_ghz, radar_pos, radar_pos, target_pos[None, :])
    index = np.arange(len(r))
    coefficients = coefficients[index, index, :]  # each radar's own echo
    elapsed = time.perf_counter() - start
    with np.errstate(divide="ignore"):
        gain_db = 10.0 * np.log10(np.abs(coefficients.sum(-1)) ** 2)
    extra = _direct_path_extra(radar_pos, target_pos, rcs_function)
    if eps_sigma is not None:
        extra.update(relative_permittivity=eps_sigma[0], conductivity_s_m=eps_sigma[1])
    return LinkResult(
        gain_db, coefficients, np.count_nonzero(coefficients, axis=-1), elapsed, chosen, active_variant(), extra
    )


def _checked_size(size_m, target_height_m, h_target: float, over_ground: bool) -> np.ndarray:
    """The target's cuboid [m], three sizes > 0 that clear the ground at the target's height."""
    size = np.asarray(size_m, float)
    if size.shape != (3,) or not np.all(np.isfinite(size)) or np.any(size <= 0):
        raise ParameterError("target_size_m", size_m, "three sizes > 0 m")
    if over_ground and h_target <= size[2] / 2:
        raise ParameterError(
            "target_height_m", target_height_m, f"> {size[2] / 2:g} m (the target must clear the ground)"
        )
    return size


def _direct_path_extra(radar_pos, target_pos, rcs_function) -> dict:
    """Slant range [m] of each radar and the cross-section [m^2] the direct path sees (its bisector aspect)."""
    to_radar = radar_pos - target_pos
    slant = np.linalg.norm(to_radar, axis=-1)
    direct_aspect = bisector_aspect(-to_radar / slant[:, None], to_radar / slant[:, None])
    return {"slant_range_m": slant, "sigma_direct_m2": np.asarray(rcs_function(*direct_aspect), float)}
