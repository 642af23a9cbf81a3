"""A detector in the loop: train on one csuas dataset, score on held-out ones, beside the physics Pd
(``csuas bench --only detector_loop``; docs/datasets.md, "A detector in the loop").

Two separable steps:

* :func:`csuas.validation.detector.sets.make_sets` renders the datasets (needs Mitsuba);
* :func:`train_and_evaluate` trains and scores (needs torch, torchvision, NumPy, SciPy and Pillow, not
  Mitsuba), so it runs on a GPU machine over datasets rendered elsewhere::

      python -m csuas.validation.detector.detector_loop --train DIR/train --test DIR/test --device cuda --out OUT

It writes ``OUT/detector_loop.json`` (the scores, :mod:`csuas.validation.detector.evaluation`, and the
conditions), ``OUT/detector_loop.png`` (:mod:`csuas.validation.detector.figure`) and
``OUT/detections.json`` (COCO results on the held-out frames).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import asdict
from pathlib import Path

from csuas.base.errors import CsuasError, ParameterError
from csuas.base.fileio import prepare_output_dir, write_text_atomic
from csuas.base.paths import inside
from csuas.validation.detector.training import MISSING, Training, torchvision_available

#: GPU-sized run of the bench when CUDA is present: frames of each split and epochs.
GPU_SIZES, GPU_EPOCHS = (1200, 600), 12


def _coco_results(frames, detections) -> list[dict]:
    return [
        {"image": str(f.path), "category_id": 1, "bbox": [round(float(v), 2) for v in box], "score": round(float(s), 5)}
        for f, (boxes, scores) in zip(frames, detections)
        for box, s in zip(boxes, scores)
    ]


def train_and_evaluate(
    train_dir, test_dir, device: str = "cpu", training: Training = Training(), out=None, pfa=None
) -> dict:
    """Train the detector on the datasets of ``train_dir``, score it on those of ``test_dir``.

    Parameters
    ----------
    train_dir, test_dir : str or Path
        A csuas dataset, or a folder of them (:func:`csuas.validation.detector.sets.dataset_folders`).
    device : str
        torch device (``cpu``, ``cuda``).
    training : Training
        Epochs, batch, learning rate, seed, CPU threads.
    out : str or Path, optional
        Folder for ``detector_loop.json``, ``detector_loop.png`` and ``detections.json``.
    pfa : float, optional
        Per-pixel false-alarm probability of the physics threshold; the EO default (``eo.pfa``) unless given.

    Returns
    -------
    dict
        :func:`csuas.validation.detector.evaluation.evaluate`'s scores, and ``conditions`` (frames, device,
        training, its steps, first and last loss, ``train_s``, ``detect_s``), ``files``.
    """
    from csuas.validation.detector.evaluation import evaluate
    from csuas.validation.detector.frames import load_frames
    from csuas.validation.detector.physics import eo_pfa
    from csuas.validation.detector.sets import dataset_folders
    from csuas.validation.detector.training import detect, train

    pfa = eo_pfa() if pfa is None else pfa
    if not 0 < pfa < 1:  # refused before the training, not after
        raise ParameterError("pfa", pfa, "a probability 0 < pfa < 1")
    folders = {"train_dir": dataset_folders(train_dir), "test_dir": dataset_folders(test_dir)}
    for name, found in folders.items():
        if not found:
            raise ParameterError(
                name, str(train_dir if name == "train_dir" else test_dir), "a csuas dataset or a folder of them"
            )
    root = prepare_output_dir(out) if out is not None else None
    train_frames, test_frames = load_frames(folders["train_dir"]), load_frames(folders["test_dir"])
    model, log = train(train_frames, device, training)
    detections, detect_s = detect(model, test_frames, device)
    result = evaluate(test_frames, detections, pfa)
    result["conditions"] = {
        "train_frames": len(train_frames),
        "test_frames": len(test_frames),
        "train_sets": sorted(folders["train_dir"]),
        "test_sets": sorted(folders["test_dir"]),
        "frame_px": list(test_frames[0].size_px),
        "device": device,
        "training": asdict(training),
        "steps": log["steps"],
        "loss_first": log["losses"][0],
        "loss_last": log["losses"][-1],
        "train_s": log["time_s"],
        "detect_s": detect_s,
    }
    if root is not None:
        result["files"] = _write(root, result, _coco_results(test_frames, detections))
    return result


def figure_title(result: dict) -> str:
    """The figure's title: what was trained on what, how long, and the overall AP50."""
    c = result["conditions"]
    return (
        f"from-scratch Faster R-CNN MobileNetV3 on {c['train_frames']} csuas frames ({', '.join(c['train_sets'])}), "
        f"{c['training']['epochs']} epochs on {c['device']} in {c['train_s']:.0f} s;\n"
        f"held out: {c['test_frames']} frames ({', '.join(c['test_sets'])}), other seeds; "
        f"AP50 {result['all']['ap50']:.2f}, physics Pfa {result['pfa']:.0e} per pixel"
    )


def _write(root: Path, result: dict, detections: list) -> dict:
    from csuas.validation.detector.figure import loop_figure

    title = figure_title(result)
    files = {
        "figure": str(loop_figure(inside(root, "detector_loop.png"), result, title)),
        "detections": str(write_text_atomic(inside(root, "detections.json"), json.dumps(detections))),
    }
    result["files"] = {**files, "scores": str(inside(root, "detector_loop.json"))}
    write_text_atomic(inside(root, "detector_loop.json"), json.dumps(result, indent=1, allow_nan=False))
    return result["files"]


def summary_rows(result: dict) -> list[dict]:
    """One row per bin of pixels on target and per background class (``csuas bench`` text)."""
    keys = ("frames", "ap50", "ap50_stderr", "pd_learned", "pd_ttpf_johnson", "pd_camera_snr", "pd_physical")
    rows = [{"group": "all", **{k: result["all"][k] for k in keys}}]
    rows += [
        {"group": f"px {r['pixels_min']:g}-{r['pixels_max'] or 'inf'}", **{k: r[k] for k in keys}}
        for r in result["by_pixels_on_target"]
    ]
    rows += [{"group": f"background {r['background']}", **{k: r[k] for k in keys}} for r in result["by_background"]]
    return rows


def bench_detector_loop(out_dir="csuas-bench/detector_loop", device: str | None = None) -> list[dict] | dict:
    """``csuas bench --only detector_loop``: render the sets, train, score; CPU-sized, GPU-sized with CUDA.

    Returns the rows of :func:`summary_rows` and a last row of conditions and files; or ``{"skipped": ...}``
    without torchvision.
    """
    if not torchvision_available():
        return {"skipped": MISSING}
    import torch

    from csuas.validation.detector.sets import DEFAULT_SIZES, make_sets

    device = device or ("cuda" if torch.cuda.is_available() else "cpu")
    sizes, epochs = (GPU_SIZES, GPU_EPOCHS) if device.startswith("cuda") else (DEFAULT_SIZES, Training().epochs)
    start = time.perf_counter()
    sets = make_sets(Path(out_dir) / "sets", sizes=sizes)
    render_s = time.perf_counter() - start
    result = train_and_evaluate(sets["train"], sets["test"], device, Training(epochs=epochs), out=out_dir)
    c = result["conditions"]
    tail = {"render_s": render_s, "train_s": c["train_s"], "detect_s": c["detect_s"], "device": device}
    tail.update(
        train_frames=c["train_frames"], test_frames=c["test_frames"], epochs=epochs, figure=result["files"]["figure"]
    )
    return [*summary_rows(result), tail]


def main(argv=None) -> int:
    """``python -m csuas.validation.detector.detector_loop``: :func:`train_and_evaluate` on datasets on disk."""
    parser = argparse.ArgumentParser(
        prog="python -m csuas.validation.detector.detector_loop", description=__doc__.split("\n")[0]
    )
    parser.add_argument("--train", required=True, help="training dataset, or a folder of them")
    parser.add_argument("--test", required=True, help="held-out dataset, or a folder of them")
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--device", default="cpu", help="torch device: cpu (default), cuda, cuda:1")
    defaults = Training()
    parser.add_argument("--epochs", type=int, default=defaults.epochs)
    parser.add_argument("--batch", type=int, default=defaults.batch)
    parser.add_argument("--learning-rate", type=float, default=defaults.learning_rate)
    parser.add_argument("--seed", type=int, default=defaults.seed)
    parser.add_argument("--threads", type=int, default=defaults.threads, help="CPU threads of torch")
    parser.add_argument(
        "--max-steps", type=int, default=None, help="stop after this many training steps (a smoke test)"
    )
    parser.add_argument(
        "--pfa", type=float, default=None, help="per-pixel Pfa of the physics threshold (default eo.pfa)"
    )
    args = parser.parse_args(argv)

    try:  # bad input: exit 2, before torch is looked for
        training = Training(args.epochs, args.batch, args.learning_rate, args.seed, args.threads, args.max_steps)
        if not torchvision_available():
            print(MISSING, file=sys.stderr)
            return 0
        result = train_and_evaluate(args.train, args.test, args.device, training, out=args.out, pfa=args.pfa)
    except CsuasError as exc:  # a line per mistake, as the csuas command line
        for line in str(exc).splitlines():
            print(f"detector_loop: error: {line}", file=sys.stderr)
        return 2
    for row in summary_rows(result):
        print(", ".join(f"{k}={v:.3g}" if isinstance(v, float) else f"{k}={v}" for k, v in row.items()))
    print(json.dumps({"conditions": result["conditions"], "files": result["files"]}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
