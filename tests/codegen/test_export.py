"""Code export (`lagrangian.export`, ``lagrangian export``): the written NumPy module and C library
reproduce the in-package q̈ = M⁻¹F (`CompiledSystem.rhs`) at random states, and bad input
writes nothing."""

from __future__ import annotations

import ctypes
import functools
import importlib.util
import os
import re
import shutil
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR, Numeric, mutated_example, random_states

import lagrangian
from lagrangian.cli.main import main
from lagrangian.codegen import model_identifier
from lagrangian.model import zoo
from lagrangian.numerics._dae import ConstrainedSystem

# Different but exact expression forms of M and F (the in-package C hoists and regroups them):
# the results agree to rounding, amplified at most by M's condition number at these states.
RTOL = 1e-12

CASES = ["lagrange_top.toml", "double_pendulum.toml", "kapitza_pendulum.toml", "block_on_belt.toml",
         "zoo:planar_chain:5"]


@functools.cache
def _eom(case: str) -> lagrangian.EquationsOfMotion:
    model = zoo.planar_chain(5) if case == "zoo:planar_chain:5" else lagrangian.load_model(EXAMPLES_DIR / case)
    return lagrangian.derive(model)


@functools.cache
def _system(case: str) -> lagrangian.CompiledSystem:
    return lagrangian.CompiledSystem(_eom(case), integrals=())


def _states(case: str, count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(t, y) of ``count`` random states, y in the exported state order."""
    eom = _eom(case)
    names = random_states(case, eom.coordinates, count, seed)
    y = np.array([[s[c] for c in eom.coordinates] + [s[c + "_dot"] for c in eom.coordinates] for s in names])
    t = np.random.default_rng(seed).uniform(0.0, 2.0, count)
    return t, y


def _reference(case: str, t: np.ndarray, y: np.ndarray) -> np.ndarray:
    system = _system(case)
    return np.array([system.rhs(ti, yi, system.parameter_vector()) for ti, yi in zip(t, y, strict=True)])


def _assert_close(actual: np.ndarray, expected: np.ndarray) -> None:
    scale = np.max(np.abs(expected), axis=-1, keepdims=True)
    np.testing.assert_allclose(actual, expected, rtol=RTOL, atol=RTOL * float(np.max(scale)))


def _import(path: Path):
    spec = importlib.util.spec_from_file_location(f"exported_{path.stem}_{id(path)}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES)
def test_numpy_export_reproduces_the_package(case, tmp_path):
    eom = _eom(case)
    (path,) = lagrangian.export(eom, "numpy", tmp_path / "out")
    module = _import(path)
    assert module.STATE == (*eom.coordinates, *(c + "_dot" for c in eom.coordinates))
    assert list(module.PARAMETERS) == [p.name for p in eom.model.parameters]
    t, y = _states(case, 12, seed=3)
    expected = _reference(case, t, y)
    for ti, yi, ei in zip(t, y, expected, strict=True):  # one state at a time
        _assert_close(module.rhs(ti, yi), ei)
    _assert_close(module.rhs(t, y), expected)  # batched: (N, 2n), t of shape (N,)
    n = len(eom.q)
    M = module.mass_matrix(y[:, :n], None, t)
    assert M.shape == (len(y), n, n)
    np.testing.assert_allclose(M, np.swapaxes(M, -1, -2), rtol=0, atol=0)


def test_an_angle_abs_theta_is_exported_with_sign(tmp_path):
    # tools/fuzz.py seed 108, case 12549: the spherical pendulum's R2 turned by |θ|.  M and F held d|θ|/dθ,
    # which SymPy's printers cannot print; it is written sign(θ).  Where θ > 0 the model is the example
    # itself, and where θ < 0 its mirror: the exported right-hand side is the example's (θ ↦ |θ|).
    path = mutated_example(tmp_path, "spherical_pendulum.toml", 'rotation = ["theta", "x"]',
                           'rotation = ["abs(theta)", "x"]')
    (exported,) = lagrangian.export(lagrangian.derive(lagrangian.load_model(path)), "numpy", tmp_path / "out")
    module = _import(exported)
    (plain,) = lagrangian.export(_eom("spherical_pendulum.toml"), "numpy", tmp_path / "plain")
    reference = _import(plain)
    assert module.STATE == ("psi", "theta", "psi_dot", "theta_dot")
    for y in ([0.3, 0.7, 1.1, -0.4], [-1.2, 1.9, -0.5, 0.8]):
        np.testing.assert_allclose(module.rhs(0.0, np.array(y)), reference.rhs(0.0, np.array(y)), rtol=1e-13)
    mirrored = module.rhs(0.0, np.array([0.3, -0.7, 1.1, 0.4]))  # θ < 0: |θ| = −θ, d|θ|/dt = −θ̇
    expected = reference.rhs(0.0, np.array([0.3, 0.7, 1.1, -0.4]))
    np.testing.assert_allclose(mirrored, expected * np.array([1, -1, 1, -1]), rtol=1e-13)


def test_numpy_export_parameters(tmp_path):
    (path,) = lagrangian.export(_eom("double_pendulum.toml"), "numpy", tmp_path / "dp")
    module = _import(path)
    y = np.array([0.3, -0.2, 0.5, 1.0])
    base = module.rhs(0.0, y)
    p = module.parameter_array({"g": 2 * module.PARAMETERS["g"]})
    assert not np.allclose(module.rhs(0.0, y, p), base)
    np.testing.assert_array_equal(module.rhs(0.0, y, dict(module.PARAMETERS)), base)
    with pytest.raises(KeyError, match="not a parameter"):
        module.parameter_array({"nope": 1.0})


def _c_library(directory: Path, ident: str) -> ctypes.CDLL:
    lib = directory / f"lib{ident}.so"
    subprocess.run(["gcc", "-O2", "-std=c99", "-Wall", "-Wextra", "-Werror", "-shared", "-fPIC", "-o", str(lib),
                    str(directory / f"{ident}.c"), "-lm"], check=True, capture_output=True)
    return ctypes.CDLL(str(lib))


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
@pytest.mark.parametrize("case", CASES)
def test_c_export_reproduces_the_package(case, tmp_path):
    eom = _eom(case)
    paths = lagrangian.export(eom, "c", tmp_path / "out")
    header = paths[0].read_text()
    ident = paths[0].stem
    assert f"#define {ident.upper()}_N {len(eom.q)}" in header
    for name in eom.coordinates:
        assert f'"{name}_dot"' in header
    lib = _c_library(tmp_path / "out", ident)
    fn = getattr(lib, f"{ident}_rhs")
    double_p = ctypes.POINTER(ctypes.c_double)
    fn.argtypes = [ctypes.c_double, double_p, double_p, double_p]
    fn.restype = None
    p = np.array([v for v in eom.model.parameter_values.values()], dtype=float)
    t, y = _states(case, 12, seed=5)
    expected = _reference(case, t, y)
    out = np.empty(y.shape[1])
    for ti, yi, ei in zip(t, y, expected, strict=True):
        yi = np.ascontiguousarray(yi)
        fn(ti, yi.ctypes.data_as(double_p), p.ctypes.data_as(double_p), out.ctypes.data_as(double_p))
        _assert_close(out, ei)


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_c_export_nan_where_the_mass_matrix_is_not_positive_definite(tmp_path):
    eom = _eom("double_pendulum.toml")
    paths = lagrangian.export(eom, "c", tmp_path / "out")
    lib = _c_library(tmp_path / "out", paths[0].stem)
    fn = getattr(lib, f"{paths[0].stem}_rhs")
    double_p = ctypes.POINTER(ctypes.c_double)
    fn.argtypes = [ctypes.c_double, double_p, double_p, double_p]
    p = np.zeros(len(eom.model.parameters))  # every mass 0: M = 0
    y, out = np.array([0.3, -0.2, 0.5, 1.0]), np.zeros(4)
    fn(0.0, y.ctypes.data_as(double_p), p.ctypes.data_as(double_p), out.ctypes.data_as(double_p))
    assert np.all(np.isnan(out[2:])) and np.array_equal(out[:2], y[2:])


# A small C program (libm only) that reads p, Baumgarte's (alpha, beta), then (t, y) per line, and prints
# y' (rhs_k, checked equal to rhs), the first integrals, the constraint rows A, b, c, f, and, with rows,
# (y', lambda) of rhs_multipliers at (alpha, beta).
C_DRIVER = r"""
#include <stdio.h>
#include <string.h>
#include "NAME.h"
#define N2 (2 * UP_N)
static void show(const double *v, int count) { for (int i = 0; i < count; ++i) printf("%.17g ", v[i]); }
int main(void) {
    double p[UP_NP + 1], k[UP_NK + 1], y[N2], t, alpha, beta, out[N2], again[N2], I[UP_NI + 1];
    double A[UP_NC * UP_N + 1], b[UP_NC + 1], c[UP_NC + 1], f[UP_NC + 1];
    for (int i = 0; i < UP_NP; ++i) if (scanf("%lf", &p[i]) != 1) return 2;
    if (scanf("%lf %lf", &alpha, &beta) != 2) return 2;
    NAME_constants(p, k);
    while (scanf("%lf", &t) == 1) {
        for (int i = 0; i < N2; ++i) if (scanf("%lf", &y[i]) != 1) return 2;
        NAME_rhs_k(t, y, p, k, out);
        NAME_rhs(t, y, p, again);
        if (memcmp(out, again, sizeof out) != 0) return 3;
        NAME_first_integrals(t, y, p, I);
        ONE_BY_ONE
        NAME_constraint_rows(t, y, p, A, b, c, f);
        show(out, N2); show(I, UP_NI); show(A, UP_NC * UP_N); show(b, UP_NC); show(c, UP_NC); show(f, UP_NC);
#if UP_NC > 0
        double lam[UP_NC];
        if (NAME_rhs_multipliers(t, y, p, k, alpha, beta, out, lam) != 0) return 4;
        show(out, N2); show(lam, UP_NC);
#endif
        printf("\n");
    }
    return 0;
}
"""

C_DRIVER_CASES = ["lagrange_top.toml", "pendulum_tension.toml", "rolling_coin.toml", "zoo:planar_chain:5"]


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
@pytest.mark.parametrize("case", C_DRIVER_CASES)
def test_c_export_driver_integrals_and_constraint_rows(case, tmp_path):
    """A C program built on the export (gcc, libm only) against Python: y' against the package's
    compiled rhs (with the multipliers for the constrained models), the first integrals and the
    constraint rows against `first_integrals` and the derivation's rows evaluated by SymEngine."""
    eom = _eom(case)
    paths = lagrangian.export(eom, "c", tmp_path / "out")
    ident, n, rows = paths[0].stem, len(eom.q), eom.constraints
    driver = tmp_path / "out" / "driver.c"
    # Each integral's own function (declared in the header) must give the value of the array function.
    own = re.findall(r"^double (\w+)\(double t, const double \*y, const double \*p\);", paths[0].read_text(), re.M)
    assert len(own) == len(lagrangian.first_integrals(eom))
    checks = "\n        ".join(f"if (fabs({fn}(t, y, p) - I[{j}]) > 1e-13 * (1.0 + fabs(I[{j}]))) return 5;"
                      for j, fn in enumerate(own))
    driver.write_text(C_DRIVER.replace("ONE_BY_ONE", checks).replace("NAME", ident).replace("UP_", ident.upper() + "_"))
    exe = tmp_path / "driver"
    subprocess.run(["gcc", "-O2", "-std=c99", "-Wall", "-Wextra", "-Werror", "-o", str(exe), str(driver),
                    str(paths[1]), "-lm"], check=True, capture_output=True)
    p = np.array([v for v in eom.model.parameter_values.values()], dtype=float)
    stab = (2.0, 3.0)
    t, y = _states(case, 6, seed=13)
    def line(values) -> str:
        return " ".join(repr(float(v)) for v in values)

    text = line([*p, *stab]) + "\n" + "\n".join(line([ti, *yi]) for ti, yi in zip(t, y, strict=True))
    run = subprocess.run([str(exe)], input=text, capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    got = np.array([[float(v) for v in line.split()] for line in run.stdout.strip().splitlines()])
    integrals = lagrangian.first_integrals(eom)
    assert integrals and f'"{integrals[0].name}"' in paths[0].read_text()
    fi = Numeric(eom, [i.expression for i in integrals])
    A = Numeric(eom, [a for r in rows for a in r.coefficients])
    bcf = Numeric(eom, [r.b for r in rows] + [r.bias for r in rows]
                  + [r.expression if r.kind == "holonomic" else 0 for r in rows])
    if rows:
        dae = ConstrainedSystem(eom)
        exact, _ = dae.rhs(t, y, dae.parameter_vector())
        stabilized, lam = dae.rhs(t, y, dae.parameter_vector(), stab)
    else:
        exact = _reference(case, t, y)
    m, ni = len(rows), len(integrals)
    for k, (ti, yi) in enumerate(zip(t, y, strict=True)):
        state = {**{c: v for c, v in zip(eom.coordinates, yi[:n], strict=True)},
                 **{c + "_dot": v for c, v in zip(eom.coordinates, yi[n:], strict=True)}, str(eom.t): ti}
        parts = np.split(got[k], np.cumsum([2 * n, ni, m * n, 3 * m, 2 * n]))
        assert len(got[k]) == 2 * n + ni + (m * n + 3 * m + 2 * n + m if m else 0)
        _assert_close(parts[0], exact[k])
        _assert_close(parts[1], fi(state))
        if rows:
            _assert_close(np.concatenate([parts[2], parts[3]]), np.concatenate([A(state), bcf(state)]))
            _assert_close(parts[4], stabilized[k])
            _assert_close(parts[5], lam[k])


# -- bad input: a clear error, nothing written ------------------------------------------------
def test_unknown_target(tmp_path):
    with pytest.raises(lagrangian.ExportError, match="`fortran` is not an export target") as info:
        lagrangian.export(_eom("double_pendulum.toml"), "fortran", tmp_path / "out")
    assert "numpy" in info.value.fix
    assert not any(tmp_path.iterdir())


def test_unwritable_directory(tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    with pytest.raises(lagrangian.OutputError, match="Cannot write the export directory"):
        lagrangian.export(_eom("double_pendulum.toml"), "numpy", blocker / "out")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file"]


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="needs a non-root POSIX user")
def test_read_only_parent(tmp_path):
    parent = tmp_path / "ro"
    parent.mkdir()
    parent.chmod(0o500)
    try:
        with pytest.raises(lagrangian.OutputError, match="nothing was written"):
            lagrangian.export(_eom("double_pendulum.toml"), "c", parent / "out")
        assert not any(parent.iterdir())
    finally:
        parent.chmod(0o700)


def test_failure_mid_write_leaves_nothing(tmp_path, monkeypatch):
    calls = []
    original = Path.write_text

    def failing(self, *args, **kwargs):
        calls.append(self)
        if len(calls) == 2:
            raise OSError(28, "No space left on device")
        return original(self, *args, **kwargs)

    monkeypatch.setattr(Path, "write_text", failing)
    with pytest.raises(lagrangian.OutputError, match="No space left"):
        lagrangian.export(_eom("double_pendulum.toml"), "c", tmp_path / "out")
    assert not any(tmp_path.iterdir())


def test_existing_directory(tmp_path):
    eom = _eom("double_pendulum.toml")
    out = tmp_path / "out"
    first = lagrangian.export(eom, "numpy", out)
    first[0].write_text("stale")
    second = lagrangian.export(eom, "numpy", out)  # an earlier export of the same files is replaced
    assert first == second and "stale" not in second[0].read_text()
    (out / "notes.txt").write_text("mine")
    with pytest.raises(lagrangian.OutputError, match="notes.txt"):
        lagrangian.export(eom, "numpy", out)
    assert (out / "notes.txt").read_text() == "mine" and second[0].read_text() != "stale"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_stick_slip_models_are_refused(tmp_path):
    text = (EXAMPLES_DIR / "block_on_belt.toml").read_text().replace('regularization = "eps"', 'regularization = 0')
    belt = lagrangian.derive(lagrangian.parse_model(text))
    with pytest.raises(lagrangian.ExportError, match="stick/slip") as info:
        lagrangian.export(belt, "c", tmp_path / "belt")
    assert "regularization" in info.value.fix
    assert not any(tmp_path.iterdir())


CONSTRAINED_CASES = ["pendulum_tension.toml", "rolling_coin.toml", "rolling_disk_incline.toml"]


@pytest.mark.slow
@pytest.mark.parametrize("case", CONSTRAINED_CASES)
def test_numpy_export_of_a_constrained_model_solves_for_the_multipliers(case, tmp_path):
    """The NumPy module's rhs and rhs_multipliers (augmented solve, numpy.linalg) against the package's
    constrained system (`numerics._dae`, Schur complement in its own code), exact and with Baumgarte's
    stabilisation; its constraint rows against the derivation's rows evaluated by SymEngine."""
    eom = _eom(case)
    (path,) = lagrangian.export(eom, "numpy", tmp_path / "out")
    module = _import(path)
    rows = eom.constraints
    assert module.CONSTRAINTS == tuple((r.name, r.kind, str(r.multiplier)) for r in rows)
    dae = ConstrainedSystem(eom)
    t, y = _states(case, 8, seed=5)
    exact, _ = dae.rhs(t, y, dae.parameter_vector())
    stabilized, lam = dae.rhs(t, y, dae.parameter_vector(), (2.0, 3.0))
    _assert_close(module.rhs(t, y), exact)
    _assert_close(module.rhs(t[0], y[0]), exact[0])  # one state
    got, got_lam = module.rhs_multipliers(t, y, None, 2.0, 3.0)
    _assert_close(got, stabilized)
    _assert_close(got_lam, lam)
    n, m = len(eom.q), len(rows)
    A, b, c, f = module.constraint_rows(t, y[:, :n], y[:, n:])
    assert A.shape == (len(y), m, n) and b.shape == c.shape == f.shape == (len(y), m)
    rows_at = Numeric(eom, [a for r in rows for a in r.coefficients] + [r.b for r in rows] + [r.bias for r in rows]
                      + [r.expression if r.kind == "holonomic" else 0 for r in rows])
    for k, (ti, yi) in enumerate(zip(t, y, strict=True)):
        state = {**dict(zip(eom.coordinates, yi[:n], strict=True)), **{c_ + "_dot": v for c_, v in zip(eom.coordinates, yi[n:], strict=True)},
                 str(eom.t): ti}
        _assert_close(np.concatenate([A[k].ravel(), b[k], c[k], f[k]]), rows_at(state))


def _jax_and_numpy(case: str, tmp_path: Path):  # type: ignore[no-untyped-def]
    """JAX in double precision (skipped without it), the case's derivation, its JAX and NumPy exports."""
    jax = pytest.importorskip("jax")
    jax.config.update("jax_enable_x64", True)
    eom = _eom(case)
    (path,) = lagrangian.export(eom, "jax", tmp_path / "jax")
    (np_path,) = lagrangian.export(eom, "numpy", tmp_path / "np")
    return jax, eom, _import(path), _import(np_path)


@pytest.mark.slow
@pytest.mark.parametrize("case", ["pendulum_tension.toml", "rolling_coin.toml"])
def test_jax_export_of_a_constrained_model(case, tmp_path):
    jax, _, module, reference = _jax_and_numpy(case, tmp_path)
    t, y = _states(case, 6, seed=9)
    p = reference.parameter_array()
    f = jax.jit(jax.vmap(lambda ti, yi: module.rhs_multipliers(ti, yi, p, 2.0, 3.0)))
    got, lam = f(t, y)
    expected, expected_lam = reference.rhs_multipliers(t, y, p, 2.0, 3.0)
    _assert_close(np.asarray(got), expected)
    _assert_close(np.asarray(lam), expected_lam)
    _assert_close(np.asarray(jax.jit(module.rhs)(t, y)), reference.rhs(t, y))


@pytest.mark.octave
@pytest.mark.skipif(shutil.which("octave") is None, reason="needs GNU Octave (make test installs it)")
@pytest.mark.parametrize("case", ["pendulum_tension.toml", "rolling_coin.toml"])
def test_octave_export_of_a_constrained_model_runs(case, tmp_path):
    eom = _eom(case)
    lagrangian.export(eom, "octave", tmp_path / "out")
    (np_path,) = lagrangian.export(eom, "numpy", tmp_path / "np")
    reference = _import(np_path)
    ident = model_identifier(eom.model.name)
    t, y = _states(case, 3, seed=17)

    def column(v) -> str:
        return "[" + "; ".join(repr(float(x)) for x in v) + "]"

    calls = "".join(f"[yd, lam] = {ident}_rhs_multipliers({float(ti)!r}, {column(yi)}, d, 2, 3); "
                    f"disp(num2str([yd; lam]', 17)); disp(num2str({ident}_rhs({float(ti)!r}, {column(yi)}, d)', 17));"
                    for ti, yi in zip(t, y, strict=True))
    script = f"addpath('{tmp_path / 'out'}'); [n, d] = {ident}_parameters(); {calls}"
    run = subprocess.run(["octave", "--no-gui", "--quiet", "--no-window-system", "--eval", script],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    lines = [np.array([float(v) for v in line.split()]) for line in run.stdout.strip().splitlines()]
    stabilized, lam = reference.rhs_multipliers(t, y, None, 2.0, 3.0)
    exact = reference.rhs(t, y)
    for k in range(len(t)):
        _assert_close(lines[2 * k], np.concatenate([stabilized[k], lam[k]]))
        _assert_close(lines[2 * k + 1], exact[k])


# -- command line -------------------------------------------------------------------------------
def test_cli_export(tmp_path, capsys):
    assert main(["export", "zoo:planar_chain:2", "--to", "numpy", "-o", str(tmp_path / "chain"), "--set", "g=1.5"]) == 0
    assert "wrote" in capsys.readouterr().out
    (path,) = (tmp_path / "chain").iterdir()
    assert _import(path).PARAMETERS["g"] == 1.5


@pytest.mark.slow
def test_cli_exports_a_constrained_model_to_c(tmp_path, capsys):
    assert main(["export", str(EXAMPLES_DIR / "rolling_coin.toml"), "--to", "c", "-o", str(tmp_path / "coin")]) == 0
    header = (tmp_path / "coin" / "rolling_upright_coin.h").read_text()
    assert "#define ROLLING_UPRIGHT_COIN_NC 2" in header and "rolling_upright_coin_rhs_multipliers(" in header


@pytest.mark.slow
def test_cli_default_directory(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["export", str(EXAMPLES_DIR / "double_pendulum.toml"), "--to", "c"]) == 0
    (folder,) = tmp_path.iterdir()
    assert folder.name.endswith("_c") and len(list(folder.iterdir())) == 2


@pytest.mark.parametrize(("argv", "code", "message"), [
    (["--to", "fortran"], 2, "`fortran` is not an export target"),
    (["--to", "numpy", "--set", "theta=1"], 2, "no initial state"),
    (["--to", "numpy", "-o", "{tmp}/a_file/out"], 3, "Cannot write the export directory"),
    ([str(EXAMPLES_DIR / "block_on_incline.toml"), "--to", "numpy"], 2, "stick/slip"),
])
def test_cli_errors(argv, code, message, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a_file").write_text("x")
    assert main(["export", *(a.replace("{tmp}", str(tmp_path)) for a in argv)]) == code
    err = capsys.readouterr().err
    assert message in err and "tip:" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file"]


# -- jax: with JAX when it is installed; else its logic run on a stand-in `jax` whose `jax.numpy` is NumPy ----
@pytest.mark.parametrize("case", ["lagrange_top.toml", "kapitza_pendulum.toml", "zoo:planar_chain:5"])
def test_jax_export_logic_on_numpy(case, tmp_path, monkeypatch):
    if importlib.util.find_spec("jax") is not None:
        pytest.skip("JAX is installed: test_jax_export runs it for real")
    fake = types.ModuleType("jax")
    fake.numpy = np
    monkeypatch.setitem(sys.modules, "jax", fake)  # removed again after the test
    monkeypatch.setitem(sys.modules, "jax.numpy", np)
    (path,) = lagrangian.export(_eom(case), "jax", tmp_path / "out")
    module = _import(path)
    t, y = _states(case, 8, seed=7)
    expected = _reference(case, t, y)
    _assert_close(module.rhs(t, y), expected)
    _assert_close(module.rhs(t[0], y[0]), expected[0])


@pytest.mark.slow
@pytest.mark.parametrize("case", ["lagrange_top.toml", "kapitza_pendulum.toml"])
def test_jax_export(case, tmp_path):
    """JAX itself (the `jax` extra, in `test`): rhs, mass_matrix and forcing jitted and vmapped in
    double precision, against the NumPy export and the package to 1e-12."""
    jax, eom, module, reference = _jax_and_numpy(case, tmp_path)
    t, y = _states(case, 8, seed=7)
    n, p = len(eom.q), reference.parameter_array()
    expected = reference.rhs(t, y, p)
    _assert_close(expected, _reference(case, t, y))
    f = jax.jit(jax.vmap(module.rhs, in_axes=(0, 0, None)))
    actual = f(t, y, p)
    assert actual.dtype == np.float64 and actual.shape == y.shape
    _assert_close(np.asarray(actual), expected)
    _assert_close(np.asarray(jax.jit(module.rhs)(t, y)), expected)  # batched without vmap
    M = jax.jit(jax.vmap(module.mass_matrix, in_axes=(0, None, 0)))(y[:, :n], p, t)
    np.testing.assert_allclose(np.asarray(M), reference.mass_matrix(y[:, :n], p, t), rtol=RTOL, atol=1e-14)
    F = jax.jit(jax.vmap(module.forcing, in_axes=(0, 0, 0, None)))(t, y[:, :n], y[:, n:], p)
    _assert_close(np.asarray(F), reference.forcing(t, y[:, :n], y[:, n:], p))


# -- octave: run by GNU Octave when installed; else a check of the files' structure and tokens -------
OCTAVE_WORDS = {"function", "end", "zeros", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh",
                "exp", "log", "sqrt", "abs", "sign", "pi", "NaN", "t", "y", "p", "M", "F", "names", "defaults",
                "ydot"}


@pytest.mark.parametrize("case", ["lagrange_top.toml", "kapitza_pendulum.toml", "block_on_belt.toml"])
def test_octave_export_structure(case, tmp_path):
    eom = _eom(case)
    paths = lagrangian.export(eom, "octave", tmp_path / "out")
    ident = paths[0].name.removesuffix("_parameters.m")
    assert [p.name for p in paths] == [f"{ident}_{f}.m" for f in ("parameters", "mass_matrix", "forcing", "rhs")]
    for path in paths:
        lines = path.read_text().splitlines()
        assert lines[0].startswith("function ") and f"= {path.stem}(" in lines[0] and lines[-1] == "end"
        code = [line.split("%")[0] for line in lines[1:-1] if not line.lstrip().startswith("%")]
        for line in code:
            if "'" in line:  # the names' cell array in _parameters
                continue
            assert line.count("(") == line.count(")") and line.count("[") == line.count("]"), line
            assert not line.strip() or line.rstrip().endswith(";"), line
            words = set(re.findall(r"[A-Za-z_]\w*", line))
            own = {f"{ident}_mass_matrix", f"{ident}_forcing"}  # what _rhs calls
            assert words <= OCTAVE_WORDS | own | {w for w in words if re.fullmatch(r"[xyp]_\d+", w)}, line
    assert f"names = {{{', '.join(repr(p.name) for p in eom.model.parameters)}}};" in paths[0].read_text()


@pytest.mark.octave
@pytest.mark.skipif(shutil.which("octave") is None, reason="GNU Octave is not installed")
@pytest.mark.parametrize("case", ["lagrange_top.toml", "zoo:planar_chain:5"])
def test_octave_export_runs(case, tmp_path):
    eom = _eom(case)
    paths = lagrangian.export(eom, "octave", tmp_path / "out")
    ident = paths[0].name.removesuffix("_parameters.m")
    t, y = _states(case, 4, seed=11)
    expected = _reference(case, t, y)
    calls = "".join(f"disp(num2str({ident}_rhs({float(ti)!r}, [{'; '.join(repr(float(v)) for v in yi)}], d)', 17));"
                    for ti, yi in zip(t, y, strict=True))
    script = f"addpath('{tmp_path / 'out'}'); [n, d] = {ident}_parameters(); {calls}"
    run = subprocess.run(["octave", "--no-gui", "--quiet", "--no-window-system", "--eval", script],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    out = run.stdout
    actual = np.array([[float(v) for v in line.split()] for line in out.strip().splitlines()])
    _assert_close(actual, expected)
