"""Radar cross-section by shooting and bouncing rays with physical optics (docs/simulation.md).

Public entry points (importing this package does not import Mitsuba or Dr.Jit;
the engine selects a variant through :func:`csuas.render.backend.use_variant`
when it first runs):

* :func:`compute_rcs` -- monostatic or bistatic RCS of a mesh or drone preset
  for batches of frequencies x aspects, with quality presets and an error
  estimate (:mod:`csuas.render.rcs.solver`; engine in
  :mod:`csuas.render.rcs.engine`); :func:`rcs_of` takes the same run as records
  (:class:`RcsAspects`, :class:`RcsTracing`) for a prepared engine;
* :func:`aspect_sweep`, :func:`rcs_table`, :func:`plot_polar`,
  :func:`band_sweep`, :func:`sphere_average` (Eq. 6) in
  :mod:`csuas.render.rcs.sweep`;
* :func:`density_for_accuracy` (the tube density for a requested error) in
  :mod:`csuas.render.rcs.convergence`;

Its checks (Table 8, 3GPP TR 38.901), its measured accuracy against cost
(:func:`csuas.validation.rcs.convergence.convergence_curve`, ``preset_errors``) and benchmarks
live in :mod:`csuas.validation.rcs`.
"""

from csuas.drone_models.geometry import direction_vector

from .convergence import density_for_accuracy
from .geometry import TargetMesh, load_target, polarisation_basis, prepare_mesh
from .materials import RadioMaterial, resolve_material
from .solver import QUALITY_PRESETS, RcsAspects, RcsResult, RcsTracing, compute_rcs, rcs_of
from .sweep import PAPER_BANDS_GHZ, aspect_sweep, band_sweep, plot_polar, rcs_table, sphere_average

__all__ = [
    "TargetMesh",
    "direction_vector",
    "load_target",
    "polarisation_basis",
    "prepare_mesh",
    "RadioMaterial",
    "resolve_material",
    "QUALITY_PRESETS",
    "RcsResult",
    "compute_rcs",
    "rcs_of",
    "RcsAspects",
    "RcsTracing",
    "PAPER_BANDS_GHZ",
    "aspect_sweep",
    "band_sweep",
    "plot_polar",
    "rcs_table",
    "sphere_average",
    "density_for_accuracy",
]
