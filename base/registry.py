"""The one registry idiom of csuas: a dict from a public name to ``"package.module:attribute"``.

Commands, render modes, benchmark suites, report check modules and simulation check providers
are all registered this way, so listing the names (for ``--help``, ``choices``, the report's
order) imports nothing heavy; :func:`resolve` imports the entry when it is used.
"""

from __future__ import annotations

import importlib

from csuas.base.interrupts import raise_if_interrupted


def resolve(reference: str):
    """The object a registry entry names.

    Parameters
    ----------
    reference : str
        ``"package.module:attribute"`` (a dotted attribute path after the colon is followed), or
        ``"package.module"`` for the module itself.
    """
    module_name, _, attribute = reference.partition(":")
    found = importlib.import_module(module_name)
    raise_if_interrupted()  # an interrupt that a C extension swallowed while the module loaded
    for part in filter(None, attribute.split(".")):
        found = getattr(found, part)
    return found
