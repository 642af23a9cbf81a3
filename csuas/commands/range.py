"""``csuas range SCENARIO``: predicted detection range of each sensor, with everything it used.

JSON (``--json``): ``sensors.<name>`` with ``range_m``, ``modality``, ``model``, ``terms`` (each
``{value, unit, source}``), ``reason`` (why a range is zero, short, unbounded or capped),
``horizontal_range_m`` (with ``target.altitude_m``; null where the target is never within range),
``inputs`` (every parameter used, ``{value, unit, source}``, source ``scenario``, ``preset NAME``,
``derived from ...`` or ``default (TABLE)``) and ``notes``; top-level ``target_inputs``,
``environment_inputs``, ``effects``, ``ignored_effects`` and ``warnings``. With ``target.swarm`` also a
top-level ``swarm`` (``count``, ``formation``, ``offsets_m``) and per sensor ``swarm``
(:func:`csuas.core.swarm_detection.swarm_range`: ``first_detection_m`` of any member, ``resolved_count`` and
``largest_group`` there, ``single_drone_range_m``, ``terms``, ``assumption``); the other keys stay one drone's.
"""

from __future__ import annotations

import sys

import numpy as np

from csuas.core.radar import radar_wavelength_m
from csuas.core.range_notes import sensor_notes
from csuas.core.ranges import evaluate
from csuas.core.scenario import load_scenario, provenance
from csuas.core.swarm_detection import formation_json, swarm_range

#: Effects a scenario may declare that no range model of the paper reads, with the reason (paper convention;
#: the physical convention's EO camera chain reads the illuminance, docs/detection.md).
IGNORED_EFFECTS = {
    "night": "no range model of the paper reads illuminance_lx (Table 11): the EO model (Eqs. 18, 21) "
    "has no light-level term, so night changes no range (the physical convention's EO camera chain reads it)",
    "fog_layer": "the paper's fog fills the whole path (Eqs. 19-21): fog_top_m changes no range (the physical "
    "convention's EO path crosses fog only below it)",
}
#: Meaning of a null horizontal range (the target higher above the sensor than the slant range).
NEVER_WITHIN_RANGE = "null: the target's altitude exceeds the slant range, it is never within range at that altitude"


def add_arguments(parser):
    """Declare the options of ``csuas range``."""
    parser.add_argument(
        "scenario",
        help="scenario TOML file, or an embedded scenario name (default, adverse, black_hornet, fixed_wing, swarm)",
    )
    parser.add_argument(
        "--convention",
        choices=("paper", "physical"),
        default=None,
        help="override the scenario's convention (docs/conventions.md)",
    )


def _scalar(value):
    arr = np.asarray(value)
    return arr.item() if arr.size == 1 else arr


def run(args) -> dict:
    """Evaluate the scenario; return ``{scenario, convention, effects, sensors: {name: {...}}, ...}``."""
    scenario = load_scenario(args.scenario)
    for warning in scenario.warnings:
        print(f"csuas range: warning: {warning}", file=sys.stderr)
    convention = args.convention or scenario.convention
    results = evaluate(scenario, convention)
    sensors = {}
    for name, result in results.items():
        spec = scenario.sensors[name]
        entry = result.as_dict()
        entry["range_m"] = _scalar(entry["range_m"])
        entry["terms"] = {k: {**v, "value": _scalar(v["value"])} for k, v in entry["terms"].items()}
        if "horizontal_range_m" in entry["terms"]:
            horizontal = entry["terms"]["horizontal_range_m"]
            entry["horizontal_range_m"] = horizontal["value"]
            if np.any(np.isnan(horizontal["value"])):
                entry["horizontal_range_m_note"] = horizontal["value_note"] = NEVER_WITHIN_RANGE
        if "reason" in entry:
            entry["reason"] = _scalar(entry["reason"])
        entry["preset"] = spec.preset
        entry["inputs"] = provenance(spec.modality, spec.params, spec.origin)
        if spec.modality == "radar" and spec.params.get("frequency_ghz") is not None:
            entry["inputs"]["wavelength_m"] = {
                "value": radar_wavelength_m(spec.params, convention),
                "unit": "m",
                "source": "derived from frequency_ghz (c = 3e8 m/s in the paper convention, Section 4.9.3)",
            }
        entry["notes"] = sensor_notes(spec.modality, spec.preset, spec.explicit)
        if scenario.swarm is not None:
            entry["swarm"] = swarm_range(scenario, name, convention)
        sensors[name] = entry
    effects = sorted(scenario.effects)
    out = {
        "scenario": scenario.name,
        "convention": convention,
        "target": scenario.target_preset,
        "environment": scenario.environment_preset,
        "effects": effects,
        "ignored_effects": {e: IGNORED_EFFECTS[e] for e in effects if e in IGNORED_EFFECTS and convention == "paper"},
        "warnings": list(scenario.warnings),
        "target_inputs": provenance("target", scenario.target, scenario.origin["target"]),
        "environment_inputs": provenance("environment", scenario.environment, scenario.origin["environment"]),
        "sensors": sensors,
    }
    if scenario.swarm is not None:
        out["swarm"] = formation_json(scenario)
    return out


def _metres(value) -> str:
    if value is None or not np.isfinite(value):
        return "unbounded" if value is not None and value > 0 else "n/a"
    return f"{value:.1f} m" if value >= 1.0 else f"{value:.3g} m"


def _value(value) -> str:
    if isinstance(value, (float, np.floating)):
        return f"{value:.6g}" if np.isfinite(value) else ("n/a" if np.isnan(value) else f"{value:+}")
    if isinstance(value, np.ndarray):
        return np.array2string(value, precision=4, separator=", ")
    return str(value)


def render_text(result: dict) -> str:
    """The ranges, then each sensor's applied terms and the inputs not at their defaults."""
    lines = [
        f"scenario {result['scenario']} ({result['convention']} convention), target {result['target']}, "
        f"environment {result['environment']}, effects: {', '.join(result['effects']) or 'none'}"
    ]
    lines += [f"  note: {effect} changes nothing: {why}" for effect, why in result["ignored_effects"].items()]
    for name, s in result["sensors"].items():
        horizontal = f", horizontal {_metres(s['horizontal_range_m'])}" if "horizontal_range_m" in s else ""
        lines.append(f"  {name:<12} {s['modality']:<9} {_metres(s['range_m']):>14}{horizontal}   {s['model']}")
        if s.get("reason"):
            lines.append(f"      why: {s['reason']}")
        lines += [
            f"      term  {k:<26} {_value(t['value']):>14} {t['unit']:<6} {t['source']}" for k, t in s["terms"].items()
        ]
        lines += [
            f"      input {k:<26} {_value(i['value']):>14} {i['unit']:<6} {i['source']}"
            for k, i in s["inputs"].items()
            if not i["source"].startswith("default")
        ]
        lines += [f"      note: {n}" for n in s["notes"]]
        if "swarm" in s:
            w = s["swarm"]
            lines.append(
                f"      swarm of {w['count']}: first detection {_metres(w['first_detection_m'])} "
                f"({w['resolved_count']} resolved there, largest group {w['largest_group']}); {w['assumption']}"
            )
    given = {
        **{f"target.{k}": v for k, v in result["target_inputs"].items()},
        **{f"environment.{k}": v for k, v in result["environment_inputs"].items()},
    }
    shown = [
        f"  input {k:<32} {_value(i['value']):>14} {i['unit']:<6} {i['source']}"
        for k, i in given.items()
        if not i["source"].startswith("default")
    ]
    if shown:
        lines.append("  target and environment inputs not at their defaults (all of them: --json):")
        lines += shown
    return "\n".join(lines)
