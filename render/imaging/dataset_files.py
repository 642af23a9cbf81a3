"""The files of a ``csuas dataset`` that other tools open: scaled PNGs, 8-bit previews, YOLO's ``data.yaml``,
MOTChallenge ground truth and a contact sheet (docs/datasets.md).

* Images: the sensor's DN in the high bits of a 16-bit grey PNG (a 12-bit DN times 2^4), so that viewers
  and 8-bit readers (OpenCV's default read keeps the high byte) show the frame as the sensor saw it; the
  PNG's ``sBIT`` chunk holds the significant bits (PNG 1.2, section 4.2.6) and its text chunks
  ``csuas_bits`` and ``csuas_dn_scale`` the factor (a pixel value / ``csuas_dn_scale`` is the DN). An 8-bit
  dataset is written as an 8-bit PNG unscaled.
* Previews: 8-bit sRGB. EO: the DN over the DN range is linear in electrons, encoded by the sRGB transfer
  function (IEC 61966-2-1, through colour-science); thermal: the DN stretched linearly between the
  frame's 0.5th and 99.5th percentiles (temperature, not light, so no display gamma).
* ``data.yaml``: the Ultralytics dataset file (``train``, ``val``, ``nc``, ``names``, no ``path``: the root is
  the file's own folder); its readers find ``labels/NAME.txt`` beside ``images/NAME.png`` by the folder name.
* ``gt/gt.txt`` and ``seqinfo.ini``: MOTChallenge ground truth of a sequence, one line per box,
  ``frame, id, left, top, width, height, 1, class, visibility`` with 1-based frames and pixel boxes
  (Dendorfer et al., *MOTChallenge*, IJCV 2021, and the MOT17 devkit's format).
* ``contact_sheet.png``: the first frames' previews reduced onto one sheet, named, with their boxes in red.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from csuas.base.fileio import atomic_path, write_text_atomic

#: Bit depth of a written PNG above 8 bits.
PNG_BITS = 16
#: Contact sheet: frames on it, columns and the width of one frame on it [px].
SHEET_FRAMES, SHEET_COLUMNS, SHEET_TILE_PX, SHEET_GUTTER_PX = 16, 4, 480, 4
#: Thermal previews: the percentiles mapped to black and white.
THERMAL_STRETCH_PERCENTILES = (0.5, 99.5)


def dn_scale(bits: int) -> int:
    """The factor from the sensor's DN to the PNG's pixel value (module docstring): 2^(16 - bits), 1 at 8 bits."""
    return 1 if bits == 8 else 2 ** (PNG_BITS - int(bits))


def write_dn_png(path, dn: np.ndarray, bits: int) -> Path:
    """Write a frame's DN as a grey PNG scaled to its bit depth, with ``sBIT`` and the scale in text chunks."""
    from PIL import Image, PngImagePlugin

    info = PngImagePlugin.PngInfo()
    info.add(b"sBIT", bytes([int(bits)]))
    info.add_text("csuas_bits", str(int(bits)))
    info.add_text("csuas_dn_scale", str(dn_scale(bits)))
    pixels = dn.astype(np.uint8) if bits == 8 else (dn.astype(np.uint16) * np.uint16(dn_scale(bits)))
    with atomic_path(path) as tmp:
        # zlib's fastest level: a noisy frame shrinks little more at the default level, in 20 times the time
        Image.fromarray(pixels).save(tmp, format="PNG", compress_level=1, pnginfo=info)
    return Path(path)


def read_dn_png(path) -> np.ndarray:
    """The sensor's DN of a PNG written by :func:`write_dn_png` (its pixel values over ``csuas_dn_scale``)."""
    from PIL import Image

    with Image.open(path) as image:
        scale = int(image.info.get("csuas_dn_scale", 1))
        return np.asarray(image).astype(np.uint16) // np.uint16(scale)


@functools.lru_cache(maxsize=8)
def _srgb_table(bits: int) -> np.ndarray:
    """The 8-bit sRGB code of every DN of a ``bits``-deep linear frame."""
    import colour

    linear = np.arange(2**bits, dtype=float) / (2**bits - 1)
    table = np.rint(255.0 * np.clip(colour.cctf_encoding(linear, function="sRGB"), 0.0, 1.0)).astype(np.uint8)
    table.flags.writeable = False
    return table


def preview(dn: np.ndarray, bits: int, thermal: bool) -> np.ndarray:
    """The 8-bit sRGB grey preview (H, W) of a frame's DN (module docstring)."""
    if not thermal:
        return _srgb_table(int(bits))[np.clip(dn, 0, 2**bits - 1).astype(np.intp)]
    lo, hi = (float(v) for v in np.percentile(dn, THERMAL_STRETCH_PERCENTILES))
    stretched = (dn.astype(float) - lo) / max(hi - lo, 1.0)
    return np.rint(255.0 * np.clip(stretched, 0.0, 1.0)).astype(np.uint8)


def write_preview(path, image: np.ndarray) -> Path:
    """Write an 8-bit preview as a PNG tagged sRGB (``sRGB`` chunk, perceptual intent)."""
    from PIL import Image, PngImagePlugin

    info = PngImagePlugin.PngInfo()
    info.add(b"sRGB", bytes([0]))
    with atomic_path(path) as tmp:
        Image.fromarray(image).save(tmp, format="PNG", compress_level=1, pnginfo=info)
    return Path(path)


def data_yaml(names: list) -> str:
    """The Ultralytics ``data.yaml`` of a dataset folder: every image for training and validation, class names."""
    # no ``path``: Ultralytics then takes data.yaml's own folder as the root, wherever the folder is moved to
    # (a relative ``path`` resolves against the working directory or its DATASETS_DIR setting instead)
    lines = ["# csuas dataset (docs/datasets.md): YOLO labels in labels/, images in images/, root: this folder"]
    lines += ["train: images", "val: images", f"nc: {len(names)}", "names:"]
    lines += [f"  {index}: {name}" for index, name in enumerate(names)]
    return "\n".join(lines) + "\n"


def mot_line(frame_id: int, track_id: int, bbox, class_id: int, visibility: float) -> str:
    """One MOTChallenge ground-truth line (module docstring); ``frame_id`` and ``track_id`` 1-based."""
    x, y, w, h = bbox
    return f"{int(frame_id)},{int(track_id)},{x},{y},{w},{h},1,{int(class_id)},{float(visibility):.4f}"


def seqinfo(name: str, frame_rate_hz: float, length: int, width: int, height: int) -> str:
    """The MOTChallenge ``seqinfo.ini`` of ``mot/VIDEO/``: its images lie in the dataset's ``images/`` (``imDir``
    relative to it), named by the dataset rather than by frame number (COCO's ``frame_id`` maps them)."""
    return (
        f"[Sequence]\nname={name}\nimDir=../../images\nframeRate={frame_rate_hz:g}\nseqLength={int(length)}\n"
        f"imWidth={int(width)}\nimHeight={int(height)}\nimExt=.png\n"
    )


def write_contact_sheet(path, frames: list) -> Path:
    """The first frames reduced onto one sheet, 4 px apart, each named in its corner, their boxes drawn in red
    (at least 5 px across, to be seen).

    Parameters
    ----------
    frames : list of (ndarray, list, str)
        Each frame's 8-bit preview (H, W), its COCO boxes [x, y, w, h] in pixels and its name.
    """
    from PIL import Image, ImageDraw

    shown = frames[:SHEET_FRAMES]
    height, width = shown[0][0].shape
    scale = SHEET_TILE_PX / width
    tile_h = round(height * scale)
    step_x, step_y = SHEET_TILE_PX + SHEET_GUTTER_PX, tile_h + SHEET_GUTTER_PX
    rows, columns = -(-len(shown) // SHEET_COLUMNS), min(len(shown), SHEET_COLUMNS)
    sheet = Image.new("RGB", (step_x * columns - SHEET_GUTTER_PX, step_y * rows - SHEET_GUTTER_PX), (20, 20, 20))
    draw = ImageDraw.Draw(sheet)
    for index, (image, boxes, name) in enumerate(shown):
        left, top = step_x * (index % SHEET_COLUMNS), step_y * (index // SHEET_COLUMNS)
        tile = Image.fromarray(image).convert("RGB").resize((SHEET_TILE_PX, tile_h), Image.Resampling.BOX)
        sheet.paste(tile, (left, top))
        draw.text((left + 4, top + 2), name, fill=(255, 255, 0))
        for x, y, w, h in boxes:
            cx, cy = left + (x + w / 2) * scale, top + (y + h / 2) * scale
            half_w, half_h = max(w * scale / 2 + 1, 2.5), max(h * scale / 2 + 1, 2.5)
            x0, x1 = max(cx - half_w, left), min(cx + half_w, left + SHEET_TILE_PX - 1)
            y0, y1 = max(cy - half_h, top), min(cy + half_h, top + tile_h - 1)
            draw.rectangle([x0, y0, x1, y1], outline=(255, 0, 0), width=1)  # kept inside its tile
    with atomic_path(path) as tmp:
        sheet.save(tmp, format="PNG")
    return Path(path)


def write_yolo_dataset_file(path: Path, names: list) -> Path:
    """Write ``data.yaml`` (:func:`data_yaml`) at ``path``, in the dataset folder."""
    return write_text_atomic(path, data_yaml(names))
