"""Exceptions of csuas: every user-facing error names the parameter, its value and what is allowed."""

from __future__ import annotations


class CsuasError(Exception):
    """Base class of errors the command line reports as one line with exit code 2."""


class ParameterError(CsuasError, ValueError):
    """A parameter value outside its valid domain.

    Parameters
    ----------
    name : str
        Canonical parameter name (docs/scenarios.md), e.g. ``"eo.hfov_deg"``.
    value : object
        The offending value.
    allowed : str
        What is allowed, e.g. ``"0 < x <= 180"``.
    """

    def __init__(self, name: str, value: object, allowed: str):
        self.name, self.value, self.allowed = name, value, allowed
        super().__init__(f"{name} = {plain(value)} is invalid; allowed: {allowed}")


def plain(value: object) -> str:
    """A value as a user wrote it: ``95.0``, ``'fog'``, ``[1.0, 2.0]``, never ``np.float64(95.0)``."""
    item = getattr(value, "item", None)
    if callable(item) and getattr(value, "ndim", 1) == 0:
        value = item()
    elif hasattr(value, "tolist"):
        value = value.tolist()
    return repr(value)


class ScenarioError(CsuasError):
    """A scenario file that cannot be read or does not follow the scenario format."""


class InputErrors(CsuasError):
    """Several mistakes of one input, reported together: one line each.

    Parameters
    ----------
    errors : list of CsuasError
        The individual errors, in the order they were found.
    """

    def __init__(self, errors):
        self.errors = list(errors)
        super().__init__("\n".join(str(e) for e in self.errors))


def raise_all(errors) -> None:
    """Raise the one error of ``errors``, or :class:`InputErrors` of several; nothing when empty."""
    errors = list(errors)
    if len(errors) == 1:
        raise errors[0]
    if errors:
        raise InputErrors(errors)
