"""Optical atmosphere: Beer-Lambert (Eq. 10), Koschmieder (Eq. 12) and Kruse (Eqs. 19-20).

Convention note (docs/conventions.md point 1): Kruse and Koschmieder give an extinction
coefficient in km^-1, which the paper labels dB/km and inserts in the decibel
form of Beer-Lambert, Eq. 10 (Table 47's eta_TL = 0.681 is computed that way).
The ``paper`` convention reproduces this; ``physical`` uses tau = exp(-beta R).

References
----------
Kruse, P. W., McGlauchlin, L. D., McQuistan, R. B. (1962). Elements of Infrared Technology.
Kim, I. I., McArthur, B., Korevaar, E. (2001). Comparison of laser beam propagation at 785 nm and
1550 nm in fog and haze for optical wireless communications. Proc. SPIE 4214 (the q of Eq. 20).
Koschmieder, H. (1924). Theorie der horizontalen Sichtweite.
Bucholtz, A. (1995). Rayleigh-scattering calculations for the terrestrial atmosphere. Applied Optics
34(15), 2765-2773 (sea-level Rayleigh extinction of the US Standard Atmosphere).
Marshall, J. S., Palmer, W. McK. (1948). The distribution of raindrops with size. J. Meteorol. 5,
165-166 (the drop-size distribution of rain extinction); van de Hulst, H. C. (1957). Light
Scattering by Small Particles, Section 8.42 (extinction efficiency 2 of drops much larger than
the wavelength).
Shettle, E. P., Fenn, R. W. (1979). Models for the aerosols of the lower atmosphere and the effects of
humidity variations on their optical properties. AFGL-TR-79-0214 (the advection and radiation fog models),
tabulated in LOWTRAN 7 (Kneizys, F. X. et al. 1988, Users Guide to LOWTRAN 7, AFGL-TR-88-0177; BLOCK DATA
EXTDTA: VX2, FG1EXT, FG2EXT).
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require
from csuas.core.radiometry import band_limits_um
from csuas.core.result import check_convention

#: -ln(0.02): Koschmieder constant for a 2 % contrast threshold (Eq. 12).
KOSCHMIEDER_2PCT = -np.log(0.02)
#: Visibility breakpoints of Kim's q (Eq. 20) [km].
KRUSE_BREAKPOINTS_KM = (0.5, 1.0, 6.0, 50.0)


def koschmieder_extinction_per_km(visibility_km, threshold=0.02):
    """Extinction coefficient [1/km] from meteorological visibility (Eq. 12).

    Parameters
    ----------
    visibility_km : array_like
        Visibility V [km], > 0.
    threshold : float
        Contrast threshold of the visibility definition (0.02 in the paper;
        WMO uses 0.05).

    Returns
    -------
    ndarray
        sigma = -ln(threshold) / V [1/km]; Table 16: 4.89, 9.78, 39.12 at 0.8, 0.4, 0.1 km.
    """
    v = require("visibility_km", visibility_km, gt=0, allow_inf=True)
    require("threshold", threshold, gt=0, lt=1)
    return -np.log(threshold) / v


def kruse_q(visibility_km):
    """Size-distribution exponent q of the Kruse/Kim model (Eq. 20).

    Breakpoints at 0.5, 1, 6 and 50 km. q is continuous at 0.5, 1 and 6 km and
    jumps from 1.3 to 1.6 above 50 km; exactly at a breakpoint the lower branch
    applies (the paper's strict inequalities leave the breakpoints open).
    """
    v = require("visibility_km", visibility_km, gt=0, allow_inf=True)
    return np.select(
        [v > 50.0, v > 6.0, v > 1.0, v > 0.5],
        [1.6, 1.3, 0.16 * v + 0.34, v - 0.5],
        default=0.0,
    )


#: Rayleigh (molecular) extinction of sea-level air at 550 nm [1/km] (Bucholtz 1995, US Standard
#: Atmosphere, 288.15 K, 1013.25 hPa); its Koschmieder visibility, 3.912/0.0116 = 337 km, is the
#: clearest air can be.
RAYLEIGH_EXTINCTION_550NM_PER_KM = 0.0116
#: Wavelength exponent of Rayleigh extinction near 550 nm (Bucholtz 1995's fit: 4.05 at 0.55 um).
RAYLEIGH_EXPONENT = 4.05


def extinction_per_km(wavelength_nm, visibility_km, convention="paper"):
    """Optical extinction coefficient [1/km] at a wavelength and meteorological visibility.

    ``paper``: Kruse/Kim (Eqs. 19-20) as printed, whose exponent q jumps from 1.3 to 1.6 at
    50 km, so that below 550 nm extinction rises (and the EO range falls, by up to 25 %) as the
    air clears past 50 km (docs/conventions.md point 12).

    ``physical``: continuous in visibility. Molecular (Rayleigh) extinction of Bucholtz (1995)
    scales as lambda^-4.05; the rest of Koschmieder's 3.912/V is aerosol, scaled by Kim's q
    below 6 km and Kruse's 1.3 above (the 1.6 branch stood for the molecular part, here explicit):

        beta(lambda, V) = b_R (lambda/550)^-4.05 + (3.912/V - b_R) (lambda/550)^-q(V),
        b_R = min(0.0116 /km, 3.912/V).

    At 550 nm both give Koschmieder's 3.912/V (up to the 337 km Rayleigh limit).
    """
    check_convention(convention)
    if convention == "paper":
        return kruse_extinction_per_km(wavelength_nm, visibility_km)
    lam = require("wavelength_nm", wavelength_nm, gt=0) / 550.0
    v = require("visibility_km", visibility_km, gt=0, allow_inf=True)
    total = KOSCHMIEDER_2PCT / v
    molecular = np.minimum(RAYLEIGH_EXTINCTION_550NM_PER_KM, total)
    q_aerosol = np.minimum(kruse_q(v), 1.3)
    return molecular * lam ** (-RAYLEIGH_EXPONENT) + (total - molecular) * lam ** (-q_aerosol)


def kruse_extinction_per_km(wavelength_nm, visibility_km):
    """Kruse/Kim extinction coefficient (Eq. 19) [1/km] (labelled dB/km in the paper).

    Parameters
    ----------
    wavelength_nm : array_like
        Wavelength [nm]; the model is empirical for visible and near-IR light.
    visibility_km : array_like
        Visibility [km].

    Returns
    -------
    ndarray
        sigma = 3.912/V * (lambda/550 nm)^-q.
    """
    lam = require("wavelength_nm", wavelength_nm, gt=0)
    v = require("visibility_km", visibility_km, gt=0, allow_inf=True)
    return KOSCHMIEDER_2PCT / v * (lam / 550.0) ** (-kruse_q(v))


def transmittance(extinction, range_m, convention="physical"):
    """One-way atmospheric transmittance over ``range_m``.

    Parameters
    ----------
    extinction : array_like
        Extinction coefficient; read as dB/km by the ``paper`` convention
        (Eq. 10: tau = 10^(-sigma z/10)) and as 1/km by ``physical``
        (tau = exp(-beta z)).
    range_m : array_like
        Path length [m], >= 0.
    convention : {"paper", "physical"}

    Returns
    -------
    ndarray
        Transmittance in [0, 1].
    """
    check_convention(convention)
    k = require("extinction", extinction, ge=0)
    z_km = require("range_m", range_m, ge=0, allow_inf=True) / 1000.0
    with np.errstate(invalid="ignore"):
        optical = np.where(k == 0, 0.0, k * z_km)
    if convention == "paper":
        return db_transmittance(k, range_m)
    return np.exp(-optical)


def db_transmittance(attenuation_db_km, range_m):
    """Transmittance of a path with a specific attenuation in dB/km: 10^(-a z / 10) (Eq. 10).

    Parameters
    ----------
    attenuation_db_km : array_like
        Specific attenuation a [dB/km], >= 0 (zero gives exactly 1 at any range).
    range_m : array_like
        Path length z [m], >= 0.
    """
    a = require("attenuation_db_km", attenuation_db_km, ge=0)
    z_km = require("range_m", range_m, ge=0, allow_inf=True) / 1000.0
    with np.errstate(invalid="ignore"):
        return np.power(10.0, -np.where(a == 0, 0.0, a * z_km) / 10.0)


def range_for_transmittance(extinction, tau, convention="physical"):
    """Inverse of :func:`transmittance`: the range [m] at which tau is reached.

    Returns +inf where the extinction is 0 and 0 where tau >= 1.
    """
    check_convention(convention)
    k = require("extinction", extinction, ge=0)
    t = require("tau", tau, gt=0)
    optical = -np.log10(t) * 10.0 if convention == "paper" else -np.log(t)
    optical = np.maximum(optical, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(optical == 0, 0.0, np.where(k == 0, np.inf, 1000.0 * optical / np.where(k == 0, 1.0, k)))


def koschmieder_apparent_contrast(c0, extinction_per_km, range_m):
    """Apparent contrast against the horizon sky, C(R) = C0 exp(-beta R) (Koschmieder)."""
    return np.asarray(c0, dtype=float) * transmittance(extinction_per_km, range_m, "physical")


#: Marshall-Palmer drop-size distribution N(D) = N0 exp(-Lambda D), Lambda = 4.1 R^-0.21 [mm^-1]:
#: N0 [m^-3 mm^-1], the slope coefficient [mm^-1] and exponent of the rain rate (Marshall & Palmer 1948).
MARSHALL_PALMER_N0, MARSHALL_PALMER_SLOPE, MARSHALL_PALMER_EXPONENT = 8000.0, 4.1, -0.21
#: Extinction efficiency of raindrops (0.1-6 mm) in the visible and thermal infrared: the geometric-optics
#: limit, drops being thousands of wavelengths across (van de Hulst 1957).
RAIN_EXTINCTION_EFFICIENCY = 2.0
#: The source of :func:`rain_extinction_per_km`, for the terms of range and render.
RAIN_EXTINCTION_SOURCE = "Marshall-Palmer drops, extinction efficiency 2 (geometric optics): 0.365 R^0.63"


def rain_extinction_per_km(rain_rate_mm_h):
    """Extinction of rain in the visible and thermal infrared [1/km] (Marshall-Palmer, Q_ext = 2).

    beta = integral of Q_ext (pi D^2 / 4) N0 exp(-Lambda D) dD = Q_ext pi N0 / (2 Lambda^3), with
    Lambda = 4.1 R^-0.21 mm^-1: 0.365 R^0.63 km^-1 (R [mm/h]); 3.11 km^-1 at 30 mm/h. Wavelength-independent
    from 0.4 to 12 um since every drop is far larger than the wavelength.

    Parameters
    ----------
    rain_rate_mm_h : array_like
        Rain rate R [mm/h], >= 0 (0 gives 0).
    """
    r = require("rain_rate_mm_h", rain_rate_mm_h, ge=0)
    with np.errstate(divide="ignore"):
        slope = MARSHALL_PALMER_SLOPE * np.where(r > 0, r, 1.0) ** MARSHALL_PALMER_EXPONENT  # [1/mm]
    per_m = RAIN_EXTINCTION_EFFICIENCY * np.pi * MARSHALL_PALMER_N0 / (2.0 * slope**3) * 1e-6  # mm^2 -> m^2
    return np.where(r > 0, per_m * 1000.0, 0.0)


#: The source of :func:`fog_path_fraction`, for the terms of range.
FOG_LAYER_SOURCE = "layered fog: L_fog / R = (h_top - h_low) / (h_high - h_low), clipped to [0, 1] (straight path)"


def fog_path_fraction(sensor_height_m, target_height_m, fog_top_m):
    """Fraction of a straight slant path that lies inside a fog layer from the ground to ``fog_top_m``.

    A straight path rises linearly, so the length below h_top is L_fog = R (h_top - h_low) / (h_high - h_low),
    clipped to [0, R]; a level path (h_low = h_high) is all in fog below the top and all clear above it.
    The fog's share of the transmittance is then exp(-beta L_fog) (Beer-Lambert over the fog's length).

    Parameters
    ----------
    sensor_height_m, target_height_m : array_like
        Heights of the path's ends above the ground [m].
    fog_top_m : array_like
        Height of the fog's top above the same ground [m], >= 0.

    Returns
    -------
    ndarray
        L_fog / R in [0, 1]: 1 fully inside, 0 fully above, between when the path crosses the top.
    """
    h_s = require("sensor_height_m", sensor_height_m)
    h_t = require("target_height_m", target_height_m)
    top = require("fog_top_m", fog_top_m, ge=0)
    low, high = np.minimum(h_s, h_t), np.maximum(h_s, h_t)
    rise = high - low
    with np.errstate(divide="ignore", invalid="ignore"):
        crossing = np.clip((top - low) / np.where(rise > 0, rise, 1.0), 0.0, 1.0)
    return np.where(rise > 0, crossing, (low < top).astype(float))


#: Wavelengths [um] of LOWTRAN 7's aerosol tables from 3 to 14.8 um (VX2, Kneizys et al. 1988).
FOG_TABLE_UM = (
    3.0,
    3.3923,
    3.75,
    4.5,
    5.0,
    5.5,
    6.0,
    6.2,
    6.5,
    7.2,
    7.9,
    8.2,
    8.7,
    9.0,
    9.2,
    10.0,
    10.591,
    11.0,
    11.5,
    12.5,
    14.8,
)
#: Extinction of LOWTRAN 7's fog models at those wavelengths over their extinction at 0.55 um (FG1EXT: advection
#: fog, the larger drops; FG2EXT: radiation fog, the smaller; Shettle & Fenn 1979, as printed in LOWTRAN 7).
FOG_EXTINCTION_RATIO = {
    "advection": (
        1.04899,
        1.06823,
        1.07804,
        1.09272,
        1.10367,
        1.11684,
        1.10430,
        1.11367,
        1.12899,
        1.14987,
        1.17209,
        1.18278,
        1.20133,
        1.21266,
        1.21949,
        1.22677,
        1.15589,
        1.05684,
        0.98291,
        1.01120,
        1.10911,
    ),
    "radiation": (
        1.10816,
        1.43285,
        1.45272,
        1.18709,
        1.04367,
        0.82354,
        0.71747,
        0.92405,
        0.79342,
        0.60266,
        0.47677,
        0.43171,
        0.36734,
        0.33259,
        0.31184,
        0.24139,
        0.21601,
        0.24006,
        0.28816,
        0.42671,
        0.56861,
    ),
}
#: The source of :func:`fog_infrared_extinction_per_km`, for the terms of range and render.
FOG_INFRARED_SOURCE = (
    "fog of Shettle & Fenn 1979 (LOWTRAN 7 FG1EXT advection / FG2EXT radiation fog, environment.fog_type), band mean "
    "of its ratio to 0.55 um, times 3.912 / V_fog"
)


def fog_extinction_ratio(wavelength_um, fog="advection"):
    """Extinction of a fog at a wavelength over its extinction at 0.55 um [-] (Shettle & Fenn 1979, LOWTRAN 7).

    Linear between the tabulated wavelengths of :data:`FOG_TABLE_UM` (3-14.8 um); the table's values at them.

    Parameters
    ----------
    wavelength_um : array_like
        Wavelength [um], 3 to 14.8.
    fog : {"advection", "radiation"}
        LOWTRAN 7's advection fog (FG1EXT, drops of mode radius near 10 um: as opaque in the infrared as in the
        visible) or radiation fog (FG2EXT, smaller drops: a quarter of it near 10 um).
    """
    if fog not in FOG_EXTINCTION_RATIO:
        raise ParameterError("fog", fog, ", ".join(FOG_EXTINCTION_RATIO))
    lam = require("wavelength_um", wavelength_um, ge=FOG_TABLE_UM[0], le=FOG_TABLE_UM[-1])
    return np.interp(lam, FOG_TABLE_UM, FOG_EXTINCTION_RATIO[fog])


def fog_infrared_extinction_per_km(visibility_km, band="lwir", fog="advection"):
    """Extinction of fog in a thermal band [1/km]: its 0.55 um extinction 3.912 / V times the band's mean ratio.

    LOWTRAN 7 scales its fog models to a visibility the same way (Koschmieder at 0.55 um, Eq. 12). The ratio
    (:func:`fog_extinction_ratio`) is averaged over the band uniformly in wavelength (exactly: it is linear
    between the table's wavelengths): 1.144 over the LWIR 8-12 um and 1.081 over the MWIR 3-5 um of the
    advection fog (0.300 and 1.281 of the radiation fog).

    Parameters
    ----------
    visibility_km : array_like
        Fog visibility V [km], > 0.
    band : str or (float, float)
        ``lwir``, ``mwir`` or (low_um, high_um) within 3-14.8 um.
    fog : {"advection", "radiation"}
        As :func:`fog_extinction_ratio`.
    """
    low, high = band_limits_um(band)
    if low < FOG_TABLE_UM[0] or high > FOG_TABLE_UM[-1]:
        raise ParameterError("band", band, f"within {FOG_TABLE_UM[0]:g}-{FOG_TABLE_UM[-1]:g} um (the fog table)")
    inner = [lam for lam in FOG_TABLE_UM if low < lam < high]
    nodes = np.array([low, *inner, high])
    ratio = fog_extinction_ratio(nodes, fog)
    mean = float(np.sum((ratio[1:] + ratio[:-1]) / 2.0 * np.diff(nodes)) / (high - low))
    return koschmieder_extinction_per_km(visibility_km) * mean
