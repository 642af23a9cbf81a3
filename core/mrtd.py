"""MRTD curves of thermal imagers: a documented parametric default and user tables.

The paper uses a measured MRTD curve (Eqs. 27-29) but gives no default. csuas
provides a simplified analytic MRTD (Lloyd 1975; Holst 2008, "Electro-Optical
Imaging System Performance", ch. 12) built from values on a datasheet:

    MRTD(f) = K * NETD * (f / f_N) / MTF_sys(f),   0 < f <= f_N

with K = pi^2 / (4 sqrt(14)) (4-bar target of aspect 7:1, eye integration
omitted), f_N = 1 / (2 IFOV) the detector Nyquist frequency [cy/rad], and
MTF_sys the product of the diffraction MTF of a circular aperture (cut-off
D / lambda = f_optics / (F lambda)) and the detector footprint MTF
|sinc(f IFOV)|. Beyond f_N the bars cannot be resolved (MRTD = +inf): the
Nyquist limit makes the MRTD range never exceed the Johnson range of Eq. 23
for the same task, which it equals for a hot enough target.

User curves are (frequency [cy/mrad], MRTD [K]) tables, interpolated linearly
in log(MRTD), monotone increasing; above the last frequency MRTD = +inf.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.checks import require
from csuas.core.johnson import ifov_from_pitch_rad
from csuas.core.radiometry import BANDS_UM
from csuas.core.solve import bracketed_root

#: Lloyd's 4-bar constant pi^2 / (4 sqrt(14)).
LLOYD_K = np.pi**2 / (4.0 * np.sqrt(14.0))


def diffraction_mtf(nu):
    """MTF of an aberration-free circular pupil at normalised frequency nu = f / f_cutoff."""
    x = np.clip(np.asarray(nu, dtype=float), 0.0, 1.0)
    return (2.0 / np.pi) * (np.arccos(x) - x * np.sqrt(1.0 - x * x))


@dataclass(frozen=True)
class ParametricMrtd:
    """Default analytic MRTD (module docstring).

    Attributes
    ----------
    netd_k : float
        Noise-equivalent temperature difference [K].
    ifov_rad : float
        Pixel IFOV [rad] (Eq. 22: pitch / focal length).
    f_number : float
        Optics f-number.
    pitch_m : float
        Detector pitch [m].
    wavelength_m : float
        Band-centre wavelength [m] for the diffraction MTF.
    """

    netd_k: float
    ifov_rad: float
    f_number: float
    pitch_m: float
    wavelength_m: float

    @property
    def nyquist_cy_rad(self):
        """Detector Nyquist frequency f_N = 1/(2 IFOV) [cy/rad]."""
        return 0.5 / self.ifov_rad

    @classmethod
    def from_datasheet(cls, netd_mk: float, ifov_rad: float, f_number: float, pitch_um: float, band: str):
        """The parametric MRTD of a camera's datasheet values, at the centre wavelength of its band.

        Parameters
        ----------
        netd_mk : float
            NETD [mK].
        ifov_rad : float
            Pixel IFOV [rad] (Eq. 22: pitch / focal length).
        f_number : float
            Optics f-number.
        pitch_um : float
            Detector pitch [um].
        band : {"lwir", "mwir"}
            Thermal band (:data:`csuas.core.radiometry.BANDS_UM`); its centre sets the diffraction MTF.
        """
        low, high = BANDS_UM[band]
        return cls(
            netd_k=netd_mk / 1000.0,
            ifov_rad=float(ifov_rad),
            f_number=f_number,
            pitch_m=pitch_um * 1e-6,
            wavelength_m=0.5 * (low + high) * 1e-6,
        )

    def shape(self, u):
        """MRTD / NETD at u = f / f_N (dimensionless), +inf beyond Nyquist."""
        u = np.asarray(u, dtype=float)
        ratio_nyq_cut = self.f_number * self.wavelength_m / (2.0 * self.pitch_m)  # f_N / f_cutoff
        mtf = diffraction_mtf(u * ratio_nyq_cut) * np.abs(np.sinc(0.5 * u))
        with np.errstate(divide="ignore"):
            value = LLOYD_K * u / mtf
        return np.where((u > 1.0) | (mtf <= 0), np.inf, value)

    def __call__(self, frequency_cy_rad):
        """MRTD [K] at spatial frequencies [cy/rad]."""
        f = require("frequency_cy_rad", frequency_cy_rad, ge=0, allow_inf=True)
        return self.netd_k * self.shape(f / self.nyquist_cy_rad)

    def max_frequency(self, delta_t_k):
        """Highest frequency [cy/rad] with MRTD <= delta_t (Eq. 27), capped at Nyquist."""
        target = np.asarray(delta_t_k, dtype=float) / self.netd_k
        limit = self.shape(1.0)
        u, _ = bracketed_root(lambda x: self.shape(x) - target, np.zeros(target.shape), np.ones(target.shape))
        u = np.where(target >= limit, 1.0, np.where(target <= 0, 0.0, u))
        return u * self.nyquist_cy_rad


@dataclass(frozen=True)
class TabulatedMrtd:
    """A measured MRTD curve (spatial frequency [cy/mrad], MRTD [K]).

    Frequencies and MRTD values must both be strictly increasing, MRTD > 0.
    """

    frequency_cy_mrad: tuple
    mrtd_k: tuple

    def __post_init__(self):
        f = np.asarray(self.frequency_cy_mrad, dtype=float)
        m = np.asarray(self.mrtd_k, dtype=float)
        if f.ndim != 1 or f.shape != m.shape or f.size < 2:
            raise ParameterError(
                "tir.mrtd_frequency_cy_mrad", list(f.flat), "a list of >= 2 frequencies matching tir.mrtd_k in length"
            )
        if np.any(np.diff(f) <= 0) or np.any(f < 0):
            raise ParameterError("tir.mrtd_frequency_cy_mrad", list(f), "non-negative, strictly increasing")
        if np.any(m <= 0) or np.any(np.diff(m) <= 0):
            raise ParameterError("tir.mrtd_k", list(m), "positive and strictly increasing with frequency")

    def __call__(self, frequency_cy_rad):
        """MRTD [K] at frequencies [cy/rad]; +inf above the table."""
        f = np.asarray(frequency_cy_rad, dtype=float) / 1000.0
        ft, mt = np.asarray(self.frequency_cy_mrad), np.log(np.asarray(self.mrtd_k))
        value = np.exp(np.interp(f, ft, mt))
        return np.where(f > ft[-1], np.inf, value)

    def max_frequency(self, delta_t_k):
        """Highest frequency [cy/rad] with MRTD <= delta_t, by inverse interpolation."""
        ft, mt = np.asarray(self.frequency_cy_mrad), np.log(np.asarray(self.mrtd_k))
        dt = np.asarray(delta_t_k, dtype=float)
        with np.errstate(divide="ignore"):
            log_dt = np.log(np.maximum(dt, 0.0))
        return np.interp(log_dt, mt, ft, left=0.0, right=ft[-1]) * 1000.0


def sensor_mrtd(params: dict):
    """A thermal sensor's MRTD curve from its canonical parameters.

    The user's table (``mrtd_frequency_cy_mrad``, ``mrtd_k``) when given, else the parametric
    default of :class:`ParametricMrtd` from ``netd_mk``, ``pitch_um``, ``focal_mm``, ``f_number``
    and the centre wavelength of ``band`` (docs/scenarios.md names the parameters).
    """
    if params.get("mrtd_k") is not None:
        return TabulatedMrtd(tuple(params["mrtd_frequency_cy_mrad"]), tuple(params["mrtd_k"]))
    return ParametricMrtd.from_datasheet(
        netd_mk=params["netd_mk"],
        ifov_rad=ifov_from_pitch_rad(params["pitch_um"], params["focal_mm"]),
        f_number=params["f_number"],
        pitch_um=params["pitch_um"],
        band=params["band"],
    )
