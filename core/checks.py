"""Argument validation for the analytic core: clear errors, never silent NaN.

Every public model function validates its inputs with :func:`require`, which
raises :class:`csuas.base.errors.ParameterError` naming the parameter, the first
offending value and the allowed domain.
"""

from __future__ import annotations

import numpy as np

from csuas.base.errors import ParameterError, raise_all
from csuas.defaults import load_parameters


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


def require_registry_bounds(arguments: dict, keys: dict, lower: tuple = ()) -> None:
    """Refuse NaN and values above the upper bound that ``defaults/parameters.toml`` states.

    The scenario layer checks every parameter against its registry entry; this applies the same
    upper bounds to a model called directly, so that an absurd but finite input (``g_tx_db = 3026``)
    is refused naming it instead of overflowing into an unexplained range. Lower bounds stay with
    each model's own :func:`require` calls (some allow -inf, such as a silent noise floor), except
    for the arguments named in ``lower``, whose registry lower bound applies too.

    Parameters
    ----------
    arguments : dict
        The model's arguments by name (``locals()`` at its first line); None means not given.
    keys : dict
        Argument name -> ``"section.key"`` of its entry in ``defaults/parameters.toml``.
    lower : tuple of str
        Arguments whose registry lower bound (``min``, exclusive with ``min_exclusive``) is checked too.

    Raises
    ------
    ParameterError or InputErrors
        Every NaN or too-large argument at once, naming the argument and its registry entry.
    """

    registry = load_parameters()
    errors = []
    for name, key in keys.items():
        value = arguments.get(name)
        if value is None:
            continue
        section, entry = key.split(".")
        spec = registry[section][entry]
        bounds = {"le": spec["max"]}
        if name in lower:
            bounds["gt" if spec.get("min_exclusive") else "ge"] = spec["min"]
        try:
            require(name, value, **bounds, allow_inf=True, why=f"{key} in defaults/parameters.toml")
        except ParameterError as exc:
            errors.append(exc)
    raise_all(errors)
