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

from csuas.core.atmosphere import extinction_per_km, fog_path_fraction, transmittance
from csuas.render.imaging.camera import Framing
from csuas.render.imaging.common import prepare
from csuas.render.imaging.eo import LUMINANCE_WEIGHTS
from csuas.render.imaging.measure import measure_window
from csuas.render.imaging.path import NO_PATH, eo_path
from csuas.render.imaging.quality import resolve_quality
from csuas.render.imaging.records import EoSensor, RenderSettings, View
from csuas.render.imaging.scene import diffuse_rgb, mitsuba_mesh, path_integrator
from csuas.render.imaging.trace import Sampling, trace_window


def _scene(normalised, horizon_radiance: float, medium=None, medium_radius: float = 0.0, boundary=None):
    """The target under a uniform sky; with ``medium``, inside a sphere of it (or the given ``boundary`` shape)."""
    import mitsuba as mi

    sky = {"type": "constant", "radiance": {"type": "rgb", "value": horizon_radiance}}
    scene = {"type": "scene", "environment": sky}
    inside = boundary is None or boundary.get("target_inside", True)
    for i, part in enumerate(normalised.parts):
        scene[f"part_{i}"] = mitsuba_mesh(part, diffuse_rgb(part.material), exterior=medium if inside else None)
    if medium is not None:
        shape = {"type": "sphere", "radius": float(medium_radius)}
        if boundary is not None:
            shape = {"type": "cube", "to_world": boundary["to_world"]}
        scene["fog"] = {**shape, "bsdf": {"type": "null"}, "interior": medium}
    return mi.load_dict(scene)


#: Path length of the medium's volumetric path tracer: Russian roulette ends most paths earlier.
MEDIUM_MAX_DEPTH = 4096


def medium_vs_analytic_airlight(
    target,
    view: View,
    sensor: EoSensor = EoSensor(),
    *,
    visibility_km: float,
    horizon_radiance: float = 3342.0,
    settings: RenderSettings = RenderSettings(),
    medium_depth: int = MEDIUM_MAX_DEPTH,
) -> dict:
    """Apparent target luminance through a fog medium, against the analytic Koschmieder airlight.

    Parameters
    ----------
    target : str, Drone or list of parts
    view : View
        Slant range [m], aspect and pixel offset, as in :func:`csuas.render.imaging.eo.render_eo`.
    sensor : EoSensor
        Field of view, pixels and the wavelength of the Kruse/Kim extinction (Eqs. 19-20).
    visibility_km : float
        Visibility of the Kruse/Kim extinction [km].
    horizon_radiance : float
        Uniform sky luminance L_h [cd m^-2] lighting the medium.
    settings : RenderSettings
        Quality and seed as in :func:`csuas.render.imaging.eo.render_eo` (the vacuum render traces paths of 3).
    medium_depth : int
        Longest path of the volumetric path tracer (Russian roulette ends most paths earlier).

    Returns
    -------
    dict
        ``transmittance``, ``inherent_radiance`` (vacuum render),
        ``analytic_radiance`` (L0 tau + L_h (1 - tau)), ``medium_radiance``
        and its ``medium_stderr`` (jackknife), ``difference_sigma``,
        ``time_vacuum_s``, ``time_medium_s``.
    """
    from csuas.render.backend import use_variant

    q = resolve_quality(settings.quality)
    r, normalised, framing = prepare(target, view, sensor)
    use_variant("ad_rgb")
    beta = float(extinction_per_km(sensor.wavelength_nm, visibility_km, "physical"))
    sampling = Sampling(q.n_side, q.n_batches, settings.seed, channels=3)
    geometry = _scene(normalised, horizon_radiance)
    path = eo_path(r, visibility_km, sensor.wavelength_nm, horizon_radiance)
    vacuum = _vacuum_render(geometry, framing, sampling, horizon_radiance, path)
    fog = _fog_render(normalised, geometry, framing, sampling, horizon_radiance, beta, medium_depth)
    l_med, se = fog["radiance"], fog["stderr"]
    l_an, se_an = vacuum["analytic_radiance"], vacuum["analytic_stderr"]
    combined = float(np.hypot(se, se_an))
    return {
        "range_m": r,
        "extinction_per_km": beta,
        "transmittance": float(transmittance(beta, r, "physical")),
        "inherent_radiance": vacuum["inherent_radiance"],
        "analytic_radiance": l_an,
        "analytic_stderr": se_an,
        "medium_radiance": l_med,
        "medium_stderr": se,
        "difference_sigma": abs(l_med - l_an) / combined if combined > 0 else 0.0,
        "time_vacuum_s": vacuum["time_s"],
        "time_medium_s": fog["time_s"],
    }


def _vacuum_render(geometry, framing: Framing, sampling: Sampling, horizon_radiance: float, path) -> dict:
    """The target in vacuum: its inherent luminance and the analytic path's apparent one, each with its error."""
    t0 = time.perf_counter()
    background = np.full(3, horizon_radiance)
    vacuum = trace_window(geometry, path_integrator(3), framing, sampling)
    inherent = measure_window(vacuum, background, NO_PATH, LUMINANCE_WEIGHTS)
    analytic = measure_window(vacuum, background, path, LUMINANCE_WEIGHTS)
    return {
        "inherent_radiance": inherent.values["target_radiance"],
        "analytic_radiance": analytic.values["target_radiance_apparent"],
        "analytic_stderr": analytic.stderr["target_radiance_apparent"],
        "time_s": time.perf_counter() - t0,
    }


def _fog_render(
    normalised,
    geometry,
    framing: Framing,
    sampling: Sampling,
    horizon_radiance: float,
    beta: float,
    max_depth: int,
    boundary: dict | None = None,
) -> dict:
    """The target inside a homogeneous conservative medium of extinction ``beta`` [1/km] (module docstring):
    a sphere around camera and target, or ``boundary`` (:func:`_slab_boundary`)."""
    import mitsuba as mi

    t0 = time.perf_counter()
    sigma_t = beta / 1000.0 * normalised.radius_m  # per render unit
    fog = mi.load_dict({"type": "homogeneous", "sigma_t": sigma_t, "albedo": 1.0})
    scene = _scene(normalised, horizon_radiance, fog, 1.5 * framing.camera_distance, boundary)
    integrator = mi.load_dict({"type": "volpath", "max_depth": int(max_depth)})
    camera_inside = boundary is None or boundary["camera_inside"]
    foggy = trace_window(scene, integrator, framing, sampling, medium=fog if camera_inside else None, geometry=geometry)
    # The medium render already contains the path: measure it without analytic path effects.
    medium = measure_window(foggy, np.full(3, horizon_radiance), NO_PATH, LUMINANCE_WEIGHTS)
    return {
        "radiance": medium.values["target_radiance"],
        "stderr": medium.stderr["target_radiance"],
        "time_s": time.perf_counter() - t0,
    }


def _slab_boundary(normalised, framing: Framing, top_above_target_m: float) -> dict:
    """A fog slab's cube in render units: its top ``top_above_target_m`` above the target (at the origin), normal to
    the world's up, reaching far below and beside camera and target; whether camera and target lie inside."""
    import mitsuba as mi

    up = np.asarray(normalised.to_render([0.0, 0.0, 1.0]), dtype=float)
    top = top_above_target_m / normalised.radius_m
    half = 4.0 * framing.camera_distance
    centre = up * (top - half)
    side = np.cross(up, [1.0, 0.0, 0.0] if abs(up[0]) < 0.9 else [0.0, 1.0, 0.0])
    to_world = (
        mi.ScalarTransform4f()
        .look_at(origin=centre.tolist(), target=(centre + up).tolist(), up=side.tolist())
        .scale([half, half, half])
    )
    camera_height = framing.camera_distance * up[2]  # the camera on the render frame's +z axis
    return {"to_world": to_world, "camera_inside": camera_height < top, "target_inside": top > 0.0}


def layered_medium_vs_analytic_airlight(
    target,
    view: View,
    sensor: EoSensor = EoSensor(),
    *,
    visibility_km: float,
    target_height_m: float,
    fog_top_m: float,
    horizon_radiance: float = 3342.0,
    settings: RenderSettings = RenderSettings(),
) -> dict:
    """Apparent target luminance through a fog layer (a scattering slab up to ``fog_top_m``, vacuum above) against
    the render's layered path: L0 tau + L_h (1 - tau), tau = exp(-beta L_fog) with L_fog / R of
    :func:`csuas.core.atmosphere.fog_path_fraction` (:func:`csuas.render.imaging.path.eo_path`).

    The slab is conservative and lit by the uniform sky from every side: radiative equilibrium holds in it as in
    the sphere of :func:`medium_vs_analytic_airlight`, so the airlight of the fog's share of the path is exactly
    L_h (1 - tau). The sensor stands ``R sin(elevation)`` above the target (``view``); heights in [m].

    Returns
    -------
    dict
        As :func:`medium_vs_analytic_airlight`, with ``fog_path_fraction``.
    """
    from csuas.render.backend import use_variant

    q = resolve_quality(settings.quality)
    r, normalised, framing = prepare(target, view, sensor)
    use_variant("ad_rgb")
    beta = float(extinction_per_km(sensor.wavelength_nm, visibility_km, "physical"))
    sensor_height = target_height_m + r * np.sin(np.radians(view.elevation_deg))
    fraction = float(fog_path_fraction(sensor_height, target_height_m, fog_top_m))
    sampling = Sampling(q.n_side, q.n_batches, settings.seed, channels=3)
    geometry = _scene(normalised, horizon_radiance)
    path = eo_path(r, visibility_km, sensor.wavelength_nm, horizon_radiance, 0.0, "physical", (fraction, np.inf))
    vacuum = _vacuum_render(geometry, framing, sampling, horizon_radiance, path)
    boundary = _slab_boundary(normalised, framing, fog_top_m - target_height_m)
    fog = _fog_render(normalised, geometry, framing, sampling, horizon_radiance, beta, MEDIUM_MAX_DEPTH, boundary)
    combined = float(np.hypot(fog["stderr"], vacuum["analytic_stderr"]))
    return {
        "range_m": r,
        "fog_path_fraction": fraction,
        "transmittance": path.transmittance,
        "inherent_radiance": vacuum["inherent_radiance"],
        "analytic_radiance": vacuum["analytic_radiance"],
        "analytic_stderr": vacuum["analytic_stderr"],
        "medium_radiance": fog["radiance"],
        "medium_stderr": fog["stderr"],
        "difference_sigma": abs(fog["radiance"] - vacuum["analytic_radiance"]) / combined if combined > 0 else 0.0,
        "time_s": vacuum["time_s"] + fog["time_s"],
    }
