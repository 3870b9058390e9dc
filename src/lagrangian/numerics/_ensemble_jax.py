"""The ``jax`` backend of `lagrangian.ensemble`: the JAX export's rhs, vmapped, integrated by diffrax.

    ds = lagrangian.ensemble(model, 10.0, initial=grid(...), backend="jax")

The route to a GPU (or any accelerator JAX runs on): the members of a chunk are one
``jax.vmap`` of ``diffrax.diffeqsolve`` over y' = rhs(t, y, p), rhs being the `jax` export's
(q' and q'' from M q'' = F, `codegen.targets.jax`), so each member keeps its own adaptive step (the
vmapped while-loop runs until the slowest member is done).  ``method="dop853"`` maps to
diffrax's ``Dopri8`` (the same Dormand–Prince 8(5,3)-order family; Hairer, Nørsett & Wanner,
*Solving ODEs I*, II.10) under a ``PIDController`` with the run's rtol and atol; the step
controllers differ, so members agree with the C path to the tolerance, not to the bit.

What the C path has and this one has not: events, the first integrals' drift, the
mass matrix's conditioning (NaN), Dask.  ``rhs_calls`` counts the solver's stages per step;
a failed member's ``t_final`` is the last output time it reached (diffrax fills the states
after a failure with inf, and says no more).
Each chunk is padded to the chunk size (the last member repeated) so that JAX compiles
one program per run.  JAX computes in float32 unless ``jax_enable_x64`` is on; this backend
turns it on (a process-wide JAX setting), since float32 cannot reach the tolerances of a
mechanics run.
"""

from __future__ import annotations

import hashlib
import importlib.util
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..errors import SimulationError

__all__ = ["jax_runner"]

# member status (`_batch.STATUS`): ok, blow-up, step-limit
_OK, _BLOW_UP, _STEP_LIMIT = 0, 2, 3


def _modules():
    try:
        import diffrax
        import jax
    except ImportError:
        raise SimulationError("backend='jax' needs JAX and diffrax, which are not installed.",
                              fix="pip install 'lagrangian[jax]' (jax[cuda12] for an NVIDIA GPU)") from None
    return jax, diffrax


def _imported(text: str):
    """The generated module, imported as a user imports an export: from a file (in a folder
    removed at once; the module stays in memory).  The text is the package's own printing
    (SymPy's JaxPrinter) of expression trees, not text from a model file."""
    with tempfile.TemporaryDirectory(prefix="lagrangian-jax-") as folder:
        path = Path(folder) / "lagrangian_jax_ensemble.py"
        path.write_text(text, encoding="utf-8")
        spec = importlib.util.spec_from_file_location("_lagrangian_jax_export", path)
        if spec is None or spec.loader is None:  # pragma: no cover - a .py file always has a loader
            raise ImportError(f"cannot load `{path}` as a Python module")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    return module


def jax_runner(eom, *, t_start: float, t_end: float, t_out: np.ndarray, rtol: float, atol: float,
               max_step: float | None, max_steps: int, keep: bool) -> tuple[str, Callable]:
    """(key, run): the digest of the generated JAX module, and run(Y0 (m, 2n), P (m, n_params)) -> rows.

    The rows are those of `numerics._batch.run_chunk` without events and drift.
    """
    jax, diffrax = _modules()
    jax.config.update("jax_enable_x64", True)  # see the module docstring
    # The JAX export target: this backend runs the code `export --target jax` writes.
    from ..codegen import exported_symbols
    from ..codegen.targets.jax import jax_module

    text = jax_module(exported_symbols(eom, "jax"))
    rhs = _imported(text).rhs
    n2 = 2 * len(eom.q)
    ts = np.asarray(t_out, dtype=float)
    ends_at_t_end = len(ts) > 0 and ts[-1] == t_end
    saved = ts if ends_at_t_end else np.append(ts, t_end)  # the final state is always saved
    solver = diffrax.Dopri8()
    tableau = solver.tableau
    per_step = len(tableau.c) + 1 - int(bool(getattr(tableau, "fsal", False)))
    controller = diffrax.PIDController(rtol=rtol, atol=atol, dtmax=max_step)
    term = diffrax.ODETerm(lambda t, y, p: rhs(t, y, p))

    def one(y0, p):
        sol = diffrax.diffeqsolve(term, solver, float(t_start), float(t_end), None, y0, args=p,
                                  saveat=diffrax.SaveAt(ts=jax.numpy.asarray(saved)), stepsize_controller=controller,
                                  max_steps=int(max_steps), throw=False)
        return (sol.ys, sol.result == diffrax.RESULTS.successful, sol.result == diffrax.RESULTS.max_steps_reached,
                sol.stats["num_steps"])

    solve = jax.jit(jax.vmap(one))
    key = hashlib.sha256(text.encode("utf-8")).hexdigest()

    def run(Y0: np.ndarray, P: np.ndarray, size: int | None = None) -> dict[str, np.ndarray]:
        m = len(Y0)
        pad = max(0, (size or m) - m)  # one compiled program for every chunk of the run
        Y0p = np.concatenate([Y0, np.repeat(Y0[-1:], pad, axis=0)]).astype(float)
        Pp = np.concatenate([P, np.repeat(P[-1:], pad, axis=0)]).astype(float)
        ys, ok, limit, steps = (np.asarray(a)[:m] for a in solve(Y0p, Pp))
        finite = np.isfinite(ys).all(axis=2)
        status = np.where(ok & finite.all(axis=1), _OK, np.where(limit, _STEP_LIMIT, _BLOW_UP)).astype(np.int8)
        Y_out = np.where(finite[:, : len(ts), None], ys[:, : len(ts)], np.nan)  # diffrax fills inf after a failure
        last = np.where(finite, saved[None, :], -np.inf).max(axis=1)  # the last time with a finite state
        ok_rows = status == _OK
        with np.errstate(invalid="ignore"):
            rows: dict[str, np.ndarray] = {
                "status": status,
                "t_final": np.where(ok_rows, float(t_end), np.where(np.isfinite(last), last, np.nan)),
                "steps": steps.astype(np.int64),
                "rhs_calls": (per_step * steps).astype(np.int64),
                "conditioning": np.full(m, np.nan),
                "state_min": np.fmin.reduce(Y_out, axis=1),
                "state_max": np.fmax.reduce(Y_out, axis=1),
                "state_final": np.where(ok_rows[:, None], ys[:, -1, :n2], np.nan),
            }
        if keep:
            rows["state"] = Y_out
        return rows

    return key, run
