"""``csuas rcs MESH_OR_PRESET --frequency-ghz F``: radar cross-section by SBR-PO.

Method: docs/simulation.md; JSON keys: docs/command-line.md.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from csuas.base.cost import Estimate, add_limit_arguments, check_limits
from csuas.base.errors import ParameterError, raise_all
from csuas.base.paths import output_file
from csuas.base.schema import validate
from csuas.core.scenario import swarm_formation
from csuas.core.swarm import array_factor, line_of_sight_axes, target_frame_offsets_m
from csuas.core.units import wavelength_m
from csuas.defaults.scenario_schema import SwarmTable
from csuas.render.quality import RCS


def add_arguments(parser) -> None:
    """Options of ``csuas rcs``."""
    parser.add_argument(
        "mesh_or_preset",
        metavar="MESH_OR_PRESET",
        help="mesh file trimesh reads (metres) or a drone preset name (e.g. dji_mini_4_pro)",
    )
    parser.add_argument("--frequency-ghz", type=float, required=True, help="radar frequency [GHz]")
    parser.add_argument(
        "--azimuth-deg",
        type=float,
        default=0.0,
        help="direction target -> radar, azimuth from +x toward +y [deg] (default 0)",
    )
    parser.add_argument(
        "--elevation-deg",
        type=float,
        default=0.0,
        help="direction target -> radar, elevation from the xy-plane [deg] (default 0)",
    )
    parser.add_argument(
        "--observe-azimuth-deg",
        type=float,
        default=None,
        help="bistatic: direction target -> receiver, azimuth [deg] (default: monostatic)",
    )
    parser.add_argument(
        "--observe-elevation-deg",
        type=float,
        default=None,
        help="bistatic: direction target -> receiver, elevation [deg] (default: monostatic)",
    )
    parser.add_argument(
        "--material",
        default=None,
        help="one material for all faces: pec, an ITU name (itu_concrete, ...) or a drone material "
        "(plastic, carbon_fibre, ...); default: a preset's part materials, PEC for a mesh file",
    )
    parser.add_argument(
        "--shell-thickness-mm",
        type=float,
        default=None,
        help="dielectric materials are thin shells of this wall thickness [mm] (0: half-spaces); "
        "default: 2 mm for a preset's plastic parts, half-spaces otherwise",
    )
    parser.add_argument(
        "--quality",
        choices=RCS.names,
        default="standard",
        help=f"{RCS.help_text()} (default standard)",
    )
    parser.add_argument(
        "--rays-per-wavelength",
        type=float,
        default=None,
        help="tube density N >= 1 (tube spacing lambda/N); overrides --quality",
    )
    parser.add_argument("--max-bounces", type=int, default=None, help="maximum reflections per tube (>= 1)")
    parser.add_argument(
        "--polarisation",
        choices=("VV", "HH", "HV", "VH"),
        default="VV",
        help="polarisation of rcs_m2 (receive, transmit); all four are reported",
    )
    _add_error_arguments(parser)
    parser.add_argument(
        "--sphere-average",
        action="store_true",
        help="also the sphere-averaged RCS of Eq. 6, adaptive: randomly rotated lattices of aspects are added "
        "until the mean is within --sphere-accuracy-db (cost grows with f^2, use --quality draft above ~20 GHz "
        "on a CPU)",
    )
    parser.add_argument(
        "--sphere-accuracy-db",
        type=float,
        default=0.5,
        help="accuracy of --sphere-average: the 95 %% bound of its mean [dB] (default 0.5)",
    )
    parser.add_argument(
        "--max-tubes",
        type=float,
        default=1e9,
        help="refuse work estimated above this many tubes in all (default 1e9, a few minutes on 2 CPU cores)",
    )
    _add_swarm_arguments(parser)
    add_limit_arguments(parser)
    parser.add_argument(
        "--plot",
        metavar="PNG",
        default=None,
        help="write a polar plot of RCS vs azimuth (2 deg steps) at the given elevation",
    )


def _add_error_arguments(parser) -> None:
    """Options of the error bound: replicas, edge diffraction, the bounce limit's truncation."""
    parser.add_argument(
        "--no-error-estimate",
        action="store_true",
        help="trace one grid instead of the shifted replicas that bound the discretisation error "
        "(a quarter of the time)",
    )
    parser.add_argument(
        "--edge-diffraction",
        action="store_true",
        help="add the fringe field of conducting wedge edges and sheet rims (PTD equivalent edge currents)",
    )
    parser.add_argument(
        "--truncation-fraction",
        type=float,
        default=None,
        help="raise the bounce limit (from --max-bounces or the preset's, by half each time) until the RCS the "
        "tubes still alive at the limit could add is at most this fraction of the result (e.g. 0.01)",
    )


def _offsets(text: str) -> list[list[float]]:
    """``--swarm-offsets-m``: ``X,Y,Z;X,Y,Z;...`` [m]."""
    rows = []
    for row in text.split(";"):
        try:
            values = [float(p) for p in row.split(",")]
        except ValueError:
            values = []
        if len(values) != 3:
            raise argparse.ArgumentTypeError(f"{row!r} is not X,Y,Z (three numbers [m]); rows split by ';'")
        rows.append(values)
    return rows


def _add_swarm_arguments(parser) -> None:
    """A swarm traced together: the scenario's target.swarm keys (docs/scenarios.md "Swarms")."""
    parser.add_argument(
        "--swarm-count",
        type=int,
        default=None,
        help="trace N copies together, --swarm-spacing-m apart in a line "
        "across the line of sight (horizontal) centred on the target",
    )
    parser.add_argument("--swarm-spacing-m", type=float, default=None, help="spacing of --swarm-count's line [m]")
    parser.add_argument(
        "--swarm-offsets-m",
        type=_offsets,
        default=None,
        metavar="X,Y,Z;X,Y,Z",
        help="or each copy's offset [m], rows split by ';': x along the line of sight away from the radar, "
        "y across it, z up",
    )


def _formation(args):
    """The swarm of ``--swarm-*`` (the schema of a scenario's target.swarm), or None."""
    given = {
        k: v
        for k, v in (
            ("count", args.swarm_count),
            ("spacing_m", args.swarm_spacing_m),
            ("offsets_m", args.swarm_offsets_m),
        )
        if v is not None
    }
    return swarm_formation(validate(SwarmTable, given, prefix="swarm") if given else None, key="swarm")


def _swarm(args, formation, single_engine, res, pol: str) -> dict:
    """The swarm's figures beside its coherent sum: one drone's RCS, the closed form of N point scatterers
    (one drone's RCS times the array factor) and the random-phase mean N sigma."""
    single, _ = _trace(args, single_engine)
    sigma_one = float(single.rcs_m2(pol).ravel()[0])
    axes = line_of_sight_axes(args.azimuth_deg, args.elevation_deg)
    observe = line_of_sight_axes(float(res.observe_azimuth_deg.ravel()[0]), float(res.observe_elevation_deg.ravel()[0]))
    mesh_offsets = target_frame_offsets_m(formation.offsets_m, args.azimuth_deg, args.elevation_deg)
    factor = array_factor(mesh_offsets, -axes[0], -observe[0], float(wavelength_m(args.frequency_ghz)))
    return {
        "count": formation.count,
        "formation": formation.kind,
        "offsets_m": formation.offsets_m.tolist(),
        "mesh_offsets_m": mesh_offsets.tolist(),
        "single_rcs_m2": sigma_one,
        "array_factor": factor,
        "point_scatterer_rcs_m2": factor * sigma_one,
        "random_phase_mean_rcs_m2": formation.count * sigma_one,
        "note": "rcs_m2 is the coherent sum of the N meshes traced together (shadowing and multiple bounces "
        "between drones included); point_scatterer_rcs_m2 the closed form without them",
    }


def run(args) -> dict:
    """Compute the RCS; returns the ``--json`` object (keys of docs/command-line.md plus details)."""
    from csuas.render.rcs.geometry import formation_target
    from csuas.render.rcs.solver import POLARISATIONS, get_engine, resolve_quality

    start = time.perf_counter()
    _validate(args)
    rays_per_wavelength, max_bounces = resolve_quality(args.quality, args.rays_per_wavelength, args.max_bounces)
    shell = None if args.shell_thickness_mm is None else args.shell_thickness_mm / 1000.0
    engine = get_engine(args.mesh_or_preset, args.material, shell_thickness_m=shell)
    formation, single_engine = _formation(args), engine
    if formation is not None:
        offsets = target_frame_offsets_m(formation.offsets_m, args.azimuth_deg, args.elevation_deg)
        engine = get_engine(formation_target(engine.target, offsets))
    cost = _cost(args, engine.target.bounding_radius_m, rays_per_wavelength, max_bounces, engine.target.wires)
    res, tried = _trace(args, engine)
    bistatic = args.observe_azimuth_deg is not None
    pol = args.polarisation
    sigma = float(res.rcs_m2(pol).ravel()[0])
    err = res.error_estimate_db(pol)
    err = None if err is None else float(err.ravel()[0])
    target = engine.target
    warnings = _warnings(sigma, err, res, pol, target.bounding_radius_m)
    if sigma <= 0.0 or (err is not None and not (math.isfinite(err) and err <= UNRELIABLE_ERROR_DB)):
        err = None
    bound = _error_bound(err, res, pol, target.bounding_radius_m)
    out = {
        "target": args.mesh_or_preset,
        "frequency_ghz": args.frequency_ghz,
        "wavelength_m": float(wavelength_m(args.frequency_ghz)),
        "azimuth_deg": args.azimuth_deg,
        "elevation_deg": args.elevation_deg,
        "polarisation": pol,
        "geometry": "bistatic" if bistatic else "monostatic",
        "observe_azimuth_deg": float(res.observe_azimuth_deg.ravel()[0]),
        "observe_elevation_deg": float(res.observe_elevation_deg.ravel()[0]),
        "rcs_m2": sigma,
        "rcs_dbsm": _dbsm(sigma),
        "error_db": bound["total_db"],
        "error_bound": bound,
        "warnings": warnings,
        "cost_estimate": cost,
        "rcs_m2_by_polarisation": {p: float(res.rcs_m2(p).ravel()[0]) for p in POLARISATIONS},
        "rcs_dbsm_by_polarisation": {p: _dbsm(float(res.rcs_m2(p).ravel()[0])) for p in POLARISATIONS},
        "rays": res.tubes,
        "rays_per_wavelength": res.rays_per_wavelength,
        "max_bounces": res.max_bounces,
        "bounces": _bounces(res.exits_by_bounce),
        "ray_casts": res.ray_casts,
        "rays_x_bounces_per_s": res.rays_x_bounces_per_s,
        "materials": res.materials,
        "shell_thickness_m": {m.name: m.thickness_m for m in target.materials},
        "mesh": {
            "faces": int(len(target.faces)),
            "dropped_degenerate_faces": target.dropped_faces,
            "bounding_radius_m": target.bounding_radius_m,
        },
        "variant": res.variant,
        "method": "SBR-PO (Ling, Chou & Lee 1989) with per-tube footprint sinc factors (Bhalla & Ling 1995), "
        "exact single reflections of fully lit facets"
        + (", PTD fringe currents of conducting edges (Michaeli 1984)" if args.edge_diffraction else "")
        + (", thin wires by the method of moments" if target.wires is not None else ""),
        "edge_diffraction": bool(args.edge_diffraction),
        "replicas": res.replicas,
        "bounces_tried": tried,
    }
    if target.wires is not None:
        out["thin_wires"] = _thin_wires(target.wires, res, pol)
    if formation is not None:
        out["swarm"] = _swarm(args, formation, single_engine, res, pol)
    if args.sphere_average:
        out["sphere_average"] = _sphere_average(args, engine)
    if args.plot:
        _plot_azimuth_cut(args, engine)
        out["plot"] = args.plot
    out["time_s"] = time.perf_counter() - start
    out["sbr_time_s"] = res.time_s
    return out


def _thin_wires(wires, res, pol: str) -> dict:
    """The target's thin wires alone at the run's aspect: their share of the coherent field (method of moments)."""
    from csuas.render.rcs.solver import POLARISATIONS
    from csuas.render.rcs.thin_wire import wire_field

    amplitude, error = wire_field(
        wires,
        res.frequency_ghz[:1],
        (res.azimuth_deg[:1], res.elevation_deg[:1]),
        (res.observe_azimuth_deg[:1, :1], res.observe_elevation_deg[:1, :1]),
    )
    rx, tx = POLARISATIONS[pol]
    field, bound = amplitude[0, 0, rx, tx], float(error[0, 0, rx, tx])
    sigma = 4.0 * math.pi * abs(field) ** 2
    return {
        "count": len(wires),
        "rcs_m2": sigma,
        "rcs_dbsm": _dbsm(sigma),
        "amplitude_error_relative": bound / abs(field) if field != 0.0 else None,
        "method": "thin-wire method of moments (Galerkin, triangle functions; Harrington 1968), added coherently "
        "to the SBR field; no coupling with the body",
    }


def _sphere_average(args, engine) -> dict:
    """``--sphere-average``: Eq. 6's average of the chosen polarisation, its one-value arrays as numbers."""
    from csuas.render.rcs.sweep import sphere_average

    avg = sphere_average(
        engine,
        args.frequency_ghz,
        accuracy_db=args.sphere_accuracy_db,
        polarisation=args.polarisation,
        quality=args.quality,
        rays_per_wavelength=args.rays_per_wavelength,
        max_bounces=args.max_bounces,
    )
    return {
        k: (v.tolist()[0] if isinstance(v, np.ndarray) and v.size == 1 else v)
        for k, v in avg.items()
        if k not in ("samples_m2", "directions")
    }


def _plot_azimuth_cut(args, engine) -> None:
    """``--plot``: a polar plot of every polarisation over azimuth at the chosen elevation, to ``args.plot``."""
    from csuas.render.rcs.sweep import aspect_sweep, plot_polar

    azimuth = np.arange(0.0, 360.0, 2.0)
    cut = aspect_sweep(
        engine,
        args.frequency_ghz,
        azimuth,
        args.elevation_deg,
        quality=args.quality,
        rays_per_wavelength=args.rays_per_wavelength,
        max_bounces=args.max_bounces,
        error_estimate=False,
    )
    plot_polar(
        azimuth,
        {p: v[0] for p, v in cut["rcs_dbsm"].items()},
        args.plot,
        title=f"{args.mesh_or_preset}: RCS [dBsm] at {args.frequency_ghz:g} GHz, elevation {args.elevation_deg:g} deg",
    )


#: An error estimate above this [dB] says the estimate itself failed (the half-density run hit
#: little or nothing); it is reported as a warning, never as a bound.
UNRELIABLE_ERROR_DB = 10.0

#: Aspects of the first batch of the adaptive sphere average (8 lattices of 16 directions, as many flash-drawn).
FIRST_BATCH_ASPECTS = 256
#: Below this k*a (a the bounding radius) edge diffraction and creeping waves, which SBR-PO leaves out,
#: matter: the figure is indicative only (docs/validation.md, SBR-PO).
KA_VALIDITY = 5.0
#: Fewer tubes than this sample the target too coarsely for the error estimate to mean anything.
MIN_TUBES = 100


def _validate(args) -> None:
    """Every numeric option checked before the mesh is loaded; all mistakes at once."""
    errors = []
    if not (0.0 < args.frequency_ghz <= 3000.0):
        errors.append(ParameterError("frequency_ghz", args.frequency_ghz, "0 < f <= 3000 [GHz]"))
    for option, value in (("azimuth_deg", args.azimuth_deg), ("observe_azimuth_deg", args.observe_azimuth_deg)):
        if value is not None and not (-360.0 <= value <= 360.0):
            errors.append(ParameterError(option, value, "-360 to 360 [deg]"))
    for option, value in (("elevation_deg", args.elevation_deg), ("observe_elevation_deg", args.observe_elevation_deg)):
        if value is not None and not (-90.0 <= value <= 90.0):
            errors.append(ParameterError(option, value, "-90 to 90 [deg]"))
    if args.shell_thickness_mm is not None and not (0.0 < args.shell_thickness_mm < 1000.0):
        errors.append(ParameterError("shell_thickness_mm", args.shell_thickness_mm, "0 < t < 1000 [mm]"))
    if not (args.max_tubes >= 1.0 and math.isfinite(args.max_tubes)):
        errors.append(ParameterError("max_tubes", args.max_tubes, "a finite number >= 1"))
    if args.truncation_fraction is not None and not (0.0 < args.truncation_fraction < 1.0):
        errors.append(ParameterError("truncation_fraction", args.truncation_fraction, "0 < x < 1"))
    if not (0.0 < args.sphere_accuracy_db <= 10.0):
        errors.append(ParameterError("sphere_accuracy_db", args.sphere_accuracy_db, "0 < x <= 10 [dB]"))
    if args.plot:
        try:
            output_file(args.plot, "plot")
        except ParameterError as exc:
            errors.append(exc)
    raise_all(errors)


def _cost(args, bounding_radius_m: float, rays_per_wavelength: float, max_bounces: int, wires=None) -> dict:
    """Tubes and time of the whole command (and of its thin wires), estimated before tracing; refused above
    ``--max-tubes``."""
    from csuas.render.rcs.solver import REPLICAS, estimate_peak_bytes, estimate_seconds, estimate_tubes
    from csuas.render.rcs.thin_wire import estimate_cost

    per_grid = estimate_tubes(bounding_radius_m, args.frequency_ghz, rays_per_wavelength)
    # the aspect itself on REPLICAS shifted grids (one without an error estimate); the sphere average's first
    # batch (it is adaptive: later batches run while it converges) and the plot's cut on one grid each
    grids = (1 if args.no_error_estimate else REPLICAS) + (FIRST_BATCH_ASPECTS if args.sphere_average else 0)
    grids += 180 if args.plot else 0
    per_aspect = per_grid * (1 if args.no_error_estimate else REPLICAS)
    aspects = 1 + (FIRST_BATCH_ASPECTS if args.sphere_average else 0) + (180 if args.plot else 0)
    tubes = per_grid * grids
    cost = {
        "tubes": tubes,
        "tubes_per_aspect": per_aspect,
        "aspects": aspects,
        "seconds_2_cpu_cores": estimate_seconds(tubes, max_bounces),
    }
    wire_seconds, wire_bytes = (0.0, 0.0) if wires is None else estimate_cost(wires, args.frequency_ghz)
    cost["seconds_2_cpu_cores"] += wire_seconds
    if tubes > args.max_tubes:
        raise ParameterError(
            "max_tubes",
            args.max_tubes,
            f"at least the estimated {tubes:.3g} tubes (about {cost['seconds_2_cpu_cores'] / 60:.0f} "
            f"min on 2 CPU cores) for this target, frequency and --rays-per-wavelength "
            f"{rays_per_wavelength:g}; raise --max-tubes to run it, or lower the density",
        )
    what = f"{tubes:.3g} tubes over {aspects} aspect(s) at --rays-per-wavelength {rays_per_wavelength:g}"
    if wires is not None:
        what += f" and {len(wires)} thin wires"
    check_limits(Estimate(what, cost["seconds_2_cpu_cores"], estimate_peak_bytes(per_grid) + wire_bytes), args, "rcs")
    return cost


def _trace(args, engine):
    """The run of ``csuas rcs``, and the bounce limits tried with their truncated fraction (one without
    ``--truncation-fraction``: the limit given, fraction of that run)."""
    from csuas.render.rcs.bounces import rcs_until_truncated, truncated_fraction
    from csuas.render.rcs.solver import compute_rcs

    kwargs = {
        "quality": args.quality,
        "rays_per_wavelength": args.rays_per_wavelength,
        "max_bounces": args.max_bounces,
        "error_estimate": not args.no_error_estimate,
        "edge_diffraction": args.edge_diffraction,
        "observe_azimuth_deg": args.observe_azimuth_deg,
        "observe_elevation_deg": args.observe_elevation_deg,
    }
    where = (engine, args.frequency_ghz, args.azimuth_deg, args.elevation_deg)
    if args.truncation_fraction is not None:
        res, tried = rcs_until_truncated(*where, fraction=args.truncation_fraction, **kwargs)
        return res, [{"max_bounces": b, "truncated_fraction": f} for b, f in tried]
    res = compute_rcs(*where, **kwargs)
    return res, [{"max_bounces": res.max_bounces, "truncated_fraction": truncated_fraction(res)}]


def _bounces(exits_by_bounce: np.ndarray) -> dict:
    """Tubes radiating after 0 (missed), 1, 2, ... bounces, and the most bounces any tube made."""
    return {
        "exits_by_bounce": exits_by_bounce.tolist(),
        "max_reached": int(np.flatnonzero(exits_by_bounce)[-1]) if exits_by_bounce.any() else 0,
    }


def _error_bound(discretisation_db, res, polarisation: str, bounding_radius_m: float) -> dict:
    """The bound against the exact answer and its terms [dB] (:mod:`csuas.render.rcs.model_error`).

    ``total_db`` (the ``error_db`` key) is null where the discretisation bound is withheld, the target
    is too small for the model (k a < 2, no model bound) or the tubes the bounce limit stopped could
    outweigh the result (raise --max-bounces).
    """
    from csuas.render.rcs.model_error import (
        PO_FLOOR_COEFFICIENT,
        PO_MODEL_COEFFICIENT,
        electrical_size,
        total_bound_db,
    )

    model_db = float(res.model_error_db[0])
    floor_db = float(res.model_floor_db(polarisation).ravel()[0])
    truncation_db = float(res.truncation_db(polarisation).ravel()[0])
    edges = res.edge_residual_db(polarisation)
    edge_residual_db = 0.0 if edges is None else float(edges.ravel()[0])
    total = None
    if discretisation_db is not None:
        total = float(total_bound_db(discretisation_db, model_db, floor_db, truncation_db, edge_residual_db))
    return {
        "total_db": total if total is not None and math.isfinite(total) else None,
        "discretisation_db": discretisation_db,
        "model_db": model_db if math.isfinite(model_db) else None,
        "model_floor_db": floor_db if math.isfinite(floor_db) else None,
        "truncation_db": truncation_db if math.isfinite(truncation_db) else None,
        "edge_residual_db": None if edges is None or not math.isfinite(edge_residual_db) else edge_residual_db,
        "model_ka": float(electrical_size(res.frequency_ghz[0], bounding_radius_m)),
        "model": f"physical optics against the exact answer: relative amplitude {PO_MODEL_COEFFICIENT:g}/(k a), "
        "a the bounding radius, calibrated on the Mie series of PEC spheres at ka 2-50, plus "
        f"sqrt({PO_FLOOR_COEFFICIENT:g} lambda^2 / sigma), calibrated on the EFIE's cylinders and the drone's arm "
        "with its motor; truncation: the tubes alive at the bounce limit re-radiating once more at random phase"
        + (
            "; edge residual: the edge waves first-order PTD misses (double diffraction), calibrated on the EFIE "
            "of PEC plates (csuas.render.rcs.edge_residual)"
            if edges is not None
            else ""
        ),
    }


def _warnings(sigma_m2: float, error_db, res, polarisation: str, bounding_radius_m: float) -> list[str]:
    """What makes the figure less than it seems: nothing hit, too few tubes, ka below validity, bounces cut."""
    tubes, frequency_ghz = res.tubes, float(res.frequency_ghz[0])
    warnings = []
    truncation = float(res.truncation_db(polarisation).ravel()[0])
    if sigma_m2 > 0.0 and not math.isfinite(truncation):
        warnings.append(
            f"the tubes the bounce limit ({res.max_bounces}) stopped could add more than the result: no bound "
            "(error_db null); raise --max-bounces or give --truncation-fraction"
        )
    if sigma_m2 <= 0.0:
        warnings.append(
            "no tube returned any field toward the receiver: the RCS is below what this tube grid "
            "resolves, not zero; raise --rays-per-wavelength"
        )
    if tubes < MIN_TUBES:
        warnings.append(
            f"only {tubes} tubes cover the target: multiple reflections and partly shadowed facets "
            f"are sampled coarsely (single reflections of fully lit facets are exact); "
            f"raise --rays-per-wavelength"
        )
    ka = 2.0 * math.pi / float(wavelength_m(frequency_ghz)) * bounding_radius_m
    if ka < KA_VALIDITY:
        warnings.append(
            f"ka = {ka:.3g} < {KA_VALIDITY:g}: SBR-PO has no edge diffraction or creeping waves, "
            f"so below ka of about 5 the figure is indicative only"
        )
    if error_db is not None and not (math.isfinite(error_db) and error_db <= UNRELIABLE_ERROR_DB):
        warnings.append(
            f"the error estimate ({error_db:.3g} dB) failed: the shifted grid replicas disagree by as "
            f"much as the field itself; error_db is withheld, raise --rays-per-wavelength"
        )
    return warnings


def _dbsm(sigma_m2: float):
    """10 log10(sigma) [dBsm], or None for a zero RCS (explained in ``warnings``)."""
    return 10.0 * math.log10(sigma_m2) if sigma_m2 > 0.0 else None


def render_text(result: dict) -> str:
    """Human-readable summary of ``csuas rcs``."""
    where = (
        ""
        if result["geometry"] == "monostatic"
        else (
            f", receiver at azimuth {result['observe_azimuth_deg']:g} deg, "
            f"elevation {result['observe_elevation_deg']:g} deg"
        )
    )
    lines = [
        f"{result['geometry'].capitalize()} RCS of {result['target']} at {result['frequency_ghz']:g} GHz, "
        f"azimuth {result['azimuth_deg']:g} deg, elevation {result['elevation_deg']:g} deg{where} "
        f"({result['polarisation']}):",
        f"  {result['rcs_m2']:.4g} m^2"
        + ("" if result["rcs_dbsm"] is None else f" = {result['rcs_dbsm']:.2f} dBsm")
        + ("" if result["error_db"] is None else f"  (bound {result['error_db']:.2f} dB against the exact answer)"),
        "  "
        + "  ".join(f"{p} {'-' if v is None else f'{v:.2f}'}" for p, v in result["rcs_dbsm_by_polarisation"].items())
        + " dBsm",
        f"  {result['rays']} tubes at {result['rays_per_wavelength']:g} per wavelength, "
        f"{result['ray_casts']} ray casts, {result['rays_x_bounces_per_s']:.3g} rays x bounces / s "
        f"(a first launch includes kernel compilation), {result['time_s']:.2f} s",
    ]
    if "swarm" in result:
        w = result["swarm"]
        lines.append(
            f"  swarm of {w['count']} traced together; one drone {w['single_rcs_m2']:.4g} m^2, N point scatterers "
            f"{w['point_scatterer_rcs_m2']:.4g} m^2 (array factor {w['array_factor']:.3g}), random phases "
            f"{w['random_phase_mean_rcs_m2']:.4g} m^2"
        )
    if "sphere_average" in result:
        avg = result["sphere_average"]
        lines.append(
            f"  sphere average (Eq. 6): {avg['mean_m2']:.4g} m^2 = {avg['mean_dbsm']:.2f} dBsm "
            f"(within {avg['error_db']:.2f} dB at 95 %, {avg['n_aspects']} aspects"
            + ("" if avg["converged"] else f", short of the requested {avg['accuracy_db']:g} dB")
            + ")"
        )
    if "plot" in result:
        lines.append(f"  polar plot: {result['plot']}")
    lines.extend(f"  warning: {w}" for w in result["warnings"])
    return "\n".join(lines)
