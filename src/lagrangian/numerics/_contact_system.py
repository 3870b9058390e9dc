"""A model with unilateral contacts as numeric functions: every row at once, any subset active.

`ContactSystem` derives the model once — every contact row with the bilateral complementary rows:
the gap's row, and the sliding row of a contact with friction (`dynamics._constraints.sliding_row`),
whatever their rank — and compiles the whole into C once (`ConstrainedSystem`): M, F, and for each
row A_k, b_k (through ġ = A q̇ + b), the bias c_k (g̈ = A q̈ + c) and the gap g_k.  The rows that
act at an instant — the bilateral ones, the closed contacts, the sticking ones — are a subset,
solved from

    [ M  −A_Sᵀ ] [ q̈ ]   [  F   ]
    [ A_S  0   ] [ λ_S ] = [ −c_S ]

(`accelerations`), and the state is projected onto that subset (`project_active`).  Where the
model has no bilateral row, the phases in which every contact is open run in the compiled
integrator with the gaps as event functions (``fast``: `CompiledSystem` of the model without
contacts), so a bouncing ball's flights cost microseconds.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np
import symengine as se

from ..dynamics import SLIDING_SUFFIX, EquationsOfMotion, derive
from ..errors import ModelError, SimulationError
from ..model import coefficient_values_error
from ..model.spec import Model
from ._compile import compiler
from ._dae import ConstrainedSystem
from ._projection import project_many
from ._system import CompiledSystem

__all__ = ["GAP_EVENT", "ContactSystem", "Probe", "contacts_of", "solve_small"]

#: Prefix of the compiled gap event functions (not an identifier, so never a user's event).
GAP_EVENT = "~gap:"


def solve_small(M: np.ndarray, b: np.ndarray) -> np.ndarray:
    """M⁻¹ b for the small matrices of contact events (one coordinate: a division, without NumPy's overhead)."""
    if M.shape == (1, 1):
        return b / M[0, 0]
    return np.linalg.solve(M, b)


def contacts_of(model: Model) -> tuple:
    """The model's unilateral constraints (``form = "unilateral"``), in declaration order."""
    return tuple(c for c in model.constraints if getattr(c, "unilateral", False))


class Probe:
    """(M, F, A, c, g, f) and (T, U) at one state, through preallocated buffers (a few µs a call, not 60).

    A contact event asks for them a handful of times; `ConstrainedSystem.parts` allocates its
    arrays and converts every pointer at each call.  The arrays returned are the buffers
    themselves: valid until the next call.
    """

    def __init__(self, system: ConstrainedSystem, p: np.ndarray) -> None:
        n, m = system.n, len(system.rows)
        self.system, self.p = system, np.ascontiguousarray(p, dtype=float)
        self.T, self.Y = np.zeros(2), np.zeros((2, 2 * n))
        self.out = (np.zeros((n, n)), np.zeros(n), np.zeros((m, n)), np.zeros(m), np.zeros(m), np.zeros(m))
        self.mon = np.zeros((2, max(len(system.monitors), 1)))
        lib = system._lib
        if lib is not None:
            ptr = [a.ctypes.data for a in (self.T, self.Y, self.p, *self.out)]
            self._parts = lambda: lib.lgd_eval_parts(1, *ptr)
            mptr = (self.T.ctypes.data, self.Y.ctypes.data, self.p.ctypes.data, self.mon.ctypes.data)
            self._monitors = lambda: lib.lgd_eval_monitors(2, *mptr)
        else:
            self._parts = self._monitors = None
        names = list(system.monitors)
        self._energy = [names.index(k) for k in (("T_total", "U_total") if "T_total" in names else ("T", "U"))]

    def parts(self, t: float, y: np.ndarray) -> tuple[np.ndarray, ...]:
        if self._parts is None:
            return self.system.parts(t, y, self.p)
        self.T[0] = t
        self.Y[0] = y
        self._parts()
        return self.out

    def energy(self, t: float, y0: np.ndarray, y1: np.ndarray) -> tuple[float, float]:
        """E = T + U at two states (at the same t)."""
        if self._monitors is None:
            values = self.system.monitor_values(t, np.stack([y0, y1]), self.p)
        else:
            self.T[:] = t
            self.Y[0], self.Y[1] = y0, y1
            self._monitors()
            values = self.mon
        i, j = self._energy
        return float(values[0, i] + values[0, j]), float(values[1, i] + values[1, j])


class _Active:
    """The rows of a `ConstrainedSystem` restricted to a subset, as `project_many` reads them (one state
    through a `Probe` when given)."""

    def __init__(self, system: ConstrainedSystem, rows: np.ndarray, probe: Probe | None = None) -> None:
        self.system, self.rows, self.n, self.probe = system, rows, system.n, probe
        self.holonomic = system.holonomic[rows]

    def parts(self, t, y, p):
        r = self.rows
        if self.probe is not None and np.size(y) == 2 * self.n:
            M, F, A, c, g, f = self.probe.parts(float(np.ravel(t)[0]), np.ravel(y))
            return M[None], F[None], A[r][None], c[r][None], g[r][None], f[r][None]
        M, F, A, c, g, f = self.system.parts(t, y, p)
        return M, F, A[..., r, :], c[..., r], g[..., r], f[..., r]


class ContactSystem:
    """The numeric side of a model with unilateral contacts (module docstring).

    Attributes
    ----------
    model : the model; ``contacts`` : its unilateral constraints, ``names`` their names.
    eom : the model derived: its rows are the bilateral ones and every contact's (gap, sliding).
    full : `ConstrainedSystem` of every row; ``n`` coordinates.
    bilateral, normal, tangent : indices of the bilateral rows, of each contact's gap row, and of
        each contact's sliding row (−1 without friction) in ``full.rows``.
    fast : `CompiledSystem` of the model without contacts whose events are the gaps (`fast_system`),
        when the model has no bilateral row and a C compiler exists; else None.
    """

    def __init__(self, model: Model, *, backend: str = "auto") -> None:
        self.contacts = contacts_of(model)
        if not self.contacts:
            raise ModelError("The model has no unilateral contact.", fix="use lagrangian.simulate")
        self.model = model
        self.names = tuple(c.name for c in self.contacts)
        # Every row at once: the bilateral ones, each contact's gap and, with friction, its sliding row.
        self.eom: EquationsOfMotion = derive(model)
        self.full = ConstrainedSystem(self.eom, backend=backend)
        rows = list(self.full.rows)
        self.n = self.full.n
        self.bilateral = np.array([k for k, r in enumerate(self.eom.constraints) if r.constraint not in self.names],
                                  dtype=int)
        self.normal = np.array([rows.index(c.name) for c in self.contacts], dtype=int)
        self.tangent = np.array([rows.index(c.name + SLIDING_SUFFIX) if c.slip is not None else -1
                                 for c in self.contacts], dtype=int)
        params = [se.Symbol(name) for name in self.full.parameters]
        coefficients = [c.restitution for c in self.contacts]
        coefficients += [c.friction if c.friction is not None else se.Integer(0) for c in self.contacts]
        self._coefficients = se.Lambdify(params, coefficients) if params else None
        self._coefficient_exprs = coefficients
        # No t in M, F and the rows: a state at rest in equilibrium stays at rest (`_contact_phase`).
        t = self.eom.t
        exprs = [*(e for row in self.eom.M for e in row), *self.eom.F,
                 *(x for r in self.eom.constraints for x in (*r.coefficients, r.b, r.bias, r.expression))]
        self.autonomous = all(t not in e.free_symbols for e in exprs)
        self._use_c = backend == "c" or (backend == "auto" and compiler() is not None)
        self._fast: dict[tuple, CompiledSystem] = {}
        self.fast = self.fast_system(())

    def fast_system(self, events: Sequence[tuple[str, se.Basic]]) -> CompiledSystem | None:
        """The compiled model without its contacts, its events the gaps then ``events`` (None with bilateral rows
        or without a C compiler); derived and compiled once per set of events."""
        if len(self.bilateral) or not self._use_c:
            return None
        key = tuple((name, str(expr)) for name, expr in events)
        if key not in self._fast:
            open_eom = derive(replace(self.model, constraints=()))  # every constraint is a contact here
            gaps = [(GAP_EVENT + c.name, c.expression) for c in self.contacts]
            self._fast[key] = CompiledSystem(open_eom, events=gaps + list(events), backend="c")
        return self._fast[key]

    # -- values ------------------------------------------------------------------------------
    def coefficients(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(e, μ) per contact at the parameter values ``p`` (μ = NaN for a frictionless contact).

        Raises
        ------
        SimulationError
            e outside [0, 1] or μ < 0 (values given with ``parameters=``/``--set``).
        """
        m = len(self.contacts)
        if self._coefficients is None:
            values = np.array([float(e) for e in self._coefficient_exprs])
        else:
            values = np.asarray(self._coefficients(p[: len(self.full.parameters)]), dtype=float).ravel()
        e, mu = values[:m], values[m:]
        for k, c in enumerate(self.contacts):
            problem = coefficient_values_error(c.name, float(e[k]), float(mu[k]) if c.slip is not None else None)
            if problem is not None or not np.isfinite(e[k]):
                loc = self.model.where("constraint", c.name)
                where = f" (declared at {loc.file}:{loc.line})" if loc.file and loc.line else ""
                raise SimulationError(f"{problem or f'e = {e[k]} is not a number'}{where}.",
                                      fix="0 ≤ e ≤ 1 (0: plastic, 1: elastic), μ ≥ 0")
        mu = np.where(self.tangent >= 0, mu, np.nan)
        return e, mu

    def active_rows(self, closed: np.ndarray) -> np.ndarray:
        """Indices into ``full.rows`` of the bilateral rows, the closed gaps and their sliding rows (sticking)."""
        rows = [*self.bilateral.tolist()]
        for k in np.flatnonzero(closed):
            rows.append(int(self.normal[k]))
            if self.tangent[k] >= 0:
                rows.append(int(self.tangent[k]))
        return np.array(rows, dtype=int)

    def core(self, A: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """An independent subset of ``rows`` at a state of Jacobian A (all of them when they are independent).

        A block flat on the ground has four acting rows (two corners, normal and sticking) for three
        coordinates: q̈ and the projection use three of them (QR with column pivoting of A_rowsᵀ), and the
        reactions are spread over the four (`solve`).
        """
        if len(rows) < 2:
            return rows
        As = A[rows]
        sv = np.linalg.svd(As, compute_uv=False)
        rank = int(np.sum(sv > 1e-9 * max(float(sv[0]), 1e-300)))
        if rank == len(rows):
            return rows
        import scipy.linalg  # late: only statically indeterminate contacts need it

        _, _, pivots = scipy.linalg.qr(As.T, pivoting=True, mode="economic")
        return np.sort(rows[pivots[:rank]])

    def solve(self, M: np.ndarray, F: np.ndarray, A: np.ndarray, c: np.ndarray, y: np.ndarray, rows: np.ndarray,
              core: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(ẏ, λ) at one state with the rows ``rows`` acting (module docstring); λ over ``full.rows`` (0 elsewhere).

        With ``core`` (an independent subset, `core`) q̈ comes from it, and the reactions are the least-norm
        λ over ``rows`` with the same generalized force A_coreᵀλ_core (statically indeterminate contacts).
        """
        n = self.n
        lam = np.zeros(len(self.full.rows))
        out = np.empty(2 * n)
        out[:n] = y[n:]
        use = rows if core is None else core
        try:
            if len(use):
                As = A[use]
                X = solve_small(M, np.concatenate([As.T, F[:, None]], axis=1))
                XA, XF = X[:, :-1], X[:, -1]
                lam_s = solve_small(As @ XA, -c[use] - As @ XF)
                out[n:] = XF + XA @ lam_s
                lam[use] = lam_s
                if core is not None and len(core) < len(rows):
                    lam[rows] = np.linalg.lstsq(A[rows].T, As.T @ lam_s, rcond=None)[0]
            else:
                out[n:] = solve_small(M, F)
        except np.linalg.LinAlgError:
            raise SimulationError("The mass matrix, or the matrix A M⁻¹ Aᵀ of the rows acting, is singular: "
                                  "the contacts closed together are redundant, or the coordinates are singular.",
                                  fix="check the contacts' gaps (two contacts that say the same thing), and the "
                                      "coordinates") from None
        return out, lam

    def accelerations(self, t: float, y: np.ndarray, p: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(ẏ, λ) at one state with the rows ``rows`` acting (`solve`, redundant rows allowed)."""
        M, F, A, c, _, _ = self.full.parts(t, y, p)
        return self.solve(M, F, A, c, y, rows, self.core(A, rows))

    def accelerations_many(self, t: np.ndarray, Y: np.ndarray, p: np.ndarray, rows: np.ndarray
                           ) -> tuple[np.ndarray, np.ndarray]:
        """`accelerations` at many states with the same rows acting: (N, 2n) and (N, rows), solved in a batch."""
        M, F, A, c, _, _ = self.full.parts(t, Y, p)
        n, N = self.n, len(Y)
        out = np.empty((N, 2 * n))
        out[:, :n] = Y[:, n:]
        lam = np.zeros((N, len(self.full.rows)))
        if not len(rows):
            out[:, n:] = np.linalg.solve(M, F[..., None])[..., 0]
            return out, lam
        if N and len(self.core(A[0], rows)) < len(rows):  # statically indeterminate: state by state
            for k in range(N):
                out[k], lam[k] = self.solve(M[k], F[k], A[k], c[k], Y[k], rows, self.core(A[k], rows))
            return out, lam
        As = A[:, rows]
        X = np.linalg.solve(M, np.concatenate([np.swapaxes(As, 1, 2), F[..., None]], axis=2))
        XA, XF = X[..., :-1], X[..., -1]
        lam_s = np.linalg.solve(As @ XA, (-c[:, rows] - np.einsum("nki,ni->nk", As, XF))[..., None])[..., 0]
        out[:, n:] = XF + np.einsum("nik,nk->ni", XA, lam_s)
        lam[:, rows] = lam_s
        return out, lam

    def project_active(self, t, y: np.ndarray, p: np.ndarray, rows: np.ndarray, tol: float,
                       probe: Probe | None = None) -> tuple[np.ndarray, bool]:
        """States moved onto the acting rows (positions onto their gaps, velocities onto ġ = 0; `project_many`):
        one state (2n,) or many (N, 2n), as given."""
        if not len(rows):
            return y, False
        Y, changed = project_many(_Active(self.full, rows, probe), t, y, p, tol)  # type: ignore[arg-type]
        return (Y[0] if np.ndim(y) == 1 else Y), changed

    def energy(self, t: float, Y: np.ndarray, p: np.ndarray) -> np.ndarray:
        """(T, U) at each state of Y (N, 2n): shape (N, 2)."""
        values = self.full.monitor_values(t, Y, p)
        names = list(self.full.monitors)
        T = names.index("T_total" if "T_total" in names else "T")
        U = names.index("U_total" if "U_total" in names else "U")
        return values[:, [T, U]]

    def parameter_values(self, parameters: Mapping[str, float] | None) -> tuple[np.ndarray, np.ndarray | None]:
        """The parameter arrays of ``full`` and of ``fast`` (None without it)."""
        p = self.full.parameter_vector(parameters)
        return p, (self.fast.parameter_vector(parameters) if self.fast is not None else None)
