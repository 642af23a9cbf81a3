"""Accuracy against time of the imaging renderers: error of a figure against samples per pixel.

The sweep renders one case at increasing strata per pixel side and compares each figure with an
exact (or reference-quality) value: exact silhouettes (:mod:`csuas.drone_models.silhouette`) and
band-Planck oracles. It measured the presets of :mod:`csuas.render.imaging.quality`.
"""

from __future__ import annotations

import time

from csuas.render.imaging.quality import Quality, resolve_quality


def accuracy_sweep(render, n_sides, reference: float, metric: str = "pixels_on_target", n_batches: int = 8) -> list:
    """Error and wall time of a figure against samples per pixel.

    Parameters
    ----------
    render : callable(Quality) -> ImagingResult
        Renders the case at the given quality.
    n_sides : iterable of int
        Strata per pixel side to try (spp = n_side**2 * n_batches).
    reference : float
        Exact (or reference-quality) value of the figure.
    metric : str
        Name of the figure in ``result.values``.
    n_batches : int

    Returns
    -------
    list of dict
        One row per sample count: ``spp``, ``value``, ``stderr``, ``error``
        (value - reference), ``relative_error``, ``time_s``.
    """
    rows = []
    for n in n_sides:
        q = resolve_quality(Quality(f"sweep_{n}", int(n), int(n_batches)))
        t0 = time.perf_counter()
        result = render(q)
        elapsed = time.perf_counter() - t0
        value = result.values[metric]
        rows.append(
            {
                "spp": q.spp,
                "value": value,
                "stderr": result.stderr[metric],
                "error": value - reference,
                "relative_error": (value - reference) / reference if reference else None,
                "time_s": elapsed,
            }
        )
    return rows
