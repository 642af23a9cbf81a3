"""``csuas dataset SPEC --out DIR``: labelled EO frames of drones drawn from a spec (docs/datasets.md).

JSON (``--json``): ``images``, ``rendered``, ``resumed``, ``redone`` (images whose record an earlier run
left unreadable, rendered again), ``annotations`` (the COCO file's path), ``time_s``, ``out`` and
``cost_estimate`` (:mod:`csuas.render.imaging.dataset_cost`, checked before any image is drawn).
"""

from __future__ import annotations

import sys

from csuas.base.cost import add_limit_arguments, check_limits
from csuas.base.paths import checked_path
from csuas.core.scenario import load_scenario


def add_arguments(parser):
    """Declare the options of ``csuas dataset``."""
    parser.add_argument("spec", help="dataset spec TOML file, or an embedded spec (example)")
    parser.add_argument("--out", required=True, help="output folder (images/, labels/, records/, annotations.json)")
    add_limit_arguments(parser)


def run(args) -> dict:
    """Render what is not yet on disk, and write the labels."""
    from csuas.render.imaging.dataset import generate, imaging_sensor, load_dataset_spec
    from csuas.render.imaging.dataset_cost import dataset_estimate

    spec = load_dataset_spec(args.spec)
    checked_path(args.out, "--out")  # a NUL or an overlong name is refused before the estimate looks inside
    params = imaging_sensor(load_scenario(spec.scenario), spec.sensor).params
    estimate = dataset_estimate(spec, (int(params["n_h"]), int(params["n_v"])), args.out)
    check_limits(estimate, args, "dataset")  # before any image is drawn
    summary = generate(spec, args.out, progress=sys.stderr)
    summary["out"] = str(args.out)
    summary["cost_estimate"] = estimate.as_dict()
    return summary


def render_text(result: dict) -> str:
    """What was written, and how long it took."""
    redone = f", {len(result['redone'])} redone (unreadable records)" if result.get("redone") else ""
    return (
        f"dataset: {result['images']} images ({result['rendered']} rendered, "
        f"{result['resumed']} already on disk{redone}) "
        f"in {result['time_s']:.1f} s\nlabels: {result['annotations']}"
    )
