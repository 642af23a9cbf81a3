"""Video sequences of a ``csuas dataset``: a drone flying a trajectory past a camera, frame by frame
(docs/datasets.md, spec table ``sequence``).

The world frame is local east-north-up with the camera at its origin. The drone flies the trajectory at
constant speed: ``waypoints_m`` ([east, north, up] from the camera [m]) and ``speed_m_s``, or an
``approach`` (from ``range_m`` at ``bearing_deg``, clockwise from north, and ``elevation_deg`` above the
horizon, level toward the point above the camera at ``speed_m_s``); after the last waypoint it hovers.
Frame k is taken at t = k / ``frame_rate_hz`` (default: the sensor's ``look_rate_hz``).

Attitude: the drone flies level with its nose (+x) along its horizontal velocity, so the view's
``azimuth_deg`` and ``elevation_deg`` (from the drone toward the camera, in its body frame,
:mod:`csuas.drone_models.geometry`) follow the path. Pointing: ``fixed`` (the mean direction of the
drone over the sequence) or ``track`` (a pan-tilt unit on the drone, each frame off by a Gaussian
``jitter_urad`` rms in pan and in tilt, seeded). The drone's film offset is its pinhole projection in
the camera's axes (right = boresight x up, image rows down); its image velocity [px/s] is the central
difference of that offset over +-1 ms of the drone's velocity at the frame (with the pointing's smooth
part), and drives the chain's ``motion`` and ``rolling_shutter`` stages
(:mod:`csuas.render.imaging.sensor_chain`), whose ``line_time_us`` defaults to the slowest readout the
frame rate allows, one frame period over the rows. Both stages move the whole frame with the drone's
image velocity: exact for a uniform background, a smear of the slow clear-sky gradient otherwise.
With ``rotor_rpm`` the rotors are blades at the phase of each frame's time (rpm x 6 deg/s), frozen at
that instant: the blades' own smear within the exposure is not rendered (at 6000 rpm and the 0.13 ms of
a daylight exposure they sweep 4.7 deg, as daylight video shows them nearly still; where an exposure
sweeps a blade spacing the swept discs, the default without ``rotor_rpm``, are the better model).
The labels are the drone at the frame's reference time (the middle row's read, the middle of the
exposure), with the rolling shutter's row-by-row read applied to its coverage.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError

#: Keys of the spec's ``sequence`` table.
SEQUENCE_KEYS = ("frames", "frame_rate_hz", "approach", "waypoints_m", "speed_m_s", "pointing", "jitter_urad")
SEQUENCE_KEYS += ("line_time_us", "rotor_rpm")
#: Keys of an ``approach`` and their valid ranges.
APPROACH_LIMITS = {
    "bearing_deg": (-360.0, 360.0),
    "range_m": (1.0, 1e5),
    "speed_m_s": (0.0, 200.0),
    "elevation_deg": (-10.0, 89.0),
}
#: Time step of the image velocity's central difference [s].
VELOCITY_STEP_S = 1e-3


@dataclass(frozen=True)
class SequenceSpec:
    """The ``sequence`` table of a dataset spec (module docstring)."""

    frames: int
    waypoints_m: tuple
    speed_m_s: float
    frame_rate_hz: float | None = None
    pointing: str = "fixed"
    jitter_urad: float = 0.0
    line_time_us: float | None = None
    rotor_rpm: float | None = None


def _number(value, lo: float, hi: float) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and lo <= value <= hi


def approach_waypoints(bearing_deg: float, range_m: float, elevation_deg: float) -> tuple:
    """Start and end of an approach (module docstring): [east, north, up] [m] from the camera."""
    bearing, elevation = math.radians(bearing_deg), math.radians(elevation_deg)
    ground, height = range_m * math.cos(elevation), range_m * math.sin(elevation)
    return ((ground * math.sin(bearing), ground * math.cos(bearing), height), (0.0, 0.0, height))


def parse_sequence(table) -> tuple:
    """The :class:`SequenceSpec` of a spec's ``sequence`` table and the list of its mistakes (keys ``sequence.*``)."""
    errors: list = []
    if not isinstance(table, dict):
        return None, [ParameterError("sequence", table, "a table of " + ", ".join(SEQUENCE_KEYS))]
    unknown = [k for k in table if k not in SEQUENCE_KEYS]
    errors += [ParameterError(f"sequence.{k}", table[k], "a key of: " + ", ".join(SEQUENCE_KEYS)) for k in unknown]
    frames = table.get("frames")
    if not (isinstance(frames, int) and not isinstance(frames, bool) and 1 <= frames <= 100_000):
        errors.append(ParameterError("sequence.frames", frames, "a whole number of frames, 1 to 100,000"))
    approach, waypoints, speed = table.get("approach"), table.get("waypoints_m"), table.get("speed_m_s")
    path: tuple = ()
    if (approach is None) == (waypoints is None):
        valid = "either approach or waypoints_m (with speed_m_s)"
        errors.append(ParameterError("sequence.approach", approach, valid))
    elif approach is not None:
        given = approach if isinstance(approach, dict) else {}
        known = {"elevation_deg": 5.0, **given}
        for key in [k for k in given if k not in APPROACH_LIMITS]:
            errors.append(
                ParameterError(f"sequence.approach.{key}", given[key], "a key of: " + ", ".join(APPROACH_LIMITS))
            )
        bad = [k for k, (lo, hi) in APPROACH_LIMITS.items() if not _number(known.get(k), lo, hi)]
        for key in bad:
            lo, hi = APPROACH_LIMITS[key]
            errors.append(ParameterError(f"sequence.approach.{key}", known.get(key), f"{lo:g} to {hi:g}"))
        if not bad:
            path = approach_waypoints(known["bearing_deg"], known["range_m"], known["elevation_deg"])
            speed = known["speed_m_s"]
    else:
        points = waypoints if isinstance(waypoints, list) else []
        if len(points) < 2 or not all(
            isinstance(p, list) and len(p) == 3 and all(_number(v, -1e5, 1e5) for v in p) for p in points
        ):
            valid = "two or more [east, north, up] in metres"
            errors.append(ParameterError("sequence.waypoints_m", waypoints, valid))
        else:
            path = tuple(tuple(float(v) for v in p) for p in points)
        if not _number(speed, 0.0, 200.0):
            errors.append(ParameterError("sequence.speed_m_s", speed, "0 to 200 m/s"))
    rate, pointing = table.get("frame_rate_hz"), table.get("pointing", "fixed")
    if rate is not None and not (_number(rate, 0.01, 10_000.0) and rate > 0):
        errors.append(ParameterError("sequence.frame_rate_hz", rate, "0.01 to 10,000 Hz"))
    if pointing not in ("fixed", "track"):
        errors.append(ParameterError("sequence.pointing", pointing, "fixed or track"))
    jitter, line_time = table.get("jitter_urad", 0.0), table.get("line_time_us")
    if not _number(jitter, 0.0, 1e5):
        errors.append(ParameterError("sequence.jitter_urad", jitter, "0 to 100,000 urad rms"))
    if line_time is not None and not _number(line_time, 0.0, 1e6):
        errors.append(ParameterError("sequence.line_time_us", line_time, "0 to 1,000,000 us"))
    rpm = table.get("rotor_rpm")
    if rpm is not None and not _number(rpm, 0.0, 100_000.0):
        errors.append(ParameterError("sequence.rotor_rpm", rpm, "0 to 100,000 revolutions per minute"))
    if errors:
        return None, errors
    return SequenceSpec(frames, path, float(speed), rate, pointing, float(jitter), line_time, rpm), []


def flight(spec: SequenceSpec, t_s: float) -> tuple:
    """The drone's position [m] and velocity [m/s] (east, north, up) at time ``t_s`` along the waypoints."""
    points = np.asarray(spec.waypoints_m, float)
    travelled = spec.speed_m_s * t_s
    for start, end in zip(points[:-1], points[1:]):
        length = float(np.linalg.norm(end - start))
        direction = (end - start) / length if length > 0 else np.zeros(3)
        if travelled <= length:
            return start + travelled * direction, spec.speed_m_s * direction
        travelled -= length
    return points[-1], np.zeros(3)


def _heading_rad(spec: SequenceSpec, t_s: float) -> float:
    """The drone's nose direction (radians from east toward north): its horizontal velocity, or the last leg's."""
    _, velocity = flight(spec, t_s)
    if math.hypot(velocity[0], velocity[1]) == 0.0:
        points = np.asarray(spec.waypoints_m, float)
        legs = np.diff(points, axis=0)
        horizontal = [leg for leg in legs if math.hypot(leg[0], leg[1]) > 0]
        velocity = horizontal[-1] if horizontal else np.array([1.0, 0.0, 0.0])
    return math.atan2(velocity[1], velocity[0])


def body_view(position, heading_rad: float) -> tuple:
    """Azimuth and elevation [deg] of the camera seen from a level drone at ``position``, nose at ``heading_rad``."""
    toward = -np.asarray(position, float) / float(np.linalg.norm(position))
    nose = np.array([math.cos(heading_rad), math.sin(heading_rad), 0.0])
    left = np.array([-math.sin(heading_rad), math.cos(heading_rad), 0.0])
    azimuth = math.degrees(math.atan2(float(toward @ left), float(toward @ nose)))
    return azimuth, math.degrees(math.asin(float(np.clip(toward[2], -1.0, 1.0))))


def film_offset(position, boresight, ifov_rad: float) -> tuple:
    """The pinhole image of ``position`` relative to the frame's centre [px] (x right, y down) for a boresight."""
    b = np.asarray(boresight, float) / float(np.linalg.norm(boresight))
    right = np.cross(b, [0.0, 0.0, 1.0])
    right /= float(np.linalg.norm(right))
    up = np.cross(right, b)
    p = np.asarray(position, float)
    depth = float(p @ b)
    if depth <= 0:
        return (math.inf, math.inf)
    return (float(p @ right) / depth / ifov_rad, -float(p @ up) / depth / ifov_rad)


def _pan_tilt(direction) -> tuple:
    d = np.asarray(direction, float)
    return math.atan2(d[0], d[1]), math.atan2(d[2], math.hypot(d[0], d[1]))


def _from_pan_tilt(pan: float, tilt: float) -> np.ndarray:
    return np.array([math.cos(tilt) * math.sin(pan), math.cos(tilt) * math.cos(pan), math.sin(tilt)])


def sequence_frames(spec: SequenceSpec, ifov_rad: float, frame_size: tuple, frame_rate_hz: float, seed: int) -> list:
    """Every frame's time, view and image velocity (module docstring), in order.

    Returns
    -------
    list of dict
        ``frame_id`` (0-based), ``time_s``, ``range_m``, ``azimuth_deg``, ``elevation_deg``,
        ``target_offset_px``, ``velocity_px_s``, ``position_m`` (east, north, up) and ``sun_azimuth_deg`` (the
        sun's azimuth in the drone's body frame: the sun stays behind the camera's mean pointing in the world
        while the drone turns under it), ``boresight_enu`` (the camera's unit pointing) and ``sun_world_deg``
        (the sun's azimuth in the world, radians from east toward north, in degrees).

    Raises
    ------
    ParameterError
        ``sequence.frames`` when the drone leaves the frame (fixed pointing) or comes within 1 m.
    """
    times = np.arange(spec.frames) / frame_rate_hz
    positions = [flight(spec, float(t))[0] for t in times]
    mean = np.mean([p / np.linalg.norm(p) for p in positions], axis=0)
    rng = np.random.default_rng([int(seed), 7])
    width, height = frame_size
    sun_world = math.atan2(-mean[1], -mean[0])  # the sun behind the camera's mean pointing, fixed in the world
    out = []
    for k, (t, position) in enumerate(zip(times, positions)):
        if float(np.linalg.norm(position)) < 1.0:
            raise ParameterError("sequence.frames", spec.frames, f"frames before the drone reaches the camera ({k})")
        pan, tilt = _pan_tilt(mean if spec.pointing == "fixed" else position)
        if spec.pointing == "track":
            pan += spec.jitter_urad * 1e-6 * rng.standard_normal()
            tilt += spec.jitter_urad * 1e-6 * rng.standard_normal()
        offset = film_offset(position, _from_pan_tilt(pan, tilt), ifov_rad)
        if not (abs(offset[0]) <= width / 2 and abs(offset[1]) <= height / 2):
            valid = f"frames while the drone is in the field of view ({k}), or pointing = 'track'"
            raise ParameterError("sequence.frames", spec.frames, valid)
        speed = flight(spec, float(t))[1]
        ahead, behind = (position + dt * speed for dt in (VELOCITY_STEP_S, -VELOCITY_STEP_S))
        velocity = np.subtract(
            film_offset(ahead, mean if spec.pointing == "fixed" else ahead, ifov_rad),
            film_offset(behind, mean if spec.pointing == "fixed" else behind, ifov_rad),
        ) / (2 * VELOCITY_STEP_S)
        heading = _heading_rad(spec, float(t))
        azimuth, elevation = body_view(position, heading)
        out.append(
            {
                "frame_id": k,
                "time_s": float(t),
                "range_m": float(np.linalg.norm(position)),
                "azimuth_deg": azimuth,
                "elevation_deg": elevation,
                "target_offset_px": offset,
                "velocity_px_s": (float(velocity[0]), float(velocity[1])),
                "position_m": [float(v) for v in position],
                "sun_azimuth_deg": _wrapped_deg(sun_world - heading),
                "boresight_enu": [float(v) for v in _from_pan_tilt(pan, tilt)],
                "sun_world_deg": math.degrees(sun_world),
            }
        )
    return out


def _wrapped_deg(angle_rad: float) -> float:
    """An angle in degrees, -180 to 180."""
    return (math.degrees(angle_rad) + 180.0) % 360.0 - 180.0


def blade_phase_deg(rotor_rpm: float, time_s: float) -> float:
    """Azimuth of the first blade [deg] at ``time_s`` of rotors turning at ``rotor_rpm`` from 0 at t = 0."""
    return (float(rotor_rpm) * 6.0 * float(time_s)) % 360.0  # 360 deg per revolution / 60 s


def sequence_target(item: dict):
    """The drone of a frame: its preset name (rotors as swept discs), or, with ``rotor_rpm``, the preset with
    its blades at the frame's phase (:func:`csuas.drone_models.presets.build_drone`)."""
    if "blade_phase_deg" not in item:
        return item["drone"]
    from csuas.drone_models.presets import build_drone

    return build_drone(item["drone"], propellers="blades", blade_phase_deg=item["blade_phase_deg"])


def sequence_items(spec: SequenceSpec, drones: list, count: int, seed: int, params: dict) -> list:
    """Every frame of every video, in order: one video per drone model (``count`` each, own seeds and jitter).

    Each item is :func:`sequence_frames`'s frame with ``drone``, ``index``, ``name``, ``video_id`` and
    ``track_id`` (1-based, one track per video), ``frame_rate_hz`` and ``line_time_s``.
    """
    rate = float(spec.frame_rate_hz or params["look_rate_hz"])
    width, height = int(params["n_h"]), int(params["n_v"])
    ifov = math.radians(params["hfov_deg"]) / width
    line_time = 1.0 / (rate * height) if spec.line_time_us is None else spec.line_time_us * 1e-6
    items: list = []
    videos = [drone for drone in dict.fromkeys(drones) for _ in range(count)]
    for video_id, drone in enumerate(videos, 1):
        for frame in sequence_frames(spec, ifov, (width, height), rate, seed * 1000 + video_id):
            index = len(items)
            items.append(
                {
                    **frame,
                    "drone": drone,
                    "index": index,
                    "name": f"{index:06d}_{drone}",
                    "video_id": video_id,
                    "track_id": video_id,
                    "frame_rate_hz": rate,
                    "line_time_s": line_time,
                    **(
                        {}
                        if spec.rotor_rpm is None
                        else {"blade_phase_deg": blade_phase_deg(spec.rotor_rpm, frame["time_s"])}
                    ),
                }
            )
    return items
