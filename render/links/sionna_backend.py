"""Import Sionna RT on the Mitsuba variant csuas chose.

``import sionna.rt`` selects a Mitsuba variant by itself, but only when none
is active yet: it tries ``cuda_ad_mono_polarized``, then
``metal_ad_mono_polarized``, then ``llvm_ad_mono_polarized`` (sionna-rt 2.2,
``sionna/rt/__init__.py``). When some other variant is already active (say
``llvm_ad_rgb`` left by the EO renderer) it keeps it, and its radio materials
then fail. Its radio-material classes are also bound, at import, to the
back-end active then, so Sionna cannot move between CUDA and LLVM afterwards.

:func:`load_sionna_rt` therefore selects the polarised variant through
:func:`csuas.render.backend.use_variant` (which finds a working libLLVM,
prefers CUDA, falls back to LLVM, and honours ``CSUAS_VARIANT``) *before*
the first import, and re-activates the same variant on every later call, in
case another renderer switched variants in between.
"""

from __future__ import annotations

import os
import sys

from csuas.base.interrupts import deferred_interrupts
from csuas.render.backend import BackendError, use_variant

#: Mitsuba variant family Sionna RT needs (polarised, monochromatic, differentiable).
SIONNA_FAMILY = "ad_mono_polarized"

_loaded_variant: str | None = None


def _requested_variant() -> str | None:
    """The exact variant asked for through ``CSUAS_VARIANT``, mapped to Sionna's family."""
    wanted = os.environ.get("CSUAS_VARIANT")
    if not wanted:
        return None
    backend = wanted.split("_", 1)[0]
    return f"{backend}_{SIONNA_FAMILY}"


def load_sionna_rt():
    """Return the ``sionna.rt`` module with its Mitsuba variant active.

    Returns
    -------
    module
        ``sionna.rt``, imported on ``cuda_ad_mono_polarized`` when Dr.Jit sees
        a CUDA device, otherwise ``llvm_ad_mono_polarized``; the back-end of
        ``CSUAS_VARIANT`` (e.g. ``llvm_ad_rgb`` -> ``llvm``) wins when set.

    Raises
    ------
    BackendError
        When no libLLVM is usable, or when ``sionna.rt`` was imported earlier
        in this process on another back-end than the one now requested.
    """
    global _loaded_variant
    if _loaded_variant is not None:
        import mitsuba as mi

        if mi.variant() != _loaded_variant:
            mi.set_variant(_loaded_variant)
        return sys.modules["sionna.rt"]
    requested = _requested_variant()
    if "sionna.rt" in sys.modules:
        import mitsuba as mi

        current = mi.variant()
        if current is None or SIONNA_FAMILY not in current or (requested and requested != current):
            raise BackendError(
                f"sionna.rt was imported outside csuas on variant {current!r}; "
                "import it through csuas.render.links.sionna_backend.load_sionna_rt() first"
            )
        _loaded_variant = current
        return sys.modules["sionna.rt"]
    variant = use_variant(SIONNA_FAMILY, variant=requested)
    with deferred_interrupts():
        import sionna.rt  # noqa: F401 - the variant chosen above is kept by Sionna

    _loaded_variant = variant
    return sys.modules["sionna.rt"]


def active_variant() -> str | None:
    """The Mitsuba variant Sionna RT runs on, or None before :func:`load_sionna_rt`."""
    return _loaded_variant
