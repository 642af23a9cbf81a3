"""Result record of one rendered range (EO or thermal IR)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class ImagingResult:
    """One render of a target at one range.

    Attributes
    ----------
    modality : {"eo", "tir"}
    band : str
        ``"visible"`` (luminance) or the thermal band name.
    range_m, azimuth_deg, elevation_deg : float
        Geometry (docs/command-line.md direction convention).
    ifov_rad : float
        Pixel IFOV [rad].
    window : Window
        Rendered pixels of the full sensor frame.
    values, stderr : dict
        Figures (:mod:`csuas.render.imaging.measure`) and Monte Carlo standard errors.
    image : ndarray, shape (C, H, W)
        Apparent radiance at the sensor, linear.
    coverage : ndarray, shape (H, W)
        Fractional target coverage.
    units : str
        Unit of ``image``.
    channels : tuple of str
        Channel names of ``image``.
    terms : list of dict
        Path effects applied (empty when the atmosphere is off).
    quality : Quality
    samples : int
        Camera rays traced.
    samples_per_pixel : int
        Samples per sampled pixel region (n_side**2 x batches; raised above the
        preset for small targets).
    time_s : float
        Wall time of the render and measurement [s].
    notes : list of str
    """

    modality: str
    band: str
    range_m: float
    azimuth_deg: float
    elevation_deg: float
    ifov_rad: float
    window: object
    values: dict
    stderr: dict
    image: np.ndarray
    coverage: np.ndarray
    units: str
    channels: tuple
    terms: list
    quality: object
    samples: int
    samples_per_pixel: int
    time_s: float
    notes: list = field(default_factory=list)

    def summary(self) -> dict:
        """JSON-ready figures (docs/command-line.md keys ``range_m``, ``pixels_on_target``, ``pixels_across_dcrit``,
        ``contrast``, ``stderr``, ``time_s``; thermal adds ``delta_t_k``)."""
        out = {
            "range_m": self.range_m,
            "modality": self.modality,
            "band": self.band,
            "azimuth_deg": self.azimuth_deg,
            "elevation_deg": self.elevation_deg,
            "ifov_rad": self.ifov_rad,
        }
        out.update(self.values)
        out.update(
            stderr=dict(self.stderr),
            time_s=self.time_s,
            samples=self.samples,
            samples_per_pixel=self.samples_per_pixel,
            quality=self.quality.name,
            window_px=self.window.as_dict(),
            terms=list(self.terms),
            units=self.units,
            notes=list(self.notes),
        )
        return out
