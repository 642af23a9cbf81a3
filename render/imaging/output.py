"""Image files of a render: linear float32 OpenEXR with metadata, and PNG previews (docs/simulation.md).

EXR channels: EO ``R, G, B`` (apparent luminance-scaled radiance [cd m^-2])
and ``A`` (fractional target coverage); thermal ``L`` (apparent band
radiance [W m^-2 sr^-1]), ``T`` (radiance temperature [K]) and ``A``. The
rendered window is the EXR's ``dataWindow`` inside a ``displayWindow`` of the
full sensor frame (N_H x N_V pixels), at its pixel offset in that frame.
Header attributes ``csuas_*``: the keys of :data:`csuas.render.files.METADATA_KEYS`
(every mode writes them all), plus the window's offset and samples per pixel.

PNG previews. EO: through the sRGB encoding of colour-science
(``colour.cctf_encoding``) at a fixed exposure, a camera set for clear
daylight (:data:`EXPOSURE_REFERENCE_LX`): a white Lambertian surface under
that illuminance is display white, so twilight and night look dark; with
``exposure="auto"`` the brightest pixel is white instead. Thermal: radiance
temperature in a colour map with a colour bar in kelvin. Small windows are
enlarged by pixel replication. Files are written atomically
(:func:`csuas.base.fileio.atomic_path`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from csuas.base.errors import ParameterError
from csuas.base.fileio import atomic_path
from csuas.base.paths import inside
from csuas.core.radiometry import radiance_temperature
from csuas.render.files import METADATA_KEYS, write_colour_map

#: Previews are enlarged by pixel replication to at least this many pixels across.
PREVIEW_MIN_PX = 256
#: Illuminance of the fixed preview exposure: the paper's clear day (Table 11) [lx].
EXPOSURE_REFERENCE_LX = 70_000.0
EXPOSURES = ("scene", "auto")


def _channels(result) -> dict:
    channels = {name: np.ascontiguousarray(result.image[i], dtype=np.float32) for i, name in enumerate(result.channels)}
    if result.modality == "tir":
        channels["T"] = np.ascontiguousarray(radiance_temperature(result.image[0], result.band), dtype=np.float32)
    channels["A"] = np.ascontiguousarray(result.coverage, dtype=np.float32)
    return channels


def _header(result, meta: dict, channel_names) -> dict:
    import OpenEXR

    w = result.window
    rows, columns = result.coverage.shape
    values = {
        **meta,
        "modality": result.modality,
        "band": result.band,
        "units": result.units,
        "channels": ",".join(channel_names),
        "range_m": float(result.range_m),
        "azimuth_deg": float(result.azimuth_deg),
        "elevation_deg": float(result.elevation_deg),
        "ifov_rad": float(result.ifov_rad),
    }
    missing = [k for k in METADATA_KEYS if k not in values]
    if missing:
        raise ValueError(f"EXR metadata lacks {missing}")
    header = {
        "compression": OpenEXR.ZIP_COMPRESSION,
        "type": OpenEXR.scanlineimage,
        "dataWindow": (np.array([w.x0, w.y0], np.int32), np.array([w.x0 + columns - 1, w.y0 + rows - 1], np.int32)),
        "displayWindow": (
            np.array([0, 0], np.int32),
            np.array([int(meta["frame_width_px"]) - 1, int(meta["frame_height_px"]) - 1], np.int32),
        ),
        "csuas_window_x0": int(w.x0),
        "csuas_window_y0": int(w.y0),
        "csuas_samples_per_pixel": int(result.samples_per_pixel),
    }
    header.update(
        {
            f"csuas_{k}": (v if isinstance(v, (int, float)) and not isinstance(v, bool) else str(v))
            for k, v in values.items()
        }
    )
    return header


def write_exr(result, path, meta: dict) -> Path:
    """Write the apparent image and coverage of ``result`` as a float32 EXR; return the path.

    ``meta`` gives the keys of :data:`~csuas.render.files.METADATA_KEYS` that the result does not
    carry: target, scenario, sensor, quality, seed, frame_width_px, frame_height_px.
    """
    import OpenEXR

    channels = _channels(result)
    with atomic_path(path) as tmp:
        with OpenEXR.File(_header(result, meta, list(channels)), channels) as exr:
            exr.write(str(tmp))
    return Path(path)


def _enlarge(image: np.ndarray) -> np.ndarray:
    factor = max(1, PREVIEW_MIN_PX // max(image.shape[:2]))
    return np.repeat(np.repeat(image, factor, axis=0), factor, axis=1)


def preview_eo(result, exposure: str = "scene") -> np.ndarray:
    """8-bit-ready EO display image (H, W, 3) in [0, 1] (module docstring for the exposures)."""
    import colour

    if exposure not in EXPOSURES:
        raise ParameterError("exposure", exposure, ", ".join(EXPOSURES))
    linear = np.moveaxis(result.image, 0, -1)
    if exposure == "auto":
        peak = float(linear.max())
        white = peak if peak > 0 else 1.0
    else:
        white = EXPOSURE_REFERENCE_LX / math.pi  # luminance of a white Lambertian surface [cd m^-2]
    return np.clip(colour.cctf_encoding(np.clip(linear / white, 0.0, 1.0)), 0.0, 1.0)


def preview_rgb(result, exposure: str = "auto") -> np.ndarray:
    """Display image (H, W, 3) in [0, 1]: EO by :func:`preview_eo`, thermal as a colour map of T."""
    if result.modality != "tir":
        return preview_eo(result, exposure)
    from matplotlib import colormaps

    temp = radiance_temperature(result.image[0], result.band)
    lo, hi = float(temp.min()), float(temp.max())
    if hi - lo < 1e-6:
        lo, hi = lo - 1.0, hi + 1.0
    return colormaps["inferno"]((temp - lo) / (hi - lo))[..., :3]


def write_png(result, path, exposure: str = "scene") -> Path:
    """Write the preview PNG of ``result`` (EO image, or thermal map with a colour bar); return the path."""
    if result.modality == "tir":
        return write_colour_map(
            path,
            radiance_temperature(result.image[0], result.band),
            "radiance temperature [K]",
            "inferno",
            f"thermal {result.band}, R = {result.range_m:g} m",
        )
    from matplotlib import image as mpimg

    with atomic_path(path) as tmp:
        mpimg.imsave(str(tmp), _enlarge(preview_eo(result, exposure)), format="png")
    return Path(path)


def write_images(result, out_dir, stem: str, meta: dict, exposure: str = "scene") -> list:
    """EXR and PNG of ``result`` under ``out_dir`` as ``<stem>.exr`` and ``<stem>.png``."""
    exr, png = inside(out_dir, f"{stem}.exr"), inside(out_dir, f"{stem}.png")
    return [str(write_exr(result, exr, meta)), str(write_png(result, png, exposure))]
