"""The command line's file writing: atomic, and an `OSError` becomes an `OutputError`."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

from .._atomic import check_destination, write_atomic, write_atomic_with
from ..errors import OutputError

__all__ = ["write_atomic", "write_atomic_with", "write_output", "check_output"]


def write_output(path: str | Path, data: str | bytes | Callable[[BinaryIO], None]) -> None:
    """`write_atomic` for the command line: an `OSError` becomes an `OutputError` (exit code 3)."""
    try:
        if callable(data):
            write_atomic_with(path, data)
        else:
            write_atomic(path, data)
    except OSError as exc:
        raise OutputError(f"Cannot write `{path}`: {exc.strerror or exc}.",
                          fix="check that the folder exists and is writable; the old file, if any, is unchanged") from exc


def check_output(path: str | Path) -> None:
    """Before a command runs: ``-o FILE`` must name a file in an existing, writable folder (`OutputError`)."""
    check_destination(path, name_fix="give a file name after -o", fix_suffix="; nothing was run")
