"""Two-ray (direct + ground-reflected) model of a link over flat ground.

NumPy only. The exact vector form: isotropic antennas whose field lies along
the spherical unit vector theta-hat of the ray (vertical polarisation, "V")
or phi-hat ("H"), the reflected ray obtained by image theory on the plane
z = 0 and its field split into the TE (perpendicular) and TM (parallel)
components with the Fresnel coefficients of a homogeneous half-space of
complex relative permittivity eta = eps_r - j sigma / (omega eps_0)
(ITU-R P.2040-3, Eqs. 8-9 and 31-33; time convention exp(+j omega t), so a
path of length L carries exp(-j 2 pi L / lambda)).

Over a perfect conductor (eta -> infinity) the TM coefficient tends to +1,
so a vertical dipole's image is an upright dipole; at grazing incidence both
coefficients of any finite ground tend to -1, which gives the classic
two-ray law |h|^2 -> (lambda/(4 pi d))^2 (4 pi h_t h_r/(lambda d))^2 far
beyond the last lobe (Rappaport, *Wireless Communications*, 2nd ed.,
Sec. 4.6).
"""

from __future__ import annotations

import numpy as np

from csuas.core.units import wavelength_m


def fresnel_coefficients(cos_incidence, eta):
    """Fresnel reflection coefficients of a half-space for a wave coming from vacuum.

    Parameters
    ----------
    cos_incidence : array_like
        Cosine of the angle of incidence from the surface normal [-], in (0, 1].
    eta : array_like of complex
        Complex relative permittivity of the half-space.

    Returns
    -------
    r_te, r_tm : numpy.ndarray of complex
        Perpendicular (TE) and parallel (TM) coefficients; the TM one refers
        to unit vectors p = s x k of the incident and reflected waves, the
        convention in which a perfect conductor gives r_tm = +1.
    """
    cos_t = np.asarray(cos_incidence, dtype=float)
    eta = np.asarray(eta, dtype=complex)
    root = np.sqrt(eta - (1.0 - cos_t**2))
    r_te = (cos_t - root) / (cos_t + root)
    r_tm = (eta * cos_t - root) / (eta * cos_t + root)
    return r_te, r_tm


def _theta_hat(k):
    """Spherical unit vector theta-hat of the direction k (..., 3)."""
    rho = np.hypot(k[..., 0], k[..., 1])
    cos_phi = np.where(rho > 0, k[..., 0] / np.where(rho > 0, rho, 1.0), 1.0)
    sin_phi = np.where(rho > 0, k[..., 1] / np.where(rho > 0, rho, 1.0), 0.0)
    return np.stack([k[..., 2] * cos_phi, k[..., 2] * sin_phi, -rho], axis=-1)


def _phi_hat(k):
    """Spherical unit vector phi-hat of the direction k (..., 3)."""
    rho = np.hypot(k[..., 0], k[..., 1])
    cos_phi = np.where(rho > 0, k[..., 0] / np.where(rho > 0, rho, 1.0), 1.0)
    sin_phi = np.where(rho > 0, k[..., 1] / np.where(rho > 0, rho, 1.0), 0.0)
    return np.stack([-sin_phi, cos_phi, np.zeros_like(rho)], axis=-1)


def _polarization_vector(k, polarization):
    return _theta_hat(k) if polarization == "V" else _phi_hat(k)


def _leg(start, end, eta, bounce):
    """One ray from ``start`` to ``end`` (..., 3), direct or once reflected on z = 0.

    Returns the unit directions of departure and arrival, the unfolded length
    [m] and a function mapping the departing field vector to the arriving one.
    """
    target = end if not bounce else end * np.array([1.0, 1.0, -1.0])
    path = target - start
    length = np.linalg.norm(path, axis=-1)
    k_dep = path / length[..., None]
    if not bounce:
        return k_dep, k_dep, length, lambda e: e
    k_arr = k_dep * np.array([1.0, 1.0, -1.0])  # after the bounce, going up
    r_te, r_tm = fresnel_coefficients(k_arr[..., 2], eta)
    s = np.cross(k_dep, np.array([0.0, 0.0, 1.0]))
    s_norm = np.linalg.norm(s, axis=-1, keepdims=True)
    s = np.where(s_norm > 1e-12, s / np.where(s_norm > 0, s_norm, 1.0), np.array([0.0, 1.0, 0.0]))
    p_dep, p_arr = np.cross(s, k_dep), np.cross(s, k_arr)

    def reflect(e):
        return (r_te * np.sum(e * s, -1))[..., None] * s + (r_tm * np.sum(e * p_dep, -1))[..., None] * p_arr

    return k_dep, k_arr, length, reflect


def two_ray_paths(frequency_ghz, tx_position_m, rx_position_m, eta, polarization="V"):
    """Complex amplitudes of the direct and ground-reflected rays between two isotropic antennas.

    Parameters
    ----------
    frequency_ghz : float
        Carrier frequency [GHz].
    tx_position_m, rx_position_m : array_like, shape (..., 3)
        Antenna positions [m], both above the ground plane z = 0.
    eta : complex or None
        Complex relative permittivity of the ground; None for free space.
    polarization : {"V", "H"}
        Field along theta-hat ("V") or phi-hat ("H") at both antennas.

    Returns
    -------
    numpy.ndarray of complex, shape (..., 2)
        Channel coefficients (lambda/(4 pi L)) * polarisation factor *
        exp(-j 2 pi L/lambda) of the direct and the reflected ray; the
        reflected one is 0 without ground. Path gain = |sum|^2.
    """
    wavelength = float(wavelength_m(frequency_ghz))
    tx, rx = np.broadcast_arrays(np.asarray(tx_position_m, float), np.asarray(rx_position_m, float))
    rays = []
    for bounce in (False, True):
        if bounce and eta is None:
            rays.append(np.zeros(tx.shape[:-1], dtype=complex))
            continue
        k_dep, k_arr, length, transport = _leg(tx, rx, eta, bounce)
        field = transport(_polarization_vector(k_dep, polarization))
        received = np.sum(field * _polarization_vector(-k_arr, polarization), -1)
        rays.append(wavelength / (4 * np.pi * length) * received * np.exp(-2j * np.pi * length / wavelength))
    return np.stack(rays, axis=-1)


def radar_four_paths(frequency_ghz, radar_position_m, target_position_m, sigma_m2, eta, polarization="V"):
    """Complex amplitudes of the four monostatic radar paths over flat ground.

    The target is a point scatterer of cross-section sigma in every
    direction that maps the theta-hat and phi-hat components of the incident
    wave onto those of the scattered wave (no depolarisation), as Sionna RT's
    ``ConstantCPM`` does. The four paths are radar -> target -> radar with
    each leg direct or reflected once on the ground (Eq. 68 for the
    direct-direct path in free space: |a|^2 = lambda^2 sigma / ((4 pi)^3 R^4)).

    Parameters
    ----------
    frequency_ghz : float
        Carrier frequency [GHz].
    radar_position_m, target_position_m : array_like, shape (..., 3)
        Positions [m], both above z = 0.
    sigma_m2 : array_like
        Radar cross-section [m^2], broadcast over the positions.
    eta : complex or None
        Complex relative permittivity of the ground; None for free space
        (then only the direct-direct path is non-zero).
    polarization : {"V", "H"}

    Returns
    -------
    numpy.ndarray of complex, shape (..., 4)
        Paths (direct, direct), (direct, ground), (ground, direct),
        (ground, ground); received/transmitted power = |sum|^2.
    """
    wavelength = float(wavelength_m(frequency_ghz))
    radar, target = np.broadcast_arrays(np.asarray(radar_position_m, float), np.asarray(target_position_m, float))
    amplitude = wavelength * np.sqrt(np.asarray(sigma_m2, float)) / (4 * np.pi) ** 1.5
    paths = []
    for bounce_in in (False, True):
        for bounce_out in (False, True):
            if eta is None and (bounce_in or bounce_out):
                paths.append(np.zeros(radar.shape[:-1], dtype=complex))
                continue
            k1, k1_arr, l1, transport1 = _leg(radar, target, eta, bounce_in)
            e_target = transport1(_polarization_vector(k1, polarization))
            k2, k2_arr, l2, transport2 = _leg(target, radar, eta, bounce_out)
            e_scattered = np.sum(e_target * _theta_hat(k1_arr), -1)[..., None] * _theta_hat(k2) + np.sum(
                e_target * _phi_hat(k1_arr), -1
            )[..., None] * _phi_hat(k2)
            received = np.sum(transport2(e_scattered) * _polarization_vector(-k2_arr, polarization), -1)
            paths.append(amplitude * received * np.exp(-2j * np.pi * (l1 + l2) / wavelength) / (l1 * l2))
    return np.stack(paths, axis=-1)


def two_ray_path_gain_db(frequency_ghz, distance_m, tx_height_m, rx_height_m, eta, polarization="V"):
    """Path gain [dB] of the two-ray model, isotropic antennas, horizontal distance d.

    Parameters
    ----------
    frequency_ghz : float
        Carrier frequency [GHz].
    distance_m : array_like
        Horizontal distance between the antennas [m].
    tx_height_m, rx_height_m : float
        Antenna heights above the ground [m].
    eta : complex or None
        Complex relative permittivity of the ground (see
        :func:`complex_permittivity`); None gives free space (Friis).
    polarization : {"V", "H"}

    Returns
    -------
    numpy.ndarray
        10 log10 |h_direct + h_reflected|^2 [dB].
    """
    d = np.atleast_1d(np.asarray(distance_m, dtype=float))
    tx = np.stack([np.zeros_like(d), np.zeros_like(d), np.full_like(d, tx_height_m)], -1)
    rx = np.stack([d, np.zeros_like(d), np.full_like(d, rx_height_m)], -1)
    h = two_ray_paths(frequency_ghz, tx, rx, eta, polarization).sum(-1)
    return 20.0 * np.log10(np.abs(h))
