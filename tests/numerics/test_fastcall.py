"""`CompiledSystem.rhs_c`: the vectorcall wrapper gives the batch path's ẏ and refuses bad arrays.

The wrapper (`numerics/_fastcall.c`) is handed a raw C function address and reads the
arrays' memory directly, so what it accepts must be exactly what the C expects: contiguous
float64 arrays of the right lengths.
"""

import numpy as np
import pytest

import lagrangian
from lagrangian.model.zoo import lagrange_top, planar_chain
from lagrangian.numerics import compile_system


@pytest.fixture(scope="module")
def top():
    return compile_system(lagrangian.derive(lagrange_top()))


def test_the_wrapper_is_used_where_it_builds(top):
    assert "rhs_c" in vars(top), "the vectorcall wrapper did not build (Python.h or NumPy headers missing?)"
    assert type(top.rhs_c).__name__ == "RhsCaller"


@pytest.mark.slow
@pytest.mark.parametrize("make", [lagrange_top, lambda: planar_chain(4)], ids=["top", "chain4"])
def test_one_state_equals_the_batch_and_the_ctypes_path(make):
    system = compile_system(lagrangian.derive(make()))
    p = system.parameter_vector()
    rng = np.random.default_rng(3)
    Y = rng.uniform(0.3, 1.2, size=(16, 2 * system.n))
    batch = system.rhs(0.4, Y, p)
    by_ctypes = type(system).rhs_c.__get__(system)
    for y, expected in zip(Y, batch, strict=True):
        out, out_ctypes = np.empty_like(y), np.empty_like(y)
        assert system.rhs_c(0.4, y, p, out) == 0
        assert by_ctypes(0.4, y, p, out_ctypes) == 0
        np.testing.assert_array_equal(out, expected)
        np.testing.assert_array_equal(out, out_ctypes)


def test_a_singular_state_returns_the_status(top):
    p = top.parameter_vector()
    y = np.array([0.0, 0.0, 0.0, 0.1, 0.2, 3.0])  # θ = 0: Euler angles, M singular
    assert top.rhs_c(0.0, y, p, np.empty(6)) != 0


@pytest.mark.parametrize("args, error, words", [
    (lambda y, p, o: (0.0, y[:3], p, o), ValueError, "`y` holds 3 numbers, 6 are needed"),
    (lambda y, p, o: (0.0, y.astype(np.float32), p, o), TypeError, "`y` must be a contiguous float64"),
    (lambda y, p, o: (0.0, y, p[:2], o), ValueError, "`p` holds 2 numbers"),
    (lambda y, p, o: (0.0, y, p, np.empty(12)[::2]), TypeError, "`out` must be a contiguous, writable"),
    (lambda y, p, o: (0.0, list(y), p, o), TypeError, "`y` must be a NumPy array"),
    (lambda y, p, o: ("t", y, p, o), TypeError, "must be real number"),
    (lambda y, p, o: (0.0, y, p), TypeError, "exactly 4 positional arguments"),
])
def test_bad_arrays_are_refused_before_the_c_runs(top, args, error, words):
    y, p, out = np.full(6, 0.5), top.parameter_vector(), np.empty(6)
    frozen = out.copy()
    readonly = np.empty(6)
    readonly.flags.writeable = False
    with pytest.raises(error, match=words):
        top.rhs_c(*args(y, p, out))
    with pytest.raises(TypeError, match="writable"):
        top.rhs_c(0.0, y, p, readonly)
    np.testing.assert_array_equal(np.isnan(out), np.isnan(frozen))


@pytest.mark.slow
def test_the_wrapper_keeps_its_library_alive():
    """Holding rhs_c alone (the CompiledSystem gone) keeps the code it calls loaded."""
    import gc
    import sys

    system = compile_system(lagrangian.derive(lagrange_top()))
    f, p = system.rhs_c, system.parameter_vector()
    library = system._lib
    before = sys.getrefcount(library)
    del system, library
    gc.collect()
    out = np.empty(6)
    assert f(0.0, np.full(6, 0.5), p, out) == 0 and np.isfinite(out).all()
    assert before >= 3  # the system's attribute, the wrapper's owner, and getrefcount's argument
