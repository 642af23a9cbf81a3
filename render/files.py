"""Names and metadata shared by every render output file (EO, thermal, lidar).

A file name carries every coordinate that can vary between the renders of one command, so that
renders into one folder never overwrite each other:
``<scenario>_<sensor>_<modality>_r<range>m_az<azimuth>_el<elevation>_<quality>[_seed<seed>]``.
Every EXR header carries the same ``csuas_*`` keys (:data:`METADATA_KEYS`); maps (thermal,
lidar) are previewed by :func:`write_colour_map`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from csuas.base.fileio import atomic_path
from csuas.base.paths import file_name_part

#: Header attributes (``csuas_<key>``) every render's EXR carries.
METADATA_KEYS = (
    "modality",
    "target",
    "scenario",
    "sensor",
    "band",
    "units",
    "channels",
    "quality",
    "seed",
    "frame_width_px",
    "frame_height_px",
    "range_m",
    "azimuth_deg",
    "elevation_deg",
    "ifov_rad",
)


def _number(value: float) -> str:
    """A coordinate for a file name: ``100``, ``2.5``, ``1e+06``; a minus sign as ``m``."""
    return f"{value:.6g}".replace("-", "m")


def coordinates_label(range_m: float, azimuth_deg: float, elevation_deg: float) -> str:
    """The part of a file name that says where the sensor is: ``r100m_az0_el15``."""
    return f"r{_number(range_m)}m_az{_number(azimuth_deg)}_el{_number(elevation_deg)}"


def file_stem(
    scenario: str,
    sensor: str,
    modality: str,
    range_m: float,
    azimuth_deg: float,
    elevation_deg: float,
    quality: str,
    seed: int,
) -> str:
    """File name without suffix of one render (module docstring).

    Raises
    ------
    ParameterError
        When the scenario's ``name`` or the sensor's key cannot be part of a file name
        (:func:`csuas.base.paths.file_name_part`).
    """
    file_name_part(scenario, "name")
    file_name_part(sensor, "sensors")
    stem = f"{scenario}_{sensor}_{modality}_{coordinates_label(range_m, azimuth_deg, elevation_deg)}_{quality}"
    return stem + (f"_seed{seed}" if seed else "")


def write_colour_map(path, values: np.ndarray, label: str, colormap: str, title: str) -> Path:
    """A readable PNG of a 2-D map: nearest-neighbour pixels, a labelled colour bar and a title.

    Whatever the map's size (a 106 x 22 strip, a 4 x 4 window), the figure is at least
    6 x 4.5 inches at 100 dpi.
    """
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot as plt

    data = np.asarray(values, dtype=float)
    low, high = float(np.nanmin(data)), float(np.nanmax(data))
    if high - low < 1e-6:
        low, high = low - 1.0, high + 1.0
    fig, ax = plt.subplots(figsize=(6.0, 4.5), dpi=100)
    try:
        shown = ax.imshow(data, cmap=colormap, vmin=low, vmax=high, interpolation="nearest", aspect="equal")
        fig.colorbar(shown, ax=ax, label=label, shrink=0.9)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("pixel")
        ax.set_ylabel("pixel")
        fig.tight_layout()
        with atomic_path(path) as tmp:
            fig.savefig(str(tmp), format="png")
    finally:
        plt.close(fig)
    return Path(path)
