"""Object labels from a render's exact coverage: box, mask, COCO and YOLO records.

A render gives, for the pixels of its window, the fraction of each pixel's area the target covers
(:attr:`csuas.render.imaging.result.ImagingResult.coverage`). The label of the target in the full
frame of ``frame_width`` x ``frame_height`` pixels is read from it:

* ``bbox``: [x, y, w, h] in pixels of the tight box of the pixels with coverage > 0 (COCO's
  convention: x, y of the top-left corner, pixel edges at integers), clipped to the frame; a target
  below a pixel still gets a box of one pixel, flagged ``subpixel``;
* ``segmentation``: COCO's uncompressed run-length encoding of the same pixels over the whole frame
  (column-major, starting with a run of zeros; Lin et al., *Microsoft COCO*, ECCV 2014, and the
  ``pycocotools`` mask format);
* ``clipped``: the target reaches beyond the frame;
* YOLO: ``class x_centre y_centre width height``, normalised by the frame size.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError


def _frame_pixels(coverage, x0: int, y0: int, frame_width: int, frame_height: int):
    """Frame rows, columns and coverage of the covered pixels inside the frame, and whether any fell outside."""
    cov = np.asarray(coverage, float)
    if cov.ndim != 2 or not np.isfinite(cov).all() or cov.min() < 0 or cov.max() > 1 + 1e-9:
        raise ParameterError("coverage", f"array of shape {cov.shape}", "a finite 2-D array of fractions 0..1")
    if frame_width < 1 or frame_height < 1:
        raise ParameterError("frame size", f"{frame_width} x {frame_height}", "at least 1 x 1 px")
    ys, xs = np.nonzero(cov > 0)
    rows, cols = ys + y0, xs + x0
    inside = (cols >= 0) & (cols < frame_width) & (rows >= 0) & (rows < frame_height)
    return rows[inside], cols[inside], cov[ys[inside], xs[inside]], bool((~inside).any())


def frame_mask(coverage: np.ndarray, x0: int, y0: int, frame_width: int, frame_height: int) -> np.ndarray:
    """Boolean mask (frame_height, frame_width) of the frame's pixels with coverage > 0.

    Parameters
    ----------
    coverage : ndarray (H, W)
        Fractional coverage of the window's pixels, 0..1.
    x0, y0 : int
        Frame coordinates of the window's top-left pixel (may be negative or beyond the frame).
    frame_width, frame_height : int
        Frame size [px], >= 1.
    """
    rows, cols, _, _ = _frame_pixels(coverage, x0, y0, frame_width, frame_height)
    mask = np.zeros((frame_height, frame_width), bool)
    mask[rows, cols] = True
    return mask


def label(coverage: np.ndarray, x0: int, y0: int, frame_width: int, frame_height: int) -> dict:
    """The target's label in the frame (module docstring): ``bbox``, ``area``, ``segmentation``, flags.

    Parameters are those of :func:`frame_mask`.

    Returns
    -------
    dict
        ``bbox`` [x, y, w, h] (None when nothing of the target is in the frame), ``area`` (pixels of
        the mask), ``pixels_on_target`` (sum of coverage inside the frame), ``segmentation`` (COCO
        uncompressed RLE), ``clipped``, ``subpixel``, ``in_frame``.
    """
    rows, cols, values, clipped = _frame_pixels(coverage, x0, y0, frame_width, frame_height)
    mask = np.zeros((frame_height, frame_width), bool)
    mask[rows, cols] = True
    in_frame = rows.size > 0
    bbox = None
    if in_frame:
        bbox = [int(cols.min()), int(rows.min()), int(cols.max() - cols.min() + 1), int(rows.max() - rows.min() + 1)]
    covered = float(values.sum())
    return {
        "bbox": bbox,
        "area": int(rows.size),
        "pixels_on_target": covered,
        "segmentation": run_length(mask),
        "clipped": clipped,
        "subpixel": bool(in_frame and covered < 1.0),
        "in_frame": bool(in_frame),
    }


def run_length(mask: np.ndarray) -> dict:
    """COCO uncompressed RLE of a boolean mask: ``{"size": [h, w], "counts": [...]}``, column-major.

    The counts alternate runs of False and True, starting with False (a leading 0 when the first
    pixel is True).
    """
    m = np.asarray(mask, bool)
    flat = m.ravel(order="F")
    counts: list = []
    if flat.size:
        boundaries = np.flatnonzero(flat[1:] != flat[:-1]) + 1
        counts = np.diff(np.concatenate([[0], boundaries, [flat.size]])).tolist()
        if flat[0]:
            counts = [0, *counts]
    return {"size": [int(m.shape[0]), int(m.shape[1])], "counts": [int(c) for c in counts]}


def decode_run_length(rle: dict) -> np.ndarray:
    """The boolean mask of a COCO uncompressed RLE (the inverse of :func:`run_length`)."""
    h, w = rle["size"]
    values = np.zeros(sum(rle["counts"]), bool)
    position, state = 0, False
    for count in rle["counts"]:
        values[position : position + count] = state
        position, state = position + count, not state
    return values.reshape((h, w), order="F")


def yolo_line(bbox, frame_width: int, frame_height: int, class_id: int = 0) -> str:
    """YOLO label line of a COCO box: ``class x_centre y_centre width height``, normalised to 0..1."""
    x, y, w, h = bbox
    return (
        f"{int(class_id)} {(x + w / 2) / frame_width:.6f} {(y + h / 2) / frame_height:.6f} "
        f"{w / frame_width:.6f} {h / frame_height:.6f}"
    )
