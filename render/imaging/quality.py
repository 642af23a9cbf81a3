"""Sample-count presets of the imaging renderers and their measured accuracy (docs/validation.md).

A preset fixes the jittered strata per pixel side (``n_side``; n_side**2
samples per pixel and batch) and the number of independent batches that give
the jackknife standard error. Their errors are measured with
:func:`csuas.validation.imaging.accuracy.accuracy_sweep` against exact silhouettes and band-Planck oracles
(``tests/test_render_quality.py``), not assumed. Measured on 2 CPU cores
(LLVM), DJI Mini 4 Pro at 500 m, azimuth 30 deg, elevation 20 deg, default EO
sensor (13.30 px on target, 3.03 px across d_crit, 169-pixel window); thermal:
0.3 m graybody plate at 200 m reflecting 293.15 K surroundings (exact
Delta T -7.243 K):

=========  ====  ==================  ==================  ===============  ===============  ==========
preset     spp   pixels on target    px across d_crit    EO contrast      TIR Delta T [K]  time/range
=========  ====  ==================  ==================  ===============  ===============  ==========
draft        32  +2.0 % (se 1.7 %)   -0.05 % (se 0.02 %) +0.016 (se .025) +0.12 (se 0.10)  0.4 s
standard    128  +0.2 % (se 0.5 %)   -0.03 % (se 0.03 %) +0.011 (se .020) +0.00 (se 0.07)  0.2-0.4 s
reference  2048  +0.06 % (se 0.08 %) -0.00 % (se 0.02 %) (reference)      +0.03 (se 0.02)  0.1-0.5 s
=========  ====  ==================  ==================  ===============  ===============  ==========

Errors are against the exact silhouette and the band-Planck Delta T; the EO
contrast error is against the reference render (-0.334 +- 0.003). Small
targets get more samples than the preset's per-pixel count
(:data:`csuas.render.imaging.trace.MIN_BOX_PIXELS`), which is why the thermal
plate (about 2 px) costs little at every preset.
Memory: launches of at most 2**21 rays; the worst window
(the drone at 10 m, 475 x 475 px) at reference quality traced 4.6e8 rays in
97 s with a peak resident set of 0.77 GB.
"""

from __future__ import annotations

from dataclasses import dataclass

from csuas.base.errors import ParameterError
from csuas.render.quality import IMAGING


@dataclass(frozen=True)
class Quality:
    """Monte Carlo effort of a render.

    Attributes
    ----------
    name : str
    n_side : int
        Jittered strata per pixel side; n_side**2 samples per pixel per batch.
    n_batches : int
        Independent batches (>= 2 for a standard error).
    """

    name: str
    n_side: int
    n_batches: int

    @property
    def spp(self) -> int:
        """Samples per pixel in total."""
        return self.n_side * self.n_side * self.n_batches


#: Rung name -> :class:`Quality`, from :data:`csuas.render.quality.IMAGING`.
QUALITY_PRESETS = IMAGING.presets(Quality)


def resolve_quality(quality) -> Quality:
    """A :class:`Quality` from a preset name or a Quality (validated)."""
    if isinstance(quality, Quality):
        if quality.n_side < 1 or quality.n_batches < 2:
            raise ParameterError("quality", quality, "n_side >= 1 and n_batches >= 2")
        return quality
    if quality not in QUALITY_PRESETS:
        raise ParameterError("quality", quality, ", ".join(QUALITY_PRESETS))
    return QUALITY_PRESETS[quality]
