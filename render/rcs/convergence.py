"""The rule for choosing the SBR-PO tube density, and the engine's measured accuracy against cost.

Error model. Point-sampled tubes of size ``d = lambda / N`` cover the
illuminated silhouette up to a staircase along its boundary: the covered
area errs by a fraction of order ``perimeter * d / area`` (docs/validation.md, SBR-PO
facts), and the RCS of a specular return (proportional to area squared) by

    error_db ~= C * P * lambda / (A * N)                         (1)

with P and A the perimeter [m] and area [m^2] of the specular region seen
along the incidence direction. :func:`csuas.validation.rcs.convergence.convergence_curve`
measures the mean absolute error over random grid placements against closed forms;
:data:`ERROR_COEFFICIENT_DB` is the fitted ``C``, and
:func:`density_for_accuracy` inverts (1):

    N = C * P * lambda / (A * error_db),     at least 1.

Measured on 2 CPU cores (llvm_ad_mono), square PEC plate 0.1 m at 10 GHz,
normal incidence, mean |error| over 64 random grid offsets with the grid
aligned with the plate edges (the worst orientation):
N = 1: 1.28 dB, 2: 0.73, 4: 0.33, 8: 0.175, 16: 0.081, 32: 0.041 dB, i.e.
``error * N / (P lambda / A)`` = 1.06 ... 1.21, fitted C = 1.1 dB (the
largest error of the 64 is about 2.5 times the mean). With random grid
rotations the staircase errors partly cancel along each edge and the error
falls faster (N = 1: 0.67 dB, 4: 0.051, 16: 0.0047, about N^-1.7), so (1)
is a conservative rule. This is the tube grid alone (the engine's exact
first-hit integration switched off): what remains of it wherever a facet is
partly shadowed or lit by a reflection. The quality presets (draft N = 2,
standard N = 5, reference N = 10, four replicas each) measured on the canonical
set of :func:`csuas.validation.rcs.convergence.preset_errors` are in
:data:`PRESET_MEASURED_ERROR_DB`.
"""

from __future__ import annotations

import math

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.units import wavelength_m
from csuas.render.quality import RCS

from .geometry import load_target

#: Fitted coefficient C of the error model (1) [dB] (module docstring).
ERROR_COEFFICIENT_DB = 1.1

#: Mean and largest |error| [dB] of the quality presets over the canonical cases of
#: :func:`csuas.validation.rcs.convergence.preset_errors`
#: (plate, disk, dihedral, square and triangular trihedral, cylinder at 10 GHz; sphere ka = 50 against its
#: PO value), one :func:`compute_rcs` run each (replicated grids, exact first hits), and the time of the 7
#: solves [s]; measured with ``preset_errors()`` on 2 CPU cores (llvm_ad_mono). The largest errors are the
#: square trihedral's triple reflection; the single reflections (plate, disk, cylinder, sphere) are exact
#: PO of the mesh, whose faceting leaves 0.001-0.012 dB against the closed forms.
PRESET_MEASURED_ERROR_DB = RCS.per_rung(
    draft={"mean": 0.076, "max": 0.27, "time_s": 0.06},
    standard={"mean": 0.037, "max": 0.16, "time_s": 0.06},
    reference={"mean": 0.0074, "max": 0.020, "time_s": 0.09},
)


def density_for_accuracy(
    error_db: float,
    perimeter_m: float,
    area_m2: float,
    frequency_ghz: float,
    coefficient_db: float = ERROR_COEFFICIENT_DB,
) -> float:
    """Rays per wavelength needed for a requested RCS error, by the error model (1).

    Parameters
    ----------
    error_db : float
        Requested mean absolute error [dB] (> 0).
    perimeter_m, area_m2 : float
        Perimeter [m] and area [m^2] of the specular region (for a drone,
        its silhouette from the aspect of interest: :func:`silhouette_perimeter_area`).
    frequency_ghz : float
        Frequency [GHz].
    coefficient_db : float
        ``C`` of (1); default the fitted :data:`ERROR_COEFFICIENT_DB`.

    Returns
    -------
    float
        ``N`` [rays per wavelength], at least 1.
    """
    for name, value in (
        ("error_db", error_db),
        ("perimeter_m", perimeter_m),
        ("area_m2", area_m2),
        ("frequency_ghz", frequency_ghz),
        ("coefficient_db", coefficient_db),
    ):
        if not (isinstance(value, (int, float, np.floating)) and math.isfinite(value) and value > 0):
            raise ParameterError(name, value, "a finite number > 0")
    wavelength = wavelength_m(frequency_ghz)
    return max(1.0, coefficient_db * perimeter_m * wavelength / (area_m2 * error_db))


def silhouette_perimeter_area(target, azimuth_deg: float, elevation_deg: float) -> tuple[float, float]:
    """Perimeter [m] and area [m^2] of a mesh's silhouette seen from a direction (polygon union)."""
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    from .geometry import polarisation_basis

    mesh = load_target(target)
    e_v, e_h = polarisation_basis(azimuth_deg, elevation_deg)
    tri = mesh.vertices[mesh.faces]
    uv = np.stack([tri @ e_h, tri @ e_v], axis=-1)
    d1, d2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    keep = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) > 1e-15
    polys = [Polygon(t) for t in uv[keep]]
    shape = unary_union(polys)
    return float(shape.length), float(shape.area)
