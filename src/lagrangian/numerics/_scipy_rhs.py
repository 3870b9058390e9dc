r"""A plain right-hand side for SciPy: ``f(t, y)`` and its analytic Jacobian ``f.jac(t, y)``.

``compiled.rhs_function(parameters)`` returns an `RhsFunction` that
``scipy.integrate.solve_ivp(f, t_span, y0, jac=f.jac)`` takes directly: y = (q, q̇) and

    ẏ = (q̇, q̈),   M(q, t) q̈ = F(q, q̇, t)

evaluated by the compiled C code (``rhs_c``).  Every call returns a **fresh** array: an
integrator keeps the values it is given (SciPy's RK stages ``K[s]``, Radau's ``f``), so an
evaluator that returns the same buffer each time — as PyDy's Cython generator does —
silently corrupts the run.

The Jacobian is analytic.  Differentiating M q̈ = F with respect to a state y_j
[Hairer & Wanner, *Solving ODEs II*, § IV.8; Featherstone, *Rigid Body Dynamics
Algorithms*, § 9.3]:

    ∂q̈/∂y_j = M⁻¹ (∂F/∂y_j − (∂M/∂y_j) q̈),     J = [[0, I], [∂q̈/∂q, ∂q̈/∂q̇]],

with ∂M/∂y_j and ∂F/∂y_j differentiated symbolically by SymEngine and evaluated by its
``Lambdify`` (common subexpressions shared), built on the first call of ``jac``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np
import symengine as se

from ..errors import SimulationError

__all__ = ["RhsFunction"]


class RhsFunction:
    """``f(t, y)`` → ẏ (a new array each call) for `scipy.integrate.solve_ivp`, and ``f.jac(t, y)``.

    Attributes
    ----------
    system : the `CompiledSystem` it evaluates.
    p : the parameter vector in use (`CompiledSystem.parameter_vector`).
    jacobian : ``"analytic"`` (see the module docstring).

    ``y`` may also be of shape (2n, k) (``solve_ivp(..., vectorized=True)``): then ẏ has that shape.
    """

    jacobian = "analytic"

    def __init__(self, system, parameters: Mapping[str, float] | None = None) -> None:
        eom = system.eom
        if eom.constraints:
            raise SimulationError(
                f"`{eom.model.name}` keeps complementary constraints: its motion is a differential-algebraic "
                "system (M q'' = F + Aᵀλ, A q'' + c = 0), not an ODE f(t, y).",
                fix="use lagrangian.simulate, which integrates it with the constraints enforced, or make the "
                    "constraints principal (choose coordinates that satisfy them)")
        self.system = system
        self.n = system.n
        self.p = system.parameter_vector(parameters)
        self._fast = getattr(system, "_lib", None) is not None
        self._derivatives: Callable[[np.ndarray], np.ndarray] | None = None

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if y.ndim == 2:  # solve_ivp(vectorized=True): one state per column
            return np.ascontiguousarray(self.system.rhs(t, y.T, self.p).T)
        if not self._fast:
            return self.system.rhs(t, y, self.p)
        y = np.ascontiguousarray(y)
        out = np.empty(2 * self.n)
        if self.system.rhs_c(float(t), y, self.p, out):
            return self.system.rhs(t, y, self.p)  # raises the SimulationError that names the cause
        return out

    def jac(self, t: float, y: np.ndarray) -> np.ndarray:
        """∂ẏ/∂y, shape (2n, 2n), analytic (module docstring)."""
        if self.system.inputs:
            raise SimulationError(f"The analytic Jacobian differentiates M and F with the inputs as constants, and "
                                  f"{', '.join(self.system.inputs)} follow a law here (u(t, q, q̇)).",
                                  fix="leave jac out (solve_ivp then differences f itself), or compile the system "
                                      "without the law")
        n = self.n
        y = np.ascontiguousarray(y, dtype=float).reshape(2 * n)
        M, F = self.system.mass_forces(t, y, self.p)
        try:
            qdd = np.linalg.solve(M, F)
        except np.linalg.LinAlgError as exc:
            raise SimulationError("The mass matrix M is singular at this state, so q'' has no Jacobian there.",
                                  fix="check the state") from exc
        if self._derivatives is None:
            self._derivatives = self._build()
        k = len(self.system.parameters)
        values = np.asarray(self._derivatives(np.concatenate([[float(t)], y, self.p[:k]])), dtype=float)
        dM = values[: 2 * n * n * n].reshape(2 * n, n, n)   # ∂M/∂y_j
        dF = values[2 * n * n * n:].reshape(2 * n, n)       # ∂F/∂y_j
        rhs = dF - dM @ qdd                                 # row j: ∂F/∂y_j − (∂M/∂y_j) q̈
        J = np.zeros((2 * n, 2 * n))
        J[:n, n:] = np.eye(n)
        J[n:, :] = np.linalg.solve(M, rhs.T)
        return J

    def _build(self):
        eom = self.system.eom
        states = [*eom.q, *eom.qd]
        args = [eom.t, *states, *(se.Symbol(name) for name in self.system.parameters)]
        exprs = [se.diff(eom.M[a][b], s) for s in states for a in range(self.n) for b in range(self.n)]
        exprs += [se.diff(f, s) for s in states for f in eom.F]
        return se.Lambdify(args, exprs, cse=True)
