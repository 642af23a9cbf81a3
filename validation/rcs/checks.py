"""Checks of the paper's default RCS against the SBR-PO RCS of the drone model.

Two entries for ``csuas defaults check`` / ``csuas report``:

* ``rcs.<preset>.mean_dbsm.table8`` -- Table 8's ``sigma_radar = 0.01 m^2``
  (-20 dBsm) against the drone's sphere-averaged RCS by Eq. 6 (linear,
  cos-weighted mean of the VV and HH returns), tolerance +-3 dB;
* ``rcs.<preset>.mean_of_dbsm.3gpp_tr38901`` -- 3GPP TR 38.901 (v19, Table
  7.9.2.1-1) small-UAV log-normal model, mean -12.81 dBsm, spread 3.74 dB,
  against the mean over the sphere of the drone's RCS in dBsm, tolerance one
  spread.

Cost. The computation is kept cheap enough for ``csuas defaults check``
(a few seconds on 2 CPU cores): :data:`CHECK_SETTINGS` uses the paper's
default radar wavelength 1.25 cm (Table 39, 23.98 GHz), 3 rays per
wavelength, 3 bounces and a 24 x 8 aspect quadrature (192 aspects, about
5 s including kernel compilation). The drone's plastic and painted parts are
2 mm dielectric shells, so its battery, motors and arms inside or behind them
are illuminated, and so are the flight controller's board, its ground plane and the wiring inside
(the radar model of docs/simulation.md). Measured on the DJI Mini 4 Pro model (VV/HH mean), quick report
of 2026-11-27: Eq. 6 mean -18.6 dBsm (1536 aspects) with these settings against -19.7 dBsm in the
standard-quality table (defaults/drone_rcs_statistics.csv); mean of the dBsm values -23.2 dBsm. Before
the model's rotors became blades (swept discs) these were -18.0 and -21.5 dBsm.
"""

from __future__ import annotations

import functools
from dataclasses import replace

import numpy as np

from csuas.base.checks import Check
from csuas.core import units
from csuas.render.quality import RCS

#: Coarse settings of the default checks (documented in the module docstring): the SBR-PO draft rung.
CHECK_SETTINGS = {
    "preset": "dji_mini_4_pro",
    "frequency_ghz": float(units.frequency_ghz(0.0125)),
    **RCS.values("draft"),
    "accuracy_db": 0.5,
}

TABLE8_SIGMA_M2 = 0.01
TR38901_SMALL_UAV_MEAN_DBSM = -12.81
TR38901_SMALL_UAV_SPREAD_DB = 3.74

_WHY_LOW = (
    "SBR-PO on the faceted model has deep nulls between specular flashes: no edge diffraction (PTD) at these "
    "settings, no creeping waves or surface roughness, and its wires (ka 0.02-0.3) are far below PO's validity: "
    "these fill the nulls of measured drones; "
)
_WHY_HIGH = (
    "the model's metal parts (battery can, motors, landing legs) are smooth specular reflectors, and "
    "2 mm plastic shells pass most of the power to them; "
)


@functools.lru_cache(maxsize=4)
def _drone_average(preset: str, frequency_ghz: float, n: float, bounces: int, accuracy_db: float) -> dict:
    from csuas.render.rcs.sweep import sphere_average

    return sphere_average(
        preset,
        frequency_ghz,
        accuracy_db=accuracy_db,
        polarisation="mean",
        rays_per_wavelength=n,
        max_bounces=bounces,
    )


def default_checks(settings: dict | None = None) -> list[Check]:
    """The drone's mean RCS against Table 8 and 3GPP TR 38.901 (see module docstring).

    Parameters
    ----------
    settings : dict, optional
        Overrides of :data:`CHECK_SETTINGS` (preset, frequency_ghz,
        rays_per_wavelength, max_bounces, accuracy_db).

    Returns
    -------
    list of csuas.base.checks.Check
    """
    s = {**CHECK_SETTINGS, **(settings or {})}
    avg = _drone_average(
        s["preset"],
        float(s["frequency_ghz"]),
        float(s["rays_per_wavelength"]),
        int(s["max_bounces"]),
        float(s["accuracy_db"]),
    )
    mean_dbsm = float(avg["mean_dbsm"][0])
    mean_of_db = float(avg["mean_of_dbsm"][0])
    extra = {
        "frequency_ghz": float(s["frequency_ghz"]),
        "rays_per_wavelength": float(s["rays_per_wavelength"]),
        "max_bounces": int(s["max_bounces"]),
        "n_aspects": int(avg["n_aspects"]),
        "quadrature_error_rel": float(avg["quadrature_error_rel"][0]),
        "error_db": float(avg["error_db"][0]),
        "converged": avg["converged"],
        "rays": int(avg["rays"]),
        "time_s": float(avg["time_s"]),
        "mean_m2": float(avg["mean_m2"][0]),
        "std_of_dbsm": float(avg["std_of_dbsm"][0]),
        "within_paper_class1_range_0.001_0.1_m2": bool(0.001 <= avg["mean_m2"][0] <= 0.1),
    }
    method = (
        f"SBR-PO RCS of the {s['preset']} mesh with its part materials at {s['frequency_ghz']:.2f} GHz, "
        f"mean of VV and HH over {int(avg['n_aspects'])} aspects of randomly rotated Fibonacci lattices "
        f"(adaptive to {float(s['accuracy_db']):g} dB at 95 %)"
    )
    table8 = Check.of_paper(
        name=f"rcs.{s['preset']}.mean_dbsm.table8",
        paper=float(10 * np.log10(TABLE8_SIGMA_M2)),
        computed=mean_dbsm,
        unit="dBsm",
        source="Table 8 (sigma_radar = 0.01 m^2), Eq. 6",
        method=method + "; Eq. 6 linear mean",
        abs_tol=3.0,
        extra=extra,
    )
    tr38901 = Check.of_paper(
        name=f"rcs.{s['preset']}.mean_of_dbsm.3gpp_tr38901",
        paper=TR38901_SMALL_UAV_MEAN_DBSM,
        computed=mean_of_db,
        unit="dBsm",
        source="3GPP TR 38.901 v19 Table 7.9.2.1-1, small UAV: log-normal, mean -12.81 dBsm, spread 3.74 dB",
        method=method + "; mean over the sphere of 10 log10(sigma)",
        abs_tol=TR38901_SMALL_UAV_SPREAD_DB,
        extra=extra,
    )
    out = []
    for check, reference in ((table8, "Table 8's 0.01 m^2"), (tr38901, "the 3GPP small-UAV mean")):
        if not check.ok:
            low = check.measured < check.expected
            why = (_WHY_LOW if low else _WHY_HIGH) + (
                "3GPP's small-UAV figure is a log-normal fit to measured UAVs of 0.3 x 0.4 x 0.2 m (metal-rich "
                "airframes), and the mean of dBsm values weighs the model's deep nulls heavily, while the linear "
                "Eq. 6 mean is dominated by the flashes; "
                if "3gpp" in check.name
                else "Table 8 states a generic class-1 value (the paper's Section 4.9 spans 0.001-0.1 m^2); "
            )
            why += (
                f"computed {'below' if low else 'above'} {reference} by {abs(check.measured - check.expected):.1f} dB."
            )
            # 3GPP's figure measures real drones: missing it is a limit of the faceted SBR-PO model (no edge
            # diffraction, idealised materials); Table 8's generic value is the paper's own choice.
            key = "limitation" if "3gpp" in check.name else "known_deviation"
            check = replace(check, **{key: why})
        out.append(check)
    return out
