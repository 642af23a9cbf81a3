"""``csuas micro-doppler PRESET --out DIR``: the Doppler spectrum of a drone's spinning rotor blades.

The slow-time field of the preset's blades (PO, :mod:`csuas.render.rcs.micro_doppler`) plus the
body's static return, sampled at the PRF over the dwell; the spectrum (Hann window by default), its
lines at multiples of ``N Omega``, the blade-flash period and the time-averaged RCS of the spinning
rotors against the blades at rest. The arguments are checked and the cost (samples x blade facets,
and the body's SBR run) estimated and held against ``--max-seconds`` and ``--max-memory-gb`` before
``--out`` is made; then the simulation runs. Writes ``micro_doppler.json`` and ``micro_doppler.png`` (the
spectrum and a spectrogram) into ``--out``.
"""

from __future__ import annotations

import json
import time

import numpy as np

from csuas.base.cost import add_limit_arguments, check_limits
from csuas.base.errors import ParameterError
from csuas.base.fileio import atomic_path, prepare_output_dir, write_text_atomic
from csuas.base.paths import inside

#: Default radar: X band, 20 kHz PRF (above twice the Mini 4 Pro's tip Doppler at 10 GHz, 6.3 kHz).
DEFAULT_FREQUENCY_GHZ = 10.0
DEFAULT_PRF_HZ = 20_000.0
DEFAULT_DWELL_S = 0.1


def add_arguments(parser) -> None:
    """Options of ``csuas micro-doppler``."""
    from csuas.render.rcs.micro_doppler import DEFAULT_ROTOR_RPM, WINDOWS

    parser.add_argument("preset", metavar="PRESET", help="drone preset with rotor blades (e.g. dji_mini_4_pro)")
    parser.add_argument("--out", help="output folder (micro_doppler.json, micro_doppler.png)")
    parser.add_argument(
        "--frequency-ghz", type=float, default=DEFAULT_FREQUENCY_GHZ, help="radar frequency [GHz] (default 10)"
    )
    parser.add_argument(
        "--rpm",
        type=float,
        default=DEFAULT_ROTOR_RPM,
        help=f"rotor rate of every rotor [rev/min] (default {DEFAULT_ROTOR_RPM:g}, assumed hover rate)",
    )
    parser.add_argument("--prf-hz", type=float, default=DEFAULT_PRF_HZ, help="pulse repetition frequency [Hz]")
    parser.add_argument("--dwell-s", type=float, default=DEFAULT_DWELL_S, help="dwell [s] (default 0.1)")
    parser.add_argument("--azimuth-deg", type=float, default=0.0, help="azimuth toward the radar [deg] (default 0)")
    parser.add_argument(
        "--elevation-deg", type=float, default=10.0, help="elevation toward the radar [deg] (default 10)"
    )
    parser.add_argument("--window", choices=tuple(WINDOWS), default="hann", help="spectral window (default hann)")
    parser.add_argument(
        "--allow-aliasing",
        action="store_true",
        help="flag PRF < 2 x tip Doppler in the output instead of refusing it",
    )
    add_limit_arguments(parser)


def _plot(path, result, preset: str, frequency_ghz: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_s, ax_g) = plt.subplots(2, 1, figsize=(8, 7))
    level = 10 * np.log10(np.maximum(result.spectrum_m2, 1e-20))
    ax_s.plot(result.frequency_hz, level, lw=0.7, color="0.3", label=f"spectrum ({result.window} window)")
    for edge in (-result.max_tip_doppler_hz, result.max_tip_doppler_hz):
        ax_s.axvline(edge, color="tab:red", ls="--", lw=0.8)
    lines = result.lines
    ax_s.plot(
        [x["frequency_hz"] for x in lines],
        [10 * np.log10(max(x["power"], 1e-20)) for x in lines],
        "o",
        ms=3,
        color="tab:blue",
        label=f"lines, every {result.line_spacing_hz:g} Hz",
    )
    ax_s.set(
        xlabel="Doppler [Hz]",
        ylabel="line RCS [dBsm]",
        ylim=(max(level.max() - 90, -200), level.max() + 5),
        title=f"{preset}: rotor micro-Doppler, {frequency_ghz:g} GHz (red: +-max tip Doppler)",
    )
    ax_s.legend(fontsize=8)
    segment = max(16, int(len(result.time_s) // 40))
    ax_g.specgram(
        result.field_m,
        NFFT=segment,
        Fs=1.0 / (result.time_s[1] - result.time_s[0]),
        noverlap=segment // 2,
        cmap="viridis",
        scale="dB",
    )
    ax_g.set(xlabel="time [s]", ylabel="Doppler [Hz]", title=f"spectrogram ({segment}-sample Hann segments)")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")
    plt.close(fig)


def run(args) -> dict:
    """Check, estimate, prepare ``--out``, simulate, write the JSON and the plot; returns the ``--json`` object."""
    from csuas.render.rcs.micro_doppler import MODEL_LIMITS, estimate_cost, plan_micro_doppler, simulate
    from csuas.render.rcs.solver import to_dbsm

    start = time.perf_counter()
    if args.out is None:
        raise ParameterError("--out", None, "an output folder")
    plan = plan_micro_doppler(
        args.preset,
        args.frequency_ghz,
        args.prf_hz,
        args.dwell_s,
        args.rpm,
        (args.azimuth_deg, args.elevation_deg),
        args.window,
        args.allow_aliasing,
    )
    estimate = estimate_cost(plan)
    check_limits(estimate, args, "micro-doppler")  # before --out is made and any field computed
    out = prepare_output_dir(args.out)
    result = simulate(plan)
    summary, png = inside(out, "micro_doppler.json"), inside(out, "micro_doppler.png")
    _plot(png, result, args.preset, args.frequency_ghz)
    record = {
        "preset": args.preset,
        "frequency_ghz": args.frequency_ghz,
        "rpm": args.rpm,
        "prf_hz": args.prf_hz,
        "dwell_s": args.dwell_s,
        "azimuth_deg": args.azimuth_deg,
        "elevation_deg": args.elevation_deg,
        "window": result.window,
        "rotors": result.rotors,
        "flash_period_s": result.flash_period_s,
        "line_spacing_hz": result.line_spacing_hz,
        "max_tip_doppler_hz": result.max_tip_doppler_hz,
        "aliased": result.aliased,
        "lines": [{**x, "rcs_dbsm": float(to_dbsm(x["power"]))} for x in result.lines],
        "rcs_spinning_m2": result.rcs_spinning_m2,
        "rcs_at_rest_m2": result.rcs_at_rest_m2,
        "body_rcs_m2": result.body_rcs_m2,
        "body_bound_db": result.body_bound_db if np.isfinite(result.body_bound_db) else None,
        "spectrum": {
            "frequency_hz": result.frequency_hz.tolist(),
            "rcs_dbsm": [float(v) for v in to_dbsm(result.spectrum_m2)],
        },
        "model_limits": MODEL_LIMITS,
        "cost_estimate": estimate.as_dict(),
        "simulation_time_s": result.time_cost_s,
        "time_s": time.perf_counter() - start,
        "json": str(summary),
        "png": str(png),
    }
    write_text_atomic(summary, json.dumps(record, indent=1, allow_nan=False))
    return record


def _db(value_m2: float) -> float:
    return 10.0 * np.log10(max(value_m2, 1e-30))


def render_text(result: dict) -> str:
    """Summary of ``csuas micro-doppler``."""
    bound = "none" if result["body_bound_db"] is None else f"{result['body_bound_db']:.2f} dB"
    strongest = sorted((x for x in result["lines"] if x["order"] != 0), key=lambda x: -x["power"])[:3]
    return "\n".join(
        [
            f"Rotor micro-Doppler of {result['preset']} at {result['frequency_ghz']:g} GHz, {result['rpm']:g} rpm, "
            f"PRF {result['prf_hz']:g} Hz, dwell {result['dwell_s']:g} s ({result['window']} window)",
            f"  blade-flash period {1e3 * result['flash_period_s']:.3f} ms, "
            f"lines every {result['line_spacing_hz']:g} Hz, "
            f"max tip Doppler {result['max_tip_doppler_hz']:.0f} Hz"
            + ("  ALIASED (PRF < 2 f_tip)" if result["aliased"] else ""),
            f"  time-mean RCS of the spinning blades {_db(result['rcs_spinning_m2']):.1f} dBsm, at rest "
            f"{_db(result['rcs_at_rest_m2']):.1f} dBsm; body {_db(result['body_rcs_m2']):.1f} dBsm "
            f"(bound {bound})",
            "  strongest lines: " + ", ".join(f"{x['frequency_hz']:g} Hz {x['rcs_dbsm']:.1f} dBsm" for x in strongest),
            f"  model: {result['model_limits']}",
            f"  {result['time_s']:.1f} s; files: {result['json']}, {result['png']}",
        ]
    )
