"""SIGINT and SIGTERM that are never lost.

Python raises ``KeyboardInterrupt`` at the next bytecode after SIGINT, but a C extension running at
that moment (Dr.Jit compiling its first kernels, Mitsuba loading a scene) may check for signals
itself and drop the exception. The handlers installed here also record the signal, so that
:func:`raise_if_interrupted` raises it again at the next checkpoint: every atomic file write
(:func:`csuas.base.fileio.atomic_path`) and the end of each command. SIGTERM is raised as
:class:`Terminated`, a ``KeyboardInterrupt``, so that every clean-up path treats both alike.

A ``KeyboardInterrupt`` raised *inside* the import of a nanobind extension (Mitsuba building its enum
types, say) is worse than lost: nanobind turns it into a C++ exception that nothing catches, and the
process aborts (exit -6). :func:`deferred_interrupts` holds the signal while such a module loads and
delivers it once the import is complete.
"""

from __future__ import annotations

import contextlib
import signal
import threading

_received: list[int] = []


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like SIGINT so that every ``finally`` and atomic write cleans up."""


def _exception(signum: int) -> KeyboardInterrupt:
    return Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()


def _handler(signum, frame):
    _received.append(signum)
    raise _exception(signum)


@contextlib.contextmanager
def _handlers(handler):
    """``handler`` for SIGINT and SIGTERM while the block runs; the previous handlers afterwards."""
    previous = {sig: signal.signal(sig, handler) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


@contextlib.contextmanager
def deferred_interrupts():
    """Hold SIGINT and SIGTERM while the block runs; deliver the first one held when it ends.

    For imports of C extensions that must not be interrupted half-way. The held signal is raised again
    with the handlers in force before the block, so it ends the process, raises ``KeyboardInterrupt``
    or is recorded by :func:`handling_interrupts`, exactly as it would have outside the block. Off the
    main thread (where Python runs no signal handlers) the block runs unchanged.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []

    def hold(signum, frame):
        held.append(signum)

    try:
        with _handlers(hold):
            yield
    finally:
        if held:
            signal.raise_signal(held[0])


def pending() -> KeyboardInterrupt | None:
    """The interrupt received since :func:`handling_interrupts` began, or None.

    An exception that a C extension raised while it was being interrupted (a half-imported module's
    ``NameError``, say) is a consequence of the interrupt: the caller reports the interrupt instead.
    """
    return _exception(_received[0]) if _received else None


def raise_if_interrupted() -> None:
    """Raise the interrupt received since :func:`handling_interrupts` began, if any."""
    if _received:
        raise _exception(_received[0])


@contextlib.contextmanager
def handling_interrupts():
    """Record SIGINT and SIGTERM while the block runs; restore the previous handlers afterwards.

    What was recorded is forgotten when the block ends, so that a later checkpoint outside it (a
    library call after an interrupted command, in the same process) raises nothing.
    """
    _received.clear()
    try:
        with _handlers(_handler):
            yield
    finally:
        _received.clear()
