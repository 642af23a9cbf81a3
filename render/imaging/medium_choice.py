"""Which path an EO render takes through fog, its medium, and what each costs: the analytic path or the medium.

The EO render applies its path analytically (:mod:`csuas.render.imaging.path`): L = L0 tau + L_h (1 - tau)
(Koschmieder 1924). That is the exact solution of the transfer equation on a path whose source function is
uniform and equal to the horizon sky L_h. It is an approximation where

* a fog layer's top lies between the sensor and the drone: the source function changes along the slant path
  (the analytic path averages the extinction, :func:`csuas.core.atmosphere.fog_path_fraction`);
* the sky is not uniform: the fog's single-scattered source of sun, sky and ground
  (:func:`single_scatter_source`) differs from L_h by more than :data:`SOURCE_SHARE_LIMIT` of the background
  after the path, or the ground, not the horizon sky, lies behind the drone (the sensor above it, the ground's
  luminance differing from the sky's);
* the optical depth is large enough that light scattered forward by the droplets near the drone lands on the
  drone's own pixels and blurs it: :func:`blur_share` (single scattering of a Henyey-Greenstein phase function),
  above :data:`BLUR_SHARE_LIMIT` of the directly transmitted light (with g 0.85 and the default camera's
  IFOV of 9.09e-5 rad, from a scattering optical depth of 16.9).

There the medium is the more faithful model, but a Monte Carlo one: at a low quality its noise can exceed the
analytic path's error. ``--atmosphere-method auto`` therefore compares the two on the contrast scale
(:func:`compare_errors`): the analytic path's approximation error estimated with the single-scattered source
(:func:`analytic_error`) against the medium's standard error predicted before any trace (:func:`medium_stderr`,
a noise model calibrated on medium renders), and traces the medium only where :data:`MEDIUM_CONFIDENCE` times
its predicted standard error at the requested quality lies below the analytic error; otherwise it keeps the
analytic path, lists the approximation and names the quality at which the medium would be the more accurate.
The medium itself is traced by :mod:`csuas.render.imaging.medium_path`; :func:`render_estimate` is the cost
of renders before any.

References: Koschmieder, Beitr. Phys. fr. Atmos. 12 (1924); Henyey & Greenstein, ApJ 93, 70 (1941); Hess, Koepke
& Schult, Bull. Am. Meteor. Soc. 79, 831 (1998) (OPAC: water droplets of fog and cloud at 550 nm, asymmetry
parameter 0.85-0.87, single-scattering albedo 1.000).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from csuas.base.cost import Estimate
from csuas.base.errors import ParameterError
from csuas.core.atmosphere import extinction_per_km
from csuas.drone_models.geometry import direction_vector
from csuas.drone_models.silhouette import projected_metrics
from csuas.render.imaging.common import prepare
from csuas.render.imaging.eo import LUMINANCE_WEIGHTS, sun_and_sky
from csuas.render.imaging.quality import resolve_quality
from csuas.render.imaging.records import Daylight, EoSensor, FogLayer, View
from csuas.render.imaging.scene import target_parts
from csuas.render.request import ATMOSPHERE_METHODS

#: Choices of ``csuas render --atmosphere-method``.
METHODS = ATMOSPHERE_METHODS

#: Henyey-Greenstein asymmetry of fog droplets at 550 nm (OPAC, Hess et al. 1998: 0.85-0.87).
FOG_ASYMMETRY_G = 0.85

#: Single-scattering albedo of water droplets in the visible (OPAC: 1.000; water's k ~ 2e-9 at 550 nm).
FOG_ALBEDO = 1.0

#: ``auto`` takes the medium where the forward-scattered light on the drone's pixels passes this share of its
#: directly transmitted light (:func:`blur_share`).
BLUR_SHARE_LIMIT = 0.01

#: ``auto`` takes the medium where the single-scattered source of the fog differs from the horizon sky of the
#: airlight by more than this share of the background's luminance, after the path (:func:`single_scatter_source`).
SOURCE_SHARE_LIMIT = 0.1

#: Directions of the quadrature of :func:`single_scatter_source`: cosines of the polar angle, azimuths.
SOURCE_GRID = (400, 128)

#: Without a fog top, the fog reaches this share of the camera distance above the higher of camera and drone.
SCENE_TOP_MARGIN = 0.1

#: Half width of the fog's box, and its depth below the lower of camera and drone, in camera distances.
BOX_HALF_WIDTH = 4.0

#: ``auto`` takes the medium where this many of its predicted standard errors lie below the analytic path's
#: estimated error (two: the medium's error is then the smaller at about 95 % confidence).
MEDIUM_CONFIDENCE = 2.0

#: Noise model of the medium's trace (:func:`medium_stderr`): relative standard deviation of one camera ray's
#: luminance, s = a + b x on the drone's pixels and on the background, x = E_sun / (pi J1) the sun's normal
#: irradiance against the fog's single-scattered source (:func:`single_scatter_source`). Least squares on eight
#: draft medium renders of the default drone (150 m at visibility 1, 0.4, 0.2, 0.1 km under the default sun,
#: diffuse share 0.15; 0.4 and 0.1 km under a uniform sky; 150 and 250 m at 0.3 km with diffuse share 0.6; seed 0
#: and 3, load average 9-10, 1.8-4.0 s each), s from each render's jackknife standard errors of the drone's and
#: the background's luminance times the square root of their rays. Over optical depths 0.5-5.9 a power of the
#: optical depth (tau^0.3, tau^0.5) fitted worse (predicted/measured 0.43-2.25 against 0.67-1.95).
NOISE_TARGET, NOISE_BACKGROUND = (0.34, 0.46), (0.34, 0.61)

#: Rays per launch of the medium's tracer (its paths hold more state than the vacuum's).
MEDIUM_LAUNCH = 1 << 18


@dataclass(frozen=True)
class FogMedium:
    """The participating medium of an EO render.

    Attributes
    ----------
    beta_per_km : float
        Extinction of the fog (or of the uniform air) [1/km].
    clear_beta_per_km : float
        Extinction of the clear air above a fog layer's top [1/km] (unused without a top).
    top_above_target_m : float or None
        Height of the fog's top above the drone [m]; None: the fog fills the scene (module docstring).
    g, albedo : float
        Henyey-Greenstein asymmetry and single-scattering albedo.
    """

    beta_per_km: float
    clear_beta_per_km: float = 0.0
    top_above_target_m: float | None = None
    g: float = FOG_ASYMMETRY_G
    albedo: float = FOG_ALBEDO


@dataclass(frozen=True)
class ErrorComparison:
    """``auto``'s comparison of the two paths on the contrast scale (:func:`compare_errors`).

    Attributes
    ----------
    quality : str
        The requested quality's name.
    analytic_error : float
        Estimated error of the analytic path's contrast [-] (:func:`analytic_error`), the sum of ``terms``.
    terms : tuple of dict
        Its parts (``name``, ``value``, ``source``).
    medium_stderr : float
        Predicted standard error of the medium's contrast at ``quality`` [-] (:func:`medium_stderr`).
    suggested_quality : str or None
        The lowest quality at which the medium would be the more accurate (None: none of the presets).
    suggested_seconds : float or None
        Its estimated time of the medium's trace [s] (:func:`render_estimate`'s constants).
    """

    quality: str
    analytic_error: float
    terms: tuple
    medium_stderr: float
    suggested_quality: str | None
    suggested_seconds: float | None

    @property
    def medium_wins(self) -> bool:
        """Whether the medium is the more accurate at the requested quality (module docstring)."""
        return MEDIUM_CONFIDENCE * self.medium_stderr < self.analytic_error

    def sentence(self) -> str:
        """The decision in words, with both error figures."""
        figures = (
            f"the analytic path's estimated contrast error {self.analytic_error:.3g} against "
            f"{MEDIUM_CONFIDENCE:g} x the medium's predicted standard error {self.medium_stderr:.3g} at {self.quality}"
        )
        if self.medium_wins:
            return f"auto: the medium is the more accurate: {figures}"
        if self.suggested_quality is None:
            return f"auto: analytic, the more accurate at every quality: {figures}"
        return (
            f"auto: analytic, the more accurate at this quality: {figures}; --atmosphere-method medium --quality "
            f"{self.suggested_quality} (about {self.suggested_seconds:.3g} s of tracing) would remove the approximation"
        )

    def as_dict(self) -> dict:
        """JSON form: both errors with their sources, the confidence factor and the suggested quality."""
        return {
            "quality": self.quality,
            "analytic_error": {
                "name": "contrast_error_estimate",
                "value": self.analytic_error,
                "unit": "-",
                "terms": list(self.terms),
                "source": "single-scattered source of the fog (sun, sky, ground) in place of the horizon sky, "
                "render/imaging/medium_choice.py analytic_error",
            },
            "medium_stderr": {
                "value": self.medium_stderr,
                "unit": "-",
                "source": "noise model of the medium's trace calibrated on medium renders (medium_stderr)",
            },
            "confidence": MEDIUM_CONFIDENCE,
            "suggested_quality": self.suggested_quality,
            "suggested_seconds": self.suggested_seconds,
        }


@dataclass(frozen=True)
class MethodChoice:
    """Which path a render takes and why: ``method`` (``analytic`` or ``medium``), ``reasons`` (words),
    the ``medium`` it traces (None for analytic), the forward-scatter ``blur_share`` of its line of sight and
    ``auto``'s ``comparison`` of the two paths' errors (None where it made none)."""

    method: str
    reasons: tuple
    medium: FogMedium | None
    blur_share: float
    comparison: ErrorComparison | None = None

    def as_dict(self) -> dict:
        """JSON form (``method``, ``reasons``, ``blur_share``, the comparison, and the medium's coefficients)."""
        out = {"method": self.method, "reasons": list(self.reasons), "blur_share": self.blur_share}
        if self.comparison is not None:
            out["comparison"] = self.comparison.as_dict()
        if self.medium is not None:
            m = self.medium
            out["medium"] = {
                "extinction_per_km": m.beta_per_km,
                "clear_extinction_per_km": m.clear_beta_per_km if m.top_above_target_m is not None else None,
                "fog_top_above_target_m": m.top_above_target_m,
                "phase_function": "henyey_greenstein",
                "g": m.g,
                "albedo": m.albedo,
                "source": "extinction: csuas.core.atmosphere.extinction_per_km (Kruse/Kim, Eqs. 19-20) + rain, as "
                "csuas range; g and albedo of fog droplets at 550 nm (OPAC, Hess et al. 1998)",
            }
        return out


def _cone_share(tan_theta: float, g: float) -> float:
    """Share of Henyey-Greenstein scattering within theta of the forward direction (its closed-form cumulative
    distribution in cos theta), for theta given by its tangent."""
    mu = 1.0 / math.sqrt(1.0 + tan_theta * tan_theta)
    if g == 0.0:
        return (1.0 - mu) / 2.0
    return (1.0 - g * g) / (2.0 * g) * (1.0 / (1.0 - g) - (1.0 + g * g - 2.0 * g * mu) ** -0.5)


def blur_share(scattering_depth: float, ifov_rad: float, g: float = FOG_ASYMMETRY_G) -> float:
    """Share of a target's light scattered forward once onto its own image within one pixel, per directly
    transmitted share (Henyey-Greenstein phase function, uniform scattering along the path).

    Light scattered at a distance x in front of the target by the angle theta appears displaced by
    x tan(theta) / R; it stays within alpha of the image where tan(theta) < alpha R / x. With P(theta) the
    phase function's share within theta (:func:`_cone_share`), the share scattered in dx is beta_s dx
    P(atan(alpha R / x)); with u = alpha R / x the integral over 0 < x < R is
    tau_s alpha I(g), I(g) = int_alpha^inf P(atan u) / u^2 du, taken from 0 for alpha much below 1 rad
    (the integrand tends to p(0) pi = (1 + g) / (4 (1 - g)^2) at u = 0).

    Parameters
    ----------
    scattering_depth : float
        Scattering optical depth of the line of sight tau_s = beta_s R [-].
    ifov_rad : float
        The pixel's angle alpha [rad].
    g : float
        Asymmetry parameter, -1 < g < 1.
    """
    from scipy import integrate

    near, _ = integrate.quad(
        lambda u: _cone_share(u, g) / (u * u) if u > 0 else (1.0 + g) / (4.0 * (1.0 - g) ** 2), 0.0, 1.0
    )
    far, _ = integrate.quad(lambda u: _cone_share(u, g) / (u * u), 1.0, math.inf)
    return float(scattering_depth) * float(ifov_rad) * (near + far)


def _hg(cos_theta, g: float):
    """Henyey-Greenstein phase function [1/sr] (Henyey & Greenstein 1941)."""
    return (1.0 - g * g) / (4.0 * np.pi * (1.0 + g * g - 2.0 * g * cos_theta) ** 1.5)


def single_scatter_source(light: Daylight, view: View, g: float = FOG_ASYMMETRY_G) -> float:
    """The fog's source function for single scattering toward the sensor [cd m^-2]: the render's sky (above the
    horizon), ground (below) and sun scattered by the phase function into the line of sight,
    J1 = int L(w) p(-w . d) dw + E_sun p(-s . d), with d the direction from the drone toward the sensor and s
    toward the sun. Koschmieder's airlight takes the horizon sky L_h instead (exact for a uniform sky: J1 = L_h).
    """
    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    d = direction_vector(view.azimuth_deg, view.elevation_deg)
    n_mu, n_phi = SOURCE_GRID
    mu = (np.arange(n_mu) + 0.5) / n_mu * 2.0 - 1.0  # cosine of each source direction's angle from the zenith
    phi = (np.arange(n_phi) + 0.5) / n_phi * 2.0 * np.pi
    sin = np.sqrt(1.0 - mu * mu)[:, None]
    w = np.stack([sin * np.cos(phi), sin * np.sin(phi), np.broadcast_to(mu[:, None], (n_mu, n_phi))], axis=-1)
    radiance = np.where(mu > 0.0, sky["sky_radiance"], sky["ground_radiance"])[:, None]
    weight = (2.0 / n_mu) * (2.0 * np.pi / n_phi)
    diffuse = float(np.sum(radiance * _hg(-(w @ d), g)) * weight)
    sun_az = view.azimuth_deg if light.sun_azimuth_deg is None else light.sun_azimuth_deg
    to_sun = direction_vector(sun_az, light.sun_elevation_deg)
    return diffuse + sky["sun_irradiance_lx"] * float(_hg(-float(to_sun @ d), g))


def _fog_beta(light: Daylight, sensor: EoSensor) -> tuple[float, float]:
    """Extinction of the fog (the render's visibility) and of the clear air above a layer [1/km], rain added."""
    fog = float(extinction_per_km(sensor.wavelength_nm, light.visibility_km, "physical"))
    clear = 0.0
    layer = light.fog_layer  # a FogLayer, or a (share, clear visibility [km]) pair given as such
    clear_km = layer.clear_visibility_km if isinstance(layer, FogLayer) else None if layer is None else layer[1]
    if clear_km is not None and math.isfinite(clear_km):
        clear = float(extinction_per_km(sensor.wavelength_nm, clear_km, "physical"))
    return fog + light.rain_extinction_per_km, clear + light.rain_extinction_per_km


def fog_medium(light: Daylight, sensor: EoSensor, fog_top_above_target_m: float | None) -> FogMedium:
    """The medium of a render's path: the core's extinction (:func:`_fog_beta`), the layer's top, fog droplets."""
    beta, clear = _fog_beta(light, sensor)
    return FogMedium(beta, clear, fog_top_above_target_m if light.fog_layer is not None else None)


def choose_method(
    requested: str,
    light: Daylight,
    view: View,
    sensor: EoSensor,
    fog_top_above_target_m: float | None,
    weather: bool,
    target=None,
    quality="standard",
) -> MethodChoice:
    """The path a render takes: ``analytic``, ``medium``, or ``auto`` = the medium where the analytic path is an
    approximation (module docstring), the scenario declares weather (fog, a fog layer, rain or a visibility) and
    the medium is the more accurate at the requested quality (:func:`compare_errors`), the analytic path otherwise.

    Parameters
    ----------
    requested : {"auto", "analytic", "medium"}
    light : Daylight
        With the path's visibility (None: the atmosphere is off), rain, fog layer and convention.
    view : View
        The sensor stands ``range_m sin(elevation_deg)`` above the drone.
    sensor : EoSensor
    fog_top_above_target_m : float or None
        The fog layer's top above the drone [m] (None: no layer).
    weather : bool
        Whether the scenario declares weather (:attr:`csuas.core.scenario.Scenario.effects`).
    target : str, Drone or list of parts
        What the render traces (``auto``'s comparison needs it where the analytic path is an approximation).
    quality : str or Quality
        The render's quality (``auto``'s comparison).

    Raises
    ------
    ParameterError
        ``atmosphere_method``: not a choice, or ``medium`` without a path or under the paper convention;
        ``target``: none given where ``auto`` compares the two paths.
    """
    if requested not in METHODS:
        raise ParameterError("atmosphere_method", requested, ", ".join(METHODS))
    if requested == "analytic":
        return MethodChoice("analytic", ("requested",), None, 0.0)
    usable = light.visibility_km is not None and light.convention == "physical"
    if requested == "medium" and not usable:
        raise ParameterError(
            "atmosphere_method",
            requested,
            "analytic or auto (the medium needs the path on and the physical convention)",
        )
    if not (usable and weather):
        why = "no weather declared" if not weather else "no path, or the paper convention's (Eq. 10 as printed)"
        return MethodChoice("analytic", (f"auto: {why}",), None, 0.0)
    medium = fog_medium(light, sensor, fog_top_above_target_m)
    ifov = math.radians(sensor.hfov_deg) / sensor.n_h
    share = blur_share(medium.albedo * _line_of_sight_depth(medium, view), ifov, medium.g)
    reasons = _approximations(light, view, medium, share)
    if requested == "medium":
        return MethodChoice("medium", ("requested", *reasons), medium, share)
    if not reasons:
        return MethodChoice("analytic", ("auto: Koschmieder's uniform path holds",), None, share)
    if target is None:
        raise ParameterError("target", None, "the rendered target (auto compares the two paths' errors)")
    comparison = compare_errors(target, light, view, sensor, medium, share, quality)
    reasons = (*reasons, comparison.sentence())
    if comparison.medium_wins:
        return MethodChoice("medium", reasons, medium, share, comparison)
    return MethodChoice("analytic", reasons, None, share, comparison)


def _line_of_sight_depth(medium: FogMedium, view: View) -> float:
    """Optical depth of the line of sight in the fog [-] (a layer: the share of the path below its top)."""
    r_km = view.range_m / 1000.0
    top = medium.top_above_target_m
    if top is None:
        return medium.beta_per_km * r_km
    rise = view.range_m * math.sin(math.radians(view.elevation_deg))  # sensor above the drone [m]
    low, high = min(0.0, rise), max(0.0, rise)
    if high - low <= 0.0:
        share = 1.0 if top > 0.0 else 0.0
    else:
        share = min(max((top - low) / (high - low), 0.0), 1.0)
    return medium.beta_per_km * r_km * share + medium.clear_beta_per_km * r_km * (1.0 - share)


def _approximations(light: Daylight, view: View, medium: FogMedium, share: float) -> tuple:
    """Where Koschmieder's uniform path is an approximation on this render (module docstring), in words."""
    reasons = []
    top = medium.top_above_target_m
    rise = view.range_m * math.sin(math.radians(view.elevation_deg))
    if top is not None and min(0.0, rise) < top < max(0.0, rise):
        reasons.append(f"the slant path crosses the fog's top ({top:.4g} m above the drone, the sensor {rise:.4g} m)")
    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    if view.elevation_deg > 0.0 and sky["ground_radiance"] != sky["sky_radiance"]:
        reasons.append(
            f"the ground ({sky['ground_radiance']:.4g} cd/m^2) lies behind the drone, not the horizon sky "
            f"({sky['sky_radiance']:.4g} cd/m^2) of the airlight"
        )
    tau = math.exp(-_line_of_sight_depth(medium, view))
    source = single_scatter_source(light, view, medium.g)
    if abs(source - sky["sky_radiance"]) * (1.0 - tau) > SOURCE_SHARE_LIMIT * sky["sky_radiance"]:
        reasons.append(
            f"the sky is not uniform: the fog scatters {source:.4g} cd/m^2 of sun, sky and ground into the line of "
            f"sight (single scattering), not the horizon sky's {sky['sky_radiance']:.4g} of the airlight"
        )
    if share > BLUR_SHARE_LIMIT:
        reasons.append(
            f"forward-scattered light on the drone's pixels {share:.3g} of the direct (> {BLUR_SHARE_LIMIT:g})"
        )
    return tuple(reasons)


def _inherent_luminance(target, light: Daylight, view: View) -> tuple[float, float]:
    """The drone's and the background's luminance in vacuum, before any render [cd m^-2].

    The drone: its parts' surface-area weighted luminance reflectance (:data:`LUMINANCE_WEIGHTS` of
    ``reflectance_rgb``) times the irradiance of a face turned to the sensor over pi (the sun at its angle to the
    line of sight, half the sky and half the ground: the plate of validation/imaging/weather.py). A rough figure
    (the default drone at 150 m: 3236 against the render's 2818 cd/m^2); the error estimate depends on it only
    through the drone's contrast. The background: the ground where the sensor looks down on the drone, else the sky.
    """
    parts = target_parts(target)
    area = np.array([float(p.mesh.area) for p in parts])
    rho = np.array([float(np.dot(LUMINANCE_WEIGHTS, p.material.reflectance_rgb)) for p in parts])
    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    d = direction_vector(view.azimuth_deg, view.elevation_deg)
    sun_az = view.azimuth_deg if light.sun_azimuth_deg is None else light.sun_azimuth_deg
    cos_sun = max(0.0, float(direction_vector(sun_az, light.sun_elevation_deg) @ d))
    irradiance = sky["sun_irradiance_lx"] * cos_sun + math.pi * (sky["sky_radiance"] + sky["ground_radiance"]) / 2.0
    background = sky["ground_radiance"] if view.elevation_deg > 0.0 else sky["sky_radiance"]
    return float(area @ rho / area.sum()) * irradiance / math.pi, background


def _beyond_depth(medium: FogMedium, view: View) -> float:
    """Optical depth of the line of sight beyond the drone to the end of the medium [-]: :data:`BOX_HALF_WIDTH`
    camera distances (the medium's box), of fog, or, with a layer, of fog up to its top (clear air above it)."""
    length_km = BOX_HALF_WIDTH * view.range_m / 1000.0
    top, sin_el = medium.top_above_target_m, math.sin(math.radians(view.elevation_deg))
    if top is None:
        return medium.beta_per_km * length_km
    if sin_el < 0.0:  # the sensor below the drone: the line of sight goes on upward
        fog_km = min(length_km, max(top, 0.0) / 1000.0 / -sin_el)
    elif top > 0.0:
        fog_km = length_km
    else:  # the drone above the top: fog only where the line of sight goes down through it
        fog_km = max(0.0, length_km - (-top / 1000.0 / sin_el if sin_el > 0.0 else math.inf))
    return medium.beta_per_km * fog_km + medium.clear_beta_per_km * (length_km - fog_km)


def _layer_sun_loss(light: Daylight, view: View, medium: FogMedium) -> float:
    """Share of the sun's single-scattered source that a fog layer takes away above the fog of the line of sight
    [-]: 1 - exp(-beta d / sin(sun elevation)), d the mean depth of the path's fog below the top (0 without a top:
    the scenario's illuminance is the fog's)."""
    top = medium.top_above_target_m
    rise = view.range_m * math.sin(math.radians(view.elevation_deg))
    low, high = min(0.0, rise), max(0.0, rise)
    if top is None or top <= low:
        return 0.0
    depth_km = (top - (low + min(high, top)) / 2.0) / 1000.0
    return 1.0 - math.exp(-medium.beta_per_km * depth_km / math.sin(math.radians(light.sun_elevation_deg)))


def _michelson(target: float, background: float) -> float:
    """Contrast (L_t - L_b) / (L_t + L_b) of the render's figures [-]."""
    return (target - background) / (target + background) if target + background > 0.0 else 0.0


def analytic_error(target, light: Daylight, view: View, medium: FogMedium, share: float) -> tuple[float, tuple, float]:
    """Estimated error of the analytic path's contrast where it is an approximation [-], its parts, and the
    contrast the medium would give (the estimate's) [-].

    The analytic path: L_t tau + L_h (1 - tau) against L_b tau + L_h (1 - tau), tau = exp(-tau_los). The estimate
    replaces L_h by the fog's single-scattered source J (:func:`single_scatter_source`) and puts the background
    beyond the drone, behind the medium's depth of fog (:func:`_beyond_depth`): L_t tau + J (1 - tau) against
    L_b tau_b + J (1 - tau_b). Terms: ``airlight_source`` (J1 of the scenario's light), ``fog_layer_sun`` (the sun
    in J dimmed by the fog above the path, :func:`_layer_sun_loss`), ``forward_scatter`` (the blur share of the
    direct light kept on the drone's pixels, :func:`blur_share`, times the contrast). Single scattering only: the
    medium's multiple scattering raises its source further (the default fog at 150 m: background 6120 cd/m^2 in
    the medium against J1 = 4271), so the estimate is low where the fog is deep.
    """
    lt, lb = _inherent_luminance(target, light, view)
    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    los = _line_of_sight_depth(medium, view)
    tau, tau_b = math.exp(-los), math.exp(-los - _beyond_depth(medium, view))
    j1 = single_scatter_source(light, view, medium.g)
    sun_az = view.azimuth_deg if light.sun_azimuth_deg is None else light.sun_azimuth_deg
    to_sun = direction_vector(sun_az, light.sun_elevation_deg)
    d = direction_vector(view.azimuth_deg, view.elevation_deg)
    sun_part = sky["sun_irradiance_lx"] * float(_hg(-float(to_sun @ d), medium.g))
    j = j1 - sun_part * _layer_sun_loss(light, view, medium)

    def contrast(source: float, background_transmittance: float) -> float:
        return _michelson(
            lt * tau + source * (1.0 - tau), lb * background_transmittance + source * (1.0 - background_transmittance)
        )

    c_analytic = _michelson(lt * tau + sky["sky_radiance"] * (1.0 - tau), lb * tau + sky["sky_radiance"] * (1.0 - tau))
    c_single, c_layer = contrast(j1, tau_b), contrast(j, tau_b)
    terms = (
        ("airlight_source", abs(c_single - c_analytic), "single-scattered sun, sky and ground in place of L_h"),
        ("fog_layer_sun", abs(c_layer - c_single), "the sun dimmed by the fog above the path"),
        ("forward_scatter", share * abs(c_layer), "blur_share of the direct light kept on the drone's pixels"),
    )
    records = tuple({"name": n, "value": v, "unit": "-", "source": src} for n, v, src in terms)
    return float(sum(t[1] for t in terms)), records, c_layer


def footprint(target, view: View, sensor: EoSensor) -> tuple[float, int]:
    """The drone's pixels (its exact silhouette's area over (IFOV R)^2,
    :func:`csuas.drone_models.silhouette.projected_metrics`) and the render window's pixels."""
    _, _, framing = prepare(target, view, sensor)
    area = projected_metrics([p.mesh for p in target_parts(target)], view.azimuth_deg, view.elevation_deg)
    ifov = math.radians(sensor.hfov_deg) / sensor.n_h
    window = framing.window.n_pixels
    return min(float(area["projected_area_m2"]) / (ifov * view.range_m) ** 2, float(window)), window


def medium_stderr(target_pixels: float, window_pixels: int, sun_ratio: float, contrast: float, quality) -> float:
    """Predicted standard error of the medium's contrast [-] (the noise model, :data:`NOISE_TARGET`).

    The trace takes N = :func:`medium_samples` rays, N_t = N target_pixels / window_pixels of them on the drone;
    with the relative standard deviation of one ray's luminance s = a + b x (drone, background; x = ``sun_ratio``
    = E_sun / (pi J1)), the luminances' relative errors are s_t / sqrt(N_t) and s_b / sqrt(N - N_t), and the
    contrast's (1 - C^2) / 2 sqrt(s_t^2 / N_t + s_b^2 / (N - N_t)) (C = (L_t - L_b) / (L_t + L_b), first order).
    Predicted over measured (the jackknife's, itself within about 27 % with 8 batches): 0.67-1.95 on fifteen
    renders, 0.74-1.84 on the seven not used to fit it (80-300 m, optical depth 0.5-5.9, draft and standard); it
    errs toward more noise, which keeps ``auto`` on the analytic path.
    """
    samples = medium_samples(window_pixels, quality)
    on_target = max(samples * target_pixels / window_pixels, 1.0)
    rest = max(samples - on_target, 1.0)
    s_t, s_b = (a + b * sun_ratio for a, b in (NOISE_TARGET, NOISE_BACKGROUND))
    return 0.5 * (1.0 - contrast * contrast) * math.sqrt(s_t * s_t / on_target + s_b * s_b / rest)


def sun_ratio(light: Daylight, view: View, g: float = FOG_ASYMMETRY_G) -> float:
    """The light of the noise model: the sun's normal irradiance over pi times the fog's single-scattered source,
    E_sun / (pi J1) [-] (0 without sun)."""
    sky = sun_and_sky(light.illuminance_lx, light.diffuse_fraction, light.sun_elevation_deg, light.ground_reflectance)
    source = single_scatter_source(light, view, g)
    return sky["sun_irradiance_lx"] / (math.pi * source) if source > 0.0 else 0.0


def compare_errors(target, light: Daylight, view: View, sensor: EoSensor, medium: FogMedium, share: float, quality):
    """``auto``'s comparison (:class:`ErrorComparison`): the analytic path's estimated error against the medium's
    predicted standard error at the requested quality, and the lowest preset at which the medium wins."""
    from csuas.render.imaging.quality import QUALITY_PRESETS

    error, terms, contrast = analytic_error(target, light, view, medium, share)
    pixels, window = footprint(target, view, sensor)
    ratio = sun_ratio(light, view, medium.g)

    def stderr(q) -> float:
        return medium_stderr(pixels, window, ratio, contrast, q)

    ladder = sorted(QUALITY_PRESETS.values(), key=lambda q: q.spp)
    better = [q for q in ladder if MEDIUM_CONFIDENCE * stderr(q) < error]
    seconds = None
    if better:
        seconds = _medium_seconds(medium_samples(window, better[0]), medium.beta_per_km * view.range_m / 1000.0)
    requested = resolve_quality(quality)
    return ErrorComparison(requested.name, error, terms, stderr(requested), better[0].name if better else None, seconds)


#: Cost of a render (2 CPU cores, LLVM): start (Mitsuba and the first kernels) [s], an analytic window per range
#: [s] (render/imaging/quality.py's 0.1-0.5 s), a medium's scene and kernels [s], and a medium's sample [s] at
#: optical depth tau of beta R, times 1 + tau + 0.01 tau^2 (the scatterings of its walk in the fog's box). Fitted
#: to the default drone at 150 m, standard quality, 156,800 samples: 3.6 s (tau 0.29), 2.9 s (1.17), 7.7 s
#: (5.9), and 28,800 samples at tau 15.6: 5.6 s, under a load average of 5-6. ``csuas bench --only cost_models``
#: (render-medium, load average 13): estimated 4.1 / 5.8 / 7.4 s against 11.1 / 10.4 / 15.7 s wall and 3.9 / 3.6
#: / 5.1 CPU-s (the command's processor time, what an idle machine's wall time approaches).
START_SECONDS, ANALYTIC_SECONDS, MEDIUM_START_SECONDS, SAMPLE_SECONDS = 2.0, 0.5, 1.0, 6e-6

#: Peak resident memory of a render with Mitsuba loaded [B] (ru_maxrss 0.34-0.36 GB, the benchmark's three runs),
#: and per ray of a medium's launch [B] (its path state).
PROCESS_BYTES, MEDIUM_RAY_BYTES = 330e6, 400.0


def medium_samples(window_pixels: int, quality) -> int:
    """Camera rays a medium trace of a window of ``window_pixels`` takes (:mod:`csuas.render.imaging.medium_path`)."""
    q = resolve_quality(quality)
    n_side = max(q.n_side, math.ceil(q.n_side * math.sqrt(64.0 / window_pixels)))
    return int(window_pixels) * n_side * n_side * q.n_batches


def _medium_seconds(samples: int, tau: float) -> float:
    """Time of a medium's scene and trace of ``samples`` rays at optical depth ``tau`` = beta R [s] (constants
    above)."""
    return MEDIUM_START_SECONDS + samples * SAMPLE_SECONDS * (1.0 + tau + 0.01 * tau * tau)


def render_estimate(target, sensor: EoSensor, renders: list, quality) -> Estimate:
    """Time and peak memory of EO renders, before any: ``renders`` lists (View, MethodChoice) pairs; each costs
    an analytic window, and a medium trace where its choice is the medium (constants above)."""
    seconds, peak, media = START_SECONDS, PROCESS_BYTES, 0
    for view, choice in renders:
        seconds += ANALYTIC_SECONDS
        if choice.method != "medium":
            continue
        media += 1
        _, _, framing = prepare(target, view, sensor)
        samples = medium_samples(framing.window.n_pixels, quality)
        seconds += _medium_seconds(samples, choice.medium.beta_per_km * view.range_m / 1000.0)
        peak = max(peak, PROCESS_BYTES + MEDIUM_RAY_BYTES * min(samples, MEDIUM_LAUNCH))
    what = f"{len(renders)} EO render(s) at {resolve_quality(quality).name}, {media} through the medium"
    return Estimate(what, seconds, peak)
