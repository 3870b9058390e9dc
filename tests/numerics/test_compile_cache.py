"""The compile cache loads only what it built itself.

Loading a shared library runs its code, and a truncated one can crash the process
(SIGBUS), so each reproducer runs in a subprocess over a copy of one primed cache: the
run must still work, say once on stderr what it rebuilt or refused, and never load the
bad file.
"""

import hashlib
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from lagrangian.numerics import _compile

SRC = str(Path(_compile.__file__).resolve().parents[2])

RUN = textwrap.dedent("""
    import numpy as np
    import lagrangian
    from lagrangian.model.zoo import planar_chain
    from lagrangian.numerics import compile_system
    system = compile_system(lagrangian.derive(planar_chain(1)))
    y, out = np.full(2, 0.3), np.empty(2)
    assert system.rhs_c(0.0, y, system.parameter_vector(), out) == 0
    print("fast" if "rhs_c" in vars(system) else "ctypes")
""")


def run(cache: Path, umask: int = 0o022, **env: str) -> subprocess.CompletedProcess:
    environ = {**os.environ, "LAGRANGIAN_CACHE": str(cache), "PYTHONPATH": SRC, **env}
    return subprocess.run([sys.executable, "-c", RUN], capture_output=True, text=True, env=environ, timeout=300,
                          umask=umask)


@pytest.fixture(scope="module")
def primed(tmp_path_factory) -> Path:
    cache = tmp_path_factory.mktemp("primed") / "cache"
    result = run(cache)
    assert result.returncode == 0 and result.stdout.strip() == "fast", result.stderr
    assert result.stderr == ""
    return cache


@pytest.fixture
def cache(primed, tmp_path) -> Path:
    copy = tmp_path / "cache"
    shutil.copytree(primed, copy)
    return copy


def model_library(cache: Path) -> Path:
    (library,) = cache.glob("lg_*.so")
    return library


def fastcall_module(cache: Path) -> Path:
    (module,) = cache.glob("lg_*/lagrangian_fastcall*.so")
    return module


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def assert_rebuilt(cache: Path, library: Path, result: subprocess.CompletedProcess, words: str) -> None:
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "fast"
    assert "Traceback" not in result.stderr
    assert words in result.stderr and result.stderr.count("\n") == 1, result.stderr
    assert library.stat().st_size > 5000
    assert (library.parent / (library.name + ".sha256")).read_text().strip() == sha256(library)


@pytest.mark.slow
def test_the_cache_folder_is_private_and_every_library_has_its_checksum(primed):
    assert primed.stat().st_mode & 0o777 == 0o700
    for library in (model_library(primed), fastcall_module(primed)):
        assert (library.parent / (library.name + ".sha256")).read_text().strip() == sha256(library)


@pytest.mark.slow
def test_a_warm_cache_is_used_silently(cache):
    before = model_library(cache).stat().st_mtime_ns
    result = run(cache)
    assert result.returncode == 0 and result.stderr == ""
    assert model_library(cache).stat().st_mtime_ns == before


@pytest.mark.slow
def test_a_group_writable_umask_does_not_make_every_run_rebuild(tmp_path):
    # With umask 002 (usual where each user has their own group) the compiler's output is
    # group-writable: the cache must store it private, or every later run would refuse it.
    cache = tmp_path / "cache"
    first = run(cache, umask=0o002)
    assert first.returncode == 0 and first.stderr == "", first.stderr
    second = run(cache, umask=0o002)
    assert second.returncode == 0 and second.stderr == "", second.stderr
    assert model_library(cache).stat().st_mode & 0o077 == 0


@pytest.mark.slow
def test_a_zero_byte_library_is_rebuilt(cache):
    library = model_library(cache)
    library.write_bytes(b"")
    assert_rebuilt(cache, library, run(cache), "does not match its checksum")


@pytest.mark.slow
def test_a_truncated_library_is_rebuilt_not_loaded(cache):
    library = model_library(cache)
    library.write_bytes(library.read_bytes()[:5000])
    assert_rebuilt(cache, library, run(cache), "does not match its checksum")


@pytest.mark.slow
def test_the_checksum_rejects_a_truncated_library_before_anything_loads_it(cache, monkeypatch):
    # In-process: `build_shared` only checks and builds, it never loads, so the truncated
    # file cannot reach dlopen here; the path it returns is a fresh, matching build.
    library = model_library(cache)
    library.write_bytes(library.read_bytes()[:5000])
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(cache))
    _compile._cache_for.cache_clear()
    assert "does not match its checksum" in _compile._why_not_verified(library)
    loaded = []
    monkeypatch.setattr(_compile.ctypes, "CDLL", lambda path: loaded.append(Path(path).read_bytes()) or path)
    import lagrangian
    from lagrangian.codegen import generate_c
    from lagrangian.model.zoo import planar_chain

    generated = generate_c(lagrangian.derive(planar_chain(1)), (), ())
    _compile.compile_library(generated.source, generated.key)
    _compile._cache_for.cache_clear()
    assert len(loaded) == 1 and len(loaded[0]) > 5000


@pytest.mark.slow
def test_a_library_without_checksum_is_rebuilt(cache):
    library = model_library(cache)
    (library.parent / (library.name + ".sha256")).unlink()
    assert_rebuilt(cache, library, run(cache), "has no checksum")


@pytest.mark.slow
def test_a_library_that_passes_its_checksum_but_does_not_load_is_rebuilt(cache):
    library = model_library(cache)
    library.write_bytes(b"not an ELF file")
    (library.parent / (library.name + ".sha256")).write_text(sha256(library))
    assert_rebuilt(cache, library, run(cache), "did not load")


@pytest.mark.slow
def test_a_truncated_fastcall_module_is_rebuilt(cache):
    module = fastcall_module(cache)
    module.write_bytes(module.read_bytes()[: module.stat().st_size // 2])
    assert_rebuilt(cache, module, run(cache), "does not match its checksum")


PLANTED = r"""
#include <stdio.h>
__attribute__((constructor)) static void planted(void) {
    FILE *f = fopen("%s", "w");
    if (f) { fputs("ran", f); fclose(f); }
}
"""


def plant(library: Path, marker: Path, tmp_path: Path) -> None:
    """Put a library whose constructor writes ``marker`` under ``library``'s name, with a matching checksum."""
    c_file = tmp_path / "planted.c"
    c_file.write_text(PLANTED % marker)
    subprocess.run([*_compile.compiler(), "-shared", "-fPIC", "-o", str(library), str(c_file)], check=True)
    (library.parent / (library.name + ".sha256")).write_text(sha256(library))


@pytest.mark.slow
@pytest.mark.parametrize("which", [model_library, fastcall_module], ids=["model", "fastcall"])
def test_a_library_planted_in_a_group_writable_cache_is_never_loaded(cache, tmp_path, which):
    marker = tmp_path / "constructor-ran"
    plant(which(cache), marker, tmp_path)
    cache.chmod(0o775)
    result = run(cache)
    assert result.returncode == 0 and result.stdout.strip() == "fast", result.stderr
    assert not marker.exists(), "the planted library was loaded"
    assert "writable by group or others" in result.stderr and "LAGRANGIAN_CACHE" in result.stderr
    assert "Traceback" not in result.stderr and result.stderr.count("\n") == 1


@pytest.mark.slow
@pytest.mark.skipif(os.getuid() != 0, reason="giving a file to another user needs root")
def test_a_library_owned_by_another_user_is_never_loaded(cache, tmp_path):
    marker = tmp_path / "constructor-ran"
    library = model_library(cache)
    plant(library, marker, tmp_path)
    os.chown(library, 12345, 12345)
    result = run(cache)
    assert result.returncode == 0 and result.stdout.strip() == "fast", result.stderr
    assert not marker.exists(), "the planted library was loaded"
    assert "belongs to another user" in result.stderr


@pytest.mark.slow
@pytest.mark.parametrize("where", ["under-a-file", "read-only", "home-under-a-file"])
def test_an_unwritable_cache_falls_back_to_a_private_temporary_one(tmp_path, where):
    env = {}
    if where.endswith("under-a-file"):
        (tmp_path / "file").write_text("")
        cache = tmp_path / "file" / "cache"
        if where == "home-under-a-file":  # the default ~/.cache/lagrangian, with no LAGRANGIAN_CACHE
            env = {"HOME": str(cache), "LAGRANGIAN_CACHE": ""}
    else:
        if os.getuid() == 0:
            pytest.skip("root writes into read-only folders")
        cache = tmp_path / "ro"
        cache.mkdir(mode=0o500)
    result = run(cache, **env)
    assert result.returncode == 0 and result.stdout.strip() == "fast", result.stderr
    assert "not using the compile cache" in result.stderr and "Traceback" not in result.stderr
