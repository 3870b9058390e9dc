"""Stage 7 — optimal control: the inputs, and the motion they cause, that minimize an objective (direct collocation).

``optimize(model, t_end=..., initial=..., final=..., bounds=..., objective=...)`` → `OptimalTrajectory`:
the dynamics M(q) q̈ − F(q, q̇, u) = 0 enter as implicit rows at every collocation point (no M⁻¹),
CasADi differentiates them exactly, IPOPT solves the program, and the optimized inputs are replayed
through an accurate integrator to check the motion.  ``load_problem("problem.toml")`` reads a problem
file (docs/optimal-control.md).  A stage above `numerics`: it uses its `Trajectory` and compiled systems.
"""

from ._casadi import casadi_expressions as casadi_expressions
from ._file import load_problem as load_problem
from ._optimize import optimize as optimize
from ._problem import METHODS as METHODS
from ._problem import Objective as Objective
from ._problem import Problem as Problem
from ._result import OptimalTrajectory as OptimalTrajectory
from ._result import Replay as Replay

__all__ = [
           "METHODS",
           "Objective",
           "OptimalTrajectory",
           "Problem",
           "Replay",
           "casadi_expressions",
           "load_problem",
           "optimize",
]
