"""Image files of a render: linear float32 OpenEXR with metadata, and PNG previews (docs/simulation.md).

EXR channels: EO ``R, G, B`` (apparent luminance-scaled radiance [cd m^-2])
and ``A`` (fractional target coverage); thermal ``L`` (apparent band
radiance [W m^-2 sr^-1]), ``T`` (radiance temperature [K]) and ``A``.
Header attributes ``csuas_*`` carry range, IFOV, modality, band, units, the
window's position in the full sensor frame, direction and samples per pixel.
PNG previews: EO through the sRGB encoding of colour-science
(``colour.cctf_encoding``), scaled so the brightest pixel is white; thermal
as a colour map of the radiance temperature. Small windows are enlarged by
pixel replication. Files are written atomically (:func:`csuas.base.fileio.atomic_path`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from csuas.base.fileio import atomic_path

#: Previews are enlarged by pixel replication to at least this many pixels across.
PREVIEW_MIN_PX = 256


def _header(result) -> dict:
    import OpenEXR

    w = result.window
    return {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
            "csuas_modality": result.modality, "csuas_band": result.band, "csuas_units": result.units,
            "csuas_range_m": float(result.range_m), "csuas_ifov_rad": float(result.ifov_rad),
            "csuas_azimuth_deg": float(result.azimuth_deg), "csuas_elevation_deg": float(result.elevation_deg),
            "csuas_window_x0": int(w.x0), "csuas_window_y0": int(w.y0),
            "csuas_samples_per_pixel": int(result.samples_per_pixel),
            "csuas_channels": ",".join(result.channels) + ",A (coverage)"}


def write_exr(result, path) -> Path:
    """Write the apparent image and coverage of ``result`` as a float32 EXR; return the path."""
    import OpenEXR

    channels = {name: np.ascontiguousarray(result.image[i], dtype=np.float32) for i, name in enumerate(result.channels)}
    if result.modality == "tir":
        from csuas.core.radiometry import radiance_temperature
        channels["T"] = np.ascontiguousarray(radiance_temperature(result.image[0], result.band), dtype=np.float32)
    channels["A"] = np.ascontiguousarray(result.coverage, dtype=np.float32)
    with atomic_path(path) as tmp:
        with OpenEXR.File(_header(result), channels) as exr:
            exr.write(str(tmp))
    return Path(path)


def _enlarge(image: np.ndarray) -> np.ndarray:
    factor = max(1, PREVIEW_MIN_PX // max(image.shape[:2]))
    return np.repeat(np.repeat(image, factor, axis=0), factor, axis=1)


def preview_rgb(result) -> np.ndarray:
    """8-bit-ready display image (H, W, 3) in [0, 1]."""
    if result.modality == "tir":
        from matplotlib import colormaps

        from csuas.core.radiometry import radiance_temperature
        temp = radiance_temperature(result.image[0], result.band)
        lo, hi = float(temp.min()), float(temp.max())
        if hi - lo < 1e-6:
            lo, hi = lo - 1.0, hi + 1.0
        return colormaps["inferno"]((temp - lo) / (hi - lo))[..., :3]
    import colour

    linear = np.moveaxis(result.image, 0, -1)
    peak = float(linear.max())
    return np.clip(colour.cctf_encoding(np.clip(linear / (peak if peak > 0 else 1.0), 0.0, 1.0)), 0.0, 1.0)


def write_png(result, path) -> Path:
    """Write the preview PNG of ``result``; return the path."""
    from matplotlib import image as mpimg

    with atomic_path(path) as tmp:
        mpimg.imsave(str(tmp), _enlarge(preview_rgb(result)), format="png")
    return Path(path)


def write_images(result, out_dir, stem: str) -> list:
    """EXR and PNG of ``result`` under ``out_dir`` as ``<stem>.exr`` and ``<stem>.png``."""
    out = Path(out_dir)
    return [str(write_exr(result, out / f"{stem}.exr")), str(write_png(result, out / f"{stem}.png"))]
