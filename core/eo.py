"""Electro-optical detection range: Johnson/TTPF (Eq. 18) limited by contrast (Eq. 21) and by light.

The paper's procedure (Section 4.3.3) starts from the Johnson range and
reduces it until the attenuated contrast C0 tau(R) reaches C_min. Its exact
solution is the minimum of the Johnson range and the contrast-limited range
where C0 tau(R) = C_min, which has a closed form for both conventions. In the
physical convention a camera given as a radiometric instrument
(:mod:`csuas.core.camera`) adds the light-limited range, so the illuminance of
Tables 10-11 changes the EO range.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.atmosphere import (
    FOG_LAYER_SOURCE,
    RAIN_EXTINCTION_SOURCE,
    extinction_per_km,
    range_for_transmittance,
    transmittance,
)
from csuas.core.camera import light_limited_range_m
from csuas.core.checks import require, require_registry_bounds
from csuas.core.johnson import ifov_rad, johnson_range_m
from csuas.core.result import RangeResult, Term, check_convention


def contrast_limited_range_m(c0, c_min, extinction, convention="paper"):
    """Range [m] where the attenuated contrast C0 tau(R) falls to C_min (Eq. 21).

    Parameters
    ----------
    c0 : array_like
        Inherent contrast magnitude |C0| (Eq. 3), 0..1.
    c_min : array_like
        Minimum detectable contrast, > 0.
    extinction : array_like
        Kruse extinction (Eq. 19), read as dB/km (paper) or 1/km (physical).
    convention : {"paper", "physical"}

    Returns
    -------
    ndarray
        Range [m]: 0 where |C0| <= C_min (never detectable), +inf without extinction.
    """
    c0 = np.abs(require("c_eo", c0, ge=-1, le=1))
    cm = require("c_min", c_min, gt=0, le=1)
    ratio = np.where(c0 > cm, cm / np.where(c0 > 0, c0, 1.0), 1.0)
    r = range_for_transmittance(extinction, ratio, convention)
    return np.where(c0 > cm, r, 0.0)


#: Source of the extinction term per convention (csuas.core.atmosphere.extinction_per_km).
EXTINCTION_SOURCE = {
    "paper": "Eqs. 19-20 (Kim's q, which steps from 1.3 to 1.6 at 50 km visibility)",
    "physical": "Koschmieder with Rayleigh (Bucholtz 1995) and aerosol (Kim's q, no 50 km step) parts",
}


#: Arguments of :func:`eo_range` -> their defaults/parameters.toml entries (upper bounds checked).
EO_REGISTRY = {
    "d_crit_m": "target.d_crit_m",
    "hfov_deg": "eo.hfov_deg",
    "n_h": "eo.n_h",
    "lp_task": "eo.lp_task",
    "n_ttpf": "eo.n_ttpf",
    "c_eo": "target.c_eo",
    "c_min": "eo.c_min",
    "wavelength_nm": "eo.wavelength_nm",
    "visibility_km": "environment.visibility_km",
}


#: Appended to the extinction term's source when a fog layer averages it along the path.
LAYERED = ", path average over the fog layer"


def _layered_extinction(sigma_fog, wavelength_nm, fog_layer, convention):
    """Extinction [1/km] averaged along a slant path that crosses a fog layer, and its term (:func:`eo_range`)."""
    if fog_layer is None:
        return sigma_fog, []
    if convention == "paper":
        raise ParameterError("fog_layer", fog_layer, "None in the paper convention (its fog fills the path)")
    fraction = require("fog_path_fraction", fog_layer[0], ge=0, le=1)
    clear = extinction_per_km(wavelength_nm, fog_layer[1], convention)
    return fraction * sigma_fog + (1.0 - fraction) * clear, [Term("fog_path_fraction", fraction, "-", FOG_LAYER_SOURCE)]


def path_extinction(wavelength_nm, visibility_km, convention="paper", rain_extinction_per_km=0.0, fog_layer=None):
    """Extinction of an EO sensor's path and its terms, as :func:`eo_range` applies them and the render's path does.

    Parameters
    ----------
    wavelength_nm, visibility_km, convention, rain_extinction_per_km, fog_layer
        As in :func:`eo_range`.

    Returns
    -------
    (ndarray, list of Term)
        The total extinction (dB/km read by ``paper``, 1/km by ``physical``: Kruse's, path-averaged over a fog
        layer, plus the rain's) and its terms: ``kruse_extinction``, then ``fog_path_fraction`` with a fog
        layer and ``rain_extinction_per_km`` with rain.
    """
    sigma = extinction_per_km(wavelength_nm, visibility_km, convention)
    rain = require("rain_extinction_per_km", rain_extinction_per_km, ge=0)
    if np.any(rain > 0) and convention == "paper":
        raise ParameterError("rain_extinction_per_km", float(np.max(rain)), "0 in the paper convention (no rain term)")
    sigma, layer_terms = _layered_extinction(sigma, wavelength_nm, fog_layer, convention)
    unit = "dB/km" if convention == "paper" else "1/km"
    source = EXTINCTION_SOURCE[convention] + (LAYERED if layer_terms else "")
    terms = [Term("kruse_extinction", sigma, unit, source), *layer_terms]
    if np.any(rain > 0):
        terms.append(Term("rain_extinction_per_km", rain, "1/km", RAIN_EXTINCTION_SOURCE))
    return sigma + rain, terms


def eo_range(
    *,
    d_crit_m,
    hfov_deg,
    n_h,
    lp_task,
    n_ttpf,
    c_eo,
    c_min,
    wavelength_nm,
    visibility_km,
    convention="paper",
    camera=None,
    rain_extinction_per_km=0.0,
    fog_layer=None,
) -> RangeResult:
    """EO detection range: min(Johnson/TTPF, contrast limit) (Eqs. 15-21).

    Parameters
    ----------
    d_crit_m : array_like
        Critical dimension [m] (Table 8).
    hfov_deg, n_h : array_like
        Horizontal field of view [deg] and pixels (Table 22).
    lp_task, n_ttpf : array_like
        Line pairs (Table 20) and TTPF multiplier (Table 21).
    c_eo, c_min : array_like
        Inherent and minimum contrast (Table 24).
    wavelength_nm, visibility_km : array_like
        Sensor wavelength [nm] and visibility [km] for the Kruse extinction
        (Eqs. 19-20); in fog, the fog visibility.
    convention : {"paper", "physical"}
        How the Kruse coefficient enters Beer-Lambert (docs/conventions.md point 1).
    camera : dict, optional
        Physical convention only: the keyword arguments of
        :func:`csuas.core.camera.light_limited_range_m` other than ``c_eo``, ``ifov_rad_`` and
        ``transmittance_at`` (``camera``: a :class:`csuas.core.camera.CameraChain`); adds the
        light-limited range (scalar inputs).
    rain_extinction_per_km : array_like
        Physical convention only: extinction of rain [1/km]
        (:func:`csuas.core.atmosphere.rain_extinction_per_km`), added to Kruse's; 0 adds no term.
    fog_layer : tuple of (array_like, array_like), optional
        Physical convention only: (L_fog / R, clear visibility [km]) of a fog layer the slant path crosses
        (:func:`csuas.core.atmosphere.fog_path_fraction`); the extinction is then the path average
        f beta(V_fog) + (1 - f) beta(V_clear). None: the fog (``visibility_km``) fills the path.

    Returns
    -------
    RangeResult
        ``range_m`` and the terms: Johnson range, extinction, contrast-limited
        range; ``reason`` names the limiting factor per element.
    """
    require_registry_bounds(locals(), EO_REGISTRY)
    check_convention(convention)
    ifov = ifov_rad(hfov_deg, n_h)
    r_johnson = johnson_range_m(d_crit_m, ifov, lp_task, n_ttpf)
    sigma, path_terms = path_extinction(wavelength_nm, visibility_km, convention, rain_extinction_per_km, fog_layer)
    r_contrast = contrast_limited_range_m(c_eo, c_min, sigma, convention)
    r = np.minimum(r_johnson, r_contrast)
    reason = np.where(
        r_contrast <= 0,
        "never detectable: |c_eo| <= c_min",
        np.where(r_contrast < r_johnson, "contrast-limited (Eq. 21)", "resolution-limited (Eq. 18)"),
    )
    terms = [
        Term("ifov_rad", ifov, "rad", "Eq. 15"),
        Term("johnson_range_m", r_johnson, "m", "Eq. 18"),
        *path_terms,
        Term("contrast_limited_range_m", r_contrast, "m", "Eq. 21"),
    ]
    model = "johnson_ttpf+contrast (Eqs. 18, 21)"
    if camera is not None and convention == "physical":
        r_light, chain = light_limited_range_m(
            c_eo=c_eo,
            ifov_rad_=float(ifov),
            transmittance_at=lambda rr: transmittance(sigma, rr, convention),
            **camera,
        )
        reason = np.where((r_light < r) | ((r_light <= 0) & (r_contrast > 0)), "light-limited (camera noise)", reason)
        r = np.minimum(r, r_light)
        terms += [
            Term("background_electrons", chain["background_e"], "e", "camera equation, auto-exposure"),
            Term("exposure_s", chain["exposure_s"], "s", "auto-exposure (half full well, max_exposure_ms)"),
            Term("pixel_noise_electrons", chain["noise_e"], "e", "shot + dark + read (EMVA 1288)"),
            Term("light_limited_range_m", r_light, "m", "blob SNR = Q^-1(Pfa) - Q^-1(p_desired)"),
        ]
        model = "johnson_ttpf+contrast+light (Eqs. 18, 21; camera chain)"
    return RangeResult(r, "eo", model, terms, reason)
