"""``csuas pathloss``: RF path gain drone -> RF sensor by Sionna RT, beside Friis and two-ray (docs/command-line.md)."""

from __future__ import annotations

import numpy as np

from csuas.core.dielectric import ground_permittivity
from csuas.core.rf import free_space_path_loss_db
from csuas.render.quality import LINKS


def add_arguments(parser):
    """Declare the options of ``csuas pathloss``."""
    parser.add_argument("--frequency-ghz", type=float, required=True, help="carrier frequency [GHz], 0.1-100")
    parser.add_argument(
        "--distance-m",
        type=float,
        nargs="+",
        required=True,
        help="horizontal distance(s) drone -> sensor [m]; all solved in one Sionna call",
    )
    parser.add_argument("--tx-height-m", type=float, default=10.0, help="height of the drone's transmitter [m]")
    parser.add_argument("--rx-height-m", type=float, default=10.0, help="height of the RF sensor [m]")
    parser.add_argument(
        "--ground",
        default="none",
        help="ITU-R P.2040 material of a flat ground (concrete, medium_dry_ground, ...) or none",
    )
    parser.add_argument(
        "--budget",
        default="standard",
        help=f"sample budget: {LINKS.help_text()}; or sionna_default (default standard)",
    )
    parser.add_argument("--samples", type=int, default=None, help="rays per source (overrides the budget)")
    parser.add_argument("--max-depth", type=int, default=None, help="maximum interactions (overrides the budget)")


def _listed(values: np.ndarray):
    """A scalar for one distance, a list for several."""
    values = np.asarray(values, dtype=float)
    return values.item() if values.size == 1 else values.tolist()


def run(args) -> dict:
    """Solve the links; return path_gain_db, friis_db, time_s (and two_ray_db over ground)."""
    from csuas.render.links.budget import resolve_budget
    from csuas.render.links.rf import rf_path_gain
    from csuas.render.links.two_ray import two_ray_path_gain_db

    ground = None if str(args.ground).lower() == "none" else args.ground
    result = rf_path_gain(
        args.frequency_ghz,
        args.distance_m,
        args.tx_height_m,
        args.rx_height_m,
        ground=ground,
        budget=resolve_budget(args.budget, args.samples, args.max_depth),
    )
    d = np.asarray(args.distance_m, dtype=float)
    slant = result.extra["slant_range_m"]
    out = {
        "frequency_ghz": args.frequency_ghz,
        "distance_m": _listed(d),
        "slant_range_m": _listed(slant),
        "tx_height_m": args.tx_height_m,
        "rx_height_m": args.rx_height_m,
        "ground": ground,
        "path_gain_db": _listed(result.path_gain_db),
        "friis_db": _listed(-free_space_path_loss_db(args.frequency_ghz, slant)),
        # One batched Sionna call serves all distances: each gets an equal share of its wall time.
        "time_s": _listed(np.full(d.size, result.time_s / d.size)),
        "time_total_s": result.time_s,
        "paths": result.n_paths.tolist() if d.size > 1 else int(result.n_paths[0]),
        "budget": result.budget.name,
        "samples": result.budget.samples,
        "max_depth": result.budget.max_depth,
        "variant": result.variant,
    }
    if ground is not None:
        eta = ground_permittivity(result.extra, args.frequency_ghz)
        out["two_ray_db"] = _listed(
            two_ray_path_gain_db(args.frequency_ghz, d, args.tx_height_m, args.rx_height_m, eta)
        )
        out["relative_permittivity"] = result.extra["relative_permittivity"]
        out["conductivity_s_m"] = result.extra["conductivity_s_m"]
    return out


def render_text(result: dict) -> str:
    """Table of path gain against Friis (and two-ray) per distance."""
    as_list = lambda v: v if isinstance(v, list) else [v]
    ground = result["ground"] or "free space"
    lines = [
        f"path gain at {result['frequency_ghz']:g} GHz, drone {result['tx_height_m']:g} m -> sensor "
        f"{result['rx_height_m']:g} m, {ground}; Sionna RT {result['budget']} budget "
        f"({result['samples']} rays, depth {result['max_depth']}) on {result['variant']}, "
        f"{result['time_total_s'] * 1e3:.1f} ms"
    ]
    header = f"  {'distance [m]':>12} {'Sionna [dB]':>12} {'Friis [dB]':>11}"
    header += f" {'two-ray [dB]':>13}" if "two_ray_db" in result else ""
    lines.append(header)
    rows = zip(
        as_list(result["distance_m"]),
        as_list(result["path_gain_db"]),
        as_list(result["friis_db"]),
        as_list(result.get("two_ray_db", [None] * len(as_list(result["distance_m"])))),
    )
    for d, gain, friis, two_ray in rows:
        line = f"  {d:>12g} {gain:>12.3f} {friis:>11.3f}"
        lines.append(line + (f" {two_ray:>13.3f}" if two_ray is not None else ""))
    return "\n".join(lines)
