"""Regression against a stored report (``csuas report --baseline old.json``).

Every check of the old report is matched by name with the new one. A
regression is

* a check of the old report that is missing from the new one;
* a check that passed (or was a known deviation) and now fails;
* an expected or measured value that moved by more than the check's stated
  tolerance (the larger of the two reports' tolerances, so that a baseline
  taken at a coarser quality is compared with its own, wider, tolerance), or
  that became non-finite.

A measured value that moved beyond the tolerance toward its expected value is an improvement:
listed, not counted. Checks new in this report are listed, not counted as regressions.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from csuas.base.errors import ParameterError


def load_baseline(path) -> dict:
    """A report JSON with a ``checks`` list (ParameterError when unreadable or malformed)."""
    p = Path(path)
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ParameterError("--baseline", str(path), "an existing report.json") from None
    except IsADirectoryError:
        raise ParameterError("--baseline", str(path), "a report.json file (this is a folder)") from None
    except OSError as exc:
        raise ParameterError("--baseline", str(path), f"a readable report.json ({exc.strerror or exc})") from None
    except (json.JSONDecodeError, UnicodeDecodeError, RecursionError) as exc:
        raise ParameterError("--baseline", str(path), f"a JSON report (it does not parse: {exc})") from None
    if not isinstance(data, dict) or not isinstance(data.get("checks"), list):
        raise ParameterError("--baseline", str(path), "a report.json with a 'checks' list")
    malformed = [
        i for i, c in enumerate(data["checks"]) if not (isinstance(c, dict) and isinstance(c.get("name"), str))
    ]
    if malformed:
        raise ParameterError(
            "--baseline",
            str(path),
            f"a report.json whose checks are objects with a 'name' "
            f"(entries {', '.join(map(str, malformed[:5]))} are not)",
        )
    return data


def _number(value):
    try:
        v = float(value)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def compare(new_checks: list, old_checks: list) -> dict:
    """Regressions of ``new_checks`` against ``old_checks`` (lists of check dicts of docs/command-line.md).

    Returns
    -------
    dict
        ``regressions`` and ``improvements`` (lists of ``{name, what, old, new, tolerance}``),
        ``missing_checks`` (names absent from the new report, also regressions),
        ``compared`` (count), ``new_checks`` (names absent from the baseline).
    """
    new = {c["name"]: c for c in new_checks}
    old = {c["name"]: c for c in old_checks}
    regressions, improvements = [], []
    for name, o in old.items():
        n = new.get(name)
        if n is None:
            regressions.append(
                {"name": name, "what": "missing from the new report", "old": None, "new": None, "tolerance": None}
            )
            continue
        if (o.get("ok") or o.get("known_deviation")) and not (n.get("ok") or n.get("known_deviation")):
            regressions.append(
                {
                    "name": name,
                    "what": "passed before, fails now",
                    "old": o.get("measured"),
                    "new": n.get("measured"),
                    "tolerance": n.get("tolerance"),
                }
            )
            continue
        stated = [t for t in (_number(n.get("tolerance")), _number(o.get("tolerance"))) if t is not None]
        tol = max(stated) if stated else None
        for key in ("expected", "measured"):
            before, after = _number(o.get(key)), _number(n.get(key))
            if before is None and after is None:
                continue
            if before is not None and after is None:
                regressions.append(
                    {
                        "name": name,
                        "what": f"{key} is no longer a finite number",
                        "old": before,
                        "new": n.get(key),
                        "tolerance": tol,
                    }
                )
            elif before is not None and tol is not None and abs(after - before) > tol:
                entry = {
                    "name": name,
                    "what": f"{key} moved by {after - before:+.4g} {n.get('unit', '')} (tolerance {tol:.4g})",
                    "old": before,
                    "new": after,
                    "tolerance": tol,
                }
                (improvements if key == "measured" and _closer(n, o) else regressions).append(entry)
    return {
        "regressions": regressions,
        "improvements": improvements,
        "compared": len(old),
        "new_checks": sorted(set(new) - set(old)),
        "missing_checks": sorted(set(old) - set(new)),
    }


def _closer(new: dict, old: dict) -> bool:
    """True when the new measured value lies nearer its expected value than the old one did.

    A measured error that falls from 1 dB to 3e-6 dB moves by more than its tolerance, but toward
    the reference: an improvement, reported and not failing.
    """
    e_new, m_new = _number(new.get("expected")), _number(new.get("measured"))
    e_old, m_old = _number(old.get("expected")), _number(old.get("measured"))
    if None in (e_new, m_new, e_old, m_old):
        return False
    return abs(m_new - e_new) < abs(m_old - e_old)
