"""The C runtime: plain files copied whole into the compiled simulation and into the C export."""

from __future__ import annotations

import pytest
from lagrangian_test_support import eom_of

import lagrangian
from lagrangian.codegen import RUNTIME_FILES, export_files, generate_c, generate_dae_c, runtime_source


@pytest.fixture(scope="module")
def top() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.lagrange_top())


def test_every_runtime_file_is_plain_c_with_its_opening_comment():
    for name in RUNTIME_FILES:
        text = runtime_source(name)
        assert text.startswith("/* lagrangian runtime: "), name
        assert "\r" not in text and text.endswith("\n"), name
    with pytest.raises(ValueError, match="not a runtime file"):
        runtime_source("../_codegen.py")


def test_the_compiled_simulation_holds_the_runtime_whole(top):
    source = generate_c(top).source
    solve, integrators = runtime_source("solve_mass.c"), runtime_source("integrators.c")
    # Whole and in order: the integrators call lg_cholesky_solve, defined before them.
    assert source.index(solve) < source.index(integrators)
    assert source.endswith(integrators)


def test_the_constrained_code_holds_cholesky_and_dae_whole():
    eom = eom_of("sliding_ladder.toml")
    assert eom.constraints
    source = generate_dae_c(eom, [eom.T], []).source
    assert source.endswith(runtime_source("cholesky.c") + "\n" + runtime_source("dae.c"))


def test_the_c_export_copies_the_same_solve(top):
    (source,) = [text for name, text in export_files(top, "c").items() if name.endswith(".c")]
    # The package's own routine, with its n the export's: no renaming, no cutting.
    assert "#define LG_N LAGRANGE_TOP_N\n" + runtime_source("solve_mass.c") in source
    assert runtime_source("cholesky.c") not in source  # unused static functions would fail -Werror

    constrained = eom_of("sliding_ladder.toml")
    (source,) = [text for name, text in export_files(constrained, "c").items() if name.endswith(".c")]
    assert runtime_source("cholesky.c") in source
    assert runtime_source("solve_mass.c") not in source


def test_dop853s_tableau_is_scipys_and_is_read_without_importing_scipy_integrate():
    import subprocess
    import sys

    from scipy.integrate._ivp import dop853_coefficients as scipy_tableau

    from lagrangian.codegen._runtime import _scipy_dop853_coefficients

    alone = _scipy_dop853_coefficients()
    assert alone is not scipy_tableau and alone.N_STAGES == scipy_tableau.N_STAGES
    for name in ("A", "B", "C", "E3", "E5", "D"):
        assert (getattr(alone, name) == getattr(scipy_tableau, name)).all(), name
    # A model compiled for the first time does not wait for SciPy's integrators to import (0.4 s).
    probe = ("import sys; from lagrangian.codegen._runtime import dop853_defines; d = dop853_defines(); "
             "print('scipy.integrate' in sys.modules, d['LG_DOP_STAGES'])")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, timeout=120)
    assert out.stdout.split() == ["False", str(scipy_tableau.N_STAGES)]
