"""Write a file atomically: a temporary file in the same folder, then `os.replace`.

A failed or interrupted write never leaves a half-written file over an older one.
Every stage that writes files (numerics saving a trajectory, plots, the command line)
goes through here.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

from .errors import OutputError

__all__ = ["write_atomic", "write_atomic_with", "check_writable", "check_destination"]


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_atomic_with(path: str | Path, writer: Callable[[BinaryIO], object]) -> None:
    """Call ``writer(handle)`` on a temporary binary file beside ``path``, then move it over ``path``.

    Raises `OSError` (and removes the temporary file) when anything fails; ``path`` is
    then exactly as it was before.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    try:
        # mkstemp makes the file private (0600); give it the mode a plain open() would.
        os.chmod(tmp, path.stat().st_mode & 0o7777 if path.exists() else 0o666 & ~_umask())
        with os.fdopen(fd, "wb") as handle:
            writer(handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


def write_atomic(path: str | Path, data: str | bytes) -> None:
    """Write text (UTF-8) or bytes to ``path`` atomically."""
    payload = data.encode("utf-8") if isinstance(data, str) else data
    write_atomic_with(path, lambda handle: handle.write(payload))


def check_writable(path: str | Path) -> None:
    """Raise `OSError` unless a file can be written at ``path`` the way `write_atomic` writes it.

    A temporary file is created beside ``path`` and removed: the one test that holds for a
    read-only folder, a read-only file system and root alike, so that a long run is not
    spent before a write that fails.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    os.close(fd)
    os.unlink(tmp)


def check_destination(path: str | Path, *, name_fix: str, fix_suffix: str = "") -> None:
    """Raise `OutputError` unless ``path`` names a file in an existing, writable folder.

    One check for every stage that writes a file the user named (``simulate -o``, the command
    line's ``-o``), run before the work: ``name_fix`` is the fix when ``path`` is a folder,
    ``fix_suffix`` ends the other fixes (e.g. "; nothing was run").
    """
    path = Path(path)
    if path.is_dir():
        raise OutputError(f"`{path}` is a folder, not a file.", fix=name_fix)
    folder = path.parent
    if not folder.is_dir():
        raise OutputError(f"Cannot write `{path}`: the folder `{folder}` does not exist.",
                          fix="create the folder first, or write elsewhere" + fix_suffix)
    try:
        check_writable(path)
    except OSError as exc:
        raise OutputError(f"Cannot write `{path}`: the folder `{folder}` is not writable ({exc.strerror or exc}).",
                          fix="write elsewhere, or make the folder writable; nothing was run") from None
