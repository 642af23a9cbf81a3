"""The bounce limit chosen by the power the stopped tubes still carry.

A tube the bounce limit stops while it would hit the target again still carries power; if it went on
and radiated once more, it could add at most ``4 pi A^2 P / lambda^2`` (a flat aperture of its
cross-section A re-radiating its relative power P; Knott, Shaeffer and Tuley, *Radar Cross Section*,
2nd ed., 2004, ch. 5). Their sum at random phase is ``RcsResult.truncated_sigma_m2``, and its ratio to
the result is the truncation term of the bound (:meth:`csuas.render.rcs.solver.RcsResult.truncation_db`).
:func:`rcs_until_truncated` raises the limit (by half each time, up to
:data:`csuas.render.rcs.solver.MAX_BOUNCES`) until that ratio is at most a stated fraction
(default :data:`TRUNCATION_FRACTION`) for every co-polarised figure.
"""

from __future__ import annotations

import math

import numpy as np

from csuas.base.errors import ParameterError

from .solver import MAX_BOUNCES, compute_rcs, resolve_quality

#: Default largest ratio of the stopped tubes' RCS to the result (-20 dB: a truncation term of 0.92 dB).
TRUNCATION_FRACTION = 0.01


def truncated_fraction(result) -> float:
    """Largest ratio of the stopped tubes' RCS to the result over the co-polarised (VV, HH) figures."""
    ratios = []
    for pol, tx in (("VV", 0), ("HH", 1)):
        sigma = result.rcs_m2(pol)
        live = np.broadcast_to(result.truncated_sigma_m2[..., tx][..., None], sigma.shape)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratios.append(np.where(live > 0.0, live / sigma, 0.0))
    return float(np.nanmax(np.concatenate([r.ravel() for r in ratios])))


def rcs_until_truncated(
    target, frequency_ghz, azimuth_deg=0.0, elevation_deg=0.0, *, fraction=TRUNCATION_FRACTION, **kwargs
):
    """:func:`compute_rcs` with the bounce limit raised until :func:`truncated_fraction` <= ``fraction``.

    Parameters
    ----------
    target, frequency_ghz, azimuth_deg, elevation_deg, **kwargs
        As :func:`csuas.render.rcs.solver.compute_rcs`; ``max_bounces`` (or the quality preset's) is
        the first limit tried.
    fraction : float
        Largest ratio accepted, 0 < fraction < 1.

    Returns
    -------
    (RcsResult, list of (int, float))
        The last run, and each limit tried with its fraction. At :data:`MAX_BOUNCES` the run is
        returned whatever its fraction (its truncation term says how much is missing).
    """
    if not (0.0 < fraction < 1.0):
        raise ParameterError("truncation_fraction", fraction, "0 < x < 1")
    _, bounces = resolve_quality(kwargs.get("quality", "standard"), None, kwargs.pop("max_bounces", None))
    tried = []
    while True:
        result = compute_rcs(target, frequency_ghz, azimuth_deg, elevation_deg, max_bounces=bounces, **kwargs)
        tried.append((bounces, truncated_fraction(result)))
        if tried[-1][1] <= fraction or bounces >= MAX_BOUNCES:
            return result, tried
        bounces = min(MAX_BOUNCES, math.ceil(1.5 * bounces))
