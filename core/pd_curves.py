"""Probability of detection against range for every sensor of a scenario, and fused (``csuas pd``).

Each sensor's deterministic model (:mod:`csuas.core.ranges`) stays the single source of its
budget. For a threshold-limited sensor (acoustic, RF, radar, lidar) the budget margin at range R,
m(R) [dB], is how far the threshold could rise and the model still reach R: the model is
evaluated once over a grid of threshold shifts (it is vectorised), and m(R) interpolated in
log R. The SNR at R is the SNR at the threshold plus m(R), so m = 0 at the deterministic
range, and every convention's losses (fixed paths, or attenuation growing with R) are
included exactly as the range model has them. The detector of each modality (its record's
``detector``, :mod:`csuas.core.modality`; the formulas of :mod:`csuas.core.detection` and
:mod:`csuas.core.radar_detection`) turns that SNR into Pd; the
imaging sensors use the target transfer probability function of the resolvable cycles. The
line-of-sight horizon, when the scenario gives heights, ends every optical and radio sensor's
reach. Every assumption is a sensor parameter with its default and source
(``defaults/parameters.toml``, docs/detection.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core import camera, detection, johnson, radar, radar_detection, rcs_statistics, tir
from csuas.core.atmosphere import transmittance
from csuas.core.checks import require
from csuas.core.fusion import approach_looks, cumulative_pd, first_detection, fuse_k_of_n, fuse_or
from csuas.core.horizon import line_of_sight_limit_m
from csuas.core.modality import BY_NAME, PartTable
from csuas.core.mrtd import sensor_mrtd
from csuas.core.ranges import (
    ADAPTERS,
    HORIZONS,
    REFERENCE_SENSOR_HEIGHT_M,
    REFERENCE_TARGET_HEIGHT_M,
    evaluate,
    thermal_contrast,
)
from csuas.core.result import check_convention
from csuas.core.scenario import Scenario, SensorSpec
from csuas.core.solve import bracketed_root

#: Threshold shifts over which a model is evaluated to read its margin [dB]; beyond them Pd is saturated.
MARGIN_GRID_DB = np.linspace(-150.0, 150.0, 2401)
#: Probabilities at which ``range_at_pd`` is reported.
REPORTED_PD = (0.5, 0.9)
#: Noise crossings alone along an approach above which ``approach`` says so.
FALSE_ALARM_NOTE = 0.01
#: Points of the default log-spaced range grid, and how far beyond the longest range it reaches.
GRID_POINTS, GRID_BEYOND = 400, 3.0


@dataclass
class PdCurve:
    """Pd of one sensor over a range grid.

    Attributes
    ----------
    sensor, modality : str
    range_m, pd : ndarray
        The range grid [m] and Pd on it.
    deterministic_range_m : float
        The sensor's range from :func:`csuas.core.ranges.evaluate` (the paper's model), before the horizon.
    pd_at_deterministic_range : float or None
        Pd there: the probability the deterministic threshold implies (None when that range is 0).
    assumptions : list of str
        The detector and its parameters, each with where it comes from.
    looks : str
        ``independent`` or ``correlated`` successive looks; ``look_rate_hz`` their rate.
    """

    sensor: str
    modality: str
    range_m: np.ndarray
    pd: np.ndarray
    deterministic_range_m: float
    pd_at_deterministic_range: float | None
    assumptions: list = field(default_factory=list)
    looks: str = "independent"
    look_rate_hz: float = 1.0


def margin_db(scenario: Scenario, sensor: SensorSpec, convention: str, range_m) -> np.ndarray:
    """Budget margin [dB] of a threshold-limited sensor at each range: 0 at its deterministic range.

    Parameters
    ----------
    scenario, sensor
        The resolved scenario and one of its acoustic, RF, radar or lidar sensors.
    convention : {"paper", "physical"}
    range_m : array_like
        Ranges [m], >= 0.

    Returns
    -------
    ndarray
        m(R) [dB], clipped to the grid's +-150 dB (Pd is saturated well before).
    """
    r_query = require("range_m", range_m, ge=0)
    key, in_db = BY_NAME[sensor.modality].threshold_key(sensor.params)
    base = sensor.params[key]
    shifted = base + MARGIN_GRID_DB if in_db else base * 10.0 ** (MARGIN_GRID_DB / 10.0)
    model = replace(sensor, params={**sensor.params, key: shifted})
    reach = np.asarray(ADAPTERS[sensor.modality](scenario, model, convention).range_m, dtype=float)
    usable = np.isfinite(reach) & (reach > 0)
    if not np.any(usable):  # the budget reaches no range at any threshold shift
        return np.full(r_query.shape, MARGIN_GRID_DB[0])
    log_reach, shift = np.log(reach[usable])[::-1], MARGIN_GRID_DB[usable][::-1]  # increasing reach
    keep = np.concatenate([[True], np.diff(log_reach) > 0])
    with np.errstate(divide="ignore"):
        log_r = np.log(np.maximum(r_query, 1e-300))
    return np.interp(log_r, log_reach[keep], shift[keep], left=MARGIN_GRID_DB[-1], right=MARGIN_GRID_DB[0])


def _horizon(scenario: Scenario, sensor: SensorSpec) -> tuple[float, str]:
    """Line-of-sight limit of an optical or radio sensor [m] and how it was set; inf for acoustics.

    With the sensor's ``height_m`` the limit is that of the sensor and the target above it (as
    ``csuas range`` caps the deterministic range); without it, that of the reference heights
    ``csuas range`` flags (a 2 m sensor, a drone at the 120 m ceiling), which Pd cannot pass either.
    """
    if sensor.modality not in HORIZONS:
        return np.inf, ""
    k, label = HORIZONS[sensor.modality]
    height = sensor.params.get("height_m")
    if height is None:
        limit = float(line_of_sight_limit_m(REFERENCE_SENSOR_HEIGHT_M, REFERENCE_TARGET_HEIGHT_M, k))
        how = (
            f"of a {REFERENCE_SENSOR_HEIGHT_M:g} m sensor and a {REFERENCE_TARGET_HEIGHT_M:g} m target, the "
            f"reference csuas range flags (set sensors.{sensor.name}.height_m and target.altitude_m to place it)"
        )
    else:
        target_height = max(height + scenario.target["altitude_m"], 0.0)
        limit = float(line_of_sight_limit_m(height, target_height, k))
        how = f"of the sensor at {height:g} m and the target at {target_height:g} m"
    return limit, f"Pd = 0 beyond the {label} ({limit / 1000:.3g} km) {how}"


def _source(sensor: SensorSpec, key: str) -> str:
    return f"sensors.{sensor.name}.{key}" + ("" if key in sensor.explicit else " default")


def _ttpf_note(sensor: SensorSpec) -> str:
    exponent = sensor.params["ttpf_exponent"]
    return f"target transfer probability function, exponent {exponent} ({_source(sensor, 'ttpf_exponent')})"


def _johnson_pd(scenario, sensor, r, cutoff_m, notes):
    """TTPF of the cycles across d_crit (Eq. 17), 0 beyond ``cutoff_m``; its note appended to ``notes``."""
    p, t = sensor.params, scenario.target
    ifov = johnson.ifov_rad(p["hfov_deg"], p["n_h"])
    r50 = johnson.johnson_range_m(t["d_crit_m"], ifov, p["lp_task"], 1.0)
    notes.append(f"cycles across d_crit from Eq. 17: x = R50 / R, R50 = {float(r50):.4g} m")
    return detection.imaging_pd(r, r50, p["ttpf_exponent"], cutoff_m)


def _eo_pd(scenario, sensor, convention, r, result):
    """Pd of an EO camera: the TTPF to the contrast-limited range (Eq. 21), times, in the physical
    convention, the camera's detection of the blob above its noise."""
    p, t = sensor.params, scenario.target
    cutoff = float(np.asarray(result.term("contrast_limited_range_m").value))
    notes = [_ttpf_note(sensor), "Pd = 0 beyond the contrast-limited range (Eq. 21)"]
    pd = _johnson_pd(scenario, sensor, r, cutoff, notes)
    if convention == "physical":
        ifov = johnson.ifov_rad(p["hfov_deg"], p["n_h"])
        noise = float(np.asarray(result.term("pixel_noise_electrons").value))
        excess = abs(float(camera.luminance_excess(t["c_eo"]))) * float(
            np.asarray(result.term("background_electrons").value)
        )
        tau = transmittance(float(np.asarray(result.term("kruse_extinction").value)), r, convention)
        snr = detection.blob_snr(excess * tau, noise, detection.target_pixels(t["projected_area_m2"], ifov, r))
        pd = pd * detection.gaussian_pd(snr, p["pfa"])
        notes.append(
            f"times the camera's detection above noise: blob SNR of {excess:.3g} e excess per pixel over "
            f"{noise:.3g} e noise, Gaussian threshold at Pfa = {p['pfa']:g} ({_source(sensor, 'pfa')})"
        )
    return pd, notes


def _tir_pd(scenario, sensor, convention, r, result):
    """Pd of a thermal imager by its range model: blob detection in NETD, MRTD's resolvable cycles, or Johnson's."""
    p, t = sensor.params, scenario.target
    if p["model"] == "netd":
        ifov = johnson.ifov_rad(p["hfov_deg"], p["n_h"])
        dt0, extra = thermal_contrast(scenario, sensor, convention)
        dt = tir.attenuated_delta_t(dt0, r, p["extinction_db_km"], convention, **extra)
        snr = detection.blob_snr(dt, p["netd_mk"] / 1000.0, detection.target_pixels(t["projected_area_m2"], ifov, r))
        notes = [
            f"blob detection in temporal noise: SNR = |Delta T(R)| sqrt(pixels) / NETD, NETD {p['netd_mk']:g} mK "
            f"({_source(sensor, 'netd_mk')}), below a pixel |Delta T| pixels / NETD",
            f"Gaussian threshold at Pfa = {p['pfa']:g} ({_source(sensor, 'pfa')}): Pd = Q(Q^-1(Pfa) - SNR)",
        ]
        return detection.gaussian_pd(snr, p["pfa"]), notes
    notes = [_ttpf_note(sensor)]
    if p["model"] == "mrtd":
        notes.append(
            "resolvable cycles: the highest frequency whose MRTD the apparent Delta T(R) exceeds, over lp_task"
        )
        return _mrtd_pd(scenario, sensor, convention, r), notes
    return _johnson_pd(scenario, sensor, r, np.inf, notes), notes


def _mrtd_pd(scenario, sensor, convention, r):
    """TTPF of the resolvable cycles f*(R) d_crit / (lp R), f* where MRTD(f*) = |Delta T(R)|."""
    p, t = sensor.params, scenario.target
    curve = sensor_mrtd(p)
    dt0, extra = thermal_contrast(scenario, sensor, convention)
    dt = np.abs(tir.attenuated_delta_t(dt0, r, p["extinction_db_km"], convention, **extra))
    f_star = curve.max_frequency(dt)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(r > 0, f_star * t["d_crit_m"] / (p["lp_task"] * np.where(r > 0, r, 1.0)), np.inf)
    return detection.ttpf_probability(np.where(np.isnan(x), 0.0, x), p["ttpf_exponent"])


def _margin_and_pfa(scenario, sensor, convention, r):
    """A threshold sensor's margin at each range [dB] (:func:`margin_db`), its Pfa and the note of the Pfa."""
    pfa = sensor.params["pfa"]
    return margin_db(scenario, sensor, convention, r), pfa, [f"Pfa = {pfa:g} ({_source(sensor, 'pfa')})"]


def _radar_pd(scenario, sensor, convention, r, result):
    """Pd of a radar: square-law detection of the integrated pulses, Swerling or the drone's own aspect RCS.

    ``result`` (the deterministic range) is not needed: the margin re-reads the model.
    """
    p = sensor.params
    m, pfa, notes = _margin_and_pfa(scenario, sensor, convention, r)
    n, integration = int(p["n_pulses"]), p["integration"]
    gain_db = 10 * np.log10(float(radar.integration_gain(n, integration, convention)))
    snr1_db = p["snr_min_db"] - gain_db
    swerling = int(p["swerling"])
    if integration == "none":
        n, mode = 1, "noncoherent"
    else:
        mode = integration
    notes += [
        f"{n} pulse(s), {mode} integration",
        f"single-pulse SNR at the deterministic range: snr_min_db - integration gain = {snr1_db:.4g} dB",
    ]
    fluctuation = p.get("fluctuation", "swerling")
    if fluctuation == "swerling":
        notes.insert(1, f"square-law detector, Swerling {swerling} ({_source(sensor, 'swerling')})")
        return radar_detection.pd_exact(snr1_db + m, pfa, n, swerling, mode), notes
    polarisation = fluctuation.removeprefix("aspect_").upper()
    frequency_ghz = radar.radar_frequency_ghz(p)
    dof, band = rcs_statistics.aspect_chi_square_dof(scenario.target_preset, frequency_ghz, polarisation)
    notes.insert(
        1,
        f"square-law detector, RCS of {scenario.target_preset} over aspects, scan to scan: chi-square with "
        f"{dof:.3g} degrees of freedom ({polarisation}, {band:g} GHz band of defaults/drone_rcs_statistics.csv)",
    )
    return rcs_statistics.pd_chi_square_target(snr1_db + m, pfa, n, dof, mode), notes


def _energy_pd(sensor, snr_db, pfa):
    """The energy detector's Pd at each SNR [dB] with the sensor's M, fading and Rician K."""
    p = sensor.params
    fading = p.get("fading", "none")
    return detection.energy_detector_pd(snr_db, pfa, p["time_bandwidth"], fading, p.get("rician_k_db", 0.0))


def _energy_note(sensor) -> str:
    return f"energy detector, M = {sensor.params['time_bandwidth']:g} ({_source(sensor, 'time_bandwidth')})"


def _rf_pd(scenario, sensor, convention, r, result):
    """Pd of an RF detector: an energy detector, its SNR given at the sensitivity, with the link's fading.

    ``result`` (the deterministic range) is not needed: the margin re-reads the model.
    """
    p = sensor.params
    m, pfa, notes = _margin_and_pfa(scenario, sensor, convention, r)
    reference, fading = p["snr_at_sensitivity_db"], p.get("fading", "none")
    notes.append(_energy_note(sensor))
    notes.append(f"SNR {reference:g} dB at s_rx_dbm ({_source(sensor, 'snr_at_sensitivity_db')})")
    notes.append(f"fading {fading}" + (f", K = {p['rician_k_db']:g} dB" if fading == "rician" else ""))
    return _energy_pd(sensor, reference + m, pfa), notes


def _acoustic_pd(scenario, sensor, convention, r, result):
    """Pd of an acoustic array: an energy detector at the required SNR.

    ``result`` (the deterministic range) is not needed: the margin re-reads the model.
    """
    m, pfa, notes = _margin_and_pfa(scenario, sensor, convention, r)
    reference = sensor.params["snr_req_db"]
    notes.append(_energy_note(sensor))
    notes.append(f"SNR at the threshold: snr_req_db = {reference:g} dB")
    return _energy_pd(sensor, reference + m, pfa), notes


def acoustic_pd_with_loss(scenario: Scenario, sensor_name: str, range_m, loss_db) -> np.ndarray:
    """Pd of an acoustic sensor at slant ranges with an extra path loss, e.g. a terrain barrier (ISO 9613-2 Eq. 12).

    The energy detector of :func:`_acoustic_pd` at the SNR snr_req_db + m(R) - loss: the budget margin
    (:func:`margin_db`, the scenario's convention) less the loss the free-field model does not hold.

    Parameters
    ----------
    scenario : Scenario
    sensor_name : str
        Key of an acoustic sensor of the scenario.
    range_m, loss_db : array_like
        Slant ranges [m] and the extra loss at each [dB], >= 0.
    """
    sensor = scenario.sensors[sensor_name]
    if sensor.modality != "acoustic":
        raise ParameterError("sensor", sensor_name, "an acoustic sensor of the scenario")
    loss = require("loss_db", loss_db, ge=0)
    m = margin_db(scenario, sensor, check_convention(scenario.convention), range_m)
    return _energy_pd(sensor, sensor.params["snr_req_db"] + m - loss, sensor.params["pfa"])


def _lidar_pd(scenario, sensor, convention, r, result):
    """Pd of a lidar: photon counting (Poisson) or a linear-mode receiver in Gaussian noise.

    ``result`` (the deterministic range) is not needed: the margin re-reads the model.
    """
    p = sensor.params
    m, pfa, notes = _margin_and_pfa(scenario, sensor, convention, r)
    if p["detector"] == "poisson":
        signal = p["photons_at_threshold"] * 10.0 ** (m / 10.0)
        notes.append(
            f"photon counting: {p['photons_at_threshold']:g} signal photons at p_rx_min_w, "
            f"{p['noise_photons']:g} noise counts per gate"
        )
        return detection.lidar_pd_poisson(signal, p["noise_photons"], pfa), notes
    notes.append(
        f"linear-mode receiver in Gaussian noise, electrical SNR {p['snr_at_threshold_db']:g} dB at p_rx_min_w "
        "(SNR grows as the square of the received power)"
    )
    return detection.lidar_pd_gaussian(p["snr_at_threshold_db"] + 2.0 * m, pfa), notes


#: Modality -> its detector (each record's ``detector``, csuas.core.modality).
DETECTORS = PartTable("detector")


def sensor_pd(scenario: Scenario, sensor_name: str, range_m, convention: str | None = None) -> PdCurve:
    """Pd against range of one sensor of a scenario.

    Parameters
    ----------
    scenario : Scenario
    sensor_name : str
        Key of the sensor in the scenario.
    range_m : array_like
        Slant ranges [m], >= 0.
    convention : {"paper", "physical"}, optional
        Overrides the scenario's convention.
    """
    conv = check_convention(convention or scenario.convention)
    if sensor_name not in scenario.sensors:
        raise ParameterError("sensor", sensor_name, ", ".join(scenario.sensors))
    sensor = scenario.sensors[sensor_name]
    r = require("range_m", range_m, ge=0)
    result = ADAPTERS[sensor.modality](scenario, sensor, conv)  # the paper's model, before the horizon
    deterministic = float(np.asarray(result.range_m))
    # the grid and the deterministic range in one evaluation (a threshold sensor's margin is read once)
    at = np.append(r.ravel(), deterministic)
    pd_at, notes = DETECTORS[sensor.modality](scenario, sensor, conv, at, result)
    pd = np.asarray(pd_at, dtype=float)[:-1].reshape(r.shape)
    at_deterministic = float(pd_at[-1]) if deterministic > 0 else None  # a zero range crosses no threshold
    horizon, note = _horizon(scenario, sensor)
    if np.isfinite(horizon):
        pd = np.where(r > horizon, 0.0, pd)
        notes.append(note)
    return PdCurve(
        sensor_name,
        sensor.modality,
        r,
        pd,
        deterministic,
        at_deterministic,
        notes,
        sensor.params["looks"],
        float(sensor.params["look_rate_hz"]),
    )


def default_range_grid(scenario: Scenario, convention: str | None = None) -> np.ndarray:
    """GRID_POINTS log-spaced ranges from 1 m to GRID_BEYOND times the longest range Pd can reach [m].

    Each sensor's reach is its deterministic range, or its line-of-sight horizon where nearer.
    """
    reach = [
        min(float(np.max(r.range_m)), _horizon(scenario, scenario.sensors[name])[0])
        for name, r in evaluate(scenario, convention).items()
    ]
    longest = max([r for r in reach if np.isfinite(r) and r > 0], default=1000.0)
    return np.geomspace(1.0, max(GRID_BEYOND * longest, 10.0), GRID_POINTS)


def range_at_pd(pd_of_range, search_range_m, targets=REPORTED_PD) -> list:
    """The largest range at which a Pd model still reaches each target, solved on the model [m].

    The last crossing is bracketed on ``search_range_m`` and solved in log range by
    :func:`csuas.core.solve.bracketed_root` on ``pd_of_range`` itself (not interpolated between
    the search points); a jump (a horizon, the EO contrast limit) is found where it is.

    Parameters
    ----------
    pd_of_range : callable
        ``pd_of_range(range_m) -> ndarray``: Pd at each range of an array [m].
    search_range_m : array_like
        Ranges that bracket the crossings [m], > 0, increasing.
    targets : sequence of float
        Probabilities, each 0..1.

    Returns
    -------
    list of float or None
        One range per target [m]: the solved crossing; the last search point itself where Pd still
        reaches the target there; None where Pd reaches it at no search point.
    """
    r = require("search_range_m", search_range_m, gt=0)
    p = np.asarray(pd_of_range(r), dtype=float)
    found, lo, hi, index = [], [], [], []
    for i, target in enumerate(targets):
        above = np.nonzero(p >= target)[0]
        found.append(None if above.size == 0 else float(r[above[-1]]))
        if above.size and above[-1] < r.size - 1:
            lo.append(np.log(r[above[-1]]))
            hi.append(np.log(r[above[-1] + 1]))
            index.append(i)
    if index:
        goal = np.asarray(targets, dtype=float)[index]
        root, _ = bracketed_root(
            lambda u: np.asarray(pd_of_range(np.exp(u)), dtype=float) - goal, lo, hi, xtol=1e-10, rtol=0.0
        )
        for i, u in zip(index, root):
            found[i] = float(np.exp(u))
    return found


def _fuse_stack(stack: np.ndarray, rule: str) -> np.ndarray:
    """Fuse independent sensors' probabilities (sensors along the first axis) by ``or`` or ``k-of-n:K``."""
    if rule == "or":
        return fuse_or(stack)
    kind, _, k = rule.partition(":")
    if kind != "k-of-n" or not k.isdigit():
        raise ParameterError("fusion", rule, "or, or k-of-n:K with K a whole number")
    return fuse_k_of_n(stack, int(k))


def fuse(curves: list, rule: str = "or") -> np.ndarray:
    """Fused Pd of independent sensors on a shared range grid: ``or`` or ``k-of-n:K``."""
    return _fuse_stack(np.stack([c.pd for c in curves]), rule)


def fused_pd_of_range(scenario: Scenario, rule: str = "or", convention: str | None = None):
    """The fused Pd of all the scenario's sensors as a function of range (for :func:`range_at_pd`)."""
    return lambda r: fuse([sensor_pd(scenario, name, r, convention) for name in scenario.sensors], rule)


def approach(
    scenario: Scenario,
    sensor_name: str,
    speed_m_s: float,
    start_range_m: float,
    stop_range_m: float = 0.0,
    convention: str | None = None,
) -> dict:
    """Cumulative Pd of one sensor along a straight approach at constant speed, looking at its own rate.

    Parameters
    ----------
    scenario, sensor_name, convention
        As in :func:`sensor_pd`.
    speed_m_s : float
        Closing speed of the drone [m/s].
    start_range_m, stop_range_m : float
        Where the approach starts and ends [m].

    Returns
    -------
    dict
        ``look_range_m`` and ``cumulative_pd`` at each of the sensor's looks (independent or
        correlated, the sensor's ``looks``), ``median_range_m`` of the first detection (a look;
        None when the approach ends first), ``never`` (the probability of no detection),
        ``false_alarm_cumulative`` (independent looks with a Pfa: 1 - (1 - Pfa)^n after n looks
        with Pd > 0, what noise crossings alone put in ``cumulative_pd``; else None) and ``notes``
        (that floor when it exceeds 1 %).
    """
    sensor = scenario.sensors.get(sensor_name)
    if sensor is None:
        raise ParameterError("sensor", sensor_name, ", ".join(scenario.sensors))
    looks = approach_looks(start_range_m, stop_range_m, speed_m_s, sensor.params["look_rate_hz"])
    curve = sensor_pd(scenario, sensor_name, looks, convention)
    cumulative = cumulative_pd(curve.pd, sensor.params["looks"])
    first = first_detection(looks, cumulative)
    out = {
        "look_range_m": looks,
        "cumulative_pd": cumulative,
        "median_range_m": first["median_range_m"],
        "never": float(first["never"]),
        "false_alarm_cumulative": None,
        "notes": [],
    }
    pfa = sensor.params.get("pfa")
    if pfa is not None and sensor.params["looks"] == "independent":
        counted = np.cumsum(curve.pd > 0)  # looks beyond the horizon (Pd = 0) add no noise crossing
        out["false_alarm_cumulative"] = -np.expm1(counted * np.log1p(-pfa))
        floor = out["false_alarm_cumulative"][-1]
        if floor > FALSE_ALARM_NOTE:
            out["notes"].append(
                f"false alarms alone reach {floor:.2g} over the approach's {counted[-1]} looks within reach "
                f"(Pfa {pfa:g} each)"
            )
    return out


def _step(looks: np.ndarray, values: np.ndarray, r: np.ndarray) -> np.ndarray:
    """A quantity known after each look (far to near), read at ranges r: that of the last look at or beyond r."""
    index = np.searchsorted(-looks, -r, side="right") - 1
    return np.where(index >= 0, values[np.maximum(index, 0)], 0.0)


def fused_cumulative(approaches: list, range_m, rule: str = "or") -> np.ndarray:
    """Cumulative Pd of independent sensors along one approach, on common ranges.

    Each sensor's cumulative probability at R is that of its last look at or beyond R (a step
    function: nothing is gained between looks). The sensors' events "has detected by R" are
    independent, so the fused probability is the rule applied to them: ``or``,
    1 - prod(1 - C_s(R)); ``k-of-n:K``, the probability that at least K sensors have each
    detected by R (exact Poisson-binomial tail, :func:`csuas.core.fusion.fuse_k_of_n`).

    Parameters
    ----------
    approaches : list of dict
        :func:`approach` results.
    range_m : array_like
        Ranges [m], >= 0.
    rule : str
        ``or`` or ``k-of-n:K``.
    """
    r = require("range_m", range_m, ge=0)
    stack = np.stack([_step(a["look_range_m"], a["cumulative_pd"], r) for a in approaches])
    return _fuse_stack(stack, rule)


def fused_first_detection_m(approaches: list, rule: str = "or") -> float | None:
    """Median range of the fused first detection [m]: the first look of any sensor by which it reaches 0.5.

    The fused cumulative Pd only rises at a look of some sensor and never falls along the approach
    (each sensor's does not, and OR and the k-of-n tail grow with each), so its discrete first-detection
    distribution lives on the sensors' looks: the median is the farthest of each sensor's first look at
    which the fused Pd reaches 0.5, found by bisection over that sensor's looks. None when it never does.
    """
    median = None
    for a in approaches:
        looks = a["look_range_m"]  # far to near
        lo, hi = 0, looks.size
        while lo < hi:
            mid = (lo + hi) // 2
            if fused_cumulative(approaches, looks[mid : mid + 1], rule)[0] >= 0.5:
                hi = mid
            else:
                lo = mid + 1
        if lo < looks.size and (median is None or looks[lo] > median):
            median = float(looks[lo])
    return median
