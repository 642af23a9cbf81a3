"""``csuas defaults list|check``: the paper's parameters, and every derivable default recomputed (SPEC 8)."""

from __future__ import annotations

from csuas.defaults import load_parameters


def add_arguments(parser):
    """Declare the options of ``csuas defaults``."""
    parser.add_argument("action", choices=("list", "check"), help="list the parameters, or check derived defaults")
    parser.add_argument("--core-only", action="store_true",
                        help="check: skip the checks that need a simulation (drone mesh, RCS, LCS)")


def list_parameters() -> list[dict]:
    """One entry per canonical parameter: name, value, unit, source, valid range or choices, description."""
    entries = []
    for section, params in load_parameters().items():
        for name, spec in params.items():
            entry = {"name": f"{section}.{name}", "value": spec.get("value"), "unit": spec["unit"],
                     "source": spec["source"], "description": spec["description"]}
            if "choices" in spec:
                entry["choices"] = spec["choices"]
            else:
                entry["min"], entry["max"] = spec["min"], spec["max"]
            entries.append(entry)
    return entries


def run(args) -> dict:
    """``{"parameters": [...]}`` for list, ``{"checks": [...], "summary": {...}}`` for check."""
    if args.action == "list":
        return {"parameters": list_parameters()}
    from csuas.validation.defaults_checks import all_checks

    checks = [c.as_dict() for c in all_checks(include_simulation=not args.core_only)]
    summary = {"total": len(checks), "ok": sum(c["ok"] for c in checks),
               "known_deviation": sum((not c["ok"]) and c["known_deviation"] is not None for c in checks),
               "failed": sum((not c["ok"]) and c["known_deviation"] is None for c in checks)}
    return {"checks": checks, "summary": summary, "exit_code": 1 if summary["failed"] else 0}


def render_text(result: dict) -> str:
    """Aligned table of parameters or checks."""
    if "parameters" in result:
        return "\n".join(f"{p['name']:<36} {str(p['value']):>12} {p['unit']:<10} {p['source']}"
                         for p in result["parameters"])
    lines = []
    for c in result["checks"]:
        verdict = "ok" if c["ok"] else ("known" if c["known_deviation"] else "FAIL")
        lines.append(f"{verdict:<6} {c['name']:<40} paper {c['paper']:<12.6g} computed {c['computed']:<12.6g} {c['unit']}")
        if not c["ok"] and c["known_deviation"]:
            lines.append(f"       -> {c['known_deviation']}")
    s = result["summary"]
    lines.append(f"{s['ok']}/{s['total']} ok, {s['known_deviation']} known deviations, {s['failed']} failed")
    return "\n".join(lines)
