"""SBR-PO radar cross-section against its canonical oracles, convergence, and the drone's RCS patterns.

Oracles (docs/validation.md, closed forms): PEC plate 4 pi A^2/lambda^2, disk,
dihedral 8 pi a^2 b^2/lambda^2, square trihedral 12 pi a^4/lambda^2,
triangular trihedral, cylinder 2 pi r L^2/lambda, sphere ka = 50 (physical
optics value), as listed by :func:`csuas.render.rcs.convergence.canonical_cases`.
Knob: rays per wavelength and bounces (the quality presets of
:data:`csuas.render.rcs.solver.QUALITY_PRESETS`).
"""

from __future__ import annotations

import numpy as np

from csuas.base.checks import Check
from csuas.validation.report.figures import accuracy_vs_time as plot_accuracy
from csuas.validation.report.figures import from_writer
from csuas.validation.report.registry import CheckSpec, Section, timed

#: SBR quality preset per report quality.
QUALITY = {"quick": "draft", "full": "standard"}
#: Convergence sweep (rays per wavelength, random grid placements) per report quality.
CONVERGENCE = {
    "quick": {"densities": (1, 2, 4, 8), "trials": 8},
    "full": {"densities": (1, 2, 4, 8, 16, 32), "trials": 64},
}
#: Drone polar cut (quality, azimuth step [deg]) per report quality.
POLAR = {"quick": {"quality": "draft", "step_deg": 2.0}, "full": {"quality": "standard", "step_deg": 0.5}}
#: Margin over the preset's largest measured error on the canonical set (one grid placement here).
MARGIN = 1.5


def canonical(quality: str) -> Section:
    """Each canonical target at its oracle aspect, 10 GHz, mean of VV and HH."""
    from csuas.render.rcs.convergence import PRESET_MEASURED_ERROR_DB, canonical_cases
    from csuas.render.rcs.solver import compute_rcs, to_dbsm

    s = Section()
    tolerance = MARGIN * PRESET_MEASURED_ERROR_DB[quality]["max"]
    for name, mesh, az, el, exact in canonical_cases(10.0):
        res, elapsed = timed(compute_rcs, mesh, 10.0, az, el, material="pec", quality=quality)
        sigma = 0.5 * (res.rcs_m2("VV") + res.rcs_m2("HH")).ravel()[0]
        err = max(float(res.error_estimate_db("VV").ravel()[0]), float(res.error_estimate_db("HH").ravel()[0]))
        s.outcomes.append(
            Check(
                f"rcs.canonical.{name}.dbsm",
                float(to_dbsm(exact)),
                float(to_dbsm(sigma)),
                tolerance,
                "dBsm",
                error_estimate=err,
                time_s=elapsed,
                source="closed form (docs/validation.md)",
                method=f"SBR-PO, PEC, 10 GHz, az {az:g} el {el:.3f} deg, {quality}: "
                f"{res.rays_per_wavelength:g} rays per wavelength, {res.max_bounces} bounces, {res.tubes} tubes",
                details={"exact_m2": exact, "sigma_m2": float(sigma)},
            )
        )
    s.notes.append(
        f"Tolerance {tolerance:.2f} dB = {MARGIN:g} x the largest error of preset '{quality}' measured "
        "over 4 grid placements of the canonical set (csuas.render.rcs.convergence)."
    )
    return s


def convergence(settings: dict) -> Section:
    """Error against rays per wavelength and time on the plate oracle (grid aligned: the worst case)."""
    from csuas.render.rcs.convergence import ERROR_COEFFICIENT_DB, convergence_curve
    from csuas.render.rcs.solver import QUALITY_PRESETS

    s = Section()
    rows, elapsed = timed(convergence_curve, settings["densities"], trials=settings["trials"])
    s.figures.append(
        plot_accuracy(
            "rcs_accuracy_vs_time",
            "SBR-PO: mean |error| on the 0.1 m plate at 10 GHz vs time",
            rows,
            knob="rays_per_wavelength",
            error_key="mean_abs_error_db",
            error_label="mean |error| [dB]",
            stderr_key="model_error_db",
            stderr_label="error model C P lambda / (A N)",
            caption=f"{settings['trials']} random grid placements per density; labels: rays per wavelength.",
            presets={name: q["rays_per_wavelength"] for name, q in QUALITY_PRESETS.items()},
        )
    )
    for r in rows:
        # the error model (1) of convergence.py: the measured mean within a factor 2 of the rule
        s.outcomes.append(
            Check(
                f"rcs.convergence.plate.N{r['rays_per_wavelength']:g}.mean_abs_error_db",
                r["model_error_db"],
                r["mean_abs_error_db"],
                r["model_error_db"],
                "dB",
                time_s=r["time_s"] * settings["trials"],
                source=f"error model C P lambda/(A N), C = {ERROR_COEFFICIENT_DB} dB (csuas.render.rcs.convergence)",
                method="mean |error| of the plate against 4 pi A^2/lambda^2 over random grid placements",
                details={"max_abs_error_db": r["max_abs_error_db"], "tubes": r["tubes"]},
            )
        )
    s.table = rows
    s.notes.append(f"convergence sweep {elapsed:.1f} s")
    return s


def drone_polar(settings: dict) -> Section:
    """Azimuth cut of the drone's RCS at the default radar wavelength (1.25 cm) and 2.4 GHz, VV and HH."""
    from csuas.render.rcs.solver import get_engine
    from csuas.render.rcs.sweep import aspect_sweep, plot_polar

    s = Section()
    engine = get_engine("dji_mini_4_pro")
    az = np.arange(0.0, 360.0, settings["step_deg"])
    curves_db = {}
    total = 0.0
    for f in (2.4, 23.98):
        cut, elapsed = timed(aspect_sweep, engine, f, az, 0.0, quality=settings["quality"], error_estimate=False)
        total += elapsed
        for pol in ("VV", "HH"):
            curves_db[f"{f:g} GHz {pol}"] = cut["rcs_dbsm"][pol][0]
        lin = 0.5 * (cut["rcs_m2"]["VV"][0] + cut["rcs_m2"]["HH"][0])
        s.table.append(
            {
                "frequency_ghz": f,
                "azimuth_mean_dbsm": float(10 * np.log10(lin.mean())),
                "max_dbsm": float(10 * np.log10(lin.max())),
                "min_dbsm": float(10 * np.log10(lin.min())),
                "time_s": elapsed,
            }
        )
    s.figures.append(
        from_writer(
            "rcs_polar_drone",
            "DJI Mini 4 Pro RCS vs azimuth, elevation 0",
            lambda path: plot_polar(az, curves_db, path, title="DJI Mini 4 Pro model, RCS [dBsm] vs azimuth"),
            caption=f"SBR-PO, part materials, quality {settings['quality']}, step {settings['step_deg']:g} deg "
            f"({total:.1f} s).",
        )
    )
    return s


SPECS = [
    CheckSpec(
        "rcs.canonical",
        "SBR-PO vs canonical RCS oracles",
        "rcs",
        "closed-form RCS (plate, disk, dihedral, trihedrals, cylinder, PO sphere) vs SBR-PO",
        f"{MARGIN:g} x the preset's largest measured error on this set",
        canonical,
        "SBR quality preset (rays per wavelength, bounces)",
        QUALITY,
        True,
    ),
    CheckSpec(
        "rcs.convergence",
        "SBR-PO accuracy vs rays per wavelength and time",
        "rcs",
        "measured mean error on the plate vs the documented error model",
        "the measured mean error within a factor 2 of the model's rule (0 to 2x)",
        convergence,
        "rays per wavelength swept, grid placements",
        CONVERGENCE,
        True,
    ),
    CheckSpec(
        "rcs.drone_polar",
        "Drone RCS polar cuts",
        "rcs",
        "plot only (the Eq. 6 mean is checked in defaults.rcs)",
        "none",
        drone_polar,
        "SBR quality, azimuth step",
        POLAR,
        True,
    ),
]
