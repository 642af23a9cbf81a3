"""Cost of ``csuas dataset`` (time and peak memory), from the spec and the sensor's frame before any draw.

An image costs the render of the window around the target (by quality preset, nearly independent
of the frame) and the sensor chain over the full frame (in proportion to its pixels); the
process holds two frames (one rendered while the previous one is written), every image's draw
and COCO entry, and Mitsuba.

Times are for 2 idle CPU cores, from the figures measured there (README: the example's 20 frames
of 1920 x 1080 px at draft in 4.6 s, start included; docs/performance.md: 0.016 s of render and
0.117 s of chain a frame over 1000 frames) and, for the other presets and the per-pixel share,
from runs on 2 CPU cores under a load average of 10-20, scaled down by their ratio to those
(about 10: draft 640 x 360 px 0.45 s, 1920 x 1080 px 1.5-1.75 s, 4000 x 2250 px 9.3 s an image;
reference 640 x 360 px 1.3 s). Memory does not depend on the load: ru_maxrss 208 MB, 375 MB and
1040 MB for those three frames. The ``cost_models`` benchmark compares the model with measurements
on three frame sizes.

A frame is one array through the sensor chain (its PSF and noise act on the whole frame), so a
frame too large for memory is refused, not split.
"""

from __future__ import annotations

import math
from pathlib import Path

from csuas.base.cost import Estimate
from csuas.render.quality import IMAGING

#: Start: imports of Mitsuba and its kernels [s].
START_SECONDS = 2.0
#: Render of the target's window and its labels, per image and quality preset [s].
WINDOW_SECONDS = IMAGING.per_rung(draft=0.02, standard=0.04, reference=0.1)
#: The sensor chain over the full frame, per pixel [s] (0.117 s for 2.07 Mpx; the PNG is written meanwhile).
PIXEL_SECONDS = 5.7e-8
#: Resident memory of the process with Mitsuba loaded, before a frame [B].
PROCESS_BYTES = 176e6
#: Memory per frame pixel: two frames' signal, noise and DN arrays and the chain's temporaries [B].
PIXEL_BYTES = 96.0
#: Memory per image of the spec: its draw (625 B measured for 10^5 draws) and its COCO entry [B].
IMAGE_BYTES = 1250.0
#: Time to draw one image's drone, range, aspect and offset [s] (98 us measured for 10^5 draws).
DRAW_SECONDS = 1e-4
#: Clutter over the full frame, per pixel [s]: the frame's rays, the declared layers and their blends under the
#: drone (render/imaging/clutter.py). Measured: example-cluttered 3.34 CPU-s a 2.07 Mpx frame against the
#: example's 0.66 at the same load (about 4, 6 frames each); the difference less its confusers (about 0.45 CPU-s,
#: 1.5 window renders), scaled by the example's ratio of measured CPU-s to this model's seconds (0.66 / 0.14),
#: is 0.47 s a frame.
CLUTTER_PIXEL_SECONDS = 2.3e-7
#: Memory per frame pixel that clutter adds: the rays (3 floats), a layer's opacity and light, the class map and
#: the blend's temporaries [B] (example-cluttered peaked at 0.92 GiB against the example's 0.46 GiB, 2.07 Mpx).
CLUTTER_PIXEL_BYTES = 235.0
#: An insect's defocus blur (FFT convolution of its supersampled window) [s] (assumption: like a window render).
INSECT_SECONDS = 0.05


def image_count(spec) -> int:
    """Images of a spec: the product of its list axes' lengths (``drones`` is drawn) times ``count``."""
    listed = [len(v) for name, v in spec.axes.items() if name != "drones" and not isinstance(v, dict)]
    return math.prod(listed) * spec.count


def _mean_count(value) -> float:
    """Mean of a confuser count: a whole number, or ``{min, max}`` drawn uniformly."""
    if isinstance(value, int):
        return float(value)
    low, high = (value["min"], value["max"]) if isinstance(value, dict) else (value.min, value.max)
    return (low + high) / 2.0


def _layer_seconds(spec, pixels: float) -> float:
    """Time a frame's confusers (one window render each; an insect's blur) and clutter (per pixel) add [s]."""
    seconds = 0.0
    confusers = getattr(spec, "confusers", None)
    if confusers is not None:
        meshes = _mean_count(confusers.birds) + _mean_count(confusers.aircraft)
        seconds += meshes * WINDOW_SECONDS[spec.quality] + _mean_count(confusers.insects) * INSECT_SECONDS
    if getattr(spec, "clutter", None) is not None:
        seconds += CLUTTER_PIXEL_SECONDS * pixels
    return seconds


def dataset_estimate(spec, frame_px: tuple[int, int], out_dir) -> Estimate:
    """Time and peak memory of rendering the images of ``spec`` not yet in ``out_dir``.

    Parameters
    ----------
    spec : DatasetSpec
    frame_px : (int, int)
        The sensor's frame, width and height [px].
    out_dir : str or Path
        The output folder: images whose record is already there are not rendered again.
    """
    images = image_count(spec)
    records = Path(out_dir) / "records"
    done = sum(1 for _ in records.glob("*.json")) if records.is_dir() else 0
    todo = max(images - done, 0)
    pixels = float(frame_px[0]) * float(frame_px[1])
    per_image = WINDOW_SECONDS[spec.quality] + PIXEL_SECONDS * pixels + _layer_seconds(spec, pixels)
    seconds = START_SECONDS + images * DRAW_SECONDS + todo * per_image
    clutter_bytes = CLUTTER_PIXEL_BYTES * pixels if getattr(spec, "clutter", None) is not None else 0.0
    peak = PROCESS_BYTES + PIXEL_BYTES * pixels + clutter_bytes + IMAGE_BYTES * images
    what = f"a dataset of {images:,} images ({todo:,} to render) of {frame_px[0]} x {frame_px[1]} px at {spec.quality}"
    return Estimate(what, seconds, peak)
