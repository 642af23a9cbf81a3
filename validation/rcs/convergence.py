"""Accuracy against cost of the SBR-PO engine, measured on closed-form oracles (docs/validation.md).

:func:`convergence_curve` measures the error of the tube grid alone against its density on the
square-plate oracle (the data behind the error model (1) of :mod:`csuas.render.rcs.convergence`
and its fitted coefficient :data:`~csuas.render.rcs.convergence.ERROR_COEFFICIENT_DB`);
:func:`preset_errors` measures each quality preset of :func:`~csuas.render.rcs.solver.compute_rcs`
on the canonical oracles of :func:`canonical_cases` (the figures recorded in
:data:`~csuas.render.rcs.convergence.PRESET_MEASURED_ERROR_DB`). The closed forms of the oracles
are listed in docs/validation.md.
"""

from __future__ import annotations

import math
import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.units import wavelength_m, wavenumber_rad_m
from csuas.render.rcs import canonical
from csuas.render.rcs.convergence import ERROR_COEFFICIENT_DB
from csuas.render.rcs.engine import Jobs, SbrEngine
from csuas.render.rcs.geometry import load_target
from csuas.render.rcs.solver import QUALITY_PRESETS, compute_rcs


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
    k = float(wavenumber_rad_m(frequency_ghz))
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
