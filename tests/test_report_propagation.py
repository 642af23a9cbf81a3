"""The propagation checks of the report (gases, sound, barrier, field comparison) run and pass or name a limitation."""

from csuas.validation.report.checks_propagation import SPECS
from csuas.validation.report.registry import run_spec


def test_propagation_checks_pass_or_state_their_limitation():
    for spec in SPECS:
        section = run_spec(spec, "quick")
        assert section.error is None, section.error
        verdicts = {o.name: o.verdict for o in section.outcomes}
        assert all(v == "ok" for n, v in verdicts.items() if not n.startswith("sound.field.")), verdicts
        assert all(v in ("ok", "limit") for v in verdicts.values()), verdicts
        assert section.table or spec.name in ("propagation.sound", "propagation.barrier")
