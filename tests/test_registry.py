"""Every registry entry (csuas.base.registry idiom) names an object of the kind its registry promises."""

import pytest

from csuas.base.registry import resolve
from csuas.cli import COMMANDS
from csuas.commands.bench import SUITES
from csuas.commands.render import MODES
from csuas.validation.core.checks import SIMULATION_PROVIDERS
from csuas.validation.report.registry import CheckSpec
from csuas.validation.report.runner import SPEC_LISTS


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_command_module_has_its_three_functions(name):
    module = resolve(f"csuas.commands.{name.replace('-', '_')}")
    assert all(callable(getattr(module, f, None)) for f in ("add_arguments", "run", "render_text"))


@pytest.mark.parametrize("reference", [*MODES.values(), *SUITES.values(), *SIMULATION_PROVIDERS.values()])
def test_every_function_entry_resolves_to_a_callable(reference):
    assert callable(resolve(reference))


def test_every_report_entry_is_a_list_of_uniquely_named_specs():
    specs = [spec for reference in SPEC_LISTS for spec in resolve(reference)]
    assert specs and all(isinstance(spec, CheckSpec) for spec in specs)
    assert len({spec.name for spec in specs}) == len(specs)


def test_a_dotted_attribute_is_followed_and_a_bad_entry_fails_loudly():
    assert resolve("csuas.base.checks:Check.of_paper").__name__ == "of_paper"
    with pytest.raises(AttributeError):
        resolve("csuas.base.checks:NoSuchThing")
    with pytest.raises(ModuleNotFoundError):
        resolve("csuas.no_such_module:x")
