"""Compile generated C once per source text and load it with `ctypes`.

A source is one translation unit, or several (`codegen._cparts`: a long model's functions in parts),
compiled in parallel, as many at a time as this process may use cores, and linked.  The units of
parts can be handed to the compilers (`Compilers`) while the rest of the source is still being
generated: the compilers then work while Python writes.

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
import queue
import shlex
import shutil
import stat
import subprocess
import sys
import tempfile
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from types import TracebackType
from typing import TypeVar

from ..codegen import COLD_UNIT
from ..errors import SimulationError

__all__ = ["Compilers", "build_shared", "cache_dir", "cached_library", "compile_library", "compiler",
           "load_verified", "unit_flags"]

FLAGS = ("-O2", "-fPIC", "-shared", "-std=c99", "-fno-math-errno")
#: Added for the units after the first of a split build (`codegen._cparts`: the parts of long generated
#: functions, straight-line arithmetic): -O1 compiles them in about 60 % of -O2's time, and the
#: 30-joint arm's q̈ is no slower, M and F as fast (benchmarks/startup_and_compile.py).  The first
#: unit (the integrators' loops) keeps -O2.
PART_FLAGS = ("-O1",)
#: Instead, for the units of cold parts (`codegen.COLD_UNIT`: the monitors, run once per output sample,
#: and the hoisted constants, once per parameter set): -Og compiles them in about 60 % of -O1's time.
#: With SSE2 arithmetic and no contraction (``-std=c99``) the numbers are the same at every level.
COLD_FLAGS = ("-Og",)


def unit_flags(unit: str, *, part: bool) -> tuple[str, ...]:
    """What is added to `FLAGS` for ``unit`` of a split build: nothing for the main unit (the first), `PART_FLAGS`
    for a part's, `COLD_FLAGS` for a cold part's."""
    if not part:
        return ()
    return COLD_FLAGS if unit.startswith(COLD_UNIT) else PART_FLAGS


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


def compile_library(source: str | Sequence[str], key: str, *, compilers: Compilers | None = None) -> ctypes.CDLL:
    """Compile ``source`` (or reuse the cached build) and load it.

    ``source`` is one translation unit, or several compiled in parallel and linked together;
    ``compilers`` may already be compiling some of them (`Compilers.part`).

    Raises
    ------
    SimulationError
        When there is no compiler or it rejects the source (with its first lines of output).
    """
    return load_verified(source, key, lambda path: ctypes.CDLL(str(path)), compilers=compilers)


_Loaded = TypeVar("_Loaded")


def load_verified(source: str | Sequence[str], key: str, load: Callable[[Path], _Loaded], *,
                  flags: Sequence[str] = (), name: str | None = None, compilers: Compilers | None = None) -> _Loaded:
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
    compilers : Compilers, optional
        The compilers that may already be at work on some of the units (`Compilers.part`).

    Returns
    -------
    object
        What ``load`` returns.

    Raises
    ------
    SimulationError
        When there is no compiler, it rejects the source, or a fresh build does not load.
    """
    path = build_shared(source, key, flags=flags, name=name, compilers=compilers)
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
    shape = "" if units == 1 else f" units={units} {' '.join(PART_FLAGS)} cold {' '.join(COLD_FLAGS)}"
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
                 rebuild: bool = False, compilers: Compilers | None = None) -> Path:
    """The cached shared object built from ``source`` (built now if it is not there yet or fails its checksum).

    ``source``: one translation unit, or several (compiled in parallel, `jobs` at a time, and linked).

    ``flags`` are added to the compiler's; ``name`` is the file name inside the build's own
    folder (an extension module must be named after its module), default ``lg_<hash>.so``.
    ``rebuild`` builds anew even over a library that passes its checks.  ``compilers``: the
    compilers that may already be at work on some units (`Compilers.part`); their objects are used.

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
            _check(_run(Path(tmp), [*command, "-o", str(built), str(c_file), "-lm"], "model"))
        elif compilers is not None and compilers.flags == tuple(flags):
            _link(command, compilers, units, built)
        else:
            with Compilers(flags) as own:
                _link(command, own, units, built)
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


def _run(folder: Path, words: Sequence[str], name: str) -> tuple[int, str]:
    """Run one compiler command; (0, "") on success, else (status, its messages)."""
    log = folder / f"{name}.log"
    with open(log, "w", encoding="utf-8") as handle:  # a file, not a pipe: a full pipe would block it
        status = subprocess.run(list(words), stdout=handle, stderr=subprocess.STDOUT, check=False).returncode
    return (0, "") if status == 0 else (status, log.read_text(encoding="utf-8", errors="replace"))


class Compilers:
    """The compilers of one split build, `jobs` at a time, each unit started as soon as it is handed over.

    A long model's parts (`codegen._cparts`) are handed over while the rest of its C is being
    generated (`part`, given to `codegen.generate_c` as ``on_unit``), so that the compilers work
    while Python writes: for the 30-joint arm, about 1.5 s of generation beside some 6.5 s of compiling.
    Each compiler is run by a worker thread, which waits on it without holding the interpreter.
    `build_shared` then asks for every unit (`object_of`: the one already compiled, or compiled
    now) and links.  The main unit, the last written and among the longest to compile (the
    integrators, at -O2), goes before the parts still waiting, so that the build does not end on it alone.
    Leaving the ``with`` block stops the compilers still running and removes their files, whether
    the build was linked, found in the cache, or abandoned on an error.

    Parameters
    ----------
    flags : added to the compiler's command, as `build_shared`'s ``flags``.
    """

    def __init__(self, flags: Sequence[str] = ()) -> None:
        self.flags = tuple(flags)
        self._cc = compiler()
        self._folder: Path | None = None
        self._objects: dict[tuple[str, bool], Future[tuple[int, str, Path]]] = {}
        # (rank, order, job): the main unit (rank 0) before the parts (rank 1), each rank in order.
        self._waiting: queue.PriorityQueue[tuple[int, int, _Job | None]] = queue.PriorityQueue()
        self._workers: list[threading.Thread] = []
        self._running: set[subprocess.Popen] = set()
        self._lock = threading.Lock()
        self._closed = False

    def __enter__(self) -> Compilers:
        return self

    def __exit__(self, kind: type[BaseException] | None, value: BaseException | None,
                 traceback: TracebackType | None) -> None:
        self.close()

    def part(self, unit: str) -> None:
        """Start compiling ``unit``, a unit of a part, as soon as a core is free (nothing without a compiler:
        the build then says there is none)."""
        if self._cc is not None:
            self.object_of(unit, part=True)

    def object_of(self, unit: str, *, part: bool) -> Future[tuple[int, str, Path]]:
        """The compilation of ``unit`` to an object file: (status, messages, object file), when done."""
        key = (unit, part)
        if key not in self._objects:
            if self._cc is None or self._closed:
                raise SimulationError("The compilers of this build are not available (no compiler, or closed).",
                                      fix="report this as a bug of lagrangian, with the model file")
            if self._folder is None:
                self._folder = Path(tempfile.mkdtemp(prefix="lagrangian-units-"))
            k = len(self._objects)
            c_file, o_file = self._folder / f"unit{k}.c", self._folder / f"unit{k}.o"
            c_file.write_text(unit, encoding="utf-8")
            words = [*self._cc, *(w for w in FLAGS if w != "-shared"), *self.flags, *unit_flags(unit, part=part),
                     "-c", "-o", str(o_file), str(c_file)]
            future: Future[tuple[int, str, Path]] = Future()
            self._objects[key] = future
            self._waiting.put((int(part), k, _Job(words, o_file, f"cc{k}", future)))
            if len(self._workers) < jobs():
                worker = threading.Thread(target=self._work, name=f"lagrangian-cc{len(self._workers)}", daemon=True)
                self._workers.append(worker)
                worker.start()
        return self._objects[key]

    def _work(self) -> None:
        """A worker: the waiting jobs, best rank first, until `close` sends it ``None``."""
        while True:
            job = self._waiting.get()[2]
            if job is None:
                return
            if job.future.set_running_or_notify_cancel():
                try:
                    job.future.set_result(self._compile(job))
                except BaseException as exc:  # noqa: BLE001 - re-raised by the build from `future.result()`, not a hang
                    job.future.set_exception(exc)

    def _compile(self, job: _Job) -> tuple[int, str, Path]:
        log = job.o_file.parent / f"{job.name}.log"
        with open(log, "w", encoding="utf-8") as handle:  # a file, not a pipe: a full pipe would block it
            with self._lock:
                if self._closed:
                    return 1, "the build was stopped", job.o_file
                try:
                    process = subprocess.Popen(job.words, stdout=handle, stderr=subprocess.STDOUT)
                except OSError as exc:  # the compiler cannot be started: the build's error says why
                    return 127, f"{job.words[0]}: {exc}", job.o_file
                self._running.add(process)
            try:
                status = process.wait()
            finally:
                with self._lock:
                    self._running.discard(process)
        return status, "" if status == 0 else log.read_text(encoding="utf-8", errors="replace"), job.o_file

    def close(self) -> None:
        """Stop the compilers still running, end the workers, and remove the objects' folder."""
        with self._lock:
            self._closed = True
            for process in self._running:
                process.kill()
        for k, _ in enumerate(self._workers):
            self._waiting.put((-1, k, None))  # before any job still waiting
        for worker in self._workers:
            worker.join()
        for future in self._objects.values():
            future.cancel()  # those never started
        if self._folder is not None:
            shutil.rmtree(self._folder, ignore_errors=True)


@dataclass(frozen=True)
class _Job:
    """One unit to compile: the command, the object file it writes, its log's name, and its future."""

    words: list[str]
    o_file: Path
    name: str
    future: Future[tuple[int, str, Path]]


def _link(command: Sequence[str], compilers: Compilers, units: Sequence[str], built: Path) -> None:
    """Every unit compiled (the parts' units perhaps already), then linked into ``built``."""
    compiled = [compilers.object_of(unit, part=k > 0) for k, unit in enumerate(units)]
    objects = []
    for future in compiled:
        status, messages, o_file = future.result()
        _check((status, messages))
        objects.append(str(o_file))
    _check(_run(built.parent, [*command, "-o", str(built), *objects, "-lm"], "link"))


def _check(result: tuple[int, str]) -> None:
    status, messages = result
    if status != 0:
        first = "\n".join(messages.splitlines()[:8])
        raise SimulationError(f"The C compiler rejected the generated code:\n{first}",
                              fix="report this as a bug of lagrangian, with the model file")
