"""Output of lidar cross-section maps: EXR (float32, linear, with metadata) and PNG preview.

The map is the LCS contributed by each cell of the sampled window [m^2 per
pixel]; its sum is the target's LCS. Files are written atomically
(:func:`csuas.base.fileio.atomic_path`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from csuas.base.fileio import atomic_path
from csuas.base.paths import inside
from csuas.render.files import write_colour_map

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


def write_png_preview(path, image: np.ndarray, title: str = "lidar cross-section map") -> str:
    """Write a readable colour-mapped PNG of ``image`` with a colour bar [m^2 per pixel]."""
    return str(write_colour_map(path, image, "LCS per pixel [m^2]", PREVIEW_COLORMAP, title))


def write_lcs_map(out_dir, stem: str, image: np.ndarray, metadata: dict) -> list:
    """Write ``<stem>.exr`` and ``<stem>.png`` into ``out_dir`` (created); return both paths."""
    directory = Path(out_dir)
    directory.mkdir(parents=True, exist_ok=True)
    title = (
        f"lidar {metadata.get('band', '')}, R = {metadata.get('range_m', 0):g} m: "
        f"LCS {metadata.get('lcs_m2', float('nan')):.3g} m^2"
    )
    return [
        write_exr(inside(directory, f"{stem}.exr"), image, metadata),
        write_png_preview(inside(directory, f"{stem}.png"), image, title),
    ]
