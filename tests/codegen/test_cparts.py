"""Long generated functions in parts, compiled as units in parallel: the same numbers as in one piece."""

import ctypes
import math

import numpy as np
import pytest

import lagrangian
from lagrangian.codegen import COLD_UNIT, _cparts
from lagrangian.codegen._cparts import PART_MACROS, function_text, units_of
from lagrangian.errors import SimulationError
from lagrangian.model.zoo import serial_arm
from lagrangian.numerics import _compile, compile_system

#: A recurrence long enough to cut: x_k = sin(x_{k-1}) + p_(k mod 3) x_{k-2}, out_j = x_{7j} y_1.
STEPS = 60
SIGNATURE = "static void lg_walk(double t, const double *y, const double *p, double *out)"
HEADER = {"_y0": "y[0]", "_y1": "y[1]", "_p0": "p[0]", "_p1": "p[1]", "_p2": "p[2]", "_t": "t"}


def _body() -> list[str]:
    lines = ["    const double x0 = _y0;", "    const double x1 = _y0*_t;"]
    lines += [f"    const double x{k} = sin(x{k - 1}) + _p{k % 3}*x{k - 2};" for k in range(2, STEPS)]
    return lines + [f"    out[{j}] = x{7 * j}*_y1;" for j in range(STEPS // 7 + 1)]


def _walk_in_python(t: float, y: list[float], p: list[float]) -> list[float]:
    x = [y[0], y[0] * t]
    for k in range(2, STEPS):
        x.append(math.sin(x[k - 1]) + p[k % 3] * x[k - 2])
    return [x[7 * j] * y[1] for j in range(STEPS // 7 + 1)]


def _library(limit: int, key: str):
    """The recurrence compiled whole (one unit) or in parts of ``limit`` statements (several units)."""
    parts: list = []
    text = function_text(SIGNATURE, HEADER, _body(), parts, limit=limit)
    entry = "void walk(double t, const double *y, const double *p, double *out) { lg_walk(t, y, p, out); }\n"
    if not parts:
        return _compile.compile_library("#include <math.h>\n" + text + entry, key), 0
    main = "\n".join(["#include <math.h>", PART_MACROS["unit"], *(part.declaration + ";" for part in parts), text,
                      entry])
    return _compile.compile_library(units_of(parts, main), key), len(parts)


@pytest.fixture
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


@pytest.mark.slow
def test_a_function_in_parts_gives_the_numbers_of_the_whole_function(private_cache):
    whole, none = _library(10_000, "walk-whole")
    cut, count = _library(9, "walk-parts")
    assert none == 0 and count == math.ceil(len(_body()) / 9)
    rng = np.random.default_rng(7)
    for _ in range(20):
        t = float(rng.uniform(-1, 1))
        y, p = rng.uniform(-1, 1, 2), rng.uniform(-0.9, 0.9, 3)
        out = [np.zeros(STEPS // 7 + 1) for _ in range(2)]
        for lib, o in zip((whole, cut), out, strict=True):
            lib.walk(ctypes.c_double(t), y.ctypes.data_as(ctypes.c_void_p), p.ctypes.data_as(ctypes.c_void_p),
                     o.ctypes.data_as(ctypes.c_void_p))
        assert np.array_equal(out[0], out[1])  # the same statements in the same order: the same doubles
        np.testing.assert_allclose(out[1], _walk_in_python(t, list(y), list(p)), rtol=1e-12, atol=1e-12)


def test_a_part_reads_earlier_parts_locals_from_their_slots():
    parts: list = []
    caller = function_text(SIGNATURE, HEADER, _body(), parts, limit=9)
    assert "double lg_w[" in caller and caller.count("lg_walk_part") == len(parts)
    # x_k needs x_{k-1} and x_{k-2}: the first statement of each later part reads two slots.
    for part in parts[1:]:
        assert "lg_w[" in part.text.split("\n")[2]
    # The arguments are read where they are used, not copied into locals.
    assert all("const double _y" not in part.text for part in parts)


def test_a_unit_the_compiler_rejects_is_an_error_naming_it(private_cache):
    with pytest.raises(SimulationError, match="rejected the generated code"):
        _compile.compile_library(["int lg_ok(void) { return 0; }\n", "this is not C\n"], "rejected")


@pytest.mark.slow
@pytest.mark.parametrize("joints, limit, cut_functions", [
    (3, 25, ("lg_mass_forces", "lg_hamilton_force")),  # the course's form: M and F by Cholesky
    (4, 80, ("lg_mass_forces", "lg_aba_backward", "lg_monitors")),  # recursive, q'' by the articulated body
])
def test_a_robot_compiled_in_parts_moves_as_compiled_in_one_piece(private_cache, monkeypatch, joints, limit,
                                                                   cut_functions):
    inputs = {"tau1": "0.5*sin(2*t)"}  # the inputs' law wraps the model's functions (`_input_code`)
    # One derivation for both: a second `derive` in a process may number SymEngine's subexpressions
    # otherwise (the same equations, other C).
    eom = lagrangian.derive(serial_arm(joints))
    whole = compile_system(eom, inputs=inputs)
    # Another cache: the first build's plan (`_plans`) would otherwise give its library to the second.
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(private_cache.parent / "cache-parts"))
    monkeypatch.setattr(_cparts, "MAX_STATEMENTS", limit)
    cut = compile_system(eom, inputs=inputs)
    assert all(f"{name}_part1(" in cut.source for name in cut_functions)
    # The monitors' and constants' parts are cold (-Og), and give the same doubles all the same (below).
    cold = sum(unit.startswith(COLD_UNIT) for unit in cut.generated.units)
    assert cold == cut.source.count("LG_PART void lg_monitors_part") + cut.source.count("LG_PART void lg_constants_part")
    assert cold > 0
    assert "_part0(" not in whole.source
    n = joints
    rng = np.random.default_rng(3)
    Y = np.hstack([rng.uniform(-np.pi, np.pi, (50, n)), rng.uniform(-2, 2, (50, n))])
    T = rng.uniform(0, 5, 50)
    p = whole.parameter_vector()
    assert np.array_equal(p, cut.parameter_vector(), equal_nan=True)  # lg_constants, in parts too (NaN: the law's hint)
    # The same statements in the same order: the same doubles, to the last bit.
    assert np.array_equal(whole.rhs(T, Y, p), cut.rhs(T, Y, p))
    for a, b in zip(whole.mass_forces(T, Y, p), cut.mass_forces(T, Y, p), strict=True):
        assert np.array_equal(a, b)
    assert np.array_equal(whole.monitor_values(T, Y, p), cut.monitor_values(T, Y, p))
    assert np.array_equal(whole.input_values(T, Y, p), cut.input_values(T, Y, p))
    for method in ("dop853", "gauss-legendre"):  # Hamilton's form: lg_hamilton_mass and _force
        a, b = (lagrangian.simulate(s, 0.5, n_out=6, method=method, dt=1e-3 if method != "dop853" else None)
                for s in (whole, cut))
        assert np.array_equal(a.q, b.q) and np.array_equal(a.qd, b.qd)
