"""`optimize`: an optimal motion of a model by direct collocation, solved by IPOPT and checked by replay.

The steps, each its own module: the problem as stated (`_problem`), its names resolved against the
model (`_layout`), the equations at one collocation point as CasADi functions (`_dynamics`, through
`_casadi`), the nonlinear program of the chosen scheme (`_transcription`, `_schemes`), a guess or a
warm start (`_guess`), IPOPT (`_solve`), and the result checked by replaying its inputs (`_replay`).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..dynamics import EquationsOfMotion, derive
from ..errors import ProblemError
from ..model import load_model
from ..model.spec import Model
from ._file import locate
from ._guess import initial_guess
from ._problem import Problem
from ._replay import replay_check
from ._result import REPLAY_TOLERANCE, OptimalTrajectory
from ._solve import STATUS_MESSAGES, SolverRun, ipopt_build, solve_nlp
from ._transcription import Transcription, transcribe

__all__ = ["optimize"]

#: The statuses whose motion is worth replaying (a solution, or close to one).
_REPLAYED = ("optimal", "acceptable")


def _equations(model: Any) -> EquationsOfMotion:
    if isinstance(model, EquationsOfMotion):
        return model
    if isinstance(model, (str, Path)):
        model = load_model(model)
    if isinstance(model, Model):
        return derive(model)
    raise TypeError(f"optimize needs a model file, a Model or an EquationsOfMotion, not {type(model).__name__}")


def optimize(source: Any, *, t_end: float | str | None = None, t_start: float | None = None,
             initial: Mapping[str, Any] | None = None, final: Mapping[str, Any] | None = None,
             bounds: Mapping[str, Sequence[Any]] | None = None, objective: Any = None, nodes: int | None = None,
             method: str | None = None, path: Sequence[str] | Mapping[str, Sequence[Any]] | None = None,
             parameters: Mapping[str, float] | None = None, guess: Any = None,
             warm_start: OptimalTrajectory | None = None, tolerance: float | None = None,
             max_iterations: int | None = None, hessian: str | None = None, t_guess: float | None = None,
             verify: bool = True, replay_tolerance: float = REPLAY_TOLERANCE,
             verbose: bool = False) -> OptimalTrajectory:
    r"""The inputs u(t), and the motion they cause, that minimize an objective, by direct collocation.

    The dynamics are the implicit rows M(q) q̈ − F(q, q̇, u) − Aᵀλ = 0 at every collocation point,
    with q̈ (and λ) decision variables, differentiated exactly by CasADi; IPOPT solves the
    nonlinear program.  See docs/optimal-control.md.

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion or Problem
        A model file, a `Model`, an `EquationsOfMotion`, or a `Problem` (`load_problem`), whose
        fields the other arguments given here replace (``parameters`` are merged with its own).
    t_end : float or str, optional
        The final time, or ``"free"`` (then ``bounds["t_end"]`` bounds it).
    t_start : float, optional
        The initial time (default 0).
    initial : mapping of str to object, optional
        Column → value at t0 (numbers, or text such as ``"pi"``); columns are ``x``, ``x_dot``,
        ``x_ddot``, the inputs and ``lambda_<row>``; a column not named is free.
    final : mapping of str to object, optional
        Column → value at the final time, likewise.
    bounds : mapping of str to (low, high), optional
        Column (or ``"t_end"``) → ``(low, high)``, None for no bound.
    objective : str or Objective or mapping, optional
        ``"effort"`` (∫ Σ u² dt, the default), ``"time"``, or an `Objective` / mapping with
        ``effort``, ``time``, ``running``, ``terminal``, ``track``, ``track_weights``.
    nodes : int, optional
        The mesh nodes N ≥ 2 (default 50).
    method : str, optional
        ``"hermite-simpson"`` (default, fourth order), ``"trapezoidal"`` or ``"backward-euler"``.
    path : sequence of str or mapping, optional
        Path constraints, ``"x^2 + y^2 <= 1"``, ``"-1 <= x <= 1"`` (or expression → (low, high)).
    parameters : mapping of str to float, optional
        Overrides of the model's parameter values.
    guess : str or Trajectory or mapping, optional
        ``"interpolate"`` (default), ``"simulate"``, a `Trajectory` or a mapping column → values (a
        `Problem`'s own ``guess`` when not given).
    warm_start : OptimalTrajectory, optional
        A previous result: its variables and multipliers when the problem has the same layout
        (scheme, nodes, columns), else its motion as the guess.
    tolerance : float, optional
        IPOPT's tol (1e-8).
    max_iterations : int, optional
        IPOPT's max_iter (3000).
    hessian : {"exact", "limited-memory"}, optional
        ``"exact"`` (default) or ``"limited-memory"``.
    t_guess : float, optional
        The first guess of a free duration.
    verify : bool, optional
        Replay the optimized inputs through an integrator (`Replay`).
    replay_tolerance : float, optional
        A replay error above it adds a warning.
    verbose : bool, optional
        Let IPOPT print its iterations.

    Returns
    -------
    OptimalTrajectory
        The motion at the collocation points, its inputs and multipliers as columns, the objective,
        the status (``optimal``, ``infeasible``, ``interrupted`` after Ctrl-C ...), the replay.

    Raises
    ------
    ProblemError
        A problem that cannot be stated: an unknown name, reversed bounds, nodes < 2, a model without
        inputs, a value or an expression that cannot be read.
    OptimizationError
        CasADi missing, or IPOPT failing with an error of its own.

    Examples
    --------
    >>> import lagrangian
    >>> best = lagrangian.optimize("examples/inverted_pendulum_cart.toml", t_end=2.0,
    ...     initial={"x": 0, "theta": "pi", "x_dot": 0, "theta_dot": 0},
    ...     final={"x": 0, "theta": 0, "x_dot": 0, "theta_dot": 0},
    ...     bounds={"F": (-20, 20), "x": (-2, 2)}, nodes=30)  # doctest: +SKIP
    >>> best.status, best.column("F").shape  # doctest: +SKIP
    ('optimal', (59,))
    """
    given = {"t_end": t_end, "t_start": t_start, "initial": initial, "final": final, "bounds": bounds,
             "objective": objective, "nodes": nodes, "method": method, "path": path, "parameters": parameters,
             "tolerance": tolerance, "max_iterations": max_iterations, "hessian": hessian, "t_guess": t_guess}
    given = {k: v for k, v in given.items() if v is not None}
    if isinstance(source, Problem):
        if parameters is not None:  # merged with the problem's own values, not in place of them
            given["parameters"] = {**source.parameters, **parameters}
        problem = dataclasses.replace(source, **given)
    else:
        if t_end is None:
            raise TypeError("optimize needs t_end: a final time, or \"free\"")
        problem = Problem(model=source, **given)
    start = time.perf_counter()
    eom = _equations(problem.model)
    try:
        tr = transcribe(problem, eom)
    except ProblemError as exc:  # from a problem file: say where in it
        raise locate(exc, problem.source) from None
    transcribed = time.perf_counter() - start
    run = _solve(tr, problem.guess if guess is None else guess, warm_start, verbose)
    return _result(tr, run, transcribed, verify, replay_tolerance)


def _layout_key(tr: Transcription) -> tuple[Any, ...]:
    """What must agree for a previous solution to be reused as it is (a warm start)."""
    return (tr.scheme.name, tr.N, tr.layout.names, tr.free_time, tr.nlp["g"].numel())


def _solve(tr: Transcription, guess: Any, warm_start: OptimalTrajectory | None, verbose: bool) -> SolverRun:
    solution = warm_start.solution if isinstance(warm_start, OptimalTrajectory) else {}
    if solution and solution.get("key") == _layout_key(tr):
        return solve_nlp(tr, solution["w"], lam_x0=solution["lam_x"], lam_g0=solution["lam_g"], verbose=verbose)
    return solve_nlp(tr, initial_guess(tr, warm_start if warm_start is not None else guess), verbose=verbose)


def _result(tr: Transcription, run: SolverRun, transcribed: float, verify: bool,
            replay_tolerance: float) -> OptimalTrajectory:
    layout, n = tr.layout, tr.layout.n
    Z, T = tr.unpack(run.w)
    t = tr.t0 + tr.tau * T
    energies = np.asarray(tr.functions.energies.map(tr.P)(Z, t.reshape(1, -1)))
    monitors = {"T": energies[0], "U": energies[1]}
    drift: dict[str, float] = {}
    if tr.functions.manifold is not None:  # the constraints at position and velocity level, along the motion
        rows = tr.eom.constraints
        names = [f"drift_{r.name}" for r in rows if r.kind == "holonomic"] + [f"drift_{r.name}_dot" for r in rows]
        residuals = np.asarray(tr.functions.manifold.map(tr.P)(Z, t.reshape(1, -1)))
        for name, values in zip(names, residuals, strict=True):
            monitors[name] = values
            drift[name] = float(np.max(np.abs(values)))
    nodes = tr.scheme.nodes(tr.N)
    U = Z[layout.slice("u")].T
    extra = {name: Z[k].copy() for k, name in enumerate(layout.names) if k >= 3 * n}
    seconds = {"transcribe": transcribed, "setup": run.setup_seconds, "solve": run.solve_seconds}
    replay, warnings = None, []
    if verify and run.status in _REPLAYED:
        start = time.perf_counter()
        y_nodes = Z[: 2 * n, nodes].T
        # each input as the scheme stands for it between its points (`OptimalTrajectory.input_table`)
        tables = {name: tr.scheme.input_table(t, U[:, k]) for k, name in enumerate(layout.inputs)}
        kind = next(iter(tables.values())).interpolation
        replay = replay_check(tr.eom, tr.values, tables, t[nodes], y_nodes,
                              f"the inputs as {tr.scheme.name} stands for them: {kind} tables", replay_tolerance)
        seconds["replay"] = time.perf_counter() - start
        if not replay.within:
            warnings.append(f"the inputs replayed over one interval depart from the optimum by {replay.local_error:.1e} "
                            f"(tolerance {replay.tolerance:.0e}): the mesh is too coarse for this motion; use more nodes"
                            + ("" if tr.scheme.name == "hermite-simpson" else " or method=\"hermite-simpson\""))
    if run.status != "optimal":
        warnings.append(STATUS_MESSAGES[run.status])
    message = STATUS_MESSAGES[run.status] + (f" ({run.solver_status})" if run.status == "failed" else "")
    return OptimalTrajectory(
        model_name=tr.eom.model.name, coordinates=layout.coordinates,
        parameters={**tr.values}, t=t, q=Z[layout.slice("q")].T.copy(), qd=Z[layout.slice("qd")].T.copy(),
        qdd=Z[layout.slice("qdd")].T.copy(), monitors=monitors, integrals=(), drift=drift, method=tr.scheme.name, steps=tr.N - 1, rhs_calls=run.evaluations, warnings=tuple(warnings),
        status=run.status, extra=extra, inputs=layout.inputs, objective=run.objective, success=run.success,
        solver_status=run.solver_status, message=message, iterations=run.iterations, violation=run.violation,
        nodes=tr.N, t_end=float(t[-1]), free_time=tr.free_time, node_rows=nodes, hessian=tr.problem.hessian,
        solver=ipopt_build(), seconds=seconds, replay=replay,
        solution={"key": _layout_key(tr), "w": run.w, "lam_x": run.lam_x, "lam_g": run.lam_g})
