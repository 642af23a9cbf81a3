"""Frames and labels of csuas datasets as the detector loop reads them (COCO ``annotations.json``, 16-bit PNGs).

Every drone model is one class here, the super-category ``drone``: the physics Pd it is compared with is
that of detection, whatever the model. A frame's image is the sensor's DN over its full scale,
DN / (2^bits - 1) in [0, 1], read from the PNG through COCO ``info``'s ``dn_scale`` (docs/datasets.md,
"Files"). NumPy, Pillow and the standard library only.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from csuas.base.errors import ParameterError


@dataclass(frozen=True)
class Frame:
    """One image of a dataset and its drones.

    Attributes
    ----------
    path : Path
        The 16-bit PNG.
    size_px : (int, int)
        Width and height [px].
    boxes : ndarray, shape (g, 4)
        The drones' COCO boxes [x, y, w, h] [px].
    labels : list of dict
        Each drone's ``csuas`` block (``pixels_on_target``, ``snr``, ``johnson_cycles``, ...).
    background : str
        The frame's background class: its label's or image's ``background_class``, else its dataset's name.
    full_scale : float
        The PNG value of the largest DN, (2^bits - 1) dn_scale.
    """

    path: Path
    size_px: tuple
    boxes: np.ndarray
    labels: list = field(default_factory=list)
    background: str = ""
    full_scale: float = 65535.0


def load_frames(datasets: dict) -> list[Frame]:
    """Every frame of the datasets ``{name: folder}`` (:func:`csuas.validation.detector.sets.dataset_folders`)."""
    frames = []
    for name, folder in datasets.items():
        coco = json.loads((Path(folder) / "annotations.json").read_text(encoding="utf-8"))
        info = coco.get("info", {})
        full_scale = (2.0 ** int(info.get("bits", 16)) - 1.0) * float(info.get("dn_scale", 1))
        drone_ids = {c["id"] for c in coco["categories"] if c.get("supercategory", "drone") == "drone"}
        by_image: dict = {}
        for ann in coco["annotations"]:  # confusers (super-category "confuser") stay in the frame, unlabelled
            if ann["category_id"] in drone_ids:
                by_image.setdefault(ann["image_id"], []).append(ann)
        for image in coco["images"]:
            anns = by_image.get(image["id"], [])
            blocks = [a.get("csuas", {}) for a in anns]
            background = next(
                (b["background_class"] for b in blocks if "background_class" in b),
                image.get("csuas", {}).get("background_class", name),
            )
            frames.append(
                Frame(
                    Path(folder) / image["file_name"],
                    (int(image["width"]), int(image["height"])),
                    np.array([a["bbox"] for a in anns], dtype=float).reshape(-1, 4),
                    blocks,
                    str(background),
                    full_scale,
                )
            )
    if not frames:
        raise ParameterError("datasets", {k: str(v) for k, v in datasets.items()}, "csuas datasets with frames")
    return frames


def read_image(frame: Frame) -> np.ndarray:
    """The frame's DN over full scale, float32 in [0, 1], shape (height, width)."""
    from PIL import Image

    with Image.open(frame.path) as image:
        values = np.asarray(image, dtype=np.float32)
    if values.ndim == 3:  # an 8-bit RGB preview: its first channel
        values = values[..., 0]
    return np.clip(values / np.float32(frame.full_scale), 0.0, 1.0)
