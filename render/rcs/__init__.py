"""Radar cross-section by shooting and bouncing rays with physical optics (SPEC 6).

Public entry points (importing this package does not import Mitsuba):

* :func:`compute_rcs` -- monostatic or bistatic RCS of a mesh or drone preset
  for batches of aspects and frequencies, with quality presets and an error
  estimate (:mod:`csuas.render.rcs.solver`);
* :func:`aspect_sweep`, :func:`plot_polar`, :func:`band_sweep`,
  :func:`sphere_average` (:mod:`csuas.render.rcs.sweep`);
* :func:`convergence_curve`, :func:`density_for_accuracy`
  (:mod:`csuas.render.rcs.convergence`);
* :func:`csuas.render.rcs.checks.default_checks` and
  :func:`csuas.render.rcs.bench.bench_sbr`.
"""

from .geometry import TargetMesh, direction_vector, load_target, polarisation_basis, prepare_mesh
from .materials import RadioMaterial, resolve_material

__all__ = ["TargetMesh", "direction_vector", "load_target", "polarisation_basis", "prepare_mesh",
           "RadioMaterial", "resolve_material"]
