"""The registry of `simulate`'s routes (`numerics._methods`): each model finds its route, an option
that only other routes honour is refused by name, the named entries are `simulate` on one route, the
table in docs/simulation.md is the registry's, and no simulator imports the dispatcher back."""

import ast
import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR as EXAMPLES

import lagrangian
from lagrangian.errors import ModelError, SimulationError
from lagrangian.numerics import SimulationOptions, simulate, simulate_contact, simulate_stick_slip
from lagrangian.numerics._methods import ROUTE_ONLY, ROUTES, method_table, route_for

ROOT = Path(__file__).resolve().parents[2]
NUMERICS = ROOT / "src" / "lagrangian" / "numerics"


def _model(name: str):  # type: ignore[no-untyped-def]
    return lagrangian.load_model(EXAMPLES / f"{name}.toml")


@pytest.mark.parametrize("example, route", [("simple_pendulum", "ode"), ("pendulum_tension", "dae"),
                                            ("bouncing_ball", "contact"), ("block_on_incline", "stick-slip"),
                                            ("tumbling_body", "free")])
def test_each_model_takes_the_route_its_mechanics_needs(example: str, route: str) -> None:
    assert route_for(_model(example), SimulationOptions(1.0))[0].name == route


def test_asking_for_sensitivities_picks_their_route_before_the_model_does() -> None:
    assert route_for(_model("simple_pendulum"), SimulationOptions(1.0, sensitivities=["l"]))[0].name == \
        "sensitivities"


def test_options_are_checked_once_when_made_and_cannot_change() -> None:
    with pytest.raises(SimulationError, match="Unknown method `RK99`"):
        SimulationOptions(1.0, method="RK99")
    with pytest.raises(SimulationError, match="rtol = 0 and atol"):
        SimulationOptions(1.0, rtol=0.0)
    with pytest.raises(SimulationError, match="Unknown stabilization `drift`"):
        SimulationOptions(1.0, stabilization="drift")
    options = SimulationOptions(1.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        options.rtol = 1e-3  # type: ignore[misc]
    assert options.but(rtol=1e-6).rtol == 1e-6 and options.rtol == 1e-10


@pytest.mark.parametrize("option, value, example, honoured_by", [
    ("rest", 1e-5, "simple_pendulum", "unilateral contacts"),
    ("max_phases", 10, "block_on_incline", "unilateral contacts"),
    ("max_switches", 10, "bouncing_ball", "exact Coulomb contact"),
])
def test_an_option_only_another_route_honours_is_refused_by_name(option: str, value: float, example: str,
                                                                 honoured_by: str) -> None:
    with pytest.raises(SimulationError, match=f"The option `{option}` applies to models with .*{honoured_by}") as err:
        simulate(_model(example), 1.0, **{option: value})
    assert err.value.fix == f"leave `{option}` out"


def test_every_option_only_some_routes_honour_is_honoured_by_one() -> None:
    for option in ROUTE_ONLY:
        assert any(option in route.options for route in ROUTES), option
    # and every option a route names is one of simulate's
    fields = {f.name for f in dataclasses.fields(SimulationOptions)}
    assert all(set(route.options) <= fields for route in ROUTES)


def test_simulate_contact_is_simulate_on_the_contacts_route_bit_for_bit() -> None:
    ball = _model("bouncing_ball")
    one = simulate(ball, 1.5, n_out=31, rest=1e-5)
    other = simulate_contact(ball, 1.5, n_out=31, rest=1e-5)
    assert np.array_equal(one.q, other.q) and np.array_equal(one.qd, other.qd)
    assert [(e.name, e.t) for e in one.events] == [(e.name, e.t) for e in other.events]
    with pytest.raises(ModelError, match="no unilateral contact"):
        simulate_contact(_model("simple_pendulum"), 1.0)
    with pytest.raises(SimulationError, match="The option `sensitivities` applies to"):
        simulate_contact(ball, 1.0, sensitivities=["g"])


def test_simulate_stick_slip_is_simulate_on_the_stick_slip_route_bit_for_bit() -> None:
    block = _model("block_on_incline")
    one = simulate(block, 1.0, n_out=21)
    other = simulate_stick_slip(block, 1.0, n_out=21)
    mode = next(name for name in one.extra if name.startswith("mode_"))
    assert np.array_equal(one.q, other.q) and np.array_equal(one.qd, other.qd)
    assert np.array_equal(one.extra[mode], other.extra[mode])
    assert one.method == other.method and "stick/slip" in one.method
    with pytest.raises(ModelError, match="no exact Coulomb contact"):
        simulate_stick_slip(_model("simple_pendulum"), 1.0)


def test_the_table_in_the_docs_is_the_registry() -> None:
    assert method_table() in (ROOT / "docs" / "simulation.md").read_text(encoding="utf-8")


def _imported(path: Path, package: str = "lagrangian.numerics") -> set[str]:
    """Every module a file imports, at any depth (function-level imports included), relative ones resolved
    against ``package`` (the file's)."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            base = {0: "", 1: f"{package}.", 2: "lagrangian."}[node.level] + (node.module or "")
            names.add(base)
            names.update(f"{base}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
    return names


def test_no_simulator_imports_the_entry_or_the_registry_back() -> None:
    # The routes are below the registry, the registry below `simulate`: a route importing either
    # (even inside a function) would close an import circle.
    above = {"lagrangian.numerics._simulate", "lagrangian.numerics._methods"}
    users = ("__init__", "_simulate", "_methods", "_top_check")  # the face, the entry, the registry, a user of simulate
    below = sorted(p for p in NUMERICS.glob("_*.py") if p.stem not in users)
    for path in below:
        assert not _imported(path) & above, path.name
    assert not _imported(NUMERICS / "_methods.py") & {"lagrangian.numerics._simulate"}


def test_the_jax_ensemble_backend_is_listed_in_numerics_without_importing_the_output_stage() -> None:
    code = ("import sys; from lagrangian.numerics._ensemble import BACKENDS; "
            "print('jax' in BACKENDS, 'lagrangian.output' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["True", "False"]
    assert not any(name.startswith("lagrangian.numerics") for name in
                   _imported(ROOT / "src" / "lagrangian" / "output" / "__init__.py", "lagrangian.output"))
