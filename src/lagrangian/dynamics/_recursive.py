"""M q̈ = F of a kinematic tree by the recursive multibody algorithms, as named intermediates.

For a system whose frames form a tree of rotations about constant axes (joint angles
q_j, possibly relative) and whose points sit at offsets affine in q (prismatic joints),
the equations of motion are built the way Featherstone's algorithms compute them
(*Rigid Body Dynamics Algorithms*, 2008, ch. 5–6; Luh, Walker & Paul 1980), but
symbolically: every link velocity, acceleration, force and composite inertia is one
named intermediate, a short expression of earlier names, instead of being substituted
into its successors.  The generated code then grows about linearly with the number of
joints for F and quadratically for M, where the expanded entries of M and F of a chain
in relative angles grow several-fold per link.

The tree (`tree_structure`, in `_tree`): each frame F comes from its parent P by the rotation
of angle α = Σ_j a_j q_j + b about an axis e shared by P and F, and its origin O_F is
O_P + d_F, where d_F (components in P, affine in q) is what every point below F has
in P.  Each body or particle is a leaf node below its frame at its own offset c.
Writing x_F for components in F's basis:

forward (R0 to the leaves), with α̇ = Σ a_j q̇_j and C the change of basis P → F:
    ω_F = C ω_P + α̇ e,                ω̇⁰_F = C ω̇⁰_P + ω_F ∧ α̇ e
    v_F = C (v_P + ω_P ∧ d + ḋ),      a⁰_F = C (a⁰_P + ω̇⁰_P ∧ d + ω_P ∧ (ω_P ∧ d) + 2 ω_P ∧ ḋ)
(⁰: the part free of q̈, as in `_inertia`); at each body, with g the gravity field,
    f = m (a⁰_G − g),                 n = Π_G ω̇⁰ + ω ∧ Π_G ω            (Newton, Euler)
backward (the leaves to R0), moments about each origin:
    f_P += Cᵀ f_F,                    n_P += Cᵀ n_F + d ∧ Cᵀ f_F
and Γ⁰_j − Q_j(gravity) = Σ over the places q_j drives a node of S_j · (f, n), with
S_j = (a_j e, 0) for a rotation and (0, ∂d/∂q_j) for a translation: the virtual power
of the inertial and gravity forces in the virtual motion q_j* (seed, section I).

M by the composite-rigid-body algorithm: the inertia of each subtree about its node's
origin, (m, h = m OG, J_O), is carried to the parent (rotation, then Huygens with the
first moment), and M_ij = S_i · X (I^c S_j) along the path between the two nodes.

The same intermediates give T = Σ ½ m v_G² + ½ ω·Π_G ω, U(gravity) = −Σ m g·OG, and
the gradient ∂(T − U)/∂q by reverse accumulation through the intermediates (Hamilton's
form for the symplectic integrator); the course-form equations L(q_i) are derived from
T and the Q_i as always (`_lagrange`), and the tests check the two against each other.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import symengine as se

from ..kinematics import Kinematics
from ..model.vectors import add3 as _add3  # the vector toolkit's 3-component algebra
from ..model.vectors import cross as _cross
from ..model.vectors import sum_of
from ..model.vectors import turn as _turn
from ._articulated import articulated_accelerations
from ._forces import LoadForces
from ._tree import TreeStructure, Vec, _Node

__all__ = ["AUTO_MIN_DEPTH", "RecursiveForm", "recursive_form"]

_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)
_ZERO3: Vec = (_ZERO, _ZERO, _ZERO)
_HALF = se.Rational(1, 2)

#: `derive`'s automatic choice: the recursive form for a tree with at least this many
#: moving rotations in series (below it the expanded entries stay short, and the course
#: derivation keeps the exact form the tests and reports of small systems are written for).
AUTO_MIN_DEPTH = 4


# -- the intermediates ---------------------------------------------------------------------------------
class _Names:
    """The sequence of named intermediates: ``self(expr)`` records expr and returns its name."""

    def __init__(self) -> None:
        self.items: list[tuple[se.Symbol, se.Basic]] = []

    def __call__(self, expr: se.Basic) -> se.Basic:
        if expr.is_Number or expr.is_Symbol:
            return expr
        if isinstance(expr, se.Mul) and len(expr.args) == 2 and expr.args[0].is_Number and expr.args[1].is_Symbol:
            return expr  # −w: nothing to share
        name = se.Dummy(f"w{len(self.items)}")
        self.items.append((name, expr))
        return name

    def vec(self, v: Sequence[se.Basic]) -> Vec:
        return tuple(self(c) for c in v)


def _dot(a: Sequence[se.Basic], b: Sequence[se.Basic]) -> se.Basic:
    return sum_of([x * y for x, y in zip(a, b, strict=True) if type(x) is not _ZERO_TYPE and type(y) is not _ZERO_TYPE])


def _scale(k: se.Basic, v: Vec) -> Vec:
    return tuple(_ZERO if type(c) is _ZERO_TYPE else k * c for c in v)


def _matvec(pi: tuple[Vec, Vec, Vec] | None, w: Vec) -> Vec:
    if pi is None:
        return _ZERO3
    return tuple(_dot(row, w) for row in pi)


def _unit(axis: int, k: se.Basic) -> Vec:
    out = [_ZERO, _ZERO, _ZERO]
    out[axis] = k
    return tuple(out)


@dataclass(frozen=True)
class RecursiveForm:
    """M q̈ = F, T, U and Hamilton's ∂(T − U)/∂q of a kinematic tree, over named intermediates.

    Parameters
    ----------
    intermediates : tuple of (SymEngine Symbol, SymEngine expression)
        (name, expression) in the order of computation; each expression holds q, q̇, t, parameters
        and earlier names only.
    M : tuple of tuples of SymEngine expressions
        The n×n mass matrix, in those names.
    F : tuple of SymEngine expressions
        The n entries of F, in those names.
    T : SymEngine expression
        The kinetic energy.
    U : SymEngine expression
        The potential (gravity, plus the potentials of the other loads).
    dL_dq : tuple of SymEngine expressions
        ∂T/∂q − ∂U_gravity/∂q + Q_i of the other loads, couples included (the right side of ṗ in
        Hamilton's form, see `codegen._codegen`), in the names.
    conservative : bool
        Every load derives from a potential (then T + U is the energy integral).
    loads : tuple of LoadForces
        The Q_i of the loads the recursion does not handle (all but uniform gravity).
    qdd : tuple of SymEngine expressions, optional
        The accelerations q̈ by the articulated-body algorithm (`_articulated`), in the names, when
        every coordinate drives one joint of its own; else None (then q̈ solves M q̈ = F).
    pivots : tuple of (SymEngine expression, SymEngine expression)
        With ``qdd``, (D_j, M_jj) for each j: the articulated pivot and M's diagonal entry.
    qdd_forward : int
        With ``qdd``, the position in ``intermediates`` where its forward pass starts (what comes
        before, the backward pass, is computed first: the C code splits there).
    """

    intermediates: tuple[tuple[se.Symbol, se.Basic], ...]
    M: tuple[tuple[se.Basic, ...], ...]
    F: tuple[se.Basic, ...]
    T: se.Basic
    U: se.Basic
    dL_dq: tuple[se.Basic, ...]
    conservative: bool
    loads: tuple[LoadForces, ...]
    qdd: tuple[se.Basic, ...] | None = None
    pivots: tuple[tuple[se.Basic, se.Basic], ...] = ()
    qdd_forward: int = 0

    def needed(self, exprs: Sequence[se.Basic], after: int = 0) -> list[tuple[se.Symbol, se.Basic]]:
        """The intermediates ``exprs`` depend on, in order (what a function that computes them must define).

        Parameters
        ----------
        exprs : sequence of SymEngine expressions
            Expressions in the names.
        after : int, optional
            With ``after``, only those at that position or later (the earlier ones are given).

        Returns
        -------
        list of (SymEngine Symbol, SymEngine expression)
            The intermediates needed, in the order of computation.
        """
        position = {s: k for k, (s, _) in enumerate(self.intermediates) if k >= after}
        keep: set[int] = set()
        stack = [position[s] for e in exprs for s in e.free_symbols if s in position]
        while stack:
            k = stack.pop()
            if k in keep:
                continue
            keep.add(k)
            stack.extend(position[s] for s in self.intermediates[k][1].free_symbols if s in position)
        return [self.intermediates[k] for k in sorted(keep)]

    def expand(self, exprs: Sequence[se.Basic]) -> list[se.Basic]:
        """``exprs`` with every intermediate replaced by its expression (small systems: it swells).

        Parameters
        ----------
        exprs : sequence of SymEngine expressions
            Expressions in the names.

        Returns
        -------
        list of SymEngine expressions
            The same, in q, q̇, t and the parameters only.
        """
        values: dict[se.Basic, se.Basic] = {}
        for s, e in self.needed(exprs):
            values[s] = e.xreplace(values)
        return [e.xreplace(values) for e in exprs]

    def evaluate(self, exprs: Sequence[se.Basic], values: dict[se.Basic, float]) -> list[float]:
        """Evaluate ``exprs`` at ``values``.

        Parameters
        ----------
        exprs : sequence of SymEngine expressions
            Expressions in the names.
        values : dict of SymEngine expression to float
            Every q, q̇, t and parameter symbol to a float.

        Returns
        -------
        list of float
            The values of ``exprs``.
        """
        known: dict[se.Basic, se.Basic] = {s: se.RealDouble(float(v)) for s, v in values.items()}
        for s, e in self.needed(exprs):
            known[s] = se.RealDouble(float(e.xreplace(known)))
        return [float(e.xreplace(known)) for e in exprs]


def _gradient(names: _Names, f: se.Basic, wrt: Sequence[se.Symbol]) -> list[se.Basic]:
    """∂f/∂x for x in ``wrt`` through the intermediates, by reverse accumulation (adjoints).

    The adjoint of each intermediate w_k is Σ over its users w_m of w̄_m ∂w_m/∂w_k, one new
    intermediate each: the gradient costs a few times f itself, whatever the length of ``wrt``.
    """
    position = {s: k for k, (s, _) in enumerate(names.items)}
    target = {x: i for i, x in enumerate(wrt)}
    adjoint: dict[int, list[se.Basic]] = {}
    out: list[list[se.Basic]] = [[] for _ in wrt]

    def push(expr: se.Basic, weight: se.Basic) -> None:
        if isinstance(expr, se.Add) and len(expr.args) > 4:
            for term in expr.args:  # each term's few symbols, not every symbol of the sum
                push(term, weight)
            return
        for s in expr.free_symbols:
            k = position.get(s)
            i = target.get(s)
            if k is None and i is None:
                continue
            d = expr.diff(s)
            if type(d) is _ZERO_TYPE:
                continue
            term = d if weight == 1 else weight * d
            if k is not None:
                adjoint.setdefault(k, []).append(term)
            else:
                out[i].append(term)  # type: ignore[index]

    push(f, se.Integer(1))
    for k in range(len(position) - 1, -1, -1):
        terms = adjoint.pop(k, None)
        if terms:
            push(names.items[k][1], names(sum_of(terms)))
    return [sum_of(o) for o in out]


def recursive_form(kin: Kinematics, tree: TreeStructure, other: tuple[LoadForces, ...]) -> RecursiveForm:
    """Build `RecursiveForm` of ``kin.model`` on its ``tree`` (`tree_structure`).

    ``other`` are the `LoadForces` of ``tree.other_loads`` (`generalized_forces`): their Q_i
    are added to F as they are.  The steps, in the order their intermediates are named:
    `_forward` (velocities and accelerations), `_newton_euler` (each body's f, n, T, U),
    `_forces` (the backward pass: F), `_composite_inertias` and `_mass_matrix` (M),
    `articulated_accelerations` (q̈), `_gradient` (∂(T − U)/∂q).
    """
    nodes = tree.nodes
    w = _Names()
    motion = _forward(w, kin, tree)
    force, moment, T_terms, U_terms = _newton_euler(w, nodes, motion)
    F, Q_other, Q_couples, couples = _forces(w, kin, tree, motion, force, moment, other)
    composite = _composite_inertias(w, nodes, motion.to_parent)
    M_out = _mass_matrix(w, nodes, kin.n, motion, composite)
    aba = articulated_accelerations(w, nodes, kin.qd, motion.omega, motion.grav, motion.to_child, motion.to_parent,
                                    couples, Q_other, composite, kin.q)
    qdd, pivots, forward = aba if aba is not None else (None, (), 0)

    T = sum_of(T_terms)
    U_gravity = sum_of(U_terms)
    dL = _gradient(w, T - U_gravity, kin.q)
    dL_dq = tuple(a + q + c for a, q, c in zip(dL, Q_other, Q_couples, strict=True))
    U_other = [f.potential for f in other if f.potential is not None]
    conservative = all(f.potential is not None for f in other) and not tree.couples
    return RecursiveForm(tuple(w.items), M_out, F, T, U_gravity + sum_of(U_other), dL_dq, conservative, other,
                         qdd, pivots, forward)


#: A change of basis between a node and its parent, applied to a vector's components.
Turn = Callable[[Vec], Vec]


@dataclass(frozen=True)
class _Motion:
    """The forward pass, one entry per node in its own basis: ω, ω̇⁰ (free of q̈), the velocity ``vel``
    and acceleration ``acc`` (free of q̈) of its origin, its position ``pos`` = OO_N, the gravity
    fields ``grav``; ``to_child[k]`` turns the parent's components into node k's, ``to_parent[k]``
    back (None for R0)."""

    omega: list[Vec]
    alpha: list[Vec]
    vel: list[Vec]
    acc: list[Vec]
    pos: list[Vec]
    grav: list[list[Vec]]
    to_child: list[Turn | None]
    to_parent: list[Turn | None]


def _forward(w: _Names, kin: Kinematics, tree: TreeStructure) -> _Motion:
    """Forward pass, R0 to the leaves, with α̇ = Σ a_j q̇_j and C the change of basis parent → node:

        ω_F = C ω_P + α̇ e,                ω̇⁰_F = C ω̇⁰_P + ω_F ∧ α̇ e,
        v_F = C (v_P + ω_P ∧ d + ḋ),      a⁰_F = C (a⁰_P + ω̇⁰_P ∧ d + ω_P ∧ (ω_P ∧ d) + 2 ω_P ∧ ḋ).
    """
    nodes = tree.nodes
    count = len(nodes)
    omega: list[Vec] = [_ZERO3] * count
    alpha: list[Vec] = [_ZERO3] * count  # ω̇⁰
    vel: list[Vec] = [_ZERO3] * count  # velocity of the node's origin
    acc: list[Vec] = [_ZERO3] * count  # its acceleration, part free of q̈
    pos: list[Vec] = [_ZERO3] * count  # its position OO_N
    grav: list[list[Vec]] = [[g for _, g in tree.gravity]] + [[] for _ in range(count - 1)]
    to_child: list[Turn | None] = [None] * count  # components in the parent → in the node
    to_parent: list[Turn | None] = [None] * count
    qd = kin.qd
    for k, node in enumerate(nodes):
        if node.parent is None:
            continue
        p = node.parent
        if node.axis is None:
            down = up = (lambda v: v)
        else:
            c, s = w(se.cos(node.angle)), w(se.sin(node.angle))
            down = (lambda v, a=node.axis, c=c, s=s: _turn(a, c, -s, v))
            up = (lambda v, a=node.axis, c=c, s=s: _turn(a, c, s, v))
        to_child[k], to_parent[k] = down, up
        d = node.offset
        d_rate = _ZERO3
        for j, u in node.offset_rates.items():
            d_rate = _add3(d_rate, _scale(qd[j], u))
        wp, ap = omega[p], alpha[p]
        vel[k] = w.vec(down(_add3(_add3(vel[p], _cross(wp, d)), d_rate)))
        a_abs = _add3(_add3(acc[p], _cross(ap, d)), _add3(_cross(wp, _cross(wp, d)), _scale(se.Integer(2), _cross(wp, d_rate))))
        acc[k] = w.vec(down(a_abs))
        pos[k] = w.vec(down(_add3(pos[p], d)))
        grav[k] = [w.vec(down(g)) for g in grav[p]]
        if node.axis is None:
            omega[k], alpha[k] = wp, ap
        else:
            spin = _unit(node.axis, sum_of([a * qd[j] for j, a in node.rates.items()]))
            omega[k] = w.vec(_add3(down(wp), spin))
            alpha[k] = w.vec(_add3(down(ap), _cross(omega[k], spin)))
    return _Motion(omega, alpha, vel, acc, pos, grav, to_child, to_parent)


def _newton_euler(w: _Names, nodes: Sequence[_Node], motion: _Motion,
                  ) -> tuple[list[Vec], list[Vec], list[se.Basic], list[se.Basic]]:
    """At each body or particle, with g its gravity field: f = m (a⁰_G − g), n = Π_G ω̇⁰ + ω ∧ Π_G ω
    (Newton, Euler), and its terms of T = ½ m v_G² + ½ ω·Π_G ω and U = −m g·OG.

    Returns (f, n) per node (zero on frames) and the lists of T's and U's terms.
    """
    count = len(nodes)
    omega, alpha, vel, acc, pos, grav = motion.omega, motion.alpha, motion.vel, motion.acc, motion.pos, motion.grav
    force: list[Vec] = [_ZERO3] * count
    moment: list[Vec] = [_ZERO3] * count
    T_terms: list[se.Basic] = []
    U_terms: list[se.Basic] = []
    for k, node in enumerate(nodes):
        if node.axis is not None or node.parent is None or (node.mass == 0 and node.inertia is None):
            continue
        m = node.mass
        g_total = _ZERO3
        for i in node.gravity:
            g_total = _add3(g_total, grav[k][i])
        force[k] = w.vec(_scale(m, _add3(acc[k], _scale(se.Integer(-1), g_total))))
        pw = _matvec(node.inertia, omega[k])
        moment[k] = w.vec(_add3(_matvec(node.inertia, alpha[k]), _cross(omega[k], pw)))
        T_terms.append(_HALF * m * _dot(vel[k], vel[k]))
        if node.inertia is not None:
            T_terms.append(_HALF * _dot(omega[k], pw))
        if node.gravity:
            U_terms.append(-m * _dot(g_total, pos[k]))
    return force, moment, T_terms, U_terms


def _backward(w: _Names, nodes: Sequence[_Node], to_parent: Sequence[Turn | None], n: int, force: list[Vec],
              moment: list[Vec]) -> list[list[se.Basic]]:
    """Backward pass, the leaves to R0, moments about each origin: f_P += Cᵀ f_F, n_P += Cᵀ n_F + d ∧ Cᵀ f_F;
    returns, for each j, the terms of Σ over the places q_j moves a node of S_j · (f, n) of its subtree,
    S_j = (a_j e, 0) for a rotation and (0, ∂d/∂q_j) for a translation."""
    out: list[list[se.Basic]] = [[] for _ in range(n)]
    force, moment = list(force), list(moment)
    for k in range(len(nodes) - 1, 0, -1):
        node = nodes[k]
        f, mo = force[k], moment[k]
        if node.axis is not None:
            f, mo = w.vec(f), w.vec(mo)  # a frame's sums, named once
        if all(type(c) is _ZERO_TYPE for c in (*f, *mo)):
            continue
        for j, a in node.rates.items():
            out[j].append(a * mo[node.axis])  # type: ignore[index]
        up = to_parent[k]
        assert up is not None  # every node but R0 has a parent
        fp = up(f)
        for j, u in node.offset_rates.items():
            out[j].append(_dot(u, fp))
        p = node.parent
        assert p is not None
        force[p] = _add3(force[p], fp)
        moment[p] = _add3(moment[p], _add3(up(mo), _cross(node.offset, fp)))
    return out


def _forces(w: _Names, kin: Kinematics, tree: TreeStructure, motion: _Motion, force: list[Vec], moment: list[Vec],
            other: tuple[LoadForces, ...]) -> tuple[tuple[se.Basic, ...], list[se.Basic], list[se.Basic], list[Vec]]:
    """F = Q(other loads) − Γ⁰ with Γ⁰_j − Q_j(gravity, couples) the backward pass of the bodies' (f, n − C⃗):
    the virtual power of the inertial, gravity and couple forces in the virtual motion q_j* (seed, section I).

    Returns F, the other loads' Q, the couples' Q (their own backward pass: Q_j = C⃗ · ∂Ω/∂q̇_j) and
    the couple on each node in its basis.
    """
    nodes, n = tree.nodes, kin.n
    count = len(nodes)
    couples = [_ZERO3] * count
    for k, couple in tree.couples:  # the torques and joint dampers: Q_j = C⃗ · ∂Ω/∂q̇_j
        couples[k] = _add3(couples[k], kin.frames.express(couple, nodes[k].frame))
    gamma0 = _backward(w, nodes, motion.to_parent, n, force,
                       [_add3(mo, _scale(se.Integer(-1), c)) for mo, c in zip(moment, couples, strict=True)])
    Q_couples = ([sum_of(q) for q in _backward(w, nodes, motion.to_parent, n, [_ZERO3] * count, couples)]
                 if tree.couples else [_ZERO] * n)
    Q_other = [sum_of([load.Q[i] for load in other]) for i in range(n)]
    F = tuple(q - sum_of(g) if g else q for q, g in zip(Q_other, gamma0, strict=True))
    return F, Q_other, Q_couples, couples


#: The composite inertia of each node's subtree about its origin, in its basis: masses m, first
#: moments h = m·(centre of mass − origin), inertia matrices J_O.
Composite = tuple[list[se.Basic], list[Vec], list[list[list[se.Basic]]]]


def _composite_inertias(w: _Names, nodes: Sequence[_Node], to_parent: Sequence[Turn | None]) -> Composite:
    """The composite-rigid-body algorithm's inertias: each subtree's (m, h, J_O) carried to its parent, the
    leaves first: rotated (J → C J Cᵀ), then moved by d with the first moment (Huygens),

        m_P += m,   h_P += h + m d,   J_P += J + 2 (d·h) I − d hᵀ − h dᵀ + m (|d|² I − d dᵀ).
    """
    count = len(nodes)
    mass: list[se.Basic] = [nd.mass for nd in nodes]
    first: list[Vec] = [_ZERO3] * count  # h = m·(centre of mass − origin)
    inertia: list[list[list[se.Basic]]] = [[[nd.inertia[r][c] if nd.inertia is not None else _ZERO
                                             for c in range(3)] for r in range(3)] for nd in nodes]
    for k in range(count - 1, 0, -1):
        node = nodes[k]
        if node.axis is not None:
            _name_subtree(w, mass, first, inertia, k)
        if type(mass[k]) is _ZERO_TYPE and all(type(x) is _ZERO_TYPE for row in inertia[k] for x in row):
            continue
        up = to_parent[k]
        assert up is not None and node.parent is not None  # every node but R0 has a parent
        _carry_to_parent(mass, first, inertia, k, node.parent, node.offset, up)
    return mass, first, inertia


def _name_subtree(w: _Names, mass: list[se.Basic], first: list[Vec], inertia: list[list[list[se.Basic]]],
                  k: int) -> None:
    """Node k's subtree (m, h, J) as named intermediates, J's lower triangle the names of its upper one."""
    mass[k] = w(mass[k])
    first[k] = w.vec(first[k])
    inertia[k] = [[w(inertia[k][r][c]) if c >= r else None for c in range(3)] for r in range(3)]
    for r in range(3):
        for c in range(r):
            inertia[k][r][c] = inertia[k][c][r]


def _carry_to_parent(mass: list[se.Basic], first: list[Vec], inertia: list[list[list[se.Basic]]], k: int, p: int,
                     d: Vec, up: Turn) -> None:
    """Add node k's subtree (m, h, J_O) to its parent p's (`_composite_inertias`' formula): rotated by ``up``
    into p's basis, then moved by d, the offset of k's origin from p's, with the first moment (Huygens)."""
    m = mass[k]
    h = up(first[k])
    rows = [up(tuple(inertia[k][r])) for r in range(3)]  # (R J)ᵀ's columns are R J's rows rotated
    J = [up(tuple(rows[c][r] for c in range(3))) for r in range(3)]
    dh, dd = _dot(d, h), _dot(d, d)
    mass[p] = mass[p] + m
    for r in range(3):
        for c in range(3):
            shift = (2 * dh + m * dd if r == c else _ZERO) - d[r] * h[c] - h[r] * d[c] - m * d[r] * d[c]
            inertia[p][r][c] = inertia[p][r][c] + J[r][c] + shift
    first[p] = _add3(first[p], _add3(h, _scale(m, d)))


def _mass_matrix(w: _Names, nodes: Sequence[_Node], n: int, motion: _Motion,
                 composite: Composite) -> tuple[tuple[se.Basic, ...], ...]:
    """M_ij = S_i · X (I^c S_j) along the path between the two nodes where q̇_i and q̇_j move them: the
    composite inertia I^c of the later node applied to its motion S_j = (ω, v of the origin), the force
    and moment carried up the tree (f → C f, n → C n + d ∧ C f) and projected on each S_i met."""
    mass, first, inertia = composite
    count = len(nodes)
    # Where each q̇_j moves a node: spatial motions S = (ω, v of the origin) in the node's basis.
    occurrences: list[list[tuple[int, Vec, Vec]]] = [[] for _ in range(count)]
    for k, node in enumerate(nodes):
        for j, a in node.rates.items():
            occurrences[k].append((j, _unit(node.axis, a), _ZERO3))  # type: ignore[arg-type]
        for j, u in node.offset_rates.items():
            occurrences[k].append((j, _ZERO3, w.vec(motion.to_child[k](u))))  # type: ignore[misc]
    above = [False] * count  # some strict ancestor of the node moves with a coordinate
    for k in range(1, count):
        p = nodes[k].up
        above[k] = above[p] or bool(occurrences[p])
    M: list[list[list[se.Basic]]] = [[[] for _ in range(n)] for _ in range(n)]
    for k in range(1, count):
        for rank, (i, S_w, S_v) in enumerate(occurrences[k]):
            J = inertia[k]
            fv = w.vec(_add3(_scale(mass[k], S_v), _cross(S_w, first[k])))  # I^c S: force and moment
            nv = w.vec(_add3(tuple(_dot(J[r], S_w) for r in range(3)), _cross(first[k], S_v)))
            a, same = k, True
            while a:
                for idx, (j, T_w, T_v) in enumerate(occurrences[a]):
                    if same and idx > rank:
                        break  # the pairs of one node are counted once, from the later occurrence
                    value = _dot(T_w, nv) + _dot(T_v, fv)
                    if type(value) is _ZERO_TYPE:
                        continue
                    M[i][j].append(value)
                    if not (same and idx == rank):
                        M[j][i].append(value)
                if not above[a]:
                    break
                up, d = motion.to_parent[a], nodes[a].offset
                fv = w.vec(up(fv))  # type: ignore[misc]
                nv = w.vec(_add3(up(nv), _cross(d, fv)))  # type: ignore[misc]
                a, same = nodes[a].parent, False
    return tuple(tuple(sum_of(M[i][j]) for j in range(n)) for i in range(n))
