"""Micro-Doppler of rotor blades: the closed form of rotating thin blades (blade flashes).

A rigid blade of length ``L`` turning about a hub at rotation rate ``Omega`` [rev/s], seen from a
radar at elevation ``beta`` above the rotor plane, returns (Chen, Li, Ho & Wechsler, IEEE TAES
42(1):2-21, 2006, Section V "rotating rotor blades"; Chen, *The Micro-Doppler Effect in Radar*,
2nd ed., 2019, Chapter 4, rotor blades) the line integral of a uniform reflectivity along the blade,

    s(t) = sum_k L sinc(Phi_k(t)) exp(j Phi_k(t)),
    Phi_k(t) = (4 pi / lambda) (L / 2) cos(beta) cos(theta_k(t)),
    theta_k(t) = 2 pi Omega t + theta_0 + 2 pi k / N,   k = 0 .. N - 1,            (Eq. MD-1)

with ``sinc(x) = sin(x) / x`` and ``theta_k`` the blade's azimuth measured in the rotor plane from the
projection of the line of sight toward the radar. Chen writes ``exp(-j Phi_k)`` with ``theta_k``
measured from the line of sight away from the radar (his range grows along the blade); this is the
same signal with this package's phase convention ``exp(+2 j k d . r)`` (``d`` toward the radar, the
convention of :mod:`csuas.render.rcs.facet_po`), in which an approaching scatterer has a positive
Doppler frequency. The hub's constant phase ``exp(-j 4 pi R_0 / lambda)`` is dropped. Chen & Ling,
*Time-Frequency Transforms for Radar Imaging and Signal Analysis*, Artech House, 2002, Eq. (8.19),
print the same sum with ``sin(Omega t + theta_0 + 2 pi k / N)`` (blade azimuth from the perpendicular
to the line of sight). The section numbers above are cited from the sources' structure; the
expression itself is re-derived here (the line integral of ``exp(2 j k d . r)`` along the blade,
checked numerically in tests/test_micro_doppler.py).

A blade flashes (``sinc`` at its peak ``1``) when it stands perpendicular to the line of sight. With
``N`` blades the flash pattern repeats every ``1 / (N Omega)`` for even ``N`` (a blade and its
opposite flash together) and every ``1 / (2 N Omega)`` for odd ``N`` (each blade flashes twice per
turn, approaching and receding, and no two at once) (Eq. MD-2; Chen 2006, Sec. V). The power
``|s|^2`` is periodic with the flash period, so its spectrum has lines spaced by the flash rate
``N Omega`` (even) or ``2 N Omega`` (odd). The complex (I/Q) signal itself repeats only when the
blade set maps onto itself, every ``1 / (N Omega)``: for odd ``N`` half a flash period later it is the
complex conjugate (``theta_k -> theta_k + pi`` flips the sign of every ``Phi_k``), so the I/Q Doppler
spectrum has lines spaced ``N Omega`` for every ``N`` (Eq. MD-3), with mirror-symmetric magnitudes.
The blade tips
move at ``v_tip = 2 pi L Omega``, the largest Doppler shift being ``2 v_tip cos(beta) / lambda``
(Eq. MD-4); complex (I/Q) samples resolve the band ``-PRF/2 .. PRF/2`` without aliasing when
``PRF >= 2 f_tip`` (Eq. MD-5).

A rotor turning about any unit axis ``a`` (a multirotor's +z, a fixed-wing pusher's or tractor's flight
axis +x), seen along the unit direction ``d`` toward the radar, is the rotor above with ``beta`` the angle
between ``d`` and the rotor plane (Eq. MD-6):

    sin(beta) = a . d,        cos(beta) = |a x d|,

and ``theta_k`` measured in the rotor plane from ``d``'s projection onto it: Eq. MD-1 depends on the
geometry only through ``r . d`` for points ``r`` of the blade, and a point at radius ``rho`` and azimuth
``theta`` in the plane has ``r . d = rho cos(beta) cos(theta)``. So the flash period (Eq. MD-2) and the line
spacing (Eq. MD-3) do not depend on the axis, while the tip Doppler (Eq. MD-4) carries the projection factor
``cos(beta) = |a x d|``: a pusher seen nose-on (``d`` along ``a``) has no Doppler spread and flashes with its
whole disc at once, seen from the side (``d`` perpendicular to ``a``) it flashes like a rotor seen edge-on.

A flat rectangular blade of chord ``w`` adds the chord-wise factor ``sinc((2 pi / lambda) w cos(beta)
sin(theta_k))`` (Eq. MD-1a): its physical-optics integral over the blade's area is the product of the
two one-dimensional integrals (Knott, Shaeffer & Tuley, *Radar Cross Section*, 2nd ed., 2004, Eq. 5.8
for the plate), the thin wire being the limit ``w -> 0``.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require, require_all
from csuas.core.units import wavelength_m


def _blade_count(n_blades) -> int:
    count = float(require("n_blades", n_blades, ge=1))
    if not count.is_integer():
        raise ParameterError("n_blades", n_blades, "a whole number >= 1")
    return int(count)


def rotor_blade_signal(
    time_s,
    blade_length_m,
    n_blades,
    rotation_rate_hz,
    frequency_ghz,
    elevation_deg=0.0,
    initial_angle_deg=0.0,
    chord_m=0.0,
):
    """Baseband return of ``N`` rotating blades (Eq. MD-1; Eq. MD-1a with a chord) [m].

    Parameters
    ----------
    time_s : array_like
        Slow-time samples [s].
    blade_length_m : float
        Blade length from the hub axis to the tip ``L`` [m], > 0.
    n_blades : int
        Blades ``N`` on the rotor, >= 1, equally spaced.
    rotation_rate_hz : float
        Rotation rate ``Omega`` [rev/s] (rpm / 60); negative turns the other way.
    frequency_ghz : float
        Radar frequency [GHz], > 0.
    elevation_deg : float
        Radar elevation ``beta`` above the rotor plane [deg], -90..90.
    initial_angle_deg : float
        Azimuth ``theta_0`` of blade 0 at t = 0 from the line of sight's projection toward the radar [deg].
    chord_m : float
        Chord ``w`` of a flat rectangular blade [m], >= 0 (0: Chen's thin blade).

    Returns
    -------
    ndarray complex, shape of ``time_s``
        ``s(t)`` [m]; times ``w sin(beta)`` it is a flat PEC blade's physical-optics amplitude [m^2].
    """
    t, length, rate, f, elevation, theta0, chord = require_all(
        ("time_s", time_s, {}),
        ("blade_length_m", blade_length_m, {"gt": 0}),
        ("rotation_rate_hz", rotation_rate_hz, {}),
        ("frequency_ghz", frequency_ghz, {"gt": 0}),
        ("elevation_deg", elevation_deg, {"ge": -90, "le": 90}),
        ("initial_angle_deg", initial_angle_deg, {}),
        ("chord_m", chord_m, {"ge": 0}),
    )
    count = _blade_count(n_blades)
    two_k = 4.0 * np.pi / wavelength_m(f)
    cos_beta = np.cos(np.radians(elevation))
    signal = np.zeros(np.shape(t), complex)
    for k in range(count):
        theta = 2.0 * np.pi * rate * t + np.radians(theta0) + 2.0 * np.pi * k / count
        phase = two_k * length / 2.0 * cos_beta * np.cos(theta)
        chord_factor = np.sinc(two_k * chord / 2.0 * cos_beta * np.sin(theta) / np.pi)
        signal = signal + length * np.sinc(phase / np.pi) * chord_factor * np.exp(1j * phase)
    return signal


def rotor_plane_elevation_deg(spin_axis, toward_radar):
    """Elevation of the radar above a rotor's plane, ``beta = asin(a . d)`` [deg] (Eq. MD-6).

    Parameters
    ----------
    spin_axis : array_like (..., 3)
        The rotor's rotation axis ``a`` (normalised here), != 0.
    toward_radar : array_like (..., 3)
        Direction ``d`` from the rotor toward the radar (normalised here), != 0.

    Returns
    -------
    ndarray
        ``beta`` in [-90, 90] deg; ``cos(beta) = |a x d|`` is the tip Doppler's projection factor.
    """
    axis, toward = np.asarray(spin_axis, float), np.asarray(toward_radar, float)
    norms = [np.linalg.norm(v, axis=-1) for v in (axis, toward)]
    for name, value, norm in (("spin_axis", spin_axis, norms[0]), ("toward_radar", toward_radar, norms[1])):
        if not np.all(np.isfinite(norm) & (norm > 0)):
            raise ParameterError(name, value, "a finite non-zero 3-vector")
    sine = np.sum(axis * toward, axis=-1) / (norms[0] * norms[1])
    return np.degrees(np.arcsin(np.clip(sine, -1.0, 1.0)))


def blade_flash_period_s(n_blades, rotation_rate_hz):
    """Period of the blade-flash pattern [s] (Eq. MD-2): ``1/(N Omega)`` for even N, ``1/(2 N Omega)`` odd.

    Parameters
    ----------
    n_blades : int
        Blades per rotor, >= 1.
    rotation_rate_hz : float
        Rotation rate [rev/s], != 0 (its sign is ignored).
    """
    count = _blade_count(n_blades)
    rate = require("rotation_rate_hz", np.abs(np.asarray(rotation_rate_hz, float)), gt=0, why="a turning rotor")
    flashes_per_turn = count if count % 2 == 0 else 2 * count
    return 1.0 / (flashes_per_turn * rate)


def line_spacing_hz(n_blades, rotation_rate_hz):
    """Spacing of the I/Q micro-Doppler spectrum's lines, ``N Omega`` for any N [Hz] (Eq. MD-3).

    The flash rate (the lines of ``|s|^2``) is ``1 / blade_flash_period_s``: ``2 N Omega`` for odd N.

    Parameters
    ----------
    n_blades : int
        Blades per rotor, >= 1.
    rotation_rate_hz : float
        Rotation rate [rev/s], != 0 (its sign is ignored).
    """
    count = _blade_count(n_blades)
    return count * require("rotation_rate_hz", np.abs(np.asarray(rotation_rate_hz, float)), gt=0, why="a turning rotor")


def max_tip_doppler_hz(blade_length_m, rotation_rate_hz, frequency_ghz, elevation_deg=0.0):
    """Largest Doppler shift of the blade tips, ``2 v_tip cos(beta) / lambda`` [Hz] (Eq. MD-4).

    Parameters
    ----------
    blade_length_m : float
        Hub axis to tip [m], > 0.
    rotation_rate_hz : float
        Rotation rate [rev/s] (its sign is ignored).
    frequency_ghz : float
        Radar frequency [GHz], > 0.
    elevation_deg : float
        Radar elevation above the rotor plane [deg], -90..90.
    """
    length, rate, f, elevation = require_all(
        ("blade_length_m", blade_length_m, {"gt": 0}),
        ("rotation_rate_hz", rotation_rate_hz, {}),
        ("frequency_ghz", frequency_ghz, {"gt": 0}),
        ("elevation_deg", elevation_deg, {"ge": -90, "le": 90}),
    )
    tip_speed = 2.0 * np.pi * length * np.abs(rate)
    return 2.0 * tip_speed * np.cos(np.radians(elevation)) / wavelength_m(f)


def blade_line_rcs_m2(
    blade_length_m, n_blades, rotation_rate_hz, frequency_ghz, elevation_deg, chord_m, n_rotors=1, samples=None
):
    """RCS of every I/Q Doppler line of rotors of flat PEC blades (Eq. MD-1a, Fourier series) [m^2].

    The rotor's return repeats every ``1 / (N Omega)`` (Eq. MD-3), so its lines lie at ``m N Omega`` with
    the Fourier coefficients ``c_m`` of one period, computed exactly by the FFT of ``samples`` points of
    the closed form over that period. The return is nearly band-limited to the tip Doppler (Eq. MD-4;
    beyond it the flashes' short ends leave 8e-5 of the power of the Mini 4 Pro's rotor at 10 GHz), so
    the default ``samples``, 16 times the lines within the tip Doppler, sums to the quadrature of the
    time-mean power within 1e-9 (tests/test_micro_doppler_detection.py). A flat
    PEC blade's PO amplitude is ``w sin(beta) s(t)`` [m^2], so line ``m`` has the RCS
    ``4 pi (w sin(beta))^2 |c_m|^2 / lambda^2`` and the lines sum to the blades' time-mean RCS
    (Parseval). ``n_rotors`` rotors at different hubs add their lines with independent phases: in
    power, on average.

    Parameters
    ----------
    blade_length_m : float
        Hub axis to tip [m], > 0.
    n_blades : int
        Blades per rotor, >= 1.
    rotation_rate_hz : float
        Rotation rate [rev/s], != 0 (its sign is ignored: the magnitudes are mirror-symmetric).
    frequency_ghz : float
        Radar frequency [GHz], > 0.
    elevation_deg : float
        Radar elevation above the rotor plane [deg], -90..90.
    chord_m : float
        Blade chord ``w`` [m], > 0.
    n_rotors : int
        Rotors of the same blades and rate, >= 1.
    samples : int, optional
        Points over one period, >= 16 (default above).

    Returns
    -------
    (order, frequency_hz, rcs_m2) : (ndarray int, ndarray, ndarray)
        Line orders ``m`` ascending, their Doppler ``m N |Omega|`` [Hz] and RCS [m^2].
    """
    length, rate, f, elevation, chord = require_all(
        ("blade_length_m", blade_length_m, {"gt": 0}),
        ("rotation_rate_hz", np.abs(np.asarray(rotation_rate_hz, float)), {"gt": 0}),
        ("frequency_ghz", frequency_ghz, {"gt": 0}),
        ("elevation_deg", elevation_deg, {"ge": -90, "le": 90}),
        ("chord_m", chord_m, {"gt": 0}),
    )
    count, rotors = _blade_count(n_blades), float(require("n_rotors", n_rotors, ge=1))
    spacing = float(line_spacing_hz(count, rate))
    if samples is None:
        lines_within_tip = float(max_tip_doppler_hz(length, rate, f, elevation)) / spacing
        samples = int(2 ** np.ceil(np.log2(16.0 * (lines_within_tip + 1.0))))
    count_t = int(require("samples", samples, ge=16))
    t = np.arange(count_t) / (count_t * spacing)
    s = rotor_blade_signal(t, length, count, rate, f, elevation, 0.0, chord)
    coefficients = np.fft.fftshift(np.fft.fft(s)) / count_t
    order = np.fft.fftshift(np.fft.fftfreq(count_t, 1.0 / count_t)).astype(int)
    amplitude_m2 = chord * np.sin(np.radians(elevation)) * np.abs(coefficients)
    rcs = rotors * 4.0 * np.pi * amplitude_m2**2 / wavelength_m(f) ** 2
    return order, order * spacing, rcs
