"""Test configuration: Hypothesis profiles and the shared helper module.

The "ci" profile (the default) is deterministic: Hypothesis derives its examples
from each test's source, so every run of the suite draws the same states.  Select
another profile with ``HYPOTHESIS_PROFILE=dev`` (more, random examples).
"""

from __future__ import annotations

import os
import sys
import types
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci",
    derandomize=True,
    max_examples=30,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("dev", max_examples=300, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

# Make `import lagrangian_test_support` work from any test module (--import-mode=importlib
# does not put test directories on sys.path).
_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)


# -- markers -------------------------------------------------------------------------------------
# `slow`, `browser`, `tex`, `octave` and `docs` are written on the tests; `robots` is found here, from
# what a test uses, so that a new test comparing with Pinocchio is marked without anyone thinking of it.

#: Names whose use makes a test need the `robots` extra: the referees Pinocchio and MuJoCo, and the URDF
#: files of example-robot-data (`urdf_robots.robot_data_file`); `Peer` wraps a Pinocchio model.
ROBOT_NAMES = frozenset({"pin", "pinocchio", "mujoco", "example_robot_data", "robot_data_file", "Peer"})


def _names(code: types.CodeType) -> set[str]:
    """The global and attribute names and the string constants of a code object and of those nested in it."""
    names = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, str):
            names.add(const)
        elif isinstance(const, types.CodeType):
            names |= _names(const)
    return names


def _uses_robots(item: pytest.Item) -> bool:
    module = getattr(item, "module", None)
    if module is not None and any(isinstance(v, types.ModuleType) and v.__name__.split(".")[0] in ROBOT_NAMES
                                  for v in vars(module).values()):
        return True  # imported at module level (`pytest.importorskip("pinocchio")`): every test needs it
    functions = [getattr(item, "function", None)]
    fixtures = getattr(getattr(item, "_fixtureinfo", None), "name2fixturedefs", {})
    functions += [d.func for name in getattr(item, "fixturenames", ()) for d in fixtures.get(name, ())]
    return any(f is not None and hasattr(f, "__code__") and _names(f.__code__) & ROBOT_NAMES for f in functions)


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    for item in items:
        if _uses_robots(item):
            item.add_marker(pytest.mark.robots)
