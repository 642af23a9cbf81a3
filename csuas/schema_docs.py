"""The key tables of docs/scenarios.md, docs/coverage.md, docs/datasets.md and docs/sweeps.md, generated from the
declared schemas of the four input files, and the quality ladders of docs/simulation.md, generated from the
simulators' :class:`csuas.base.quality.QualityLadder` records, so that the docs and the code cannot drift apart.

Each table sits between ``<!-- generated: NAME -->`` and ``<!-- end generated: NAME -->`` in its page;
``tests/test_schemas.py`` fails when a page differs from what the schemas generate. Regenerate with::

    .venv/bin/python -m csuas.schema_docs
"""

from __future__ import annotations

import sys
from pathlib import Path

from csuas.base.fileio import write_text_atomic
from csuas.base.quality import ladders_table
from csuas.base.registry import resolve
from csuas.base.schema import key_rows, key_table, replace_generated
from csuas.core.result import CONVENTIONS
from csuas.defaults import MODALITIES
from csuas.defaults.scenario_schema import scenario_schema, section_schema
from csuas.render.imaging.dataset_schema import DatasetSchema
from csuas.render.quality import LADDERS
from csuas.render.site_schema import SiteSchema
from csuas.sweep.kinds import JOB_KINDS
from csuas.sweep.schema import SweepCommon

ROOT = Path(__file__).resolve().parents[1]


def _sweep_tables() -> dict:
    common = key_rows(SweepCommon)
    per_job = [("job", "required", ", ".join(JOB_KINDS), "what each point computes")]
    chunks = ", ".join(f"{job} {kind.chunk_points}" for job, kind in JOB_KINDS.items())
    per_job.append(
        (
            "chunk_points",
            chunks,
            "a whole number >= 1",
            "points per task; absent: sized from the points and workers, at most the default (sweep/chunking.py)",
        )
    )
    tables = {"sweep": key_table(per_job + common)}
    for job, kind in JOB_KINDS.items():
        options = [row for row in key_rows(kind.schema) if row[0].startswith("options.")]
        tables[f"sweep-options-{job}"] = key_table(options) if options else "(none)"
    return tables


def _scenario_tables() -> dict:
    tables = {"scenario": key_table(key_rows(scenario_schema(CONVENTIONS)))}
    for modality in MODALITIES:
        rows = key_rows(section_schema(modality, modality, "default"), "sensors.NAME.")
        tables[f"scenario-{modality}"] = key_table(rows)
    return tables


def generated_tables() -> dict:
    """``{docs page: {marker name: Markdown table}}`` of every generated key table."""
    return {
        "docs/scenarios.md": _scenario_tables(),
        "docs/coverage.md": {"site": key_table(key_rows(SiteSchema))},
        "docs/datasets.md": {"dataset": key_table(key_rows(DatasetSchema))},
        "docs/sweeps.md": _sweep_tables(),
        "docs/simulation.md": {"quality-ladders": ladders_table(resolve(reference) for reference in LADDERS)},
    }


def generated_pages(root: Path = ROOT) -> dict:
    """``{page path: text}``: each docs page with its generated tables as the schemas give them now."""
    pages = {}
    for page, tables in generated_tables().items():
        text = (root / page).read_text(encoding="utf-8")
        for name, table in tables.items():
            text = replace_generated(text, name, table)
        pages[root / page] = text
    return pages


def main() -> int:
    """Rewrite the generated tables of the docs pages; print the pages that changed."""
    for path, text in generated_pages().items():
        if path.read_text(encoding="utf-8") != text:
            write_text_atomic(path, text)
            print(f"updated {path.relative_to(ROOT)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
