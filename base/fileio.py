"""Atomic output files: a result file is complete or absent, never half-written."""

from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from csuas.base.errors import ParameterError
from csuas.base.interrupts import raise_if_interrupted
from csuas.base.paths import checked_path, refuse_special
from csuas.base.schema import read_toml


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: Marker in the names of csuas's temporary files: ``.{stem}.csuas-tmp-{pid}-{random}{suffix}``.
TEMP_MARKER = ".csuas-tmp-"


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, another user's
        return True
    return True


def remove_stale_temps(folder: str | os.PathLike) -> list[Path]:
    """Remove csuas temporary files in ``folder`` whose writing process no longer exists.

    A SIGKILL leaves the temporary file of an atomic write behind; the next atomic write into the
    same folder removes it. Only names of csuas's own pattern (:data:`TEMP_MARKER` and a pid) are
    touched. Returns the removed paths.
    """
    removed = []
    with contextlib.suppress(OSError):
        for entry in Path(folder).iterdir():
            head, marker, tail = entry.name.partition(TEMP_MARKER)
            pid_text = tail.split("-", 1)[0]
            if not (marker and head.startswith(".") and pid_text.isdigit()) or _pid_alive(int(pid_text)):
                continue
            with contextlib.suppress(OSError):
                if entry.is_dir():
                    shutil.rmtree(entry)
                else:
                    entry.unlink()
                removed.append(entry)
    return removed


def temp_name(target: Path) -> str:
    """The prefix of a csuas temporary file beside ``target`` (the random part follows)."""
    return f".{target.stem}{TEMP_MARKER}{os.getpid()}-"


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it into place on success.

    The temporary file keeps the suffix of ``path`` so that writers that look at
    the extension (OpenEXR, matplotlib) behave, and carries csuas's marker and
    the process id, so that a later write into the same folder removes it when
    its process was killed (:func:`remove_stale_temps`). On any exception,
    including ``KeyboardInterrupt`` (and SIGTERM, which the command line raises
    as one), the temporary file is removed and ``path`` is left untouched.

    Raises
    ------
    ParameterError
        When ``path`` exists and is not a regular file (a folder, device, FIFO or socket is never
        replaced): the last guard behind the commands' own check before their work
        (:func:`csuas.base.paths.refuse_special`).
    """
    target = refuse_special(path, "output file")
    target.parent.mkdir(parents=True, exist_ok=True)
    remove_stale_temps(target.parent)
    fd, tmp = tempfile.mkstemp(prefix=temp_name(target), suffix=target.suffix, dir=target.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        raise_if_interrupted()
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp creates 0600; give the file the usual permissions
        refuse_special(target, "output file")  # again: something may have taken its place meanwhile
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def prepare_output_dir(path: str | os.PathLike, option: str = "--out") -> Path:
    """Create the output folder ``path`` (and its parents) and prove it writable, before any work.

    Raises
    ------
    ParameterError
        When ``path`` is an existing non-folder, cannot be created, or refuses a file, naming
        ``option`` and the operating system's reason.
    """
    folder = checked_path(path, option)  # no NUL, no name longer than the file system's
    if folder.exists() and not folder.is_dir():
        raise ParameterError(option, str(folder), "a folder (this path is an existing file)")
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".csuas-probe.", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise ParameterError(option, str(folder), f"a writable folder ({exc.strerror or exc})") from None
    return folder


@contextlib.contextmanager
def exclusive_lock(path: str | os.PathLike, option: str) -> Iterator[Path]:
    """Hold an exclusive, non-blocking lock on ``path`` (created) for the block.

    Raises
    ------
    ParameterError
        Naming ``option`` when another process holds the lock.
    """
    import fcntl

    lock = Path(path)
    with open(lock, "a+") as handle:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise ParameterError(
                option, str(lock.parent), f"a folder no other csuas run is writing into (its lock {lock.name} is held)"
            ) from None
        try:
            yield lock
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` atomically and return the path."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def _spelled(value: float) -> str:
    return "nan" if math.isnan(value) else ("+inf" if value > 0 else "-inf")


def to_jsonable(obj):
    """Convert NumPy scalars and arrays (recursively) into plain JSON types.

    JSON has no NaN or infinity: a non-finite float becomes ``None``. So that a null is never
    silent, a dict entry ``key`` whose scalar value is not finite gains a sibling
    ``key_nonfinite`` (``"nan"``, ``"+inf"`` or ``"-inf"``), unless the dict already explains it
    with ``key_note``.
    """
    if isinstance(obj, dict):
        out = {}
        for k, v in obj.items():
            out[str(k)] = to_jsonable(v)
            scalar = v.item() if isinstance(v, np.ndarray) and v.size == 1 else v
            if isinstance(scalar, (float, np.floating)) and not math.isfinite(float(scalar)) and f"{k}_note" not in obj:
                out[f"{k}_nonfinite"] = _spelled(float(scalar))
        return out
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, (np.bool_, bool)):
        return bool(obj)
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        value = float(obj)
        return value if math.isfinite(value) else None
    if isinstance(obj, Path):
        return str(obj)
    return obj


def dumps(obj) -> str:
    """JSON text of ``obj`` after :func:`to_jsonable`."""
    return json.dumps(to_jsonable(obj), indent=2, sort_keys=False)


def read_spec(source, embedded, what: str) -> dict:
    """The TOML table of a spec file, or of an embedded spec when ``source`` names no file.

    Parameters
    ----------
    source : str or path-like
        A TOML file, or a name that ``embedded(name)`` turns into the path of a packaged spec.
    embedded : callable
        Name -> path of the embedded spec of that name.
    what : str
        What the spec is, for the error message ("sweep spec", "dataset spec").

    Raises
    ------
    ParameterError
        No such file or embedded spec, or not valid UTF-8 TOML.
    """

    path = Path(source)
    if not path.exists() and not str(source).endswith(".toml"):
        path = embedded(str(source))
    if not path.is_file():
        raise ParameterError("spec", str(source), f"a {what} TOML file or an embedded spec name")
    return read_toml(path, "spec", what)
