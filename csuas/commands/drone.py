"""``csuas drone PRESET``: a drone model's size, silhouette metrics and orientation averages (docs/command-line.md)."""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

from csuas.base.errors import ParameterError
from csuas.base.paths import output_file
from csuas.drone_models.birds import MID_STROKE_PHASE, build_bird, list_birds
from csuas.drone_models.export import EXPORT_FORMATS, export_drone, export_format
from csuas.drone_models.mesh_input import load_mesh_drone
from csuas.drone_models.presets import build_drone, list_presets
from csuas.drone_models.rotorcraft import PROPELLER_STYLES
from csuas.drone_models.signature import K_LCS_DEFAULT, lcs_estimate
from csuas.drone_models.silhouette import (
    NonWatertightWarning,
    SilhouetteModel,
    estimated_seconds,
    projected_metrics,
)
from csuas.drone_models.sphere_average import QUALITY_PRESETS, sphere_average
from csuas.render.rcs.geometry import radar_part_list


def add_arguments(parser) -> None:
    """Options of ``csuas drone``."""
    parser.add_argument(
        "preset",
        help="drone preset (" + ", ".join(list_presets()) + "), bird class (" + ", ".join(list_birds()) + ") "
        "or a mesh file in metres (any format trimesh reads); --propellers applies to drone presets only",
    )
    parser.add_argument(
        "--azimuth-deg",
        type=float,
        default=90.0,
        help="view azimuth from +x (nose) toward +y (left) [deg], default 90 (side view)",
    )
    parser.add_argument(
        "--elevation-deg",
        type=float,
        default=0.0,
        help="view elevation from the horizontal [deg], +90 = seen from above; default 0",
    )
    parser.add_argument(
        "--propellers",
        choices=PROPELLER_STYLES,
        default="disc",
        help="propellers as swept discs (default), blades, or none",
    )
    parser.add_argument(
        "--wingbeat-phase",
        type=float,
        default=MID_STROKE_PHASE,
        help="a bird's phase in its wingbeat [cycles]: 0 top of the stroke, 0.25 wings level (default), 0.5 bottom",
    )
    parser.add_argument(
        "--quality",
        choices=tuple(QUALITY_PRESETS) + ("none",),
        default="standard",
        help="sphere-average sample preset, or none to skip it (default standard)",
    )
    parser.add_argument(
        "--max-seconds",
        type=float,
        default=600.0,
        help="refuse a sphere average estimated to take longer on 2 CPU cores (default 600)",
    )
    parser.add_argument(
        "--k-lcs", type=float, default=K_LCS_DEFAULT, help="LCS scaling factor k_LCS of Eq. 9 (default 0.1)"
    )
    parser.add_argument("--t-illum", type=float, default=1.0, help="illumination factor T_illum of Eq. 8 (default 1)")
    parser.add_argument(
        "--export", metavar="FILE", help="write the mesh (" + ", ".join(EXPORT_FORMATS) + ", by suffix)"
    )


def run(args) -> dict:
    """Build the preset and measure it; returns the ``--json`` object."""
    start = time.perf_counter()
    if args.export:
        export_format(args.export)  # reject a bad suffix, a special file or a bad name before any work
        output_file(args.export, "export")
    if args.preset in list_birds():
        drone = build_bird(args.preset, args.wingbeat_phase)
    elif args.preset in list_presets() or not Path(args.preset).suffix:
        drone = build_drone(args.preset, propellers=args.propellers)
    else:
        drone = load_mesh_drone(args.preset)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", NonWatertightWarning)
        model = SilhouetteModel.from_drone(drone)
    view = projected_metrics(model, args.azimuth_deg, args.elevation_deg)
    lcs_view = float(lcs_estimate(view["projected_area_m2"], args.k_lcs, args.t_illum))
    b = drone.bounds()
    result = {
        "preset": args.preset,
        "propellers": drone.propellers,
        "mass_kg": drone.mass_kg,
        "bbox_m": (b[1] - b[0]).tolist(),
        "bbox_min_m": b[0].tolist(),
        "bbox_max_m": b[1].tolist(),
        "view": {
            "azimuth_deg": args.azimuth_deg,
            "elevation_deg": args.elevation_deg,
            "direction": view["direction"].tolist(),
            "h_axis": view["h_axis"].tolist(),
            "v_axis": view["v_axis"].tolist(),
        },
        "d_x_proj_m": view["d_x_proj_m"],
        "d_y_proj_m": view["d_y_proj_m"],
        "d_crit_m": {"min": view["d_crit_min_m"], "geometric_mean": view["d_crit_geometric_mean_m"]},
        "projected_area_m2": view["projected_area_m2"],
        "sphere_equivalent_radius_m": view["sphere_equivalent_radius_m"],
        "lcs_m2": {"view": lcs_view, "k_lcs": args.k_lcs, "t_illum": args.t_illum},
        "emissivity": drone.emissivity("lwir"),
        "mesh": {
            "n_parts": len(drone.parts),
            "n_faces": int(sum(len(p.mesh.faces) for p in drone.parts)),
            "parts_watertight": all(p.mesh.is_watertight for p in drone.parts),
            "watertight": model.watertight,
            "n_shells": model.n_shells,
            "n_degenerate_faces": model.n_degenerate_faces,
        },
        "parts": [
            {"name": p.name, "kind": p.kind, "material": p.material.name, "area_m2": float(p.mesh.area)}
            for p in drone.parts
        ],
        "spec": drone.spec,
        "rf_model": radar_part_list(args.preset) if args.preset in list_presets() else None,
    }
    if args.quality != "none":
        _check_cost(model, args)
        avg = sphere_average(model, quality=args.quality)
        result["sphere_average"] = avg
        result["lcs_m2"]["sphere_average"] = float(
            lcs_estimate(avg["projected_area_m2"]["mean"], args.k_lcs, args.t_illum)
        )
        result["lcs_m2"]["sphere_average_stderr"] = float(
            lcs_estimate(avg["projected_area_m2"]["stderr"], args.k_lcs, args.t_illum)
        )
    if args.export:
        result["export"] = str(export_drone(drone, args.export))
    result["warnings"] = [str(w.message) for w in caught if issubclass(w.category, NonWatertightWarning)]
    result["time_s"] = time.perf_counter() - start
    return result


def _check_cost(model, args) -> None:
    """Estimate the sphere average before it starts; refuse it above ``--max-seconds``."""
    replicates, per_replicate = QUALITY_PRESETS[args.quality]
    seconds = estimated_seconds(model, replicates * per_replicate)
    if seconds > args.max_seconds:
        raise ParameterError(
            "max_seconds",
            args.max_seconds,
            f"at least the estimated {seconds:.0f} s of the {args.quality} sphere average "
            f"({replicates * per_replicate} views of {len(model.triangles)} non-convex triangles, 2 CPU cores); "
            "raise --max-seconds, or use --quality none or a lower quality",
        )
    if seconds > 10.0:
        print(f"csuas drone: sphere average of about {seconds:.0f} s", file=sys.stderr)


def render_text(result: dict) -> str:
    """Human-readable summary."""
    bx, by, bz = (1e3 * v for v in result["bbox_m"])
    view = result["view"]
    lines = [
        f"{result['preset']} (propellers: {result['propellers']}), mass "
        + ("unknown" if result["mass_kg"] is None else f"{1e3 * result['mass_kg']:.0f} g"),
        f"  bounding box          {bx:.1f} x {by:.1f} x {bz:.1f} mm (x forward, y left, z up)",
        f"  view                  azimuth {view['azimuth_deg']:g} deg, elevation {view['elevation_deg']:g} deg",
        f"  d_x_proj, d_y_proj    {1e3 * result['d_x_proj_m']:.1f} mm, {1e3 * result['d_y_proj_m']:.1f} mm",
        f"  d_crit (Eq. 1 min)    {1e3 * result['d_crit_m']['min']:.1f} mm",
        f"  d_crit (Eq. 2 root)   {1e3 * result['d_crit_m']['geometric_mean']:.1f} mm",
        f"  projected area A_p    {1e4 * result['projected_area_m2']:.2f} cm^2 "
        f"(sphere-equivalent radius {1e3 * result['sphere_equivalent_radius_m']:.1f} mm)",
        f"  LCS k*A_p*T (Eq. 9)   {result['lcs_m2']['view']:.3g} m^2 this view",
    ]
    if "sphere_average" in result:
        avg = result["sphere_average"]
        a = avg["projected_area_m2"]
        lines += [
            f"  sphere average        A_p {1e4 * a['mean']:.2f} +- {1e4 * a['stderr']:.2f} cm^2, "
            f"LCS {result['lcs_m2']['sphere_average']:.3g} m^2 ({avg['n_directions']} directions, "
            f"{avg['time_s']:.2f} s)",
            f"                        d_crit min {1e3 * avg['d_crit_min_m']['mean']:.1f} mm, "
            f"root {1e3 * avg['d_crit_geometric_mean_m']['mean']:.1f} mm",
        ]
    e = result["emissivity"]
    lines.append(
        f"  LWIR emissivity       {e['area_weighted']:.3f} area-weighted (paper 0.68 = unweighted mean of "
        "its component list)"
    )
    if result.get("rf_model"):
        lines.append("  radar model           part, material, surface (csuas drone --json: rf_model)")
        lines += [
            f"    {p['name']:<22}{p['material']:<14}{p['surface']}" + (" (inside)" if p["inside_airframe"] else "")
            for p in result["rf_model"]
        ]
    lines += [f"  warning: {w}" for w in result.get("warnings", [])]
    if "export" in result:
        lines.append(f"  exported              {result['export']}")
    return "\n".join(lines)
