"""Free bodies on a unit quaternion: the floating-base algorithms, as named intermediates.

The state of each free body (`_floating_tree.FloatingTree`, the body B with what hangs from
it) is not its six coordinates but

    r = OO_B (3, in R0),  e = (e_w, e_x, e_y, e_z) a unit quaternion (B's orientation),
    v = V(O_B/R0) (3, R0's basis),  ω = Ω(B/R0) (3, B's basis),

as in MuJoCo's free joint; the joints below B keep their coordinates q_j and rates q̇_j.  The
rotation matrix R (B's basis to R0's) is that of e divided by |e|²,

    R = 1 + 2 (e_w [ε∧] + [ε∧]²)/|e|²,     ε = (e_x, e_y, e_z),

a rotation for any e ≠ 0, so that the dynamics does not depend on the norm the integrator
keeps (it projects e back on |e| = 1, `numerics._free_simulate`).  The kinematics are

    ṙ = v,   ė = ½ e ⊗ (0, ω),   v̇ = R a_O,   ω̇ = ω̇_B,

no singular configuration anywhere (Diebel 2006, eq. 109).  (ω̇_B, a_O) and q̈ come from the
articulated-body algorithm with a floating base (Featherstone, *Rigid Body Dynamics
Algorithms*, 2008, §9.4): the backward pass of `_articulated` carries every subtree's
articulated inertia to B, whose acceleration solves I^A_B (ω̇, a_O) = −p^A_B (a 6×6
symmetric positive definite system, by LDLᵀ; its six pivots are checked like the joints'),
then the forward pass gives each q̈_j.  Gravity is an external force on each body, as there.

The mass matrix in the velocities (v, ω, q̇) is built by the composite-rigid-body algorithm
(the base's motion subspace is S = (0, Rᵀ) for v and (1, 0) for ω), and the monitors: T, the
weight's U, the energy T + U when every effort derives from a potential, the momentum P and
the angular momentum about the tree's centre of mass, σ_G = R (H_B − h × P_B / m), h the first
moment about O_B, P_B and H_B the momentum and angular momentum about O_B in B's basis.
σ_G is a first integral when every effort but uniform gravity is internal to the tree, P's
components where gravity has none.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import symengine as se

from ..errors import DerivationError
from ..model import GALILEAN_FRAME, Model, Vector
from ..model.vectors import add3, cross, sum_of, turn
from ._articulated import _Spatial, articulated_accelerations
from ._floating_tree import FloatingTree, floating_trees
from ._recursive import _carry_to_parent, _dot, _matvec, _name_subtree, _Names, _scale, _unit

__all__ = ["BaseState", "FloatingForm", "floating_form"]

Vec = tuple
_ZERO = se.Integer(0)
_ZERO3 = (_ZERO, _ZERO, _ZERO)
_HALF = se.Rational(1, 2)


@dataclass(frozen=True)
class BaseState:
    """The state symbols of one free body: r, e (w, x, y, z), v, ω; and R in the intermediates."""

    body: str
    r: tuple[se.Symbol, ...]
    e: tuple[se.Symbol, ...]
    v: tuple[se.Symbol, ...]
    w: tuple[se.Symbol, ...]
    R: tuple[tuple[se.Basic, ...], ...]


@dataclass(frozen=True)
class FloatingForm:
    """The quaternion-state equations of a model with free bodies, over named intermediates.

    Parameters
    ----------
    model : Model
        The model.
    trees : tuple of FloatingTree
        One per free body.
    bases : tuple of BaseState
        The `BaseState` of each free body.
    positions : tuple of SymEngine Symbol
        The position state symbols: per tree r, e, the joints' q.
    velocities : tuple of SymEngine Symbol
        The velocity state symbols: per tree v, ω, the joints' q̇; the generalized speeds of `M`.
    intermediates : tuple of (SymEngine Symbol, SymEngine expression)
        (name, expression) in the order of computation.
    derivative : tuple of SymEngine expressions
        The state's derivative ẏ, one expression per state symbol (positions, then velocities).
    accelerations : tuple of SymEngine expressions
        The time derivative of `velocities` (v̇, ω̇, q̈ per tree).
    pivots : tuple of (SymEngine expression, SymEngine expression)
        (D, diagonal entry) of every elimination: six per free body, one per joint.
    M : tuple of tuples of SymEngine expressions
        The mass matrix in `velocities` (composite-rigid-body algorithm).
    monitors : tuple of (str, SymEngine expression)
        (name, expression): the first integrals, then T and U.
    integrals : tuple of str
        The names of the monitors that are first integrals.
    momentum : tuple of tuples of str
        For each tree, the names of its σ_G components (for their drift scale).
    energy_inputs : tuple of str
        The inputs whose loads are the only non-conservative ones: E is a first integral while they
        are off (0), the simulation's default; a run that gives one a value drops E from `integrals`.

    Attributes
    ----------
    joint_index : tuple of tuples of int
        For each tree, the model coordinate index of each of its joints.
    """

    model: Model
    trees: tuple[FloatingTree, ...]
    bases: tuple[BaseState, ...]
    positions: tuple[se.Symbol, ...]
    velocities: tuple[se.Symbol, ...]
    intermediates: tuple[tuple[se.Symbol, se.Basic], ...]
    derivative: tuple[se.Basic, ...]
    accelerations: tuple[se.Basic, ...]
    pivots: tuple[tuple[se.Basic, se.Basic], ...]
    M: tuple[tuple[se.Basic, ...], ...]
    monitors: tuple[tuple[str, se.Basic], ...]
    integrals: tuple[str, ...]
    momentum: tuple[tuple[str, ...], ...]
    energy_inputs: tuple[str, ...] = ()

    def needed(self, exprs: Sequence[se.Basic]) -> list[tuple[se.Symbol, se.Basic]]:
        """The intermediates ``exprs`` depend on, in order.

        Parameters
        ----------
        exprs : sequence of SymEngine expressions
            Expressions in the intermediates' names.

        Returns
        -------
        list of (SymEngine Symbol, SymEngine expression)
            The intermediates needed, in the order of computation.
        """
        position = {s: k for k, (s, _) in enumerate(self.intermediates)}
        keep: set[int] = set()
        stack = [position[s] for e in exprs for s in e.free_symbols if s in position]
        while stack:
            k = stack.pop()
            if k not in keep:
                keep.add(k)
                stack.extend(position[s] for s in self.intermediates[k][1].free_symbols if s in position)
        return [self.intermediates[k] for k in sorted(keep)]


def _rotation(w: _Names, e: Sequence[se.Symbol]) -> tuple[tuple[se.Basic, ...], ...]:
    """R of the quaternion e divided by |e|² (module docstring): a rotation for any e ≠ 0."""
    ew, ex, ey, ez = e
    s = w(2 / (ew * ew + ex * ex + ey * ey + ez * ez))
    xx, yy, zz = w(s * ex * ex), w(s * ey * ey), w(s * ez * ez)
    xy, xz, yz = w(s * ex * ey), w(s * ex * ez), w(s * ey * ez)
    wx, wy, wz = w(s * ew * ex), w(s * ew * ey), w(s * ew * ez)
    return ((w(1 - yy - zz), w(xy - wz), w(xz + wy)),
            (w(xy + wz), w(1 - xx - zz), w(yz - wx)),
            (w(xz - wy), w(yz + wx), w(1 - xx - yy)))


def _times(R, v: Vec) -> Vec:
    return tuple(_dot(row, v) for row in R)


def _times_t(R, v: Vec) -> Vec:
    return tuple(_dot([R[r][c] for r in range(3)], v) for c in range(3))


def _solve6(w: _Names, inertia: _Spatial, bias: Sequence[se.Basic], pivots: list) -> tuple[Vec, Vec]:
    """x = −K⁻¹ p for the 6×6 K = [[A, B], [Bᵀ, C]] (symmetric positive definite), by LDLᵀ.

    Each pivot D_j goes to ``pivots`` with K_jj, to be checked as the Cholesky pivots are.
    """
    A, B, C = inertia.A, inertia.B, inertia.C
    K = [[A[r][c] for c in range(3)] + [B[r][c] for c in range(3)] for r in range(3)]
    K += [[B[c][r] for c in range(3)] + [C[r][c] for c in range(3)] for r in range(3)]
    L = [[_ZERO] * 6 for _ in range(6)]
    D: list[se.Basic] = []
    inv: list[se.Basic] = []
    for j in range(6):
        diag = w(K[j][j])
        D.append(w(diag - sum_of([L[j][k] ** 2 * D[k] for k in range(j) if L[j][k] != 0])))
        inv.append(w(1 / D[j]))
        pivots.append((D[j], diag))
        for i in range(j + 1, 6):
            s = K[i][j] - sum_of([L[i][k] * L[j][k] * D[k] for k in range(j) if L[i][k] != 0 and L[j][k] != 0])
            L[i][j] = w(s * inv[j]) if s != 0 else _ZERO
    z: list[se.Basic] = []
    for i in range(6):
        z.append(w(-bias[i] - sum_of([L[i][k] * z[k] for k in range(i) if L[i][k] != 0])))
    x: list[se.Basic] = [_ZERO] * 6
    for i in range(5, -1, -1):
        x[i] = w(z[i] * inv[i] - sum_of([L[k][i] * x[k] for k in range(i + 1, 6) if L[k][i] != 0]))
    return tuple(x[:3]), tuple(x[3:])


class _TreeBuilder:
    """The intermediates of one floating tree: kinematics, composite inertias, q̈, M, monitors."""

    def __init__(self, w: _Names, kin, tree: FloatingTree, gravity: Sequence[Vec]) -> None:
        self.w, self.kin, self.tree = w, kin, tree
        name = tree.joint.body
        sym = se.Symbol
        self.base = (tuple(sym(f"_{name}_r{i}") for i in range(3)), tuple(sym(f"_{name}_e{i}") for i in range(4)),
                     tuple(sym(f"_{name}_v{i}") for i in range(3)), tuple(sym(f"_{name}_w{i}") for i in range(3)))
        r, e, v, om = self.base
        self.R = _rotation(w, e)
        self.q = [kin.q[j] for j in tree.joints]
        self.qd = [kin.qd[j] for j in tree.joints]
        nodes = tree.nodes
        count = len(nodes)
        self.omega: list[Vec] = [om] + [_ZERO3] * (count - 1)
        self.grav: list[list[Vec]] = [[w.vec(_times_t(self.R, g)) for g in gravity]] + [[] for _ in range(count - 1)]
        self.vel: list[Vec] = [w.vec(_times_t(self.R, v))] + [_ZERO3] * (count - 1)
        self.pos: list[Vec] = [w.vec(_times_t(self.R, r))] + [_ZERO3] * (count - 1)
        identity = (lambda x: x)
        self.down: list = [identity] * count
        self.up: list = [identity] * count
        for k, node in enumerate(nodes):
            if k == 0:
                continue
            p = node.up
            if node.axis is not None:
                c, s = w(se.cos(node.angle)), w(se.sin(node.angle))
                self.down[k] = (lambda x, a=node.axis, c=c, s=s: turn(a, c, -s, x))
                self.up[k] = (lambda x, a=node.axis, c=c, s=s: turn(a, c, s, x))
            down, d = self.down[k], node.offset
            d_rate = _ZERO3
            for j, u in node.offset_rates.items():
                d_rate = add3(d_rate, _scale(self.qd[j], u))
            self.vel[k] = w.vec(down(add3(add3(self.vel[p], cross(self.omega[p], d)), d_rate)))
            self.pos[k] = w.vec(down(add3(self.pos[p], d)))
            self.grav[k] = [w.vec(down(g)) for g in self.grav[p]]
            if node.axis is None:
                self.omega[k] = self.omega[p]
            else:
                spin = _unit(node.axis, sum_of([a * self.qd[j] for j, a in node.rates.items()]))
                self.omega[k] = w.vec(add3(down(self.omega[p]), spin))
        self.couples: list[Vec] = [_ZERO3] * count
        for k, couple in tree.couples:
            self.couples[k] = add3(self.couples[k], self.express(couple, k))

    # -- vectors of the model in a node's basis ---------------------------------------------------
    def express(self, vector: Vector, k: int) -> Vec:
        """Components in node ``k``'s basis of a vector written in R0 or in frames of the tree."""
        nodes = self.tree.nodes
        index = {node.frame: i for i, node in reversed(list(enumerate(nodes))) if node.axis is not None or i == 0}
        moving = {self.kin.q[c] for c in range(len(self.kin.q))} - set(self.q)
        moving |= {self.kin.qd[c] for c in range(len(self.kin.qd))} - set(self.qd)
        total = _ZERO3
        for frame, comps in vector.pieces.items():
            if any(c.free_symbols & moving for c in comps):
                raise DerivationError(f"a couple on free body `{self.tree.joint.body}` depends on the coordinates of a "
                                      "free body, which the quaternion route does not integrate",
                                      fix="write it with parameters, t and the joint coordinates only")
            if frame == GALILEAN_FRAME:
                at, comps = 0, _times_t(self.R, comps)
            elif frame in index:
                at = index[frame]
            else:
                raise DerivationError(f"a couple on free body `{self.tree.joint.body}` is written in frame `{frame}`, "
                                      "which is neither R0 nor a frame of the body or of the parts it carries",
                                      fix="write it in R0 or in the body's frame")
            while at != 0:
                comps = self.up[at](comps)
                at = nodes[at].up
            chain = []
            at = k
            while at != 0:
                chain.append(at)
                at = nodes[at].up
            for i in reversed(chain):
                comps = self.down[i](comps)
            total = add3(total, comps)
        return total

    # -- composite inertias (CRBA) -------------------------------------------------------------------
    def composite(self):
        """(mass, first moment about the origin, inertia about the origin) of each node's subtree."""
        w, nodes = self.w, self.tree.nodes
        mass = [nd.mass for nd in nodes]
        first = [_ZERO3] * len(nodes)
        inertia = [[[nd.inertia[r][c] if nd.inertia is not None else _ZERO for c in range(3)] for r in range(3)]
                   for nd in nodes]
        for k in range(len(nodes) - 1, -1, -1):
            node = nodes[k]
            if node.axis is not None or k == 0:
                _name_subtree(w, mass, first, inertia, k)
            if k == 0:
                break
            _carry_to_parent(mass, first, inertia, k, node.parent, node.offset, self.up[k])
        return mass, first, inertia

    # -- the mass matrix ---------------------------------------------------------------------------
    def mass_matrix(self, composite) -> list[list[se.Basic]]:
        """M in (v, ω, q̇) of the tree: S_iᵀ X I^c S_j along the path between the two nodes."""
        w, nodes, R = self.w, self.tree.nodes, self.R
        mass, first, inertia = composite
        n = 6 + len(self.q)
        occurrences: list[list[tuple[int, Vec, Vec]]] = [[] for _ in nodes]
        occurrences[0] = [(i, _ZERO3, tuple(R[i])) for i in range(3)] + [(3 + i, _unit(i, 1), _ZERO3) for i in range(3)]
        for k, node in enumerate(nodes):
            for j, a in node.rates.items():
                occurrences[k].append((6 + j, _unit(node.axis, a), _ZERO3))  # type: ignore[arg-type]
            for j, u in node.offset_rates.items():
                occurrences[k].append((6 + j, _ZERO3, w.vec(self.down[k](u))))
        M: list[list[list[se.Basic]]] = [[[] for _ in range(n)] for _ in range(n)]
        for k in range(len(nodes)):
            for rank, (i, S_w, S_v) in enumerate(occurrences[k]):
                J = inertia[k]
                fv = w.vec(add3(_scale(mass[k], S_v), cross(S_w, first[k])))
                nv = w.vec(add3(tuple(_dot(J[r], S_w) for r in range(3)), cross(first[k], S_v)))
                a, same = k, True
                while True:
                    for idx, (j, T_w, T_v) in enumerate(occurrences[a]):
                        if same and idx > rank:
                            break
                        value = _dot(T_w, nv) + _dot(T_v, fv)
                        if value == 0:
                            continue
                        M[i][j].append(value)
                        if not (same and idx == rank):
                            M[j][i].append(value)
                    if a == 0:
                        break
                    up, d = self.up[a], nodes[a].offset
                    fv = w.vec(up(fv))
                    nv = w.vec(add3(up(nv), cross(d, fv)))
                    a, same = nodes[a].parent, False
        return [[sum_of(M[i][j]) for j in range(n)] for i in range(n)]

    # -- monitors ----------------------------------------------------------------------------------
    def energies_and_momenta(self, composite) -> tuple[se.Basic, se.Basic, Vec, Vec]:
        """T, U of the weight, P and σ_G (R0's basis) of the tree."""
        w, nodes = self.w, self.tree.nodes
        count = len(nodes)
        T_terms, U_terms = [], []
        P: list[Vec] = [_ZERO3] * count
        H: list[Vec] = [_ZERO3] * count
        for k, node in enumerate(nodes):
            if k == 0 or node.axis is not None or (node.mass == 0 and node.inertia is None):
                continue
            m = node.mass
            pw = _matvec(node.inertia, self.omega[k])
            T_terms.append(_HALF * m * _dot(self.vel[k], self.vel[k]))
            if node.inertia is not None:
                T_terms.append(_HALF * _dot(self.omega[k], pw))
            g_total = _ZERO3
            for i in node.gravity:
                g_total = add3(g_total, self.grav[k][i])
            if node.gravity:
                U_terms.append(-m * _dot(g_total, self.pos[k]))
            P[k], H[k] = _scale(m, self.vel[k]), pw
        for k in range(count - 1, 0, -1):
            if all(c == 0 for c in (*P[k], *H[k])):
                continue
            p, up, d = nodes[k].up, self.up[k], nodes[k].offset
            fp = w.vec(up(P[k]))
            P[p] = add3(P[p], fp)
            H[p] = add3(H[p], add3(w.vec(up(H[k])), cross(d, fp)))
        mass, first, _ = composite
        P0, H0 = w.vec(P[0]), w.vec(H[0])
        sigma = _times(self.R, add3(H0, _scale(-1 / mass[0], cross(first[0], P0))))
        return sum_of(T_terms), sum_of(U_terms), w.vec(_times(self.R, P0)), w.vec(sigma)


def floating_form(model: Model) -> FloatingForm:
    """The `FloatingForm` of a model with free bodies (see the module docstring).

    Parameters
    ----------
    model : Model
        A model with free bodies.

    Returns
    -------
    FloatingForm
        Its quaternion-state equations.

    Raises
    ------
    DerivationError
        When the quaternion route does not apply (`_floating_tree.floating_trees` says why).
    """
    kin, trees, structure, other = floating_trees(model)
    w = _Names()
    gravity = [g for _, g in structure.gravity]
    positions: list[se.Symbol] = []
    velocities: list[se.Symbol] = []
    derivative_q: list[se.Basic] = []
    derivative_v: list[se.Basic] = []
    pivots: list = []
    blocks: list[list[list[se.Basic]]] = []
    monitors: list[tuple[str, se.Basic]] = []
    integrals: list[str] = []
    momentum: list[tuple[str, ...]] = []
    T_all, U_all = [], []
    bases = []
    axes = model.frames[0].axes
    several = len(trees) > 1
    for tree in trees:
        b = _TreeBuilder(w, kin, tree, gravity)
        r, e, v, om = b.base
        bases.append(BaseState(tree.joint.body, r, e, v, om, b.R))
        composite = b.composite()
        a_world, a_omega, qdd = _accelerations(b, composite, pivots)
        ew, ex, ey, ez = e
        wx, wy, wz = om
        e_dot = (w(-_HALF * (ex * wx + ey * wy + ez * wz)), w(_HALF * (ew * wx + ey * wz - ez * wy)),
                 w(_HALF * (ew * wy + ez * wx - ex * wz)), w(_HALF * (ew * wz + ex * wy - ey * wx)))
        positions += [*r, *e, *b.q]
        velocities += [*v, *om, *b.qd]
        derivative_q += [*v, *e_dot, *b.qd]
        derivative_v += [*a_world, *a_omega, *qdd]
        blocks.append(b.mass_matrix(composite))
        T, U, P, sigma = b.energies_and_momenta(composite)
        T_all.append(T)
        U_all.append(U)
        tag = f"_{tree.joint.body}" if several else ""
        names = tuple(f"sigma_G{tag}_{a}" for a in axes)
        if tree.internal:
            integrals += names
            momentum.append(names)
            for a, g in zip(axes, _field(gravity), strict=True):
                if g:
                    continue
                integrals.append(f"P{tag}_{a}")
        monitors += list(zip(names, sigma, strict=True)) + [(f"P{tag}_{a}", p_a) for a, p_a in zip(axes, P, strict=True)]
    U_other = sum_of([f.potential for f in other if f.potential is not None])
    T, U = sum_of(T_all), sum_of(U_all) + U_other
    # An actuator's load is a given non-conservative effort (`_forces`), which does no work while its
    # input is off: the energy is an integral of the runs that leave those inputs at 0.
    inputs = {se.Symbol(u) for u in model.inputs}
    off = dict.fromkeys(inputs, _ZERO)
    driven = [f for f in other if f.potential is None]
    vanish = all(all(se.expand(q.xreplace(off)) == 0 for q in f.Q) for f in driven)
    energy_inputs = tuple(sorted(s.name for f in driven for q in f.Q for s in q.free_symbols if s in inputs))
    conservative = (vanish and not any(t.couples for t in trees) and kin.t not in U.free_symbols)
    first = [(name, expr) for name, expr in monitors if name in integrals]
    rest = [(name, expr) for name, expr in monitors if name not in integrals]
    energy = [("E", T + U)] if conservative else []
    n = len(velocities)
    M = [[_ZERO] * n for _ in range(n)]
    offset = 0
    for block in blocks:
        size = len(block)
        for i in range(size):
            for j in range(size):
                M[offset + i][offset + j] = block[i][j]
        offset += size
    return FloatingForm(model, trees, tuple(bases), tuple(positions), tuple(velocities), tuple(w.items),
                        tuple(derivative_q + derivative_v), tuple(derivative_v), tuple(pivots),
                        tuple(tuple(row) for row in M), tuple(energy + first + rest + [("T", T), ("U", U)]),
                        tuple(["E"] * bool(energy) + [name for name, _ in first]), tuple(momentum),
                        tuple(dict.fromkeys(energy_inputs)))


def _field(gravity: Sequence[Vec]) -> tuple[bool, bool, bool]:
    """For each axis of R0, whether some gravity field has a component along it (then P along it varies)."""
    return tuple(any(g[i] != 0 for g in gravity) for i in range(3))  # type: ignore[return-value]


def _accelerations(b: _TreeBuilder, composite, pivots: list) -> tuple[Vec, Vec, tuple[se.Basic, ...]]:
    """`_TreeBuilder.accelerations`, the root's acceleration recorded from the floating hook."""
    w, tree = b.w, b.tree
    base_pivots: list = []
    couple0 = b.couples[0]
    root: list = []

    def floating(inertia: _Spatial, pw: Vec, pv: Vec) -> tuple[Vec, Vec]:
        bias = [*(add3(pw, tuple(-c for c in couple0))), *pv]
        root.append(_solve6(w, inertia, bias, base_pivots))
        return root[0]

    aba = articulated_accelerations(w, tree.nodes, b.qd, b.omega, b.grav, b.down, b.up, b.couples, tree.tau,
                                    composite, tuple(b.q), floating)
    if aba is None:
        raise DerivationError(f"the parts carried by free body `{tree.joint.body}` do not each have a joint of "
                              "their own (a coordinate turns several frames, as a mimic joint does): the "
                              "articulated-body algorithm does not apply",
                              fix="give each moving part a coordinate of its own")
    qdd, joint_pivots, _ = aba
    pivots.extend(base_pivots)
    pivots.extend(joint_pivots)
    aw, av = root[0]
    return b.w.vec(_times(b.R, av)), aw, qdd

