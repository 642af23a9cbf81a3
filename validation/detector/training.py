"""A small torchvision detector trained from scratch on csuas frames, and its detections (torch imported lazily).

The model is torchvision's Faster R-CNN (BSD-3-Clause) on a MobileNetV3-Large trunk with a feature
pyramid, as ``fasterrcnn_mobilenet_v3_large_320_fpn``, with three changes for drones of a few pixels
in 320 x 256 frames, stated because they decide what it can find:

* the pyramid reads the trunk at strides 8, 16 and 32 (the end of each stage) rather than twice at
  stride 32, with 64 channels rather than 256 (the 256-channel heads cost ten times the trunk on a CPU);
* anchors of 4-16 px at stride 8 up to 128-512 px (the stock ones start at 32 px, larger than most drones
  here);
* the frame is not resized (``min_size`` and ``max_size`` are its own), and fewer proposals and anchor
  and box samples per frame (a frame holds one drone: 64 anchors and 32 boxes keep positives in the loss);
* group normalisation (8 groups) in the trunk instead of batch normalisation: from random weights with
  batches of 4, batch normalisation's running statistics left the eval-mode network with no detection at
  all (8 training frames of 159-2454 pixels on target, 24 steps: none; with groups: AP50 0.43 on them,
  scores 0.88-0.99 on the drones; measured on 2 shared CPU cores).

Weights start random (``weights=None``: nothing is downloaded); the grey frame is repeated over the
three input channels and normalised around the auto-exposed background (mean 0.5, standard deviation
0.25 of full scale). Training: AdamW, batches of ``batch`` frames, random horizontal flips, a fixed
seed. On a CPU torch uses ``threads`` threads: on a shared 2-core machine one thread did a training
step in 0.65 CPU-s where two spent 7-10 CPU-s spinning (measured; docs/datasets.md).

References
----------
- S. Ren, K. He, R. Girshick and J. Sun, "Faster R-CNN", NeurIPS 2015.
- A. Howard et al., "Searching for MobileNetV3", ICCV 2019.
- T.-Y. Lin et al., "Feature Pyramid Networks for Object Detection", CVPR 2017.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError, raise_all
from csuas.validation.detector.frames import Frame, read_image

#: Message when the detector extra is missing (the bench skips with it, exit 0).
MISSING = "torchvision not installed: pip install csuas[detector]"
#: Trunk layers whose outputs feed the pyramid (MobileNetV3-Large features: ends of strides 8, 16, 32).
TRUNK_LAYERS = {"6": "0", "12": "1", "16": "2"}
#: Their channels.
TRUNK_CHANNELS = [40, 112, 960]
#: Channels of the pyramid and its heads.
PYRAMID_CHANNELS = 64
#: Anchor sizes [px] per pyramid level (strides 8, 16, 32 and the pooled level), three aspect ratios each.
ANCHOR_SIZES = ((4, 8, 16), (16, 32, 64), (64, 128, 256), (128, 256, 512))
#: Groups of the trunk's group normalisation (every MobileNetV3-Large width is a multiple of 8).
GROUPS = 8
#: Input normalisation: the auto-exposed background sits at half of full scale.
IMAGE_MEAN, IMAGE_STD = 0.5, 0.25


@dataclass(frozen=True)
class Training:
    """How the detector is trained.

    Attributes
    ----------
    epochs : int
        Passes over the training frames.
    batch : int
        Frames per step.
    learning_rate : float
        AdamW's step size.
    seed : int
        Seed of the weights, the order of frames and the flips.
    threads : int
        CPU threads of torch (ignored on a GPU).
    max_steps : int or None
        Stop after this many steps (a smoke test); None: every epoch.
    """

    epochs: int = 8
    batch: int = 4
    learning_rate: float = 1e-3
    seed: int = 0
    threads: int = 1
    max_steps: int | None = None

    def __post_init__(self):

        errors = [
            ParameterError(name, getattr(self, name), "a whole number >= 1")
            for name in ("epochs", "batch", "threads")
            if not (isinstance(getattr(self, name), int) and getattr(self, name) >= 1)
        ]
        if not (isinstance(self.max_steps, int) and self.max_steps >= 1 or self.max_steps is None):
            errors.append(ParameterError("max_steps", self.max_steps, "a whole number >= 1, or None"))
        if not self.learning_rate > 0:
            errors.append(ParameterError("learning_rate", self.learning_rate, "> 0"))
        raise_all(errors)


def torchvision_available() -> bool:
    """Whether torch and torchvision import."""
    try:
        import torch  # noqa: F401
        import torchvision  # noqa: F401
    except ImportError:
        return False
    return True


def build_model(frame_px: tuple[int, int]):
    """The detector (module docstring), random weights, two classes (background, drone)."""
    from torch import nn
    from torchvision.models import mobilenet_v3_large
    from torchvision.models.detection import FasterRCNN
    from torchvision.models.detection.anchor_utils import AnchorGenerator
    from torchvision.models.detection.backbone_utils import BackboneWithFPN

    trunk = mobilenet_v3_large(weights=None, norm_layer=lambda channels: nn.GroupNorm(GROUPS, channels)).features
    backbone = BackboneWithFPN(trunk, TRUNK_LAYERS, TRUNK_CHANNELS, PYRAMID_CHANNELS)
    anchors = AnchorGenerator(ANCHOR_SIZES, ((0.5, 1.0, 2.0),) * len(ANCHOR_SIZES))
    return FasterRCNN(
        backbone,
        num_classes=2,
        rpn_anchor_generator=anchors,
        min_size=min(frame_px),
        max_size=max(frame_px),
        image_mean=[IMAGE_MEAN] * 3,
        image_std=[IMAGE_STD] * 3,
        rpn_pre_nms_top_n_train=600,
        rpn_post_nms_top_n_train=300,
        rpn_pre_nms_top_n_test=300,
        rpn_post_nms_top_n_test=100,
        rpn_batch_size_per_image=64,
        box_batch_size_per_image=32,
        representation_size=256,
        box_detections_per_img=100,
        box_score_thresh=0.001,
    )


def _tensor(frame: Frame, flip: bool):
    import torch

    image = read_image(frame)
    boxes = frame.boxes.copy()
    if flip:
        image = image[:, ::-1]
        boxes[:, 0] = frame.size_px[0] - boxes[:, 0] - boxes[:, 2]
    xyxy = np.concatenate([boxes[:, :2], boxes[:, :2] + boxes[:, 2:]], axis=1)
    target = {
        "boxes": torch.as_tensor(xyxy, dtype=torch.float32).reshape(-1, 4),
        "labels": torch.ones(len(boxes), dtype=torch.int64),
    }
    return torch.from_numpy(np.ascontiguousarray(image)).expand(3, -1, -1), target


def train(frames: list[Frame], device: str, training: Training = Training()):
    """Train a new detector on ``frames``; the model (in eval mode) and ``{steps, losses, time_s}``."""
    import torch

    if device == "cpu":
        torch.set_num_threads(training.threads)
    torch.manual_seed(training.seed)
    rng = np.random.default_rng(training.seed)
    model = build_model(frames[0].size_px).to(device)
    optimiser = torch.optim.AdamW(model.parameters(), lr=training.learning_rate, weight_decay=1e-4)
    model.train()
    start, losses, steps = time.perf_counter(), [], 0
    for _ in range(training.epochs):
        order = rng.permutation(len(frames))
        for first in range(0, len(order), training.batch):
            pairs = [_tensor(frames[i], bool(rng.integers(2))) for i in order[first : first + training.batch]]
            images = [image.to(device) for image, _ in pairs]
            targets = [{k: v.to(device) for k, v in target.items()} for _, target in pairs]
            loss = sum(model(images, targets).values())
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            losses.append(float(loss.detach()))
            steps += 1
            if training.max_steps is not None and steps >= training.max_steps:
                break
        if training.max_steps is not None and steps >= training.max_steps:
            break
    model.eval()
    return model, {"steps": steps, "losses": losses, "time_s": time.perf_counter() - start}


def detect(model, frames: list[Frame], device: str, batch: int = 8) -> tuple[list, float]:
    """Each frame's detections ``(boxes [x, y, w, h] [px], scores)`` and the time they took [s]."""
    import torch

    start, out = time.perf_counter(), []
    with torch.no_grad():
        for first in range(0, len(frames), batch):
            images = [_tensor(f, False)[0].to(device) for f in frames[first : first + batch]]
            for found in model(images):
                xyxy = found["boxes"].cpu().numpy().astype(float)
                boxes = np.concatenate([xyxy[:, :2], xyxy[:, 2:] - xyxy[:, :2]], axis=1)
                out.append((boxes, found["scores"].cpu().numpy().astype(float)))
    return out, time.perf_counter() - start
