"""Fog as Mitsuba's participating medium in an EO render (the choice: :mod:`csuas.render.imaging.medium_choice`).

Where the choice (or the request, ``medium``) takes it, the render traces the window through a homogeneous
medium (:func:`render_eo_medium`): extinction beta the core's
(:func:`csuas.core.atmosphere.extinction_per_km`, Kruse/Kim Eqs. 19-20, plus the physical convention's rain),
single-scattering albedo and Henyey-Greenstein asymmetry of :class:`~csuas.render.imaging.medium_choice.FogMedium`
(fog droplets: 1 and 0.85; Henyey & Greenstein 1941, ApJ 93, 70), lit by the render's own sun, sky and ground
(:func:`csuas.render.imaging.scene.build_eo_scene`'s emitters), with Mitsuba's volumetric path tracer
(``volpath``, all orders of scattering). Where the fog is: a box from far below the scene up to the fog's top
(``fog_top_m``; clear air of the scenario's visibility above it, a second medium), or, without a top, up to
:data:`SCENE_TOP_MARGIN` of the camera distance above the higher of camera and drone (the scenario's illuminance
is taken at the fog's top). Every pixel of the window is traced, background included; rays that hit the drone
give its apparent luminance, the others the background's, each batch apart (a jackknife standard error).

References: Koschmieder, Beitr. Phys. fr. Atmos. 12 (1924); Henyey & Greenstein, ApJ 93, 70 (1941); Hess, Koepke
& Schult, Bull. Am. Meteor. Soc. 79, 831 (1998) (OPAC: water droplets of fog and cloud at 550 nm, asymmetry
parameter 0.85-0.87, single-scattering albedo 1.000).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from csuas.base.errors import ParameterError
from csuas.drone_models.geometry import direction_vector
from csuas.render.imaging.camera import jittered_film_samples, ray_directions
from csuas.render.imaging.common import prepare
from csuas.render.imaging.eo import LUMINANCE_WEIGHTS, render_eo, sun_and_sky
from csuas.render.imaging.medium_choice import BOX_HALF_WIDTH, MEDIUM_LAUNCH, SCENE_TOP_MARGIN, FogMedium, MethodChoice
from csuas.render.imaging.quality import resolve_quality
from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
from csuas.render.imaging.scene import diffuse_rgb, mitsuba_mesh
from csuas.render.imaging.trace import _Shading, camera_rays

#: Longest path of the volumetric path tracer.
MEDIUM_MAX_DEPTH = 4096


def _homogeneous(beta_per_km: float, medium: FogMedium, radius_m: float):
    """A Mitsuba homogeneous medium of extinction ``beta_per_km`` in render units (the bounding radius)."""
    import mitsuba as mi

    return mi.load_dict(
        {
            "type": "homogeneous",
            "sigma_t": beta_per_km / 1000.0 * radius_m,
            "albedo": medium.albedo,
            "phase": {"type": "hg", "g": medium.g},
        }
    )


def _box(up, centre_lateral, bottom: float, top: float, half_width: float, interior, exterior=None) -> dict:
    """A cube from height ``bottom`` to ``top`` along ``up`` (render units), ``half_width`` across, right-handed
    (its normals point out), with its interior (and exterior) medium."""
    import mitsuba as mi

    helper = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(up, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(up, e1)
    matrix = np.eye(4)
    matrix[:3, 0], matrix[:3, 1], matrix[:3, 2] = e1 * half_width, e2 * half_width, up * (top - bottom) / 2.0
    matrix[:3, 3] = centre_lateral + up * (top + bottom) / 2.0
    shape = {"type": "cube", "bsdf": {"type": "null"}, "interior": interior, "to_world": mi.ScalarTransform4f(matrix)}
    if exterior is not None:
        shape["exterior"] = exterior
    return shape


def _fog_shapes(normalised, camera_distance: float, medium: FogMedium) -> tuple:
    """The fog's box (and the clear air above a layer's top): shapes, the camera's medium, the drone's medium."""
    up = np.asarray(normalised.to_render([0.0, 0.0, 1.0]), dtype=float)
    camera = np.array([0.0, 0.0, camera_distance])
    h_camera = float(camera @ up)
    low, high = min(0.0, h_camera), max(0.0, h_camera)
    lateral = camera / 2.0 - up * (h_camera / 2.0)
    width, bottom = BOX_HALF_WIDTH * camera_distance, low - BOX_HALF_WIDTH * camera_distance
    fog = _homogeneous(medium.beta_per_km, medium, normalised.radius_m)
    if medium.top_above_target_m is None:
        top = high + SCENE_TOP_MARGIN * camera_distance
        return {"fog": _box(up, lateral, bottom, top, width, fog)}, fog, fog
    top = medium.top_above_target_m / normalised.radius_m
    clear = _homogeneous(medium.clear_beta_per_km, medium, normalised.radius_m)
    outer_top = max(high, top) + SCENE_TOP_MARGIN * camera_distance
    shapes = {
        "clear_air": _box(up, lateral, bottom - camera_distance, outer_top, width + camera_distance, clear),
        "fog": _box(up, lateral, bottom, top, width, fog, clear),
    }
    return shapes, fog if h_camera < top else clear, fog if top > 0.0 else clear


def _medium_scene(normalised, view: View, light: Daylight, camera_distance: float, medium: FogMedium) -> tuple:
    """The drone under the render's sun, sky and ground (:func:`csuas.render.imaging.eo.render_eo`'s light),
    inside the fog's shapes; returns the scene and the camera's medium."""
    import mitsuba as mi

    from csuas.render.imaging.scene import _along, _sky_ground_envmap, _sky_ground_pattern

    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    shapes, camera_medium, drone_medium = _fog_shapes(normalised, camera_distance, medium)
    spec = {"type": "scene", **shapes}
    for i, part in enumerate(normalised.parts):
        spec[f"part_{i}"] = mitsuba_mesh(part, diffuse_rgb(part.material), exterior=drone_medium)
    if sky["sun_irradiance_lx"] > 0:
        sun_az = view.azimuth_deg if light.sun_azimuth_deg is None else light.sun_azimuth_deg
        to_sun = normalised.to_render(direction_vector(sun_az, light.sun_elevation_deg))
        spec["sun"] = {
            "type": "directional",
            "to_world": _along(-np.asarray(to_sun)),
            "irradiance": {"type": "rgb", "value": float(sky["sun_irradiance_lx"])},
        }
    if sky["sky_radiance"] > 0 or sky["ground_radiance"] > 0:
        s, g, scale = _sky_ground_pattern(sky["sky_radiance"], sky["ground_radiance"])
        spec["environment"] = _sky_ground_envmap((s, g), scale, normalised.to_render([0.0, 0.0, 1.0]))
    return mi.load_dict(spec), camera_medium


@dataclass
class _MediumSums:
    """Per-batch sums of a medium tally: drone hits and misses (luminance, count) and each pixel's radiance."""

    hit: np.ndarray  # (K, 2): luminance sum, count
    miss: np.ndarray  # (K, 2)
    pixels: np.ndarray  # (K, C, n_px)
    counts: np.ndarray  # (K, n_px)


def _trace_medium(scene, camera_medium, geometry, framing, sampling) -> _MediumSums:
    """Every pixel of the window through the medium (volpath), batch by batch; hits by the drone's geometry."""
    import drjit as dr
    import mitsuba as mi

    window, k, channels = framing.window, sampling.n_batches, 3
    n_px = window.n_pixels
    n_side = max(sampling.n_side, math.ceil(sampling.n_side * math.sqrt(64.0 / n_px)))
    integrator = mi.load_dict({"type": "volpath", "max_depth": MEDIUM_MAX_DEPTH, "rr_depth": MEDIUM_MAX_DEPTH})
    shading = _Shading(scene, integrator, camera_medium, framing.camera_distance, channels, sampling.seed, k)
    sums = _MediumSums(np.zeros((k, 2)), np.zeros((k, 2)), np.zeros((k, channels, n_px)), np.zeros((k, n_px)))
    chunk = max(1, MEDIUM_LAUNCH // (n_side * n_side))
    weights = np.asarray(LUMINANCE_WEIGHTS)
    for b in range(k):
        rng = np.random.default_rng([int(sampling.seed), b, 2])
        for p0 in range(0, n_px, chunk):
            pixels = np.arange(p0, min(p0 + chunk, n_px))
            x, y, _ = jittered_film_samples(window, pixels, n_side, rng)
            d = ray_directions(x, y, framing.sensor, framing.target_px).astype(np.float32)
            hit = np.array(geometry.ray_intersect(camera_rays(framing.camera_distance, d)).is_valid(), dtype=bool)
            value = shading.values(d, np.arange(x.size))
            lum = weights @ value
            sums.hit[b] += (lum[hit].sum(), hit.sum())
            sums.miss[b] += (lum[~hit].sum(), (~hit).sum())
            owner = np.repeat(pixels, n_side * n_side)
            for c in range(channels):
                sums.pixels[b, c] += np.bincount(owner, weights=value[c], minlength=n_px)
            sums.counts[b] += np.bincount(owner, minlength=n_px)
    dr.sync_thread()
    return sums


def _medium_figures(hit: np.ndarray, miss: np.ndarray, inherent: tuple) -> dict:
    """Apparent drone and background luminance, contrasts and the effective path of summed hits and misses.

    ``inherent``: the vacuum render's (L_t, L_b) [cd m^-2]; the effective ``transmittance`` is the contrast
    transmittance (L_t' - L_b') / (L_t - L_b) and the ``airlight`` L_b' - tau L_b (Koschmieder's, where exact).
    """
    lb = float(miss[0] / max(miss[1], 1.0))
    lt = float(hit[0] / hit[1]) if hit[1] > 0 else lb  # no ray hit the drone: its luminance is the background's
    tau = (lt - lb) / (inherent[0] - inherent[1]) if inherent[0] != inherent[1] else float("nan")
    return {
        "target_radiance_apparent": lt,
        "background_radiance_apparent": lb,
        "contrast": (lt - lb) / (lt + lb) if lt + lb > 0 else 0.0,
        "contrast_weber": (lt - lb) / lb if lb > 0 else float("inf"),
        "transmittance": tau,
        "airlight": lb - tau * inherent[1],
    }


def _jackknife(sums: _MediumSums, inherent: tuple) -> tuple[dict, dict]:
    """Figures of all batches and their delete-one-batch jackknife standard errors (Efron & Stein 1981)."""
    k = sums.hit.shape[0]
    hit, miss = sums.hit.sum(0), sums.miss.sum(0)
    values = _medium_figures(hit, miss, inherent)
    loo = [_medium_figures(hit - sums.hit[b], miss - sums.miss[b], inherent) for b in range(k)]
    stderr = {}
    for name in values:
        theta = np.array([f[name] for f in loo], dtype=float)
        stderr[name] = float(np.sqrt((k - 1) / k * np.sum((theta - theta.mean()) ** 2)))
    return values, stderr


def render_eo_medium(
    target, view: View, sensor: EoSensor, light: Daylight, choice: MethodChoice, settings: RenderSettings
) -> tuple:
    """An EO render whose path is traced through the participating medium of ``choice`` (module docstring).

    The drone's geometry, inherent figures and the analytic path's figures come from
    :func:`csuas.render.imaging.eo.render_eo` (the path on); the medium's trace then replaces the apparent
    figures, the image and the path's ``transmittance`` and ``airlight`` terms (each with its standard error).

    Returns
    -------
    (ImagingResult, dict)
        The render, and its ``atmosphere_method`` record: the choice (:meth:`MethodChoice.as_dict`), the medium's
        ``stderr``, ``time_s`` and ``samples``, the ``analytic`` figures and the ``difference`` medium - analytic
        of the contrasts with its standard error.
    """
    if choice.medium is None:
        raise ParameterError("atmosphere_method", choice.method, "a choice with a medium (choose_method)")
    from csuas.render.backend import use_variant

    analytic = render_eo(target, view, sensor, light, atmosphere=True, settings=settings)
    t0 = time.perf_counter()
    q = resolve_quality(settings.quality)
    _, normalised, framing = prepare(target, view, sensor, full=settings.full_frame)
    use_variant("ad_rgb", settings.variant)
    from csuas.render.imaging.scene import build_eo_scene

    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    geometry = build_eo_scene(
        normalised,
        sun_direction_render=[0.0, 0.0, 1.0],
        sun_irradiance=0.0,
        sky_radiance=sky["sky_radiance"],
        ground_radiance=sky["ground_radiance"],
        up_render=normalised.to_render([0.0, 0.0, 1.0]),
    )
    scene, camera_medium = _medium_scene(normalised, view, light, framing.camera_distance, choice.medium)
    from csuas.render.imaging.trace import Sampling

    sums = _trace_medium(scene, camera_medium, geometry, framing, Sampling(q.n_side, q.n_batches, settings.seed))
    inherent = (analytic.values["target_radiance"], analytic.values["background_radiance"])
    values, stderr = _jackknife(sums, inherent)
    elapsed = time.perf_counter() - t0
    return _with_medium(analytic, values, stderr, sums, choice, elapsed)


#: Figures of the render that the medium's trace replaces.
APPARENT = ("target_radiance_apparent", "background_radiance_apparent", "contrast", "contrast_weber")


def _with_medium(analytic, values: dict, stderr: dict, sums: _MediumSums, choice: MethodChoice, elapsed: float):
    """The analytic render with the medium's apparent figures, image and path terms; its method record."""
    window = analytic.window
    image = (sums.pixels.sum(0) / np.maximum(sums.counts.sum(0), 1.0)).reshape(3, window.height, window.width)
    source = (
        f"Mitsuba volpath through a homogeneous medium (Henyey-Greenstein g {choice.medium.g:g}, albedo "
        f"{choice.medium.albedo:g}), lit by the render's sun, sky and ground"
    )
    terms = [t for t in analytic.terms if t["name"] not in ("transmittance", "airlight")]
    terms += [
        {
            "name": "transmittance",
            "value": values["transmittance"],
            "unit": "-",
            "stderr": stderr["transmittance"],
            "source": source + ": contrast transmittance (L_t' - L_b') / (L_t - L_b)",
        },
        {
            "name": "airlight",
            "value": values["airlight"],
            "unit": "cd/m^2",
            "stderr": stderr["airlight"],
            "source": source + ": L_b' - tau L_b",
        },
    ]
    merged, merged_se = dict(analytic.values), dict(analytic.stderr)
    for name in APPARENT:
        merged[name], merged_se[name] = float(values[name]), float(stderr[name])
    path = {t["name"]: t["value"] for t in analytic.terms}
    record = {
        **choice.as_dict(),
        "stderr": {name: stderr[name] for name in (*APPARENT, "transmittance", "airlight")},
        "time_s": elapsed,
        "samples": int(sums.counts.sum()),
        "analytic": {
            **{name: analytic.values[name] for name in APPARENT},
            "transmittance": path["transmittance"],
            "airlight": path["airlight"],
        },
        "difference": {
            name: {
                "value": float(values[name] - analytic.values[name]),
                "stderr": float(math.hypot(stderr[name], analytic.stderr[name])),
            }
            for name in ("contrast", "contrast_weber")
        },
    }
    notes = [*analytic.notes, f"path traced through the participating medium: {'; '.join(choice.reasons)}"]
    if sums.hit[:, 1].sum() == 0:
        notes.append("no ray of the medium's trace hit the drone: its apparent figures are the background's")
    result = replace(
        analytic,
        values=merged,
        stderr=merged_se,
        image=image,
        terms=terms,
        samples=analytic.samples + record["samples"],
        time_s=analytic.time_s + elapsed,
        notes=notes,
    )
    return result, record
