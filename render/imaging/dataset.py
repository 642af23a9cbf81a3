"""Labelled EO datasets: drones x ranges x aspects drawn from a spec, rendered as full frames through the
sensor chain, with COCO and YOLO labels (``csuas dataset``, docs/datasets.md).

Spec (TOML, public interface)::

    seed = 3
    count = 20                       # random draws (per point of the list axes)
    scenario = "default"             # environment and sensors come from a scenario
    sensor = "eo"                    # which of its sensors takes the images
    drones = ["dji_mini_4_pro", "black_hornet_3"]
    range_m = {min = 50.0, max = 800.0}
    azimuth_deg = {min = 0.0, max = 360.0}
    elevation_deg = {min = -10.0, max = 30.0}
    background = "sky"
    chain = ["psf", "shot_noise", "read_noise", "quantise"]

A table with ``min`` and ``max`` draws uniformly (``drones`` from its list), a list is a grid axis:
the images are every combination of the list axes, ``count`` random draws each. Optional keys:
``quality`` (render preset, default ``draft``), ``position`` (``random``: the target anywhere in
the frame, possibly cut by its edge; ``centre``), ``bits`` (8-16), ``exr`` (also write the signal
before quantisation, in electrons, as a float32 EXR beside each image), ``cloud_cover`` (0..1, the
share of a ``clear_sky`` background under seeded clouds), ``sky_temperature_k`` (thermal sensors: a
sky of that apparent temperature above the horizon, the scenario's background below). Image ``i`` draws from the
seed ``[seed, i]``, so a given spec always gives the same bytes, and an image already on disk is
not redone.
"""

from __future__ import annotations

import collections
import itertools
import json
import math
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from csuas.base.errors import InputErrors, ParameterError
from csuas.base.fileio import atomic_path, exclusive_lock, prepare_output_dir, read_spec, write_text_atomic
from csuas.base.paths import inside, sub_folder
from csuas.base.schema import validate
from csuas.core.detection import blob_snr
from csuas.core.scenario import load_scenario
from csuas.defaults import dataset_path, load_birds
from csuas.render.imaging.dataset_schema import TAGS, DatasetSchema

#: Axes a spec may draw or list.
AXES = ("drones", "range_m", "azimuth_deg", "elevation_deg")
#: Keys a spec may hold (the schema's).
SPEC_KEYS = tuple(DatasetSchema.model_fields)
#: Chain stages of thermal frames.
THERMAL_STAGES = ("rolling_shutter", "psf", "defocus", "motion", "netd", "agc", "quantise")
#: Threads writing frames' files while the next frame renders (at most this many frames held in memory).
WRITERS = 2
#: Bird classes (defaults/birds.toml): their confuser annotations carry the wingbeat phase.
_BIRDS = tuple(load_birds())
#: Johnson tasks and their line pairs across d_crit (Table 20, standard column), most demanding first.
DRI_LINE_PAIRS = (("identification", 8.0), ("recognition", 4.0), ("detection", 1.0))


@dataclass(frozen=True)
class DatasetSpec:
    """A parsed dataset spec (module docstring)."""

    seed: int
    count: int
    scenario: str
    sensor: str | None
    axes: dict
    background: object
    chain: tuple
    quality: str
    position: str
    bits: int
    exr: bool = False
    cloud_cover: float = 0.0
    sky_temperature_k: float | None = None
    previews: bool = True
    sequence: object = None
    normal_shot_noise_above_e: float = math.inf
    confusers: object = None
    clutter: object = None


def parse_dataset_spec(data: dict) -> DatasetSpec:
    """Validate a spec's TOML table against :class:`~csuas.render.imaging.dataset_schema.DatasetSchema`;
    every mistake at once (:class:`csuas.base.errors.InputErrors`)."""
    try:
        spec = validate(DatasetSchema, data, tags=TAGS)
    except ParameterError as exc:  # one mistake: still the list of them
        raise InputErrors([exc]) from None
    axes = {name: getattr(spec, name) for name in AXES}  # a {min, max} given in the file as its model
    axes.update({name: axis.model_dump() for name, axis in axes.items() if not isinstance(axis, (list, dict))})
    sequence = None
    if spec.sequence is not None:
        from csuas.render.imaging.sequence import parse_sequence

        sequence, errors = parse_sequence(spec.sequence)
        fixed = [k for k in ("range_m", "azimuth_deg", "elevation_deg", "position") if k in data]
        errors += [ParameterError(k, data[k], "left out with a sequence (its trajectory sets it)") for k in fixed]
        if errors:
            raise InputErrors(errors)
    return DatasetSpec(
        spec.seed,
        spec.count,
        spec.scenario,
        spec.sensor,
        axes,
        spec.background,
        tuple(spec.chain),
        spec.quality,
        spec.position,
        spec.bits,
        spec.exr,
        float(spec.cloud_cover),
        spec.sky_temperature_k,
        spec.previews,
        sequence,
        float(spec.normal_shot_noise_above_e),
        spec.confusers,
        spec.clutter,
    )


def load_dataset_spec(source) -> DatasetSpec:
    """A spec from a TOML file or an embedded spec name (``defaults/datasets``, e.g. ``example``)."""

    return parse_dataset_spec(read_spec(source, dataset_path, "dataset spec"))


def draws(spec: DatasetSpec, frame_size: tuple[int, int]) -> list[dict]:
    """Every image's drone, range, aspect and target offset (module docstring), in a fixed order."""
    listed = [name for name in AXES if not isinstance(spec.axes[name], dict) and name != "drones"]
    grid = list(itertools.product(*(spec.axes[name] for name in listed)))
    out = []
    for point in grid:
        for _ in range(spec.count):
            index = len(out)
            rng = np.random.default_rng([spec.seed, index])
            item = dict(zip(listed, point))
            item["drone"] = spec.axes["drones"][int(rng.integers(len(spec.axes["drones"])))]
            for name in AXES[1:]:
                axis = spec.axes[name]
                if isinstance(axis, dict):
                    item[name] = float(rng.uniform(axis["min"], axis["max"]))
            width, height = frame_size
            offset = (0.0, 0.0)
            if spec.position == "random":
                offset = (float(rng.uniform(-width / 2, width / 2)), float(rng.uniform(-height / 2, height / 2)))
            item.update(index=index, target_offset_px=offset, name=f"{index:06d}_{item['drone']}")
            if spec.confusers is not None:  # a stream of its own: the drone's draws stay those of a spec without
                from csuas.render.imaging.confusers import draw_confusers

                item["confusers"] = draw_confusers(
                    spec.confusers, np.random.default_rng([spec.seed, index, 5]), frame_size
                )
            out.append(item)
    return out


def generate(spec: DatasetSpec, out_dir, progress=None) -> dict:
    """Render every image of the spec not yet on disk; write images, labels and ``annotations.json``.

    Layout: ``images/NAME.png`` (16-bit grey, the sensor's DN in its high bits), ``previews/NAME.png``
    (8-bit sRGB), ``labels/NAME.txt`` (YOLO), ``records/NAME.json`` (the image's COCO entries, for
    resuming), ``annotations.json`` (COCO), ``annotations_previews.json`` (the same on the previews),
    ``data.yaml`` (YOLO) and ``contact_sheet.png``
    (:mod:`csuas.render.imaging.dataset_files`).

    Returns
    -------
    dict
        ``images``, ``rendered``, ``resumed``, ``annotations`` (path), ``time_s``.
    """

    scenario = load_scenario(spec.scenario)
    sensor = imaging_sensor(scenario, spec.sensor)
    if spec.sky_temperature_k is not None and sensor.modality != "tir":
        raise ParameterError("sky_temperature_k", spec.sky_temperature_k, "only with a thermal sensor")
    sun = spec.clutter.sun_offset_deg if spec.clutter is not None else None
    if sun is not None and (sensor.modality == "tir" or spec.sequence is not None):
        raise ParameterError("clutter.sun_offset_deg", sun, "left out of thermal and sequence datasets (EO stills)")
    if spec.sequence is not None and sensor.modality == "tir" and "motion" in spec.chain:
        # a microbolometer smears a moving drone over its thermal time constant (an exponential), not an exposure
        raise ParameterError("chain", "motion", "left out of a thermal sequence (its smear is not modelled yet)")
    out = prepare_output_dir(out_dir)
    for sub in ("images", "labels", "records", *(("previews",) if spec.previews else ())):
        sub_folder(out, sub)
    inside(out, "annotations.json")  # a special file there is refused now, not after the work
    with exclusive_lock(out / LOCK_NAME, "--out"):
        return _generate_locked(spec, scenario, sensor, out, progress)


#: Lock file inside the output folder: one dataset run writes into a folder at a time.
LOCK_NAME = ".csuas-dataset.lock"


def _generate_locked(spec: DatasetSpec, scenario, sensor, out: Path, progress) -> dict:
    """The body of :func:`generate`, holding the folder's lock."""
    if spec.sequence is not None:
        from csuas.render.imaging.sequence import sequence_items

        items = sequence_items(spec.sequence, spec.axes["drones"], spec.count, spec.seed, sensor.params)
        if spec.confusers is not None:
            from csuas.render.imaging.confusers import sequence_confusers

            sequence_confusers(items, spec.confusers, spec.seed, sensor.params)
    else:
        items = draws(spec, (int(sensor.params["n_h"]), int(sensor.params["n_v"])))
    start, rendered, redone = time.perf_counter(), 0, []
    # frames' files are written by a pool (PNG compression releases the GIL) while the next is rendered
    with ThreadPoolExecutor(max_workers=WRITERS, thread_name_prefix="csuas-dataset-writer") as writer:
        writing: collections.deque = collections.deque()
        for done, item in enumerate(items, 1):
            record = out / "records" / f"{item['name']}.json"
            problem = _unreadable(record, out) if record.exists() else None
            if problem is not None:
                redone.append(item["name"])
                if progress is not None:
                    print(f"csuas dataset: warning: {problem}: image {item['name']} redone", file=progress)
            if problem is not None or not record.exists():
                frame = _frame(spec, scenario, sensor, item)
                while len(writing) >= WRITERS:
                    writing.popleft().result()
                writing.append(writer.submit(_write_image, spec, sensor, item, frame, out))
                rendered += 1
            if progress is not None:
                elapsed = time.perf_counter() - start
                eta = elapsed / rendered * (len(items) - done) if rendered else 0.0
                print(
                    f"csuas dataset: {done}/{len(items)} images, {elapsed:.0f} s, about {eta:.0f} s left", file=progress
                )
        while writing:
            writing.popleft().result()
    annotations = _coco(spec, sensor, items, out)
    _write_dataset_files(spec, sensor, items, out)
    _write_difficulty(spec, items, out)
    if spec.sequence is not None:
        _write_mot(sensor, items, out)
    return {
        "images": len(items),
        "rendered": rendered,
        "resumed": len(items) - rendered,
        "redone": redone,
        "annotations": str(annotations),
        "time_s": time.perf_counter() - start,
    }


def _unreadable(record: Path, out: Path) -> str | None:
    """Why a frame's record left by an earlier run cannot be trusted (so the frame is redone), or None.

    A record is written last, after its image and label (:func:`_write_image`); one that is not a
    JSON object with ``image.file_name`` and ``annotation``, or whose image is gone, was damaged after.
    """
    try:
        entry = json.loads(record.read_text(encoding="utf-8"))
        image = out / entry["image"]["file_name"]
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError) as exc:
        return f"records/{record.name} unreadable ({type(exc).__name__})"
    if "annotation" not in entry:  # None when the drone is out of frame, never absent
        return f"records/{record.name} unreadable (no annotation)"
    if not image.is_file():
        return f"records/{record.name} names a missing image"
    return None


def imaging_sensor(scenario, name):
    """The scenario's EO or thermal sensor ``name`` (None: the first), or a ParameterError naming ``sensor``."""
    candidates = {n: s for n, s in scenario.sensors.items() if s.modality in ("eo", "tir")}
    if name is None and candidates:
        return next(iter(candidates.values()))
    if name not in candidates:
        found = ", ".join(candidates) or "none"
        raise ParameterError("sensor", name, f"an EO or thermal sensor of the scenario: {found}")
    return candidates[name]


def _frame(spec: DatasetSpec, scenario, sensor, item: dict) -> dict:
    """Render, expose and degrade the image of one draw (:func:`_visible` or :func:`_thermal`)."""
    from csuas.render.imaging.records import View

    view = View(item["range_m"], item["azimuth_deg"], item["elevation_deg"], tuple(item["target_offset_px"]))
    seed = _frame_seed(spec, item)
    return (_thermal if sensor.modality == "tir" else _visible)(spec, scenario, sensor, item, view, seed)


def _frame_seed(spec: DatasetSpec, item: dict) -> int:
    """The render, noise and cloud seed of an image."""
    return spec.seed * 1_000_003 + item["index"]


def _clutter_seed(spec: DatasetSpec, item: dict) -> int:
    """The seed of a frame's clutter: its own for a still, its video's in a sequence (the ground stays put)."""
    return spec.seed * 1000 + item["video_id"] if "video_id" in item else _frame_seed(spec, item)


def _horizon(spec: DatasetSpec, sensor, item: dict, frame: dict) -> dict | None:
    """What :func:`csuas.render.imaging.difficulty.background_class` needs of a frame's background."""
    from csuas.render.imaging.background import cloud_opacity

    if frame.get("classes") is not None:
        return {"kind": "classes", "codes": frame["classes"]}
    thermal = sensor.modality == "tir"
    if (thermal and spec.sky_temperature_k is None) or (not thermal and not isinstance(spec.background, str)):
        return None
    if not thermal and spec.background == "sky":
        return {"kind": "sky"}
    width, height = int(sensor.params["n_h"]), int(sensor.params["n_v"])
    clouds = None
    if not thermal and spec.cloud_cover > 0:  # the clear sky's own clouds (same seed)
        clouds = cloud_opacity(height, width, spec.cloud_cover, _frame_seed(spec, item))
    view = {key: item[key] for key in ("azimuth_deg", "elevation_deg", "target_offset_px")}
    return {"kind": "horizon", "frame": (width, height), "ifov_rad": frame["result"].ifov_rad, "clouds": clouds, **view}


def _with_difficulty(annotations: list, dn: np.ndarray, horizon: dict | None) -> None:
    """Add the background class and local contrast (:mod:`csuas.render.imaging.difficulty`) to annotations' blocks."""
    from csuas.render.imaging.difficulty import annotation_difficulty
    from csuas.render.imaging.labels import decode_run_length

    for annotation in annotations:
        mask = decode_run_length(annotation["segmentation"])
        annotation["csuas"].update(annotation_difficulty(dn, mask, annotation["bbox"], horizon))


def _write_image(spec: DatasetSpec, sensor, item: dict, frame: dict, out: Path) -> None:
    """Write a frame's image, optional EXR, YOLO label and, last, its record (what resuming looks for)."""
    from csuas.render.imaging.dataset_files import preview, write_dn_png, write_preview
    from csuas.render.imaging.labels import yolo_line
    from csuas.render.imaging.swarm import member_track_id

    p = sensor.params
    thermal = sensor.modality == "tir"
    lab, dn = frame["label"], frame["chain"]["dn"]
    width, height = int(p["n_h"]), int(p["n_v"])
    write_dn_png(inside(out, "images", f"{item['name']}.png"), dn, spec.bits)
    if spec.previews:
        write_preview(inside(out, "previews", f"{item['name']}.png"), preview(dn, spec.bits, thermal))
    if spec.exr:
        unit = "K" if thermal else "electrons"
        _write_signal_exr(inside(out, "images", f"{item['name']}.exr"), frame["chain"]["signal"], item, unit)
    class_index = class_names(spec).index(item["drone"])
    drones = [
        _drone_annotation(sensor, item, frame, lab_i, class_index)
        for lab_i in frame.get("swarm_labels", [lab])  # a swarm: one per drone (render/imaging/swarm.py)
    ]
    if "swarm_labels" in frame:
        for member, annotation in enumerate(drones):
            if annotation is not None:
                annotation["csuas"]["swarm_member"] = member
                if "track_id" in item:  # a sequence: one track a drone
                    track = member_track_id(item["track_id"], member)
                    annotation.update(track_id=track, instance_id=track)
    confusers = _confuser_annotations(spec, item, frame.get("layers"))
    yolo = "".join(
        yolo_line(a["bbox"], width, height, a["category_id"] - 1) + "\n" for a in [*drones, *confusers] if a is not None
    )
    write_text_atomic(inside(out, "labels", f"{item['name']}.txt"), yolo)
    entry = {
        "image": {"file_name": f"images/{item['name']}.png", "width": width, "height": height, **_video_keys(item)},
        "annotation": drones[0],
        **({"swarm": [a for a in drones[1:] if a is not None]} if "swarm_labels" in frame else {}),
        **({"confusers": confusers} if "confusers" in item else {}),
    }
    objects = _objects(entry)
    _with_difficulty(objects, dn, _horizon(spec, sensor, item, frame) if objects else None)
    write_text_atomic(inside(out, "records", f"{item['name']}.json"), json.dumps(entry, indent=1))


def _drone_annotation(sensor, item: dict, frame: dict, lab: dict, class_index: int) -> dict | None:
    """The COCO annotation (without id) of a drone of a frame from its label, None when it is out of frame."""
    if not lab["in_frame"]:
        return None
    p = sensor.params
    thermal = sensor.modality == "tir"
    res, width, height = frame["result"], int(p["n_h"]), int(p["n_v"])
    cycles = float(res.values.get("pixels_across_dcrit", 0.0)) / 2.0  # line pairs across d_crit (Eq. 17)
    contrast_key = "delta_t_k" if thermal else "contrast"  # apparent Delta T of a thermal frame
    contrast_value = float(frame["delta_t_k"] if thermal else res.values.get(contrast_key, float("nan")))
    annotation = {
        "category_id": class_index + 1,
        "bbox": lab["bbox"],
        "area": lab["area"],
        "segmentation": lab["segmentation"],
        "iscrowd": 0,
        "csuas": {
            "drone": item["drone"],
            "modality": sensor.modality,
            "range_m": item["range_m"],
            "azimuth_deg": item["azimuth_deg"],
            "elevation_deg": item["elevation_deg"],
            "target_center_px": [width / 2 + item["target_offset_px"][0], height / 2 + item["target_offset_px"][1]],
            "pixels_on_target": lab["pixels_on_target"],
            contrast_key: contrast_value,
            "snr": frame["snr"],
            "johnson_cycles": cycles,
            "dri": next((task for task, pairs in DRI_LINE_PAIRS if cycles >= pairs), "none"),
            "clipped": lab["clipped"],
            "subpixel": lab["subpixel"],
            "exposure_s": frame["chain"].get("exposure_s", frame.get("exposure_s")),
            "visibility": lab["visibility"],
            **_motion_keys(item),
        },
    }
    if "track_id" in item:
        annotation.update(track_id=item["track_id"], instance_id=item["track_id"])
    return annotation


def _swarm(scenario, item: dict, view, drone) -> tuple:
    """A frame's drone, or with the scenario's ``target.swarm`` its drones (each one's parts, and all of them)."""
    if scenario.swarm is None:
        return None, drone
    from csuas.render.imaging.swarm import formation_members

    members = formation_members(drone, scenario.swarm, view.azimuth_deg, view.elevation_deg)
    return members, [part for parts in members for part in parts]


def _swarm_labels(frame: dict, members, view, p: dict, chain) -> None:
    """A swarm frame's label of each drone, ``frame["swarm_labels"]`` (:mod:`csuas.render.imaging.swarm`)."""
    if members is not None:
        from csuas.render.imaging.swarm import member_labels

        frame["swarm_labels"] = member_labels(members, view, frame["result"], int(p["n_h"]), int(p["n_v"]), chain)


def _objects(entry: dict) -> list:
    """Every labelled object of a record: its drone (each drone of a swarm), then its confusers."""
    return [a for a in [entry["annotation"], *entry.get("swarm", []), *entry.get("confusers", [])] if a is not None]


def _visible(spec: DatasetSpec, scenario, sensor, item: dict, view, seed: int) -> dict:
    """An EO frame of the draw through the path ``csuas range`` applies, its blob SNR against shot and read noise."""
    from csuas.render.imaging.frame import camera_from_params, eo_frame, target_snr
    from csuas.render.imaging.modes import atmosphere_on, scenario_daylight
    from csuas.render.imaging.records import EoSensor, RenderSettings
    from csuas.render.imaging.sensor_chain import ChainSettings
    from csuas.render.imaging.sequence import sequence_target

    p = sensor.params
    chain = ChainSettings(
        stages=spec.chain,
        f_number=p["f_number"],
        wavelength_um=p["wavelength_nm"] / 1000.0,
        pixel_pitch_um=p["pixel_pitch_um"],
        read_noise_e=p["read_noise_e"],
        dark_current_e_s=p["dark_current_e_s"],
        bits=spec.bits,
        normal_shot_noise_above_e=spec.normal_shot_noise_above_e,
        **_video_chain(item),
    )
    # a sequence's sun is fixed in the world; a still's behind the camera
    light = replace(
        scenario_daylight(scenario, sensor),
        background=spec.background,
        sun_azimuth_deg=item.get("sun_azimuth_deg"),
        cloud_cover=spec.cloud_cover,
    )
    if spec.clutter is not None and spec.clutter.sun_offset_deg is not None:  # a still's sun where the spec puts it
        light = _sun_in_view(light, spec.clutter.sun_offset_deg, p, item)
    layered = "confusers" in item or spec.clutter is not None
    members, target = _swarm(scenario, item, view, sequence_target(item))
    frame = eo_frame(
        target,
        view,
        EoSensor.from_params(p),
        light,
        camera_from_params(p),
        replace(chain, stages=()) if layered else chain,  # with layers, the chain runs once they are in
        settings=RenderSettings(quality=spec.quality, seed=seed),
        atmosphere=atmosphere_on(scenario, "auto", sensor),  # the path csuas range applies to the scenario
    )
    if layered:
        from csuas.render.imaging.confusers import eo_render_settings
        from csuas.render.imaging.layered import with_eo_layers
        from csuas.render.imaging.path import eo_path_at

        ambient_k = scenario.environment["temperature_k"]
        render = eo_render_settings(EoSensor.from_params(p), light, spec.quality, seed, p, ambient_k)
        render.update(target=target, view=view, full_well_e=p["full_well_e"], item=item, clutter=spec.clutter)
        render["max_exposure_s"] = p["max_exposure_ms"] / 1000.0
        render["clutter_seed"] = _clutter_seed(spec, item)
        if _layers_take_path(scenario, sensor):
            sky = float(frame["result"].values["sky_radiance"])  # the airlight's source, the drone's render's
            render["object_path"] = lambda r, up: eo_path_at(r, up, light, p["wavelength_nm"], sky)
        frame = with_eo_layers(frame, render, chain, seed)
    frame["snr"] = target_snr(frame, p["read_noise_e"])
    _swarm_labels(frame, members, view, p, chain)
    return frame


def _layers_take_path(scenario, sensor) -> bool:
    """Whether a frame's clutter and confusers take the path at their own ranges: wherever the drone's frame has
    one (``csuas range`` applies a path to the sensor, clear air's extinction included), so that a bird at the
    drone's range fades exactly as the drone does."""
    from csuas.render.imaging.modes import atmosphere_on

    return atmosphere_on(scenario, "auto", sensor)


def _sun_in_view(light, sun_offset_deg, p: dict, item: dict):
    """The daylight with its sun at ``clutter.sun_offset_deg`` from the frame's centre (above the horizon)."""
    from csuas.render.imaging.clutter import sun_direction

    size = (int(p["n_h"]), int(p["n_v"]))
    azimuth, elevation = sun_direction(size, math.radians(p["hfov_deg"]) / size[0], item, sun_offset_deg)
    if elevation <= 0.5:
        valid = f"a sun above the horizon in every frame (image {item['name']} puts it at {elevation:.1f} deg)"
        raise ParameterError("clutter.sun_offset_deg", sun_offset_deg, valid)
    return replace(light, sun_azimuth_deg=azimuth, sun_elevation_deg=elevation)


def _thermal(spec: DatasetSpec, scenario, sensor, item: dict, view, seed: int) -> dict:
    """A thermal frame of the draw (the chain's thermal stages) through the path ``csuas range`` applies, with the
    target's blob SNR against the NETD."""
    from csuas.render.imaging.frame import tir_frame
    from csuas.render.imaging.modes import atmosphere_on, scenario_thermal_scene
    from csuas.render.imaging.records import RenderSettings, ThermalSensor
    from csuas.render.imaging.sensor_chain import ChainSettings
    from csuas.render.imaging.sequence import sequence_target

    env, p = scenario.environment, sensor.params
    chain = ChainSettings(
        stages=tuple(s for s in spec.chain if s in THERMAL_STAGES),
        f_number=p["f_number"],
        wavelength_um=10.0 if p["band"] == "lwir" else 4.0,
        pixel_pitch_um=p["pitch_um"],
        netd_k=p["netd_mk"] / 1000.0,
        bits=spec.bits,
        **_video_chain(item),
    )
    scene = scenario_thermal_scene(scenario, sensor)  # its path applied where csuas range applies one
    if not atmosphere_on(scenario, "auto", sensor):
        scene = replace(scene, extinction_db_km=None)
    layered = "confusers" in item or spec.clutter is not None
    members, target = _swarm(scenario, item, view, sequence_target(item))
    frame = tir_frame(
        target,
        view,
        ThermalSensor.from_params(p),
        scene,
        replace(chain, stages=()) if layered else chain,  # with layers, the chain runs once they are in
        settings=RenderSettings(quality=spec.quality, seed=seed),
        sky_temperature_k=spec.sky_temperature_k,
    )
    if layered:
        from csuas.render.imaging.layered import with_tir_layers
        from csuas.render.imaging.path import tir_path_at

        render = {"sensor": ThermalSensor.from_params(p), "scene": scene, "quality": spec.quality, "seed": seed}
        render.update(f_number=p["f_number"], pitch_um=p["pitch_um"], ambient_k=env["temperature_k"])
        render.update(target=target, view=view, item=item, clutter=spec.clutter, clutter_seed=_clutter_seed(spec, item))
        if _layers_take_path(scenario, sensor):
            render["object_path"] = lambda r, up: tir_path_at(r, up, scene, p["band"])
        frame = with_tir_layers(frame, render, chain, seed)
    excess = abs(frame["target_excess_k"])
    pixels = float(max(frame["label"]["pixels_on_target"], 1e-12))
    frame["snr"] = float(blob_snr(excess / pixels, p["netd_mk"] / 1000.0, pixels))
    _swarm_labels(frame, members, view, p, chain)
    return frame


def _write_signal_exr(path: Path, signal: np.ndarray, item: dict, unit: str) -> None:
    """The frame's signal before quantisation (electrons or kelvin) as a one-channel float32 EXR, with its draw."""
    import OpenEXR

    header = {
        "compression": OpenEXR.ZIP_COMPRESSION,
        "type": OpenEXR.scanlineimage,
        "csuas_units": unit,
        "csuas_drone": str(item["drone"]),
        "csuas_range_m": float(item["range_m"]),
        "csuas_azimuth_deg": float(item["azimuth_deg"]),
        "csuas_elevation_deg": float(item["elevation_deg"]),
    }
    with atomic_path(path) as tmp:
        with OpenEXR.File(header, {"Y": np.ascontiguousarray(signal, dtype=np.float32)}) as exr:
            exr.write(str(tmp))


def _coco(spec: DatasetSpec, sensor, items: list, out: Path) -> Path:
    p = sensor.params
    images, annotations = [], []
    for image_id, item in enumerate(items, 1):
        entry = json.loads((out / "records" / f"{item['name']}.json").read_text(encoding="utf-8"))
        images.append(
            {"id": image_id, **entry["image"], "csuas": {"hfov_deg": p["hfov_deg"], "vfov_deg": p["vfov_deg"]}}
        )
        for annotation in _objects(entry):
            annotations.append({"id": len(annotations) + 1, "image_id": image_id, **annotation})
    from csuas.render.imaging.confusers import SUPERCATEGORY
    from csuas.render.imaging.dataset_files import PNG_BITS, dn_scale

    drones = list(dict.fromkeys(spec.axes["drones"]))
    info = {"description": "csuas dataset", "seed": spec.seed, "scenario": spec.scenario, "bits": spec.bits}
    info.update(png_bits=8 if spec.bits == 8 else PNG_BITS, dn_scale=dn_scale(spec.bits))
    coco = {
        "info": info,
        "images": images,
        "annotations": annotations,
        "categories": [
            {"id": index, "name": name, "supercategory": "drone" if index <= len(drones) else SUPERCATEGORY}
            for index, name in enumerate(class_names(spec), 1)
        ],
    }
    if spec.sequence is not None:
        coco["videos"] = _videos(items)
    if spec.previews:  # the same labels on the 8-bit previews, for loaders that read through Pillow's 8-bit modes
        shown = [{**image, "file_name": "previews/" + image["file_name"].split("/", 1)[1]} for image in images]
        on_previews = {**coco, "info": {**info, "bits": 8, "png_bits": 8, "dn_scale": 1, "encoding": "sRGB"}}
        write_text_atomic(
            inside(out, "annotations_previews.json"), json.dumps({**on_previews, "images": shown}, indent=1)
        )
    return write_text_atomic(inside(out, "annotations.json"), json.dumps(coco, indent=1))


def class_names(spec: DatasetSpec) -> list:
    """The dataset's classes, one per drone model in the spec's order, then the confuser classes
    (:func:`csuas.render.imaging.confusers.confuser_classes`); COCO id = index + 1, YOLO class = index."""
    from csuas.render.imaging.confusers import confuser_classes

    drones = list(dict.fromkeys(spec.axes["drones"]))
    return drones + [name for name in confuser_classes(spec.confusers) if name not in drones]


def _confuser_annotations(spec: DatasetSpec, item: dict, labels) -> list:
    """COCO annotations (without ids) of a frame's confusers in the frame: box, mask, class and their draw."""
    names = class_names(spec)
    out = []
    for draw, lab in zip(item.get("confusers", []), labels or []):
        if lab is None or not lab["in_frame"]:
            continue
        block = {key: draw[key] for key in ("class", "range_m", "azimuth_deg", "elevation_deg") if key in draw}
        block.update(confuser_id=draw["confuser_id"], clipped=lab["clipped"], visibility=lab["visibility"])
        block.update(pixels_on_target=lab["pixels_on_target"], subpixel=lab["subpixel"])
        if draw["class"] in _BIRDS:
            block["wingbeat_phase"] = draw["wingbeat_phase"]
        if "blur_px" in lab:
            block.update(length_m=draw["length_m"], blur_px=lab["blur_px"])
        annotation = {
            "category_id": names.index(draw["class"]) + 1,
            "bbox": lab["bbox"],
            "area": lab["area"],
            "segmentation": lab["segmentation"],
            "iscrowd": 0,
            "csuas": block,
        }
        if "track_id" in draw:
            annotation.update(track_id=draw["track_id"], instance_id=draw["track_id"])
        out.append(annotation)
    return out


def _write_dataset_files(spec: DatasetSpec, sensor, items: list, out: Path) -> None:
    """``data.yaml`` and the contact sheet of the first frames (:mod:`csuas.render.imaging.dataset_files`)."""
    from csuas.render.imaging.dataset_files import (
        SHEET_FRAMES,
        preview,
        read_dn_png,
        write_contact_sheet,
        write_yolo_dataset_file,
    )

    write_yolo_dataset_file(inside(out, "data.yaml"), class_names(spec))
    sheet = []
    for item in items[:SHEET_FRAMES]:
        entry = json.loads((out / "records" / f"{item['name']}.json").read_text(encoding="utf-8"))
        dn = read_dn_png(out / entry["image"]["file_name"])
        boxes = [a["bbox"] for a in _objects(entry)]
        sheet.append((preview(dn, spec.bits, sensor.modality == "tir"), boxes, item["name"]))
    write_contact_sheet(inside(out, "contact_sheet.png"), sheet)


#: Columns of ``difficulty.csv``: one row per labelled object.
DIFFICULTY_COLUMNS = ("file_name", "category", "track_id", "x", "y", "w", "h", "background_class")
DIFFICULTY_COLUMNS += ("local_contrast", "target_mean_dn", "ring_mean_dn", "ring_sigma_dn", "pixels_on_target")


def _write_difficulty(spec: DatasetSpec, items: list, out: Path) -> None:
    """``difficulty.csv``: every labelled object's box, background class and local contrast (binning by difficulty)."""
    import csv
    import io

    names = class_names(spec)
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(DIFFICULTY_COLUMNS)
    for item in items:
        entry = json.loads((out / "records" / f"{item['name']}.json").read_text(encoding="utf-8"))
        for annotation in _objects(entry):
            block = annotation["csuas"]
            contrast = block.get("local_contrast")
            writer.writerow(
                [entry["image"]["file_name"], names[annotation["category_id"] - 1], annotation.get("track_id", "")]
                + list(annotation["bbox"])
                + [block.get("background_class", "")]
                + ["" if contrast is None else f"{contrast:.6g}"]
                + [f"{block.get(k, float('nan')):.6g}" for k in ("target_mean_dn", "ring_mean_dn", "ring_sigma_dn")]
                + [f"{block['pixels_on_target']:.6g}"]
            )
    write_text_atomic(inside(out, "difficulty.csv"), text.getvalue())


def _video_chain(item: dict) -> dict:
    """The chain settings a sequence frame adds (frame rate, line time, image velocity); none for a still."""
    if "video_id" not in item:
        return {}
    keys = ("frame_rate_hz", "line_time_s", "velocity_px_s")
    return {key: tuple(item[key]) if key == "velocity_px_s" else item[key] for key in keys}


def _video_keys(item: dict) -> dict:
    """COCO video keys of a sequence frame's image (``video_id`` 1-based, ``frame_id`` 0-based)."""
    return {"video_id": item["video_id"], "frame_id": item["frame_id"]} if "video_id" in item else {}


def _motion_keys(item: dict) -> dict:
    """A sequence frame's time, image velocity and the drone's position in the annotation's ``csuas`` block."""
    keys = ("time_s", "velocity_px_s", "position_m", "blade_phase_deg")
    return {key: item[key] for key in keys if key in item} if "video_id" in item else {}


def _videos(items: list) -> list:
    """COCO's ``videos``: one per video of a sequence dataset, with its frame rate and frame count."""
    videos: dict = {}
    for item in items:
        video = videos.setdefault(
            item["video_id"],
            {
                "id": item["video_id"],
                "name": f"{item['video_id']:03d}_{item['drone']}",
                "frame_rate_hz": item["frame_rate_hz"],
            },
        )
        video["frames"] = video.get("frames", 0) + 1
    return list(videos.values())


def _write_mot(sensor, items: list, out: Path) -> None:
    """MOTChallenge ground truth of every video: ``mot/VIDEO/gt/gt.txt`` and ``seqinfo.ini`` (1-based frames)."""
    from csuas.render.imaging.dataset_files import mot_line, seqinfo

    p = sensor.params
    for video in _videos(items):
        lines = []
        for item in (i for i in items if i["video_id"] == video["id"]):
            entry = json.loads((out / "records" / f"{item['name']}.json").read_text(encoding="utf-8"))
            for annotation in _objects(entry):  # the drone (each drone of a swarm), then the confusers
                block, class_id, track = annotation["csuas"], annotation["category_id"], annotation["track_id"]
                lines.append(mot_line(item["frame_id"] + 1, track, annotation["bbox"], class_id, block["visibility"]))
        folder = sub_folder(sub_folder(out, "mot"), video["name"])
        write_text_atomic(inside(sub_folder(folder, "gt"), "gt.txt"), "".join(line + "\n" for line in lines))
        info = seqinfo(video["name"], video["frame_rate_hz"], video["frames"], int(p["n_h"]), int(p["n_v"]))
        write_text_atomic(inside(folder, "seqinfo.ini"), info)
