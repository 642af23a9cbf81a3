"""``csuas pd-radar``: probability of detection of a radar's square-law detector, or the SNR it needs.

``--snr-db X`` gives ``pd``; ``--pd D`` instead gives ``required_snr_db`` (single pulse). Swerling
0-4, N pulses, coherent or noncoherent integration, exact (core.radar_detection) or one of the
Albersheim and Shnidman approximations (docs/detection.md).
"""

from __future__ import annotations

from csuas.base.errors import ParameterError
from csuas.core.radar_detection import INTEGRATIONS, METHODS, pd_exact, required_snr_db


def add_arguments(parser):
    """Declare the options of ``csuas pd-radar``."""
    given = parser.add_mutually_exclusive_group(required=True)
    given.add_argument("--snr-db", type=float, default=None, help="single-pulse SNR [dB]: gives pd")
    given.add_argument("--pd", type=float, default=None, help="desired probability of detection: gives required_snr_db")
    parser.add_argument("--pfa", type=float, required=True, help="probability of false alarm, 0 < Pfa < 1")
    parser.add_argument("--n-pulses", type=int, default=1, help="pulses integrated (default 1)")
    parser.add_argument("--swerling", type=int, default=0, help="Swerling case 0 (steady), 1, 2, 3 or 4 (default 0)")
    parser.add_argument("--integration", choices=INTEGRATIONS, default="noncoherent", help="default noncoherent")
    parser.add_argument("--method", choices=METHODS, default="exact", help="exact (default), albersheim, shnidman")


def run(args) -> dict:
    """``pd`` for a given SNR, or ``required_snr_db`` for a given Pd, with the inputs echoed."""
    out = {
        "pfa": args.pfa,
        "n_pulses": args.n_pulses,
        "swerling": args.swerling,
        "integration": args.integration,
        "method": args.method,
    }
    if args.snr_db is not None:
        if args.method != "exact":
            raise ParameterError("method", args.method, "exact with --snr-db; the approximations need --pd")
        out["snr_db"] = args.snr_db
        out["pd"] = float(pd_exact(args.snr_db, args.pfa, args.n_pulses, args.swerling, args.integration))
    else:
        out["pd_requested"] = args.pd
        out["required_snr_db"] = float(
            required_snr_db(args.pd, args.pfa, args.n_pulses, args.swerling, args.integration, args.method)
        )
    return out


def render_text(result: dict) -> str:
    """One line: the answer and what it assumed."""
    case = (
        f"Swerling {result['swerling']:g}, {result['n_pulses']:g} pulse(s) {result['integration']}, "
        f"Pfa {result['pfa']:g}, {result['method']}"
    )
    if "pd" in result:
        return f"Pd = {result['pd']:.6g} at {result['snr_db']:g} dB single-pulse SNR ({case})"
    return f"required single-pulse SNR = {result['required_snr_db']:.4f} dB for Pd {result['pd_requested']:g} ({case})"
