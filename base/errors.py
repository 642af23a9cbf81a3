"""Exceptions of csuas: every user-facing error names the parameter, its value and what is allowed."""

from __future__ import annotations


class CsuasError(Exception):
    """Base class of errors the command line reports as one line with exit code 2."""


class ParameterError(CsuasError, ValueError):
    """A parameter value outside its valid domain.

    Parameters
    ----------
    name : str
        Canonical parameter name (SPEC 3.2), e.g. ``"eo.hfov_deg"``.
    value : object
        The offending value.
    allowed : str
        What is allowed, e.g. ``"0 < x <= 180"``.
    """

    def __init__(self, name: str, value: object, allowed: str):
        self.name, self.value, self.allowed = name, value, allowed
        super().__init__(f"{name} = {value!r} is invalid; allowed: {allowed}")


class ScenarioError(CsuasError):
    """A scenario file that cannot be read or does not follow the scenario format."""
