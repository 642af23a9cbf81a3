"""Probability of detection: the exact detectors against published values and Monte Carlo, and the
drone's own RCS fluctuation against the Swerling models (docs/detection.md).

* ``detection.published``: Richards' Albersheim example (13.1 dB), the steady and Swerling 1
  single-pulse requirements of Meyer & Mayer / DiFranco & Rubin (13.2 and 21.1 dB at Pd 0.9,
  Pfa 1e-6), the Swerling 1 closed form, and the TTPF against every column of Table 21.
* ``detection.monte_carlo``: a simulated detector (validation.detection.monte_carlo) against
  core.radar_detection for every Swerling case and both integrations. Knob: dwells simulated.
* ``detection.drone_fluctuation``: the SBR-PO RCS of the default drone over random aspects per
  band, its log-normal and chi-square fits, and Pd against range from that distribution beside
  Swerling 1 with the same mean; the exact average over the samples is checked against a detector
  simulation drawing the same samples. Knob: aspects and bands.
"""

from __future__ import annotations

import math

import numpy as np

from csuas.base.checks import Check
from csuas.core.detection import ttpf_cycles_ratio
from csuas.core.radar_detection import albersheim_snr_db, pd_exact, required_snr_db
from csuas.core.rcs_statistics import fit_chi_square, fit_lognormal, pd_over_rcs_samples, rcs_summary
from csuas.validation.report.figures import PlotAxes, curves
from csuas.validation.report.registry import CheckGroup, CheckSpec, Section, timed

N_SIGMA = 3.0
TRIALS = {"quick": 20_000, "full": 200_000}
FLUCTUATION = {
    "quick": {"bands_ghz": (9.4, 24.0), "aspects": 256},
    "full": {"bands_ghz": (2.4, 5.8, 9.4, 16.0, 24.0, 35.0), "aspects": 1024},
}
PRESET = "dji_mini_4_pro"
#: Table 21 of the paper: (P_desired, n_TTPF) with 0 < P < 1 (P = 1 needs infinitely many cycles).
TABLE_21 = ((0.95, 2.00), (0.80, 1.50), (0.50, 1.00), (0.30, 0.75), (0.10, 0.50), (0.02, 0.25))


def published(_knob=None) -> Section:
    """Printed requirements and closed forms against the exact detectors; the TTPF against Table 21."""

    s = Section()
    for name, swerling, printed, source in (
        ("steady", 0, 13.2, "Meyer & Mayer (1973), DiFranco & Rubin (1968): Pd 0.9, Pfa 1e-6, N 1"),
        ("swerling_1", 1, 21.1, "Meyer & Mayer (1973): Pd 0.9, Pfa 1e-6, N 1"),
    ):
        value, elapsed = timed(required_snr_db, 0.9, 1e-6, 1, swerling)
        s.outcomes.append(
            Check(
                f"detection.required_snr.{name}",
                printed,
                float(value),
                0.05,
                "dB",
                time_s=elapsed,
                tolerance_source="half a unit of the printed 0.1 dB",
                source=source,
                method="core.radar_detection.required_snr_db (exact inverse)",
            )
        )
    value, elapsed = timed(albersheim_snr_db, 0.9, 1e-6, 1)
    s.outcomes.append(
        Check(
            "detection.albersheim.richards_example",
            13.1,
            float(value),
            0.05,
            "dB",
            time_s=elapsed,
            tolerance_source="half a unit of the printed 0.1 dB",
            source="Richards, Fundamentals of Radar Signal Processing (2014), Albersheim's example",
            method="core.radar_detection.albersheim_snr_db",
        )
    )
    for snr_db in (0.0, 10.0, 20.0):
        closed = 1e-6 ** (1 / (1 + 10 ** (snr_db / 10)))
        value, elapsed = timed(pd_exact, snr_db, 1e-6, 1, 1)
        s.outcomes.append(
            Check(
                f"detection.swerling_1_closed_form.{snr_db:g}dB",
                closed,
                float(value),
                1e-12,
                "-",
                time_s=elapsed,
                source="Swerling 1, one pulse: Pd = Pfa^(1 / (1 + SNR))",
                method="core.radar_detection.pd_exact",
            )
        )
    for p, n_ttpf in TABLE_21:
        value, elapsed = timed(ttpf_cycles_ratio, p)
        s.outcomes.append(
            Check(
                f"detection.ttpf.table_21.p_{p:g}",
                n_ttpf,
                float(value),
                0.04 * n_ttpf,
                "-",
                time_s=elapsed,
                tolerance_source="the Johnson-era TTPF gives Table 21's multipliers within 3.7 % (docs/detection.md)",
                source="Table 21 (n_TTPF for P_desired)",
                method="x solving x^E / (1 + x^E) = P, E = 2.7 + 0.7 x (core.detection.ttpf_cycles_ratio)",
            )
        )
    return s


def monte_carlo(trials: int) -> Section:
    """Simulated detectors against the exact Pd: Swerling 0-4, noncoherent and coherent, N 1 and 8."""
    from csuas.validation.detection.monte_carlo import simulate_detector

    s = Section()
    rng = np.random.default_rng(2024)
    rows = []
    for integration in ("noncoherent", "coherent"):
        for swerling in range(5):
            for n in (1, 8):
                if integration == "coherent" and swerling == 4 and n > 1:
                    continue  # independent chi-square-4 phasors summed: no closed form (docs/detection.md)
                no_gain = n == 1 or (integration == "coherent" and swerling == 2)  # decorrelated echoes add in power
                snr_db = 8.0 if no_gain else 0.0
                exact = float(pd_exact(snr_db, 1e-4, n, swerling, integration))
                (simulated, stderr), elapsed = timed(
                    simulate_detector, snr_db, 1e-4, n, swerling, integration, trials, rng
                )
                rows.append({"integration": integration, "swerling": swerling, "n_pulses": n, "snr_db": snr_db,
                             "exact_pd": exact, "simulated_pd": simulated, "stderr": stderr})  # fmt: skip
                s.outcomes.append(
                    Check(
                        f"detection.monte_carlo.{integration}.swerling_{swerling}.n_{n}",
                        exact,
                        simulated,
                        N_SIGMA * stderr,
                        "-",
                        error_estimate=stderr,
                        time_s=elapsed,
                        tolerance_source=f"{N_SIGMA:g} binomial standard errors of {trials} simulated dwells",
                        source="core.radar_detection.pd_exact (closed forms)",
                        method=f"complex Gaussian noise + sampled RCS, square-law detector, Pfa 1e-4, {trials} dwells",
                    )
                )
    s.table = rows
    return s


def drone_fluctuation(settings: dict) -> Section:
    """The drone's RCS over random aspects per band: fits, nearest Swerling case, Pd against range."""
    from csuas.validation.detection.fluctuation import drone_rcs_samples
    from csuas.validation.detection.monte_carlo import simulate_over_rcs_samples

    s = Section()
    bands = settings["bands_ghz"]
    samples, elapsed = timed(drone_rcs_samples, PRESET, bands, settings["aspects"], seed=7)
    rng = np.random.default_rng(99)
    snr_at_mean = np.linspace(-5.0, 35.0, 81)  # relative range: R / R_ref = 10^(-(SNR - SNR_ref) / 40)
    lines = []
    for i, band in enumerate(bands):
        vv = samples["VV"][i]
        vv = vv[vv > 0]
        summary, lognormal, chi = rcs_summary(vv), fit_lognormal(vv), fit_chi_square(vv)
        s.table.append(
            {
                "band_ghz": band,
                "aspects": summary["n"],
                "mean_dbsm": round(float(summary["mean_dbsm"]), 2),
                "median_dbsm": round(summary["median_dbsm"], 2),
                "p10_dbsm": round(summary["p10_dbsm"], 2),
                "p90_dbsm": round(summary["p90_dbsm"], 2),
                "lognormal_mean_dbsm": round(lognormal["mean_dbsm"], 2),
                "lognormal_std_db": round(lognormal["std_db"], 2),
                "chi_square_dof": round(chi["dof"], 2),
                "nearest_swerling": chi["nearest_swerling_scan"],
            }
        )
        pd_drone = pd_over_rcs_samples(snr_at_mean, vv, 1e-6, 10)
        if i == len(bands) - 1:
            lines += [
                (f"drone aspects, {band:g} GHz VV", snr_at_mean, pd_drone),
                ("Swerling 1, same mean", snr_at_mean, pd_exact(snr_at_mean, 1e-6, 10, 1)),
                ("Swerling 3, same mean", snr_at_mean, pd_exact(snr_at_mean, 1e-6, 10, 3)),
                ("steady, same mean", snr_at_mean, pd_exact(snr_at_mean, 1e-6, 10, 0)),
            ]
        snr_check = 15.0
        exact = float(pd_over_rcs_samples(snr_check, vv, 1e-6, 10))
        (simulated, stderr), mc_time = timed(simulate_over_rcs_samples, snr_check, vv, 1e-6, 10, 20_000, rng)
        s.outcomes.append(
            Check(
                f"detection.drone_fluctuation.{band:g}GHz.pd_at_15dB",
                exact,
                simulated,
                N_SIGMA * stderr,
                "-",
                error_estimate=stderr,
                time_s=elapsed / len(bands) + mc_time,
                tolerance_source=f"{N_SIGMA:g} binomial standard errors of 20000 simulated dwells",
                source="exact average of the steady Pd over the drone's RCS samples (core.rcs_statistics)",
                method=f"{summary['n']} SBR-PO aspects of {PRESET} at {band:g} GHz VV, detector simulated with "
                "those samples, 10 pulses noncoherent, Pfa 1e-6",
                details={"chi_square_dof": chi["dof"], "lognormal_std_db": lognormal["std_db"]},
            )
        )
    s.figures.append(
        curves(
            "pd_drone_fluctuation",
            "Pd of the drone's own aspect distribution vs the Swerling models (10 pulses, Pfa 1e-6)",
            axes=PlotAxes("mean single-pulse SNR [dB] (40 dB = a tenth of the range)", "probability of detection"),
            lines=lines,
            caption=f"SBR-PO at {samples['tubes']:,} tubes over {settings['aspects']} random aspects in "
            f"{samples['time_s']:.1f} s; the drone's chi-square degrees of freedom per band are in the table.",
        )
    )
    k_values = ", ".join(f"{row['band_ghz']:g} GHz: 2k = {row['chi_square_dof']:g}" for row in s.table)
    s.notes.append(
        f"The drone's RCS over aspects fluctuates like a chi-square with {k_values} degrees of freedom "
        "(Swerling 1 has 2, Swerling 3 has 4); below 2 the tail is heavier than Swerling 1's and the drone "
        f"needs more SNR for a high Pd. Sampling error of a fitted k: about k sqrt(2 / n) with n = "
        f"{settings['aspects']} aspects ({math.sqrt(2 / settings['aspects']):.0%})."
    )
    return s


#: The report section of these checks.
GROUP = CheckGroup(
    "detection",
    "Probability of detection: exact detectors, Monte Carlo and the drone's own fluctuation",
    80,
    "The exact detectors against published values and Monte Carlo, and the drone's simulated RCS "
    "fluctuation against the Swerling models.",
)


SPECS = [
    CheckSpec(
        "detection.published",
        "Radar detection requirements and the TTPF against published values",
        GROUP,
        "Meyer & Mayer, Richards' Albersheim example, Swerling 1 closed form, Table 21 vs csuas",
        "half a unit of the printed digit; 1e-12 for closed forms; 4 % of Table 21's multipliers",
        published,
    ),
    CheckSpec(
        "detection.monte_carlo",
        "Exact Pd of Swerling 0-4 detectors vs Monte Carlo",
        GROUP,
        "simulated square-law detector (noise + sampled RCS) vs core.radar_detection.pd_exact",
        f"{N_SIGMA:g} binomial standard errors",
        monte_carlo,
        "simulated dwells",
        TRIALS,
    ),
    CheckSpec(
        "detection.drone_fluctuation",
        "The drone's own RCS fluctuation and its Pd",
        GROUP,
        "SBR-PO RCS over random aspects: log-normal and chi-square fits; Pd from the samples vs a detector simulation",
        f"{N_SIGMA:g} binomial standard errors",
        drone_fluctuation,
        "bands and aspects",
        FLUCTUATION,
        True,
    ),
]
