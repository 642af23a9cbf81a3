"""``csuas report``: the registry of validation checks, the report files and the baseline comparison.

References: docs/validation.md.

Modules
-------
registry
    :class:`CheckSpec` (a declared check), :class:`Check` (one compared
    figure), :class:`Section`, :func:`run_spec` (exceptions become failed checks).
checks_defaults, checks_conventions, checks_links, checks_rcs, checks_lidar, checks_imaging
    The registered checks, one module per area (``SPECS`` lists).
figures
    Plots as PNG bytes.
html
    Self-contained HTML page and Markdown summary.
baseline
    Regression against an older ``report.json``.
runner
    :func:`run_report`: runs the registry, writes the files atomically.

Importing this package imports neither Mitsuba nor Sionna; the checks do, when run.
"""

from csuas.base.checks import Check
from csuas.validation.report.registry import QUALITIES, CheckSpec, Figure, Section, run_spec

__all__ = ["QUALITIES", "CheckSpec", "Figure", "Check", "Section", "run_spec"]
