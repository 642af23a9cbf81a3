"""Aspect sweeps, polar plots and the sphere-averaged RCS of Eq. 6, to a stated accuracy.

Eq. 6 of the paper averages the RCS over all directions with the solid-angle
weight ``cos(phi)`` (phi the elevation):

    sigma_mean = 1/(4 pi) * int_0^{2 pi} int_{-pi/2}^{pi/2} sigma(theta, phi) cos(phi) dphi dtheta,

the mean over directions uniform on the sphere. :func:`sphere_average` estimates
it by randomised quasi-Monte Carlo, the design of every sphere average in csuas
(:func:`csuas.drone_models.geometry.rotated_lattices`): ``R`` replicates of a
Fibonacci lattice of equal-area points, each under an independent uniform random
rotation, so that each replicate mean is unbiased and independent of the others
(Owen, *Monte Carlo theory, methods and examples*, ch. 17). The result is the
mean of the replicate means; with ``SE`` their standard error and ``t`` Student's
97.5 % quantile for ``R - 1`` degrees of freedom, the error bound of the mean is

    error_db = -10 log10(1 - t SE / mean)      (the larger side of the 95 % interval).

Batches of replicates are added until ``error_db`` meets the requested accuracy
(default :data:`SPHERE_AVERAGE_ACCURACY_DB`) at every frequency, or the aspect
budget is spent. The SBR noise of each aspect is part of the replicate spread,
so each aspect is traced on one tube grid.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from csuas.base.errors import InputErrors, ParameterError
from csuas.base.fileio import atomic_path

from .aspect_sampling import flash_proposal, uniform_weight
from .solver import compute_rcs, get_engine, lower_side_db, to_dbsm

#: The paper's radar bands [GHz] (Section 4.8: 2.4 GHz to Ka band).
PAPER_BANDS_GHZ = (2.4, 8.0, 12.0, 18.0, 24.0, 35.0)


def aspect_sweep(
    target, frequency_ghz, azimuth_deg, elevation_deg=0.0, *, polarisations=("VV", "HH"), **kwargs
) -> dict:
    """Monostatic RCS along a cut of aspects at one or more frequencies.

    Parameters
    ----------
    target : mesh, file, preset name or SbrEngine
    frequency_ghz : float or array_like (F,)
    azimuth_deg, elevation_deg : array_like, broadcast to (A,)
        Aspect cut [deg], e.g. ``np.arange(0, 360, 1)`` at elevation 0.
    polarisations : sequence of str
        Which polarisations to return.
    **kwargs
        Passed to :func:`compute_rcs` (quality, material, ...).

    Returns
    -------
    dict
        ``frequency_ghz``, ``azimuth_deg``, ``elevation_deg``, and per
        polarisation ``rcs_m2[pol]`` / ``rcs_dbsm[pol]`` / ``error_db[pol]`` of
        shape (F, A); ``rays``, ``time_s``.
    """
    result = compute_rcs(target, frequency_ghz, azimuth_deg, elevation_deg, **kwargs)
    out = {
        "frequency_ghz": result.frequency_ghz,
        "azimuth_deg": result.azimuth_deg,
        "elevation_deg": result.elevation_deg,
        "rcs_m2": {},
        "rcs_dbsm": {},
        "error_db": {},
        "rays": result.tubes,
        "ray_casts": result.ray_casts,
        "time_s": result.time_s + result.error_time_s,
        "rays_per_wavelength": result.rays_per_wavelength,
        "max_bounces": result.max_bounces,
    }
    for pol in polarisations:
        out["rcs_m2"][pol] = result.rcs_m2(pol)[..., 0]
        out["rcs_dbsm"][pol] = result.rcs_dbsm(pol)[..., 0]
        err = result.error_estimate_db(pol)
        out["error_db"][pol] = None if err is None else err[..., 0]
    return out


def rcs_table(target, frequency_ghz: float, azimuth_deg, elevation_deg, *, polarisation: str = "VV", **kwargs) -> dict:
    """Monostatic RCS on an azimuth x elevation grid, for interpolation by link simulators.

    Parameters
    ----------
    target : mesh, file, preset name or SbrEngine
    frequency_ghz : float
        Frequency [GHz].
    azimuth_deg, elevation_deg : array_like (Na,), (Ne,)
        Grid axes [deg] (docs/command-line.md directions, target -> radar).
    polarisation : str
        "VV", "HH", "HV", "VH".
    **kwargs
        Passed to :func:`compute_rcs`.

    Returns
    -------
    dict
        ``azimuth_deg`` (Na,), ``elevation_deg`` (Ne,), ``rcs_m2`` (Na, Ne),
        ``error_db`` (Na, Ne) or None, ``rays``, ``time_s`` (the layout of
        ``csuas.render.links.rcs_table.RCSTable``).
    """
    az = np.atleast_1d(np.asarray(azimuth_deg, float))
    el = np.atleast_1d(np.asarray(elevation_deg, float))
    grid_az, grid_el = np.meshgrid(az, el, indexing="ij")  # (Na, Ne)
    res = compute_rcs(target, frequency_ghz, grid_az.ravel(), grid_el.ravel(), **kwargs)
    err = res.error_estimate_db(polarisation)
    return {
        "frequency_ghz": float(frequency_ghz),
        "azimuth_deg": az,
        "elevation_deg": el,
        "polarisation": polarisation,
        "rcs_m2": res.rcs_m2(polarisation)[0, :, 0].reshape(grid_az.shape),
        "error_db": None if err is None else err[0, :, 0].reshape(grid_az.shape),
        "rays": res.tubes,
        "time_s": res.time_s + res.error_time_s,
    }


def plot_polar(azimuth_deg, curves_dbsm: dict, path, *, title: str = "", floor_dbsm: float | None = None):
    """Write a polar plot (PNG) of RCS [dBsm] against azimuth, atomically.

    Parameters
    ----------
    azimuth_deg : array_like (A,)
        Angles [deg].
    curves_dbsm : dict
        Label -> RCS values (A,) [dBsm].
    path : str or Path
        Output PNG file (written via a temporary file and renamed).
    floor_dbsm : float, optional
        Radial minimum [dBsm]; default 40 dB below the maximum.

    Returns
    -------
    Path
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    angle = np.radians(np.asarray(azimuth_deg, float))
    order = np.argsort(angle)
    peak = max(float(np.max(v)) for v in curves_dbsm.values())
    floor = peak - 40.0 if floor_dbsm is None else floor_dbsm
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="polar")
    for label, values in curves_dbsm.items():
        v = np.maximum(np.asarray(values, float), floor)[order]
        ax.plot(np.append(angle[order], angle[order][0]), np.append(v, v[0]), label=label, lw=1)
    ax.set_rlim(floor, np.ceil(peak / 5.0) * 5.0 + 5.0)
    ax.set_title(title or "RCS [dBsm] vs azimuth")
    ax.legend(loc="lower left", fontsize=8, bbox_to_anchor=(-0.1, -0.1))
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, bbox_inches="tight", format="png")
    plt.close(fig)
    return path


#: Default accuracy of :func:`sphere_average`: the bound on its mean [dB] (module docstring).
SPHERE_AVERAGE_ACCURACY_DB = 0.5

#: Default aspect budget of :func:`sphere_average` per frequency.
SPHERE_AVERAGE_MAX_ASPECTS = 4096


def _polarised(result, polarisation: str) -> np.ndarray:
    """RCS (F, A, M) [m^2] of one polarisation, or of the VV/HH mean for ``"mean"``."""
    if polarisation.lower() == "mean":
        return 0.5 * (result.rcs_m2("VV") + result.rcs_m2("HH"))
    return result.rcs_m2(polarisation)


def _by_frequency(chunks: list, n_frequencies: int) -> np.ndarray:
    """(frequency index, values) chunks joined per frequency into an array (F, n)."""
    return np.stack([np.concatenate([v for i, v in chunks if i == f]) for f in range(n_frequencies)])


def _average_bound_db(replicate_means: np.ndarray) -> np.ndarray:
    """Upper side of the 95 % Student-t interval of the mean of replicate means (R, F), in dB (F,)."""
    from scipy.stats import t

    r = replicate_means.shape[0]
    mean = replicate_means.mean(axis=0)
    half = t.ppf(0.975, r - 1) * replicate_means.std(axis=0, ddof=1) / np.sqrt(r)
    with np.errstate(divide="ignore", invalid="ignore"):
        return lower_side_db(half / mean, 10.0)


def sphere_average(
    target,
    frequency_ghz,
    *,
    accuracy_db: float = SPHERE_AVERAGE_ACCURACY_DB,
    polarisation: str = "VV",
    replicates: int = 8,
    aspects_per_replicate: int = 16,
    max_aspects: int = SPHERE_AVERAGE_MAX_ASPECTS,
    seed: int = 0,
    **kwargs,
) -> dict:
    """Sphere-averaged monostatic RCS by Eq. 6 to a stated accuracy, and the aspect distribution.

    Parameters
    ----------
    target : mesh, file, preset name or SbrEngine
    frequency_ghz : float or array_like (F,)
        Radar frequencies [GHz].
    accuracy_db : float
        Stop when the 95 % bound of the mean is within this [dB] at every frequency (> 0).
    polarisation : str
        "VV", "HH", "HV", "VH", or "mean" (average of VV and HH): the one averaged and judged.
    replicates : int
        Randomly rotated lattices added per batch (>= 2).
    aspects_per_replicate : int
        Points of each Fibonacci lattice (>= 4).
    max_aspects : int
        Aspect budget per frequency; reaching it ends the average unconverged.
    seed : int
        Seed of the rotations (batch ``i`` uses ``seed + i``): results are reproducible.
    **kwargs
        Passed to :func:`compute_rcs`; ``error_estimate`` defaults to False.

    Returns
    -------
    dict
        Per frequency (arrays of shape (F,)): ``mean_m2`` (Eq. 6), ``mean_dbsm``, ``error_db``
        (the bound of the module docstring), ``quadrature_error_rel`` (its relative half-width),
        ``mean_of_dbsm`` and ``std_of_dbsm`` (moments of the RCS in dB, the statistics of 3GPP
        TR 38.901's log-normal UAV model), ``median_m2``; ``converged`` (bool), ``n_aspects``,
        ``replicates``, ``accuracy_db``, ``samples_m2`` (polarisation -> (F, n) at the n uniform
        aspects, for VV, HH and the judged one), ``directions`` (n, 3) of those,
        ``mean_m2_by_polarisation`` and ``error_db_by_polarisation`` (the same three), and ``rays``,
        ``time_s``. ``n_aspects`` counts the flash-drawn aspects too (2n).

    Raises
    ------
    ParameterError
        ``accuracy_db <= 0``, ``replicates < 2``, ``aspects_per_replicate < 4`` or ``max_aspects``
        below one batch.
    """
    _check_sphere_budget(accuracy_db, replicates, aspects_per_replicate, max_aspects)
    from csuas.drone_models.geometry import direction_angles, rotated_lattices

    kwargs.setdefault("error_estimate", False)
    engine = get_engine(target, kwargs.pop("material", None), shell_thickness_m=kwargs.pop("shell_thickness_m", None))
    start = time.perf_counter()
    judged = str(polarisation)
    frequencies = np.atleast_1d(np.asarray(frequency_ghz, float))
    proposals = [flash_proposal(engine.target, f) for f in frequencies]
    n_r, half = int(replicates), int(aspects_per_replicate)
    drawn = _SphereSamples({pol: [] for pol in ("VV", "HH", judged)}, {pol: [] for pol in ("VV", "HH", judged)})
    batch = 0
    while True:
        # per replicate: a rotated lattice (the uniform half, also the aspect distribution's sample) and
        # as many flash-drawn aspects, all weighted by the balance heuristic (aspect_sampling)
        rng = np.random.default_rng([seed, batch])
        lattice = rotated_lattices(n_r, half, seed + batch)  # (R, n, 3)
        for f_index, (f, proposal) in enumerate(zip(frequencies, proposals)):
            flashes = proposal.sample(n_r * half, rng).reshape(n_r, half, 3)
            both = np.concatenate([lattice, flashes], axis=1).reshape(-1, 3)
            az, el = direction_angles(both)
            result = compute_rcs(engine, f, az, el, **kwargs)
            drawn.add(result, f_index, uniform_weight(both, proposal).reshape(n_r, 2 * half), half)
        drawn.directions.append(lattice.reshape(-1, 3))
        batch += 1
        per_replicate = {pol: _by_frequency(chunks, len(frequencies)).T for pol, chunks in drawn.estimates.items()}
        error_db = _average_bound_db(per_replicate[judged])  # (R, F) -> (F,)
        next_total = 2 * half * (per_replicate[judged].shape[0] + n_r)
        if np.all(error_db <= accuracy_db) or next_total > max_aspects:
            break
    found = {
        **_sphere_statistics(frequencies, drawn, per_replicate, judged),
        "error_db": error_db,
        "quadrature_error_rel": 1.0 - 10.0 ** (-error_db / 10.0),
        "converged": bool(np.all(error_db <= accuracy_db)),
        "accuracy_db": float(accuracy_db),
        "rays_per_wavelength": result.rays_per_wavelength,
        "max_bounces": result.max_bounces,
        "time_s": time.perf_counter() - start,
        "polarisation": polarisation,
    }
    return {key: found[key] for key in SPHERE_AVERAGE_KEYS}


#: Keys of :func:`sphere_average`'s result, in the order it gives them.
SPHERE_AVERAGE_KEYS = (
    "frequency_ghz",
    "mean_m2",
    "mean_dbsm",
    "error_db",
    "quadrature_error_rel",
    "mean_of_dbsm",
    "std_of_dbsm",
    "median_m2",
    "converged",
    "accuracy_db",
    "n_aspects",
    "replicates",
    "samples_m2",
    "mean_m2_by_polarisation",
    "error_db_by_polarisation",
    "directions",
    "rays",
    "rays_per_wavelength",
    "max_bounces",
    "time_s",
    "polarisation",
)


def _check_sphere_budget(accuracy_db, replicates, aspects_per_replicate, max_aspects) -> None:
    """Refuse, all at once, an accuracy <= 0, fewer than 2 replicates or 4 aspects, or a budget under one batch."""

    problems = []
    if not (np.isfinite(accuracy_db) and accuracy_db > 0):
        problems.append(ParameterError("accuracy_db", accuracy_db, "0 < x dB"))
    if int(replicates) != replicates or replicates < 2:
        problems.append(ParameterError("replicates", replicates, "integer >= 2"))
    if int(aspects_per_replicate) != aspects_per_replicate or aspects_per_replicate < 4:
        problems.append(ParameterError("aspects_per_replicate", aspects_per_replicate, "integer >= 4"))
    batch_aspects = 2 * replicates * aspects_per_replicate  # the lattices and as many flash-drawn aspects
    if not problems and max_aspects < batch_aspects:
        problems.append(ParameterError("max_aspects", max_aspects, f">= one batch of {batch_aspects} aspects"))
    if problems:
        raise InputErrors(problems)


@dataclass
class _SphereSamples:
    """What :func:`sphere_average` has drawn so far.

    ``samples``: polarisation -> (frequency index, RCS [m^2] at the uniform aspects) chunks;
    ``estimates``: polarisation -> (frequency index, one weighted mean per replicate) chunks;
    ``directions``: the uniform aspects (n, 3) of each batch; ``rays``: tubes traced.
    """

    samples: dict
    estimates: dict
    directions: list = field(default_factory=list)
    rays: int = 0

    def add(self, result, f_index: int, weight: np.ndarray, half: int) -> None:
        """Add one frequency's RCS over a batch: (R, 2 half) aspects, the first half uniform, with their weights."""
        self.rays += result.tubes
        n_r = weight.shape[0]
        for pol in self.samples:
            sigma_pol = _polarised(result, pol)[0, :, 0].reshape(n_r, 2 * half)
            self.estimates[pol].append((f_index, (sigma_pol * weight).mean(axis=1)))  # one estimate per replicate
            self.samples[pol].append((f_index, sigma_pol[:, :half].ravel()))


def _sphere_statistics(frequencies, drawn: _SphereSamples, per_replicate: dict, judged: str) -> dict:
    """The mean (Eq. 6), the moments of the RCS in dB and the samples of :func:`sphere_average`'s result."""
    mean = per_replicate[judged].mean(axis=0)
    stacked = {pol: _by_frequency(chunks, len(frequencies)) for pol, chunks in drawn.samples.items()}
    sigma = stacked[judged]  # (F, uniform aspects)
    db = to_dbsm(sigma)
    return {
        "frequency_ghz": frequencies,
        "mean_m2": mean,
        "mean_dbsm": to_dbsm(mean),
        "mean_of_dbsm": db.mean(axis=1),
        "std_of_dbsm": db.std(axis=1),
        "median_m2": np.median(sigma, axis=1),
        "n_aspects": int(2 * sigma.shape[1]),
        "replicates": int(per_replicate[judged].shape[0]),
        "samples_m2": stacked,
        "mean_m2_by_polarisation": {pol: r.mean(axis=0) for pol, r in per_replicate.items()},
        "error_db_by_polarisation": {pol: _average_bound_db(r) for pol, r in per_replicate.items()},
        "directions": np.concatenate(drawn.directions),
        "rays": drawn.rays,
    }


def band_sweep(
    target,
    bands_ghz=PAPER_BANDS_GHZ,
    *,
    accuracy_db: float = SPHERE_AVERAGE_ACCURACY_DB,
    cut_step_deg: float = 2.0,
    **kwargs,
) -> list[dict]:
    """The drone's RCS against azimuth and elevation at each band, with its Eq. 6 mean.

    Parameters
    ----------
    target : mesh, file, preset name or SbrEngine
    bands_ghz : sequence of float
        Frequencies [GHz]; default the paper's 2.4, 8, 12, 18, 24, 35 GHz.
    accuracy_db : float
        Accuracy of the sphere average (:func:`sphere_average`) [dB].
    cut_step_deg : float
        Step of the azimuth cut (elevation 0) and elevation cut (azimuth 0) [deg].
    **kwargs
        Passed to :func:`compute_rcs` (material, ...); ``quality`` defaults
        to ``"draft"`` here: the DJI Mini 4 Pro at 35 GHz then needs about
        5e4 tubes per aspect and ~800 aspects per band (the tube count grows
        with f^2, so 2.4 GHz costs 200 times less than 35 GHz).

    Returns
    -------
    list of dict
        One per band: ``frequency_ghz``, ``azimuth_cut`` and ``elevation_cut``
        (angles and VV/HH dBsm), and the :func:`sphere_average` figures.
    """
    if not cut_step_deg > 0:
        raise ParameterError("cut_step_deg", cut_step_deg, "x > 0 deg")
    kwargs.setdefault("quality", "draft")
    engine = get_engine(target, kwargs.pop("material", None), shell_thickness_m=kwargs.pop("shell_thickness_m", None))
    az_cut = np.arange(0.0, 360.0, cut_step_deg)
    el_cut = np.arange(-90.0, 90.0 + 1e-9, cut_step_deg)
    out = []
    for f in bands_ghz:
        start = time.perf_counter()
        azs = aspect_sweep(engine, f, az_cut, 0.0, error_estimate=False, **kwargs)
        els = aspect_sweep(engine, f, 0.0, el_cut, error_estimate=False, **kwargs)
        avg = sphere_average(engine, f, accuracy_db=accuracy_db, polarisation="mean", **kwargs)
        out.append(
            {
                "frequency_ghz": float(f),
                "azimuth_cut": {
                    "azimuth_deg": az_cut,
                    "elevation_deg": 0.0,
                    "rcs_dbsm": {p: v[0] for p, v in azs["rcs_dbsm"].items()},
                },
                "elevation_cut": {
                    "azimuth_deg": 0.0,
                    "elevation_deg": el_cut,
                    "rcs_dbsm": {p: v[0] for p, v in els["rcs_dbsm"].items()},
                },
                **{
                    k: (v[0] if isinstance(v, np.ndarray) and v.shape == (1,) else v)
                    for k, v in avg.items()
                    if k not in ("frequency_ghz", "samples_m2", "directions")
                },
                "time_s": time.perf_counter() - start,
            }
        )
    return out


def plot_band_sweep(sweep: list[dict], path, *, title: str = "") -> object:
    """Polar plot of the azimuth cuts (VV) of :func:`band_sweep`, one curve per band."""
    curves = {
        f"{b['frequency_ghz']:g} GHz (mean {b['mean_dbsm']:.1f} dBsm)": b["azimuth_cut"]["rcs_dbsm"]["VV"]
        for b in sweep
    }
    return plot_polar(
        sweep[0]["azimuth_cut"]["azimuth_deg"], curves, path, title=title or "RCS [dBsm] vs azimuth, elevation 0, VV"
    )
