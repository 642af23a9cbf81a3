"""``csuas defaults check``: every default the paper derives from other values, recomputed.

Each check compares a value printed in the paper with csuas' independent
computation (ITU-R recommendations, Koschmieder, Kruse, Table 31, the paper's
own equations). Tolerances are half a unit of the last printed digit, except
where the paper computed from rounded or interpolated inputs: ITU values within
1 % (rain; the paper interpolated P.838-3's tables) or 0.5 % (fog), and values
the paper truncated within one unit of the last digit. A disagreement the paper
explains (or that we can explain) carries a ``known_deviation`` text instead of
being hidden.
"""

from __future__ import annotations

import numpy as np

from csuas.base.checks import Check
from csuas.base.registry import resolve
from csuas.core import acoustic, atmosphere, itu, radar, tir
from csuas.defaults import default_values, load_tables

#: Relative tolerance of ITU rain values: the paper interpolated P.838-3's tabulated coefficients.
RAIN_REL_TOL = 0.01
#: Relative tolerance of ITU fog values (interpolated K_l).
FOG_REL_TOL = 0.005
#: Check providers computed from simulations, name -> "module:function" (csuas.base.registry), wired here
#: only: ``csuas defaults check`` runs them all, the report's ``defaults.<name>`` runs each with its knob.
#: drone: d_crit, emissivity and LCS by Eq. 9 of the meshes (Tables 8, 27, 52); rcs: SBR-PO mean RCS vs
#: Table 8 and 3GPP TR 38.901; lidar: ray-traced LCS vs Table 8 and k_LCS.
SIMULATION_PROVIDERS = {
    "drone": "csuas.validation.drone.checks:default_checks",
    "rcs": "csuas.validation.rcs.checks:default_checks",
    "lidar": "csuas.validation.lidar.checks:default_checks",
}


def _printed_tol(value: float, digits: int = 3) -> float:
    """Half a unit of the last of ``digits`` significant digits of ``value``."""
    if value == 0:
        return 0.0
    exponent = np.floor(np.log10(abs(value))) - (digits - 1)
    return 0.5 * 10.0**exponent


def itu_checks() -> list[Check]:
    """Tables 35-37 and 42-44: ITU-R P.838-3 rain and P.840 fog coefficients and attenuations."""
    printed = load_tables()["printed"]
    rain, fog = printed["itu838"], printed["itu840"]
    checks = []
    for i, f in enumerate(rain["frequency_ghz"]):
        k, alpha = itu.rain_coefficients(f)
        note = None
        if f == 5.8:
            note = (
                "the paper interpolated P.838-3's tabulated values linearly; the recommendation's "
                "closed-form fit gives k = 4.006e-4, alpha = 1.585 at 5.8 GHz"
            )
        checks.append(
            Check.of_paper(
                f"T35/T42.k.{f:g}GHz",
                rain["k"][i],
                float(k),
                "-",
                "Tables 35, 42",
                "ITU-R P.838-3, vertical polarisation, horizontal path",
                rel_tol=RAIN_REL_TOL,
                known_deviation=note,
            )
        )
        checks.append(
            Check.of_paper(
                f"T35/T42.alpha.{f:g}GHz",
                rain["alpha"][i],
                float(alpha),
                "-",
                "Tables 35, 42",
                "ITU-R P.838-3, vertical polarisation, horizontal path",
                rel_tol=RAIN_REL_TOL,
                known_deviation=note,
            )
        )
        for j, r in enumerate(rain["rain_rate_mm_h"]):
            gamma = float(itu.rain_specific_attenuation_db_km(f, r))
            checks.append(
                Check.of_paper(
                    f"T35/T42.gamma_rain.{f:g}GHz.{r:g}mm_h",
                    rain["gamma_db_km"][i][j],
                    gamma,
                    "dB/km",
                    "Tables 35, 42",
                    "Eq. 58 with ITU-R P.838-3 k, alpha",
                    rel_tol=RAIN_REL_TOL,
                    known_deviation=note,
                )
            )
    for i, f in enumerate(fog["frequency_ghz"]):
        k_l = float(itu.fog_coefficient_kl(f, 293.15))
        checks.append(
            Check.of_paper(
                f"T36/T43.K_l.{f:g}GHz",
                fog["k_l"][i],
                k_l,
                "(dB/km)/(g/m^3)",
                "Tables 36, 43",
                "ITU-R P.840 double-Debye water permittivity at 293.15 K",
                rel_tol=FOG_REL_TOL,
            )
        )
        for j, lwc in enumerate(fog["lwc_g_m3"]):
            gamma = float(itu.fog_specific_attenuation_db_km(f, lwc, 293.15))
            checks.append(
                Check.of_paper(
                    f"T36/T43.gamma_fog.{f:g}GHz.{lwc:g}g_m3",
                    fog["gamma_db_km"][i][j],
                    gamma,
                    "dB/km",
                    "Tables 36, 43",
                    "Eq. 60 with ITU-R P.840 K_l",
                    rel_tol=FOG_REL_TOL,
                )
            )
    return checks


def environment_checks() -> list[Check]:
    """Table 16 fog extinction (Eq. 12) and Table 47 lidar transmission (Kruse, Eq. 10)."""
    misc = load_tables()["printed"]["misc"]
    visibilities = load_tables()["classes"]["fog_visibility_m"]
    checks = []
    for name, sigma_paper in zip(("light", "moderate", "dense"), misc["fog_sigma_per_km"]):
        sigma = float(atmosphere.koschmieder_extinction_per_km(visibilities[name] / 1000.0))
        checks.append(
            Check.of_paper(
                f"T16.sigma_fog.{name}",
                sigma_paper,
                sigma,
                "1/km",
                "Table 16",
                "Koschmieder, Eq. 12: -ln(0.02)/V",
                abs_tol=_printed_tol(sigma_paper),
            )
        )
    sigma = float(atmosphere.kruse_extinction_per_km(1550.0, 3.0))
    checks.append(
        Check.of_paper(
            "T47.kruse_sigma.1550nm.3km",
            misc["kruse_sigma_1550nm_3km"],
            sigma,
            "dB/km (paper)",
            "Table 47 text",
            "Kruse/Kim, Eqs. 19-20 (the paper truncates 0.5576)",
            abs_tol=0.001,
        )
    )
    eta = float(atmosphere.transmittance(sigma, 3000.0, "paper"))
    checks.append(
        Check.of_paper(
            "T47.eta_tl",
            misc["eta_tl"],
            eta,
            "-",
            "Table 47",
            "Eq. 10 over 3 km with the Kruse sigma",
            abs_tol=0.0011,
            extra={
                "physical_value": float(atmosphere.transmittance(sigma, 3000.0, "physical")),
                "note": "the paper rounds sigma to 0.557 before Eq. 10, which gives 0.6808",
            },
        )
    )
    return checks


def acoustic_and_radar_loss_checks() -> list[Check]:
    """Acoustic (Tables 31-32) and radar losses (Tables 41, 44, Eq. 85)."""
    misc = load_tables()["printed"]["misc"]
    checks = [
        Check.of_paper(
            "T32.wind_noise.6.7m_s",
            misc["wind_noise_6_7_m_s_db"],
            float(acoustic.wind_noise_db(6.7)),
            "dB",
            "Table 32",
            "linear interpolation of Table 31",
            abs_tol=0.005,
        ),
        Check.of_paper(
            "T32.g_array",
            misc["g_array_db"],
            float(acoustic.array_gain_db(128)),
            "dB",
            "Table 32",
            "Eq. 42: 10 log10(128)",
            abs_tol=0.5,
            known_deviation="Table 32 rounds the array gain to 20 dB; Eq. 42 gives 21.07 dB for 128 microphones",
        ),
    ]
    hardware = load_tables()["radar"]["hardware_losses_db"]
    checks.append(
        Check.of_paper(
            "T41.l_hardware",
            misc["l_hardware_t41_db"],
            float(sum(v for k, v in hardware.items() if k != "source")),
            "dB",
            "Table 41",
            "sum of Table 41's contributions",
            abs_tol=0.05,
        )
    )
    g_rain = float(itu.rain_specific_attenuation_db_km(12.0, 6.0))
    g_fog = float(itu.fog_specific_attenuation_db_km(12.0, 0.2, 293.15))
    checks.append(
        Check.of_paper(
            "T44.l_propagation",
            misc["l_propagation_t44_db"],
            g_rain + g_fog,
            "dB",
            "Table 44",
            "Eq. 83, 1 km of moderate rain and fog at 12 GHz (the paper truncates 0.1985)",
            abs_tol=0.001,
        )
    )
    checks.append(
        Check.of_paper(
            "Eq85.l_radar_total",
            misc["l_radar_total_eq85_db"],
            float(radar.total_loss_db(10.0, 3.0, g_rain, g_fog, 3.0, 3.0)),
            "dB",
            "Eq. 85",
            "Eqs. 83-84, 3 km of moderate rain and fog at 12 GHz with ITU-R gammas "
            "(the paper's rounded 0.183 and 0.0154 give 13.5952)",
            abs_tol=0.001,
        )
    )
    return checks


def thermal_checks() -> list[Check]:
    """TIR consistency of Table 25 (Eq. 23), C_TIR of Table 8 (Eq. 5) and Eq. 26's linear Delta T."""
    misc = load_tables()["printed"]["misc"]
    checks = []
    tir_d = default_values("tir")
    ratio = (tir_d["n_h"] / np.deg2rad(tir_d["hfov_deg"])) / (tir_d["focal_mm"] * 1e-3 / (tir_d["pitch_um"] * 1e-6))
    checks.append(
        Check.of_paper(
            "T25.ifov_consistency",
            misc["tir_hfov_pitch_consistency"],
            float(ratio),
            "-",
            "Eq. 23",
            "(N_H / HFOV) / (f / p) with Table 25's values",
            abs_tol=0.001,
        )
    )
    target, env = default_values("target"), default_values("environment")
    c_tir = (target["t_suas_k"] - env["t_bg_k"]) / (target["t_suas_k"] + env["t_bg_k"])
    checks.append(
        Check.of_paper(
            "T8.c_tir",
            target["c_tir"],
            float(c_tir),
            "-",
            "Table 8",
            "Eq. 5 with T_sUAS, T_bg",
            abs_tol=0.005,
            known_deviation="Table 8 sets C_TIR = 0.5 (an upper-bound style value) while "
            "Eq. 5 gives -0.017 for T_sUAS = 288.15 K and T_bg = 298.15 K",
        )
    )
    dt_linear = float(
        tir.delta_t_linear(target["emissivity_suas"], target["t_suas_k"], env["emissivity_bg"], env["t_bg_k"])
    )
    dt_lwir = float(
        tir.delta_t_radiometric(
            target["emissivity_suas"], target["t_suas_k"], env["emissivity_bg"], env["t_bg_k"], "lwir"
        )
    )
    checks.append(
        Check.of_paper(
            "Eq26.delta_t.lwir",
            dt_linear,
            dt_lwir,
            "K",
            "Eq. 26 (Table 27 values)",
            "band-integrated Planck radiance, 8-12 um, no reflected surroundings",
            abs_tol=0.5,
            known_deviation="Eq. 26 multiplies emissivity by temperature; radiometry (docs/conventions.md point 2) "
            "gives less than half of that difference",
        )
    )
    return checks


#: The analytic core's check providers, in order: ``csuas defaults check`` and the report's ``defaults.core``.
CORE_PROVIDERS = (itu_checks, environment_checks, acoustic_and_radar_loss_checks, thermal_checks)


def core_checks() -> list[Check]:
    """All checks the analytic core can compute on its own."""
    return [check for provider in CORE_PROVIDERS for check in provider()]


def all_checks(include_simulation: bool = True) -> list[Check]:
    """Core checks plus those of the simulation providers (drone mesh, RCS, LCS)."""
    checks = core_checks()
    if include_simulation:
        for reference in SIMULATION_PROVIDERS.values():
            checks += resolve(reference)()
    return checks
