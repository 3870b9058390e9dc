"""Compile generated C once per source text and load it with `ctypes`.

A source is one translation unit, or several (`codegen._cparts`: a long model's functions in parts),
compiled in parallel, as many at a time as this process may use cores, and linked.

The shared library is cached under ``$LAGRANGIAN_CACHE`` (default
``~/.cache/lagrangian``), named by the SHA-256 of its source and the compiler command,
so a model compiled once loads in milliseconds afterwards, and a changed model or
compiler never reuses a stale library.  The compiler is ``$CC`` or the first of
``cc``, ``gcc``, ``clang`` on the PATH; without one, `compiler` returns None and the
caller falls back to SymEngine's evaluators and SciPy's integrators.

Loading a library runs its code, so the cache is trusted only as far as it is private:
the folder is created with mode 0700, and a folder or file owned by another user or
writable by group or others is not used (one line on stderr says why and how to fix it;
the run goes on with a private temporary cache, as it does when the folder cannot be
written).  Each library is written atomically (a temporary file in the same folder, then
`os.replace`), and its SHA-256 is written after it in a sidecar ``<library>.sha256``; a
library is loaded only when the sidecar matches it, so a truncated, empty or swapped file
is rebuilt instead of crashing the process (SIGBUS on a truncated library) or failing on
every later run.
"""

from __future__ import annotations

import atexit
import ctypes
import hashlib
import os
import shlex
import shutil
import stat
import subprocess
import sys
import tempfile
from collections.abc import Callable, Sequence
from functools import cache
from pathlib import Path
from typing import TypeVar

from ..errors import SimulationError

__all__ = ["build_shared", "cache_dir", "cached_library", "compile_library", "compiler", "load_verified"]

FLAGS = ("-O2", "-fPIC", "-shared", "-std=c99", "-fno-math-errno")
#: Added for the units after the first of a split build (`codegen._cparts`: the parts of long generated
#: functions, straight-line arithmetic): -O1 compiles them in about 60 % of -O2's time, and the
#: 30-joint arm's q̈ is no slower, M and F as fast (benchmarks/startup_and_compile.py).  The first
#: unit (the integrators' loops) keeps -O2.
PART_FLAGS = ("-O1",)
#: How long to wait between looks at the compilers running in parallel (s).
_POLL = 0.02


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
    """The configured cache folder: ``$LAGRANGIAN_CACHE``, else ``~/.cache/lagrangian``."""
    root = os.environ.get("LAGRANGIAN_CACHE")
    return Path(root) if root else Path.home() / ".cache" / "lagrangian"


_said: set[str] = set()


def _say_once(message: str) -> None:
    # One line on stderr, once per process: a rebuilt cache entry is worth knowing about,
    # not worth a traceback or a warning on every model.
    if message not in _said:
        _said.add(message)
        print(f"lagrangian: {message}", file=sys.stderr)


def _unsafe(path: Path) -> str | None:
    """Why ``path`` must not be trusted (another user's, or writable by group/others), or None."""
    info = path.stat()
    if info.st_uid != os.getuid():
        return f"`{path}` belongs to another user (uid {info.st_uid})"
    if info.st_mode & 0o022:
        return f"`{path}` is writable by group or others (mode {stat.S_IMODE(info.st_mode):o})"
    return None


def _private_folder(folder: Path) -> Path:
    """``folder``, created with mode 0700 if missing; `OSError` when it is not private or not writable."""
    folder.mkdir(mode=0o700, parents=True, exist_ok=True)
    reason = _unsafe(folder)
    if reason:
        raise PermissionError(reason)
    if not os.access(folder, os.W_OK | os.X_OK):
        raise PermissionError(f"`{folder}` is not writable")
    return folder


@cache
def _cache_for(configured: Path) -> Path:
    try:
        return _private_folder(configured)
    except OSError as exc:
        reason = str(exc) if isinstance(exc, PermissionError) and exc.errno is None else \
            f"`{configured}` cannot be used ({exc.strerror or exc})"
    fallback = Path(tempfile.mkdtemp(prefix="lagrangian-cache-"))  # mkdtemp: mode 0700, ours
    atexit.register(shutil.rmtree, fallback, ignore_errors=True)  # this run's builds only: not kept
    _say_once(f"not using the compile cache: {reason}; compiling into {fallback} for this run instead "
              f"(fix: `chmod 700` / `chown` that folder, or set LAGRANGIAN_CACHE to a private one)")
    return fallback


def _usable_cache() -> Path:
    """The cache folder this process may load from: the configured one when it is private, else a temporary one."""
    return _cache_for(cache_dir())


def _sidecar(library: Path) -> Path:
    return library.with_name(library.name + ".sha256")


def _digest(path: Path) -> str:
    with open(path, "rb") as handle:
        return hashlib.file_digest(handle, "sha256").hexdigest() if hasattr(hashlib, "file_digest") \
            else hashlib.sha256(handle.read()).hexdigest()


def _why_not_verified(library: Path) -> str | None:
    """Why the cached ``library`` must not be loaded (None: it is the file this cache built)."""
    reason = _unsafe(library)
    if reason:
        return reason
    try:
        recorded = _sidecar(library).read_text(encoding="ascii").strip()
    except (OSError, UnicodeDecodeError):
        return f"`{library.name}` has no checksum"
    if _unsafe(_sidecar(library)) or recorded != _digest(library):
        return f"`{library.name}` does not match its checksum (truncated or replaced)"
    return None


def compile_library(source: str | Sequence[str], key: str) -> ctypes.CDLL:
    """Compile ``source`` (or reuse the cached build) and load it.

    ``source`` is one translation unit, or several compiled in parallel and linked together.

    Raises
    ------
    SimulationError
        When there is no compiler or it rejects the source (with its first lines of output).
    """
    return load_verified(source, key, lambda path: ctypes.CDLL(str(path)))


_Loaded = TypeVar("_Loaded")


def load_verified(source: str | Sequence[str], key: str, load: Callable[[Path], _Loaded], *,
                  flags: Sequence[str] = (), name: str | None = None) -> _Loaded:
    """Run ``load(path)`` on the checked build of ``source``; on a load failure, rebuild once and load again.

    Parameters
    ----------
    source : str or sequence of str
        The C source, or its translation units.
    key : str
        The compile cache's key of the source.
    load : callable
        Loads the shared library at a path.
    flags : sequence of str, optional
        Extra compiler flags.
    name : str, optional
        A name for the library, in messages.

    Returns
    -------
    object
        What ``load`` returns.

    Raises
    ------
    SimulationError
        When there is no compiler, it rejects the source, or a fresh build does not load.
    """
    path = build_shared(source, key, flags=flags, name=name)
    try:
        return load(path)
    except (OSError, ImportError) as exc:
        _say_once(f"the cached `{path.name}` did not load ({exc}); rebuilding it")
    path = build_shared(source, key, flags=flags, name=name, rebuild=True)
    try:
        return load(path)
    except (OSError, ImportError) as exc:
        raise SimulationError(f"A freshly compiled library does not load: {exc}",
                              fix="report this as a bug of lagrangian, with the model file") from exc


def _command_id(command: Sequence[str], key: str, units: int) -> str:
    """The name of the library built by ``command`` from the ``units`` units whose key is ``key``."""
    # The number of units enters the name: a split build is another library than a one-unit build.
    shape = "" if units == 1 else f" units={units} {' '.join(PART_FLAGS)}"
    return hashlib.sha256((key + " ".join(command) + shape + sys.platform).encode()).hexdigest()[:32]


def cached_library(key: str, units: int) -> ctypes.CDLL | None:
    """The library `compile_library` built from ``units`` units of key ``key``, loaded, when the cache
    has it and it passes its checks; None otherwise (nothing is built: the caller generates the
    source and calls `compile_library`)."""
    cc = compiler()
    if cc is None:
        return None
    library = _usable_cache() / f"lg_{_command_id([*cc, *FLAGS], key, units)}.so"
    if not library.is_file() or _why_not_verified(library) is not None:
        return None
    try:
        return ctypes.CDLL(str(library))
    except OSError:
        return None


def build_shared(source: str | Sequence[str], key: str, *, flags: Sequence[str] = (), name: str | None = None,
                 rebuild: bool = False) -> Path:
    """The cached shared object built from ``source`` (built now if it is not there yet or fails its checksum).

    ``source``: one translation unit, or several (compiled in parallel, `jobs` at a time, and linked).

    ``flags`` are added to the compiler's; ``name`` is the file name inside the build's own
    folder (an extension module must be named after its module), default ``lg_<hash>.so``.
    ``rebuild`` builds anew even over a library that passes its checks.

    Raises
    ------
    SimulationError
        When there is no compiler or it rejects the source (with its first lines of output).
    """
    cc = compiler()
    if cc is None:
        raise SimulationError("No C compiler was found (looked for $CC, cc, gcc, clang).",
                              fix="install one (e.g. `apt-get install gcc`) or use backend='symengine'")
    units = [source] if isinstance(source, str) else list(source)
    command = [*cc, *FLAGS, *flags]
    command_id = _command_id(command, key, len(units))
    folder = _usable_cache()
    if name is not None:
        try:
            folder = _private_folder(folder / f"lg_{command_id}")
        except OSError as exc:
            # The build's own folder is someone else's: build in a fresh private one instead.
            _say_once(f"not using `{folder / f'lg_{command_id}'}` ({exc}); building elsewhere")
            folder = Path(tempfile.mkdtemp(prefix=f"lg_{command_id}_", dir=folder))
    library = folder / (f"lg_{command_id}.so" if name is None else name)
    if library.exists() and not rebuild:
        reason = _why_not_verified(library)
        if reason is None:
            return library
        _say_once(f"{reason}; rebuilding it")
    with tempfile.TemporaryDirectory(dir=folder) as tmp:
        built = Path(tmp) / "model.so"
        if len(units) == 1:
            c_file = Path(tmp) / "model.c"
            c_file.write_text(units[0], encoding="utf-8")
            _check(_run_all([[*command, "-o", str(built), str(c_file), "-lm"]], Path(tmp)))
        else:
            _build_units(command, units, Path(tmp), built)
        digest = Path(tmp) / "model.sha256"
        digest.write_text(_digest(built) + "\n", encoding="ascii")
        # Private whatever the umask: with umask 002 the compiler's output is group-writable,
        # and `_unsafe` would refuse it on every later run.
        os.chmod(built, 0o700)
        os.chmod(digest, 0o600)
        # Library first, its checksum second (both atomic renames in the same folder): a reader
        # that sees the new checksum sees the library it describes.  Concurrent builds of the
        # same key are harmless; at worst a mismatched pair makes the next run rebuild.
        os.replace(built, library)
        os.replace(digest, _sidecar(library))
    return library


def jobs() -> int:
    """How many compilers to run at once: the cores this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # not Linux
        return max(1, os.cpu_count() or 1)


def _build_units(command: Sequence[str], units: Sequence[str], tmp: Path, built: Path) -> None:
    """Compile each unit to an object file, `jobs` at a time, then link them into ``built``."""
    compile_only = [word for word in command if word != "-shared"]
    objects, commands = [], []
    for k, unit in enumerate(units):
        c_file, o_file = tmp / f"unit{k}.c", tmp / f"unit{k}.o"
        c_file.write_text(unit, encoding="utf-8")
        objects.append(str(o_file))
        commands.append([*compile_only, *(PART_FLAGS if k else ()), "-c", "-o", str(o_file), str(c_file)])
    _check(_run_all(commands, tmp))
    _check(_run_all([[*command, "-o", str(built), *objects, "-lm"]], tmp))


def _run_all(commands: Sequence[Sequence[str]], tmp: Path) -> tuple[int, str]:
    """Run ``commands``, `jobs` at a time; (0, "") when all succeed, else the first failure's (status, stderr).

    Each compiler's messages go to a file (a pipe per process could fill and block it); on an
    exception (Ctrl-C) the compilers still running are stopped before it goes on.
    """
    pending = list(enumerate(commands))
    running: dict[int, tuple[subprocess.Popen, Path]] = {}
    failure: tuple[int, str] = (0, "")
    try:
        while pending or running:
            while pending and len(running) < jobs() and not failure[0]:
                k, words = pending.pop(0)
                log = tmp / f"cc{k}.log"
                with open(log, "w", encoding="utf-8") as handle:
                    running[k] = (subprocess.Popen(list(words), stdout=handle, stderr=subprocess.STDOUT), log)
            if failure[0] and not running:
                break
            for k, (process, log) in list(running.items()):
                try:
                    status = process.wait(timeout=_POLL if len(running) > 1 else None)
                except subprocess.TimeoutExpired:
                    continue
                del running[k]
                if status != 0 and not failure[0]:
                    failure = (status, log.read_text(encoding="utf-8", errors="replace"))
    finally:
        for process, _ in running.values():
            process.kill()
            process.wait()
    return failure


def _check(result: tuple[int, str]) -> None:
    status, messages = result
    if status != 0:
        first = "\n".join(messages.splitlines()[:8])
        raise SimulationError(f"The C compiler rejected the generated code:\n{first}",
                              fix="report this as a bug of lagrangian, with the model file")
