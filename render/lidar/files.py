"""Output of lidar cross-section maps: EXR (float32, linear, with metadata) and PNG preview.

The map is the LCS contributed by each cell of the sampled window [m^2 per
pixel]; its sum is the target's LCS. Files are written atomically
(:func:`csuas.base.fileio.atomic_path`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from csuas.base.fileio import atomic_path

#: Colour map of the PNG preview (perceptually uniform, dark = no return).
PREVIEW_COLORMAP = "magma"


def _header_value(value):
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value)
    return str(value)


def write_exr(path, image: np.ndarray, metadata: dict) -> str:
    """Write a single-channel (``Y``) float32 EXR with ``csuas_*`` header attributes.

    Parameters
    ----------
    path : str or pathlib.Path
        Destination ``.exr``.
    image : numpy.ndarray, shape (rows, columns)
        Linear values (row 0 at the top).
    metadata : dict
        Scalars or strings; stored as ``csuas_<key>`` attributes.

    Returns
    -------
    str
        The path written.
    """
    import OpenEXR

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    header.update({f"csuas_{k}": _header_value(v) for k, v in metadata.items()})
    pixels = np.ascontiguousarray(image, dtype=np.float32)
    with atomic_path(path) as tmp:
        OpenEXR.File(header, {"Y": pixels}).write(str(tmp))
    return str(path)


def write_png_preview(path, image: np.ndarray) -> str:
    """Write a colour-mapped PNG of ``image`` scaled from 0 to its maximum."""
    import matplotlib.image

    top = float(np.max(image)) if image.size else 0.0
    with atomic_path(path) as tmp:
        matplotlib.image.imsave(str(tmp), np.asarray(image, dtype=float), cmap=PREVIEW_COLORMAP, vmin=0.0,
                                vmax=top if top > 0.0 else 1.0, format="png")
    return str(path)


def write_lcs_map(out_dir, stem: str, image: np.ndarray, metadata: dict) -> list:
    """Write ``<stem>.exr`` and ``<stem>.png`` into ``out_dir`` (created); return both paths."""
    directory = Path(out_dir)
    directory.mkdir(parents=True, exist_ok=True)
    return [write_exr(directory / f"{stem}.exr", image, metadata),
            write_png_preview(directory / f"{stem}.png", image)]
