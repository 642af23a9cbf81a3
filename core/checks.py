"""Argument validation for the analytic core: clear errors, never silent NaN.

Every public model function validates its inputs with :func:`require`, which
raises :class:`csuas.base.errors.ParameterError` naming the parameter, the first
offending value and the allowed domain.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError, raise_all


def require(name: str, value, *, gt=None, ge=None, lt=None, le=None, allow_inf: bool = False, why: str = ""):
    """Return ``value`` as a float array after checking its domain.

    Parameters
    ----------
    name : str
        Canonical parameter name used in the error message.
    value : array_like
        Value(s) to check.
    gt, ge, lt, le : float, optional
        Strict / inclusive lower and upper bounds.
    allow_inf : bool
        Whether +/-inf values are allowed (e.g. a -inf dB noise term).
    why : str, optional
        Where the bounds come from, appended to the message (e.g. the validity of a recommendation).

    Raises
    ------
    ParameterError
        If any element is NaN, infinite (unless allowed) or outside the bounds.
    """
    arr = np.asarray(value, dtype=float)
    bad = np.isnan(arr) | ((not allow_inf) & np.isinf(arr))
    parts = []
    if gt is not None:
        bad |= ~(arr > gt)
        parts.append(f"> {gt:g}")
    if ge is not None:
        bad |= ~(arr >= ge)
        parts.append(f">= {ge:g}")
    if lt is not None:
        bad |= ~(arr < lt)
        parts.append(f"< {lt:g}")
    if le is not None:
        bad |= ~(arr <= le)
        parts.append(f"<= {le:g}")
    if np.any(bad):
        first = arr[bad].flat[0] if arr.ndim else float(arr)
        allowed = " and ".join(parts) if parts else "a number"
        allowed += "" if allow_inf else " (finite)"
        allowed += f": {why}" if why else ""
        raise ParameterError(name, float(first), allowed)
    return arr


def require_all(*checks):
    """Check several parameters with :func:`require` and report every failure at once.

    Parameters
    ----------
    *checks : (str, array_like, dict)
        ``(name, value, bounds)`` with ``bounds`` the keyword arguments of :func:`require`.

    Returns
    -------
    list of ndarray
        The checked arrays, in order.

    Raises
    ------
    ParameterError or InputErrors
        One failure, or several together (:func:`csuas.base.errors.raise_all`).
    """
    arrays, errors = [], []
    for name, value, bounds in checks:
        try:
            arrays.append(require(name, value, **bounds))
        except ParameterError as exc:
            errors.append(exc)
    raise_all(errors)
    return arrays
