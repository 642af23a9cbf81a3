"""Output paths built from what users name: one safe file-name part, one containment rule.

Every command that writes builds its file names through :func:`file_name_part` (a scenario's
``name``, its sensor keys, a site's sensor names) and its paths through :func:`inside` (a path under
the output folder the user named) or :func:`output_file` (a single file the user named, such as
``--plot`` or ``--export``). The rules, stated in docs/conventions.md ("Output files"):

* a name that becomes part of a file name matches :data:`SAFE_NAME` (letters, digits, ``_``, ``-``
  and ``.``, 1 to :data:`MAX_NAME_CHARS` characters, not starting with ``.`` or ``-``); anything else
  is refused (exit 2, naming the key), never rewritten, so that a file's name always is the name the
  user wrote;
* every path written lies inside the output folder after every symbolic link of its folders is
  followed (the output folder itself is resolved once: a link the user named is the user's choice);
* a file is only ever replaced when it is a regular file (or a new name): a device, FIFO, socket or
  folder in its place is refused before any work (:func:`refuse_special`), and again by
  :func:`csuas.base.fileio.atomic_path` as the last guard.
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path

from csuas.base.errors import ParameterError

#: Longest name that becomes part of a file name [characters]; a render's file name joins two of them
#: with its coordinates and stays under the 255 bytes of common file systems.
MAX_NAME_CHARS = 64
#: What a user-given name may be to become part of a file name.
SAFE_NAME = re.compile(rf"[A-Za-z0-9_][A-Za-z0-9_.-]{{0,{MAX_NAME_CHARS - 1}}}")
SAFE_NAME_TEXT = (
    f"1 to {MAX_NAME_CHARS} letters, digits, '_', '-' or '.', starting with a letter, digit or '_' "
    "(it becomes part of an output file name)"
)
#: Longest single file name most file systems accept [bytes].
NAME_MAX_BYTES = 255

_KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISSOCK, "a socket"),
)


def file_name_part(value, key: str) -> str:
    """``value`` unchanged when it may become part of a file name (:data:`SAFE_NAME`).

    Parameters
    ----------
    value : object
        A name the user gave (a scenario's ``name``, a sensor's key).
    key : str
        Where it was given, for the error (``"name"``, ``"sensors"``).

    Raises
    ------
    ParameterError
        Naming ``key`` and the value, when ``value`` is not a string matching :data:`SAFE_NAME`.
    """
    if not (isinstance(value, str) and SAFE_NAME.fullmatch(value)):
        raise ParameterError(key, value, SAFE_NAME_TEXT)
    return value


def _kind(path: Path) -> str | None:
    """What ``path`` is when it exists and is not a regular file (links followed), else None."""
    try:
        mode = os.stat(path).st_mode
    except (FileNotFoundError, NotADirectoryError):
        return None
    if stat.S_ISREG(mode):
        return None
    return next((text for test, text in _KINDS if test(mode)), "not a regular file")


def refuse_special(path, option: str) -> Path:
    """``path`` when it is a new name or a regular file; refused when anything else is there.

    Raises
    ------
    ParameterError
        Naming ``option`` and what ``path`` is (a folder, a character device, a FIFO, ...).
    """
    target = Path(path)
    kind = _kind(target)
    if kind is not None:
        raise ParameterError(
            option, str(target), f"a regular file or a new name (this is {kind}; it is never replaced)"
        )
    return target


def checked_path(path, option: str) -> Path:
    """``path`` as a Path; refused (naming ``option``) when it holds a NUL or a name longer than the file system's."""
    text = os.fspath(path)
    if "\0" in text:
        raise ParameterError(option, text, "a path without NUL characters")
    if any(len(os.fsencode(part)) > NAME_MAX_BYTES for part in Path(text).parts):
        raise ParameterError(option, text, f"file names of at most {NAME_MAX_BYTES} bytes each")
    return Path(text)


def _resolved(path: Path, option: str) -> Path:
    """``path`` with every symbolic link followed; a loop of links is refused naming ``option``."""
    try:
        return path.resolve()
    except (OSError, RuntimeError) as exc:  # Python 3.11 raises RuntimeError on a loop
        raise ParameterError(option, str(path), f"a path without a loop of symbolic links ({exc})") from None


def output_file(path, option: str) -> Path:
    """A single output file the user named (``--plot``, ``--export``): checked before any work.

    Its folder is the file's own parent (created when written); the file itself must be a new name
    or a regular file (:func:`refuse_special`), its folder not an existing non-folder.
    """
    target = checked_path(path, option)
    refuse_special(target, option)
    parent = _kind(target.parent)
    if parent is not None and parent != "a folder":
        raise ParameterError(option, str(target), f"a path in a folder ({target.parent} is {parent})")
    return target


def inside(folder, *parts: str, option: str = "--out") -> Path:
    """The path ``folder/parts...``, refused unless it lies inside ``folder``.

    ``folder`` is resolved once (a symbolic link the user named is followed); the folders between it
    and the file are resolved too, so that neither ``..``, an absolute part nor a link inside the
    output folder can lead elsewhere. The last part is a name in that folder: a link there is
    replaced by the atomic write, never followed. The file must be a new name or a regular file
    (:func:`refuse_special`). Returns the path as joined (``folder`` as the user wrote it).

    Raises
    ------
    ParameterError
        Naming ``option`` when the path leaves ``folder``, holds a NUL, has a name too long, or is a
        special file.
    """
    named = checked_path(folder, option)
    root = _resolved(named, option)
    joined = checked_path(named.joinpath(*parts), option)
    parent = _resolved(joined.parent, option)
    if joined.name in ("", ".", "..") or (parent != root and root not in parent.parents):
        raise ParameterError(option, str(joined), f"a path inside the output folder {root}")
    return refuse_special(joined, option)


def sub_folder(folder, name: str, option: str = "--out") -> Path:
    """The folder ``folder/name``, created; refused unless it lies inside ``folder`` with links followed.

    For the sub-folders a command writes into (``images/``, ``chunks/``, ``figures/``): checked before
    the command's work, so that a link there to another folder is refused rather than written through.

    Raises
    ------
    ParameterError
        Naming ``option`` when ``folder/name`` leads outside ``folder`` or is not a folder.
    """
    named = checked_path(folder, option)
    root, path = _resolved(named, option), named / name
    if root not in _resolved(path, option).parents:
        raise ParameterError(option, str(path), f"a path inside the output folder {root}")
    kind = _kind(path)
    if kind not in (None, "a folder"):
        raise ParameterError(option, str(path), f"a folder (this is {kind})")
    path.mkdir(exist_ok=True)
    return path
