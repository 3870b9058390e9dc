"""A run by one of SciPy's ``solve_ivp`` methods (RK45, RK23, DOP853, Radau, BDF, LSODA) on the compiled q̈.

The right-hand side and the events are the compiled system's; SciPy steps in Python, so
Ctrl-C stops it at once (`Interrupted`, without the part computed: it stays inside
``solve_ivp``).  A table's samples and a switch's times are breakpoints where the solver starts
again (`_input_run.solve_in_segments`).  Used by the ODE route (`_ode`) and the free bodies'
route (`_free_simulate`).
"""

from __future__ import annotations

import numpy as np

from ..errors import Interrupted, SimulationError
from ._input_run import check_callback, solve_in_segments
from ._progress import Reporter, make_reporter

__all__ = ["run_scipy"]


def _counting_solver(method: str, count: dict, reporter: Reporter | None) -> type:
    """SciPy's solver class for ``method``, counting its accepted steps (and reporting progress)."""
    import scipy.integrate

    base = getattr(scipy.integrate, method)

    class Counted(base):  # type: ignore[misc, valid-type]
        def __init__(self, *args, **kwargs) -> None:
            super().__init__(*args, **kwargs)
            count["solver"] = self

        def _step_impl(self):
            success, message = super()._step_impl()
            if success:
                count["steps"] += 1
                if reporter is not None:
                    reporter.update(self.t)
            return success, message

    Counted.__name__ = Counted.__qualname__ = base.__name__
    return Counted


def run_scipy(system, p, y0, t_start, t_end, t_out, method, rtol, atol, max_step, specs, progress=False):
    """(t, Y, events, rhs calls, accepted steps, solve_ivp's status) of SciPy's ``method`` on ``system``."""
    from scipy.integrate import solve_ivp

    def fun(t, y):
        try:
            return system.rhs(t, y, p)
        except SimulationError:
            check_callback(system)  # a Python input function's error first: it caused this one
            raise

    def make_event(k, spec):
        def g(t, y):
            return float(system.event_values(t, y, p)[k])
        g.direction = spec.direction
        g.terminal = spec.terminal
        return g

    count: dict = {"steps": 0, "solver": None}
    reporter = make_reporter(progress, t_start, t_end)

    def reached() -> float:
        return float(count["solver"].t) if count["solver"] is not None else float(t_start)

    try:
        # A failure is raised as a SimulationError below; NumPy's floating-point warnings on the way add nothing.
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            def solve(a: float, b: float, y: np.ndarray, grid: np.ndarray):
                return solve_ivp(fun, (a, b), y, method=_counting_solver(method, count, reporter),
                                 t_eval=grid, rtol=rtol, atol=atol, max_step=np.inf if max_step is None else max_step,
                                 events=[make_event(k, s) for k, s in enumerate(specs)] or None)

            # A table's samples and a switch's times are breakpoints: one solve_ivp per interval (`_input_run`).
            law = system.law_block(p) if len(system.law.breakpoints) else None
            sol = solve_in_segments(solve, t_start, t_end, t_out, y0, system.law.breakpoints, law, len(specs))
    except KeyboardInterrupt:
        # SciPy's loop runs in Python, so Ctrl-C stops it at once; what it had is inside
        # solve_ivp and lost, so the Interrupted carries no trajectory.
        if reporter:
            reporter.finish(reached(), False)
        raise Interrupted(reached()) from None
    except SimulationError as exc:
        if reporter:
            reporter.finish(reached(), False)
        raise SimulationError(f"{exc.message} (during SciPy's {method} integration)", fix=exc.fix, t=exc.t,
                              state=exc.state) from None
    except (ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
        # e.g. "array must not contain infs or NaNs" from the linear algebra of an implicit method
        # whose error weights atol + rtol |y| underflow, or a blow-up of the state.
        if reporter:
            reporter.finish(reached(), False)
        t_fail = reached()
        raise SimulationError(
            f"SciPy's {method} failed at t = {t_fail:.9g}: {exc} (rtol = {rtol:g}, atol = {atol:g}).",
            fix="use tolerances the method can meet (atol no smaller than about 1e-15 times the size of the state, "
                "rtol >= 1e-13), or try method='dop853'; if the state grows without bound, check the model",
            t=t_fail) from None
    if reporter:
        reporter.finish(reached(), sol.status >= 0)
    if sol.status < 0:
        raise SimulationError(f"SciPy's {method} stopped at t = {sol.t[-1] if len(sol.t) else t_start:.9g}: "
                              f"{sol.message}", fix="loosen the tolerances or try another method")
    evs = []
    for k, spec in enumerate(specs):
        for te, ye in zip(sol.t_events[k], sol.y_events[k], strict=True):
            evs.append((spec.name, float(te), ye))
    evs.sort(key=lambda e: e[1])
    return sol.t, np.ascontiguousarray(sol.y.T), evs, int(sol.nfev), int(count["steps"]), sol.status
