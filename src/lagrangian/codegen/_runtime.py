"""The C runtime: the model-independent C files that generated code is compiled with.

The files in ``runtime/`` are plain C, each copied whole after the generated functions it
calls (never cut apart):

- ``solve_mass.c``: M x = F by Cholesky for the model's n (``LG_N``), the integrators' solve and
  the C export's;
- ``integrators.c``: DOP853 (its step-size control written once, for the sensitivities too) and the
  Gauss-Legendre method, events, ensembles (`_codegen`);
- ``cholesky.c``: the Cholesky factorisation and solve for any n, the Schur complement's
  (`_codegen_dae` and the C export of a model with complementary constraints) and the sensitivities';
- ``dae.c``: q̈ and λ of M q̈ = F + Aᵀλ, A q̈ + c = 0 through the Schur complement (`_codegen_dae`);
- ``sensitivity.c``: DOP853 on the state and its forward sensitivities (`numerics.Sensitivities`),
  after ``integrators.c`` and ``cholesky.c``.

Each file's opening comment says what it expects the code before it to define.  DOP853's
tableau is not written in C: `dop853_defines` takes it from SciPy's own coefficient module
(Hairer, Nørsett & Wanner, *Solving ODEs I*, II.5), so the compiled method and SciPy's are
the same method, coefficient for coefficient.
"""

from __future__ import annotations

import importlib.util
from functools import cache
from importlib import resources
from pathlib import Path
from types import ModuleType

import numpy as np

__all__ = ["RUNTIME_FILES", "dop853_defines", "runtime_source"]

#: The files of ``runtime/``, in the order a translation unit that needs several of them holds them.
RUNTIME_FILES = ("solve_mass.c", "integrators.c", "cholesky.c", "dae.c", "sensitivity.c")


@cache
def runtime_source(name: str) -> str:
    """The text of the runtime file ``name`` (one of `RUNTIME_FILES`), whole.

    Parameters
    ----------
    name : str
        One of `RUNTIME_FILES`.

    Returns
    -------
    str
        The file's text.
    """
    if name not in RUNTIME_FILES:
        raise ValueError(f"`{name}` is not a runtime file; they are {', '.join(RUNTIME_FILES)}")
    return resources.files(__package__).joinpath("runtime").joinpath(name).read_text(encoding="utf-8")


def _scipy_dop853_coefficients() -> ModuleType:
    """SciPy's ``scipy.integrate._ivp.dop853_coefficients``, loaded from its file alone.

    Importing it the usual way imports ``scipy.integrate`` first (0.4 s, most of SciPy's
    integrators, quadratures and special functions), which a model compiled for the first
    time would wait for and not use; the module itself needs NumPy only.  Where SciPy's
    layout is not the one expected, the usual import is used.
    """
    spec = importlib.util.find_spec("scipy")  # finds the package, does not import it
    folders = list(spec.submodule_search_locations or ()) if spec is not None else []
    for folder in folders:
        path = Path(folder) / "integrate" / "_ivp" / "dop853_coefficients.py"
        alone = importlib.util.spec_from_file_location("lagrangian.codegen._scipy_dop853", path)
        if path.is_file() and alone is not None and alone.loader is not None:
            module = importlib.util.module_from_spec(alone)
            alone.loader.exec_module(module)
            return module
    from scipy.integrate._ivp import dop853_coefficients

    return dop853_coefficients


@cache
def dop853_defines() -> dict[str, str]:
    """DOP853's tableau as C macros (``LG_DOP_A``: initialisers), from SciPy's own coefficient module."""
    c = _scipy_dop853_coefficients()

    def init(a: np.ndarray) -> str:
        if a.ndim == 1:
            return "{" + ", ".join(repr(float(x)) for x in a) + "}"
        return "{" + ", ".join(init(row) for row in a) + "}"

    stages, ext = c.N_STAGES, c.N_STAGES_EXTENDED
    return {
        "LG_DOP_STAGES": str(stages),
        "LG_DOP_STAGES_EXT": str(ext),
        "LG_DOP_POWER": str(c.INTERPOLATOR_POWER),
        "LG_DOP_A": init(np.asarray(c.A, dtype=float)[:ext, :ext]),
        "LG_DOP_B": init(np.asarray(c.B, dtype=float)),
        "LG_DOP_C": init(np.asarray(c.C, dtype=float)[:ext]),
        "LG_DOP_E3": init(np.asarray(c.E3, dtype=float)),
        "LG_DOP_E5": init(np.asarray(c.E5, dtype=float)),
        "LG_DOP_D": init(np.asarray(c.D, dtype=float)),
    }
