"""``csuas defaults list|check|presets``: parameters, derivable defaults recomputed, presets (docs/command-line.md)."""

from __future__ import annotations

from csuas.defaults import load_parameters, load_presets


def add_arguments(parser):
    """Declare the options of ``csuas defaults``."""
    parser.add_argument(
        "action",
        choices=("list", "check", "presets"),
        help="list the parameters, check derived defaults, or list every preset with the values it sets",
    )
    parser.add_argument(
        "--core-only", action="store_true", help="check: skip the checks that need a simulation (drone mesh, RCS, LCS)"
    )


def list_parameters() -> list[dict]:
    """One entry per canonical parameter: name, value, unit, source, valid range or choices, description."""
    entries = []
    for section, params in load_parameters().items():
        for name, spec in params.items():
            entry = {
                "name": f"{section}.{name}",
                "value": spec.get("value"),
                "unit": spec["unit"],
                "source": spec["source"],
                "description": spec["description"],
            }
            if "choices" in spec:
                entry["choices"] = spec["choices"]
            else:
                entry["min"], entry["max"] = spec["min"], spec["max"]
            entries.append(entry)
    return entries


def list_presets() -> list[dict]:
    """Every target, environment and sensor preset: kind, modality, name, description, source, values set."""
    entries = []
    for kind, table in load_presets().items():
        groups = table.items() if kind == "sensor" else [(None, table)]
        for modality, presets in groups:
            for name, preset in presets.items():
                values = {k: v for k, v in preset.items() if k not in ("description", "source")}
                entries.append(
                    {
                        "kind": kind,
                        "modality": modality,
                        "name": name,
                        "description": preset.get("description", ""),
                        "source": preset.get("source", ""),
                        "sets": values,
                    }
                )
    return entries


def run(args) -> dict:
    """``{"parameters": [...]}`` for list, ``{"presets": [...]}`` for presets, checks and summary for check."""
    if args.action == "list":
        return {"parameters": list_parameters()}
    if args.action == "presets":
        return {"presets": list_presets()}
    from csuas.validation.core.checks import all_checks

    checks = [c.as_dict() for c in all_checks(include_simulation=not args.core_only)]
    summary = {
        "total": len(checks),
        "ok": sum(c["ok"] for c in checks),
        "known_deviation": sum((not c["ok"]) and c["known_deviation"] is not None for c in checks),
        "limitation": sum(
            (not c["ok"]) and c["known_deviation"] is None and c["limitation"] is not None for c in checks
        ),
        "failed": sum((not c["ok"]) and c["known_deviation"] is None and c["limitation"] is None for c in checks),
    }
    return {"checks": checks, "summary": summary, "exit_code": 1 if summary["failed"] else 0}


def render_text(result: dict) -> str:
    """Aligned table of parameters or checks."""
    if "parameters" in result:
        lines = []
        for p in result["parameters"]:
            valid = ("one of " + ", ".join(p["choices"])) if "choices" in p else f"{p['min']:g} .. {p['max']:g}"
            lines.append(
                f"{p['name']:<34} {str(p['value']):>10} {p['unit']:<8} [{valid}]  {p['description']} ({p['source']})"
            )
        return "\n".join(lines)
    if "presets" in result:
        lines = []
        for p in result["presets"]:
            where = f"{p['kind']}.{p['modality']}" if p["modality"] else p["kind"]
            sets = ", ".join(f"{k} = {v}" for k, v in p["sets"].items()) or "nothing (the defaults)"
            lines.append(f"{where}.{p['name']}: {p['description']}\n    sets {sets}  ({p['source']})")
        return "\n".join(lines)
    lines = []
    for c in result["checks"]:
        verdict = "ok" if c["ok"] else ("known" if c["known_deviation"] else ("limit" if c["limitation"] else "FAIL"))
        lines.append(
            f"{verdict:<6} {c['name']:<40} paper {c['paper']:<12.6g} computed {c['computed']:<12.6g} {c['unit']}"
        )
        if not c["ok"] and (c["known_deviation"] or c["limitation"]):
            lines.append(f"       -> {c['known_deviation'] or c['limitation']}")
    s = result["summary"]
    lines.append(
        f"{s['ok']}/{s['total']} ok, {s['known_deviation']} known deviations of the paper, "
        f"{s['limitation']} limits of csuas's models, {s['failed']} failed"
    )
    return "\n".join(lines)
