"""Accuracy against cost of the SBR-PO engine, and the rule for choosing the tube density.

Error model. Point-sampled tubes of size ``d = lambda / N`` cover the
illuminated silhouette up to a staircase along its boundary: the covered
area errs by a fraction of order ``perimeter * d / area`` (docs/validation.md, SBR-PO
facts), and the RCS of a specular return (proportional to area squared) by

    error_db ~= C * P * lambda / (A * N)                         (1)

with P and A the perimeter [m] and area [m^2] of the specular region seen
along the incidence direction. :func:`convergence_curve` measures the mean
absolute error over random grid placements against closed forms;
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
set of :func:`preset_errors` are in :data:`PRESET_MEASURED_ERROR_DB`.
"""

from __future__ import annotations

import math
import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.units import wavelength_m
from csuas.render.quality import RCS

from . import canonical
from .engine import Jobs, SbrEngine
from .geometry import load_target

#: Fitted coefficient C of the error model (1) [dB] (module docstring).
ERROR_COEFFICIENT_DB = 1.1

#: Mean and largest |error| [dB] of the quality presets over the canonical cases of :func:`preset_errors`
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


def convergence_curve(
    densities=(1, 2, 4, 8, 16, 32),
    *,
    trials: int = 64,
    seed: int = 1,
    orientation: str = "aligned",
    max_bounces: int = 1,
) -> list[dict]:
    """Error of the tube grid alone against density and time, on the square-plate oracle at normal incidence.

    A 0.1 m PEC plate at 10 GHz (exact 4 pi A^2 / lambda^2 = +1.46 dBsm) is
    solved with ``trials`` random grid offsets per density, with the exact
    first-hit integration switched off so that the tubes alone make the field
    (what they do wherever a facet is partly shadowed or lit by a reflection).

    Parameters
    ----------
    densities : sequence of float
        Rays per wavelength N (each >= 1).
    trials : int
        Random grid placements per density.
    seed : int
        Random seed (deterministic results).
    orientation : {"aligned", "random"}
        Grid rows parallel to the plate edges (worst case, the rule (1)) or
        rotated at random about the normal.

    Returns
    -------
    list of dict
        Per density: ``rays_per_wavelength``, ``mean_abs_error_db``,
        ``max_abs_error_db``, ``model_error_db`` (rule (1)), ``tubes`` per
        solve, ``time_s`` per solve (warm), ``rays_x_bounces_per_s``.
    """
    if int(trials) != trials or trials < 1:
        raise ParameterError("trials", trials, "integer >= 1")
    if orientation not in ("aligned", "random"):
        raise ParameterError("orientation", orientation, "'aligned' or 'random'")
    rng = np.random.default_rng(seed)
    a, f = 0.1, 10.0
    lam = wavelength_m(f)
    exact = 4 * math.pi * (a * a) ** 2 / lam**2
    p_over_a = 4 * a / (a * a)
    az = rng.uniform(0.0, 90.0, int(trials)) if orientation == "random" else np.zeros(int(trials))
    el = np.full(int(trials), 90.0)
    mesh = canonical.plate(a)
    shifts = rng.uniform(0.0, 1.0, (int(trials), 2))
    engine = SbrEngine(load_target(mesh))
    engine.trace(Jobs.build(az[:1], el[:1], f, 1.0), max_bounces, exact_first_hits=False)  # compile once
    out = []
    for n in densities:
        start = time.perf_counter()
        res = engine.trace(Jobs.build(az, el, f, float(n), grid_shift=shifts), max_bounces, exact_first_hits=False)
        elapsed = time.perf_counter() - start
        sigma = res.sigma_m2[:, 0, 0, 0]
        err = np.abs(10 * np.log10(np.maximum(sigma, 1e-300) / exact))
        out.append(
            {
                "case": f"plate_0.1m_10GHz_normal_{orientation}",
                "rays_per_wavelength": float(n),
                "mean_abs_error_db": float(err.mean()),
                "max_abs_error_db": float(err.max()),
                "model_error_db": ERROR_COEFFICIENT_DB * p_over_a * lam / n,
                "tubes": float(res.tubes.mean()),
                "time_s": elapsed / len(az),
                "rays_x_bounces_per_s": res.ray_casts / elapsed,
            }
        )
    return out


def canonical_cases(frequency_ghz: float = 10.0) -> list[tuple]:
    """(name, mesh, azimuth_deg, elevation_deg, exact_m2) of the canonical oracles (docs/validation.md)."""
    lam = float(wavelength_m(frequency_ghz))
    k = 2 * math.pi / lam
    axis_el = math.degrees(math.asin(1 / math.sqrt(3)))
    ka = 50.0
    radius = ka / k
    x = 2 * ka
    po_sphere = math.pi * radius**2 * abs((np.exp(-1j * x) * (1 + 1j * x) - 1) / x) ** 2
    return [
        ("plate", canonical.plate(0.1), 0.0, 90.0, 4 * math.pi * 0.01**2 / lam**2),
        ("disk", canonical.disk(0.1), 0.0, 90.0, 4 * math.pi**3 * 0.1**4 / lam**2),
        ("dihedral", canonical.dihedral(0.1, 0.15), 0.0, 0.0, 8 * math.pi * 0.1**2 * 0.15**2 / lam**2),
        ("trihedral_square", canonical.trihedral(0.1, "square"), 45.0, axis_el, 12 * math.pi * 0.1**4 / lam**2),
        (
            "trihedral_triangular",
            canonical.trihedral(0.1, "triangular"),
            45.0,
            axis_el,
            4 * math.pi * 0.1**4 / (3 * lam**2),
        ),
        ("cylinder", canonical.cylinder(0.05, 0.3), 30.0, 0.0, 2 * math.pi * 0.05 * 0.3**2 / lam),
        ("sphere_ka50_po", canonical.sphere(radius, 6), 17.0, 23.0, po_sphere),
    ]


def preset_errors(presets=None, frequency_ghz: float = 10.0) -> dict:
    """Measured error of each quality preset on the canonical oracles, as :func:`compute_rcs` runs it.

    Parameters
    ----------
    presets : sequence of str, optional
        Names from :data:`csuas.render.rcs.solver.QUALITY_PRESETS` (default all).
    frequency_ghz : float
        Radar frequency [GHz].

    Returns
    -------
    dict
        Preset -> ``mean_abs_error_db``, ``max_abs_error_db``, ``time_s``, per-case ``cases[name]``
        (|error| of the VV/HH mean [dB]) and ``covered[name]`` (the error estimate bounds it).
    """
    from .solver import QUALITY_PRESETS, compute_rcs

    presets = list(QUALITY_PRESETS) if presets is None else list(presets)
    cases = canonical_cases(frequency_ghz)
    out = {}
    engines = {name: SbrEngine(load_target(mesh)) for name, mesh, *_ in cases}
    for preset in presets:
        if preset not in QUALITY_PRESETS:
            raise ParameterError("preset", preset, ", ".join(QUALITY_PRESETS))
        per_case, covered, elapsed = {}, {}, 0.0
        for name, _mesh, az, el, exact in cases:
            res = compute_rcs(engines[name], frequency_ghz, az, el, quality=preset)
            elapsed += res.time_s + res.error_time_s
            sigma = 0.5 * (res.sigma_m2[0, 0, 0, 0, 0] + res.sigma_m2[0, 0, 0, 1, 1])
            per_case[name] = float(abs(10 * np.log10(max(sigma, 1e-300) / exact)))
            covered[name] = bool(per_case[name] <= float(np.max(res.error_db[0, 0, 0, [0, 1], [0, 1]])))
        out[preset] = {
            "rays_per_wavelength": QUALITY_PRESETS[preset]["rays_per_wavelength"],
            "max_bounces": QUALITY_PRESETS[preset]["max_bounces"],
            "mean_abs_error_db": float(np.mean(list(per_case.values()))),
            "max_abs_error_db": float(max(per_case.values())),
            "time_s": elapsed,
            "cases": per_case,
            "covered": covered,
        }
    return out
