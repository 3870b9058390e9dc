"""The compilers of a split build: units compiled as they are generated, once each, and stopped on leaving."""

from __future__ import annotations

import os
import time

import numpy as np
import pytest

import lagrangian
from lagrangian.codegen import COLD_UNIT, _cparts
from lagrangian.errors import SimulationError
from lagrangian.model.zoo import serial_arm
from lagrangian.numerics import _compile, _system, compile_system


@pytest.fixture
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(tmp_path / "cache"))
    _compile._cache_for.cache_clear()
    yield tmp_path / "cache"
    _compile._cache_for.cache_clear()


def _commands(monkeypatch) -> list[list[str]]:
    """Every compiler command the build starts (``subprocess.run`` too starts it through ``Popen``)."""
    seen: list[list[str]] = []
    popen = _compile.subprocess.Popen

    def recording_popen(words, *args, **kwargs):
        seen.append(list(words))
        return popen(words, *args, **kwargs)

    monkeypatch.setattr(_compile.subprocess, "Popen", recording_popen)
    return seen


@pytest.mark.slow
def test_each_unit_is_compiled_once_the_parts_while_they_are_generated(private_cache, monkeypatch):
    monkeypatch.setattr(_cparts, "MAX_STATEMENTS", 80)
    eom = lagrangian.derive(serial_arm(4))
    seen = _commands(monkeypatch)
    handed: list[tuple[str, int]] = []
    part = _compile.Compilers.part

    def watched(self, unit):
        handed.append((unit, len(seen)))  # how many compilers had started when this part came
        part(self, unit)

    monkeypatch.setattr(_compile.Compilers, "part", watched)
    sought: list[int] = []
    find = _system.tree_integrals

    def integrals(*args, **kwargs):
        sought.append(len(handed))  # how many parts were compiling when the integrals were sought
        return find(*args, **kwargs)

    monkeypatch.setattr(_system, "tree_integrals", integrals)
    system = compile_system(eom)
    # M and F's parts went to the compilers before the first integrals were sought (lg_monitors needs them).
    assert sought and sought[0] > 0
    units = system.generated.units
    compiles = [words for words in seen if "-c" in words]
    links = [words for words in seen if "-c" not in words and any(os.path.basename(w) == "unit0.o" for w in words)]
    assert len(compiles) == len(units) and len(links) == 1
    # Every part was handed over as it was written, in order, and compilers started before the last one came.
    assert [unit for unit, _ in handed] == list(units[1:])
    assert handed[-1][1] > 0
    # The main unit at -O2, the parts at -O1, the cold ones (the monitors, the constants) at -Og.
    levels = [[w for w in words if w.startswith("-O")][-1] for words in compiles]
    cold = sum(u.startswith(COLD_UNIT) for u in units)
    assert 0 < cold < len(units) - 1
    assert levels.count("-O2") == 1  # the main unit
    assert levels.count("-Og") == cold and levels.count("-O1") == len(units) - 1 - cold
    y = np.random.default_rng(0).uniform(-1, 1, 8)
    assert np.all(np.isfinite(system.monitor_values(0.0, y, system.parameter_vector())))


def test_the_main_unit_goes_before_the_parts_still_waiting(tmp_path, monkeypatch):
    order = tmp_path / "order"
    fake = tmp_path / "fake-cc"  # records which unit it compiles, slowly enough for the others to wait
    fake.write_text(f'#!/bin/sh\nfor a; do case "$a" in *.c) head -n 1 "$a" >> {order};; esac; done\nsleep 0.2\n')
    fake.chmod(0o755)
    monkeypatch.setenv("CC", str(fake))
    monkeypatch.setattr(_compile, "jobs", lambda: 1)
    with _compile.Compilers() as compilers:
        compilers.part("part 0\n")
        deadline = time.monotonic() + 30
        while not order.exists() and time.monotonic() < deadline:  # the one compiler is busy with it
            time.sleep(0.01)
        for k in (1, 2):
            compilers.part(f"part {k}\n")
        main = compilers.object_of("main\n", part=False)
        assert main.result()[0] == 0
        assert all(compilers.object_of(f"part {k}\n", part=True).result()[0] == 0 for k in range(3))
    assert order.read_text().split("\n")[:4] == ["part 0", "main", "part 1", "part 2"]


def test_a_rejected_part_is_an_error_naming_the_compilers_message(private_cache):
    with _compile.Compilers() as compilers:
        compilers.part("int lg_fine(void) { return 1; }\n")
        compilers.part("this is not C at all\n")
        with pytest.raises(SimulationError, match="rejected the generated code") as caught:
            _compile.compile_library(["int lg_main(void) { return 0; }\n", "int lg_fine(void) { return 1; }\n",
                                      "this is not C at all\n"], "rejected-part", compilers=compilers)
    assert "error" in str(caught.value)


def test_leaving_the_block_stops_the_compilers_still_running(tmp_path, monkeypatch):
    slow = tmp_path / "slow-cc"
    slow.write_text("#!/bin/sh\nsleep 60\n")
    slow.chmod(0o755)
    monkeypatch.setenv("CC", str(slow))
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        with _compile.Compilers() as compilers:
            for k in range(2 * _compile.jobs() + 1):
                compilers.part(f"int lg_part{k};\n")
            time.sleep(0.3)
            folder = compilers._folder
            running = list(compilers._running)
            assert running and folder is not None and folder.is_dir()
            raise KeyboardInterrupt  # Ctrl-C while the model is being generated
    assert time.perf_counter() - start < 30
    assert all(process.poll() is not None for process in running)  # stopped, not left to finish
    assert not folder.exists()


def test_a_fault_in_a_compiler_thread_reaches_the_build_instead_of_hanging_it(private_cache, monkeypatch):
    def broken(self, job):
        raise RuntimeError("a fault of the build's own code")

    monkeypatch.setattr(_compile.Compilers, "_compile", broken)
    with _compile.Compilers() as compilers:
        compilers.part("int lg_part;\n")
        with pytest.raises(RuntimeError, match="own code"):
            compilers.object_of("int lg_part;\n", part=True).result(timeout=60)
