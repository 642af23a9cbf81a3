"""Run the registry and write the report: ``report.html``, ``report.json``, ``report.md``, ``figures/*.png``.

All files are written atomically (:func:`csuas.base.fileio.atomic_path`). Progress
goes to a text stream (standard error for the command), one line per check.
"""

from __future__ import annotations

import datetime
import os
import platform
import time
from pathlib import Path

from csuas.base.errors import ParameterError
from csuas.base.fileio import atomic_path, dumps, exclusive_lock, prepare_output_dir, to_jsonable, write_text_atomic
from csuas.base.paths import inside, sub_folder
from csuas.base.registry import resolve
from csuas.validation.report.baseline import compare, load_baseline
from csuas.validation.report.html import render_html, render_markdown
from csuas.validation.report.registry import QUALITIES, groups_of, run_spec

#: The report's check modules, in report order (csuas.base.registry): each holds a list of CheckSpec.
SPEC_LISTS = (
    "csuas.validation.report.checks_defaults:SPECS",
    "csuas.validation.report.checks_conventions:SPECS",
    "csuas.validation.report.checks_links:SPECS",
    "csuas.validation.report.checks_rcs:SPECS",
    "csuas.validation.report.checks_micro_doppler:SPECS",
    "csuas.validation.report.checks_lidar:SPECS",
    "csuas.validation.report.checks_imaging:SPECS",
    "csuas.validation.report.checks_detection:SPECS",
    "csuas.validation.report.checks_terrain:SPECS",
    "csuas.validation.report.checks_engage:SPECS",
    "csuas.validation.report.checks_propagation:SPECS",
    "csuas.validation.report.checks_swarm:SPECS",
)


def all_specs() -> list:
    """Every registered check, in report order."""
    return [spec for reference in SPEC_LISTS for spec in resolve(reference)]


def check_record(spec, outcome) -> dict:
    """JSON record of one figure: the docs/command-line.md keys first, then unit, error estimate and provenance."""
    return {
        "name": outcome.name,
        "expected": outcome.expected,
        "measured": outcome.measured,
        "tolerance": outcome.tolerance,
        "ok": outcome.ok,
        "known_deviation": outcome.known_deviation,
        "time_s": outcome.time_s,
        "verdict": outcome.verdict,
        "unit": outcome.unit,
        "limitation": outcome.limitation,
        "tolerance_source": outcome.tolerance_source or spec.tolerance_why,
        "error_estimate": outcome.error_estimate,
        "check": spec.name,
        "group": spec.group.name,
        "source": outcome.source,
        "method": outcome.method,
        "details": outcome.details,
    }


def _machine() -> str:
    return (
        f"{platform.node() or 'host'} ({platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()})"
    )


def _version() -> str:
    try:
        from importlib.metadata import version

        return version("csuas")
    except Exception:
        return "unknown"


def run_report(quality: str = "quick", out_dir="csuas-report", baseline=None, specs=None, progress=None) -> dict:
    """Run the checks, write the report files and return the report's JSON object.

    Parameters
    ----------
    quality : {"quick", "full"}
        Accuracy knobs of the simulated checks.
    out_dir : str or Path
        Folder of ``report.html``, ``report.json``, ``report.md`` and ``figures/``.
    baseline : str or Path, optional
        An older ``report.json`` to compare against (regressions make the exit code 1).
    specs : list of CheckSpec, optional
        Subset of the registry (default :func:`all_specs`).
    progress : text stream, optional
        Where to print one line per check.

    Returns
    -------
    dict
        ``checks`` (docs/command-line.md keys), ``summary``, ``groups`` (the sections of the checks run, by
        order: ``name``, ``title``, ``order``, ``description``), ``sections``, ``baseline``,
        ``files``, ``exit_code`` (0: every check passes or is a known
        deviation and nothing regressed; 1 otherwise).
    """
    if quality not in QUALITIES:
        raise ParameterError("quality", quality, ", ".join(QUALITIES))
    old = load_baseline(baseline) if baseline is not None else None
    specs = all_specs() if specs is None else list(specs)
    groups_of(specs)  # two groups that clash are refused before the work
    out = prepare_output_dir(out_dir)
    sub_folder(out, "figures")
    for name in REPORT_FILES:
        inside(out, name)  # a special file there is refused now, not after the checks
    with exclusive_lock(out / LOCK_NAME, "--out"):
        return _run_locked(quality, out, baseline, old, specs, progress)


#: Lock file inside the output folder: one report writes into a folder at a time.
LOCK_NAME = ".csuas-report.lock"
#: The report's own files; report.json, written last, is the manifest of a complete set.
REPORT_FILES = ("report.json", "report.html", "report.md")


def _summary(checks: list) -> dict:
    """The report's counts: ``total``, ``ok``, ``known_deviation``, ``limitation``, ``failed``."""
    return {
        "total": len(checks),
        "ok": sum(c["verdict"] == "ok" for c in checks),
        "known_deviation": sum(c["verdict"] == "known" for c in checks),
        "limitation": sum(c["verdict"] == "limit" for c in checks),
        "failed": sum(c["verdict"] == "FAIL" for c in checks),
    }


def _run_locked(quality, out: Path, baseline, old, specs, progress) -> dict:
    """The body of :func:`run_report`, holding the folder's lock.

    The previous report's own files go first, so that an interrupted run can never leave new
    figures beside an old ``report.json``; ``report.json`` is written last and lists the set.
    """
    for name in REPORT_FILES:
        (out / name).unlink(missing_ok=True)
    start = time.perf_counter()
    results, checks, section_records = [], [], []
    for i, spec in enumerate(specs, 1):
        if progress is not None:
            print(f"[{i:2d}/{len(specs)}] {spec.name} ...", file=progress, flush=True)
        section = run_spec(spec, quality)
        results.append((spec, section))
        records = [check_record(spec, o) for o in section.outcomes]
        checks += records
        figure_files = []
        for fig in section.figures:
            path = inside(out, "figures", f"{fig.name}.png")
            with atomic_path(path) as tmp:
                tmp.write_bytes(fig.png)
            figure_files.append(
                {"name": fig.name, "title": fig.title, "caption": fig.caption, "file": str(path.relative_to(out))}
            )
        section_records.append(
            {
                "name": spec.name,
                "title": spec.title,
                "group": spec.group.name,
                "compares": spec.compares,
                "tolerance_why": spec.tolerance_why,
                "knob": spec.knob,
                "knob_value": spec.knob_value(quality),
                "simulated": spec.simulated,
                "time_s": section.time_s,
                "error": section.error,
                "table": section.table,
                "notes": section.notes,
                "figures": figure_files,
            }
        )
        if progress is not None:
            verdicts = [r["verdict"] for r in records]
            tally = ", ".join(f"{verdicts.count(v)} {v}" for v in ("ok", "known", "limit", "FAIL") if verdicts.count(v))
            print(
                f"        {section.time_s:6.2f} s  {tally or 'table and plots only'}"
                + (f"  ERROR {section.error}" if section.error else ""),
                file=progress,
                flush=True,
            )
    summary = _summary(checks)
    written = {f["file"] for sec in section_records for f in sec["figures"]}
    for stale in (out / "figures").glob("*.png"):
        if str(stale.relative_to(out)) not in written:
            stale.unlink()
    report = {
        "quality": quality,
        "generated_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "machine": _machine(),
        "version": _version(),
        "time_s": time.perf_counter() - start,
        "summary": summary,
        "groups": [group.as_dict() for group in groups_of(specs)],
        "checks": to_jsonable(checks),
        "sections": to_jsonable(section_records),
        "baseline": None,
    }
    if old is not None:
        report["baseline"] = {
            "file": str(baseline),
            "quality": old.get("quality"),
            **compare(report["checks"], old["checks"]),
        }
    regressions = report["baseline"]["regressions"] if report["baseline"] else []
    report["exit_code"] = 1 if summary["failed"] or regressions else 0
    report["files"] = {
        "html": str(out / "report.html"),
        "json": str(out / "report.json"),
        "markdown": str(out / "report.md"),
    }
    report["figures"] = sorted(written)
    write_text_atomic(inside(out, "report.md"), render_markdown(report))
    write_text_atomic(inside(out, "report.html"), render_html(report, results))
    write_text_atomic(inside(out, "report.json"), dumps(report))
    if progress is not None and report["baseline"]:
        b = report["baseline"]
        lines = (
            [f"REGRESSION {r['name']}: {r['what']}" for r in b["regressions"]]
            + [f"improvement {r['name']}: {r['what']}" for r in b["improvements"]]
            + [f"new check {n}" for n in b["new_checks"]]
            + [f"missing check {n}" for n in b["missing_checks"]]
        )
        print("\n".join(lines), file=progress, flush=True)
    return report
