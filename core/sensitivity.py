"""One-at-a-time sensitivity analysis (Section 4.9) and the platform comparison (Table 52).

The three range models of Section 4.9 are evaluated exactly as printed:

* ``eo_johnson``: Eq. 105, R = d_crit N_H / (2 lp n_TTPF HFOV);
* ``acoustic``: Eqs. 106-108 (no array gain in Section 4.9);
* ``radar``: Eq. 109, monostatic, lambda = c/f with c = 3e8 m/s and
  k_B = 1.381e-23 J/K as in Section 4.9.3.

:func:`one_at_a_time` perturbs each parameter to its low and high value with
the others at their defaults and ranks the parameters by the span of the
range, as a tornado plot does.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.acoustic import acoustic_range
from csuas.core.johnson import ifov_rad, johnson_range_m
from csuas.core.radar import radar_range
from csuas.core.units import C_LIGHT_PAPER, wavelength_m
from csuas.defaults import default_values, load_presets, load_sensitivity

#: The one-at-a-time analyses of Section 4.9 (Tables 48-51), by their key in ``sensitivity.toml``.
ANALYSES = ("eo", "acoustic_calm", "acoustic_wind", "radar")


def eo_johnson_model(d_crit_m, n_ttpf, n_h, hfov_deg, lp_task=1.0):
    """Eq. 105 [m]."""
    return johnson_range_m(d_crit_m, ifov_rad(hfov_deg, n_h), lp_task, n_ttpf)


def acoustic_model(sl_db, snr_req_db, noise_level_db, wind_noise_level_db=None, wind_distance_m=50.0, g_array_db=0.0):
    """Eqs. 106-108 [m]; wind noise given directly as in Table 50."""
    return acoustic_range(
        sl_db=sl_db,
        snr_req_db=snr_req_db,
        noise_level_db=noise_level_db,
        g_array_db=g_array_db,
        wind_noise_level_db=wind_noise_level_db,
        wind_distance_m=wind_distance_m,
    ).range_m


def radar_model(
    p_tx_w, g_db, frequency_ghz, sigma_radar_m2, snr_min_db, noise_figure_db, bandwidth_mhz, t0_k=290.0, k_b=1.381e-23
):
    """Eq. 109 [m], monostatic (G_tx = G_rx = g)."""
    return radar_range(
        p_tx_w=p_tx_w,
        g_tx_db=g_db,
        g_rx_db=g_db,
        wavelength_m=wavelength_m(frequency_ghz, C_LIGHT_PAPER),
        sigma_m2=sigma_radar_m2,
        snr_min_db=snr_min_db,
        t0_k=t0_k,
        noise_figure_db=noise_figure_db,
        bandwidth_mhz=bandwidth_mhz,
        k_b=k_b,
    ).range_m


MODELS = {"eo_johnson": eo_johnson_model, "acoustic": acoustic_model, "radar": radar_model}


@dataclass(frozen=True)
class TornadoBar:
    """One parameter of a tornado plot.

    Attributes
    ----------
    parameter : str
    low_value, default_value, high_value : float
        Perturbation range of the parameter.
    range_at_low_m, range_at_high_m : float
        Predicted range with the parameter at its low / high value [m].
    """

    parameter: str
    low_value: float
    default_value: float
    high_value: float
    range_at_low_m: float
    range_at_high_m: float

    @property
    def span_m(self) -> float:
        """Total influence: |R(high) - R(low)| [m]."""
        return abs(self.range_at_high_m - self.range_at_low_m)

    def as_dict(self) -> dict:
        """JSON form."""
        return {
            "parameter": self.parameter,
            "low": self.low_value,
            "default": self.default_value,
            "high": self.high_value,
            "range_at_low_m": self.range_at_low_m,
            "range_at_high_m": self.range_at_high_m,
            "span_m": self.span_m,
        }


def one_at_a_time(model, parameters: dict, fixed: dict | None = None):
    """One-at-a-time sensitivity of ``model`` (Section 4.9).

    Parameters
    ----------
    model : callable or str
        A function of keyword parameters returning a range [m], or a name of :data:`MODELS`.
    parameters : dict
        ``{name: (low, default, high)}``.
    fixed : dict, optional
        Keyword arguments held constant.

    Returns
    -------
    baseline_m : float
        Range with every parameter at its default.
    bars : list of TornadoBar
        Sorted by decreasing span.
    """
    if isinstance(model, str):
        if model not in MODELS:
            raise ParameterError("model", model, ", ".join(MODELS))
        model = MODELS[model]
    fixed = dict(fixed or {})
    defaults = {}
    for name, triple in parameters.items():
        if len(triple) != 3:
            raise ParameterError(f"parameters.{name}", triple, "[low, default, high]")
        defaults[name] = triple[1]
    baseline = float(model(**defaults, **fixed))
    bars = []
    for name, (low, default, high) in parameters.items():
        values = np.array([low, high], dtype=float)
        ranges = model(**{**defaults, name: values}, **fixed)
        ranges = np.broadcast_to(ranges, values.shape)
        bars.append(TornadoBar(name, float(low), float(default), float(high), float(ranges[0]), float(ranges[1])))
    bars.sort(key=lambda bar: bar.span_m, reverse=True)
    return baseline, bars


def platform_comparison(targets: dict, eo_params: dict, acoustic_params: dict, radar_params: dict) -> dict:
    """Table 52: EO, radar and acoustic ranges of several targets under the Section 4.9 defaults.

    Parameters
    ----------
    targets : dict
        ``{name: {"d_crit_m", "sigma_radar_m2", "sl_db"}}``.
    eo_params, acoustic_params, radar_params : dict
        Default sensor parameters (Tables 48, 49, 51) without the target terms.

    Returns
    -------
    dict
        ``{name: {"eo": R, "radar": R, "acoustic": R}}`` [m].
    """
    out = {}
    for name, t in targets.items():
        out[name] = {
            "eo": float(eo_johnson_model(d_crit_m=t["d_crit_m"], **eo_params)),
            "radar": float(radar_model(sigma_radar_m2=t["sigma_radar_m2"], **radar_params)),
            "acoustic": float(acoustic_model(sl_db=t["sl_db"], **acoustic_params)),
        }
    return out


def _section_defaults(analysis: str) -> dict:
    """The default value of every parameter of one Section 4.9 analysis (Tables 48-51)."""
    spec = load_sensitivity()[analysis]
    return {name: triple[1] for name, triple in spec["parameters"].items()} | dict(spec.get("fixed", {}))


def table_52_platforms() -> dict:
    """Table 52 under the Section 4.9 defaults, with the paper's printed values beside."""
    targets = {}
    for name in load_sensitivity()["platforms"]:
        if name == "source":
            continue
        target = default_values("target") | load_presets()["target"][name]
        targets[name] = {k: target[k] for k in ("d_crit_m", "sigma_radar_m2", "sl_db")}
    eo = {k: v for k, v in _section_defaults("eo").items() if k != "d_crit_m"}
    radar = {k: v for k, v in _section_defaults("radar").items() if k != "sigma_radar_m2"}
    acoustic = {k: v for k, v in _section_defaults("acoustic_calm").items() if k != "sl_db"}
    computed = platform_comparison(targets, eo, acoustic, radar)
    return {
        name: {"computed_m": ranges, "paper_m": load_sensitivity()["platforms"][name]["paper"]}
        for name, ranges in computed.items()
    }
