"""``csuas dataset SPEC --out DIR``: labelled EO frames of drones drawn from a spec (docs/datasets.md).

JSON (``--json``): ``images``, ``rendered``, ``resumed``, ``redone`` (images whose record an earlier run
left unreadable, rendered again), ``annotations`` (the COCO file's path),
``time_s`` and ``out``.
"""

from __future__ import annotations

import sys


def add_arguments(parser):
    """Declare the options of ``csuas dataset``."""
    parser.add_argument("spec", help="dataset spec TOML file, or an embedded spec (example)")
    parser.add_argument("--out", required=True, help="output folder (images/, labels/, records/, annotations.json)")


def run(args) -> dict:
    """Render what is not yet on disk, and write the labels."""
    from csuas.render.imaging.dataset import generate, load_dataset_spec

    spec = load_dataset_spec(args.spec)
    summary = generate(spec, args.out, progress=sys.stderr)
    summary["out"] = str(args.out)
    return summary


def render_text(result: dict) -> str:
    """What was written, and how long it took."""
    redone = f", {len(result['redone'])} redone (unreadable records)" if result.get("redone") else ""
    return (
        f"dataset: {result['images']} images ({result['rendered']} rendered, "
        f"{result['resumed']} already on disk{redone}) "
        f"in {result['time_s']:.1f} s\nlabels: {result['annotations']}"
    )
