"""Constraint reactions from the vector theorems, and the Newton–Euler check along a trajectory.

What the given efforts leave of the resultant theorem is the resultant of the constraint
actions: for the top, m γ(G/R0) = P + R_O gives R_O = m γ(G/R0) − P.  Inside a system,
a body also receives the actions of its neighbours (joints, rods), which only the whole
connected group sums away (action and reaction), so reactions are reported per *group*:
elements whose motions share a coordinate are linked by constraints, and for a group

    R = Σ_group m γ(G) − Σ_group F_given,       M_A = Σ_group δ_A − Σ_group M_A(given)

is the resultant and moment at A of what the ground exerts on it — always well defined.
When exactly one body of the group has a fixed point O (it is *pinned*), R is the
reaction R_O of that pin (the model declares no other contact with the ground) and M_O the
moment the pin transmits: it has no component along the axes the pin lets the body turn
about (∂Ω/∂q̇_i: the joint is perfect), so a ball joint (three free axes, the top)
transmits none, and a hinge only the components across its axis.

`check_trajectory` evaluates, at the states of a trajectory (q̈ from the trajectory), the
projected theorems of `verify` and the vector theorems with these reactions, with
SymEngine's LLVM-compiled `Lambdify`.
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import ModelError, SimulationError
from ..kinematics import Kinematics
from ..model import GALILEAN_FRAME, ORIGIN, Vector
from ..model.vectors import as_expr
from ._newton_euler import Verification, verify


class Trajectory(Protocol):
    """What the checks along a motion read of it: a `lagrangian.numerics.Trajectory` is one.

    Declared here, by what is used, so that analysis does not name numerics (the stage
    after it) even for annotations: imports flow one way.
    """

    # Read-only members (properties), which a frozen dataclass's fields satisfy.
    @property
    def coordinates(self) -> Sequence[str]: ...
    @property
    def parameters(self) -> Mapping[str, float]: ...
    @property
    def t(self) -> np.ndarray: ...
    @property
    def q(self) -> np.ndarray: ...
    @property
    def qd(self) -> np.ndarray: ...
    @property
    def qdd(self) -> np.ndarray: ...
    @property
    def extra(self) -> Mapping[str, np.ndarray]: ...

__all__ = ["Reaction", "reactions", "ReactionHistory", "reaction_history", "TrajectoryResiduals",
           "check_trajectory"]

#: Largest number of frames tried when choosing where a reaction's formula reads shortest.
MAX_DISPLAY_FRAMES = 12
#: Relative size below which a singular value of the free axes counts as zero (rank test).
RANK_RTOL = 1e-9


@dataclass(frozen=True, slots=True)
class Reaction:
    """The resultant (and moment) of the ground's constraint actions on a group of elements.

    Parameters
    ----------
    name : str
        ``"R_O"`` for the pin at O of a pinned group, else ``"R(→C+P)"``.
    point : str
        Where ``moment`` is taken: the pin, or O.
    pinned : str or None
        The pinned body, or None.
    elements : tuple of str
        The bodies and particles of the group.
    force : Vector
        R = Σ m γ(G/R0) − Σ F_given, a symbolic vector (q, q̇, q̈, t).
    moment : Vector
        M = Σ δ_point − Σ M_point(given).
    free_axes : tuple of Vector
        Directions the pin lets its body turn about (∂Ω/∂q̇_i), in R0 order of q.
    free_rotations : int
        How many of them are independent (3: a ball joint).
    frame : str
        The frame in which ``force_components`` are written (the shortest formula).
    force_components : tuple of three SymEngine expressions
        R in the basis of ``frame``.
    """

    name: str
    point: str
    pinned: str | None
    elements: tuple[str, ...]
    force: Vector
    moment: Vector
    free_axes: tuple[Vector, ...]
    free_rotations: int
    frame: str
    force_components: tuple[se.Basic, se.Basic, se.Basic]

    @property
    def transmits_moment(self) -> bool:
        """False for a pin that lets its body turn about every axis (a ball joint)."""
        return not (self.pinned is not None and self.free_rotations == 3)


def _groups(v: Verification) -> list[list[int]]:
    """Indices of the elements of each group linked by shared coordinates (union–find)."""
    kin = v.eom.kinematics
    coordinate_of = {s: k for k, s in enumerate(kin.q)} | {s: k for k, s in enumerate(kin.qd)}
    parent = list(range(len(v.theorems)))

    def root(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    owner: dict[int, int] = {}
    for e, th in enumerate(v.theorems):
        # The rates in V(G) and Ω: the coordinates that move the element (an angle may sit
        # in a frame's rotation, never in the components of OG).
        free = kin.velocity(th.name).free_symbols() | kin.position(th.name).free_symbols()
        if th.kind == "body":
            free |= kin.omega(kin.model.body(th.name).frame).free_symbols()
        for s in free:
            k = coordinate_of.get(s)
            if k is None:
                continue
            if k in owner:
                parent[root(e)] = root(owner[k])
            else:
                owner[k] = e
    out: dict[int, list[int]] = {}
    for e in range(len(v.theorems)):
        out.setdefault(root(e), []).append(e)
    return list(out.values())


def _rank(kin: Kinematics, vectors: Sequence[Vector]) -> int:
    """Number of independent vectors at a random configuration (numeric)."""
    if not vectors:
        return 0
    comps = [kin.frames.express(w, GALILEAN_FRAME) for w in vectors]
    symbols = sorted(set().union(*(c.free_symbols for row in comps for c in row)), key=str)
    rng = random.Random(11)
    # A few random points, until one where every component is a finite real number: asin(φ) has
    # none at φ > 1 (SymEngine's "Not Implemented"), 1e308 θ overflows.
    for low, high in ((0.3, 1.7), (0.3, 1.7), (0.05, 0.95), (0.05, 0.95), (-0.95, -0.05)):
        point = {s: se.RealDouble(rng.uniform(low, high)) for s in symbols}
        try:
            matrix = np.array([[float(c.subs(point)) for c in row] for row in comps], dtype=float)
        except (RuntimeError, TypeError, ValueError, OverflowError):
            continue
        if np.isfinite(matrix).all():
            s = np.linalg.svd(matrix, compute_uv=False)
            return int(np.sum(s > RANK_RTOL * max(s[0], 1e-300)))
    return len(vectors)  # no point where they are all defined: taken as independent, as declared


def _shortest_frame(kin: Kinematics, v: Vector) -> tuple[str, tuple[se.Basic, se.Basic, se.Basic]]:
    names = [f.name for f in kin.model.frames if not f.name.startswith("_")]
    if len(names) > MAX_DISPLAY_FRAMES:
        names = [GALILEAN_FRAME]
    sizes = []
    for name in names:
        comps = kin.frames.express(v, name)
        sizes.append((sum(len(str(se.expand(c))) for c in comps), name, comps))
    _, name, comps = min(sizes, key=lambda item: item[0])  # the first among equals
    return name, comps


def reactions(source: Verification | EquationsOfMotion, *, display: bool = True) -> tuple[Reaction, ...]:
    """The reactions of the ground on each group of linked elements (see the module docstring).

    Parameters
    ----------
    source : Verification or EquationsOfMotion
        The equations, or their verification (`verify`) when already made.
    display : bool, optional
        ``display=False`` leaves ``force_components`` in R0's basis instead of the frame where they
        read shortest: that choice expands R in every frame (seconds for a robot arm), and the
        numbers along a trajectory (`reaction_history`) do not need it.

    Returns
    -------
    tuple of Reaction
        One per group of linked elements.

    Examples
    --------
    >>> import lagrangian
    >>> [r.name for r in reactions(lagrangian.derive(lagrangian.lagrange_top()))]
    ['R_O']
    """
    v = source if isinstance(source, Verification) else verify(source)
    kin = v.eom.kinematics
    model = kin.model
    out = []
    for group in _groups(v):
        elements = [v.theorems[e] for e in group]
        _need_masses(model, [th.name for th in elements if th.kind == "body"])
        pins = [th for th in elements if th.kind == "body" and model.body(th.name).fixed_point is not None]
        point = pins[0].point if len(pins) == 1 else ORIGIN
        force, moment = Vector.zero(), Vector.zero()
        for th in elements:
            r = th.constraint_force
            force = force + r
            arm = kin.position(th.point) - kin.position(point)  # A P_E: δ_A = δ_P + AP ∧ m γ(G)
            moment = moment + th.constraint_moment
            if not arm.is_zero() and not r.is_zero():
                moment = moment + kin.frames.cross(arm, r)
        names = tuple(th.name for th in elements)
        if len(pins) == 1:
            pinned = pins[0].name
            axes = tuple(w for w in kin.partial_omegas(model.body(pinned).frame) if not w.is_zero())
            name = f"R_{point}"
        else:
            pinned, axes = None, ()
            name = "R(→" + "+".join(names) + ")"
        if display:
            frame, comps = _shortest_frame(kin, force)
        else:
            frame, comps = GALILEAN_FRAME, tuple(_r0(kin, force))
        out.append(Reaction(name, point, pinned, names, force, moment, axes, _rank(kin, axes), frame, comps))
    return tuple(out)


def _need_masses(model, bodies: Sequence[str]) -> None:
    """A reaction takes Σ m γ(G) and the weights of its group: each body needs its mass.

    A body may leave its mass out when its centre is fixed (the Lagrange equations do not
    hold it); its mass then still weighs on the reaction of its axle.
    """
    for name in bodies:
        if not model.body(name).mass_given:
            where = model.where("body", name)
            raise ModelError(f"the reactions need the mass of body `{name}`, which the model leaves out "
                             "(its weight bears on its axle)", symbol=name, file=where.file, line=where.line,
                             fix=f'give it its mass, e.g. mass = "M" under [bodies.{name}]; the equations of motion '
                                 "do not need it")


# -- numbers along a trajectory ------------------------------------------------------------------
class _Numeric:
    """Expressions of (q, q̇, q̈, t) as one LLVM-compiled function of the trajectory's states."""

    def __init__(self, eom: EquationsOfMotion, parameters: Mapping[str, float], exprs: Sequence[se.Basic],
                 inputs: Sequence[str] = ()) -> None:
        values = {se.Symbol(k): float(x) for k, x in parameters.items()}
        args = [*eom.q, *eom.qd, *eom.qdd, eom.t, *eom.multipliers, *(se.Symbol(u) for u in inputs)]
        subbed = [as_expr(e).subs(values) for e in exprs]
        left = set().union(*(e.free_symbols for e in subbed)) - set(args) if subbed else set()
        if left:
            names = ", ".join(sorted(f"`{s}`" for s in map(str, left)))
            raise SimulationError(f"The parameters {names} have no value in the trajectory, and the reactions "
                                  "need them.", fix="simulate with a value for each (parameters={...}, or --set "
                                  "NAME=... on the command line)")
        self.size = len(subbed)
        self._f = se.Lambdify(args, subbed, backend="llvm", cse=True) if subbed else None

    def __call__(self, states: np.ndarray) -> np.ndarray:
        if self._f is None:
            return np.zeros((len(states), 0))
        return np.asarray(self._f(states), dtype=float).reshape(len(states), self.size)


def _varying_inputs(trajectory: Trajectory, eom: EquationsOfMotion) -> list[str]:
    """The inputs whose values are columns of the trajectory (they varied), not parameter values."""
    return [u for u in eom.model.inputs if u not in trajectory.parameters and u in trajectory.extra]


def _states(trajectory: Trajectory, eom: EquationsOfMotion) -> np.ndarray:
    # With complementary constraints, the multipliers λ_k are columns of the trajectory too; so are
    # the inputs that varied along the motion.
    missing = [s.name for s in eom.multipliers if s.name not in trajectory.extra]
    if missing:
        raise SimulationError(f"The trajectory has no values of the multiplier `{missing[0]}`.",
                              fix="simulate the model with its complementary constraints (lagrangian.simulate)")
    lam = [trajectory.extra[s.name] for s in eom.multipliers]
    inputs = [trajectory.extra[u] for u in _varying_inputs(trajectory, eom)]
    return np.column_stack([trajectory.q, trajectory.qd, trajectory.qdd, trajectory.t, *lam, *inputs])


def _r0(kin: Kinematics, v: Vector) -> list[se.Basic]:
    return list(kin.frames.express(v, GALILEAN_FRAME))


@dataclass(frozen=True)
class ReactionHistory:
    """A reaction along a trajectory, in R0 components.

    Parameters
    ----------
    name : str
        The reaction's name (`Reaction.name`).
    point : str
        Where ``moment`` is taken.
    t : ndarray of shape (N,)
        The times.
    force : ndarray of shape (N, 3)
        The resultant.
    moment : ndarray of shape (N, 3)
        The moment at ``point``.
    """

    name: str
    point: str
    t: np.ndarray
    force: np.ndarray
    moment: np.ndarray


def reaction_history(source: Verification | EquationsOfMotion,
                     trajectory: Trajectory) -> dict[str, ReactionHistory]:
    """Every reaction of `reactions` evaluated at the trajectory's states (q̈ from the trajectory).

    Parameters
    ----------
    source : Verification or EquationsOfMotion
        The equations, or their verification.
    trajectory : Trajectory
        A simulated motion.

    Returns
    -------
    dict of str to ReactionHistory
        By reaction name.
    """
    # The vector theorems only: the symbolic check of each L(q_i) is not needed for the numbers.
    v = source if isinstance(source, Verification) else verify(source, check=False)
    _check_coordinates(v, trajectory)
    kin = v.eom.kinematics
    out = {}
    states = _states(trajectory, v.eom)
    for r in reactions(v, display=False):
        values = _Numeric(v.eom, trajectory.parameters, _r0(kin, r.force) + _r0(kin, r.moment),
                          _varying_inputs(trajectory, v.eom))(states)
        out[r.name] = ReactionHistory(r.name, r.point, trajectory.t, values[:, :3], values[:, 3:])
    return out


@dataclass(frozen=True)
class TrajectoryResiduals:
    """Newton–Euler residuals at the states of a trajectory, relative to the size of their terms.

    Parameters
    ----------
    t : ndarray of shape (N,)
        The times.
    coordinates : tuple of str
        The names of q_i.
    projections : ndarray of shape (N, n)
        ``|Σ m γ·∂V/∂q̇_i + δ·∂Ω/∂q̇_i − (efforts)|`` over Σ of the terms' sizes.
    reactions : mapping of str to ReactionHistory
        Name → `ReactionHistory` (R and M in R0 components).
    resultant : mapping of str to ndarray
        Name → (N,) relative residual of Σ m γ(G) = Σ F_given + R, with R from its formula.
    moment : mapping of str to ndarray
        Name → (N,) relative residual of the moment theorem at the pin with R, along the axes the pin
        leaves free (all three for a ball joint: δ_O = M_O(given), the seed's equation).
    """

    t: np.ndarray
    coordinates: tuple[str, ...]
    projections: np.ndarray
    reactions: Mapping[str, ReactionHistory]
    resultant: Mapping[str, np.ndarray]
    moment: Mapping[str, np.ndarray]

    @property
    def max_relative(self) -> float:
        """The largest relative residual of all."""
        values = [float(np.max(self.projections, initial=0.0))]
        values += [float(np.max(a, initial=0.0)) for a in (*self.resultant.values(), *self.moment.values())]
        return max(values)

    def worst(self) -> tuple[str, float]:
        """The check with the largest relative residual and that residual.

        Returns
        -------
        name : str
            The check (``"L(theta)"``, ``"resultant theorem with R_O"``...).
        residual : float
            Its largest relative residual.
        """
        items = [(f"L({c})", float(np.max(self.projections[:, k], initial=0.0)))
                 for k, c in enumerate(self.coordinates)]
        items += [(f"resultant theorem with {k}", float(np.max(a, initial=0.0))) for k, a in self.resultant.items()]
        items += [(f"moment theorem with {k}", float(np.max(a, initial=0.0))) for k, a in self.moment.items()]
        return max(items, key=lambda kv: kv[1])


def _check_coordinates(v: Verification, trajectory: Trajectory) -> None:
    if tuple(trajectory.coordinates) != v.eom.coordinates:
        raise SimulationError(
            f"The trajectory's coordinates {list(trajectory.coordinates)} are not those of the model "
            f"{list(v.eom.coordinates)}.", fix="check it against the model it was simulated from")


def _norms(a: np.ndarray) -> np.ndarray:
    """Euclidean norms of consecutive 3-vectors: (N, 3k) → (N, k)."""
    return np.linalg.norm(a.reshape(len(a), -1, 3), axis=2)


def check_trajectory(source: Verification | EquationsOfMotion, trajectory: Trajectory) -> TrajectoryResiduals:
    """The Newton–Euler theorems evaluated along ``trajectory`` (residuals ≈ rounding, ≤ 1e-9 relative).

    Each residual is divided by the sum of the sizes of the terms it balances (``|m γ||∂V| +
    (|δ| + |Ω||σ|)|∂Ω| + |F||∂V| + |M||∂Ω|`` for a projection), so it measures the cancellation, not
    the motion's scale: ``|Ω||σ|`` bounds the gyroscopic part Ω ∧ σ of δ = dσ/dt, whose two parts
    cancel for a body turning freely (δ = 0 = M), where ``|δ|`` alone would measure rounding by
    rounding.  Vectors are evaluated in R0 components from one compiled function.

    Parameters
    ----------
    source : Verification or EquationsOfMotion
        The equations, or their verification.
    trajectory : Trajectory
        A simulated motion.

    Returns
    -------
    TrajectoryResiduals
        The relative residuals at each state.
    """
    v = source if isinstance(source, Verification) else verify(source)
    _check_coordinates(v, trajectory)
    eom, kin = v.eom, v.eom.kinematics
    model = kin.model
    n = kin.n
    exprs: list[se.Basic] = []
    for th in v.theorems:  # per element: m γ, F, δ_P, M_P, σ_P and Ω (R0 components)
        omega = kin.omega(model.body(th.name).frame) if th.kind == "body" else Vector.zero()
        for vec in (th.mass_acceleration, th.force, th.dynamic_moment, th.moment, th.angular_momentum, omega):
            exprs += _r0(kin, vec)
    for th in v.theorems:  # per element and coordinate: ∂V(P)/∂q̇_i, ∂Ω/∂q̇_i
        dw = kin.partial_omegas(model.body(th.name).frame) if th.kind == "body" else (Vector.zero(),) * n
        for dv, w in zip(kin.partial_velocities(th.point), dw, strict=True):
            exprs += _r0(kin, dv) + _r0(kin, w)
    exprs += list(v.virtual_power)
    all_reactions = reactions(v)
    for r in all_reactions:
        exprs += _r0(kin, r.force) + _r0(kin, r.moment)
        exprs += [c for th_name in r.elements for c in _r0(kin, kin.position(v.element(th_name).point)
                                                          - kin.position(r.point))]
        exprs += [c for w in r.free_axes for c in _r0(kin, w)]
    values = _Numeric(eom, trajectory.parameters, exprs, _varying_inputs(trajectory, eom))(_states(trajectory, eom))
    N, E = len(values), len(v.theorems)
    element_vectors = values[:, :18 * E].reshape(N, E, 6, 3)
    at = 18 * E
    partial = values[:, at:at + 6 * E * n].reshape(N, E, n, 2, 3)
    at += 6 * E * n
    extra = values[:, at:at + n]
    at += n
    m_gamma, force, delta, moment, sigma, spin = (element_vectors[:, :, k, :] for k in range(6))
    d_v, d_w = partial[:, :, :, 0, :], partial[:, :, :, 1, :]
    dyn = np.einsum("nej,neij->ni", m_gamma, d_v) + np.einsum("nej,neij->ni", delta, d_w)
    given = np.einsum("nej,neij->ni", force, d_v) + np.einsum("nej,neij->ni", moment, d_w) + extra
    norm = np.linalg.norm
    scale = (np.einsum("ne,nei->ni", norm(m_gamma, axis=2) + norm(force, axis=2), norm(d_v, axis=3))
             + np.einsum("ne,nei->ni", norm(delta, axis=2) + norm(moment, axis=2)
                         + norm(spin, axis=2) * norm(sigma, axis=2), norm(d_w, axis=3))
             + np.abs(extra))
    projections = np.abs(dyn - given) / np.maximum(scale, np.finfo(float).tiny)
    histories, resultant, moment_res = {}, {}, {}
    index = {th.name: e for e, th in enumerate(v.theorems)}
    for r in all_reactions:
        k = len(r.elements)
        block = values[:, at:at + 6 + 3 * k + 3 * len(r.free_axes)]
        at += block.shape[1]
        R, M = block[:, :3], block[:, 3:6]
        arms = block[:, 6:6 + 3 * k].reshape(N, k, 3)
        axes = block[:, 6 + 3 * k:].reshape(N, len(r.free_axes), 3)
        histories[r.name] = ReactionHistory(r.name, r.point, trajectory.t, R, M)
        members = [index[name] for name in r.elements]
        sum_mg = m_gamma[:, members].sum(axis=1)
        sum_f = force[:, members].sum(axis=1)
        size = norm(sum_mg, axis=1) + norm(sum_f, axis=1) + norm(R, axis=1)
        resultant[r.name] = norm(sum_mg - sum_f - R, axis=1) / np.maximum(size, np.finfo(float).tiny)
        if r.pinned is None or not r.free_axes:
            continue
        # Moment theorem at the pin for the group, with R applied there (no arm): δ = M(given) + M_joint,
        # M_joint across the free axes only; the residual is what lies along them.
        arm_terms = np.cross(arms, m_gamma[:, members] - force[:, members])
        total = delta[:, members].sum(axis=1) - moment[:, members].sum(axis=1) + arm_terms.sum(axis=1)
        along = np.zeros_like(total)
        for j in range(N):
            u, s, _ = np.linalg.svd(axes[j].T, full_matrices=False)
            basis = u[:, s > RANK_RTOL * max(s[0], 1e-300)] if len(s) else u[:, :0]
            along[j] = basis @ (basis.T @ total[j])
        m_size = (norm(delta[:, members], axis=2).sum(axis=1) + norm(moment[:, members], axis=2).sum(axis=1)
                  + norm(arms, axis=2).sum(axis=1) * (norm(sum_mg, axis=1) + norm(sum_f, axis=1)))
        moment_res[r.name] = norm(along, axis=1) / np.maximum(m_size, np.finfo(float).tiny)
    return TrajectoryResiduals(trajectory.t, eom.coordinates, projections, histories, resultant, moment_res)
