"""``csuas range SCENARIO``: predicted detection range of each sensor (SPEC 8)."""

from __future__ import annotations

import numpy as np

from csuas.ranges import evaluate
from csuas.scenario import load_scenario


def add_arguments(parser):
    """Declare the options of ``csuas range``."""
    parser.add_argument("scenario", help="scenario TOML file, or an embedded scenario name (default, adverse, black_hornet)")
    parser.add_argument("--convention", choices=("paper", "physical"), default=None,
                        help="override the scenario's convention (SPEC 3.4)")


def _scalar(value):
    arr = np.asarray(value)
    return arr.item() if arr.size == 1 else arr


def run(args) -> dict:
    """Evaluate the scenario; return ``{scenario, convention, effects, sensors: {name: {...}}}``."""
    scenario = load_scenario(args.scenario)
    convention = args.convention or scenario.convention
    results = evaluate(scenario, convention)
    sensors = {}
    for name, result in results.items():
        entry = result.as_dict()
        entry["range_m"] = _scalar(entry["range_m"])
        entry["terms"] = {k: {**v, "value": _scalar(v["value"])} for k, v in entry["terms"].items()}
        if "reason" in entry:
            entry["reason"] = _scalar(entry["reason"])
        sensors[name] = entry
    return {"scenario": scenario.name, "convention": convention, "target": scenario.target_preset,
            "effects": sorted(scenario.effects), "sensors": sensors}


def render_text(result: dict) -> str:
    """Human-readable table of the ranges."""
    lines = [f"scenario {result['scenario']} ({result['convention']} convention), target {result['target']}, "
             f"effects: {', '.join(result['effects']) or 'none'}"]
    for name, s in result["sensors"].items():
        reason = f"  [{s['reason']}]" if s.get("reason") else ""
        lines.append(f"  {name:<12} {s['modality']:<9} {s['range_m']:>12.1f} m   {s['model']}{reason}")
    return "\n".join(lines)
