"""Dr.Jit / Mitsuba back-end selection: libLLVM discovery and variant choice.

Importing :mod:`csuas` never selects a Mitsuba variant. The renderers call
:func:`use_variant` lazily, which

1. makes sure Dr.Jit's LLVM back-end will load a libLLVM that works
   (Debian's LLVM 14 and 15 crash with "Cannot select ... fminimum"; LLVM 16 or
   newer works), by setting ``DRJIT_LIBLLVM_PATH`` when it is unset;
2. picks the first available variant of the requested family, CUDA first,
   then LLVM (``cuda_ad_rgb`` then ``llvm_ad_rgb``), unless the caller or the
   environment variable ``CSUAS_VARIANT`` names one.
"""

from __future__ import annotations

import glob
import os
import re

from csuas.base.errors import CsuasError
from csuas.base.interrupts import deferred_interrupts

#: Oldest LLVM major version whose code generation Dr.Jit 1.5 handles here.
MIN_LLVM_MAJOR = 16

_LIB_DIRS = (
    "/usr/lib/x86_64-linux-gnu",
    "/usr/lib/aarch64-linux-gnu",
    "/usr/lib64",
    "/usr/lib",
    "/usr/local/lib",
    "/opt/homebrew/opt/llvm/lib",
    "/usr/local/opt/llvm/lib",
)

_INSTALL_HINT = (
    "install LLVM 19 (Debian/Ubuntu: 'apt-get install -y libllvm19') or set "
    "DRJIT_LIBLLVM_PATH to a libLLVM of version >= {min} (or run 'make setup')"
)


class BackendError(CsuasError):
    """No usable Dr.Jit back-end (libLLVM missing or too old, variant unknown)."""


def _llvm_major(path: str) -> int:
    match = re.search(r"LLVM(?:-|\.so\.)(\d+)", os.path.basename(path))
    return int(match.group(1)) if match else -1


def find_libllvm(search_dirs: tuple[str, ...] = _LIB_DIRS) -> str | None:
    """Return the newest libLLVM shared library of a usable version, or None.

    Parameters
    ----------
    search_dirs : tuple of str
        Directories searched for ``libLLVM-<major>*.so*``.

    Returns
    -------
    str or None
        Path of the newest library with major version >= ``MIN_LLVM_MAJOR``.
    """
    candidates = []
    for directory in search_dirs:
        candidates += glob.glob(os.path.join(directory, "libLLVM-[0-9]*.so*"))
        candidates += glob.glob(os.path.join(directory, "libLLVM.so.[0-9]*"))
        candidates += glob.glob(os.path.join(directory, "llvm-[0-9]*", "lib", "libLLVM*.so*"))
    usable = [p for p in candidates if _llvm_major(p) >= MIN_LLVM_MAJOR]
    if not usable:
        return None
    return max(usable, key=lambda p: (_llvm_major(p), -len(p)))


def ensure_libllvm() -> str:
    """Make sure ``DRJIT_LIBLLVM_PATH`` names a usable libLLVM; return it.

    Raises
    ------
    BackendError
        When the variable names a missing file, or it is unset and no libLLVM of
        a usable version is installed; the message says how to fix it.
    """
    given = os.environ.get("DRJIT_LIBLLVM_PATH")
    if given:
        if not os.path.exists(given):
            raise BackendError(
                f"DRJIT_LIBLLVM_PATH={given!r} does not exist; " + _INSTALL_HINT.format(min=MIN_LLVM_MAJOR)
            )
        return given
    found = find_libllvm()
    if found is None:
        raise BackendError(
            f"no libLLVM >= {MIN_LLVM_MAJOR} found for Dr.Jit's LLVM back-end; "
            + _INSTALL_HINT.format(min=MIN_LLVM_MAJOR)
        )
    os.environ["DRJIT_LIBLLVM_PATH"] = found
    return found


def cuda_available() -> bool:
    """True when Dr.Jit sees a CUDA device (never raises).

    libLLVM is located first: Dr.Jit looks for its back-ends once per process,
    so importing it before ``DRJIT_LIBLLVM_PATH`` is set would leave the LLVM
    back-end inactive for good.
    """
    try:
        ensure_libllvm()
    except BackendError:
        pass
    try:
        with deferred_interrupts():
            import drjit as dr

        return bool(dr.has_backend(dr.JitBackend.CUDA))
    except Exception:
        return False


def use_variant(family: str = "ad_rgb", variant: str | None = None) -> str:
    """Select and return a Mitsuba variant, CUDA preferred, LLVM fallback.

    Parameters
    ----------
    family : str
        Variant family without back-end prefix, e.g. ``"ad_rgb"``,
        ``"ad_mono"``, ``"ad_mono_polarized"``.
    variant : str, optional
        Exact variant; overrides the family and ``CSUAS_VARIANT``.

    Returns
    -------
    str
        The variant now active in Mitsuba.
    """
    ensure_libllvm()
    with deferred_interrupts():
        import mitsuba as mi

    wanted = variant or os.environ.get("CSUAS_VARIANT")
    available = mi.variants()
    if wanted:
        if wanted not in available:
            raise BackendError(f"variant={wanted!r} is not available; valid: {', '.join(available)}")
        order = [wanted]
    else:
        order = ([f"cuda_{family}"] if cuda_available() else []) + [
            f"llvm_{family}",
            f"scalar_{family.replace('ad_', '')}",
        ]
    for name in order:
        if name in available:
            if mi.variant() != name:
                with deferred_interrupts():
                    mi.set_variant(name)
            return name
    raise BackendError(f"family={family!r} has no available variant; valid: {', '.join(available)}")
