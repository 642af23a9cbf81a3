"""SBR-PO radar cross-section against its oracles, a full-wave solver, and the drone's RCS statistics.

Oracles (docs/validation.md, closed forms): PEC plate 4 pi A^2/lambda^2, disk,
dihedral 8 pi a^2 b^2/lambda^2, square trihedral 12 pi a^4/lambda^2,
triangular trihedral, cylinder 2 pi r L^2/lambda, sphere ka = 50 (physical
optics value), as listed by :func:`csuas.validation.rcs.convergence.canonical_cases`;
the exact faceted physical optics of PEC spheres (ka 3-50) and the NASA almond
(:mod:`csuas.render.rcs.facet_po`); the EFIE of bempp-cl for the sphere
(against Mie), plates with and without edge diffraction, a cylinder and a drone
arm with its motor (:mod:`csuas.validation.rcs.fullwave_checks`, ``--full``
only: numba compiles bempp-cl's kernels for 35 s); the bound's edge term on plates against the recorded
EFIE (:mod:`csuas.validation.rcs.edge_residual_cases`; one re-solved in ``--full``); the shipped drone RCS
statistics against 3GPP TR 38.901, published 24 GHz measurements and the measured rise of small
drones' mean RCS from 15 to 25 GHz (judged at the table's 16 and 24 GHz bands); each figure's bound
against the exact answer on Mie spheres (``rcs.bound``) and, ``--full`` only, on PEC cylinders and the
drone's arm with its motor against dated EFIE records (``rcs.bound_parts``,
:mod:`csuas.validation.rcs.part_references`).
Knob: rays per wavelength and bounces (the quality presets of
:data:`csuas.render.rcs.solver.QUALITY_PRESETS`).
"""

from __future__ import annotations

import numpy as np

from csuas.base.checks import Check
from csuas.base.fileio import atomic_path
from csuas.core.units import wavenumber_rad_m
from csuas.defaults import load_drone_rcs_statistics
from csuas.validation.report.figures import AccuracyColumns, from_writer
from csuas.validation.report.figures import accuracy_vs_time as plot_accuracy
from csuas.validation.report.registry import CheckGroup, CheckSpec, Section, timed

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
    from csuas.render.rcs.convergence import PRESET_MEASURED_ERROR_DB
    from csuas.render.rcs.solver import compute_rcs, to_dbsm
    from csuas.validation.rcs.convergence import canonical_cases

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
        "on the canonical set, one run of four replicated grids each (csuas.render.rcs.convergence)."
    )
    return s


def convergence(settings: dict) -> Section:
    """Error against rays per wavelength and time on the plate oracle (grid aligned: the worst case)."""
    from csuas.render.rcs.convergence import ERROR_COEFFICIENT_DB
    from csuas.render.rcs.solver import QUALITY_PRESETS
    from csuas.validation.rcs.convergence import convergence_curve

    s = Section()
    rows, elapsed = timed(convergence_curve, settings["densities"], trials=settings["trials"])
    s.figures.append(
        plot_accuracy(
            "rcs_accuracy_vs_time",
            "SBR-PO: mean |error| on the 0.1 m plate at 10 GHz vs time",
            rows,
            columns=AccuracyColumns(
                "rays_per_wavelength",
                "mean_abs_error_db",
                error_label="mean |error| [dB]",
                stderr_key="model_error_db",
                stderr_label="error model C P lambda / (A N)",
            ),
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


#: Target of the issue's PO accuracy: SBR-PO within this of exact PO on spheres ka 3-50 and the almond [dB].
PO_TOLERANCE_DB = 0.5
#: Sphere sizes and almond frequencies of :func:`po_oracle`.
PO_SPHERES_KA = (3.0, 5.0, 10.0, 20.0, 50.0)
PO_ALMOND = {"frequency_ghz": (1.19, 7.0, 9.92), "azimuth_deg": (0.0, 30.0, 90.0, 150.0, 180.0)}
#: Full-wave comparisons per report quality (None: not run, with a note). --full runs the sizes the tests
#: run (76 s on 2 CPU cores, 35 s of it numba compilation); fullwave_checks' larger ``full`` sizes are not
#: run by the report.
FULLWAVE = {"quick": None, "full": {"full": False}}
#: Published means at 24 GHz of Phantom 3, Bebop, Solo, Mavic Pro and Matrice 600 [dBsm]
#: (IEICE Communications Express 9(7), 2020), and 3GPP TR 38.901 v19 Table 7.9.2.1-1's small UAV.
MEASURED_24GHZ_DBSM = (-19.1, -8.1)
TR38901_SMALL_UAV = {"mean_dbsm": -12.81, "spread_db": 3.74}
#: The measured frequency trend of small drones' mean RCS from 15 to 25 GHz.
EZUMA_TREND_SOURCE = (
    "Ezuma, Funderburk & Guvenc, Compact-Range RCS Measurements and Modeling of Small Drones at 15 GHz and "
    "25 GHz, IEEE Radio and Wireless Symposium 2020 (arXiv 1911.05926): three small drones, 'for each drone, the "
    "RCS at 25 GHz is higher than the RCS at 15 GHz' (the same authors measured six UAVs at both bands in "
    "IEEE T-AES 58(1):27-46, 2022)"
)
#: Why a preset's 16 -> 24 GHz trend may differ from the measured drones' (filled where one remains).
TREND_LIMITATIONS: dict[str, str] = {}


def po_oracle(quality: str) -> Section:
    """SBR-PO against the exact faceted PO of PEC spheres (ka 3-50) and the NASA almond, VV and HH."""
    from csuas.render.rcs import canonical
    from csuas.render.rcs.facet_po import facet_po_sigma_m2
    from csuas.render.rcs.solver import compute_rcs
    from csuas.validation.rcs.fullwave_checks import mie_pec_over_pia2

    s = Section()
    cases = []
    k10 = float(wavenumber_rad_m(10.0))
    for ka in PO_SPHERES_KA:
        mesh = canonical.sphere(ka / k10, 6)
        cases.append((f"sphere_ka{ka:g}", mesh, 10.0, np.array([17.0, 200.0]), np.array([23.0, -41.0]), ka))
    almond = canonical.nasa_almond()
    for f in PO_ALMOND["frequency_ghz"]:
        az = np.asarray(PO_ALMOND["azimuth_deg"])
        cases.append((f"almond_{f:g}GHz", almond, f, az, np.zeros_like(az), None))
    for name, mesh, f, az, el, ka in cases:
        res, elapsed = timed(compute_rcs, mesh, f, az, el, material="pec", quality=quality)
        reference = facet_po_sigma_m2(mesh.vertices, mesh.faces, f, az, el)
        for i in range(len(az)):
            for pol, (rx, tx) in (("VV", (0, 0)), ("HH", (1, 1))):
                details = {"faces": len(mesh.faces), "tubes": res.tubes}
                if ka is not None:
                    details["mie_over_po_db"] = float(
                        10 * np.log10(mie_pec_over_pia2(ka) * np.pi * (ka / k10) ** 2 / reference[i])
                    )
                s.outcomes.append(
                    Check(
                        f"rcs.po_oracle.{name}.az{az[i]:g}_el{el[i]:g}.{pol}",
                        float(10 * np.log10(reference[i])),
                        float(res.rcs_dbsm(pol)[0, i, 0]),
                        PO_TOLERANCE_DB,
                        "dBsm",
                        error_estimate=float(res.error_db[0, i, 0, rx, tx]),
                        time_s=elapsed / (2 * len(az)),
                        source="exact faceted physical optics of the same mesh (csuas.render.rcs.facet_po)",
                        method=f"SBR-PO, PEC, {f:g} GHz, {quality}: {res.rays_per_wavelength:g} rays per wavelength "
                        f"x {res.replicas} replicas, exact first hits",
                        tolerance_source="target of the PO accuracy (0.5 dB at ka 3-50 and on the almond)",
                        details=details,
                    )
                )
    s.notes.append(
        "The sphere's PO differs from the exact (Mie) solution by up to 2 dB at ka = 3 (creeping waves): "
        "'mie_over_po_db' in each check's details."
    )
    return s


def fullwave(settings) -> Section:
    """EFIE (bempp-cl) against Mie, and SBR-PO (with and without PTD) against the EFIE; --full only."""
    if settings is None:
        return Section(notes=["Full-wave comparisons run in the --full report (35 s of numba compilation)."])
    from csuas.validation.rcs import fullwave_checks as fc

    s = Section()
    s.outcomes += fc.sphere_mie_checks(settings["full"])
    s.outcomes += fc.ptd_checks(settings["full"])
    for case in fc.SBR_CASES:
        s.outcomes += fc.sbr_checks(case, settings["full"])
    return s


def drone_statistics(_knob=None) -> Section:
    """The shipped drone RCS statistics (csuas rcs-statistics) against 3GPP and published 24 GHz means."""

    rows = load_drone_rcs_statistics()
    s = Section(table=[dict(r) for r in rows])
    lo, hi = MEASURED_24GHZ_DBSM
    for preset in sorted({r["preset"] for r in rows}):
        at24 = [r for r in rows if r["preset"] == preset and r["frequency_ghz"] == 24.0]
        mean = float(10 * np.log10(np.mean([10 ** (r["mean_dbsm"] / 10) for r in at24])))
        measured = Check(
            f"rcs.drone_statistics.{preset}.24GHz.mean_dbsm.measured_drones",
            0.5 * (lo + hi),
            mean,
            0.5 * (hi - lo),
            "dBsm",
            error_estimate=max(r["mean_error_db"] for r in at24),
            source="measured 24 GHz means of five quadcopters, -19.1 to -8.1 dBsm (IEICE ComEx 9(7), 2020)",
            method="Eq. 6 mean of VV and HH from defaults/drone_rcs_statistics.csv",
            tolerance_source="the published range",
        )
        if not measured.ok:
            measured.limitation = (
                f"{preset} is larger than the measured quadcopters (a 2 m airframe against Phantom 3 to Matrice "
                "600); no published measurement of it was found"
                if mean > hi
                else f"{preset} is smaller than the measured quadcopters (Phantom 3 to Matrice 600, 1.3-10 kg), and "
                "its radar model leaves out the small metal parts of a real airframe (screws, heat sinks, antennas); "
                "no published measurement of it was found"
            )
        lognormal = float(np.mean([r["lognormal_mean_dbsm"] for r in at24]))
        tr38901 = Check(
            f"rcs.drone_statistics.{preset}.24GHz.mean_of_dbsm.3gpp_tr38901",
            TR38901_SMALL_UAV["mean_dbsm"],
            lognormal,
            TR38901_SMALL_UAV["spread_db"],
            "dBsm",
            source="3GPP TR 38.901 v19 Table 7.9.2.1-1, small UAV (0.3 x 0.4 x 0.2 m): log-normal -12.81 dBsm, 3.74 dB",
            method="log-normal fit (mean of dBsm over uniform aspects), VV and HH averaged",
            tolerance_source="3GPP's spread",
            details={"lognormal_std_db": [r["lognormal_std_db"] for r in at24]},
        )
        if not tr38901.ok:
            tr38901.limitation = (
                "the mean of dBsm weighs the faceted model's deep nulls, which edge diffraction (PTD, off in the "
                "table's runs), creeping waves and surface roughness fill on real drones, and the small metal parts "
                "the model leaves out (screws, heat sinks, antennas) would raise; rotors, motors, battery, board and "
                "wiring are modelled; 3GPP fits measured metal-rich UAVs of 0.3 x 0.4 x 0.2 m"
            )
        s.outcomes += [measured, tr38901, _trend_16_to_24(preset, rows)]
    s.figures.append(
        from_writer(
            "rcs_drone_statistics",
            "Drone presets: Eq. 6 mean RCS and aspect percentiles vs frequency",
            lambda path: _plot_statistics(rows, path),
            caption="defaults/drone_rcs_statistics.csv (csuas rcs-statistics): Eq. 6 mean (VV) with its 95 % bound "
            "and the 10-90 % band over aspects; grey bar: published 24 GHz means of five quadcopters; dashed: "
            "3GPP TR 38.901's small UAV.",
        )
    )
    return s


def _band_mean(rows, preset: str, frequency_ghz: float) -> tuple[float, float]:
    """Eq. 6 mean of VV and HH [dBsm] of a preset's band and the larger of the two rows' 95 % bounds [dB]."""
    band = [r for r in rows if r["preset"] == preset and r["frequency_ghz"] == frequency_ghz]
    mean = float(10 * np.log10(np.mean([10 ** (r["mean_dbsm"] / 10) for r in band])))
    return mean, max(r["mean_error_db"] for r in band)


def _trend_16_to_24(preset: str, rows) -> Check:
    """The measured 15 -> 25 GHz rise of a drone's mean RCS, judged at the table's 16 and 24 GHz bands.

    Passes when the rise ``mean(24) - mean(16)`` is positive within the two means' 95 % bounds added in
    quadrature (a fall larger than that contradicts the measurements).
    """
    low, err_low = _band_mean(rows, preset, 16.0)
    high, err_high = _band_mean(rows, preset, 24.0)
    bound = float(np.hypot(err_low, err_high))
    check = Check(
        f"rcs.drone_statistics.{preset}.16_to_24GHz.mean_dbsm.rise",
        0.0,
        high - low,
        bound,
        "dB",
        error_estimate=bound,
        source=EZUMA_TREND_SOURCE,
        method="Eq. 6 mean of VV and HH at 24 GHz minus that at 16 GHz, defaults/drone_rcs_statistics.csv "
        "(the table's bands nearest 25 and 15 GHz)",
        tolerance_source="a rise: passes when the difference exceeds minus the two 95 % bounds in quadrature",
        details={"mean_16ghz_dbsm": low, "mean_24ghz_dbsm": high},
        ok_override=bool(high - low >= -bound),
    )
    if not check.ok:
        check.limitation = TREND_LIMITATIONS.get(preset, "no physical reason identified: a model error")
    return check


#: Spheres of the bound's coverage check per report quality (random ka in 2-50, one aspect each).
BOUND_SPHERES = {"quick": 16, "full": 96}


def bound_vs_exact(cases: int) -> Section:
    """Each SBR-PO figure of PEC spheres (ka 2-50, random aspects) against the Mie series, within its bound.

    One check per sphere and polarisation (tolerance: the figure's own bound against the exact answer,
    discretisation and PO's model error) and one for the coverage of the population, beside the
    coverage of the discretisation bound alone.
    """
    from csuas.validation.rcs.model_error import coverage_check, sphere_coverage

    s = Section()
    r = sphere_coverage(cases=cases, seed=26)
    n = len(r["error_db"])
    for i in range(n):
        bounded = bool(np.isfinite(r["bound_db"][i]))
        s.outcomes.append(
            Check(
                f"rcs.bound.sphere_ka{r['ka'][i]:.3g}.az{r['azimuth_deg'][i]:.0f}_el{r['elevation_deg'][i]:.0f}."
                f"{r['polarisation'][i]}",
                float(r["mie_dbsm"][i]),
                float(r["sbr_dbsm"][i]),
                float(r["bound_db"][i]),
                "dBsm",
                limitation=None
                if bounded
                else f"no bound at ka {r['ka'][i]:.3g}: PO's model error and floor reach the whole amplitude, so the "
                "figure claims none (error_db null), which is not a miss",
                error_estimate=float(r["bound_db"][i]),
                time_s=r["time_s"] / n,
                source="exact Mie series of the PEC sphere (radius 1 m)",
                method="SBR-PO, PEC, standard quality, icosphere of 81 920 faces",
                tolerance_source="the figure's bound against the exact answer (discretisation, PO's 1.5/(k a), floor)",
                details={"discretisation_db": float(r["discretisation_db"][i])},
            )
        )
    s.outcomes.append(
        coverage_check(
            "rcs.bound.sphere_coverage",
            r["coverage_total"],
            r["time_s"],
            f"Mie series; {n} entries (ka log-uniform in 2-50, random aspects, VV and HH)",
            "fraction of entries whose bound against the exact answer covers the error",
            {"coverage_discretisation_only": r["coverage_discretisation"]},
        )
    )
    s.notes.append(
        f"The discretisation bound alone (against PO) covers {r['coverage_discretisation']:.0%} of these entries; "
        f"with PO's model error, {r['coverage_total']:.0%}."
    )
    return s


#: Edge term of the bound per report quality: the recorded EFIE's test plates (quick), and the EFIE of one
#: calibration plate solved again (full).
EDGE_RESIDUAL = {"quick": {"full": False}, "full": {"full": True}}


def edge_residual(settings) -> Section:
    """SBR-PO + PTD of PEC plates (0-80 deg off normal, VV and HH) against the EFIE, within the bound's edge term."""
    from csuas.validation.rcs.edge_residual_cases import edge_residual_checks

    return Section(outcomes=edge_residual_checks(settings["full"]))


#: Parts of the bound's coverage (cylinders, the drone's arm with its motor) per report quality: the quick report
#: runs SBR-PO on every case against the recorded EFIE (about 3 s); --full also re-solves the calibration cases'
#: EFIE (561 s and 1222 s measured at load 10-14 on the 2 shared cores, a few minutes on idle ones).
BOUND_PARTS = {"quick": {"recalibrate": False}, "full": {"recalibrate": True}}


def _reproduced_references(names) -> list[Check]:
    """The calibration cases' EFIE re-solved against their dated records (fine mesh, dBsm)."""
    from csuas.validation.rcs import part_references as pr
    from csuas.validation.rcs.part_records import PART_RECORDS

    checks = []
    for name in names:
        (run, _), elapsed = timed(pr.efie_reference, name)
        record = PART_RECORDS[name]
        for pol in ("VV", "HH"):
            deviation = np.abs(np.asarray(run["efie_dbsm"][pol]) - np.asarray(record["efie_dbsm"][pol]))
            checks.append(
                Check(
                    f"rcs.bound_parts.{name}.{pol}.efie_reproduced",
                    0.0,
                    float(deviation.max()),
                    0.01,
                    "dB",
                    time_s=elapsed / 2.0,
                    source=f"dated EFIE record of {record['date']} (validation/rcs/part_records.py)",
                    method=f"EFIE (bempp-cl) re-solved, {run['elements'][0]} and {run['elements'][1]} triangles",
                    tolerance_source="0.01 dB: the records are rounded to 1e-4 dB, GMRES stops at a 1e-6 residual",
                    details={"aspects": len(deviation), "efie_s": run["efie_s"]},
                )
            )
    return checks


def bound_parts(settings) -> Section:
    """PO's bound on PEC cylinders and the drone's arm with its motor against the EFIE; --full only.

    The calibration cases' EFIE is re-solved against its records, PO's floor coefficient K is recalibrated
    on them, and every test entry (recorded EFIE reference, live SBR-PO) is judged within its own bound.
    """
    if settings is None:
        return Section(notes=["Cylinders and the drone's arm against the EFIE run in the --full report."])
    from csuas.render.rcs.model_error import PO_FLOOR_COEFFICIENT
    from csuas.validation.rcs import model_error as me

    s = Section()
    if settings["recalibrate"]:
        s.outcomes += _reproduced_references(me.PART_CALIBRATION)
    calibration = me.part_entries(me.PART_CALIBRATION)
    needed, at = me.calibrated_floor(calibration)
    s.outcomes.append(
        Check(
            "rcs.bound_parts.floor_coefficient",
            0.95 * PO_FLOOR_COEFFICIENT,
            needed,
            0.05 * PO_FLOOR_COEFFICIENT,
            "-",
            time_s=calibration["time_s"],
            source=f"the K that covers every calibration entry ({', '.join(me.PART_CALIBRATION)})",
            method=f"largest needed K, at {calibration['label'][at]}",
            tolerance_source=f"the calibrated K within [0.9, 1] x the shipped K = {PO_FLOOR_COEFFICIENT:g} "
            "(K is the calibrated value rounded up to two significant digits)",
        )
    )
    test = me.part_entries(me.PART_TEST)
    s.outcomes += _part_entry_checks(test)
    r = me.part_coverage(test)
    s.outcomes.append(
        me.coverage_check(
            "rcs.bound_parts.coverage",
            r["coverage_total"],
            test["time_s"],
            f"EFIE references of {', '.join(me.PART_TEST)} ({r['entries']} entries)",
            "fraction of entries whose bound against the exact answer covers SBR-PO's error",
            {k: v for k, v in r.items() if k != "entries"},
        )
    )
    s.notes.append(
        f"Test parts: the bound covers {r['coverage_total']:.0%} of {r['entries']} entries "
        f"({r['finite_fraction']:.0%} finite, median {r['median_bound_db']:.1f} dB); without PO's floor it covered "
        f"{r['coverage_without_floor']:.0%}."
    )
    return s


def _part_entry_checks(entries) -> list[Check]:
    """One check per judged entry with a finite bound: SBR-PO against the EFIE reference within the figure's bound."""
    from csuas.validation.rcs.model_error import BOUND_COVERAGE

    checks = []
    n = len(entries["error_db"])
    for i in np.flatnonzero(np.isfinite(entries["bound_db"]) & entries["judged"]):
        expected, measured = float(entries["reference_dbsm"][i]), float(10.0 * np.log10(entries["sigma_m2"][i]))
        missed = abs(measured - expected) > float(entries["bound_db"][i])
        checks.append(
            Check(
                f"rcs.bound_parts.{entries['label'][i]}",
                expected,
                measured,
                float(entries["bound_db"][i]),
                "dBsm",
                limitation=f"one of the {1.0 - BOUND_COVERAGE:.0%} of figures a bound of {BOUND_COVERAGE:.0%} "
                "coverage may miss (judged by rcs.bound_parts.coverage)"
                if missed
                else None,
                error_estimate=float(entries["bound_db"][i]),
                time_s=entries["time_s"] / n,
                source="EFIE (bempp-cl), Richardson-extrapolated, dated record (validation/rcs/part_records.py)",
                method="SBR-PO, PEC, standard quality, on the EFIE's fine mesh",
                tolerance_source="the figure's bound: discretisation + PO's 1.5/(k a) + its floor + truncation",
                details={
                    "reference_error_db": float(entries["reference_error_db"][i]),
                    "floor_db": float(entries["floor_db"][i]),
                },
            )
        )
    return checks


def _plot_statistics(rows, path):
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for i, preset in enumerate(sorted({r["preset"] for r in rows})):
        vv = sorted(
            (r for r in rows if r["preset"] == preset and r["polarisation"] == "VV"), key=lambda r: r["frequency_ghz"]
        )
        f = np.array([r["frequency_ghz"] for r in vv])
        color = f"C{i}"
        ax.errorbar(
            f,
            [r["mean_dbsm"] for r in vv],
            yerr=[r["mean_error_db"] for r in vv],
            color=color,
            marker="o",
            capsize=3,
            label=f"{preset} mean (VV)",
        )
        ax.fill_between(f, [r["p10_dbsm"] for r in vv], [r["p90_dbsm"] for r in vv], color=color, alpha=0.15)
    lo, hi = MEASURED_24GHZ_DBSM
    ax.vlines(24.0, lo, hi, color="0.4", lw=6, alpha=0.5, label="measured quadcopters, 24 GHz")
    ax.axhline(TR38901_SMALL_UAV["mean_dbsm"], color="k", ls="--", lw=1, label="3GPP TR 38.901 small UAV")
    ax.set_xscale("log")
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.set_xticks([2.4, 5.8, 9.4, 16, 24, 35], ["2.4", "5.8", "9.4", "16", "24", "35"])
    ax.set_xlabel("frequency [GHz]")
    ax.set_ylabel("RCS [dBsm]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, bbox_inches="tight", format="png")
    plt.close(fig)
    return path


#: The report section of these checks.
GROUP = CheckGroup(
    "rcs",
    "Radar cross-section (SBR-PO) vs oracles",
    50,
    "SBR-PO radar cross-sections against closed forms of canonical shapes, a full-wave solver and the "
    "drone's RCS statistics.",
)


SPECS = [
    CheckSpec(
        "rcs.canonical",
        "SBR-PO vs canonical RCS oracles",
        GROUP,
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
        GROUP,
        "measured mean error on the plate vs the documented error model",
        "the measured mean error within a factor 2 of the model's rule (0 to 2x)",
        convergence,
        "rays per wavelength swept, grid placements",
        CONVERGENCE,
        True,
    ),
    CheckSpec(
        "rcs.po_oracle",
        "SBR-PO vs exact faceted PO: spheres ka 3-50 and the NASA almond",
        GROUP,
        "SBR-PO (exact first hits, replicated tube grids) vs the float64 faceted-PO integral of the same mesh",
        f"{PO_TOLERANCE_DB:g} dB, the accuracy target at ka 3-50",
        po_oracle,
        "SBR quality preset (rays per wavelength, bounces)",
        QUALITY,
        True,
    ),
    CheckSpec(
        "rcs.fullwave",
        "Full-wave (EFIE) oracle: sphere vs Mie; SBR-PO with and without edge diffraction vs EFIE",
        GROUP,
        "bempp-cl EFIE vs the Mie series; SBR-PO(+PTD) vs the EFIE on plates, a cylinder and a drone arm",
        "Richardson's estimate (sphere); the PO error (PTD must improve on it); 20 log10(1 + 1/(k l)) (specular)",
        fullwave,
        "case sizes",
        FULLWAVE,
        True,
    ),
    CheckSpec(
        "rcs.drone_statistics",
        "Drone RCS statistics vs 3GPP TR 38.901 and measured drones",
        GROUP,
        "the shipped table (csuas rcs-statistics) vs 3GPP's small-UAV log-normal, published 24 GHz means and the "
        "measured 15 -> 25 GHz rise",
        "the published range; 3GPP's spread; a rise within the two means' 95 % bounds",
        drone_statistics,
        None,
        {},
        False,
    ),
    CheckSpec(
        "rcs.bound",
        "Bounds against the exact answer: SBR-PO spheres vs Mie",
        GROUP,
        "SBR-PO of PEC spheres at random ka 2-50 and aspects vs the Mie series, within each figure's bound",
        "each figure's bound (discretisation + PO's model error); 95 % coverage of the population",
        bound_vs_exact,
        "spheres",
        BOUND_SPHERES,
        True,
    ),
    CheckSpec(
        "rcs.edge_residual",
        "Bounds against the exact answer: SBR-PO + PTD plates vs the EFIE",
        GROUP,
        "SBR-PO + PTD of PEC plates 1-3 wavelengths, 0-80 deg off normal, vs the bempp-cl EFIE (recorded; one "
        "re-solved in --full), within each figure's bound with the edge term",
        "95 % coverage of the test plates per polarisation; the record within 0.01 dB",
        edge_residual,
        "EFIE re-solved",
        EDGE_RESIDUAL,
        True,
    ),
    CheckSpec(
        "rcs.bound_parts",
        "Bounds against the exact answer: PEC cylinders and the drone's arm with its motor vs the EFIE",
        GROUP,
        "SBR-PO of finite PEC cylinders and the DJI Mini 4 Pro's arm with its motor (2.4-10 GHz) vs recorded EFIE "
        "references, within each figure's bound; the floor recalibrated on re-solved calibration cases",
        "each figure's bound; 95 % coverage of the test population; records reproduced within 0.01 dB",
        bound_parts,
        "recalibration",
        BOUND_PARTS,
        True,
    ),
    CheckSpec(
        "rcs.drone_polar",
        "Drone RCS polar cuts",
        GROUP,
        "plot only (the Eq. 6 mean is checked in defaults.rcs)",
        "none",
        drone_polar,
        "SBR quality, azimuth step",
        POLAR,
        True,
    ),
]
