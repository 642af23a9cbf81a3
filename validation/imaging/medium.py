"""Fog as a homogeneous participating medium: validation of the analytic airlight (docs/simulation.md).

The renderers apply haze and fog analytically (:mod:`csuas.render.imaging.path`):
L(R) = L0 tau + L_h (1 - tau). This module renders the same scene with the
atmosphere as a Mitsuba ``homogeneous`` medium instead, and compares.

Set-up (the case where Koschmieder's law is exact): a conservative medium
(single-scattering albedo 1, isotropic phase function) of extinction beta
(Kruse/Kim, Eqs. 19-20, physical convention, at the sensor's wavelength and
visibility) fills a sphere around camera and target, lit from outside by a
uniform sky of radiance L_h. Radiative equilibrium then holds everywhere
(every point sees L_h: the "furnace" solution of the transfer equation), so
the in-scattered radiance along the line of sight is L_h and the transfer
equation integrates to Koschmieder's law. The target, small against the
mean free path, barely perturbs the field. The volumetric path tracer
(``volpath``) solves the transfer equation by Monte Carlo with all orders of
scattering; the camera rays start inside the medium.
"""

from __future__ import annotations

import time

import numpy as np

from csuas.core.atmosphere import extinction_per_km, transmittance
from csuas.render.imaging.common import prepare
from csuas.render.imaging.eo import LUMINANCE_WEIGHTS
from csuas.render.imaging.measure import measure_window
from csuas.render.imaging.path import NO_PATH, eo_path
from csuas.render.imaging.quality import resolve_quality
from csuas.render.imaging.scene import diffuse_rgb, mitsuba_mesh, path_integrator
from csuas.render.imaging.trace import trace_window


def _scene(normalised, horizon_radiance: float, medium=None, medium_radius: float = 0.0):
    import mitsuba as mi

    sky = {"type": "constant", "radiance": {"type": "rgb", "value": horizon_radiance}}
    scene = {"type": "scene", "environment": sky}
    for i, part in enumerate(normalised.parts):
        scene[f"part_{i}"] = mitsuba_mesh(part, diffuse_rgb(part.material), exterior=medium)
    if medium is not None:
        scene["fog"] = {"type": "sphere", "radius": float(medium_radius), "bsdf": {"type": "null"}, "interior": medium}
    return mi.load_dict(scene)


def medium_vs_analytic_airlight(
    target,
    *,
    range_m: float,
    visibility_km: float,
    horizon_radiance: float = 3342.0,
    wavelength_nm: float = 550.0,
    hfov_deg: float = 10.0,
    n_h: int = 1920,
    n_v: int = 1080,
    azimuth_deg: float = 0.0,
    elevation_deg: float = 0.0,
    quality="standard",
    max_depth: int = 4096,
    seed: int = 0,
) -> dict:
    """Apparent target luminance through a fog medium, against the analytic Koschmieder airlight.

    Parameters
    ----------
    target : str, Drone or list of parts
    range_m : float
        Slant range [m].
    visibility_km : float
        Visibility of the Kruse/Kim extinction [km].
    horizon_radiance : float
        Uniform sky luminance L_h [cd m^-2] lighting the medium.
    wavelength_nm, hfov_deg, n_h, n_v, azimuth_deg, elevation_deg, quality, seed
        As in :func:`csuas.render.imaging.eo.render_eo`.
    max_depth : int
        Longest path of the volumetric path tracer (Russian roulette ends most paths earlier).

    Returns
    -------
    dict
        ``transmittance``, ``inherent_radiance`` (vacuum render),
        ``analytic_radiance`` (L0 tau + L_h (1 - tau)), ``medium_radiance``
        and its ``medium_stderr`` (jackknife), ``difference_sigma``,
        ``time_vacuum_s``, ``time_medium_s``.
    """
    import mitsuba as mi

    from csuas.render.backend import use_variant

    q = resolve_quality(quality)
    r, sensor, normalised, window, target_px, bounds = prepare(
        target,
        range_m=range_m,
        hfov_deg=hfov_deg,
        n_h=n_h,
        n_v=n_v,
        azimuth_deg=azimuth_deg,
        elevation_deg=elevation_deg,
        target_offset_px=(0.0, 0.0),
        full=False,
    )
    use_variant("ad_rgb")
    distance = r / normalised.radius_m
    beta = float(extinction_per_km(wavelength_nm, visibility_km, "physical"))
    tau = float(transmittance(beta, r, "physical"))
    background = np.full(3, horizon_radiance)
    common = dict(n_side=q.n_side, n_batches=q.n_batches, seed=seed, channels=3, bounds=bounds)

    t0 = time.perf_counter()
    geometry = _scene(normalised, horizon_radiance)
    vacuum = trace_window(geometry, path_integrator(3), sensor, window, target_px, distance, **common)
    inherent = measure_window(vacuum, background, NO_PATH, LUMINANCE_WEIGHTS)
    analytic = measure_window(
        vacuum, background, eo_path(r, visibility_km, wavelength_nm, horizon_radiance), LUMINANCE_WEIGHTS
    )
    t_vacuum = time.perf_counter() - t0

    t0 = time.perf_counter()
    sigma_t = beta / 1000.0 * normalised.radius_m  # per render unit
    fog = mi.load_dict({"type": "homogeneous", "sigma_t": sigma_t, "albedo": 1.0})
    scene = _scene(normalised, horizon_radiance, fog, medium_radius=1.5 * distance)
    integrator = mi.load_dict({"type": "volpath", "max_depth": int(max_depth)})
    foggy = trace_window(
        scene, integrator, sensor, window, target_px, distance, medium=fog, geometry=geometry, **common
    )
    # The medium render already contains the path: measure it without analytic path effects.
    medium = measure_window(foggy, background, NO_PATH, LUMINANCE_WEIGHTS)
    t_medium = time.perf_counter() - t0

    l_med, se = medium.values["target_radiance"], medium.stderr["target_radiance"]
    l_an = analytic.values["target_radiance_apparent"]
    se_an = analytic.stderr["target_radiance_apparent"]
    combined = float(np.hypot(se, se_an))
    return {
        "range_m": r,
        "extinction_per_km": beta,
        "transmittance": tau,
        "inherent_radiance": inherent.values["target_radiance"],
        "analytic_radiance": l_an,
        "analytic_stderr": se_an,
        "medium_radiance": l_med,
        "medium_stderr": se,
        "difference_sigma": abs(l_med - l_an) / combined if combined > 0 else 0.0,
        "time_vacuum_s": t_vacuum,
        "time_medium_s": t_medium,
    }
