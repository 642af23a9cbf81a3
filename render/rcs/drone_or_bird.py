"""Drone or bird by the radar's Doppler spectrum: a scenario's drone as a Doppler-spread target (``csuas pd
--micro-doppler``, engagements' ``[classification]``).

The preset's rotors (:func:`csuas.render.rcs.micro_doppler.drone_rotors`: count, blades, tip radius)
and the mean chord of its blades (root and tip, :func:`csuas.drone_models.presets.preset_parameters`)
give the blade lines of flat PEC blades in closed form
(:func:`csuas.core.micro_doppler.blade_line_rcs_m2`), turning at the scenario target's
``blade_passing_hz / N`` (the same rate its acoustic model hears); the body line is the target's
``sigma_radar_m2``, the RCS its radar budget already holds. The guard band is the widest wing-tip
Doppler of the bird classes of ``defaults/birds.toml``. The decision and its probabilities are
:func:`csuas.core.micro_doppler_detection.blade_feature_pd`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError, raise_all
from csuas.core import radar
from csuas.core.micro_doppler import blade_line_rcs_m2, line_spacing_hz, max_tip_doppler_hz
from csuas.core.micro_doppler_detection import (
    LINE_SWERLING,
    bird_guard_doppler_hz,
    blade_feature_pd,
    line_snr_fractions,
)
from csuas.defaults import load_birds


@dataclass(frozen=True)
class ClassifierSettings:
    """The Doppler dwell of the decision: PRF [Hz], dwell [s] and the radar's direction in the drone's body frame,
    elevation and azimuth from the nose [deg]. A multirotor's rotor plane is the body's xy-plane, so the elevation
    is the radar's above it; a fixed-wing's pusher turns about +x, so seen nose-on (azimuth 0) the radar is
    90 - elevation above its plane (Eq. MD-6).

    Defaults: the X-band figures of ``csuas micro-doppler`` (20 kHz, elevation 10 deg, azimuth 0: an approaching
    drone) and a 50 ms dwell (ten flash periods at 200 Hz lines), assumptions.
    """

    prf_hz: float = 20_000.0
    dwell_s: float = 0.05
    elevation_deg: float = 10.0
    azimuth_deg: float = 0.0

    def check(self, key: str = "micro_doppler") -> ClassifierSettings:
        """Raise every out-of-range field at once, named ``key.field``."""
        checks = [
            ("prf_hz", self.prf_hz, "0 < PRF <= 10 MHz", 0.0 < self.prf_hz <= 1e7),
            ("dwell_s", self.dwell_s, "0 < dwell <= 1 s", 0.0 < self.dwell_s <= 1.0),
            ("elevation_deg", self.elevation_deg, "0 < elevation < 90", 0.0 < self.elevation_deg < 90.0),
            ("azimuth_deg", self.azimuth_deg, "-360..360", -360.0 <= self.azimuth_deg <= 360.0),
        ]
        raise_all([ParameterError(f"{key}.{name}", value, why) for name, value, why, ok in checks if not ok])
        if not 1 <= round(self.prf_hz * self.dwell_s) <= 10_000:
            raise ParameterError(f"{key}.dwell_s", self.dwell_s, f"1 to 10,000 pulses at PRF {self.prf_hz:g} Hz")
        return self


def bird_guard_hz(frequency_ghz: float) -> float:
    """The widest wing-tip Doppler of the bird classes of ``defaults/birds.toml`` at a frequency [Hz]."""
    return max(
        float(bird_guard_doppler_hz(b["wingspan_m"], b["wingbeat_hz"], b["wing_stroke_amplitude_deg"], frequency_ghz))
        for b in load_birds().values()
    )


def preset_blade_lines(preset: str, frequency_ghz: float, blade_passing_hz: float, aspect_deg: tuple) -> dict:
    """The blade lines of a preset's rotors (module docstring): ``frequency_hz``, ``rcs_m2`` (zero line left out),
    seen from ``aspect_deg`` (azimuth, elevation toward the radar in the body frame [deg]); every rotor of a preset
    turns about the same axis, the radar at ``rotor_plane_elevation_deg`` above their plane (Eq. MD-6)."""
    from csuas.drone_models.presets import preset_parameters

    from .micro_doppler import drone_rotors, rotor_aspect_deg

    rotors, _ = drone_rotors(preset)
    _, params, _ = preset_parameters(preset)
    n_blades, tip = rotors[0].n_blades, max(r.tip_radius_m for r in rotors)
    chord = (params.blade_root_chord_m + params.blade_tip_chord_m) / 2.0
    rate = blade_passing_hz / n_blades
    elevation_deg = float(rotor_aspect_deg(rotors[0], *aspect_deg)[1])
    order, frequency, rcs = blade_line_rcs_m2(tip, n_blades, rate, frequency_ghz, elevation_deg, chord, len(rotors))
    return {
        "frequency_hz": frequency[order != 0],
        "rcs_m2": rcs[order != 0],
        "zero_line_rcs_m2": float(rcs[order == 0].sum()),
        "line_spacing_hz": float(line_spacing_hz(n_blades, rate)),
        "max_tip_doppler_hz": float(max_tip_doppler_hz(tip, rate, frequency_ghz, elevation_deg)),
        "rotors": len(rotors),
        "n_blades": n_blades,
        "chord_m": chord,
        "tip_radius_m": tip,
        "spin_axis": rotors[0].spin_axis.tolist(),
        "rotor_plane_elevation_deg": elevation_deg,
    }


def drone_or_bird(scenario, params: dict, snr1_db, settings: ClassifierSettings, key: str = "micro_doppler") -> dict:
    """The drone's line SNRs and the decision's probabilities for one radar of a scenario.

    Parameters
    ----------
    scenario : Scenario
        Its target preset has rotor blades, its target ``sigma_radar_m2`` and ``blade_passing_hz``.
    params : dict
        The radar's parameters (frequency, ``pfa`` per Doppler bin).
    snr1_db : array_like (R,)
        Single-pulse SNR of the body line at each range [dB].
    settings : ClassifierSettings
    key : str
        The settings' key in errors (``micro_doppler`` of ``csuas pd``, ``classification`` of engagements).

    Raises
    ------
    ParameterError
        ``target.preset`` without rotor blades; ``<key>.dwell_s`` too short to resolve the blade lines.
    """
    frequency = radar.radar_frequency_ghz(params)
    target = scenario.target
    try:
        aspect = (settings.azimuth_deg, settings.elevation_deg)
        lines = preset_blade_lines(scenario.target_preset, frequency, target["blade_passing_hz"], aspect)
    except ParameterError as exc:
        raise ParameterError("target.preset", scenario.target_preset, exc.allowed) from None
    body = float(target["sigma_radar_m2"])
    n = int(round(settings.prf_hz * settings.dwell_s))
    if n < settings.prf_hz / lines["line_spacing_hz"]:
        raise ParameterError(
            f"{key}.dwell_s",
            settings.dwell_s,
            f">= 1 / line spacing = {1.0 / lines['line_spacing_hz']:.4g} s (bins that resolve the blade lines)",
        )
    guard = bird_guard_hz(frequency)
    feature = blade_feature_pd(
        snr1_db, body, lines["frequency_hz"], lines["rcs_m2"], params["pfa"], settings.prf_hz, n, guard
    )
    body_share, line_shares = line_snr_fractions(body, np.append(lines["rcs_m2"], lines["zero_line_rcs_m2"]))
    strongest = feature["line_snr_db"].max(axis=1) if feature["lines_tested"] else np.full(np.shape(snr1_db), None)
    return {
        "line_spacing_hz": lines["line_spacing_hz"],
        "max_tip_doppler_hz": lines["max_tip_doppler_hz"],
        "guard_hz": guard,
        "pulses": n,
        "tested_bins": feature["tested_bins"],
        "lines_tested": feature["lines_tested"],
        "body_power_fraction": body_share,
        "blade_power_fraction": float(line_shares.sum()),
        "blade_line_snr_db": strongest,
        "pd_classified_drone": feature["pd_drone"],
        "p_bird_classified_drone": feature["p_bird"],
        "assumptions": [
            f"{lines['rotors']} rotors of {lines['n_blades']} flat PEC blades, "
            f"tip radius {lines['tip_radius_m']:.4g} m, "
            f"mean chord {lines['chord_m']:.4g} m, at blade_passing_hz / N (closed form, core/micro_doppler.py)",
            f"body line: target sigma_radar_m2 = {body:g} m^2; lines add in power over rotors",
            f"dwell {n} pulses at PRF {settings.prf_hz:g} Hz, elevation {settings.elevation_deg:g} deg (assumed)",
            *(
                []
                if lines["spin_axis"] == [0.0, 0.0, 1.0]
                else [
                    f"propeller axis {lines['spin_axis']} (body frame), radar at azimuth {settings.azimuth_deg:g} deg: "
                    f"{lines['rotor_plane_elevation_deg']:.4g} deg above the propeller plane (assumed aspect)"
                ]
            ),
            f"guard band +-{guard:.0f} Hz: widest bird wing-tip Doppler (defaults/birds.toml)",
            f"each line Swerling {LINE_SWERLING}, centred in its Doppler bin; Pfa {params['pfa']:g} per bin",
            *(
                ["lines beyond PRF/2 (aliased) not tested"]
                if lines["max_tip_doppler_hz"] > settings.prf_hz / 2.0
                else []
            ),
        ],
    }
