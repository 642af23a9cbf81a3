"""The drone presets' RCS statistics over aspects, per band and polarisation, as a shipped table.

For every drone preset, band (:data:`BANDS_GHZ`: 2.4, 5.8, 9.4, 16, 24 and 35 GHz) and polarisation
(VV, HH), :func:`drone_statistics` runs the adaptive Eq. 6 sphere average
(:func:`csuas.render.rcs.sweep.sphere_average`) and summarises the aspect distribution:

* ``mean_dbsm`` and ``mean_error_db``: Eq. 6's linear mean (flash-aware weighted estimate) and its
  95 % bound;
* ``median_dbsm``, ``p10_dbsm``, ``p90_dbsm``: percentiles of the uniformly drawn aspects;
* ``lognormal_mean_dbsm``, ``lognormal_std_db``: the log-normal fit (3GPP TR 38.901's UAV model);
* ``chi2_dof`` and ``nearest_swerling``: the chi-square fit with 2k degrees of freedom (k = 1 is
  Swerling 1/2, k = 2 Swerling 3/4; :func:`csuas.core.rcs_statistics.fit_chi_square`).

:func:`write_table` writes them as the CSV ``defaults/drone_rcs_statistics.csv`` that the detection
models read (:func:`csuas.defaults.load_drone_rcs_statistics`), with the settings and cost in its
header; ``csuas rcs-statistics --write-defaults`` regenerates it.
"""

from __future__ import annotations

import csv
import io
import time

import numpy as np

from csuas.base.fileio import write_text_atomic
from csuas.core.rcs_statistics import fit_chi_square, fit_lognormal, rcs_summary
from csuas.drone_models.presets import list_presets

#: Bands of the table [GHz]: 2.4 and 5.8 GHz (drone links), X (9.4), Ku (16), K (24), Ka (35).
BANDS_GHZ = (2.4, 5.8, 9.4, 16.0, 24.0, 35.0)

#: Columns of the table, in order.
COLUMNS = (
    "preset",
    "frequency_ghz",
    "polarisation",
    "mean_dbsm",
    "mean_error_db",
    "median_dbsm",
    "p10_dbsm",
    "p90_dbsm",
    "lognormal_mean_dbsm",
    "lognormal_std_db",
    "chi2_dof",
    "nearest_swerling",
    "aspects",
    "quality",
    "time_s",
)


def drone_statistics(
    presets=None,
    bands_ghz=BANDS_GHZ,
    *,
    quality: str = "standard",
    accuracy_db: float = 0.5,
    max_aspects: int = 8192,
    progress=None,
) -> list[dict]:
    """One row (:data:`COLUMNS`) per preset, band and polarisation.

    Parameters
    ----------
    presets : sequence of str, optional
        Drone presets (default all of :func:`csuas.drone_models.presets.list_presets`).
    bands_ghz : sequence of float
        Frequencies [GHz].
    quality : str
        SBR quality preset of each aspect.
    accuracy_db : float
        Requested 95 % bound of each mean [dB] (the VV/HH average is judged).
    max_aspects : int
        Aspect budget per band.
    progress : callable(done, total, seconds), optional
        Called after each band.
    """
    from csuas.render.rcs.solver import get_engine
    from csuas.render.rcs.sweep import sphere_average

    presets = list(list_presets()) if presets is None else list(presets)
    rows, total, start = [], len(presets) * len(bands_ghz), time.perf_counter()
    for preset in presets:
        engine = get_engine(preset)
        for f in bands_ghz:
            avg = sphere_average(
                engine, float(f), accuracy_db=accuracy_db, polarisation="mean", max_aspects=max_aspects, quality=quality
            )
            for pol in ("VV", "HH"):
                samples = avg["samples_m2"][pol][0]
                summary, lognormal = rcs_summary(samples), fit_lognormal(samples)
                chi = fit_chi_square(samples)
                rows.append(
                    {
                        "preset": preset,
                        "frequency_ghz": float(f),
                        "polarisation": pol,
                        "mean_dbsm": float(10 * np.log10(avg["mean_m2_by_polarisation"][pol][0])),
                        "mean_error_db": float(avg["error_db_by_polarisation"][pol][0]),
                        "median_dbsm": summary["median_dbsm"],
                        "p10_dbsm": summary["p10_dbsm"],
                        "p90_dbsm": summary["p90_dbsm"],
                        "lognormal_mean_dbsm": lognormal["mean_dbsm"],
                        "lognormal_std_db": lognormal["std_db"],
                        "chi2_dof": chi["dof"],
                        "nearest_swerling": chi["nearest_swerling_scan"],
                        "aspects": int(avg["n_aspects"]),
                        "quality": quality,
                        "time_s": float(avg["time_s"]),
                    }
                )
            if progress is not None:
                progress(len(rows) // 2, total, time.perf_counter() - start)
    return rows


def table_text(rows: list[dict], header: str) -> str:
    """The CSV text: ``#`` comment lines of ``header``, the column names, one line per row."""
    out = io.StringIO()
    for line in header.splitlines():
        out.write(f"# {line}\n")
    writer = csv.DictWriter(out, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: (f"{v:.4f}" if isinstance(v, float) else v) for k, v in row.items()})
    return out.getvalue()


def write_table(rows: list[dict], path, header: str) -> None:
    """Write :func:`table_text` atomically to ``path``."""
    write_text_atomic(path, table_text(rows, header))
