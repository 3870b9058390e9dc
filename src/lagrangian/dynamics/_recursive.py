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

The tree (`tree_structure`): each frame F comes from its parent P by the rotation of
angle α = Σ_j a_j q_j + b about an axis e shared by P and F, and its origin O_F is
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

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field

import symengine as se

from ..errors import DerivationError
from ..kinematics import Kinematics
from ..kinematics._frames import _add3, _cross, _turn
from ..model import GALILEAN_FRAME, Gravity, JointDamper, Torque, Vector
from ..model._vector import AXES, sum_of
from ._articulated import articulated_accelerations
from ._energy import _transport, rigid_inertia
from ._forces import LoadForces, _q_of

__all__ = ["RecursiveForm", "TreeStructure", "tree_structure", "recursive_form", "AUTO_MIN_DEPTH"]

Vec = tuple[se.Basic, se.Basic, se.Basic]
_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)
_ZERO3: Vec = (_ZERO, _ZERO, _ZERO)
_HALF = se.Rational(1, 2)

#: `derive`'s automatic choice: the recursive form for a tree with at least this many
#: moving rotations in series (below it the expanded entries stay short, and the course
#: derivation keeps the exact form the tests and reports of small systems are written for).
AUTO_MIN_DEPTH = 4


# -- the tree ------------------------------------------------------------------------------------
@dataclass
class _Node:
    """A frame (rotation from its parent) or a body/particle (a leaf, no rotation)."""

    name: str
    parent: int | None
    axis: int | None = None  # index of the rotation axis, None for a leaf or R0
    angle: se.Basic = _ZERO
    rates: dict[int, se.Basic] = field(default_factory=dict)  # j -> a_j = ∂α/∂q_j
    offset: Vec = _ZERO3  # d, in the parent's basis
    offset_rates: dict[int, Vec] = field(default_factory=dict)  # j -> ∂d/∂q_j
    mass: se.Basic = _ZERO
    inertia: tuple[Vec, Vec, Vec] | None = None  # Π_G in the node's basis (bodies)
    gravity: tuple[int, ...] = ()  # the gravity loads acting on this body or particle
    frame: str = GALILEAN_FRAME  # the frame whose basis the node's components are in
    children: list[int] = field(default_factory=list)


@dataclass
class TreeStructure:
    """The nodes of a kinematic tree, parents first; ``depth`` = most moving rotations in series."""

    nodes: list[_Node]
    depth: int
    gravity: tuple[tuple[Gravity, Vec], ...]  # each gravity load with its field in R0
    other_loads: tuple[int, ...]  # indices in model.loads of the loads not handled by the recursion
    couples: tuple[tuple[int, Vector], ...] = ()  # (node, couple C⃗ on it) of the torques and joint dampers


def _affine(kin: Kinematics, comps: Sequence[se.Basic]) -> dict[int, list[se.Basic]] | None:
    """{j: ∂comps/∂q_j} when every component is affine in q with constant coefficients, else None."""
    moving = set(kin.qd) | set(kin.qdd) | {kin.t}
    qset = set(kin.q)
    out: dict[int, list[se.Basic]] = {}
    for axis, c in enumerate(comps):
        free = c.free_symbols
        if free & moving:
            return None
        for j, q in enumerate(kin.q):
            if q in free:
                u = c.diff(q)
                if u.free_symbols & (qset | moving):
                    return None
                out.setdefault(j, [_ZERO, _ZERO, _ZERO])[axis] = u
    return out


def tree_structure(kin: Kinematics) -> TreeStructure | str:
    """The kinematic tree of ``kin.model``, or the reason why the model is not one."""
    model = kin.model
    if model.constraints:
        return "it has complementary constraints"
    if model.reference is not None and not model.reference.is_galilean_frame:
        return "its equations are written in a moving reference frame"
    index: dict[str, int] = {}
    nodes: list[_Node] = []
    depth: dict[str, int] = {}
    for frame in model.frames:
        node = _Node(frame.name, None if frame.parent is None else index[frame.parent], frame=frame.name)
        moving = 0
        if frame.rotation is not None:
            if not frame.rotation.elementary:  # the recursion's rotations are about x, y or z of the parent
                return f"frame `{frame.name}` turns about an axis other than its parent's x, y or z"
            node.axis = AXES[frame.rotation.axis]
            node.angle = frame.rotation.angle
            rates = _affine(kin, (frame.rotation.angle,))
            if rates is None:
                return (f"the rotation angle `{frame.rotation.angle}` of frame `{frame.name}` is not of the form "
                        "Σ a_j q_j + b with constant a_j, b")
            node.rates = {j: u[0] for j, u in rates.items()}
            moving = 1 if node.rates else 0
        depth[frame.name] = moving + (0 if frame.parent is None else depth[frame.parent])
        index[frame.name] = len(nodes)
        if node.parent is not None:
            nodes[node.parent].children.append(len(nodes))
        nodes.append(node)
    offset_set: set[int] = set()
    masses = [(b.name, b.frame, b.mass, b.center, b) for b in model.bodies]
    masses += [(p.name, None, p.mass, p.position, None) for p in model.particles]
    gravity: list[tuple[Gravity, Vec]] = []
    other: list[int] = []
    for k, load in enumerate(model.loads):
        if isinstance(load, Gravity):
            g = kin.frames.express(load.field, GALILEAN_FRAME)
            if all(not (c.free_symbols & (set(kin.q) | set(kin.qd) | {kin.t})) for c in g):
                gravity.append((load, g))
                continue
        other.append(k)
    leaf_of: dict[str, int] = {}
    for name, home, mass, position, body in masses:
        pieces = dict(position.pieces)
        if home is None:  # a particle: the deepest frame its position uses
            home = max(pieces, key=lambda f: model_depth(kin, f), default=GALILEAN_FRAME)
        path = [home]
        while nodes[index[path[-1]]].parent is not None:
            path.append(nodes[nodes[index[path[-1]]].parent].name)  # type: ignore[index]
        path.reverse()
        stray = [f for f in pieces if f not in path]
        if stray:
            return (f"the position of `{name}` has a part in frame `{stray[0]}`, which is not on the chain of frames "
                    f"from R0 to `{home}`")
        for frame, child in itertools.pairwise(path):
            piece = pieces.get(frame, _ZERO3)
            c = index[child]
            if c in offset_set:
                if any(se.expand(a - b) != 0 for a, b in zip(piece, nodes[c].offset, strict=True)):
                    return (f"the points below frame `{child}` do not share one origin for it (`{name}` differs in "
                            f"frame `{frame}`)")
                continue
            rates = _affine(kin, piece)
            if rates is None:
                return f"the position of `{name}` is not affine in the coordinates in frame `{frame}`"
            nodes[c].offset = tuple(piece)  # type: ignore[assignment]
            nodes[c].offset_rates = {j: tuple(u) for j, u in rates.items()}  # type: ignore[misc]
            offset_set.add(c)
        own = pieces.get(home, _ZERO3)
        rates = _affine(kin, own)
        if rates is None:
            return f"the position of `{name}` is not affine in the coordinates in frame `{home}`"
        leaf = _Node(name, index[home], offset=tuple(own), mass=mass, frame=home,  # type: ignore[arg-type]
                     offset_rates={j: tuple(u) for j, u in rates.items()})  # type: ignore[misc]
        if body is not None:
            _, pi_g = rigid_inertia(kin, body)  # checks the inertia (physical, at a point of the body)
            given = body.inertia
            if given.frame != body.frame and given.at != "G":
                # Given in a frame where it reads as in the body's (checked): moved to G with GP in
                # the body's components, which are constant (P is a point of the body, checked).
                gp = kin.frames.express(kin.position(given.at) - body.center, body.frame)
                pi_g = _transport(given.matrix, body.mass, gp, -1)
            leaf.inertia = pi_g  # Π_G in the body's basis
        leaf.gravity = tuple(k for k, (load, _) in enumerate(gravity) if not load.on or name in load.on)
        nodes[index[home]].children.append(len(nodes))
        leaf_of[name] = len(nodes)
        nodes.append(leaf)
    # Couples act on a body (its leaf) or a frame (its node): −C⃗ enters that node's Euler equation.
    couples: list[tuple[int, Vector]] = []
    kept: list[int] = []
    for k in other:
        load = model.loads[k]
        if isinstance(load, Torque) and _constant_q(kin, load):
            kept.append(k)  # a motor's τ about its joint axis: Q_j = τ (potential −τ q_j if τ is no input: `_constant_q`)
        elif isinstance(load, Torque):
            couples.append((leaf_of.get(load.on, index.get(load.on, 0)), load.torque))
            if load.reaction_on is not None:
                couples.append((leaf_of.get(load.reaction_on, index.get(load.reaction_on, 0)), -load.torque))
        elif isinstance(load, JointDamper):
            s1, s2 = load.bodies
            frame = {b.name: b.frame for b in model.bodies}
            relative = kin.omega(frame.get(s2, s2)) - kin.omega(frame.get(s1, s1))  # Ω(S2/S1)
            couple = relative * (-load.coefficient)
            couples.append((leaf_of.get(s2, index.get(s2, 0)), couple))
            couples.append((leaf_of.get(s1, index.get(s1, 0)), -couple))
        else:
            kept.append(k)
    return TreeStructure(nodes, max(depth.values(), default=0), tuple(gravity), tuple(kept), tuple(couples))


def _constant_q(kin: Kinematics, load: Torque) -> bool:
    """The torque's Q_j = C⃗·∂Ω(S/S')/∂q̇_j (course, virtual power) hold no q, q̇ nor t.

    That is a motor's constant τ about the axis of the joint between the two bodies it acts on:
    Q_j = τ a_j, whose potential is −τ α when τ is a constant of the model.  Such a torque is kept
    among the loads with their Q_i (a constant each) and potential, as the course's derivation has it,
    so that U holds −τ·q and T + U is the energy integral of a robot driven by constant torques, in
    both forms (by d/dt (T + U_gravity) = Σ τ_j q̇_j); a τ declared as an input u(t) is kept the same
    way, without a potential (`generalized_forces`).  Any other torque is a couple in the recursion.
    """
    Q, _, _ = _q_of(kin, load)
    moving = set(kin.q) | set(kin.qd) | {kin.t}
    return not any(x.free_symbols & moving for x in Q)


def model_depth(kin: Kinematics, frame: str) -> int:
    """Number of frames between R0 and ``frame``."""
    d, f = 0, kin.model.frame(frame)
    while f.parent is not None:
        d, f = d + 1, kin.model.frame(f.parent)
    return d


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
        return tuple(self(c) for c in v)  # type: ignore[return-value]


def _dot(a: Sequence[se.Basic], b: Sequence[se.Basic]) -> se.Basic:
    return sum_of([x * y for x, y in zip(a, b, strict=True) if type(x) is not _ZERO_TYPE and type(y) is not _ZERO_TYPE])


def _scale(k: se.Basic, v: Vec) -> Vec:
    return tuple(_ZERO if type(c) is _ZERO_TYPE else k * c for c in v)  # type: ignore[return-value]


def _matvec(pi: tuple[Vec, Vec, Vec] | None, w: Vec) -> Vec:
    if pi is None:
        return _ZERO3
    return tuple(_dot(row, w) for row in pi)  # type: ignore[return-value]


def _unit(axis: int, k: se.Basic) -> Vec:
    out = [_ZERO, _ZERO, _ZERO]
    out[axis] = k
    return tuple(out)  # type: ignore[return-value]


@dataclass(frozen=True)
class RecursiveForm:
    """M q̈ = F, T, U and Hamilton's ∂(T − U)/∂q of a kinematic tree, over named intermediates.

    Attributes
    ----------
    intermediates : (name, expression) in the order of computation; each expression holds
        q, q̇, t, parameters and earlier names only.
    M, F : n×n and n entries in those names.
    T, U : kinetic energy and potential (gravity, plus the potentials of the other loads).
    dL_dq : ∂T/∂q − ∂U_gravity/∂q + Q_i of the other loads, couples included (the right
        side of ṗ in Hamilton's form, see `_codegen`), in the names.
    conservative : every load derives from a potential (then T + U is the energy integral).
    loads : the Q_i of the loads the recursion does not handle (all but uniform gravity).
    qdd : q̈ by the articulated-body algorithm (`_articulated`), in the names, when every
        coordinate drives one joint of its own; else None (then q̈ solves M q̈ = F).
    pivots : with ``qdd``, (D_j, M_jj) for each j: the articulated pivot and M's diagonal entry.
    qdd_forward : with ``qdd``, the position in ``intermediates`` where its forward pass starts (what
        comes before, the backward pass, is computed first: the C code splits there).
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

        With ``after``, only those at that position or later (the earlier ones are given).
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
        """``exprs`` with every intermediate replaced by its expression (small systems: it swells)."""
        values: dict[se.Basic, se.Basic] = {}
        for s, e in self.needed(exprs):
            values[s] = e.xreplace(values)
        return [e.xreplace(values) for e in exprs]

    def evaluate(self, exprs: Sequence[se.Basic], values: dict[se.Basic, float]) -> list[float]:
        """Numbers of ``exprs`` at ``values`` (every q, q̇, t and parameter symbol to a float)."""
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
    are added to F as they are.
    """
    nodes = tree.nodes
    n = kin.n
    w = _Names()
    count = len(nodes)
    omega: list[Vec] = [_ZERO3] * count
    alpha: list[Vec] = [_ZERO3] * count  # ω̇⁰
    vel: list[Vec] = [_ZERO3] * count  # velocity of the node's origin
    acc: list[Vec] = [_ZERO3] * count  # its acceleration, part free of q̈
    pos: list[Vec] = [_ZERO3] * count  # its position OO_N
    grav: list[list[Vec]] = [[g for _, g in tree.gravity]] + [[] for _ in range(count - 1)]
    to_child: list = [None] * count  # components in the parent → in the node
    to_parent: list = [None] * count
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

    # -- bodies: Newton–Euler, T and U -----------------------------------------------------------
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

    # -- backward: forces of each subtree, moments about each node's origin; Γ⁰ ----------------------
    def backward(force: list[Vec], moment: list[Vec]) -> list[list[se.Basic]]:
        """Σ over the places q_j moves a node of S_j · (f, n) of the node's subtree, for each j."""
        out: list[list[se.Basic]] = [[] for _ in range(n)]
        force, moment = list(force), list(moment)
        for k in range(count - 1, 0, -1):
            node = nodes[k]
            f, mo = force[k], moment[k]
            if node.axis is not None:
                f, mo = w.vec(f), w.vec(mo)  # a frame's sums, named once
            if all(type(c) is _ZERO_TYPE for c in (*f, *mo)):
                continue
            for j, a in node.rates.items():
                out[j].append(a * mo[node.axis])  # type: ignore[index]
            up = to_parent[k]
            fp = up(f)
            for j, u in node.offset_rates.items():
                out[j].append(_dot(u, fp))
            p = node.parent
            force[p] = _add3(force[p], fp)
            moment[p] = _add3(moment[p], _add3(up(mo), _cross(node.offset, fp)))
        return out

    couples = [_ZERO3] * count
    for k, couple in tree.couples:  # the torques and joint dampers: Q_j = C⃗ · ∂Ω/∂q̇_j
        couples[k] = _add3(couples[k], kin.frames.express(couple, nodes[k].frame))
    gamma0 = backward(force, [_add3(mo, _scale(se.Integer(-1), c)) for mo, c in zip(moment, couples, strict=True)])
    Q_couples = [sum_of(q) for q in backward([_ZERO3] * count, couples)] if tree.couples else [_ZERO] * n
    Q_other = [sum_of([load.Q[i] for load in other]) for i in range(n)]
    F = tuple(q - sum_of(g) if g else q for q, g in zip(Q_other, gamma0, strict=True))

    # -- M: composite-rigid-body algorithm -----------------------------------------------------------
    mass: list[se.Basic] = [nd.mass for nd in nodes]
    first: list[Vec] = [_ZERO3] * count  # h = m·(centre of mass − origin)
    inertia: list[list[list[se.Basic]]] = [[[nd.inertia[r][c] if nd.inertia is not None else _ZERO
                                             for c in range(3)] for r in range(3)] for nd in nodes]
    for k in range(count - 1, 0, -1):
        node = nodes[k]
        if node.axis is not None:
            mass[k] = w(mass[k])
            first[k] = w.vec(first[k])
            inertia[k] = [[w(inertia[k][r][c]) if c >= r else None for c in range(3)] for r in range(3)]  # type: ignore[misc]
            for r in range(3):
                for c in range(r):
                    inertia[k][r][c] = inertia[k][c][r]
        m = mass[k]
        if type(m) is _ZERO_TYPE and all(type(x) is _ZERO_TYPE for row in inertia[k] for x in row):
            continue
        up = to_parent[k]
        h = up(first[k])
        rows = [up(tuple(inertia[k][r])) for r in range(3)]  # (R J)ᵀ's columns are R J's rows rotated
        J = [up(tuple(rows[c][r] for c in range(3))) for r in range(3)]
        d = node.offset
        dh, dd = _dot(d, h), _dot(d, d)
        p = node.parent
        mass[p] = mass[p] + m
        for r in range(3):
            for c in range(3):
                shift = (2 * dh + m * dd if r == c else _ZERO) - d[r] * h[c] - h[r] * d[c] - m * d[r] * d[c]
                inertia[p][r][c] = inertia[p][r][c] + J[r][c] + shift
        first[p] = _add3(first[p], _add3(h, _scale(m, d)))

    # Where each q̇_j moves a node: spatial motions S = (ω, v of the origin) in the node's basis.
    occurrences: list[list[tuple[int, Vec, Vec]]] = [[] for _ in range(count)]
    for k, node in enumerate(nodes):
        for j, a in node.rates.items():
            occurrences[k].append((j, _unit(node.axis, a), _ZERO3))  # type: ignore[arg-type]
        for j, u in node.offset_rates.items():
            occurrences[k].append((j, _ZERO3, w.vec(to_child[k](u))))
    above = [False] * count  # some strict ancestor of the node moves with a coordinate
    for k in range(1, count):
        p = nodes[k].parent
        above[k] = above[p] or bool(occurrences[p])  # type: ignore[index]
    M: list[list[list[se.Basic]]] = [[[] for _ in range(n)] for _ in range(n)]
    for k in range(1, count):
        for rank, (i, S_w, S_v) in enumerate(occurrences[k]):
            J = inertia[k]
            fv = w.vec(_add3(_scale(mass[k], S_v), _cross(S_w, first[k])))  # I^c S: force and moment
            nv = w.vec(_add3(tuple(_dot(J[r], S_w) for r in range(3)), _cross(first[k], S_v)))  # type: ignore[arg-type]
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
                up, d = to_parent[a], nodes[a].offset
                fv = w.vec(up(fv))
                nv = w.vec(_add3(up(nv), _cross(d, fv)))
                a, same = nodes[a].parent, False  # type: ignore[assignment]
    M_out = tuple(tuple(sum_of(M[i][j]) for j in range(n)) for i in range(n))
    aba = articulated_accelerations(w, nodes, qd, omega, grav, to_child, to_parent, couples, Q_other,
                                    (mass, first, inertia), kin.q)
    qdd, pivots, forward = aba if aba is not None else (None, (), 0)

    T = sum_of(T_terms)
    U_gravity = sum_of(U_terms)
    dL = _gradient(w, T - U_gravity, kin.q)
    dL_dq = tuple(a + q + c for a, q, c in zip(dL, Q_other, Q_couples, strict=True))
    U_other = [f.potential for f in other if f.potential is not None]
    conservative = all(f.potential is not None for f in other) and not tree.couples
    return RecursiveForm(tuple(w.items), M_out, F, T, U_gravity + sum_of(U_other), dL_dq, conservative, other,
                         qdd, pivots, forward)


def require_tree(kin: Kinematics) -> TreeStructure:
    """`tree_structure`, or a `DerivationError` saying why the recursive formulation does not apply."""
    tree = tree_structure(kin)
    if isinstance(tree, str):
        raise DerivationError(f"the recursive formulation needs a kinematic tree of rotations and translations, and "
                              f"model `{kin.model.name}` is not one: {tree}",
                              fix="use formulation='lagrange' (the course's derivation), or 'auto'")
    return tree
