"""Compile generated C once per source text and load it with `ctypes`.

The shared library is cached under ``$LAGRANGIAN_CACHE`` (default
``~/.cache/lagrangian``), named by the SHA-256 of its source and the compiler command,
so a model compiled once loads in milliseconds afterwards, and a changed model or
compiler never reuses a stale library.  The compiler is ``$CC`` or the first of
``cc``, ``gcc``, ``clang`` on the PATH; without one, `compiler` returns None and the
caller falls back to SymEngine's evaluators and SciPy's integrators.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from ..errors import SimulationError

__all__ = ["compiler", "compile_library", "build_shared", "cache_dir"]

FLAGS = ("-O2", "-fPIC", "-shared", "-std=c99", "-fno-math-errno")


def compiler() -> list[str] | None:
    """The C compiler command, or None when there is none."""
    cc = os.environ.get("CC")
    if cc:
        words = shlex.split(cc)
        return words if shutil.which(words[0]) else None
    for name in ("cc", "gcc", "clang"):
        path = shutil.which(name)
        if path:
            return [path]
    return None


def cache_dir() -> Path:
    root = os.environ.get("LAGRANGIAN_CACHE")
    return Path(root) if root else Path.home() / ".cache" / "lagrangian"


def compile_library(source: str, key: str) -> ctypes.CDLL:
    """Compile ``source`` (or reuse the cached build) and load it.

    Raises
    ------
    SimulationError
        When there is no compiler or it rejects the source (with its first lines of output).
    """
    return ctypes.CDLL(str(build_shared(source, key)))


def build_shared(source: str, key: str, *, flags: Sequence[str] = (), name: str | None = None) -> Path:
    """The cached shared object built from ``source`` (built now if it is not there yet).

    ``flags`` are added to the compiler's; ``name`` is the file name inside the build's own
    folder (an extension module must be named after its module), default ``lg_<hash>.so``.

    Raises
    ------
    SimulationError
        When there is no compiler or it rejects the source (with its first lines of output).
    """
    cc = compiler()
    if cc is None:
        raise SimulationError("No C compiler was found (looked for $CC, cc, gcc, clang).",
                              fix="install one (e.g. `apt-get install gcc`) or use backend='symengine'")
    command = [*cc, *FLAGS, *flags]
    command_id = hashlib.sha256((key + " ".join(command) + sys.platform).encode()).hexdigest()[:32]
    folder = cache_dir()
    library = folder / f"lg_{command_id}.so" if name is None else folder / f"lg_{command_id}" / name
    if not library.exists():
        library.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=folder) as tmp:
            c_file = Path(tmp) / "model.c"
            c_file.write_text(source, encoding="utf-8")
            built = Path(tmp) / "model.so"
            result = subprocess.run([*command, "-o", str(built), str(c_file), "-lm"],
                                    capture_output=True, text=True)
            if result.returncode != 0:
                first = "\n".join(result.stderr.splitlines()[:8])
                raise SimulationError(f"The C compiler rejected the generated code:\n{first}",
                                      fix="report this as a bug of lagrangian, with the model file")
            os.replace(built, library)  # atomic: a concurrent build of the same key is harmless
    return library
