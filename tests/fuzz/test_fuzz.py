"""The fuzz campaign, short: mutated example models through every stage and the CLI.

``tools/fuzz.py`` mutates the example files, runs each case in a forked process under a
memory cap (4 GiB) and a time cap, and classifies what happened; the long run is in
docs/fuzzing.md.  Here a fixed seed gives the same 300 cases on every run (about 35 s on two
idle cores), and none may end in a traceback, a hang, a memory blow-up, a crash or executed code.  (The time cap is generous
here: a loaded test machine must not turn a slow case into a "hang"; the long run uses its own.)
"""

from __future__ import annotations

import importlib.util
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "fuzz.py"
#: The short run's size (a few hundred cases, under 2 minutes); seed 1 (the long runs use others).
CASES = 300


def _tool():
    spec = importlib.util.spec_from_file_location("lagrangian_fuzz", TOOL)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
def test_short_campaign_finds_no_defect(tmp_path: Path) -> None:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), OPENBLAS_NUM_THREADS="1",
               LAGRANGIAN_CACHE=str(tmp_path / "cache"))
    # The Whipple bicycle is left to the long run: its report alone takes 10 s.
    run = subprocess.run([sys.executable, str(TOOL), "--cases", str(CASES), "--seed", "1", "--time-limit", "60",
                          "--jobs", "2", "--exclude", "whipple_bicycle", "--quiet", "--out", str(tmp_path / "out")],
                         capture_output=True, text=True, env=env, timeout=600)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    assert summary["cases"] == CASES
    bad = {k: summary["outcomes"][k] for k in ("traceback", "hang", "memory", "signal", "code")}
    assert bad == dict.fromkeys(bad, 0), (bad, summary["findings"], run.stdout[-3000:])
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    # The mutations reach every stage: some cases are refused, some run through.
    assert summary["outcomes"]["error"] > 0 and summary["outcomes"]["ok"] > 0
    stages = summary["stages"]
    for stage in ("load", "derive", "integrals", "verify", "compile", "simulate", "report"):
        assert stages.get(f"{stage}:ok", 0) > 0, stage
    assert stages.get("cli:ok", 0) == CASES


@pytest.mark.slow
def test_short_urdf_campaign_finds_no_defect(tmp_path: Path) -> None:
    # URDF files from strangers (examples/*.urdf mutated: values, joint types, entities, cycles, cuts).
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), OPENBLAS_NUM_THREADS="1",
               LAGRANGIAN_CACHE=str(tmp_path / "cache"))
    run = subprocess.run([sys.executable, str(TOOL), "--format", "urdf", "--cases", "40", "--seed", "1",
                          "--time-limit", "60", "--jobs", "2", "--quiet", "--out", str(tmp_path / "out")],
                         capture_output=True, text=True, env=env, timeout=600)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text(encoding="utf-8"))
    bad = {k: summary["outcomes"][k] for k in ("traceback", "hang", "memory", "signal", "code")}
    assert summary["cases"] == 40 and bad == dict.fromkeys(bad, 0), (bad, summary["findings"])
    assert run.returncode == 0 and summary["stages"].get("load:error", 0) > 0 and summary["stages"].get("simulate:ok")


def test_urdf_mutations_are_seeded_and_keep_the_suffix() -> None:
    import random

    fuzz = _tool()
    sources = {p.name: p.read_text(encoding="utf-8") for p in sorted((ROOT / "examples").glob("*.urdf"))}
    assert sources, "examples/*.urdf"
    first = [fuzz.make_case(random.Random(5), sources, "/c") for _ in range(5)]
    assert first == [fuzz.make_case(random.Random(5), sources, "/c") for _ in range(5)]
    assert all(name.endswith(".urdf") and text != sources[name] for name, text, _ in first)


def test_same_seed_same_cases() -> None:
    import random

    fuzz = _tool()
    sources = {p.stem: p.read_text(encoding="utf-8") for p in sorted((ROOT / "examples").glob("*.toml"))}
    first = [fuzz.make_case(random.Random(7), sources, "/c") for _ in range(3)]
    again = [fuzz.make_case(random.Random(7), sources, "/c") for _ in range(3)]
    assert first == again and first[0][1] != sources[first[0][0]]


def _hang(*_):
    time.sleep(60)


def _memory(*_):
    blocks = [bytearray(2**30) for _ in range(8)]  # 8 GiB: past the cap
    return blocks


def _crash(*_):
    os.kill(os.getpid(), signal.SIGSEGV)


def _code(*_):
    Path("CANARY").write_text("ran")  # the child runs in the case's folder


def _traceback(path, out, command, result_file):
    fuzz = sys.modules["lagrangian_fuzz_selftest"]
    fuzz._write_json(result_file, {"stages": [{"stage": "load", "outcome": "traceback", "message": "boom"}],
                                   "outcome": "traceback"})


@pytest.mark.slow
@pytest.mark.skipif(not hasattr(os, "fork"), reason="the harness forks")
@pytest.mark.parametrize("case, outcome", [(_hang, "hang"), (_memory, "memory"), (_crash, "signal"),
                                           (_code, "code"), (_traceback, "traceback")])
def test_the_harness_sees_each_kind_of_defect(tmp_path: Path, monkeypatch, case, outcome) -> None:
    fuzz = _tool()
    sys.modules["lagrangian_fuzz_selftest"] = fuzz
    monkeypatch.setattr(fuzz, "run_case", case)
    summary = fuzz.campaign(1, 0, tmp_path, time_limit=2.0, memory_gib=1.0, examples=["simple_pendulum"],
                            quiet=True, warm_up=False)
    assert summary["outcomes"][outcome] == 1, summary
    assert (tmp_path / summary["findings"][0]["file"]).exists()
