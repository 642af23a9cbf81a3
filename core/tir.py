"""Thermal-infrared detection range: Johnson (Eqs. 22-23), MRTD with attenuation (Eqs. 24-31), and NETD.

The NETD model (an extension, ``tir.model = "netd"``) detects the target as a blob of pixels in
temporal noise: its apparent Delta T summed over the n pixels it covers gives the single-frame SNR
|Delta T| sqrt(n) / NETD (a matched sum of n pixels of white noise), and |Delta T| n / NETD below a
pixel, where the pixel sees only the fraction n of the target (Holst, *Electro-Optical Imaging System
Performance*, 5th ed., 2008, ch. 21; Driggers, Friedman & Nichols, *Introduction to Infrared and
Electro-Optical Systems*, 2nd ed., 2012, ch. 12). A threshold set for Pfa on Gaussian noise detects it
with Pd = Q(Q^-1(Pfa) - SNR); the range is where Pd reaches ``p_desired``.

Conventions (docs/conventions.md point 2):

* ``paper``: Delta T = e_s T_s - e_b T_b (Eq. 26), attenuated as
  Delta T(z) = Delta T(0) exp(-sigma z) with sigma read in dB/km as printed (Eq. 31);
* ``physical``: apparent (radiance) temperatures from band-integrated Planck
  radiance; the path transmits tau = 10^(-sigma z / 10) of the radiance
  contrast and adds path radiance of the air at ``air_temperature_k``.
"""

from __future__ import annotations

import numpy as np

from csuas.core.atmosphere import FOG_INFRARED_SOURCE, FOG_LAYER_SOURCE, RAIN_EXTINCTION_SOURCE
from csuas.core.checks import require, require_registry_bounds
from csuas.core.detection import blob_snr, target_pixels
from csuas.core.johnson import ifov_rad, johnson_range_m
from csuas.core.radiometry import band_radiance, graybody_apparent_temperature, radiance_temperature
from csuas.core.result import RangeResult, Term, check_convention
from csuas.core.solve import bracketed_root


def delta_t_linear(emissivity_suas, t_suas_k, emissivity_bg, t_bg_k):
    """Linearised temperature difference (Eq. 26) [K]: e_s T_s - e_b T_b."""
    es = require("emissivity_suas", emissivity_suas, ge=0, le=1)
    eb = require("emissivity_bg", emissivity_bg, ge=0, le=1)
    ts = require("t_suas_k", t_suas_k, gt=0)
    tb = require("t_bg_k", t_bg_k, gt=0)
    return es * ts - eb * tb


def delta_t_radiometric(emissivity_suas, t_suas_k, emissivity_bg, t_bg_k, band="lwir", surroundings_k=None):
    """Apparent temperature difference [K] from band radiometry (physical convention).

    Each surface has the radiance temperature of a graybody (see
    :func:`csuas.core.radiometry.graybody_apparent_temperature`); the result
    is target minus background.
    """
    return graybody_apparent_temperature(
        emissivity_suas, t_suas_k, band, surroundings_k
    ) - graybody_apparent_temperature(emissivity_bg, t_bg_k, band, surroundings_k)


def attenuated_delta_t(
    delta_t0, range_m, extinction_db_km, convention="paper", *, t_bg_app_k=None, air_temperature_k=None, band="lwir"
):
    """Apparent temperature difference [K] after a path of ``range_m``.

    Parameters
    ----------
    delta_t0 : array_like
        Difference at zero range [K] (Eq. 26 or radiometric).
    range_m : array_like
        Path length [m].
    extinction_db_km : array_like
        Path attenuation sigma [dB/km] (Table 27).
    convention : {"paper", "physical"}
        ``paper``: Eq. 31, exp(-sigma z) with sigma as printed.
        ``physical``: radiance contrast times tau = 10^(-sigma z/10), converted
        to temperature about the background's apparent radiance plus path radiance.
    t_bg_app_k, air_temperature_k : array_like, optional
        Background apparent temperature and air temperature [K]; required by ``physical``.
    band : str
        Band of the radiometry (``physical`` only).
    """
    check_convention(convention)
    z_km = require("range_m", range_m, ge=0) / 1000.0
    sigma = require("extinction_db_km", extinction_db_km, ge=0)
    dt0 = np.asarray(delta_t0, dtype=float)
    if convention == "paper":
        return dt0 * np.exp(-sigma * z_km)
    tau = np.power(10.0, -sigma * z_km / 10.0)
    l_bg = band_radiance(t_bg_app_k, band)
    l_target = band_radiance(np.asarray(t_bg_app_k) + dt0, band)
    l_path = (1.0 - tau) * band_radiance(air_temperature_k, band)
    return radiance_temperature(tau * l_target + l_path, band) - radiance_temperature(tau * l_bg + l_path, band)


#: Source of the path attenuation term ``extinction_db_km`` of the MRTD and NETD models (and of the thermal render's
#: path): Table 27's band attenuation, plus under the physical convention the rain and fog, each also listed
#: beside it as its own term (:func:`rain_terms`, :func:`fog_terms`).
EXTINCTION_SOURCE = "Eq. 31 (Table 27; with the rain and fog terms listed beside it, physical convention)"


def path_terms(extinction_db_km, rain_db_km=0.0, fog_db_km=0.0, fog_fraction=None) -> list:
    """The terms of a thermal path as the MRTD and NETD ranges list them (and the thermal render's path).

    Parameters
    ----------
    extinction_db_km : array_like
        Path attenuation [dB/km] (Table 27, with the physical convention's rain and fog); 0 lists no term.
    rain_db_km : array_like
        Its rain part [dB/km] (:func:`csuas.core.atmosphere.rain_extinction_per_km` in dB); 0 lists no term.
    fog_db_km, fog_fraction
        Its fog part and the fog layer's share of the path (:func:`fog_terms`).
    """
    terms = [Term("extinction_db_km", extinction_db_km, "dB/km", EXTINCTION_SOURCE)]
    terms = terms if np.any(np.asarray(extinction_db_km) > 0) else []
    return terms + rain_terms(rain_db_km) + fog_terms(fog_db_km, fog_fraction)


#: Appended to the fog term's source when a fog layer's share of the path scales it.
FOG_LAYERED = ", times the fog layer's share of the path"


def fog_terms(fog_db_km, fog_fraction=None) -> list:
    """The fog terms of a thermal path (physical convention), or none without fog.

    Parameters
    ----------
    fog_db_km : array_like
        The fog's part of ``extinction_db_km`` [dB/km], already scaled by ``fog_fraction``
        (:func:`csuas.core.atmosphere.fog_infrared_extinction_per_km` in dB); 0 lists no term without a layer.
    fog_fraction : array_like or None
        L_fog / R of a fog layer (:func:`csuas.core.atmosphere.fog_path_fraction`), listed as
        ``fog_path_fraction`` with the fog term (0 too: a path above the fog); None: the fog fills the path.
    """
    if fog_fraction is None and not np.any(np.asarray(fog_db_km) > 0):
        return []
    source = FOG_INFRARED_SOURCE + (FOG_LAYERED if fog_fraction is not None else "") + " (in extinction_db_km)"
    terms = [Term("fog_extinction_db_km", fog_db_km, "dB/km", source)]
    if fog_fraction is not None:
        terms.append(Term("fog_path_fraction", fog_fraction, "-", FOG_LAYER_SOURCE))
    return terms


def rain_terms(rain_db_km) -> list:
    """The rain term of a thermal path (its part of ``extinction_db_km``) [dB/km], or none without rain."""
    if not np.any(np.asarray(rain_db_km) > 0):
        return []
    return [Term("rain_extinction_db_km", rain_db_km, "dB/km", RAIN_EXTINCTION_SOURCE + " (in extinction_db_km)")]


#: Arguments of :func:`tir_johnson_range` -> their defaults/parameters.toml entries (upper bounds checked).
TIR_JOHNSON_REGISTRY = {
    "d_crit_m": "target.d_crit_m",
    "hfov_deg": "tir.hfov_deg",
    "n_h": "tir.n_h",
    "lp_task": "tir.lp_task",
    "n_ttpf": "tir.n_ttpf",
}

#: Why a Johnson range is infinite: lp_task x n_ttpf so small (0 when P_desired = 0) that it exceeds float64.
JOHNSON_UNBOUNDED = "unbounded: d_crit_m / (lp_task n_ttpf IFOV) exceeds float64 (check lp_task and n_ttpf)"


def tir_johnson_range(*, d_crit_m, hfov_deg, n_h, lp_task, n_ttpf) -> RangeResult:
    """TIR Johnson/TTPF range (Eq. 23). The paper applies no atmosphere to it."""
    require_registry_bounds(locals(), TIR_JOHNSON_REGISTRY)
    ifov = ifov_rad(hfov_deg, n_h)
    with np.errstate(over="ignore", divide="ignore"):
        r = johnson_range_m(d_crit_m, ifov, lp_task, n_ttpf)
    reason = None if np.all(np.isfinite(r)) else np.where(np.isinf(r), JOHNSON_UNBOUNDED, "")
    return RangeResult(
        r,
        "tir",
        "johnson_ttpf (Eq. 23)",
        [Term("ifov_rad", ifov, "rad", "Eqs. 15, 22"), Term("johnson_range_m", r, "m", "Eq. 23")],
        reason,
    )


def _path_delta_t(signed_dt0, sigma, selected, shape, convention, t_bg_app_k, air_temperature_k, band):
    """Delta T(R) of the ``selected`` (flattened) elements after their path, as a function of R [m]."""
    kwargs = {}
    if convention == "physical":
        kwargs = dict(
            t_bg_app_k=np.broadcast_to(t_bg_app_k, shape).ravel()[selected],
            air_temperature_k=np.broadcast_to(air_temperature_k, shape).ravel()[selected],
            band=band,
        )
    dt0, extinction = signed_dt0[selected], sigma[selected]
    return lambda rr: attenuated_delta_t(dt0, rr, extinction, convention, **kwargs)


#: Arguments of :func:`tir_mrtd_range` -> their defaults/parameters.toml entries (upper bounds checked).
TIR_MRTD_REGISTRY = {
    "d_crit_m": "target.d_crit_m",
    "lp_task": "tir.lp_task",
    "n_ttpf": "tir.n_ttpf",
    "extinction_db_km": "tir.extinction_db_km",
    "t_bg_app_k": "environment.t_bg_k",
    "air_temperature_k": "environment.temperature_k",
}


def tir_mrtd_range(
    *,
    mrtd,
    d_crit_m,
    lp_task,
    n_ttpf,
    delta_t0_k,
    extinction_db_km,
    convention="paper",
    t_bg_app_k=None,
    air_temperature_k=None,
    band="lwir",
) -> RangeResult:
    """TIR range from an MRTD curve with path attenuation (Eqs. 24-31), solved exactly.

    The paper iterates R_hyp until it equals R_MRTD(Delta T(R_hyp)). csuas solves
    Delta T(R) = MRTD(f(R)), f(R) = lp n_TTPF R / d_crit [cy/rad] (Eqs. 24, 29),
    with a bracketed root over arrays: the residual decreases with R, and the
    unattenuated range R0 = d_crit f_max(Delta T0) / (lp n_TTPF) bounds the root
    (R0 itself is the answer where Delta T(R0) still exceeds the curve's end).

    Parameters
    ----------
    mrtd : ParametricMrtd or TabulatedMrtd
        The sensor's MRTD curve.
    d_crit_m, lp_task, n_ttpf : array_like
        Critical dimension [m], line pairs (Table 20), TTPF multiplier (Table 21).
    delta_t0_k : array_like
        Temperature difference at zero range [K]; its magnitude is used.
    extinction_db_km : array_like
        Path attenuation [dB/km] (Table 27); 0 disables the attenuation term.
    convention : {"paper", "physical"}
    t_bg_app_k, air_temperature_k, band
        Radiometric inputs of the physical attenuation (see :func:`attenuated_delta_t`).
    """
    require_registry_bounds(locals(), TIR_MRTD_REGISTRY)
    check_convention(convention)
    d = require("d_crit_m", d_crit_m, ge=0)
    lp = require("lp_task", lp_task, gt=0)
    n = require("n_ttpf", n_ttpf, gt=0)
    sigma = require("extinction_db_km", extinction_db_km, ge=0)
    signed_dt0 = require("delta_t0_k", delta_t0_k)
    shape = np.broadcast_shapes(d.shape, lp.shape, n.shape, sigma.shape, signed_dt0.shape)
    d, lp, n, sigma, signed_dt0 = (np.broadcast_to(v, shape).ravel() for v in (d, lp, n, sigma, signed_dt0))
    dt0 = np.abs(signed_dt0)
    cycles_per_m = lp * n / np.where(d > 0, d, 1.0)
    r0 = mrtd.max_frequency(dt0) / cycles_per_m
    r = r0.copy()
    attenuated = (sigma > 0) & (r0 > 0) & (d > 0)
    if np.any(attenuated):
        delta_t_at = _path_delta_t(
            signed_dt0, sigma, attenuated, shape, convention, t_bg_app_k, air_temperature_k, band
        )

        def residual(rr):
            return np.abs(delta_t_at(rr)) - mrtd(cycles_per_m[attenuated] * rr)

        root, found = bracketed_root(residual, np.zeros(int(attenuated.sum())), r0[attenuated], rtol=1e-12)
        # No sign change: Delta T still exceeds the MRTD at R0, where the curve
        # ends (Nyquist or table end), so R0 itself is the range.
        r[attenuated] = np.where(found, root, r0[attenuated])
    r = np.where(d > 0, r, 0.0)
    r, r0, sigma, attenuated, cycles_per_m = (v.reshape(shape) for v in (r, r0, sigma, attenuated, cycles_per_m))
    reason = np.where(
        r <= 0,
        "never detectable: Delta T below the MRTD at every range",
        np.where(attenuated, "MRTD with attenuation (Eqs. 27-31)", "MRTD (Eq. 29)"),
    )
    terms = [
        Term(
            "delta_t0_k",
            np.asarray(delta_t0_k, dtype=float),
            "K",
            "Eq. 26" if convention == "paper" else "band radiometry",
        ),
        Term("mrtd_range_unattenuated_m", r0, "m", "Eq. 29"),
    ]
    if np.any(sigma > 0):
        terms.append(Term("extinction_db_km", sigma, "dB/km", EXTINCTION_SOURCE))
        dt_r = np.where(r > 0, mrtd(cycles_per_m * r), 0.0)
        terms.append(Term("mrtd_at_range_k", dt_r, "K", "Eq. 27"))
    return RangeResult(r, "tir", "mrtd (Eqs. 24-31)", terms, reason)


def tir_netd_range(
    *,
    projected_area_m2,
    ifov_rad_,
    netd_mk,
    required_snr,
    delta_t0_k,
    extinction_db_km,
    convention="paper",
    t_bg_app_k=None,
    air_temperature_k=None,
    band="lwir",
) -> RangeResult:
    """NETD-limited TIR range: where the blob SNR with NETD as the noise falls to ``required_snr``.

    The SNR is :func:`csuas.core.detection.blob_snr` of the apparent Delta T over the target's pixels.

    Unattenuated it has a closed form in each regime: R0 = |Delta T0| sqrt(A) / (NETD IFOV SNR_req)
    while the target covers a pixel or more, R0 = sqrt(|Delta T0| A / (NETD SNR_req)) / IFOV below;
    with path attenuation the SNR falls faster and the range is the bracketed root in [0, R0].

    Parameters
    ----------
    projected_area_m2 : array_like
        Projected area of the target [m^2].
    ifov_rad_ : array_like
        Pixel IFOV [rad] (pitch / focal length).
    netd_mk : array_like
        NETD [mK], > 0.
    required_snr : array_like
        SNR the detection needs, >= 0 (Q^-1(Pfa) - Q^-1(p_desired) for a Gaussian threshold): 0 detects
        at any range, +inf at none.
    delta_t0_k, extinction_db_km, convention, t_bg_app_k, air_temperature_k, band
        As in :func:`tir_mrtd_range`.
    """
    check_convention(convention)
    a = require("projected_area_m2", projected_area_m2, ge=0)
    w = require("ifov_rad", ifov_rad_, gt=0)
    netd = require("netd_mk", netd_mk, gt=0) / 1000.0
    snr_req = require("required_snr", required_snr, ge=0, allow_inf=True)
    sigma = require("extinction_db_km", extinction_db_km, ge=0)
    signed_dt0 = require("delta_t0_k", delta_t0_k)
    shape = np.broadcast_shapes(a.shape, w.shape, netd.shape, snr_req.shape, sigma.shape, signed_dt0.shape)
    a, w, netd, snr_req, sigma, signed_dt0 = (
        np.broadcast_to(v, shape).ravel() for v in (a, w, netd, snr_req, sigma, signed_dt0)
    )
    dt0 = np.abs(signed_dt0)
    with np.errstate(divide="ignore", invalid="ignore"):  # SNR 0 needed: any range; inf: none
        resolved = np.where(dt0 * a > 0, dt0 * np.sqrt(a) / (netd * w * snr_req), 0.0)
        resolved_ok = a / np.square(w * np.where((resolved > 0) & np.isfinite(resolved), resolved, 1.0)) >= 1.0
        sub_pixel = np.where(dt0 * a > 0, np.sqrt(dt0 * a / (netd * snr_req)) / w, 0.0)
    r0 = np.where(np.isinf(resolved) | ((resolved > 0) & resolved_ok), resolved, sub_pixel)
    r = r0.copy()
    attenuated = (sigma > 0) & (r0 > 0) & np.isfinite(snr_req) & (snr_req > 0)
    if np.any(attenuated):
        delta_t_at = _path_delta_t(
            signed_dt0, sigma, attenuated, shape, convention, t_bg_app_k, air_temperature_k, band
        )

        def residual(rr):
            pixels = target_pixels(a[attenuated], w[attenuated], rr)
            return blob_snr(delta_t_at(rr), netd[attenuated], pixels) - snr_req[attenuated]

        root, found = bracketed_root(residual, np.full(int(attenuated.sum()), 1e-9), r0[attenuated], rtol=1e-12)
        r[attenuated] = np.where(found, root, r0[attenuated])
    r, r0 = r.reshape(shape), r0.reshape(shape)
    reason = np.where(
        r <= 0,
        "never detectable: no Delta T, no target area, or a certainty (p_desired = 1) no noise allows",
        "NETD-limited (blob SNR)",
    )
    terms = [
        Term(
            "delta_t0_k",
            np.asarray(delta_t0_k, dtype=float),
            "K",
            "Eq. 26" if convention == "paper" else "band radiometry",
        ),
        Term("required_snr", snr_req.reshape(shape), "-", "Gaussian threshold: Q^-1(Pfa) - Q^-1(p_desired)"),
        Term("netd_range_unattenuated_m", r0, "m", "|Delta T0| sqrt(A) / (NETD IFOV SNR)"),
    ]
    if np.any(sigma > 0):
        terms.append(Term("extinction_db_km", sigma.reshape(shape), "dB/km", EXTINCTION_SOURCE))
    return RangeResult(r, "tir", "netd (blob SNR, extension)", terms, reason)
