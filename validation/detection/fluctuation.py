"""The drone's own RCS fluctuation: SBR-PO RCS over random aspects, per band, as samples.

Aspects are drawn uniformly over the sphere (azimuth uniform, sine of elevation uniform), the
distribution of a drone seen from an arbitrary direction; each band is traced once for all
aspects by :func:`csuas.render.rcs.compute_rcs` at the given accuracy.
"""

from __future__ import annotations

import numpy as np

from csuas.render.rcs import compute_rcs

#: Polarisation channels of RcsResult.sigma_m2[..., receive, transmit].
CHANNELS = {"VV": (0, 0), "HH": (1, 1)}


def drone_rcs_samples(
    preset: str, bands_ghz, n_aspects: int, *, seed: int = 0, rays_per_wavelength: float = 3.0, max_bounces: int = 3
) -> dict:
    """RCS samples of a drone preset over uniformly random aspects.

    Returns
    -------
    dict
        ``{"VV": array (bands, aspects), "HH": ..., "time_s": float, "tubes": int}`` [m^2].
    """
    rng = np.random.default_rng(seed)
    azimuth = rng.uniform(0.0, 360.0, n_aspects)
    elevation = np.degrees(np.arcsin(rng.uniform(-1.0, 1.0, n_aspects)))
    result = compute_rcs(
        preset,
        np.asarray(bands_ghz, dtype=float),
        azimuth,
        elevation,
        rays_per_wavelength=rays_per_wavelength,
        max_bounces=max_bounces,
        error_estimate=False,
    )
    out = {name: result.sigma_m2[:, :, 0, rx, tx] for name, (rx, tx) in CHANNELS.items()}
    out.update(time_s=float(result.time_s), tubes=int(result.tubes))
    return out
