"""Figures of a rendered window with jackknife Monte Carlo standard errors.

From a :class:`~csuas.render.imaging.trace.WindowTally` (per-batch coverage,
target radiance and hit extents) and the analytic background and path:

* ``pixels_on_target``: sum of fractional pixel coverage [px] (unbiased);
* ``pixels_above_half``: pixels covered more than 50 % [px];
* ``pixels_across_x``, ``pixels_across_y``: extents of the target's hits along
  the image axes (the paper's d_x_proj and d_y_proj in pixels, Section 2.3.1);
  ``pixels_across_dcrit`` = their minimum (Eq. 1) and
  ``pixels_across_dcrit_geometric_mean`` = their geometric mean (Eq. 2);
* ``target_radiance``: silhouette-averaged radiance of the target (inherent,
  before the path), ``background_radiance``, and their apparent values at the
  sensor after the path (``*_apparent``);
* ``contrast``: apparent contrast of the silhouette-averaged target against the
  background, Eq. 3 (Michelson); ``contrast_weber`` = (L_t - L_b) / L_b, the
  contrast of Koschmieder's law C(R) = C0 tau(R) against the horizon sky;
  ``contrast_peak_pixel``: Eq. 3 for the pixel that differs most from the
  background (what a sub-pixel target leaves in the image);
* thermal only: ``delta_t_k`` (radiance temperatures of target minus
  background, apparent at the sensor) and ``delta_t_peak_pixel_k``.

Standard errors: delete-one-batch jackknife over the independent batches
(Efron & Stein 1981), valid for the nonlinear figures too. The extents are
each batch's extreme hits refined by local searches
(:func:`~csuas.render.imaging.trace.refine_extremes`), combined over batches.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from csuas.render.imaging.path import PathEffect


@dataclass
class Measurement:
    """Figures of one rendered window.

    Attributes
    ----------
    values, stderr : dict of str -> float
        Figures (module docstring) and their Monte Carlo standard errors.
    image : ndarray, shape (C, H, W)
        Apparent radiance at the sensor (target over background, path applied).
    coverage : ndarray, shape (H, W)
        Mean fractional coverage.
    """

    values: dict
    stderr: dict
    image: np.ndarray
    coverage: np.ndarray
    notes: list = field(default_factory=list)


def _figures(coverage, radiance, extent, background, weights, path: PathEffect, to_temperature):
    scalar = np.tensordot(weights, radiance, axes=1)
    l_bg = float(np.dot(weights, background))
    covered = float(coverage.sum())
    out = {"pixels_on_target": covered, "pixels_above_half": float(np.count_nonzero(coverage > 0.5))}
    if np.all(np.isfinite(extent)):
        ex, ey = float(extent[1] - extent[0]), float(extent[3] - extent[2])
    else:
        ex = ey = 0.0
    out.update(
        pixels_across_x=ex,
        pixels_across_y=ey,
        pixels_across_dcrit=min(ex, ey),
        pixels_across_dcrit_geometric_mean=float(np.sqrt(ex * ey)),
    )
    l_t = float(scalar.sum()) / covered if covered > 0 else l_bg
    lt_app, lb_app = float(path.apply(l_t)), float(path.apply(l_bg))
    image = path.apply(radiance + (1.0 - coverage)[None] * np.asarray(background, dtype=float)[:, None, None])
    pixel = np.tensordot(weights, image, axes=1)
    peak = float(pixel.flat[np.argmax(np.abs(pixel - lb_app))])
    total = lt_app + lb_app
    out.update(
        target_radiance=l_t,
        background_radiance=l_bg,
        target_radiance_apparent=lt_app,
        background_radiance_apparent=lb_app,
        contrast=(lt_app - lb_app) / total if total > 0 else 0.0,
        contrast_weber=(lt_app - lb_app) / lb_app if lb_app > 0 else float("inf"),
        contrast_peak_pixel=(peak - lb_app) / (peak + lb_app) if peak + lb_app > 0 else 0.0,
    )
    if to_temperature is not None:
        t_bg = float(to_temperature(lb_app))
        out.update(
            delta_t_k=float(to_temperature(lt_app)) - t_bg,
            delta_t_peak_pixel_k=float(to_temperature(peak)) - t_bg,
            background_temperature_apparent_k=t_bg,
        )
    return out, image


def _extent_of(extent_batches):
    with np.errstate(all="ignore"):
        if np.all(np.isnan(extent_batches[:, 0])):
            return np.full(4, np.nan)
        return np.array(
            [
                np.nanmin(extent_batches[:, 0]),
                np.nanmax(extent_batches[:, 1]),
                np.nanmin(extent_batches[:, 2]),
                np.nanmax(extent_batches[:, 3]),
            ]
        )


def measure_window(tally, background, path: PathEffect, weights=(1.0,), to_temperature=None) -> Measurement:
    """Figures and jackknife standard errors of a window tally.

    Parameters
    ----------
    tally : WindowTally
    background : array_like, shape (C,)
        Inherent radiance of the background behind the target, per channel.
    path : PathEffect
        Transmittance and path radiance of the range.
    weights : array_like, shape (C,)
        Channel weights of the measured scalar radiance (luminance Y for RGB).
    to_temperature : callable or None
        Radiance -> radiance temperature [K] (thermal IR).
    """
    k = tally.n_batches
    weights = np.asarray(weights, dtype=float)
    background = np.broadcast_to(np.asarray(background, dtype=float), (tally.radiance.shape[1],))
    cov_sum, rad_sum = tally.coverage.sum(0), tally.radiance.sum(0)
    values, image = _figures(
        cov_sum / k, rad_sum / k, _extent_of(tally.extent), background, weights, path, to_temperature
    )
    stderr = {name: 0.0 for name in values}
    if k > 1:
        loo = []
        for b in range(k):
            keep = np.arange(k) != b
            fig, _ = _figures(
                (cov_sum - tally.coverage[b]) / (k - 1),
                (rad_sum - tally.radiance[b]) / (k - 1),
                _extent_of(tally.extent[keep]),
                background,
                weights,
                path,
                to_temperature,
            )
            loo.append(fig)
        for name in values:
            theta = np.array([f[name] for f in loo], dtype=float)
            if np.all(np.isfinite(theta)):
                stderr[name] = float(np.sqrt((k - 1) / k * np.sum((theta - theta.mean()) ** 2)))
    notes = []
    if values["pixels_on_target"] == 0:
        notes.append("no sample hit the target: it is far below one pixel at this range and sample count")
    if not np.isfinite(values["contrast_weber"]):
        notes.append("the background radiance is 0: Weber contrast undefined (null)")
    return Measurement(values, stderr, image, cov_sum / k, notes)
