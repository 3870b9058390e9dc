"""The generated C evaluates exactly the engine's M and F (and monitors), whatever it rewrote.

Code generation rewrites the expressions for speed — sin/cos of angle sums expanded, M's
terms collected, each body's γ⁰ and dσ⁰/dt named once, parameter-only parts hoisted — so
it is checked against SymEngine evaluating ``eom.M`` and ``eom.F`` as derived.
"""

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.codegen import c_expression
from lagrangian.codegen._rewrite import collect_by_state, expand_angle_sums
from lagrangian.model.zoo import planar_chain
from lagrangian.numerics import compile_system

MODELS = {p.stem: p for p in sorted(EXAMPLES_DIR.glob("*.toml"))}


def _model(name):
    return planar_chain(7) if name == "planar_chain_7" else lagrangian.load_model(MODELS[name])


@pytest.mark.slow
@pytest.mark.parametrize("name", [*MODELS, "planar_chain_7"])
def test_compiled_c_equals_the_derived_expressions(name):
    model = _model(name)
    eom = lagrangian.derive(model)
    if eom.constraints:
        pytest.skip("complementary constraints are simulated by the DAE path")
    fast, plain = compile_system(eom), compile_system(eom, backend="symengine")
    values = {k: 0.7 for k, v in model.parameter_values.items() if v is None}
    p_fast, p_plain = fast.parameter_vector(values), plain.parameter_vector(values)
    Y = np.random.default_rng(5).uniform(-1.5, 1.5, size=(40, 2 * fast.n))
    M1, F1 = fast.mass_forces(0.37, Y, p_fast)
    M2, F2 = plain.mass_forces(0.37, Y, p_plain)
    np.testing.assert_allclose(M1, M2, rtol=1e-12, atol=1e-12 * np.abs(M2).max())
    np.testing.assert_allclose(F1, F2, rtol=1e-11, atol=1e-12 * np.abs(F2).max())
    np.testing.assert_allclose(fast.monitor_values(0.37, Y, p_fast), plain.monitor_values(0.37, Y, p_plain),
                               rtol=1e-11, atol=1e-12)


def test_angle_sums_are_expanded_and_nothing_else():
    a, b, c, w = se.symbols("a b c w")
    e = se.cos(a - b) + se.sin(a + b + c) + se.sin(2 * a) + se.cos(a + w * b)
    (out,) = expand_angle_sums([e], [a, b, c])
    assert not any(len(atom.args[0].free_symbols) > 1 and atom.args[0] != w * b
                   for atom in out.atoms(se.sin, se.cos) if atom.args[0] not in (2 * a, a + w * b))
    assert se.sin(2 * a) in out.atoms(se.sin) and se.cos(a + w * b) in out.atoms(se.cos)
    rng = np.random.default_rng(0)
    for _ in range(5):
        point = {s: float(rng.uniform(-3, 3)) for s in (a, b, c, w)}
        assert float(out.subs(point)) == pytest.approx(float(e.subs(point)), abs=1e-13)


def test_collect_groups_terms_by_their_state_factor():
    m1, m2, l, x = se.symbols("m1 m2 l x")
    (out,) = collect_by_state([m1 * l * se.cos(x) + m2 * l * se.cos(x) + m1 * x], [x])
    assert out == (m1 * l + m2 * l) * se.cos(x) + m1 * x


def test_c_printer_writes_doubles_and_products():
    x = se.Symbol("x")
    names = {x: "x"}
    assert c_expression(x**3, names) == "(x*x*x)"
    assert c_expression(x**-2, names) == "(1.0/(x*x))"
    assert c_expression(se.Integer(10)**20 * x, names) == "(1e+20*x)"
    assert c_expression(se.sqrt(x), names) == "sqrt(x)"
    with pytest.raises(lagrangian.ModelError, match="the compiled code cannot evaluate"):
        c_expression(se.gamma(x), names)
    # d|x|/dx, which SymEngine leaves unevaluated, is sign(x); the higher derivatives are 0 (x ≠ 0).
    assert c_expression(se.Abs(x).diff(x), names) == "((x) > 0.0 ? 1.0 : ((x) < 0.0 ? -1.0 : 0.0))"
    assert c_expression(se.Abs(x).diff(x).diff(x), names) == "0.0"


def test_the_generated_source_is_the_same_at_every_compile():
    """Deriving and generating twice in one process gives the same C text (so the same cache key).

    The shared body terms were SymEngine Dummies, whose hash holds a per-process counter: the
    double pendulum's sums came out in a new order each time, the cache missed and the results
    moved by a few ulp between identical runs.
    """
    from lagrangian.codegen import generate_c

    model = lagrangian.load_model(EXAMPLES_DIR / "double_pendulum.toml")
    keys = {generate_c(lagrangian.derive(model)).key for _ in range(3)}
    assert len(keys) == 1


def test_model_names_cannot_take_the_generated_codes_leading_underscore():
    builder = lagrangian.ModelBuilder("underscore")
    with pytest.raises(lagrangian.ModelError, match="not a valid parameter name"):
        builder.parameter("_k0", 1.0)


def test_c_printer_writes_the_functions_symengine_makes_by_itself(tmp_path):
    """tan(π/2 − λ) comes back from SymEngine as cot(λ), which libm lacks (found by the fuzz campaign):
    each such function is printed through libm's and checked against SymEngine's own value."""
    import shutil
    import subprocess

    if shutil.which("gcc") is None:
        pytest.skip("gcc is not installed")
    x = se.Symbol("x")
    assert type(se.tan(se.pi / 2 - x)).__name__ == "cot"
    functions = [se.cot, se.sec, se.csc, se.coth, se.sech, se.csch, se.acot, se.asec, se.acsc, se.acoth,
                 se.asech, se.acsch, se.asinh, se.acosh, se.atanh]
    points = {"cot": 0.7, "sec": 0.7, "csc": 0.7, "coth": 0.7, "sech": 0.7, "csch": 0.7, "acot": -1.7,
              "asec": 1.7, "acsc": -1.7, "acoth": 1.7, "asech": 0.6, "acsch": -1.7, "asinh": -1.7,
              "acosh": 1.7, "atanh": 0.6}
    lines = ['#include <math.h>', '#include <stdio.h>', 'int main(void) {']
    for f in functions:
        value = points[f.__name__]
        lines.append(f'    {{ const double _x = {value!r}; printf("%.17g\\n", {c_expression(f(x), {x: "_x"})}); }}')
    lines.append("    return 0;\n}")
    (tmp_path / "f.c").write_text("\n".join(lines))
    subprocess.run(["gcc", "-O0", "-o", str(tmp_path / "f"), str(tmp_path / "f.c"), "-lm"], check=True)
    out = subprocess.run([str(tmp_path / "f")], capture_output=True, text=True, check=True).stdout.split()
    for f, text in zip(functions, out, strict=True):
        expected = float(f(se.RealDouble(points[f.__name__])))
        assert float(text) == pytest.approx(expected, rel=1e-14), f.__name__
