"""The Python `ModelBuilder` API: the same systems as model files, and the same refusals.

The TOML reader goes through this builder, so a system declared in Python must derive
exactly as its model file, and a mistake must be refused with the same message.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest
import symengine as se
import sympy as sp

import lagrangian
from lagrangian import ModelBuilder, ModelError
from lagrangian._identity import are_zero
from lagrangian.model import Location

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def top_builder(**changes: object) -> ModelBuilder:
    """The seed's Lagrange top declared in Python, as in examples/lagrange_top.toml."""
    b = ModelBuilder("Lagrange top", "Heavy symmetric top with a fixed point O, in Euler angles psi, theta, phi")
    b.parameter("m", 1.0, unit="kg", description="mass of (S)")
    b.parameter("g", 9.81, unit="m/s^2", description="gravitational acceleration")
    b.parameter("a", 0.1, unit="m", description="OG = a z")
    b.parameter("A", 0.02, unit="kg m^2", description="moment of inertia about u and w, at O")
    b.parameter("C", 0.01, unit="kg m^2", description="moment of inertia about the axis z, at O")
    b.coordinate("psi", 0.0, 0.0, momentum="K", description="precession angle")
    b.coordinate("theta", 0.5, 0.0, description="nutation angle")
    b.coordinate("phi", 0.0, 50.0, momentum="H", description="proper rotation angle")
    b.frame("R0", None, axes=("x0", "y0", "z0"))
    b.frame("R1", "R0", rotation=("psi", "z"), axes=("u", "v", "z0"))
    b.frame("R2", "R1", rotation=("theta", "x"), axes=("u", "w", "z"))
    b.frame("R", "R2", rotation=("phi", "z"), axes=("x", "y", "z"))
    b.body("S", frame="R", mass=changes.get("mass", "m"), center=changes.get("center", "a*R.z"), fixed_point="O",
           inertia=changes.get("inertia", {"at": "O", "frame": "R2", "diagonal": ["A", "A", "C"]}))
    b.gravity("weight", changes.get("gravity", "-g*R0.z"))
    return b


def toml_top() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES / "lagrange_top.toml"))


def assert_same_dynamics(e1: lagrangian.EquationsOfMotion, e2: lagrangian.EquationsOfMotion) -> None:
    assert e1.coordinates == e2.coordinates
    assert se.expand(e1.T - e2.T) == 0
    assert se.expand(e1.U - e2.U) == 0
    n = len(e1.coordinates)
    for i in range(n):
        assert se.expand(e1.F[i] - e2.F[i]) == 0
        for j in range(n):
            assert se.expand(e1.M[i][j] - e2.M[i][j]) == 0
    for q1, q2 in zip(e1.equations, e2.equations, strict=True):
        assert se.expand(q1.lhs - q2.lhs) == 0 and se.expand(q1.rhs - q2.rhs) == 0


# -- the same system two ways ---------------------------------------------------------------------
def test_builder_top_derives_as_the_model_file() -> None:
    from_python = lagrangian.derive(top_builder().build())
    from_file = toml_top()
    assert_same_dynamics(from_python, from_file)
    # the course's T, exactly
    m, g, a, A, C = se.symbols("m g a A C")
    psi, theta, phi = se.symbols("psi theta phi")
    psi_d, theta_d, phi_d = se.symbols("psi_dot theta_dot phi_dot")
    t_seed = (A * (theta_d**2 + psi_d**2 * se.sin(theta) ** 2) + C * (phi_d + psi_d * se.cos(theta)) ** 2) / 2
    assert se.expand(from_python.T - t_seed) == 0


def test_builder_model_equals_the_file_model() -> None:
    from_python = top_builder().build()
    from_file = lagrangian.load_model(EXAMPLES / "lagrange_top.toml")
    assert from_python.parameters == from_file.parameters
    assert from_python.coordinates == from_file.coordinates
    assert from_python.frames == from_file.frames
    assert from_python.bodies == from_file.bodies
    assert from_python.loads == from_file.loads


def test_builder_accepts_sympy_and_symengine_objects() -> None:
    m, a, g = sp.symbols("m a g")
    A, C = se.symbols("A C")
    b = top_builder(mass=m, inertia={"at": "O", "frame": "R2", "diagonal": [A, A, C]})
    assert_same_dynamics(lagrangian.derive(b.build()), toml_top())


def test_builder_rotation_sequence_equals_the_chain() -> None:
    b = ModelBuilder("top, one frame")
    for name, value in (("m", 1.0), ("g", 9.81), ("a", 0.1), ("A", 0.02), ("C", 0.01)):
        b.parameter(name, value)
    for q in ("psi", "theta", "phi"):
        b.coordinate(q, 0.5)
    b.frame("R", "R0", rotation=[("psi", "z"), ("theta", "x"), ("phi", "z")])
    b.body("S", frame="R", mass="m", center="a*R.z", fixed_point="O",
           inertia={"at": "O", "frame": "R", "diagonal": ["A", "A", "C"]})
    b.gravity("weight", "-g*R0.z")
    eom, ref = lagrangian.derive(b.build()), toml_top()
    # Ω is then written in R rather than R2: equal up to sin² + cos² = 1
    assert are_zero([eom.T - ref.T, *(eom.M[i][j] - ref.M[i][j] for i in range(3) for j in range(3))])


# -- the same refusals ----------------------------------------------------------------------------
def error_of(build: Callable[[], object]) -> ModelError:
    with pytest.raises(ModelError) as info:
        build()
    err = info.value
    assert type(err) is ModelError
    assert err.fix and err.message
    return err


def test_frame_declared_twice_has_two_parents() -> None:
    b = top_builder()
    b.frame("R1", "R2")
    err = error_of(b.build)
    assert err.symbol == "R1" and "frame `R1` is defined twice" in err.message and "one parent" in err.message
    assert err.file is None and err.line is None


def test_frame_cycle() -> None:
    b = ModelBuilder()
    b.coordinate("q")
    b.frame("A", "B", rotation=("q", "z"))
    b.frame("B", "A")
    b.particle("P", mass=1, position="A.x")
    err = error_of(b.build)
    assert err.symbol in ("A", "B") and "cycle" in err.message


def test_unknown_symbol() -> None:
    err = error_of(top_builder(center="b*R.z").build)
    assert err.symbol == "b" and "unknown symbol `b`" in err.message


def test_unknown_symbol_in_a_sympy_expression() -> None:
    err = error_of(top_builder(mass=sp.Symbol("M")).build)
    assert err.symbol == "M" and "unknown symbol `M`" in err.message


def test_coordinate_never_used() -> None:
    b = top_builder()
    b.coordinate("chi")
    err = error_of(b.build)
    assert err.symbol == "chi" and "never used" in err.message


def test_body_without_inertia() -> None:
    b = ModelBuilder()
    b.coordinate("q")
    b.frame("R1", "R0", rotation=("q", "z"))
    b.body("S", frame="R1", mass=1, center="R1.x", inertia=None)
    err = error_of(b.build)
    assert err.symbol == "S" and "has no inertia" in err.message


def test_non_physical_inertia() -> None:
    model = top_builder(inertia={"frame": "R", "diagonal": ["A", "A", "5*A"]}).build()
    err = error_of(lambda: lagrangian.derive(model))
    assert err.symbol == "S" and "triangle inequality" in err.message


def test_inertia_not_invariant_in_its_frame() -> None:
    model = top_builder(inertia={"at": "O", "frame": "R1", "diagonal": ["A", "A", "C"]}).build()
    err = error_of(lambda: lagrangian.derive(model))
    assert err.symbol == "S" and "not invariant" in err.message


def test_inertia_not_symmetric() -> None:
    err = error_of(top_builder(inertia={"matrix": [["A", "a", 0], [0, "A", 0], [0, 0, "C"]]}).build)
    assert err.symbol == "S" and "not symmetric" in err.message


def test_vector_mixing_undefined_frames() -> None:
    err = error_of(top_builder(center="a*R.z + a*R5.x").build)
    assert err.symbol == "R5" and "unknown frame `R5`" in err.message


def test_syntax_error() -> None:
    err = error_of(top_builder(center="a*R.z +").build)
    assert "in `a*R.z +`" in err.message and "column 8" in err.message
    assert err.column is None  # no file: the column is only given in the message


def test_duplicated_name() -> None:
    b = top_builder()
    b.parameter("theta", 1.0)
    err = error_of(b.build)
    assert err.symbol == "theta" and "declared twice" in err.message


def test_point_defined_in_terms_of_itself() -> None:
    b = top_builder()
    b.point("P", "a*R.x", relative_to="P")
    err = error_of(b.build)
    assert err.symbol == "P" and "in terms of itself" in err.message


def test_load_on_unknown_point() -> None:
    b = top_builder()
    b.force("push", "m*g*R0.x", at="Z")
    err = error_of(b.build)
    assert err.symbol == "Z" and "unknown point `Z`" in err.message


def test_spring_with_three_ends() -> None:
    b = top_builder()
    b.spring("k", ["O", "S", "O"], stiffness="m")
    err = error_of(b.build)
    assert err.symbol == "k" and "exactly two points" in err.message


def test_parameter_value_not_a_number() -> None:
    b = top_builder()
    b.parameter("k", "ten")  # type: ignore[arg-type]
    err = error_of(b.build)
    assert err.symbol == "k" and "must be a number" in err.message


def test_invalid_name_is_refused_at_once() -> None:
    b = ModelBuilder()
    err = error_of(lambda: b.parameter("2k", 1.0))
    assert err.symbol == "2k"


@pytest.mark.parametrize(
    "declare",
    [
        lambda b: b.frame("R3", ["R0"]),
        lambda b: b.frame("R3", "R0", rotation=("psi", 3)),
        lambda b: b.frame("R3", "R0", rotation="psi"),
        lambda b: b.frame("R3", "R0", axes="uvw"),
        lambda b: b.point("P", "a*R.x", relative_to=["O"]),
        lambda b: b.torque("c", "R.z", on=["S"]),
        lambda b: b.force("f", "R.z", at=None),
        lambda b: b.spring("k", [1, 2], stiffness="m"),
        lambda b: b.coordinate("chi", "zero"),
        lambda b: b.parameter("k", float("nan")),
        lambda b: b.body("T", frame="R", mass=[1], center="R.x", inertia={"diagonal": [1, 1, 1]}),
        lambda b: b.body("T", frame="R", mass=1, center="R.x", inertia={"at": 3, "diagonal": [1, 1, 1]}),
        lambda b: b.body("T", frame="R", mass=1, center="R.x", inertia=[1, 1, 1]),  # type: ignore[arg-type]
    ],
)
def test_wrong_types_give_model_errors(declare: Callable[[ModelBuilder], None]) -> None:
    b = top_builder()
    declare(b)
    err = error_of(b.build)
    assert err.symbol


def test_location_given_to_the_builder_is_reported() -> None:
    b = top_builder()
    b.force("push", "m*g*R0.x", at="Z", location=Location("script.py", 42))
    err = error_of(b.build)
    assert (err.file, err.line) == ("script.py", 42)
    assert str(err).startswith("script.py:42: ")


# -- builder and file agree on the message -------------------------------------------------------------
TOML_HEAD = """\
[parameters]
m = 1.0
a = 0.5

[coordinates]
q = 0.0

[frames]
R1 = { from = "R0", rotation = ["q", "z"] }

"""


def python_head() -> ModelBuilder:
    b = ModelBuilder()
    b.parameter("m", 1.0)
    b.parameter("a", 0.5)
    b.coordinate("q", 0.0)
    b.frame("R1", "R0", rotation=("q", "z"))
    return b


CASES: dict[str, tuple[str, Callable[[ModelBuilder], None]]] = {
    "unknown symbol": (
        '[particles.P]\nmass = "m"\nposition = "l*R1.x"\n',
        lambda b: b.particle("P", mass="m", position="l*R1.x"),
    ),
    "scalar position": (
        '[particles.P]\nmass = "m"\nposition = "a"\n',
        lambda b: b.particle("P", mass="m", position="a"),
    ),
    "unknown frame": (
        '[particles.P]\nmass = "m"\nposition = "a*R2.x"\n',
        lambda b: b.particle("P", mass="m", position="a*R2.x"),
    ),
    "no inertia": (
        '[bodies.S]\nframe = "R1"\nmass = "m"\ncenter = "a*R1.x"\n',
        lambda b: b.body("S", frame="R1", mass="m", center="a*R1.x", inertia=None),
    ),
    "point cycle": (
        '[points]\nA = { from = "B", position = "a*R1.x" }\nB = { from = "A", position = "a*R1.y" }\n'
        '[particles.P]\nmass = "m"\nposition = "a*R1.x"\n',
        lambda b: (b.point("A", "a*R1.x", relative_to="B"), b.point("B", "a*R1.y", relative_to="A"),
                   b.particle("P", mass="m", position="a*R1.x")),
    ),
    "spring ends": (
        '[particles.P]\nmass = "m"\nposition = "a*R1.x"\n[loads]\nk = { spring = ["O", "P", "O"], stiffness = "m" }\n',
        lambda b: (b.particle("P", mass="m", position="a*R1.x"), b.spring("k", ["O", "P", "O"], stiffness="m")),
    ),
    "unused coordinate": (  # q turns R1, but nothing is attached to R1
        '[particles.P]\nmass = "m"\nposition = "a*R0.x"\n',
        lambda b: b.particle("P", mass="m", position="a*R0.x"),
    ),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_builder_and_file_refuse_alike(tmp_path: Path, case: str) -> None:
    toml, declare = CASES[case]
    path = tmp_path / "model.toml"
    path.write_text(TOML_HEAD + toml, encoding="utf-8")
    file_err = error_of(lambda: lagrangian.load_model(path))
    b = python_head()
    declare(b)
    py_err = error_of(b.build)
    assert (py_err.message, py_err.symbol, py_err.fix) == (file_err.message, file_err.symbol, file_err.fix)
    assert file_err.file == str(path) and file_err.line is not None
    assert py_err.file is None and py_err.line is None
