"""Per-aspect RCS tables (azimuth x elevation x frequency x polarisation) with each cell's bound.

:func:`signature_table` traces a target (a drone preset, a mesh file or a mesh) on a grid of
monostatic aspects in one launch of :func:`csuas.render.rcs.solver.compute_rcs` and returns a
:class:`SignatureTable`: the RCS [dBsm] of every cell and its bound against the exact answer, the
discretisation term (the grid replicas' spread, :mod:`csuas.render.rcs.solver`), PO's model term
(:mod:`csuas.render.rcs.model_error`) and the bounce limit's truncation term
(:meth:`csuas.render.rcs.solver.RcsResult.truncation_db`) added as relative amplitudes. The azimuth axis runs from -180
to +180 deg inclusive (MATLAB ``rcsSignature``'s default span): the +180 deg column is the -180 deg
aspect, traced once. :mod:`csuas.render.rcs.signature_files` writes the table in the layouts other
tools load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError

from .solver import POLARISATIONS, REPLICAS, compute_rcs, estimate_tubes


@dataclass
class SignatureTable:
    """RCS of a target on an aspect x frequency grid, every polarisation, with bounds.

    Attributes
    ----------
    target : str
        Preset name or mesh file.
    azimuth_deg : ndarray (P,)
        Azimuth from +x (nose) toward +y of the direction target -> radar [deg], -180 to 180.
    elevation_deg : ndarray (Q,)
        Elevation from the xy-plane [deg].
    frequency_ghz : ndarray (K,)
    polarisations : tuple of str (N,)
        Receive-transmit pairs of :data:`csuas.render.rcs.solver.POLARISATIONS`.
    rcs_dbsm : ndarray (N, K, Q, P)
        Monostatic RCS [dBsm], floored at -300 dBsm.
    bound_db : ndarray (N, K, Q, P)
        Bound against the exact answer [dB]: ``discretisation_db``, ``model_db`` and
        ``truncation_db`` together; ``inf`` where none exists.
    discretisation_db : ndarray (N, K, Q, P)
        The SBR run's bound against physical optics [dB] (99 % level, solver module docstring).
    model_db : ndarray (K,)
        PO's own error bound against the exact answer [dB], per frequency.
    truncation_db : ndarray (N, K, Q, P)
        The bounce limit's term [dB]: what the tubes it stopped could add.
    quality : str
    rays_per_wavelength, max_bounces : float, int
    tubes : int
        Tubes launched, all replicas.
    time_s : float
        Wall time of the trace, the error estimate's replicas included [s].
    """

    target: str
    azimuth_deg: np.ndarray
    elevation_deg: np.ndarray
    frequency_ghz: np.ndarray
    polarisations: tuple
    rcs_dbsm: np.ndarray
    bound_db: np.ndarray
    discretisation_db: np.ndarray
    model_db: np.ndarray
    truncation_db: np.ndarray
    quality: str
    rays_per_wavelength: float
    max_bounces: int
    tubes: int
    time_s: float


def azimuth_axis(step_deg: float) -> np.ndarray:
    """-180 to +180 deg inclusive in steps of ``step_deg``, which must divide 360 [deg]."""
    count = 360.0 / float(step_deg)
    if not (0.0 < step_deg <= 90.0) or abs(count - round(count)) > 1e-9:
        raise ParameterError("azimuth_step_deg", step_deg, "0 < step <= 90 [deg] dividing 360")
    return np.linspace(-180.0, 180.0, int(round(count)) + 1)


#: Exact first-hit integrals (facets x aspects x replicas) per CPU second, measured on the 81 920-face
#: icosphere: 8.4e7 in 11.3 s of CPU time (the machine's 2 cores shared).
FACET_JOBS_PER_S_CPU = 7.0e6


def estimate_cost(target, frequency_ghz, aspects: int, rays_per_wavelength: float, max_bounces: int) -> dict:
    """Tubes and seconds on 2 CPU cores of a table, before tracing.

    Every aspect of every frequency on :data:`csuas.render.rcs.solver.REPLICAS` shifted grids: the
    tubes of :func:`csuas.render.rcs.solver.estimate_tubes` at two bounces each, or at every bounce
    when the target has thin shells (their tubes branch and reach the bounce limit: on the DJI Mini 4
    Pro a third of the tube exits are at the limit), plus the exact first hits of every facet
    (:data:`FACET_JOBS_PER_S_CPU`). Measured on the DJI Mini 4 Pro at 9.4 GHz, 256 aspects: estimate
    3.0 s, 4.6 s of CPU time.

    Parameters
    ----------
    target : TargetMesh
        The prepared mesh (``SbrEngine.target``).
    """
    from .solver import TUBE_BOUNCES_PER_S_CPU

    shells = any(m.thickness_m for m in target.materials if not m.is_pec)
    per_grid = sum(estimate_tubes(target.bounding_radius_m, float(f), rays_per_wavelength) for f in frequency_ghz)
    tubes = per_grid * aspects * REPLICAS
    facet_jobs = len(target.faces) * aspects * len(frequency_ghz) * REPLICAS
    bounces = max_bounces if shells else min(2, max_bounces)
    seconds = tubes * bounces / TUBE_BOUNCES_PER_S_CPU + facet_jobs / FACET_JOBS_PER_S_CPU
    return {"tubes": tubes, "aspects": aspects, "seconds_2_cpu_cores": seconds}


def signature_table(
    engine,
    azimuth_deg,
    elevation_deg,
    frequency_ghz,
    *,
    polarisations=tuple(POLARISATIONS),
    quality: str = "standard",
    max_bounces: int | None = None,
) -> SignatureTable:
    """Trace the grid and return its :class:`SignatureTable` (module docstring).

    Parameters
    ----------
    engine : SbrEngine, mesh, mesh file or preset name
        The target (:func:`csuas.render.rcs.solver.get_engine`).
    azimuth_deg : array_like (P,)
        Azimuths [deg]; a last value 360 deg after the first repeats the first column.
    elevation_deg : array_like (Q,)
        Elevations [deg], -90 to 90.
    frequency_ghz : array_like (K,)
        Frequencies [GHz].
    polarisations : sequence of str
        Which of "VV", "HH", "HV", "VH" to keep.
    quality : str
        SBR quality preset (:data:`csuas.render.rcs.solver.QUALITY_PRESETS`).
    max_bounces : int, optional
        Bounce limit; default the preset's (a shelled drone needs more for a finite truncation term).
    """
    az = np.asarray(azimuth_deg, float)
    el = np.asarray(elevation_deg, float)
    wraps = len(az) > 1 and math.isclose(az[-1] - az[0], 360.0)
    traced = az[:-1] if wraps else az
    grid_el, grid_az = np.meshgrid(el, traced, indexing="ij")  # (Q, P')
    res = compute_rcs(engine, frequency_ghz, grid_az.ravel(), grid_el.ravel(), quality=quality, max_bounces=max_bounces)
    shape = (len(res.frequency_ghz), len(el), len(traced))
    columns = np.r_[np.arange(len(traced)), 0] if wraps else np.arange(len(traced))
    rcs, disc, bound, truncation = (
        np.stack([getter(p)[..., 0].reshape(shape)[..., columns] for p in polarisations])
        for getter in (res.rcs_dbsm, res.error_estimate_db, res.bound_db, res.truncation_db)
    )
    return SignatureTable(
        target=res.target_name,
        azimuth_deg=az,
        elevation_deg=el,
        frequency_ghz=res.frequency_ghz,
        polarisations=tuple(polarisations),
        rcs_dbsm=rcs,
        bound_db=bound,
        discretisation_db=disc,
        model_db=np.asarray(res.model_error_db, float),
        truncation_db=truncation,
        quality=quality,
        rays_per_wavelength=res.rays_per_wavelength,
        max_bounces=res.max_bounces,
        tubes=res.tubes,
        time_s=res.time_s + res.error_time_s,
    )
