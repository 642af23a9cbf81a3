"""The report's self-contained HTML page and Markdown summary.

The HTML has no external resource: style inline, every plot and image a
``data:image/png;base64`` URI, links only to anchors of the page itself. Both list the sections of
``report["groups"]``: exactly the groups of the checks run (declared beside each module's ``SPECS``,
:class:`csuas.validation.report.registry.CheckGroup`), by order.
"""

from __future__ import annotations

import base64
import html
import math

#: Sections with more passing checks than this fold them into a <details> element.
COLLAPSE_ABOVE = 3

#: Side-by-side tables longer than this fold into a <details> element [rows].
COLLAPSE_ROWS_ABOVE = 12

#: Verdicts in the order the contents table counts them: (verdict, column heading, CSS class).
VERDICTS = (("ok", "passed", "ok"), ("FAIL", "failed", "FAIL"), ("known", "known deviations", "known"),
            ("limit", "limitations", "known"))  # fmt: skip

#: Per-check text fields shown once above a table when every row of it shares them.
SHARED_FIELDS = (("tolerance_source", "tolerance"), ("source", "source"), ("method", "method"))

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:24px;color:#222;max-width:1300px}
h1{font-size:1.6em} h2{font-size:1.3em;margin-top:1.4em} h3{margin-top:1.4em;margin-bottom:0.2em}
details.group{border-top:2px solid #ccc;margin-top:1.2em;padding-top:6px} details.group>summary h2{display:inline}
details.group>summary{cursor:pointer;padding:4px 0} .counts{color:#555;font-size:0.9em;margin-left:8px}
details.rows>summary{cursor:pointer;color:#2a5a2a;font-size:0.9em;margin:4px 0}
table{border-collapse:collapse;margin:8px 0;font-size:0.86em} td,th{border:1px solid #ddd;padding:3px 6px;
vertical-align:top} th{background:#f3f3f3;text-align:left} td.num{text-align:right;font-family:monospace}
td.src{min-width:280px} .ok{background:#e6f4ea} .known{background:#fff4d6} .FAIL{background:#fde2e1;font-weight:bold}
.meta{color:#555;font-size:0.88em;margin:2px 0} .dev{font-size:0.82em;color:#6a4a00} .summary td{font-size:1.05em}
figure{display:inline-block;margin:6px;vertical-align:top;max-width:620px} figure img{max-width:100%;
border:1px solid #ddd} figure.wide{display:block;max-width:100%} figcaption{font-size:0.85em;color:#444}
pre{background:#f7f7f7;padding:6px;font-size:0.8em;white-space:pre-wrap}
"""


def _e(value) -> str:
    return html.escape(str(value), quote=True)


def fmt(value, digits: int = 5) -> str:
    """Readable text of any report value: numbers compact, None as a dash, dicts and lists spelled out.

    Never a Python repr: ``{'a': 1.0}`` becomes ``a = 1``, ``None`` becomes ``—``.
    """
    if value is None:
        return "\u2014"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        if isinstance(value, float) and not math.isfinite(value):
            return str(value)
        return f"{value:.{digits}g}"
    if isinstance(value, dict):
        return ", ".join(f"{k} = {fmt(v, digits)}" for k, v in value.items())
    if isinstance(value, (list, tuple)):
        return ", ".join(fmt(v, digits) for v in value)
    return str(value)


def knob_text(name, value) -> str:
    """``rays_per_wavelength = 3`` or ``exact`` for a check without an accuracy knob."""
    return f"{name} = {fmt(value)}" if name else "exact (no accuracy knob)"


def _img(figure) -> str:
    data = base64.b64encode(figure.png).decode("ascii")
    kind = " class='wide'" if figure.wide else ""
    return (
        f'<figure{kind}><img alt="{_e(figure.title)}" src="data:image/png;base64,{data}">'
        f"<figcaption><b>{_e(figure.title)}</b>. {_e(figure.caption)}</figcaption></figure>"
    )


def shared_fields(checks: list) -> dict:
    """The text fields (tolerance source, source, method) that every check of ``checks`` shares: field -> text."""
    shared = {}
    for key, _ in SHARED_FIELDS:
        values = {c.get(key) or "" for c in checks}
        if len(values) == 1 and checks:
            shared[key] = values.pop()
    return shared


def _checks_table(checks: list, said: dict) -> str:
    """A table of checks; a field's text in ``said`` (field -> text printed above the table) is not repeated per row."""
    varying = [
        (key, label) for key, label in SHARED_FIELDS if any(c.get(key) not in ("", None, said.get(key)) for c in checks)
    ]
    rows = [
        "<table><tr><th>verdict</th><th>check</th><th>expected</th><th>measured</th><th>tolerance</th>"
        "<th>error est.</th><th>unit</th><th>time [s]</th>" + ("<th>source / method</th>" if varying else "") + "</tr>"
    ]
    previous: dict = {}
    for c in checks:
        dev = "".join(
            f'<div class="dev">{label}: {"as above" if c[key] == previous.get(key) else _e(c[key])}</div>'
            for key, label in (("known_deviation", "known deviation"), ("limitation", "limit of csuas's model"))
            if c.get(key)
        )
        previous = c
        err = f'<div class="dev">{_e(c["details"].get("error", ""))}</div>' if c["details"].get("error") else ""
        texts = [(label, c.get(key)) for key, label in varying if c.get(key) and c.get(key) != said.get(key)]
        own = "<br>".join(f'<span class="meta">{label}:</span> {_e(text)}' for label, text in texts)
        rows.append(
            f'<tr class="{c["verdict"]}"><td>{c["verdict"]}</td><td>{_e(c["name"])}{dev}{err}</td>'
            f'<td class="num">{fmt(c["expected"])}</td><td class="num">{fmt(c["measured"])}</td>'
            f'<td class="num">{fmt(c["tolerance"], 3)}</td><td class="num">{fmt(c["error_estimate"], 3)}</td>'
            f'<td>{_e(c["unit"])}</td><td class="num">{c["time_s"]:.3f}</td>'
            + (f"<td class='src'>{own}</td>" if varying else "")
            + "</tr>"
        )
    rows.append("</table>")
    return "\n".join(rows)


def verdict_counts(checks: list) -> dict:
    """Number of checks per verdict (``ok``, ``FAIL``, ``known``, ``limit``) and in all (``total``)."""
    counts = {verdict: sum(c["verdict"] == verdict for c in checks) for verdict, _, _ in VERDICTS}
    counts["total"] = len(checks)
    return counts


def _counts_text(counts: dict) -> str:
    """``12 checks: 10 passed, 1 failed, 1 known deviations`` (zero counts left out)."""
    parts = [f"{counts[verdict]} {label}" for verdict, label, _ in VERDICTS if counts[verdict]]
    return f"{counts['total']} checks" + (": " + ", ".join(parts) if parts else "")


def _contents(report: dict) -> str:
    """The contents list: one row per section, linked, with its counts of checks by verdict and its time."""
    head = "".join(f"<th>{label}</th>" for _, label, _ in VERDICTS)
    rows = [f"<h2>Contents</h2><table><tr><th>section</th><th>checks</th>{head}<th>time [s]</th></tr>"]
    for group in report["groups"]:
        counts = verdict_counts([c for c in report["checks"] if c["group"] == group["name"]])
        time_s = sum(x["time_s"] for x in report["sections"] if x["group"] == group["name"])
        cells = "".join(
            f"<td class='num {css if counts[verdict] else ''}'>{counts[verdict]}</td>" for verdict, _, css in VERDICTS
        )
        rows.append(
            f"<tr><td><a href='#{_e(group['name'])}'>{_e(group['title'])}</a></td>"
            f"<td class='num'>{counts['total']}</td>{cells}"
            f"<td class='num'>{time_s:.1f}</td></tr>"
        )
    rows.append("<tr><td colspan='7'><a href='#timing'>Time of each check</a></td></tr></table>")
    return "".join(rows)


def _spec_checks(checks: list, tolerance_why: str) -> str:
    """A spec's checks: those needing attention in full, passing ones folded when there are many.

    Text every row shares is printed once above the table; a tolerance source equal to the spec's own
    ``tolerance_why`` (printed under its heading) is not printed again, above the table or in a row.
    """
    shared = shared_fields(checks)
    once = [
        f"{label}: {_e(shared[key])}"
        for key, label in SHARED_FIELDS
        if shared.get(key) and not (key == "tolerance_source" and shared[key] == tolerance_why)
    ]
    out = [f"<p class='meta'>{'<br>'.join(once)}</p>"] if once else []
    said = {"tolerance_source": tolerance_why, **shared}
    passing = [c for c in checks if c["verdict"] == "ok"]
    if len(passing) > COLLAPSE_ABOVE:  # long lists: show what needs attention, fold the rest
        others = [c for c in checks if c["verdict"] != "ok"]
        if others:
            out.append(_checks_table(others, said))
        out.append(
            f"<details class='rows'><summary>{len(passing)} passing checks</summary>"
            f"{_checks_table(passing, said)}</details>"
        )
    elif checks:
        out.append(_checks_table(checks, said))
    return "\n".join(out)


def _side_by_side(table: list) -> str:
    if not table:
        return ""
    if "quantity" in table[0]:
        rows = [
            "<table><tr><th>quantity</th><th>unit</th><th>paper</th><th>physical</th><th>simulated</th>"
            "<th>sim. error</th><th>note</th></tr>"
        ]
        for r in table:
            rows.append(
                f'<tr><td>{_e(r["quantity"])}</td><td>{_e(r["unit"])}</td><td class="num">{fmt(r["paper"])}'
                f'</td><td class="num">{fmt(r["physical"])}</td><td class="num">{fmt(r["simulated"])}</td>'
                f'<td class="num">{fmt(r["simulated_error"], 3)}</td><td>{_e(r["note"])}</td></tr>'
            )
    else:
        keys = [k for k in table[0] if not isinstance(table[0][k], (dict, list))]
        rows = ["<table><tr>" + "".join(f"<th>{_e(k)}</th>" for k in keys) + "</tr>"]
        for r in table:
            rows.append("<tr>" + "".join(f'<td class="num">{_e(fmt(r.get(k)))}</td>' for k in keys) + "</tr>")
    rows.append("</table>")
    return "\n".join(rows)


def render_html(report: dict, sections: list) -> str:
    """The HTML page of a report.

    Parameters
    ----------
    report : dict
        The report's JSON object (``summary``, ``checks``, ``sections``, ``baseline``...).
    sections : list of (CheckSpec, Section)
        With the figures (PNG bytes) to embed.
    """
    s = report["summary"]
    out = [
        f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>csuas validation report "
        f"({_e(report['quality'])})</title><style>{_CSS}</style></head><body>",
        f"<h1>csuas validation report &mdash; {_e(report['quality'])}</h1>",
        f"<p class='meta'>generated {_e(report['generated_utc'])} on {_e(report['machine'])}; "
        f"total time {report['time_s']:.1f} s; csuas {_e(report['version'])}</p>",
        "<table class='summary'><tr><th>checks</th><th>ok</th><th>known deviations of the paper</th>"
        "<th>limits of csuas's models</th><th>failed</th><th>exit code</th></tr>",
        f"<tr><td>{s['total']}</td><td class='ok'>{s['ok']}</td><td class='known'>{s['known_deviation']}</td>"
        f"<td class='known'>{s.get('limitation', 0)}</td>"
        f"<td class='{'FAIL' if s['failed'] else 'ok'}'>{s['failed']}</td><td>{report['exit_code']}</td>"
        "</tr></table>",
    ]
    baseline = report.get("baseline")
    if baseline:
        regs, better = baseline["regressions"], baseline.get("improvements", [])
        out.append(
            f"<h2 id='baseline'>Baseline comparison</h2><p>{_e(baseline['file'])}: {baseline['compared']} "
            f"checks compared, <b>{len(regs)} regression(s)</b>, {len(better)} improvement(s), "
            f"{len(baseline.get('new_checks', []))} new and {len(baseline.get('missing_checks', []))} "
            f"missing check(s).</p>"
        )
        rows = [("FAIL", "regression", r) for r in regs] + [("ok", "improvement", r) for r in better]
        if rows:
            out.append(
                "<table><tr><th>kind</th><th>check</th><th>what</th><th>old</th><th>new</th></tr>"
                + "".join(
                    f"<tr class='{cls}'><td>{kind}</td><td>{_e(r['name'])}</td><td>{_e(r['what'])}</td>"
                    f"<td>{fmt(r['old'])}</td><td>{fmt(r['new'])}</td></tr>"
                    for cls, kind, r in rows
                )
                + "</table>"
            )
        for label, key in (("New checks", "new_checks"), ("Missing checks", "missing_checks")):
            if baseline.get(key):
                out.append(f"<p><b>{label}:</b> {_e(', '.join(baseline[key]))}</p>")
    failed = [c for c in report["checks"] if c["verdict"] == "FAIL"]
    if failed:
        out.append("<h2 id='failed'>Failed checks</h2>" + _checks_table(failed, {}))
    out.append(_contents(report))
    by_spec = {}
    for c in report["checks"]:
        by_spec.setdefault(c["check"], []).append(c)
    for group in report["groups"]:
        counts = verdict_counts([c for c in report["checks"] if c["group"] == group["name"]])
        out.append(
            f"<details class='group' id='{_e(group['name'])}' open><summary><h2>{_e(group['title'])}</h2>"
            f"<span class='counts'>{_counts_text(counts)}</span></summary>"
            f"<p class='meta'>{_e(group['description'])}</p>"
        )
        for spec, section in sections:
            if spec.group.name != group["name"]:
                continue
            knob = f"; knob: {_e(knob_text(spec.knob, spec.knob_value(report['quality'])))}"
            out.append(
                f"<h3 id='{_e(spec.name)}'>{_e(spec.title)}</h3>"
                f"<p class='meta'>compares: {_e(spec.compares)}<br>tolerance: {_e(spec.tolerance_why)}{knob}"
                f"<br>time: {section.time_s:.2f} s</p>"
            )
            table = _side_by_side(section.table)
            if len(section.table) > COLLAPSE_ROWS_ABOVE:
                table = f"<details class='rows'><summary>table of {len(section.table)} rows</summary>{table}</details>"
            out.append(table)
            out.append(_spec_checks(by_spec.get(spec.name, []), spec.tolerance_why))
            out.extend(_img(f) for f in section.figures)
            if section.error:
                out.append(f"<pre>{_e(section.notes[0] if section.notes else section.error)}</pre>")
            else:
                out.extend(f"<p class='meta'>{_e(n)}</p>" for n in section.notes)
        out.append("</details>")
    out.append(
        "<h2 id='timing'>Time of each check</h2><table><tr><th>check</th><th>figures</th><th>knob</th>"
        "<th>time [s]</th></tr>"
        + "".join(
            f"<tr><td><a href='#{_e(x['name'])}'>{_e(x['name'])}</a></td><td>{len(by_spec.get(x['name'], []))}"
            f"</td><td>{_e(knob_text(x['knob'], x['knob_value']))}</td><td class='num'>{x['time_s']:.2f}</td>"
            f"</tr>"
            for x in report["sections"]
        )
        + "</table>"
    )
    out.append("</body></html>")
    return "\n".join(out)


def _markdown_sections(report: dict) -> list:
    """Lines of the Markdown's ``## Sections``: one row per group run, its counts by verdict and what it checks."""
    head = " | ".join(label for _, label, _ in VERDICTS)
    lines = ["## Sections", "", f"| section | checks | {head} | what it checks |", "|---" * (len(VERDICTS) + 3) + "|"]
    for group in report["groups"]:
        counts = verdict_counts([c for c in report["checks"] if c["group"] == group["name"]])
        cells = " | ".join(str(counts[verdict]) for verdict, _, _ in VERDICTS)
        lines.append(f"| {group['title']} | {counts['total']} | {cells} | {group['description']} |")
    return lines + [""]


def render_markdown(report: dict) -> str:
    """Markdown summary: counts, failures, known deviations, convention tables, times."""
    s = report["summary"]
    lines = [
        f"# csuas validation report ({report['quality']})",
        "",
        f"Generated {report['generated_utc']} on {report['machine']}; total {report['time_s']:.1f} s.",
        "",
        f"**{s['total']} checks: {s['ok']} ok, {s['known_deviation']} known deviations of the paper, "
        f"{s.get('limitation', 0)} limits of csuas's models, {s['failed']} failed** "
        f"(exit code {report['exit_code']}).",
        "",
    ]
    baseline = report.get("baseline")
    if baseline:
        lines += [
            f"Baseline {baseline['file']}: {baseline['compared']} compared, "
            f"{len(baseline['regressions'])} regression(s), {len(baseline.get('improvements', []))} "
            f"improvement(s).",
            "",
        ]
        lines += [f"- REGRESSION {r['name']}: {r['what']}" for r in baseline["regressions"]]
        lines += [f"- improvement {r['name']}: {r['what']}" for r in baseline.get("improvements", [])]
        lines += [f"- new check {name}" for name in baseline.get("new_checks", [])]
        lines += [f"- missing check {name}" for name in baseline.get("missing_checks", [])] + [""]
    lines += _markdown_sections(report)
    failed = [c for c in report["checks"] if c["verdict"] == "FAIL"]
    if failed:
        lines += ["## Failed", "", "| check | expected | measured | tolerance | note |", "|---|---|---|---|---|"]
        lines += [
            f"| {c['name']} | {fmt(c['expected'])} | {fmt(c['measured'])} | {fmt(c['tolerance'], 3)} | "
            f"{c['details'].get('error', '')} |"
            for c in failed
        ] + [""]
    known = [c for c in report["checks"] if c["verdict"] == "known"]
    if known:
        lines += [
            "## Known deviations of the paper",
            "",
            "| check | expected | measured | unit | explanation |",
            "|---|---|---|---|---|",
        ]
        lines += [
            f"| {c['name']} | {fmt(c['expected'])} | {fmt(c['measured'])} | {c['unit']} | "
            f"{c['known_deviation'].replace('|', '/')} |"
            for c in known
        ] + [""]
    limits = [c for c in report["checks"] if c["verdict"] == "limit"]
    if limits:
        lines += [
            "## Limits of csuas's own models",
            "",
            "| check | expected | measured | unit | explanation |",
            "|---|---|---|---|---|",
        ]
        lines += [
            f"| {c['name']} | {fmt(c['expected'])} | {fmt(c['measured'])} | {c['unit']} | "
            f"{c['limitation'].replace('|', '/')} |"
            for c in limits
        ] + [""]
    lines += [
        "## Convention differences (docs/conventions.md)",
        "",
        "| quantity | unit | paper | physical | simulated |",
        "|---|---|---|---|---|",
    ]
    for sec in report["sections"]:
        if sec["group"] == "conventions":
            lines += [
                f"| {r['quantity']} | {r['unit']} | {fmt(r['paper'])} | {fmt(r['physical'])} | "
                f"{fmt(r['simulated'])}{' +- ' + fmt(r['simulated_error'], 2) if r['simulated_error'] else ''} |"
                for r in sec["table"]
            ]
    lines += ["", "## Time of each check", "", "| check | knob | time [s] |", "|---|---|---|"]
    lines += [
        f"| {x['name']} | {knob_text(x['knob'], x['knob_value'])} | {x['time_s']:.2f} |" for x in report["sections"]
    ]
    return "\n".join(lines) + "\n"
