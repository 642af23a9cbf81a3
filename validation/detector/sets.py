"""The training and held-out csuas datasets of the detector loop (``csuas dataset``, docs/datasets.md).

Frames are 320 x 256 px crops of the default scenario's EO camera (Table 22: 10 deg over 1920 px):
a scenario whose EO sensor has those pixels and the pinhole crop's field of view,
2 atan(tan(HFOV / 2) w / N_H), so each frame is the centre of the full sensor at the same pixel
pitch, optics and noise, 24 times cheaper to render and small enough for a detector on 2 CPU cores.
Three drones at log-spaced ranges put 0.03 to about 1000 pixels on target.

Each split is one dataset per background, ``DIR/train/LABEL`` and ``DIR/test/LABEL``; a label is
any set of dataset-spec keys over the common spec (``background``, ``cloud_cover`` today; confuser
and clutter keys slot in the same way as the spec offers them). The held-out sets draw with other
seeds and add a background the training never saw. The folder name is each frame's background class
unless its label carries one (``background_class``).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from csuas.base.errors import ParameterError
from csuas.base.fileio import prepare_output_dir, write_text_atomic
from csuas.base.paths import inside, sub_folder
from csuas.core.scenario import load_scenario

#: Frame of the crop [px], width and height.
FRAME_PX = (320, 256)
#: Ranges of every set [m], a grid axis: log-spaced so the pixels on target span 0.03 to ~1000.
RANGES_M = (60.0, 120.0, 250.0, 500.0, 1000.0, 2000.0)
#: What every set shares (dataset-spec keys; docs/datasets.md).
COMMON_SPEC = {
    "sensor": "eo",
    "drones": ["dji_mini_4_pro", "dji_mavic_3", "black_hornet_3"],
    "range_m": list(RANGES_M),
    "azimuth_deg": {"min": 0.0, "max": 360.0},
    "elevation_deg": {"min": -10.0, "max": 30.0},
    "chain": ["psf", "shot_noise", "read_noise", "quantise"],
    "previews": False,
}
#: Training backgrounds: label -> spec keys over COMMON_SPEC.
TRAIN_BACKGROUNDS = {
    "sky": {"background": "sky"},
    "clear_sky_clouds": {"background": "clear_sky", "cloud_cover": 0.3},
}
#: Clutter and confusers the training never saw (docs/datasets.md, ``[clutter]`` and ``[confusers]``): land cover
#: over a fractal DEM, the skyline, a power line and soft clouds, with birds and out-of-focus insects.
CLUTTERED = {
    "clutter": {
        "terrain": True,
        "camera_height_m": 10.0,
        "relief_m": 40.0,
        "skyline": True,
        "power_lines": 1,
        "clouds": 0.35,
    },
    "confusers": {
        "birds": {"min": 0, "max": 2},
        "bird_range_m": {"min": 40.0, "max": 300.0},
        "insects": {"min": 0, "max": 1},
    },
}
#: Held-out backgrounds: the training ones with other seeds, a uniform ground of reflectance 0.2 never seen, and
#: clutter with confusers never seen.
TEST_BACKGROUNDS = {**TRAIN_BACKGROUNDS, "ground_0.2": {"background": 0.2}, "cluttered": CLUTTERED}
#: Default frames of each split (CPU-sized; docs/datasets.md, "A detector in the loop").
DEFAULT_SIZES = (192, 108)
#: Default seeds of the two splits: set i of a split draws from seed * 100 + i.
DEFAULT_SEEDS = (11, 23)


def crop_scenario_text(frame_px=FRAME_PX) -> str:
    """A scenario TOML: the default one with its EO camera cropped to ``frame_px`` (module docstring)."""

    p = load_scenario("default").sensors["eo"].params
    width, height = frame_px
    hfov = 2 * math.degrees(math.atan(math.tan(math.radians(p["hfov_deg"]) / 2) * width / p["n_h"]))
    vfov = 2 * math.degrees(math.atan(math.tan(math.radians(p["vfov_deg"]) / 2) * height / p["n_v"]))
    return (
        f"# The default scenario's EO camera cropped to its central {width} x {height} px (csuas detector loop)\n"
        'name = "detector_crop"\nconvention = "paper"\n\n[target]\npreset = "dji_mini_4_pro"\n\n'
        '[environment]\npreset = "clear_day"\n\n[sensors.eo]\nmodality = "eo"\n'
        f"n_h = {width}\nn_v = {height}\nhfov_deg = {hfov!r}\nvfov_deg = {vfov!r}\n"
    )


def set_specs(scenario_path, seed: int, frames: int, backgrounds: dict) -> dict[str, dict]:
    """The dataset spec of each background of one split: ``frames`` shared evenly (rounded up).

    Returns
    -------
    dict
        label -> spec table (as a TOML file would give it).
    """
    count = max(1, math.ceil(frames / (len(backgrounds) * len(RANGES_M))))
    return {
        label: {"seed": seed * 100 + i, "count": count, "scenario": str(scenario_path), **COMMON_SPEC, **keys}
        for i, (label, keys) in enumerate(backgrounds.items())
    }


def make_sets(out, seeds=DEFAULT_SEEDS, sizes=DEFAULT_SIZES, backgrounds=(TRAIN_BACKGROUNDS, TEST_BACKGROUNDS)) -> dict:
    """Render the training and held-out datasets into ``out/train/LABEL`` and ``out/test/LABEL``.

    Parameters
    ----------
    out : str or Path
        Output folder; datasets already there are resumed (``csuas dataset`` redoes nothing done).
    seeds : (int, int)
        Seeds of the training and held-out splits (different: the held-out frames are other draws).
    sizes : (int, int)
        Frames of each split (at least; rounded up to whole grids).
    backgrounds : (dict, dict)
        label -> spec keys of each split's sets.

    Returns
    -------
    dict
        ``train`` and ``test`` folders, ``specs`` (split -> label -> spec), ``frames``, ``time_s``;
        also written as ``out/sets.json``.
    """
    from csuas.render.imaging.dataset import generate, parse_dataset_spec

    if seeds[0] == seeds[1]:
        raise ParameterError("seeds", list(seeds), "two different seeds (the held-out frames must be other draws)")
    root = prepare_output_dir(out)
    scenario = write_text_atomic(inside(root, "scenario_crop.toml"), crop_scenario_text())
    summary: dict = {"specs": {}, "frames": {}, "time_s": 0.0}
    for split, seed, frames, sets in zip(("train", "test"), seeds, sizes, backgrounds):
        folder = sub_folder(root, split)
        summary[split] = str(folder)
        summary["specs"][split] = set_specs(scenario, seed, frames, sets)
        summary["frames"][split] = 0
        for label, table in summary["specs"][split].items():
            result = generate(parse_dataset_spec(table), sub_folder(folder, label))
            summary["frames"][split] += result["images"]
            summary["time_s"] += result["time_s"]
    write_text_atomic(inside(root, "sets.json"), json.dumps(summary, indent=1))
    return summary


def dataset_folders(folder) -> dict[str, Path]:
    """The csuas datasets of a split: ``folder`` itself when it holds ``annotations.json``, else each
    sub-folder that does, by name (its background class unless the labels carry one)."""
    root = Path(folder)
    if (root / "annotations.json").is_file():
        return {root.name: root}
    return {p.name: p for p in sorted(root.iterdir()) if (p / "annotations.json").is_file()} if root.is_dir() else {}
