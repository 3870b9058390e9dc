"""Shared helpers for the test suite: the example files, their derivations, safe state
domains and numeric evaluation of engine expressions.

`tests/conftest.py` puts this directory on ``sys.path`` so test modules can
``import lagrangian_test_support``.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import re
import signal
import subprocess
import threading
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import symengine as se

import lagrangian

EXAMPLES_DIR = Path(__file__).resolve().parents[1] / "examples"

#: Default range of a coordinate and of a rate in random states.
DEFAULT_Q = (-2.5, 2.5)
DEFAULT_QD = (-3.0, 3.0)

#: Ranges that keep each example away from its coordinate singularities (Euler angles
#: at theta = 0 or pi) and inside the domain where its closed forms hold (the cart's
#: spring keeps a positive length while x > -l0).
DOMAINS: dict[str, dict[str, tuple[float, float]]] = {
    "lagrange_top.toml": {"theta": (0.3, 2.8), "phi_dot": (-60.0, 60.0)},
    "spherical_pendulum.toml": {"theta": (0.3, 2.8)},
    "cart_pendulum.toml": {"x": (-0.3, 0.6)},
    # The rope's gap l − √(x² + y²) is not differentiable at O.
    "slack_rope_pendulum.toml": {"x": (0.2, 1.2), "y": (-1.2, -0.2)},
    "top_reaction.toml": {"theta": (0.3, 2.8), "phi_dot": (-60.0, 60.0)},
    # The exact Coulomb law T = −f N v_s/|v_s| is set-valued at v_s = 0 (sticking is the stuck
    # model's business, tests/dynamics/test_stick_slip.py): sliding states only.
    "block_on_incline.toml": {"x_dot": (0.05, 3.0)},
    # The course's equations of a free body, in its Euler angles: regular away from θ = 0 and π.
    "tumbling_body.toml": {"theta": (0.3, 2.8)},
}


def example_names() -> list[str]:
    """File names of every example model, sorted."""
    return sorted(p.name for p in EXAMPLES_DIR.glob("*.toml"))


def example_text(name: str) -> str:
    return (EXAMPLES_DIR / name).read_text(encoding="utf-8")


def mutated_example(folder: Path, name: str, old: str, new: str) -> Path:
    """examples/``name`` with its one ``old`` replaced by ``new``, written under ``folder`` (a fuzz case's
    reproducer: the tests check that ``old`` is still in the example, so that a reworded example fails
    loudly rather than testing nothing)."""
    text = example_text(name)
    assert text.count(old) == 1, f"{old!r} is not once in examples/{name}"
    path = folder / f"mutated_{name}"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


@functools.cache
def eom_of(name: str) -> lagrangian.EquationsOfMotion:
    """The engine's derivation for one example file (cached)."""
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / name))


@functools.cache
def integrals_of(name: str) -> tuple[lagrangian.FirstIntegral, ...]:
    return lagrangian.first_integrals(eom_of(name))


def domain(name: str, symbol: str) -> tuple[float, float]:
    spec = DOMAINS.get(name, {})
    if symbol in spec:
        return spec[symbol]
    return DEFAULT_QD if symbol.endswith("_dot") else DEFAULT_Q


def random_states(name: str, coordinates: Sequence[str], count: int, seed: int) -> list[dict[str, float]]:
    """``count`` states {q: value, q_dot: value} inside the example's safe domain."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        state = {}
        for c in coordinates:
            for s in (c, c + "_dot"):
                lo, hi = domain(name, s)
                state[s] = float(rng.uniform(lo, hi))
        out.append(state)
    return out


def parameter_values(eom: lagrangian.EquationsOfMotion) -> dict[se.Symbol, float]:
    values = {}
    for p in eom.model.parameters:
        assert p.value is not None, f"parameter {p.name} of {eom.model.name} has no value"
        values[se.Symbol(p.name)] = p.value
    return values


def state_symbols(eom: lagrangian.EquationsOfMotion) -> list[se.Symbol]:
    """Arguments of every numeric function here: q, q̇, q̈ (in coordinate order), t, then the
    multipliers λ_k of the complementary constraints (none for most models)."""
    return [*eom.q, *eom.qd, *eom.qdd, eom.t, *eom.multipliers]


class Numeric:
    """Numeric versions of engine expressions, parameters replaced by their values.

    Call with a state dict {name: value}; absent q̈, t and multipliers λ default to 0.
    """

    def __init__(self, eom: lagrangian.EquationsOfMotion, exprs: Sequence[se.Basic]) -> None:
        self.names = [str(s) for s in state_symbols(eom)]
        values = parameter_values(eom)
        subbed = [se.sympify(e).subs(values) for e in exprs]
        leftover = set().union(*(e.free_symbols for e in subbed)) - set(state_symbols(eom)) if subbed else set()
        assert not leftover, f"symbols without values: {leftover}"
        self.n = len(subbed)
        self._f = se.Lambdify(state_symbols(eom), subbed, real=True) if subbed else None

    def __call__(self, state: dict[str, float]) -> np.ndarray:
        if self._f is None:
            return np.zeros(0)
        args = [state.get(name, 0.0) for name in self.names]
        return np.asarray(self._f(args), dtype=float).reshape(self.n)


@functools.cache
def numeric_eom(name: str) -> tuple[Numeric, Numeric]:
    """(M, F) of an example as numeric functions (M flattened row by row)."""
    eom = eom_of(name)
    return Numeric(eom, [e for row in eom.M for e in row]), Numeric(eom, eom.F)


def engine_qdd(name: str, state: dict[str, float]) -> np.ndarray:
    """q̈ = M⁻¹F from the engine at ``state``."""
    M, F = numeric_eom(name)
    n = len(eom_of(name).q)
    return np.linalg.solve(M(state).reshape(n, n), F(state))


def with_accelerations(eom: lagrangian.EquationsOfMotion, state: dict[str, float],
                       qdd: Sequence[float]) -> dict[str, float]:
    out = dict(state)
    out.update({str(s): float(v) for s, v in zip(eom.qdd, qdd, strict=True)})
    return out


# -- model-file text manipulation ---------------------------------------------------------------
_HEADER = re.compile(r"^\s*\[")


def coordinate_entry_lines(text: str) -> list[int]:
    """Indices (0-based) of the entry lines of the [coordinates] table of ``text``."""
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.strip() == "[coordinates]") + 1
    entries = []
    while i < len(lines) and not _HEADER.match(lines[i]):
        if lines[i].strip() and not lines[i].lstrip().startswith("#"):
            entries.append(i)
        i += 1
    return entries


def permuted_coordinates(text: str, order: Sequence[int]) -> str:
    """``text`` with the entries of its [coordinates] table listed in ``order``."""
    lines = text.splitlines()
    slots = coordinate_entry_lines(text)
    assert sorted(order) == list(range(len(slots)))
    entries = [lines[k] for k in slots]
    for slot, k in zip(slots, order, strict=True):
        lines[slot] = entries[k]
    return "\n".join(lines) + "\n"


#: Beyond this many items, `other_orders` samples the orderings (6! = 720 derivations is too many).
MAX_ALL_ORDERS = 4


def other_orders(n: int) -> list[tuple[int, ...]]:
    """Every ordering of n items except the identity (for n > `MAX_ALL_ORDERS`: the reversal,
    the cyclic shifts and two interleavings, which move every item)."""
    if n <= MAX_ALL_ORDERS:
        return [p for p in itertools.permutations(range(n)) if p != tuple(range(n))]
    orders = [tuple(reversed(range(n)))]
    orders += [tuple((k + s) % n for k in range(n)) for s in range(1, n)]
    orders += [tuple(range(1, n, 2)) + tuple(range(0, n, 2)), tuple(range(0, n, 2))[::-1] + tuple(range(1, n, 2))]
    return list(dict.fromkeys(o for o in orders if o != tuple(range(n))))


def wall_spring(initial: float = 0.1, *, L: str = "L = { value = 1.0, positive = true }",
                x: str | None = None) -> str:
    """A particle P on a spring fixed to a wall at x = −L (ω = √(k/m) = √2), with L declared positive and
    x ranging over [−0.5, 0.5]: the model of the sign-assumption and coordinate-range tests.  ``L`` and
    ``x`` replace the declaration lines of L and x (the tests of how they are read)."""
    x = x if x is not None else f"x = {{ initial = {initial}, rate = 0.0, range = [-0.5, 0.5] }}"
    return f"""
[parameters]
m = 1.0
k = 2.0
{L}
[coordinates]
{x}
[points]
W = "-L*R0.x"
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
spring = {{ spring = ["W", "P"], stiffness = "k", rest_length = "L" }}
"""


@dataclasses.dataclass
class Interrupted:
    """What `interrupt_when_started` saw: the finished process, seconds from SIGINT to its exit,
    and seconds from SIGINT to the first ``said`` bytes on its standard error (None if never)."""

    process: subprocess.CompletedProcess
    stopped: float
    said: float | None


def interrupt_when_started(command: Sequence[str], env: dict[str, str], ready: bytes, *, delay: float = 1.0,
                           said: bytes = b"interrupted") -> Interrupted:
    """Run ``command``, send SIGINT ``delay`` s after ``ready`` first shows on its standard error
    (a progress bar: the compiled loop is running), and wait for it to exit (Ctrl-C tests)."""
    proc = subprocess.Popen(list(command), stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    chunks: list[bytes] = []
    started = threading.Event()
    heard: list[float] = []

    def read() -> None:
        for chunk in iter(lambda: proc.stderr.read1(4096), b""):
            chunks.append(chunk)
            if ready in chunk:
                started.set()
            if said in chunk and not heard:
                heard.append(time.monotonic())

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        assert started.wait(240), b"".join(chunks).decode()
        time.sleep(delay)
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=30)
        stopped = time.monotonic() - sent
    finally:
        proc.kill()
        proc.wait()
    reader.join(5)
    stdout = proc.stdout.read().decode()
    stderr = b"".join(chunks).decode()
    return Interrupted(subprocess.CompletedProcess(list(command), proc.returncode, stdout, stderr), stopped,
                       heard[0] - sent if heard else None)


def random_point(eom: lagrangian.EquationsOfMotion, rng: np.random.Generator) -> dict:
    """Random q, q̇, t and parameter values (each parameter its value × [0.6, 1.4]; inputs in [−1, 1]),
    symbol → number: where two formulations of M and F (the course's, the recursive one) are compared."""
    values = {s: float(rng.uniform(-np.pi, np.pi)) for s in eom.q}
    values.update({s: float(rng.uniform(-2, 2)) for s in eom.qd})
    values[eom.t] = 0.3
    for p in eom.model.parameters:
        values[p.symbol] = float(rng.uniform(-1, 1)) if p.input else float(p.value) * float(rng.uniform(0.6, 1.4))
    return values


def plain(text: str) -> str:
    """A French report's text with its typography undone (non-breaking spaces, typographic apostrophes), for tests
    that pin its words; `tests/output/test_report_typography.py` checks the typography itself."""
    return text.replace("\u00a0", " ").replace("\u202f", " ").replace("\u2019", "'")
