"""Bad model files get a clear `ModelError`: file, line, symbol, fix — never a traceback.

Each test writes a small model (the seed's Lagrange top with one mistake) to a
temporary file, loads it with `lagrangian.load_model` (and `lagrangian.derive` for
the checks that need kinematics), and checks the error's file, line, symbol, fix
and that its message names the problem.  Expected lines are found by searching the
text for the offending declaration, so the tests say *which* line is meant.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import lagrangian
from lagrangian import LagrangianError, ModelError

#: The seed's heavy symmetric top, the starting point of every broken model below.
TOP = """\
[model]
name = "Lagrange top"

[parameters]
m = { value = 1.0, unit = "kg" }
g = 9.81
a = 0.1
A = 0.02
C = 0.01

[coordinates]
psi = { initial = 0.0, rate = 0.0, momentum = "K" }
theta = { initial = 0.5, rate = 0.0 }
phi = { initial = 0.0, rate = 50.0, momentum = "H" }

[frames]
R0 = { axes = ["x0", "y0", "z0"] }
R1 = { from = "R0", rotation = ["psi", "z"], axes = ["u", "v", "z0"] }
R2 = { from = "R1", rotation = ["theta", "x"], axes = ["u", "w", "z"] }
R = { from = "R2", rotation = ["phi", "z"], axes = ["x", "y", "z"] }

[bodies.S]
frame = "R"
mass = "m"
center = "a*R.z"
fixed_point = "O"
inertia = { at = "O", frame = "R2", diagonal = ["A", "A", "C"] }

[loads]
weight = { gravity = "-g*R0.z" }
"""


# -- helpers ------------------------------------------------------------------------------
def edit(text: str, old: str, new: str) -> str:
    """``text`` with the one occurrence of ``old`` replaced (fails loudly if it is not there)."""
    assert text.count(old) == 1, f"{old!r} occurs {text.count(old)} times"
    return text.replace(old, new)


def line_of(text: str, needle: str, occurrence: int = 1) -> int:
    """1-based number of the line holding the ``occurrence``-th ``needle``."""
    hits = [n for n, line in enumerate(text.splitlines(), start=1) if needle in line]
    assert len(hits) >= occurrence, f"{needle!r} is not in the text {occurrence} time(s)"
    return hits[occurrence - 1]


def write(tmp_path: Path, text: str, name: str = "model.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def error_of(tmp_path: Path, text: str, *, derive: bool = False) -> tuple[ModelError, Path]:
    """The `ModelError` raised by loading (and deriving) ``text``; any other exception fails the test."""
    path = write(tmp_path, text)
    with pytest.raises(ModelError) as info:
        model = lagrangian.load_model(path)
        if derive:
            lagrangian.derive(model)
    return info.value, path


def check(err: ModelError, path: Path, line: int | None, symbol: str | None, *words: str) -> None:
    """The error names the file, the line, the symbol, a fix, and the problem (``words``)."""
    assert type(err) is ModelError
    assert err.file == str(path)
    assert err.line == line, f"line {err.line} instead of {line}: {err}"
    assert err.symbol == symbol, f"symbol {err.symbol!r} instead of {symbol!r}: {err}"
    assert err.fix and err.fix.strip(), f"no fix in: {err}"
    for word in words:
        assert word.lower() in err.message.lower(), f"{word!r} not in message: {err.message}"
    # The one-line form the command line prints starts with FILE:LINE.
    text = str(err)
    assert text.startswith(f"{path}:{line}" if line is not None else str(path))
    assert "Traceback" not in text
    # When the offending line of the file travels with the error, it is the right one.
    if err.source_line is not None:
        assert err.source_line == path.read_text(encoding="utf-8").splitlines()[line - 1]


# -- the template is valid ------------------------------------------------------------------
def test_template_is_the_seed_top(tmp_path: Path) -> None:
    model = lagrangian.load_model(write(tmp_path, TOP))
    eom = lagrangian.derive(model)
    assert eom.coordinates == ("psi", "theta", "phi")
    assert model.where("body", "S").line == line_of(TOP, "[bodies.S]")


def test_load_errors_carry_the_offending_line(tmp_path: Path) -> None:
    text = edit(TOP, 'center = "a*R.z"', 'center = "b*R.z"')
    err, _ = error_of(tmp_path, text)
    assert err.source_line == 'center = "b*R.z"'
    err, _ = error_of(tmp_path, edit(TOP, "g = 9.81", "g = = 9.81"))
    assert err.source_line == "g = = 9.81"


# -- unknown symbol ---------------------------------------------------------------------------
def test_unknown_symbol_in_a_vector(tmp_path: Path) -> None:
    text = edit(TOP, 'center = "a*R.z"', 'center = "b*R.z"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "center ="), "b", "unknown symbol `b`", "centre of mass", "body `S`")
    # the column is the one of `b` in the file
    assert err.column == text.splitlines()[err.line - 1].index("b*R.z") + 1
    assert "declare `b`" in err.fix


def test_unknown_symbol_in_a_rotation_angle(tmp_path: Path) -> None:
    text = edit(TOP, 'rotation = ["theta", "x"]', 'rotation = ["tehta", "x"]')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "R2 = {"), "tehta", "unknown symbol `tehta`", "rotation angle", "frame `R2`")


def test_unknown_symbol_in_a_load(tmp_path: Path) -> None:
    text = edit(TOP, '"-g*R0.z"', '"-gg*R0.z"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "weight ="), "gg", "unknown symbol `gg`", "load `weight`")


def test_unknown_symbol_in_the_inertia(tmp_path: Path) -> None:
    text = edit(TOP, '["A", "A", "C"]', '["A", "A", "D"]')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "inertia ="), "D", "unknown symbol `D`", "inertia")


def test_unknown_function(tmp_path: Path) -> None:
    text = edit(TOP, 'center = "a*R.z"', 'center = "cosine(theta)*a*R.z"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "center ="), "cosine", "unknown function `cosine`")
    assert "sin" in err.fix and "cos" in err.fix


def test_time_rate_and_pi_are_known(tmp_path: Path) -> None:
    """`t`, `pi` and the rates `q_dot` are declared implicitly: no error for them."""
    text = TOP + 'drag = { generalized_force = { psi = "-a*psi_dot*cos(pi*t)" } }\n'
    lagrangian.derive(lagrangian.load_model(write(tmp_path, text)))


# -- a coordinate never used ----------------------------------------------------------------
def test_coordinate_never_used(tmp_path: Path) -> None:
    text = edit(TOP, 'phi = { initial = 0.0, rate = 50.0, momentum = "H" }\n',
                'phi = { initial = 0.0, rate = 50.0, momentum = "H" }\nchi = 0.3\n')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "chi = 0.3"), "chi", "coordinate `chi` is never used")


def test_coordinate_that_only_turns_an_unused_frame(tmp_path: Path) -> None:
    text = edit(TOP, 'phi = { initial = 0.0, rate = 50.0, momentum = "H" }\n',
                'phi = { initial = 0.0, rate = 50.0, momentum = "H" }\nchi = 0.3\n')
    text = edit(text, 'R = { from = "R2"', 'R9 = { from = "R0", rotation = ["chi", "y"] }\nR = { from = "R2"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "chi = 0.3"), "chi", "coordinate `chi` is never used")


def test_no_coordinate_at_all(tmp_path: Path) -> None:
    text = "[parameters]\nm = 1.0\n"
    err, path = error_of(tmp_path, text)
    assert err.file == str(path) and err.fix
    assert "no coordinate" in err.message


# -- frames: cycle, two parents, unknown parent ---------------------------------------------------
def test_frame_cycle(tmp_path: Path) -> None:
    text = edit(TOP, 'R1 = { from = "R0"', 'R1 = { from = "R"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "R1 = {"), "R1", "cycle", "`R1`", "`R2`", "`R`")


def test_frame_that_is_its_own_parent(tmp_path: Path) -> None:
    text = edit(TOP, 'R1 = { from = "R0"', 'R1 = { from = "R1"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "R1 = {"), "R1", "cycle")


def test_frame_with_two_parents_is_a_duplicate_key(tmp_path: Path) -> None:
    text = edit(TOP, 'R = { from = "R2"', 'R1 = { from = "R0" }\nR = { from = "R2"')
    err, path = error_of(tmp_path, text)
    second = line_of(text, "R1 = {", 2)
    check(err, path, second, "R1", "frame `R1` is defined twice", "one parent", f"lines {line_of(text, 'R1 = {')}")


def test_frame_with_two_parents_as_tables(tmp_path: Path) -> None:
    text = edit(TOP, 'R1 = { from = "R0", rotation = ["psi", "z"], axes = ["u", "v", "z0"] }\n', "")
    text = edit(text, "[bodies.S]", '[frames.R1]\nfrom = "R0"\nrotation = ["psi", "z"]\n\n[bodies.S]')
    text += '\n[frames.R1]\nfrom = "R2"\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "[frames.R1]", 2), "R1", "frame `R1` is defined twice", "one parent")


def test_frame_from_unknown_frame(tmp_path: Path) -> None:
    text = edit(TOP, 'R2 = { from = "R1"', 'R2 = { from = "R7"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "R2 = {"), "R7", "unknown frame `R7`")


def test_galilean_frame_cannot_turn(tmp_path: Path) -> None:
    text = edit(TOP, 'R0 = { axes = ["x0", "y0", "z0"] }', 'R0 = { from = "R1" }')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "R0 = {"), "R0", "Galilean")


@pytest.mark.parametrize("rotation", ['["psi", "w"]', '["psi", 3]', '"psi"', "[]", '[["psi"]]', "3"])
def test_bad_rotation(tmp_path: Path, rotation: str) -> None:
    text = edit(TOP, 'rotation = ["psi", "z"]', f"rotation = {rotation}")
    err, path = error_of(tmp_path, text)
    assert err.line == line_of(text, "R1 = {") and err.file == str(path) and err.fix
    assert "rotation" in err.message


@pytest.mark.parametrize("axes", ['"uvz"', '["u", "v"]', '["u", "v", 3]'])
def test_bad_axes(tmp_path: Path, axes: str) -> None:
    text = edit(TOP, 'axes = ["u", "v", "z0"]', f"axes = {axes}")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "R1 = {"), "R1", "`axes` of frame `R1`")


# -- bodies and inertia ---------------------------------------------------------------------------
def test_body_without_inertia(tmp_path: Path) -> None:
    text = edit(TOP, 'inertia = { at = "O", frame = "R2", diagonal = ["A", "A", "C"] }\n', "")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "[bodies.S]"), "S", "body `S` has no inertia")
    assert "inertia = {" in err.fix and "[particles]" in err.fix


def test_negative_moment_of_inertia(tmp_path: Path) -> None:
    text = edit(TOP, "A = 0.02", "A = -0.02")
    err, path = error_of(tmp_path, text, derive=True)
    check(err, path, line_of(text, "inertia ="), "S", "not physical", "negative")


def test_negative_moment_given_directly(tmp_path: Path) -> None:
    text = edit(TOP, 'inertia = { at = "O", frame = "R2", diagonal = ["A", "A", "C"] }',
                'inertia = { frame = "R", diagonal = ["-0.5", "0.5", "0.5"] }')
    err, path = error_of(tmp_path, text, derive=True)
    check(err, path, line_of(text, "inertia ="), "S", "not physical", "negative")


def test_triangle_inequality_violated(tmp_path: Path) -> None:
    # at G: A, A, C with C > 2A is impossible for any mass distribution
    text = edit(TOP, "C = 0.01", "C = 0.5")
    text = edit(text, 'inertia = { at = "O", ', 'inertia = { ')
    err, path = error_of(tmp_path, text, derive=True)
    check(err, path, line_of(text, "inertia ="), "S", "not physical", "triangle inequality")


def test_inertia_is_checked_at_the_centre_of_mass(tmp_path: Path) -> None:
    """Π_O may look physical while Π_G, found by the parallel-axis theorem, is not."""
    # Π_G = Π_O − m a² (E − z zᵀ) = diag(A − m a², A − m a², C) = diag(0.01, 0.01, C)
    text = edit(TOP, "C = 0.01", "C = 0.025")  # at O: 0.025 <= 0.02 + 0.02; at G: 0.025 > 0.01 + 0.01
    err, path = error_of(tmp_path, text, derive=True)
    check(err, path, line_of(text, "inertia ="), "S", "triangle inequality", "at G")
    text = edit(TOP, "C = 0.01", "C = 0.015")  # physical at G too
    lagrangian.derive(lagrangian.load_model(write(tmp_path, text)))


def test_inertia_matrix_not_symmetric(tmp_path: Path) -> None:
    text = edit(TOP, 'diagonal = ["A", "A", "C"]',
                'matrix = [["A", "0", "0"], ["0.001", "A", "0"], ["0", "0", "C"]]')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "inertia ="), "S", "not symmetric", "(1,2)", "(2,1)", "1/1000")


def test_inertia_matrix_not_three_by_three(tmp_path: Path) -> None:
    text = edit(TOP, 'diagonal = ["A", "A", "C"]', 'matrix = [["A", "0"], ["0", "A"]]')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "inertia ="), "S", "3 rows of 3 entries")


def test_inertia_given_in_a_frame_where_it_is_not_invariant(tmp_path: Path) -> None:
    # diag(A, B, C) with A != B changes under the rotation phi about z between R2 and R
    text = edit(TOP, "C = 0.01", "C = 0.01\nB = 0.03")
    text = edit(text, '["A", "A", "C"]', '["A", "B", "C"]')
    err, path = error_of(tmp_path, text, derive=True)
    check(err, path, line_of(text, "inertia ="), "S", "frame `R2`", "turns relative to the body", "not invariant")
    assert "`R`" in err.fix


def test_inertia_in_an_invariant_frame_is_accepted(tmp_path: Path) -> None:
    """The seed gives diag(A, A, C) in R2: invariant under the rotation φ about z."""
    lagrangian.derive(lagrangian.load_model(write(tmp_path, TOP)))


def test_declared_fixed_point_that_moves(tmp_path: Path) -> None:
    text = edit(TOP, "[bodies.S]", '[points]\nP = "a*R.x"\n\n[bodies.S]')
    text = edit(text, 'fixed_point = "O"', 'fixed_point = "P"')
    text = edit(text, 'at = "O", ', "")
    err, path = error_of(tmp_path, text, derive=True)
    check(err, path, line_of(text, "fixed_point ="), "P", "`P` is declared the fixed point of body `S`", "moves")


def test_fixed_point_that_is_not_declared(tmp_path: Path) -> None:
    text = edit(TOP, 'fixed_point = "O"', 'fixed_point = "Q"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "fixed_point ="), "Q", "fixed point `Q`", "not a declared point")


def test_inertia_at_a_point_that_moves_in_the_body(tmp_path: Path) -> None:
    text = edit(TOP, "[bodies.S]", '[points]\nP = "a*R1.x"\n\n[bodies.S]')
    text = edit(text, 'at = "O"', 'at = "P"')
    err, path = error_of(tmp_path, text, derive=True)
    check(err, path, line_of(text, "inertia ="), "P", "moves relative to body `S`")


def test_body_on_unknown_frame(tmp_path: Path) -> None:
    text = edit(TOP, 'frame = "R"\n', 'frame = "R3"\n')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, 'frame = "R3"'), "R3", "unknown frame `R3`")


@pytest.mark.parametrize("key", ["frame", "mass", "center"])
def test_body_missing_a_key(tmp_path: Path, key: str) -> None:
    text = "\n".join(line for line in TOP.splitlines() if not line.startswith(f"{key} =")) + "\n"
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "[bodies.S]"), "S", f"body `S` has no `{key}`")


# -- vectors and expressions ------------------------------------------------------------------------
def test_vector_mixing_an_undefined_frame(tmp_path: Path) -> None:
    text = edit(TOP, 'center = "a*R.z"', 'center = "a*R.z + a*R9.x"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "center ="), "R9", "unknown frame `R9`")
    assert err.column == text.splitlines()[err.line - 1].index("R9") + 1


def test_vector_plus_scalar(tmp_path: Path) -> None:
    text = edit(TOP, 'center = "a*R.z"', 'center = "a*R.z + a"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "center ="), "S", "cannot add a vector and a scalar")


def test_scalar_where_a_vector_is_needed(tmp_path: Path) -> None:
    text = edit(TOP, 'center = "a*R.z"', 'center = "a"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "center ="), "S", "must be a vector")


def test_vector_where_a_scalar_is_needed(tmp_path: Path) -> None:
    text = edit(TOP, 'mass = "m"', 'mass = "m*R.x"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "mass ="), "S", "must be a scalar")


def test_frame_used_as_a_scalar(tmp_path: Path) -> None:
    text = edit(TOP, 'mass = "m"', 'mass = "R"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "mass ="), "R", "`R` is a frame")


def test_syntax_error_in_an_expression(tmp_path: Path) -> None:
    text = edit(TOP, 'center = "a*R.z"', 'center = "a*(R.z"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "center ="), "S", "expected `)`", "a*(R.z")
    line = text.splitlines()[err.line - 1]
    assert err.column == line.index('"a*(R.z"') + 1 + len("a*(R.z") + 1  # just after the text


@pytest.mark.parametrize("expression", ["a*", "a R.z", "a*R.z)", "", "a *** R.z", "a*R.", "a#R.z"])
def test_other_syntax_errors(tmp_path: Path, expression: str) -> None:
    text = edit(TOP, 'center = "a*R.z"', f'center = "{expression}"')
    err, path = error_of(tmp_path, text)
    assert err.line == line_of(text, "center =") and err.file == str(path) and err.fix and err.symbol
    assert f"(in `{expression}`" in err.message
    assert err.column is not None


def test_code_in_an_expression_is_refused(tmp_path: Path) -> None:
    text = edit(TOP, 'mass = "m"', "mass = '__import__(\"os\").system(\"false\")'")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "mass ="), "S", "unexpected character")


def test_division_by_zero(tmp_path: Path) -> None:
    text = edit(TOP, 'mass = "m"', 'mass = "m/(a - a)"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "mass ="), "S", "division by zero")


def test_huge_exponent_in_a_model(tmp_path: Path) -> None:
    text = edit(TOP, 'mass = "m"', 'mass = "m*9^9^9"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "mass ="), "S", "too large")


def test_expression_that_is_not_text(tmp_path: Path) -> None:
    text = edit(TOP, 'mass = "m"', "mass = [1, 2]")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "mass ="), "S", "mass of body `S`")


def test_numbers_are_accepted_for_scalars(tmp_path: Path) -> None:
    text = edit(TOP, 'mass = "m"', "mass = 1")
    lagrangian.derive(lagrangian.load_model(write(tmp_path, text)))


# -- duplicated names ------------------------------------------------------------------------------
def test_parameter_and_coordinate_with_the_same_name(tmp_path: Path) -> None:
    text = edit(TOP, "g = 9.81\n", "g = 9.81\ntheta = 1.0\n")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "theta = {"), "theta", "declared twice", "parameter",
          f"line {line_of(text, 'theta = 1.0')}")


def test_body_named_like_a_parameter(tmp_path: Path) -> None:
    text = edit(TOP, "[bodies.S]", "[bodies.m]")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "[bodies.m]"), "m", "`m` is declared twice")


def test_rate_name_clashes_with_a_parameter(tmp_path: Path) -> None:
    text = edit(TOP, "g = 9.81\n", "g = 9.81\nphi_dot = 2.0\n")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "phi = {"), "phi_dot", "declared twice")


def test_reserved_name(tmp_path: Path) -> None:
    text = edit(TOP, "g = 9.81\n", "g = 9.81\npi = 3.0\n")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "pi = 3.0"), "pi", "reserved")


def test_duplicate_key_in_a_table(tmp_path: Path) -> None:
    text = edit(TOP, "g = 9.81\n", "g = 9.81\ng = 9.80\n")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "g = 9.80"), "g", "`g` is declared twice in [parameters]", "lines")


def test_table_declared_twice(tmp_path: Path) -> None:
    text = TOP + '\n[bodies.S]\nframe = "R"\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "[bodies.S]", 2), "S", "`S` is declared twice in [bodies]")


def test_duplicate_key_in_an_inline_table(tmp_path: Path) -> None:
    text = edit(TOP, 'R2 = { from = "R1",', 'R2 = { from = "R1", from = "R0",')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "R2 = {"), "from", "`from` is given twice")


def test_invalid_name(tmp_path: Path) -> None:
    text = edit(TOP, "g = 9.81\n", 'g = 9.81\n"g 2" = 1.0\n')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, '"g 2"'), "g 2", "not a valid parameter name")


# -- TOML-level problems --------------------------------------------------------------------------
def test_toml_syntax_error(tmp_path: Path) -> None:
    text = edit(TOP, "g = 9.81", "g = = 9.81")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "g = = 9.81"), "g", "TOML syntax error")
    assert err.column is not None


def test_toml_unterminated_string(tmp_path: Path) -> None:
    text = edit(TOP, 'mass = "m"', 'mass = "m')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, 'mass = "m'), "mass", "TOML syntax error")


def test_toml_error_in_a_header(tmp_path: Path) -> None:
    text = edit(TOP, "[loads]", "[loads")
    err, path = error_of(tmp_path, text)
    assert err.line == line_of(text, "[loads") and err.fix and "TOML" in err.message


def test_unknown_table(tmp_path: Path) -> None:
    text = TOP + "\n[joints]\nrolling = true\n"
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "[joints]"), "joints", "unknown table `[joints]`")
    assert "[parameters]" in err.fix


def test_unknown_key_in_a_frame(tmp_path: Path) -> None:
    text = edit(TOP, 'R1 = { from = "R0",', 'R1 = { form = "R0", from = "R0",')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "R1 = {"), "form", "unknown key `form`", "frame `R1`")
    assert "from" in err.fix


def test_unknown_key_in_a_body(tmp_path: Path) -> None:
    text = edit(TOP, 'mass = "m"\n', 'mass = "m"\ncolour = "red"\n')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "colour ="), "colour", "unknown key `colour`", "body `S`")


def test_unknown_key_in_the_inertia(tmp_path: Path) -> None:
    text = edit(TOP, 'diagonal = ["A", "A", "C"]', 'diag = ["A", "A", "C"]')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "inertia ="), "diag", "unknown key `diag`", "inertia")


def test_unknown_key_in_model(tmp_path: Path) -> None:
    text = edit(TOP, 'name = "Lagrange top"', 'heading = "Lagrange top"')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "heading ="), "heading", "unknown key `heading` in [model]")


def test_a_text_in_an_unknown_language(tmp_path: Path) -> None:
    text = edit(TOP, 'm = { value = 1.0, unit = "kg" }',
                'm = { value = 1.0, unit = "kg", description = { fr = "masse de (S)", de = "Masse" } }')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "m = {"), "description", "unknown language `de`")


def test_a_text_that_is_not_text(tmp_path: Path) -> None:
    text = edit(TOP, 'name = "Lagrange top"', 'name = "Lagrange top"\ntitle = { fr = 3 }')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "title ="), "title", "`title.fr` must be text")


def test_unknown_key_in_a_load(tmp_path: Path) -> None:
    text = edit(TOP, 'weight = { gravity = "-g*R0.z" }', 'weight = { gravity = "-g*R0.z", at = "O" }')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "weight ="), "at", "unknown key `at`", "load `weight`")


def test_table_that_should_be_a_table(tmp_path: Path) -> None:
    text = "parameters = 3\n\n[coordinates]\nq = 0.0\n"
    err, path = error_of(tmp_path, text)
    check(err, path, 1, None, "`parameters` must be a table")


# -- points ----------------------------------------------------------------------------------------
def test_point_defined_in_terms_of_itself(tmp_path: Path) -> None:
    text = edit(TOP, "[bodies.S]", '[points]\nP = { from = "P", position = "a*R.x" }\n\n[bodies.S]')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "P = {"), "P", "point `P` is defined in terms of itself")


def test_points_defined_in_terms_of_each_other(tmp_path: Path) -> None:
    text = edit(TOP, "[bodies.S]", '[points]\nP = { from = "Q", position = "a*R.x" }\n'
                'Q = { from = "P", position = "a*R.y" }\n\n[bodies.S]')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "P = {"), "P", "`P` → `Q` → `P`", "in terms of each other")


def test_point_from_unknown_point(tmp_path: Path) -> None:
    text = edit(TOP, "[bodies.S]", '[points]\nP = { from = "Z", position = "a*R.x" }\n\n[bodies.S]')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "P = {"), "Z", "unknown point `Z`")


def test_point_without_position(tmp_path: Path) -> None:
    text = edit(TOP, "[bodies.S]", '[points]\nP = { from = "O" }\n\n[bodies.S]')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "P = {"), "P", "point `P` has no position")


# -- loads -----------------------------------------------------------------------------------------
def test_load_on_unknown_point(tmp_path: Path) -> None:
    text = TOP + 'push = { force = "m*g*R0.x", at = "Z" }\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "push ="), "Z", "load `push`", "unknown point `Z`")


def test_force_at_a_list(tmp_path: Path) -> None:
    text = TOP + 'push = { force = "m*g*R0.x", at = ["S"] }\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "push ="), "push", "must be a name")


def test_gravity_on_unknown_body(tmp_path: Path) -> None:
    text = edit(TOP, 'weight = { gravity = "-g*R0.z" }', 'weight = { gravity = "-g*R0.z", on = ["S", "T"] }')
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "weight ="), "T", "unknown body or particle `T`")


def test_torque_on_unknown_body(tmp_path: Path) -> None:
    text = TOP + 'motor = { torque = "C*R.z", on = "S2" }\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "motor ="), "S2", "torque `motor`", "unknown body or frame `S2`")


def test_spring_with_three_ends(tmp_path: Path) -> None:
    text = edit(TOP, "C = 0.01\n", "C = 0.01\nk = 10.0\n")
    text = edit(text, "[bodies.S]", '[points]\nP = "a*R0.x"\nQ = "a*R0.y"\n\n[bodies.S]')
    text += 'spring = { spring = ["S", "P", "Q"], stiffness = "k" }\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "spring = {"), "spring", "must join exactly two points", "3")


@pytest.mark.parametrize("ends", ["3", "{ a = 1 }", '["S", 2]'])
def test_spring_ends_that_are_not_names(tmp_path: Path, ends: str) -> None:
    text = TOP + f'spring = {{ spring = {ends}, stiffness = "m" }}\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "spring = {"), "spring", "list of names")


def test_spring_without_stiffness(tmp_path: Path) -> None:
    text = TOP + 'spring = { spring = ["S", "O"] }\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "spring = {"), "spring", "needs `stiffness`")


def test_load_of_no_known_kind(tmp_path: Path) -> None:
    text = TOP + 'push = { pull = "m*g*R0.x" }\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "push ="), "push", "exactly one of the keys")


def test_generalized_force_on_a_non_coordinate(tmp_path: Path) -> None:
    text = TOP + 'drag = { generalized_force = { x = "-a*psi_dot" } }\n'
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "drag ="), "x", "not a coordinate")


# -- values ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("value", ['"nine"', "[9.81]", "{ value = \"9.81\" }", "true", "inf", "nan"])
def test_parameter_value_that_is_not_a_number(tmp_path: Path, value: str) -> None:
    text = edit(TOP, "g = 9.81", f"g = {value}")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, f"g = {value}"), "g", "value of parameter `g`", "number")


def test_parameter_without_value_is_symbolic(tmp_path: Path) -> None:
    text = edit(TOP, "g = 9.81", "g = {}")
    model = lagrangian.load_model(write(tmp_path, text))
    assert model.parameter_values["g"] is None


@pytest.mark.parametrize("value", ['{ initial = "zero" }', "{ rate = inf }", '{ momentum = 3 }'])
def test_bad_coordinate_values(tmp_path: Path, value: str) -> None:
    text = edit(TOP, "theta = { initial = 0.5, rate = 0.0 }", f"theta = {value}")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "theta = {"), "theta", "coordinate `theta`")


def test_model_name_that_is_not_text(tmp_path: Path) -> None:
    text = edit(TOP, 'name = "Lagrange top"', "name = 3")
    err, path = error_of(tmp_path, text)
    check(err, path, line_of(text, "name = 3"), "name", "must be text")


# -- files -----------------------------------------------------------------------------------------
def test_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "nope.toml"
    with pytest.raises(ModelError) as info:
        lagrangian.load_model(path)
    assert info.value.file == str(path) and info.value.fix and "does not exist" in info.value.message


def test_file_that_is_not_utf8(tmp_path: Path) -> None:
    path = tmp_path / "latin1.toml"
    path.write_bytes(TOP.replace("Lagrange top", "toupie é").encode("latin-1"))
    with pytest.raises(ModelError) as info:
        lagrangian.load_model(path)
    assert info.value.file == str(path) and "cannot read" in info.value.message


def test_parse_model_names_its_source() -> None:
    with pytest.raises(ModelError) as info:
        lagrangian.parse_model(edit(TOP, "g = 9.81", "g = ="), source="<text>")
    assert info.value.file == "<text>" and info.value.line == line_of(TOP, "g = 9.81")


# -- never a traceback ------------------------------------------------------------------------------
def _load_and_derive(text: str, path: Path) -> None:
    path.write_text(text, encoding="utf-8")
    try:
        lagrangian.derive(lagrangian.load_model(path))
    except ModelError as err:
        assert err.file == str(path) and err.message and err.fix, f"incomplete error: {err!r}"
    except LagrangianError:
        pass  # kinematics or derivation refused the (well-formed) model: still a clear error


@pytest.mark.parametrize("number", range(1, len(TOP.splitlines()) + 1))
def test_any_line_removed_gives_a_model_or_a_model_error(tmp_path: Path, number: int) -> None:
    lines = TOP.splitlines()
    _load_and_derive("\n".join(lines[: number - 1] + lines[number:]) + "\n", tmp_path / "cut.toml")


@pytest.mark.parametrize("number", range(1, len(TOP.splitlines()) + 1))
def test_any_line_duplicated_gives_a_model_or_a_model_error(tmp_path: Path, number: int) -> None:
    lines = TOP.splitlines()
    _load_and_derive("\n".join(lines[:number] + lines[number - 1:]) + "\n", tmp_path / "twice.toml")


_STRINGS = sorted(set(re.findall(r'"([^"]*)"', TOP)))
_GARBAGE = ["", "R0", "R0.x", "1/0", "m*R0.x", "(", "x", "O", "S", "9^9^9", "sin", "pi", "t", "3", "-1"]


@pytest.mark.parametrize("original", _STRINGS)
def test_any_string_replaced_gives_a_model_or_a_model_error(tmp_path: Path, original: str) -> None:
    for garbage in _GARBAGE:
        text = TOP.replace(f'"{original}"', f'"{garbage}"', 1)
        _load_and_derive(text, tmp_path / "garbage.toml")
