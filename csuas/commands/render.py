"""``csuas render eo|tir|lidar SCENARIO --range-m R...``: synthetic images and their figures.

Method: docs/simulation.md; JSON keys: docs/command-line.md.

Modality dispatch: :data:`MODES` maps a mode name to ``"module:function"``
of a render mode (contract in :mod:`csuas.render.imaging.modes`), imported
only when run, so that ``csuas --help`` never imports Mitsuba.
"""

from __future__ import annotations

import sys
import time

from csuas.base.cost import add_limit_arguments, check_limits, limits_of
from csuas.base.errors import ParameterError, raise_all
from csuas.base.fileio import prepare_output_dir
from csuas.base.paths import file_name_part, inside
from csuas.base.quality import RUNGS
from csuas.base.registry import resolve
from csuas.core.scenario import load_scenario
from csuas.render.quality import IMAGING, LIDAR
from csuas.render.request import ATMOSPHERE_METHODS, RenderRequest

#: Mode name -> "module:function" of a render mode ``f(scenario, request) -> list of dict``
#: (:class:`csuas.render.request.RenderRequest`).
MODES = {
    "eo": "csuas.render.imaging.modes:eo_scenario",
    "tir": "csuas.render.imaging.modes:tir_scenario",
    "lidar": "csuas.render.lidar.runner:render_lidar",
}
#: Mode name -> "module:function" of its cost before any render, ``f(scenario, request) -> Estimate``
#: (:class:`csuas.base.cost.Estimate`), held against ``--max-seconds`` and ``--max-memory-gb``.
ESTIMATES = {"eo": "csuas.render.imaging.modes:eo_estimate"}


def add_arguments(parser) -> None:
    """Options of ``csuas render``."""
    parser.add_argument("mode", choices=tuple(MODES), help="what to render: " + ", ".join(MODES))
    parser.add_argument("scenario", metavar="SCENARIO", help="scenario TOML file or embedded scenario name")
    parser.add_argument("--range-m", type=float, nargs="+", required=True, metavar="R", help="slant ranges [m]")
    parser.add_argument(
        "--quality",
        choices=RUNGS,
        default="standard",
        help=f"eo/tir: {IMAGING.help_text()}. lidar: {LIDAR.help_text()} (default standard)",
    )
    parser.add_argument(
        "--azimuth-deg",
        type=float,
        nargs="+",
        default=[0.0],
        metavar="AZ",
        help="directions target -> sensor, azimuth from +x toward +y [deg] (default 0); every "
        "range is rendered at every azimuth and elevation",
    )
    parser.add_argument(
        "--elevation-deg",
        type=float,
        nargs="+",
        default=[0.0],
        metavar="EL",
        help="directions target -> sensor, elevation from the xy-plane [deg] (default 0)",
    )
    parser.add_argument(
        "--auto-exposure",
        action="store_true",
        help="eo previews: brightest pixel white (default: a camera set for clear daylight, so night looks dark)",
    )
    parser.add_argument("--sensor", default=None, help="sensor name in the scenario (default: the first of the mode)")
    parser.add_argument(
        "--atmosphere",
        choices=("auto", "on", "off"),
        default="auto",
        help="path transmittance and airlight/path radiance: auto = where csuas range applies one "
        "(EO always; thermal with the MRTD/NETD models or declared rain, fog or haze)",
    )
    parser.add_argument(
        "--atmosphere-method",
        choices=ATMOSPHERE_METHODS,
        default="auto",
        help="eo: the path analytic (Koschmieder), through Mitsuba's participating medium, or auto = the medium "
        "where the analytic path is an approximation (a slant path across a fog layer's top, a sunlit fog, the "
        "ground behind the drone, forward-scattered light on its pixels) and the medium is the more accurate at the "
        "requested quality (docs/simulation.md)",
    )
    parser.add_argument(
        "--convention",
        choices=("paper", "physical"),
        default=None,
        help="override the scenario's convention of the path, as csuas range --convention (docs/conventions.md)",
    )
    parser.add_argument("--seed", type=int, default=0, help="random seed (deterministic results)")
    parser.add_argument("--out", metavar="DIR", default=None, help="write EXR and PNG per range into DIR")
    parser.add_argument("--quiet", action="store_true", help="no progress on standard error")
    add_limit_arguments(parser)


def resolve_mode(name: str):
    """The render-mode callable registered under ``name`` in :data:`MODES`."""
    if name not in MODES:
        raise ParameterError("mode", name, ", ".join(MODES))
    return resolve(MODES[name])


def run(args) -> dict:
    """Render each range; returns the ``--json`` object (``results[]`` with docs/command-line.md keys)."""

    start = time.perf_counter()
    errors = [ParameterError("range_m", r, "finite and > 0 [m]") for r in args.range_m if not (0 < r < float("inf"))]
    for option, values, low, high in (
        ("azimuth_deg", args.azimuth_deg, -360.0, 360.0),
        ("elevation_deg", args.elevation_deg, -90.0, 90.0),
    ):
        errors += [ParameterError(option, v, f"{low:g} to {high:g} [deg]") for v in values if not (low <= v <= high)]
    if not (0 <= args.seed < 2**32):
        errors.append(ParameterError("seed", args.seed, "an integer from 0 to 2^32 - 1"))
    if args.atmosphere_method not in ATMOSPHERE_METHODS or (args.mode != "eo" and args.atmosphere_method == "medium"):
        allowed = ", ".join(ATMOSPHERE_METHODS) + " (medium: eo only)"
        errors.append(ParameterError("atmosphere_method", args.atmosphere_method, allowed))
    raise_all(errors)
    limits_of(args)
    directions = [(az, el) for az in args.azimuth_deg for el in args.elevation_deg]
    _refuse_colliding_names(args.range_m, directions)
    scenario = load_scenario(args.scenario)
    requests = [_request(args, azimuth, elevation) for azimuth, elevation in directions]
    _check_cost(args, scenario, requests)
    if args.out is not None:
        prepare_output_dir(args.out)
        _refuse_unsafe_targets(scenario, args, directions)
    mode = resolve_mode(args.mode)
    results = []
    for request in requests:
        rows = mode(scenario, request)
        results += [{**row, "azimuth_deg": request.azimuth_deg, "elevation_deg": request.elevation_deg} for row in rows]
    return {
        "mode": args.mode,
        "scenario": scenario.name,
        "quality": args.quality,
        "results": results,
        "time_s": time.perf_counter() - start,
    }


def _request(args, azimuth: float, elevation: float) -> RenderRequest:
    """The render mode's request of one direction from the command's options."""
    return RenderRequest(
        ranges_m=list(args.range_m),
        quality=args.quality,
        azimuth_deg=azimuth,
        elevation_deg=elevation,
        out_dir=args.out,
        seed=args.seed,
        sensor=args.sensor,
        atmosphere=args.atmosphere,
        progress=None if args.quiet else sys.stderr,
        exposure="auto" if args.auto_exposure else "scene",
        convention=args.convention,
        atmosphere_method=args.atmosphere_method,
    )


def _check_cost(args, scenario, requests: list) -> None:
    """The renders' estimated cost (:data:`ESTIMATES`, modes that have one) against ``--max-seconds`` and
    ``--max-memory-gb``, before any render or folder."""
    if args.mode not in ESTIMATES:
        return
    estimate_of = resolve(ESTIMATES[args.mode])
    estimates = [estimate_of(scenario, request) for request in requests]
    total = estimates[0]
    for more in estimates[1:]:
        total = total + more
    check_limits(total, args, "render", announce=not args.quiet)


def _refuse_unsafe_targets(scenario, args, directions) -> None:
    """Check every file the render will write, before rendering.

    The scenario's ``name`` and the rendered sensor's key become file names
    (:func:`csuas.base.paths.file_name_part`); each EXR and PNG must lie in ``--out`` and be a new
    name or a regular file (:func:`csuas.base.paths.inside`).

    Raises
    ------
    ParameterError
        The names' mistakes all at once, naming the key; else the first file that cannot be written.
    """
    from csuas.render.files import file_stem

    of_mode = [name for name, spec in scenario.sensors.items() if spec.modality == args.mode]
    chosen = (
        args.sensor if args.sensor in scenario.sensors else (of_mode[0] if of_mode and args.sensor is None else None)
    )
    errors = []
    for value, key in ((scenario.name, "name"), (chosen, "sensors")):
        try:
            if value is not None:
                file_name_part(value, key)
        except ParameterError as exc:
            errors.append(exc)
    raise_all(errors)
    if chosen is None and not (args.mode == "lidar" and args.sensor is None):
        return  # no such sensor: the render mode names the mistake
    sensor = chosen or "table45"  # lidar without a lidar sensor: Table 45's defaults
    for range_m in args.range_m:
        for azimuth, elevation in directions:
            stem = file_stem(scenario.name, sensor, args.mode, range_m, azimuth, elevation, args.quality, args.seed)
            for suffix in (".exr", ".png"):
                inside(args.out, stem + suffix)


def _refuse_colliding_names(ranges_m, directions) -> None:
    """Two renders whose file names would coincide (a value repeated, or equal to 6 digits) are refused."""
    from csuas.render.files import coordinates_label

    labels = [coordinates_label(r, az, el) for r in ranges_m for az, el in directions]
    repeated = sorted({label for label in labels if labels.count(label) > 1})
    if repeated:
        raise ParameterError(
            "range_m/azimuth_deg/elevation_deg",
            ", ".join(repeated),
            "distinct coordinates (to 6 significant digits): each render has its own files",
        )


#: Headline figures of the text output (name, label, unit), shown when a mode's rows carry them.
HEADLINE = (
    ("pixels_on_target", "pixels on target", "px"),
    ("pixels_across_dcrit", "across d_crit", "px"),
    ("contrast", "contrast", ""),
    ("delta_t_k", "Delta T", "K"),
    ("lcs_m2", "LCS", "m^2"),
)


def render_text(result: dict) -> str:
    """Human-readable table of the figures per range (any mode)."""
    lines = [f"csuas render {result['mode']} {result['scenario']} ({result['quality']}, {result['time_s']:.1f} s)"]
    for row in result["results"]:
        se = row.get("stderr", {})
        parts = []
        for key, label, unit in HEADLINE:
            if row.get(key) is None:
                continue
            err = se.get(key) if isinstance(se, dict) else (se if key == "lcs_m2" else None)
            text = f"{label} {row[key]:.4g}" + (f" ± {err:.2g}" if err is not None else "")
            parts.append(text + (f" {unit}" if unit else ""))
        lines.append(
            f"  R = {row['range_m']:g} m, azimuth {row['azimuth_deg']:g} deg, elevation "
            f"{row['elevation_deg']:g} deg: " + ", ".join(parts) + f" ({row['time_s']:.1f} s)"
        )
        lines.extend(f"    file: {f}" for f in row.get("files", []))
        lines.extend(f"    note: {n}" for n in row.get("notes", []))
    return "\n".join(lines)
