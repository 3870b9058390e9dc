"""``lagrangian optimize PROBLEM.toml [--nodes N] [--method M] [--set NAME=VALUE] [--json] [-o traj.csv|npz]
[--plot [DIR]]``: an optimal motion by direct collocation (docs/optimal-control.md).

The summary (status, objective, iterations, the replay's error) goes to standard output, or the
versioned JSON document ``lagrangian.optimize/1`` with ``--json``.  ``-o`` writes the motion
(every collocation point: t, q, q̇, q̈, the inputs, the multipliers) atomically, as ``simulate`` does.
Exit codes: 0 an optimum (or an acceptable point), 2 a problem that cannot be stated, 3 an output
that cannot be written, 4 no optimum (infeasible, iteration limit, solver failure: the last iterate
is still written, its status saying so), 130 Ctrl-C (the solver's last iterate is written, marked).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..errors import OptimizationError
from ..numerics import check_output_path, save_trajectory
from ._arguments.optimize import SCHEMA
from ._settings import plain_number

__all__ = ["optimize_document", "run"]



class OptimizationInterrupted(KeyboardInterrupt):
    """Ctrl-C stopped the solver: its last iterate was written to ``written`` (or nothing was)."""

    def __init__(self, written: str | None) -> None:
        super().__init__("interrupted")
        self.written = written


def _parameters(settings: list[str]) -> dict[str, float]:
    from ..errors import ProblemError

    out = {}
    for item in settings:
        name, sep, value = item.partition("=")
        try:
            out[name.strip()] = plain_number(value)
        except ValueError:
            raise ProblemError(f"`--set {item}` is not NAME=VALUE with a plain number.",
                               fix="e.g. --set m=0.3") from None
        if not sep:
            raise ProblemError(f"`--set {item}` is not NAME=VALUE.", fix="e.g. --set m=0.3")
    return out


def run(args: argparse.Namespace) -> str | None:
    from ..optimal import load_problem, optimize

    problem = load_problem(args.problem)
    if args.out:
        check_output_path(args.out)
    plots = None
    if args.plot is not None:
        plots = Path(args.plot) if args.plot else Path(f"{Path(args.problem).stem}_plots")
    overrides: dict[str, Any] = {"nodes": args.nodes, "method": args.method, "hessian": args.hessian,
                                 "tolerance": args.tolerance, "max_iterations": args.max_iterations}
    if args.set:
        overrides["parameters"] = _parameters(args.set)  # merged with the file's by `optimize`
    with _IpoptOutputToStderr(args.verbose):
        result = optimize(problem, guess=args.guess, verify=args.verify, verbose=args.verbose,
                          **{k: v for k, v in overrides.items() if v is not None})
    written = str(save_trajectory(result, args.out)) if args.out else None
    if result.status == "interrupted":
        sys.stderr.write(result.summary() + "\n")
        raise OptimizationInterrupted(written)
    lines = [result.summary()]
    if plots is not None:
        figures = _plots(result, problem, plots, args.animation)
        lines.append(f"plots: {len(figures)} files in {plots}/")
    if written:
        lines.append(f"wrote {written}")
    document = json.dumps(optimize_document(result, args.problem), indent=2, ensure_ascii=False) + "\n" \
        if args.json else None
    if result.status not in ("optimal", "acceptable"):
        if document is not None:  # the status is in it: a script reads why
            sys.stdout.write(document)
        raise OptimizationError("No optimal motion was found: " + result.message,
                                fix=(f"the solver's last iterate is in {written}, marked `{result.status}`; "
                                     if written else "") + "see docs/optimal-control.md, Troubleshooting")
    if document is not None:
        sys.stderr.write("\n".join(lines[1:]) + ("\n" if lines[1:] else ""))
        return document
    return "\n".join(lines) + "\n"


class _IpoptOutputToStderr:
    """With ``--verbose``, IPOPT prints to the process's standard output: send it to standard error."""

    def __init__(self, active: bool) -> None:
        self.active = active
        self.saved: int | None = None  # the file descriptor of the real standard output

    def __enter__(self) -> None:
        import os

        if self.active:
            sys.stdout.flush()
            self.saved = os.dup(1)
            os.dup2(2, 1)

    def __exit__(self, *exc: object) -> None:
        import os

        if self.saved is not None:
            sys.stdout.flush()
            os.dup2(self.saved, 1)
            os.close(self.saved)


def _plots(result: Any, problem: Any, directory: Path, animation: str) -> list[Path]:
    from ..dynamics import derive
    from ..errors import SimulationError
    from ..model import load_model

    try:
        from ..plotting import save_inputs_figure, save_plots
    except ImportError as exc:
        raise SimulationError(f"Plots need matplotlib ({exc}).", fix="pip install 'lagrangian[plot]'") from None
    eom = derive(load_model(problem.model)) if isinstance(problem.model, (str, Path)) else problem.model
    figures = save_plots(result, eom, directory, kinds=("time_series", "phase"), animation=animation != "none",
                         animation_format="gif" if animation == "none" else animation)
    return [*figures, save_inputs_figure(result, result.inputs, directory)]


def _floats(values: Any) -> list[float | None]:
    """A JSON list: NaN and ±inf as null."""
    return [float(v) if np.isfinite(v) else None for v in np.asarray(values, dtype=float).ravel()]


def optimize_document(result: Any, problem: str | None = None) -> dict[str, Any]:
    """The JSON document of an `OptimalTrajectory` (schema ``lagrangian.optimize/1``)."""
    replay = result.replay
    return {
        "schema": SCHEMA, "lagrangian": __version__, "problem": problem, "model": result.model_name,
        "method": result.method, "nodes": result.nodes, "status": result.status, "message": result.message,
        "solver_status": result.solver_status, "success": result.success, "objective": result.objective,
        "iterations": result.iterations, "violation": result.violation, "t_end": result.t_end,
        "free_time": result.free_time, "hessian": result.hessian, "solver": result.solver,
        "seconds": dict(result.seconds), "parameters": dict(result.parameters), "inputs": list(result.inputs),
        "replay": None if replay is None else {
            "max_error": replay.max_error, "final_error": replay.final_error, "local_error": replay.local_error,
            "tolerance": replay.tolerance, "within": replay.within, "integrator": replay.integrator},
        "warnings": list(result.warnings), "node_rows": [int(k) for k in result.node_rows],
        "columns": {name: _floats(result.column(name)) for name in result.columns()},
    }
