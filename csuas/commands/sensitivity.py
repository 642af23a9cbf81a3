"""``csuas sensitivity``: one-at-a-time analyses of Section 4.9 with tornado plots, and Table 52.

With ``--scenario`` of a ``target.swarm``, the figure varied is the swarm's first detection of any drone
(``csuas range``'s ``sensors.NAME.swarm.first_detection_m``), its key ``figure`` in the JSON, and
``target.swarm.count`` and ``target.swarm.spacing_m`` may be varied (a line formation's).
"""

from __future__ import annotations

from pathlib import Path

from csuas.base.errors import CsuasError, ParameterError, raise_all
from csuas.base.fileio import prepare_output_dir
from csuas.base.paths import file_name_part, inside
from csuas.base.plots import tornado_plot
from csuas.core.ranges import scenario_one_at_a_time
from csuas.core.scenario import load_scenario
from csuas.core.sensitivity import ANALYSES, one_at_a_time, table_52_platforms
from csuas.core.swarm_detection import swarm_first_detection_m
from csuas.defaults import load_sensitivity


def add_arguments(parser):
    """Declare the options of ``csuas sensitivity``."""
    parser.add_argument(
        "--analysis",
        choices=ANALYSES + ("platforms", "all"),
        default="all",
        help="which analysis of Section 4.9 (default: all)",
    )
    parser.add_argument("--out", default=None, help="folder for the tornado plots (PNG); none written without it")
    parser.add_argument(
        "--scenario",
        default=None,
        help="analyse a sensor of this scenario instead of Section 4.9's models (needs --sensor, --vary)",
    )
    parser.add_argument("--sensor", default=None, help="with --scenario: the sensor's key in the scenario")
    parser.add_argument(
        "--vary",
        nargs="+",
        default=[],
        metavar="KEY=LOW:HIGH",
        help="with --scenario: e.g. target.d_crit_m=0.08:0.12 sensor.hfov_deg=1:20 environment.rain_rate_mm_h=0:30 "
        "target.swarm.count=2:8 target.swarm.spacing_m=1:20 (a swarm scenario: its first detection of any drone)",
    )
    parser.add_argument(
        "--convention",
        choices=("paper", "physical"),
        default=None,
        help="with --scenario: override the scenario's convention",
    )


def _parse_variations(items) -> dict:
    variations = {}
    for item in items:
        key, _, bounds = item.partition("=")
        low, _, high = bounds.partition(":")
        try:
            variations[key] = (float(low), float(high))
        except ValueError:
            raise ParameterError("vary", item, "KEY=LOW:HIGH with numbers, e.g. sensor.hfov_deg=1:20") from None
    if not variations:
        raise ParameterError("vary", items, "at least one KEY=LOW:HIGH with --scenario")
    return variations


def _scenario_analysis(args) -> dict:

    scenario = load_scenario(args.scenario)
    sensor = args.sensor
    if sensor is None:
        if len(scenario.sensors) > 1:
            raise CsuasError(
                f"--sensor is required: scenario {scenario.name!r} has {len(scenario.sensors)} sensors; "
                f"name one of {', '.join(scenario.sensors)}"
            )
        sensor = next(iter(scenario.sensors))
    plot = _plot_path(args.out, scenario.name, sensor)
    figure = None if scenario.swarm is None else swarm_first_detection_m  # a swarm: its first detection of any
    variations = _parse_variations(args.vary)
    baseline, bars = scenario_one_at_a_time(scenario, sensor, variations, args.convention, figure)
    title = f"{scenario.name}: {sensor} ({scenario.sensors[sensor].modality})"
    entry = {
        "title": title,
        "source": "one-at-a-time, Section 4.9 method",
        "figure": "range_m" if figure is None else "swarm first_detection_m (any resolved group of target.swarm)",
        "baseline_m": baseline,
        "bars": [b.as_dict() for b in bars],
    }
    if plot is not None:
        entry["plot"] = str(tornado_plot(plot, title, baseline, bars))
    return {"analyses": {f"{scenario.name}.{sensor}": entry}}


def _plot_path(out, scenario: str, sensor: str) -> Path | None:
    """Where the tornado plot of ``sensor`` goes in ``out`` (None without ``--out``), checked before the work.

    Raises
    ------
    ParameterError
        When the scenario's ``name`` or the sensor's key cannot be part of a file name, or the plot
        would leave ``out`` or replace a special file (:mod:`csuas.base.paths`).
    """
    if not out:
        return None
    errors = []
    for value, key in ((scenario, "name"), (sensor, "sensors")):
        try:
            file_name_part(value, key)
        except ParameterError as exc:
            errors.append(exc)
    raise_all(errors)
    prepare_output_dir(out)
    return inside(out, f"tornado_{scenario}_{sensor}.png")


def run(args) -> dict:
    """``{analyses: {name: {baseline_m, paper_baseline_m, bars, plot}}, platforms: {...}}``."""
    if args.scenario:
        return _scenario_analysis(args)
    chosen = ANALYSES if args.analysis == "all" else ((args.analysis,) if args.analysis != "platforms" else ())
    result = {"analyses": {}}
    if args.out:
        prepare_output_dir(args.out)
    plots = {name: inside(args.out, f"tornado_{name}.png") for name in chosen} if args.out else {}
    for name in chosen:
        spec = load_sensitivity()[name]
        baseline, bars = one_at_a_time(spec["model"], spec["parameters"], spec.get("fixed"))
        entry = {
            "title": spec["title"],
            "source": spec["source"],
            "baseline_m": baseline,
            "paper_baseline_m": spec["baseline_m"],
            "bars": [b.as_dict() for b in bars],
            "paper_quoted": spec.get("paper", {}),
        }
        if args.out:
            path = plots[name]
            tornado_plot(path, f"{spec['title']} ({spec['source']})", baseline, bars, log_scale=name != "radar")
            entry["plot"] = str(path)
        result["analyses"][name] = entry
    if args.analysis in ("platforms", "all"):
        result["platforms"] = table_52_platforms()
    return result


def render_text(result: dict) -> str:
    """Tornado tables and the platform comparison."""
    lines = []
    for a in result["analyses"].values():
        paper = f" (paper {a['paper_baseline_m']} m)" if "paper_baseline_m" in a else ""
        lines.append(f"{a['title']} ({a['source']}): baseline {a['baseline_m']:.1f} m{paper}")
        for b in a["bars"]:
            lines.append(
                f"  {b['parameter']:<22} {b['low']:>9g} -> {b['range_at_low_m']:>9.1f} m   "
                f"{b['high']:>9g} -> {b['range_at_high_m']:>9.1f} m   span {b['span_m']:.1f} m"
            )
        if "plot" in a:
            lines.append(f"  plot: {a['plot']}")
    for name, p in result.get("platforms", {}).items():
        lines.append(
            f"Table 52 {name}: "
            + ", ".join(f"{k} {v:.1f} m (paper {p['paper_m'][k]})" for k, v in p["computed_m"].items())
        )
    return "\n".join(lines)
