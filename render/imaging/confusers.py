"""Confusers of a ``csuas dataset`` frame: birds, a light aircraft at distance and insects near the lens, each a
labelled class (docs/datasets.md, spec table ``[confusers]``).

* Birds (:func:`csuas.drone_models.birds.build_bird`, the classes of ``defaults/birds.toml``) and the
  light aircraft (:func:`csuas.drone_models.aircraft.build_light_aircraft`) are rendered as the drone is
  (:func:`csuas.render.imaging.eo.render_eo`, :func:`csuas.render.imaging.tir.render_tir`: their window
  only, at their range, aspect and film offset) and pasted on the frame's background the same way: the
  window's rendered light where the confuser covers a pixel, the background behind it where it does not.
  A bird's wings are at the phase of its wingbeat (drawn for a still; ``wingbeat_hz`` x t in a sequence);
  its plumage is ``surface_temperature_excess_k`` above the ambient air in the thermal band.
* An insect is a dark ellipsoid body with two wings (an analytic silhouette of ``INSECT_LENGTH_M`` drawn
  size, seen from above) close to the lens, so out of focus: with the lens focused at infinity, a point
  at distance d images as a disk of diameter

      c = A f / d = f^2 / (N d)      (thin lens; A = f / N the aperture, f = pitch / IFOV)

  on the film (Hecht, Optics, 5th ed., section 5.7.1 on depth of field), so its coverage is the silhouette
  convolved with that disk (:func:`defocus_blur_px`). EO: a Lambertian body of reflectance
  ``INSECT_REFLECTANCE`` lit by the horizontal illuminance (L = rho E_v / pi); thermal: a blackbody at the
  ambient air's temperature (a small ectotherm in flight is within a kelvin or two of the air).

With ``render["object_path"]`` (a scenario that declares weather) a confuser takes the frame's path at its own
range, as the drone at its range: its coverage-weighted light a L becomes tau(R) a L + a L_path(R)
(:func:`csuas.render.imaging.path.eo_path_at` / ``tir_path_at``; the fog layer's share from its own direction), so
a bird in fog fades with exp(-beta R) like a drone at the same range.

Confusers are pasted farthest first (a nearer one hides a farther one), on the frame that already holds the
drone: those beyond the drone under it, the nearer ones over it (:func:`csuas.render.imaging.compose.blend`).
A confuser's label is its exact coverage as the drone's (box of the pixels with
coverage > 0, ``clipped``, ``visibility``); an insect's is the blurred coverage above ``INSECT_LABEL_FLOOR``
(the share of the light it blocks). Occlusion of a confuser by the drone (or of the drone by a
confuser) is not subtracted from the labels, and the chain's ``motion`` and ``rolling_shutter`` stages move
confusers with the drone's image velocity (their labels are not read row by row).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from csuas.core.radiometry import band_radiance
from csuas.render.imaging.compose import blend
from csuas.render.imaging.records import RenderSettings, View

#: Super-category of the confuser classes in COCO (drones keep ``drone``).
SUPERCATEGORY = "confuser"
#: Class names of the light aircraft and the insect (birds are named by their class in defaults/birds.toml).
AIRCRAFT, INSECT = "light_aircraft", "insect"
#: Insect body length, drawn uniformly [m] (house fly 6-7 mm to large flies and bees 15 mm; assumption).
INSECT_LENGTH_M = (0.006, 0.015)
#: Visible reflectance of an insect (dark cuticle; assumption).
INSECT_REFLECTANCE = 0.08
#: Blurred coverage below which an insect's pixel is not labelled (0.1 % of the light blocked).
INSECT_LABEL_FLOOR = 1e-3
#: Supersampling of the insect's silhouette per pixel side before the defocus blur.
INSECT_SUPERSAMPLING = 4


def confuser_classes(conf) -> list:
    """The confuser classes a spec's ``[confusers]`` table can put in a frame, in a fixed order."""
    if conf is None:
        return []
    most = lambda value: value if isinstance(value, int) else _bounds(value)[1]
    names = list(conf.bird_classes) if most(conf.birds) > 0 else []
    return names + [AIRCRAFT] * (most(conf.aircraft) > 0) + [INSECT] * (most(conf.insects) > 0)


def _bounds(value) -> tuple:
    """(min, max) of a ``{min, max}`` table, given as a dict (a default) or as its model."""
    return (value["min"], value["max"]) if isinstance(value, dict) else (value.min, value.max)


def _how_many(value, rng) -> int:
    return int(value) if isinstance(value, int) else int(rng.integers(_bounds(value)[0], _bounds(value)[1] + 1))


def draw_confusers(conf, rng: np.random.Generator, frame_size: tuple) -> list:
    """The confusers of a still frame: class, range, aspect, film offset, wingbeat phase (birds), length (insects).

    Offsets are uniform over the frame, aspects uniform (azimuth 0-360 deg, elevation -30 to 30 deg),
    ranges uniform within the class's span.
    """
    width, height = frame_size
    out = []
    kinds = [("bird", conf.birds, conf.bird_range_m), (AIRCRAFT, conf.aircraft, conf.aircraft_range_m)]
    kinds.append((INSECT, conf.insects, conf.insect_range_m))
    for kind, count, span in kinds:
        for _ in range(_how_many(count, rng)):
            name = conf.bird_classes[int(rng.integers(len(conf.bird_classes)))] if kind == "bird" else kind
            draw = {
                "class": name,
                "range_m": float(rng.uniform(*_bounds(span))),
                "azimuth_deg": float(rng.uniform(0.0, 360.0)),
                "elevation_deg": float(rng.uniform(-30.0, 30.0)),
                "target_offset_px": (
                    float(rng.uniform(-width / 2, width / 2)),
                    float(rng.uniform(-height / 2, height / 2)),
                ),
                "wingbeat_phase": float(rng.uniform(0.0, 1.0)),
                "length_m": float(rng.uniform(*INSECT_LENGTH_M)),
            }
            out.append(draw)
    for number, draw in enumerate(out, 1):
        draw["confuser_id"] = number
    return out


def confuser_target(draw: dict, ambient_k: float):
    """The mesh of a bird or the light aircraft at the draw's wingbeat phase (None for an insect)."""
    from csuas.drone_models.aircraft import build_light_aircraft
    from csuas.drone_models.birds import build_bird

    if draw["class"] == INSECT:
        return None
    if draw["class"] == AIRCRAFT:
        return build_light_aircraft(ambient_k)
    return build_bird(draw["class"], draw["wingbeat_phase"], ambient_k)


def defocus_blur_px(distance_m: float, f_number: float, pitch_um: float, ifov_rad: float) -> float:
    """Diameter [px] of the blur disk of a point at ``distance_m`` with the lens focused at infinity (module docstring).

    c = f^2 / (N d) on the film, f = pitch / IFOV the focal length, divided by the pitch.
    """
    focal_m = pitch_um * 1e-6 / ifov_rad
    return focal_m**2 / (f_number * distance_m) / (pitch_um * 1e-6)


def _disk_kernel(diameter_px: float) -> np.ndarray:
    """A normalised uniform disk of ``diameter_px`` sampled on the supersampled grid (at least one sample)."""
    radius = max(diameter_px / 2.0, 0.5)
    n = int(math.ceil(radius))
    y, x = np.mgrid[-n : n + 1, -n : n + 1]
    disk = (np.hypot(x, y) <= radius).astype(float)
    return disk / disk.sum()


def insect_coverage(draw: dict, ifov_rad: float, frame_size: tuple, blur_px: float) -> tuple:
    """An insect's blurred coverage window and its frame origin (x0, y0) (module docstring).

    The silhouette (a body ellipse of the drawn length and a third of it wide, two wing ellipses 0.6 and
    0.25 of the length, swept back 30 deg) at the draw's film offset and a heading of ``azimuth_deg``,
    rasterised at ``INSECT_SUPERSAMPLING`` samples per pixel side, convolved with the defocus disk and
    averaged back to pixels.
    """
    from scipy.signal import fftconvolve

    s = INSECT_SUPERSAMPLING
    size_px = draw["length_m"] / draw["range_m"] / ifov_rad
    half = int(math.ceil(size_px / 2.0 + blur_px / 2.0)) + 2
    cx = frame_size[0] / 2.0 + draw["target_offset_px"][0]
    cy = frame_size[1] / 2.0 + draw["target_offset_px"][1]
    x0, y0 = int(math.floor(cx)) - half, int(math.floor(cy)) - half
    n = 2 * half + 1
    grid = (np.arange(n * s) + 0.5) / s
    x, y = grid[None, :] + x0 - cx, grid[:, None] + y0 - cy
    heading = math.radians(draw["azimuth_deg"])
    u, v = x * math.cos(heading) + y * math.sin(heading), -x * math.sin(heading) + y * math.cos(heading)
    silhouette = (u / (size_px / 2)) ** 2 + (v / (size_px / 6)) ** 2 <= 1.0
    for side in (-1.0, 1.0):
        sweep = math.radians(90.0 - 30.0) * side
        wu, wv = u * math.cos(sweep) + v * math.sin(sweep), -u * math.sin(sweep) + v * math.cos(sweep)
        wu -= 0.3 * size_px
        silhouette |= (wu / (0.3 * size_px)) ** 2 + (wv / (0.125 * size_px)) ** 2 <= 1.0
    blurred = fftconvolve(silhouette.astype(float), _disk_kernel(blur_px * s), mode="same")
    coverage = np.clip(blurred.reshape(n, s, n, s).mean(axis=(1, 3)), 0.0, 1.0)
    coverage[coverage < INSECT_LABEL_FLOOR] = 0.0
    return coverage, x0, y0


def _insect_label(draw: dict, coverage: np.ndarray, x0: int, y0: int, frame_size: tuple) -> dict:
    from csuas.render.imaging.labels import label

    out = label(coverage, x0, y0, *frame_size)
    ys, xs = np.nonzero(coverage > 0)
    box = (xs.min() + x0, xs.max() + x0 + 1, ys.min() + y0, ys.max() + y0 + 1) if xs.size else (x0, x0, y0, y0)
    inside = max(min(box[1], frame_size[0]) - max(box[0], 0), 0) * max(min(box[3], frame_size[1]) - max(box[2], 0), 0)
    out["visibility"] = float(inside / max((box[1] - box[0]) * (box[3] - box[2]), 1))
    return out


def _under(drone, draw: dict):
    """The drone's window when the confuser lies beyond the drone (drawn under it), else None (drawn over it)."""
    return drone if drone is not None and draw["range_m"] > drone.range_m else None


def eo_confusers(frame: np.ndarray, draws: list, ifov_rad: float, render: dict, drone=None) -> list:
    """Paste every confuser of ``draws`` on the EO luminance ``frame`` [cd/m^2] in place; their labels.

    ``drone``: the :class:`~csuas.render.imaging.compose.DroneWindow` already in the frame (None: none), which
    confusers beyond it are drawn under and nearer ones over.

    ``render``: ``sensor`` (EoSensor), ``light`` (Daylight, its background as the drone's render takes it),
    ``quality``, ``seed``, ``f_number``, ``pitch_um``, ``ambient_k``.
    """
    from csuas.render.imaging.eo import LUMINANCE_WEIGHTS, render_eo

    sensor, light = render["sensor"], render["light"]

    def own_light(target, view, draw):
        lit = light if draw.get("sun_azimuth_deg") is None else replace(light, sun_azimuth_deg=draw["sun_azimuth_deg"])
        res = render_eo(target, view, sensor, lit, settings=RenderSettings(render["quality"], render["seed"]))
        rendered = np.tensordot(LUMINANCE_WEIGHTS, res.image, axes=1)
        uniform = (
            float(res.values["sky_radiance"])
            if light.background == "sky"
            else float(light.background) * light.illuminance_lx / math.pi
        )
        return res, rendered - (1.0 - res.coverage) * uniform  # the confuser's own light, coverage-weighted

    insect_luminance = INSECT_REFLECTANCE * light.illuminance_lx / math.pi
    return _paste_confusers(frame, draws, ifov_rad, render, drone, insect_luminance, own_light)


def _paste_insect(frame: np.ndarray, draw: dict, ifov_rad: float, render: dict, level: float, drone) -> dict:
    """Blend an out-of-focus insect of uniform ``level`` (luminance or band radiance) on ``frame``; its label."""
    sensor = render["sensor"]
    size = (sensor.n_h, sensor.n_v)
    blur = defocus_blur_px(draw["range_m"], render["f_number"], render["pitch_um"], ifov_rad)
    coverage, x0, y0 = insect_coverage(draw, ifov_rad, size, blur)
    light = _through_path(coverage, coverage * level, draw, render)
    blend(frame, (x0, y0), coverage, light, _under(drone, draw))
    return {**_insect_label(draw, coverage, x0, y0, size), "blur_px": blur}


def tir_confusers(frame: np.ndarray, draws: list, ifov_rad: float, render: dict, drone=None) -> list:
    """Paste every confuser on the thermal band-radiance ``frame`` in place (``drone`` as :func:`eo_confusers`'s);
    their labels.

    ``render``: ``sensor`` (ThermalSensor), ``scene`` (ThermalScene), ``quality``, ``seed``, ``f_number``,
    ``pitch_um``, ``ambient_k``.
    """
    from csuas.render.imaging.tir import render_tir

    sensor = render["sensor"]

    def own_radiance(target, view, draw):
        settings = RenderSettings(render["quality"], render["seed"])
        res = render_tir(target, view, sensor, render["scene"], reflected_surroundings=True, settings=settings)
        radiance = res.image[0]
        uncovered = res.coverage == 0
        uniform = float(np.median(radiance[uncovered] if uncovered.any() else radiance))
        return res, radiance - (1.0 - res.coverage) * uniform

    insect_radiance = float(band_radiance(render["ambient_k"], sensor.band))
    return _paste_confusers(frame, draws, ifov_rad, render, drone, insect_radiance, own_radiance)


def _paste_confusers(frame, draws, ifov_rad, render: dict, drone, insect_level: float, own_signal) -> list:
    """Paste ``draws`` farthest first on ``frame`` in place: insects at ``insect_level``, meshes from
    ``own_signal(target, view, draw) -> (window result, own signal)``; their labels in draw order (None: out of
    view)."""
    sensor = render["sensor"]
    labels = []
    for draw in sorted(draws, key=lambda d: -d["range_m"]):
        if draw["class"] == INSECT:
            labels.append(_paste_insect(frame, draw, ifov_rad, render, insect_level, drone))
            continue
        target = confuser_target(draw, render["ambient_k"])
        view = _view(draw)
        if not _in_view(target, view, ifov_rad, (sensor.n_h, sensor.n_v)):
            labels.append(None)
            continue
        res, signal = own_signal(target, view, draw)
        signal = _through_path(res.coverage, signal, draw, render)
        blend(frame, (res.window.x0, res.window.y0), res.coverage, signal, _under(drone, draw))
        labels.append(_mesh_label(target, view, res, sensor))
    return _in_draw_order(draws, labels)


def _through_path(coverage: np.ndarray, light: np.ndarray, draw: dict, render: dict) -> np.ndarray:
    """A confuser's coverage-weighted light after the frame's path at its range (module docstring); as it is
    without ``render["object_path"]``."""
    path = render.get("object_path")
    if path is None:
        return light
    tau, added = path(draw["range_m"], -math.sin(math.radians(draw["elevation_deg"])))
    return tau * light + coverage * added


def _view(draw: dict) -> View:
    return View(draw["range_m"], draw["azimuth_deg"], draw["elevation_deg"], tuple(draw["target_offset_px"]))


def _in_view(target, view: View, ifov_rad: float, frame_size: tuple) -> bool:
    """Whether any part of the confuser's projected mesh lies in the frame (else not rendered)."""
    from csuas.render.imaging.camera import SensorGeometry
    from csuas.render.imaging.common import silhouette_box_px

    geometry = SensorGeometry(ifov_rad, *frame_size)
    cx, cy = geometry.default_target_px()
    centre = (cx + view.target_offset_px[0], cy + view.target_offset_px[1])
    x_lo, x_hi, y_lo, y_hi = silhouette_box_px(
        target, view.range_m, view.azimuth_deg, view.elevation_deg, geometry, centre
    )
    return x_hi > 0 and y_hi > 0 and x_lo < frame_size[0] and y_lo < frame_size[1]


def _mesh_label(target, view: View, res, sensor) -> dict:
    from csuas.render.imaging.frame import frame_label

    return frame_label(target, view, res, sensor.n_h, sensor.n_v)


def _in_draw_order(draws: list, labels_far_first: list) -> list:
    """Labels back in the order of ``draws`` (they were made farthest first)."""
    order = sorted(range(len(draws)), key=lambda i: -draws[i]["range_m"])
    out: list = [None] * len(draws)
    for position, index in enumerate(order):
        out[index] = labels_far_first[position]
    return out


def eo_render_settings(sensor, light, quality: str, seed: int, params: dict, ambient_k: float) -> dict:
    """The ``render`` argument of :func:`eo_confusers` (the drone's render's light, a clear sky taken as ``sky``)."""
    lit = replace(light, background="sky") if light.background == "clear_sky" else light
    return {
        "sensor": sensor,
        "light": lit,
        "quality": quality,
        "seed": seed,
        "f_number": params["f_number"],
        "pitch_um": params["pixel_pitch_um"],
        "ambient_k": ambient_k,
    }


#: Cruise speed of the light aircraft [m/s] (Cessna 172S: 124 knots true at 75 % power, POH Section 5; 64 m/s).
AIRCRAFT_SPEED_M_S = 64.0
#: Speed of an insect across the lens [m/s] (small flies cruise at 1-3 m/s; assumption).
INSECT_SPEED_M_S = 1.5


def _world_ray(boresight, offset_px: tuple, ifov_rad: float) -> np.ndarray:
    """Unit world direction of a film offset (x right, y down) [px] for a boresight (inverse of ``film_offset``)."""
    b = np.asarray(boresight, float)
    right = np.cross(b, [0.0, 0.0, 1.0])
    right /= float(np.linalg.norm(right))
    up = np.cross(right, b)
    ray = b + offset_px[0] * ifov_rad * right - offset_px[1] * ifov_rad * up
    return ray / float(np.linalg.norm(ray))


def _speed_m_s(name: str) -> float:
    from csuas.drone_models.birds import bird_class

    return (
        AIRCRAFT_SPEED_M_S
        if name == AIRCRAFT
        else INSECT_SPEED_M_S
        if name == INSECT
        else bird_class(name)["airspeed_m_s"]
    )


def sequence_confusers(items: list, conf, seed: int, params: dict) -> None:
    """Give every frame of every video of a sequence its confusers (``item["confusers"]``), in place.

    Each video draws its confusers once (:func:`draw_confusers`, seed [seed, video_id, 5]): where they are in
    its first frame and their range fix their world position; they fly level and straight at their class's
    airspeed (birds, ``defaults/birds.toml``), the aircraft's cruise or an insect's speed, in a drawn heading,
    nose along it; a bird's wingbeat phase advances by ``wingbeat_hz`` x t. Each frame sees them through its
    own pointing (:func:`csuas.render.imaging.sequence.film_offset`), with the sun fixed in the world.
    Track ids are 1000 x video_id + the confuser's number (the drone's is the video_id).
    """
    from csuas.drone_models.birds import bird_class
    from csuas.render.imaging.sequence import body_view, film_offset

    width, height = int(params["n_h"]), int(params["n_v"])
    ifov = math.radians(params["hfov_deg"]) / width
    first: dict = {}
    for item in items:
        video = item["video_id"]
        if video not in first:
            rng = np.random.default_rng([int(seed), int(video), 5])
            draws = draw_confusers(conf, rng, (width, height))
            for draw in draws:
                heading = float(rng.uniform(0.0, 2.0 * math.pi))
                draw["start_m"] = draw["range_m"] * _world_ray(item["boresight_enu"], draw["target_offset_px"], ifov)
                draw["velocity_m_s"] = _speed_m_s(draw["class"]) * np.array([math.cos(heading), math.sin(heading), 0.0])
                draw["heading_rad"] = heading
            first[video] = (draws, item["time_s"])
        draws, t0 = first[video]
        t = item["time_s"] - t0
        frame_draws = []
        for draw in draws:
            position = draw["start_m"] + draw["velocity_m_s"] * t
            azimuth, elevation = body_view(position, draw["heading_rad"])
            moved = {key: draw[key] for key in ("class", "confuser_id", "length_m")}
            moved.update(
                range_m=float(np.linalg.norm(position)),
                azimuth_deg=azimuth if draw["class"] != INSECT else math.degrees(draw["heading_rad"]),
                elevation_deg=elevation,
                target_offset_px=film_offset(position, item["boresight_enu"], ifov),
                wingbeat_phase=(draw["wingbeat_phase"] + _wingbeat_hz(draw["class"], bird_class) * t) % 1.0,
                sun_azimuth_deg=(item["sun_world_deg"] - math.degrees(draw["heading_rad"]) + 180.0) % 360.0 - 180.0,
                track_id=1000 * video + draw["confuser_id"],
                position_m=[float(v) for v in position],
            )
            if all(math.isfinite(v) for v in moved["target_offset_px"]):
                frame_draws.append(moved)
        item["confusers"] = frame_draws


def _wingbeat_hz(name: str, bird_class) -> float:
    return 0.0 if name in (AIRCRAFT, INSECT) else float(bird_class(name)["wingbeat_hz"])
