"""Short simulations of the examples, shared by the plotting tests (each run once per session)."""

from __future__ import annotations

import functools

import pytest
from lagrangian_test_support import eom_of, example_names

from lagrangian.numerics import simulate

#: (t_end, n_out) of each example's run: long enough for a full nutation period of the top
#: (about 0.29 s) and a swing of the pendulums, short enough to stay fast.
RUNS = {"lagrange_top.toml": (1.0, 2001)}
DEFAULT_RUN = (0.5, 101)


@functools.cache
def _run(name: str, **initial: float):
    eom = eom_of(name)
    t_end, n_out = RUNS.get(name, DEFAULT_RUN)
    return eom, simulate(eom, t_end, n_out=n_out, initial=initial or None)


@pytest.fixture(scope="session")
def run():
    """``run(name, **initial)`` → (eom, trajectory) of an example file, cached."""
    return _run


@pytest.fixture(scope="session")
def examples() -> list[str]:
    return example_names()
