"""Aspect sweeps, polar plots and the sphere-averaged RCS of Eq. 6.

Eq. 6 of the paper averages the RCS over all directions with the solid-angle
weight ``cos(phi)`` (phi the elevation):

    sigma_mean = 1/(4 pi) * int_0^{2 pi} int_{-pi/2}^{pi/2} sigma(theta, phi) cos(phi) dphi dtheta.

Substituting ``mu = sin(phi)`` turns the weight into ``dmu``, so the average is
evaluated exactly for band-limited patterns by Gauss-Legendre nodes in ``mu``
and equally spaced azimuths (trapezoidal rule, spectrally accurate for a
periodic integrand). Its sampling error is estimated by repeating the sum with
every other azimuth and half the elevation nodes.
"""

from __future__ import annotations

import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.base.fileio import atomic_path

from .solver import compute_rcs, get_engine, to_dbsm

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


def _quadrature(n_azimuth: int, n_elevation: int):
    mu, weights = np.polynomial.legendre.leggauss(n_elevation)
    azimuth = np.arange(n_azimuth) * 360.0 / n_azimuth
    elevation = np.degrees(np.arcsin(mu))
    az, el = np.meshgrid(azimuth, elevation, indexing="ij")  # (n_az, n_el)
    w = np.broadcast_to(weights[None, :] * (2.0 * np.pi / n_azimuth) / (4.0 * np.pi), az.shape)
    return az, el, w


def sphere_average(
    target, frequency_ghz, *, n_azimuth: int = 72, n_elevation: int = 24, polarisation: str = "VV", **kwargs
) -> dict:
    """Sphere-averaged monostatic RCS by Eq. 6 (cos-weighted), with its sampling error.

    Parameters
    ----------
    target : mesh, file, preset name or SbrEngine
    frequency_ghz : float or array_like (F,)
    n_azimuth : int
        Equally spaced azimuths (>= 4, even).
    n_elevation : int
        Gauss-Legendre nodes in sin(elevation) (>= 2, even).
    polarisation : str
        "VV", "HH", "HV", "VH", or "mean" (average of VV and HH).
    **kwargs
        Passed to :func:`compute_rcs`; ``error_estimate`` defaults to False.

    Returns
    -------
    dict
        Per frequency (arrays of shape (F,)): ``mean_m2`` (Eq. 6),
        ``mean_dbsm`` (10 log10 of it), ``mean_of_dbsm`` and ``std_of_dbsm``
        (moments of the RCS in dB over the sphere, the statistics of 3GPP
        TR 38.901's log-normal UAV model), ``median_m2``,
        ``quadrature_error_rel`` (|full - half rule| / full), and
        ``rays``, ``time_s``, ``n_aspects``.
    """
    if int(n_azimuth) != n_azimuth or n_azimuth < 4 or n_azimuth % 2:
        raise ParameterError("n_azimuth", n_azimuth, "even integer >= 4")
    if int(n_elevation) != n_elevation or n_elevation < 2 or n_elevation % 2:
        raise ParameterError("n_elevation", n_elevation, "even integer >= 2")
    kwargs.setdefault("error_estimate", False)
    az, el, w = _quadrature(int(n_azimuth), int(n_elevation))
    start = time.perf_counter()
    result = compute_rcs(target, frequency_ghz, az.ravel(), el.ravel(), **kwargs)
    if str(polarisation).lower() == "mean":
        sigma = 0.5 * (result.rcs_m2("VV") + result.rcs_m2("HH"))[..., 0]
    else:
        sigma = result.rcs_m2(polarisation)[..., 0]
    sigma = sigma.reshape((-1,) + az.shape)  # (F, n_az, n_el)
    mean = (sigma * w).sum(axis=(1, 2))
    az_h, el_h, w_h = _quadrature(int(n_azimuth) // 2, max(2, int(n_elevation) // 2))
    engine = get_engine(target, kwargs.get("material"), shell_thickness_m=kwargs.get("shell_thickness_m"))
    coarse = compute_rcs(
        engine,
        frequency_ghz,
        az_h.ravel(),
        el_h.ravel(),
        **{k: v for k, v in kwargs.items() if k not in ("material", "shell_thickness_m")},
    )
    sig_h = (
        0.5 * (coarse.rcs_m2("VV") + coarse.rcs_m2("HH"))
        if str(polarisation).lower() == "mean"
        else coarse.rcs_m2(polarisation)
    )[..., 0].reshape((-1,) + az_h.shape)
    mean_h = (sig_h * w_h).sum(axis=(1, 2))
    db = to_dbsm(sigma)
    mean_db = (db * w).sum(axis=(1, 2))
    std_db = np.sqrt(np.maximum(((db - mean_db[:, None, None]) ** 2 * w).sum(axis=(1, 2)), 0.0))
    return {
        "frequency_ghz": result.frequency_ghz,
        "mean_m2": mean,
        "mean_dbsm": to_dbsm(mean),
        "mean_of_dbsm": mean_db,
        "std_of_dbsm": std_db,
        "median_m2": np.median(sigma.reshape(len(mean), -1), axis=1),
        "quadrature_error_rel": np.abs(mean - mean_h) / np.maximum(mean, 1e-300),
        "n_aspects": az.size,
        "rays": result.tubes + coarse.tubes,
        "rays_per_wavelength": result.rays_per_wavelength,
        "max_bounces": result.max_bounces,
        "time_s": time.perf_counter() - start,
        "polarisation": polarisation,
    }


def band_sweep(
    target,
    bands_ghz=PAPER_BANDS_GHZ,
    *,
    n_azimuth: int = 36,
    n_elevation: int = 12,
    cut_step_deg: float = 2.0,
    **kwargs,
) -> list[dict]:
    """The drone's RCS against azimuth and elevation at each band, with its Eq. 6 mean.

    Parameters
    ----------
    target : mesh, file, preset name or SbrEngine
    bands_ghz : sequence of float
        Frequencies [GHz]; default the paper's 2.4, 8, 12, 18, 24, 35 GHz.
    n_azimuth, n_elevation : int
        Quadrature of the sphere average (:func:`sphere_average`).
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
        avg = sphere_average(engine, f, n_azimuth=n_azimuth, n_elevation=n_elevation, polarisation="mean", **kwargs)
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
                    if k != "frequency_ghz"
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
