"""q̈ of a kinematic tree by the articulated-body algorithm, as named intermediates.

M q̈ = F solved by a dense factorisation costs n³/6 multiply-adds on top of the n² of M's
composite-rigid-body entries; for a tree whose every coordinate drives one joint, the
articulated-body algorithm (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, §7.3,
Table 7.1; Featherstone 1983) gives the same q̈ in O(n) without forming M.  Here it is
written symbolically over the nodes of `_recursive.tree_structure`, each node's quantities
one named intermediate, so that the generated C code is a straight line of about 260
multiplications and 170 additions per joint of a 3D arm, structural zeros (constant axes,
zero offsets) never formed.

Spatial vectors at a node's origin O, components in its basis: motions (ω̇, a_O) with the
*classical* acceleration a_O of the origin, forces (n_O, f).  A rigid body with mass m,
first moment h = m OG and inertia J_O about O obeys

    (n_O, f) = I (ω̇, a_O) + p,   I = [[J_O, [h∧]], [−[h∧], m 1]],   p = (ω ∧ J_O ω, ω ∧ (ω ∧ h)),

the same I as with spatial accelerations; only the velocity-product terms differ.  Node k
moves from its parent P by A_k = X_k A_P + Σ_j s_j q̈_j + c_k, with X_k (ω̇, a) =
(C ω̇, C (a + ω̇ ∧ d)) (C: P's basis to k's, d = O_P O_k in P's basis),

    c_k = (ω_k ∧ α̇ e,  C (ω_P ∧ (ω_P ∧ d) + 2 ω_P ∧ ḋ)),

s_j = (a_j e, 0) for a rotation and (0, C ∂d/∂q_j) for a translation (`_recursive`).  Forces
go back by X_kᵀ: (n, f) ↦ (Cᵀn + d ∧ Cᵀf, Cᵀf).  Then, with τ_j = Q_j of the loads outside the
recursion and the gravity and couples as external forces in p:

backward, leaves to root, for each coordinate j of node k (several: one after the other,
as joints in series joined by massless links):
    U = I^A s,  D = sᵀU,  u = τ_j − sᵀp^A,
    I^a = I^A − U Uᵀ/D,  p^a = p^A + I^a c + U u/D,        I^A_P += X_kᵀ I^a X_k,  p^A_P += X_kᵀ p^a
forward, root to leaves (A_0 = 0: gravity is a force here):
    q̈_j = (u − Uᵀ (X_k A_P + c_k))/D,   A_k = X_k A_P + c_k + s q̈_j.

It applies when every coordinate drives one node; a slide shared alike by the children of one
frame (a URDF prismatic joint whose link has several children) gets a massless node of its
own first (`_shared_slides`).

D_j is the pivot of eliminating the coordinates of the subtree below j first: D_j/M_jj
is reported as the relative pivot (M_jj from the composite inertia), which the Cholesky
factorisation reports otherwise, and D_j ≤ 10⁻¹³ M_jj as a singular mass matrix.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import symengine as se

from ..model.vectors import add3 as _add3  # the vector toolkit's 3-component algebra
from ..model.vectors import cross as _cross
from ..model.vectors import sum_of

_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)
_ONE = se.Integer(1)

Vec = tuple  # three SymEngine expressions
Mat = list  # three rows of three

if TYPE_CHECKING:
    from ._recursive import _Names
    from ._tree import _Node

#: A change of basis between a node and its parent (None for the root).
Turn = Callable[[Vec], Vec] | None


def _zero(x: se.Basic) -> bool:
    return type(x) is _ZERO_TYPE


def _dot(a: Sequence[se.Basic], b: Sequence[se.Basic]) -> se.Basic:
    return sum_of([x if y == 1 else y if x == 1 else x * y for x, y in zip(a, b, strict=True) if not _zero(x) and not _zero(y)])


def _scale(k: se.Basic, v: Vec) -> Vec:
    return tuple(_ZERO if _zero(c) else k * c for c in v)


def _neg(v: Vec) -> Vec:
    return tuple(_ZERO if _zero(c) else -c for c in v)


def _col(X: Mat, c: int) -> Vec:
    return (X[0][c], X[1][c], X[2][c])


def _madd(X: Mat, Y: Mat) -> Mat:
    return [list(_add3(tuple(x), tuple(y))) for x, y in zip(X, Y, strict=True)]


def _mv(X: Mat, v: Vec) -> Vec:
    """X v."""
    return tuple(_dot(row, v) for row in X)


def _mtv(X: Mat, v: Vec) -> Vec:
    """Xᵀ v."""
    return tuple(_dot(_col(X, c), v) for c in range(3))


def _from_cols(cols: Sequence[Vec]) -> Mat:
    return [[cols[c][r] for c in range(3)] for r in range(3)]


def _rotate(up, X: Mat) -> Mat:
    """R X Rᵀ where ``up(v)`` = R v: a tensor's components from the child's basis to the parent's."""
    Y = _from_cols([up(_col(X, c)) for c in range(3)])  # R X
    return [list(up(tuple(row))) for row in Y]  # rows of (R X) Rᵀ = R applied to the rows of R X


def _cross_cols(d: Vec, X: Mat) -> Mat:
    """[d∧] X: d ∧ each column."""
    return _from_cols([_cross(d, _col(X, c)) for c in range(3)])


def _rows_cross(X: Mat, d: Vec) -> Mat:
    """X [d∧]: each row ∧ d (row r of X [d∧] is −[d∧] X_r = X_r ∧ d)."""
    return [list(_cross(tuple(row), d)) for row in X]


class _Spatial:
    """A symmetric 6×6 inertia [[A, B], [Bᵀ, C]] (A, C symmetric) acting on motions (ω̇, a)."""

    __slots__ = ("A", "B", "C")

    def __init__(self, A: Mat, B: Mat, C: Mat) -> None:
        self.A, self.B, self.C = A, B, C

    @classmethod
    def zero(cls) -> _Spatial:
        return cls([[_ZERO] * 3 for _ in range(3)], [[_ZERO] * 3 for _ in range(3)], [[_ZERO] * 3 for _ in range(3)])

    def times(self, w: Vec, v: Vec) -> tuple[Vec, Vec]:
        """I (w, v) = (A w + B v, Bᵀ w + C v)."""
        return _add3(_mv(self.A, w), _mv(self.B, v)), _add3(_mtv(self.B, w), _mv(self.C, v))

    def add(self, other: _Spatial) -> _Spatial:
        return _Spatial(_madd(self.A, other.A), _madd(self.B, other.B), _madd(self.C, other.C))

    def named(self, name) -> _Spatial:
        """Each distinct entry one intermediate (21 at most)."""
        A = [[name(self.A[r][c]) if c >= r else None for c in range(3)] for r in range(3)]
        C = [[name(self.C[r][c]) if c >= r else None for c in range(3)] for r in range(3)]
        for r in range(3):
            for c in range(r):
                A[r][c], C[r][c] = A[c][r], C[c][r]
        return _Spatial(A, [[name(x) for x in row] for row in self.B], C)

    def to_parent(self, up, d: Vec) -> _Spatial:
        """X_kᵀ I X_k: rotated to the parent's basis, then about the parent's origin (d = O_P O_k).

        With D = [d∧] (Dᵀ = −D) and the rotated blocks A', B', C':
        A_P = A' − B'D − (B'D)ᵀ − D C' D,  B_P = B' + D C',  C_P = C'.
        """
        A, B, C = _rotate(up, self.A), _rotate(up, self.B), _rotate(up, self.C)
        if all(_zero(x) for x in d):
            return _Spatial(A, B, C)
        E = _rows_cross(B, d)
        DCD = _cross_cols(d, _rows_cross(C, d))
        A_P = [[sum_of([t for t in (A[r][c], -E[r][c], -E[c][r], -DCD[r][c]) if not _zero(t)]) for c in range(3)]
               for r in range(3)]
        return _Spatial(A_P, _madd(B, _cross_cols(d, C)), C)


def _identity(v):
    return v


def _shared_slides(nodes, q, omega, grav, to_child, to_parent, couples, composite):
    """The tree with a joint of its own for each coordinate that slides several siblings alike.

    A URDF prismatic joint whose child link has several children is read as the same offset
    u q_j in each child frame's origin: one virtual node V between the parent P and those
    children (no rotation, origin at O_P + u q_j, no mass) gives q_j a joint of its own, and
    the children the offsets d − u q_j from it.  Returns the arguments rebuilt, the same ones
    when no coordinate is shared, or None when a shared coordinate is not such a slide.
    """
    where: dict[int, list[int]] = {}
    for k, node in enumerate(nodes):
        for j in (*node.rates, *node.offset_rates):
            where.setdefault(j, []).append(k)
    groups = {j: ks for j, ks in where.items() if len(ks) > 1}
    if not groups:
        return nodes, omega, grav, to_child, to_parent, couples, composite
    members = [k for ks in groups.values() for k in ks]
    if len(members) != len(set(members)):  # a node slid by two shared coordinates: not handled
        return None
    first_child: dict[int, int] = {}
    for j, ks in groups.items():
        u = nodes[ks[0]].offset_rates.get(j)
        if (len({nodes[k].parent for k in ks}) != 1 or any(j in nodes[k].rates for k in ks) or u is None
                or any(any(se.expand(a - b) != 0 for a, b in zip(nodes[k].offset_rates.get(j, u), u, strict=True)) for k in ks)):
            return None
        first_child[ks[0]] = j
    mass, first, inertia = composite
    order: list[tuple[int | None, int]] = []  # (old index or None for a virtual node, its coordinate)
    for k in range(len(nodes)):
        if k in first_child:
            order.append((None, first_child[k]))
        order.append((k, -1))
    new_index = {k: i for i, (k, _) in enumerate(order) if k is not None}
    virtual = {j: i for i, (k, j) in enumerate(order) if k is None}
    zero3 = (_ZERO,) * 3
    out = ([], [], [], [], [], [], ([], [], []))
    for k, j in order:
        if k is None:
            ks = groups[j]
            parent = nodes[ks[0]].parent
            u = nodes[ks[0]].offset_rates[j]
            node = dataclasses.replace(nodes[parent], name=f"slide of {nodes[ks[0]].name}", parent=new_index[parent],
                                       axis=None, angle=_ZERO, rates={}, offset=tuple(c * q[j] for c in u),
                                       offset_rates={j: u}, mass=_ZERO, inertia=None, gravity=(), children=ks)
            values = (omega[parent], grav[parent], _identity, _identity, zero3,
                      (sum_of([mass[i] for i in ks]), zero3, [[_ZERO] * 3 for _ in range(3)]))
        else:
            node = nodes[k]
            shared = [i for i in node.offset_rates if i in groups]
            parent = None if node.parent is None else new_index[node.parent]
            offset = node.offset
            if shared:
                (j2,) = shared
                parent = virtual[j2]
                offset = tuple(c - a * q[j2] for c, a in zip(node.offset, node.offset_rates[j2], strict=True))
            node = dataclasses.replace(node, parent=parent, offset=offset,
                                       offset_rates={i: u for i, u in node.offset_rates.items() if i not in groups})
            values = (omega[k], grav[k], to_child[k], to_parent[k], couples[k], (mass[k], first[k], inertia[k]))
        out[0].append(node)
        for lst, value in zip(out[1:6], values[:5], strict=True):
            lst.append(value)
        for lst, value in zip(out[6], values[5], strict=True):
            lst.append(value)
    return out


def articulated_accelerations(w, nodes, qd, omega, grav, to_child, to_parent, couples, tau,
                              composite, q=(), floating=None
                              ) -> tuple[tuple[se.Basic, ...], tuple[tuple[se.Basic, se.Basic], ...], int] | None:
    """q̈, the pivots (D_j, M_jj) and the position of the first intermediate of the forward pass, or None.

    None where the articulated-body algorithm does not apply (see below).

    Parameters (from `_recursive.recursive_form`)
    ----------
    w : the `_Names` sequence the intermediates are added to.
    nodes : the tree's nodes, parents first.
    qd : the rates q̇_j.
    omega, grav : each node's ω and gravity fields, in its basis (named).
    to_child, to_parent : each node's change of basis from / to its parent's.
    couples : each node's couple (torques, joint dampers), in its basis.
    tau : Q_j of the loads outside the recursion.
    composite : (mass, first moment, inertia about the origin) of each node's subtree (the CRBA's).
    floating : None for a root fixed in R0 (A_0 = 0).  For a free root (a floating base,
        `_floating`), a function of the root's articulated inertia I^A_0 (a `_Spatial`) and bias
        force (p_ω, p_v) that returns its acceleration A_0 = −(I^A_0)⁻¹ p^A_0 = (ω̇, a_O); the
        forward pass starts from it (Featherstone 2008, §9.4).

    It applies when every coordinate drives exactly one node (a joint of its own); a coordinate
    shared by several nodes (absolute angles, coupled joints) leaves M q̈ = F to the solver.
    The steps, in the order their intermediates are named: `_joints` (each coordinate's motion
    s_j), `_velocity_products` (c_k), `_rigid_inertias` and `_backward` (I^A, p^A, D_j, u_j),
    `_forward` (A_k and q̈), `_pivots` (D_j against M_jj).
    """
    shared = _shared_slides(nodes, q, omega, grav, to_child, to_parent, couples, composite) if q else None
    if shared is None and q:
        return None
    if shared is not None:
        nodes, omega, grav, to_child, to_parent, couples, composite = shared
    n = len(qd)
    joints = _joints(w, nodes, to_child, n)
    if joints is None:
        return None
    dofs, owner = joints
    c_w, c_v = _velocity_products(w, nodes, qd, omega, to_child)
    inertia, bias_w, bias_v = _rigid_inertias(nodes, omega, grav, couples)
    steps, pivots = _backward(w, nodes, dofs, (c_w, c_v), tau, to_parent, inertia, bias_w, bias_v)
    if floating is not None:
        root = floating(inertia[0], bias_w[0], bias_v[0])
    else:
        root = ((_ZERO,) * 3, (_ZERO,) * 3)
    qdd, start = _forward(w, nodes, dofs, steps, (c_w, c_v), to_child, root, n)
    return qdd, _pivots(w, dofs, owner, pivots, composite, n), start


#: Each coordinate's motion on its node: (j, s_ω, s_v), in the node's basis.
Joint = tuple[int, Vec, Vec]
#: One elimination of the backward pass: (j, s_ω, s_v, U_ω/D, U_v/D, u, 1/D).
Step = tuple[int, Vec, Vec, Vec, Vec, se.Basic, se.Basic]


def _joints(w: _Names, nodes: Sequence[_Node], to_child: Sequence[Turn], n: int,
            ) -> tuple[list[list[Joint]], list[int]] | None:
    """Each node's joints, s_j = (a_j e, 0) for a rotation and (0, C ∂d/∂q_j) for a translation, with the
    node each coordinate drives; None when a coordinate drives none or several."""
    count = len(nodes)
    dofs: list[list[Joint]] = [[] for _ in range(count)]
    owner = [-1] * n
    for k, node in enumerate(nodes):
        for j, a in node.rates.items():
            dofs[k].append((j, tuple(a if i == node.axis else _ZERO for i in range(3)), (_ZERO,) * 3))
        down = to_child[k]
        for j, u in node.offset_rates.items():
            dofs[k].append((j, (_ZERO,) * 3, w.vec(down(u)) if down is not None else u))
        for j, _, _ in dofs[k]:
            if owner[j] != -1:
                return None
            owner[j] = k
    if -1 in owner:
        return None
    return dofs, owner


def _velocity_products(w: _Names, nodes: Sequence[_Node], qd: Sequence[se.Basic], omega: Sequence[Vec],
                       to_child: Sequence[Turn]) -> tuple[list[Vec], list[Vec]]:
    """The velocity-product accelerations c_k = (ω_k ∧ α̇ e,  C (ω_P ∧ (ω_P ∧ d) + 2 ω_P ∧ ḋ))."""
    count = len(nodes)
    c_w: list[Vec] = [(_ZERO,) * 3] * count
    c_v: list[Vec] = [(_ZERO,) * 3] * count
    for k, node in enumerate(nodes):
        if node.parent is None:
            continue
        p = node.parent
        wp = omega[p]
        if node.axis is not None and node.rates:
            spin = tuple(sum_of([a * qd[j] for j, a in node.rates.items()]) if i == node.axis else _ZERO
                         for i in range(3))
            c_w[k] = w.vec(_cross(omega[k], spin))
        d_rate = (_ZERO,) * 3
        for j, u in node.offset_rates.items():
            d_rate = _add3(d_rate, _scale(qd[j], u))
        lin = _add3(_cross(wp, _cross(wp, node.offset)), _scale(se.Integer(2), _cross(wp, d_rate)))
        down = to_child[k]
        assert down is not None  # every node but the root has a parent
        c_v[k] = w.vec(down(lin))
    return c_w, c_v


def _rigid_inertias(nodes: Sequence[_Node], omega: Sequence[Vec], grav: Sequence[Sequence[Vec]], couples: Sequence[Vec],
                    ) -> tuple[list[_Spatial], list[Vec], list[Vec]]:
    """Each body's or particle's spatial inertia at G, I = [[Π_G, 0], [0, m 1]], and its bias force
    p = (ω ∧ Π_G ω − C⃗, −m g) (gravity and couples as external forces); a frame's p = (−C⃗, 0)."""
    count = len(nodes)
    inertia = [_Spatial.zero() for _ in range(count)]
    bias_w: list[Vec] = [(_ZERO,) * 3] * count
    bias_v: list[Vec] = [(_ZERO,) * 3] * count
    for k, node in enumerate(nodes):
        if node.parent is None:
            continue
        nw = _neg(couples[k])
        if node.axis is None and (node.mass != 0 or node.inertia is not None):  # a body or particle, at G
            m = node.mass
            pi = [list(row) for row in node.inertia] if node.inertia is not None else [[_ZERO] * 3 for _ in range(3)]
            inertia[k] = _Spatial(pi, [[_ZERO] * 3 for _ in range(3)],
                                  [[m if r == c else _ZERO for c in range(3)] for r in range(3)])
            if node.inertia is not None:
                nw = _add3(nw, _cross(omega[k], _mv(pi, omega[k])))
            g_total = (_ZERO,) * 3
            for i in node.gravity:
                g_total = _add3(g_total, grav[k][i])
            bias_v[k] = _scale(-m, g_total)
        bias_w[k] = nw
    return inertia, bias_w, bias_v


def _backward(w: _Names, nodes: Sequence[_Node], dofs: list[list[Joint]], c: tuple[list[Vec], list[Vec]],
              tau: Sequence[se.Basic], to_parent: Sequence[Turn],
              inertia: list[_Spatial], bias_w: list[Vec], bias_v: list[Vec],
              ) -> tuple[list[list[Step]], dict[int, se.Basic]]:
    """Backward pass, leaves to root: at each node its joints eliminated (`_eliminate`), the last one
    first, then I^A_P += X_kᵀ I^a X_k and p^A_P += X_kᵀ p^a, in place in ``inertia``, ``bias_w``,
    ``bias_v``.  Returns each node's eliminations and each coordinate's pivot D_j."""
    c_w, c_v = c
    steps: list[list[Step]] = [[] for _ in range(len(nodes))]
    pivots: dict[int, se.Basic] = {}
    for k in range(len(nodes) - 1, 0, -1):
        node = nodes[k]
        I = inertia[k]
        pw, pv = bias_w[k], bias_v[k]
        if node.children or dofs[k]:
            I = I.named(w)
            pw, pv = w.vec(pw), w.vec(pv)
        cw, cv = c_w[k], c_v[k]
        for rank, (j, sw, sv) in enumerate(reversed(dofs[k])):  # the last joint is the outermost
            I, step, D = _eliminate(w, I, pw, pv, j, sw, sv, tau)
            steps[k].append(step)
            pivots[j] = D
            if rank == 0 and any(not _zero(x) for x in (*cw, *cv)):
                gw, gv = I.times(cw, cv)
                pw, pv = _add3(pw, gw), _add3(pv, gv)
            u, Vw, Vv = step[5], step[3], step[4]
            pw, pv = w.vec(_add3(pw, _scale(u, Vw))), w.vec(_add3(pv, _scale(u, Vv)))
        if not dofs[k] and any(not _zero(x) for x in (*cw, *cv)):
            gw, gv = I.times(cw, cv)
            pw, pv = _add3(pw, gw), _add3(pv, gv)
        p = node.parent
        if all(_zero(x) for row in (*I.A, *I.B, *I.C) for x in row) and all(_zero(x) for x in (*pw, *pv)):
            continue
        up, d = to_parent[k], node.offset
        assert up is not None and p is not None  # every node but the root has a parent
        inertia[p] = inertia[p].add(I.to_parent(up, d))
        fv = up(pv)
        bias_v[p] = _add3(bias_v[p], fv)
        bias_w[p] = _add3(bias_w[p], _add3(up(pw), _cross(d, fv)))
    return steps, pivots


def _eliminate(w: _Names, I: _Spatial, pw: Vec, pv: Vec, j: int, sw: Vec, sv: Vec,
               tau: Sequence[se.Basic]) -> tuple[_Spatial, Step, se.Basic]:
    """One joint s of articulated inertia I^A and bias p^A eliminated:

        U = I^A s,  D = sᵀU,  u = τ_j − sᵀp^A,  I^a = I^A − U Uᵀ/D

    (the rows and columns of I^a along a constant axis exactly 0).  Returns I^a named, the step
    (j, s, U/D, u, 1/D) and D; p^a = p^A + I^a c + U u/D is the caller's.
    """
    Uw, Uv = I.times(sw, sv)
    Uw, Uv = w.vec(Uw), w.vec(Uv)
    D = w(_dot(sw, Uw) + _dot(sv, Uv))
    inv = w(_ONE / D)
    u = w(tau[j] - _dot(sw, pw) - _dot(sv, pv))
    Vw, Vv = w.vec(_scale(inv, Uw)), w.vec(_scale(inv, Uv))  # U/D
    U, V = (*Uw, *Uv), (*Vw, *Vv)
    blocks = [[[U[3 * b + r] * V[3 * e + c] for c in range(3)] for r in range(3)] for b, e in ((0, 0), (0, 1), (1, 1))]
    A = [[I.A[r][c] - blocks[0][r][c] for c in range(3)] for r in range(3)]
    B = [[I.B[r][c] - blocks[1][r][c] for c in range(3)] for r in range(3)]
    C = [[I.C[r][c] - blocks[2][r][c] for c in range(3)] for r in range(3)]
    s6 = (*sw, *sv)
    along = [i for i in range(6) if not _zero(s6[i])]
    if len(along) == 1:  # I^a s = 0: along a constant axis, that row and column of I^a vanish exactly
        i = along[0]
        for r in range(3):
            if i < 3:
                A[i][r] = A[r][i] = B[i][r] = _ZERO
            else:
                C[i - 3][r] = C[r][i - 3] = B[r][i - 3] = _ZERO
    return _Spatial(A, B, C).named(w), (j, sw, sv, Vw, Vv, u, inv), D


def _forward(w: _Names, nodes: Sequence[_Node], dofs: list[list[Joint]], steps: list[list[Step]],
             c: tuple[list[Vec], list[Vec]], to_child: Sequence[Turn], root: tuple[Vec, Vec], n: int) -> tuple[tuple[se.Basic, ...], int]:
    """Forward pass, root (acceleration ``root``) to the leaves, over the nodes with joints below them:

        q̈_j = (u − Uᵀ (X_k A_P + c_k))/D,   A_k = X_k A_P + c_k + s q̈_j.

    Returns q̈ and the position in the intermediates where the pass starts.
    """
    c_w, c_v = c
    count = len(nodes)
    acc_w: list[Vec] = [(_ZERO,) * 3] * count
    acc_v: list[Vec] = [(_ZERO,) * 3] * count
    acc_w[0], acc_v[0] = root
    has_dofs_below = [bool(dofs[k]) for k in range(count)]
    for k in range(count - 1, 0, -1):
        parent = nodes[k].parent
        if has_dofs_below[k] and parent is not None:
            has_dofs_below[parent] = True
    start = len(w.items)
    qdd: list[se.Basic] = [_ZERO] * n
    for k, node in enumerate(nodes):
        if node.parent is None or not has_dofs_below[k]:
            continue
        p = node.parent
        down = to_child[k]
        assert down is not None
        aw, av = down(acc_w[p]), down(_add3(acc_v[p], _cross(acc_w[p], node.offset)))
        order = list(reversed(steps[k]))  # innermost first
        for idx, (j, sw, sv, Vw, Vv, u, inv) in enumerate(order):
            if idx == len(order) - 1:
                aw, av = _add3(aw, c_w[k]), _add3(av, c_v[k])
            aw, av = w.vec(aw), w.vec(av)
            qdd[j] = w(u * inv - _dot(Vw, aw) - _dot(Vv, av))
            aw, av = _add3(aw, _scale(qdd[j], sw)), _add3(av, _scale(qdd[j], sv))
        if not order:
            aw, av = _add3(aw, c_w[k]), _add3(av, c_v[k])
        if node.children:
            acc_w[k], acc_v[k] = w.vec(aw), w.vec(av)
    return tuple(qdd), start


def _pivots(w: _Names, dofs: list[list[Joint]], owner: list[int], pivots: dict[int, se.Basic],
            composite: tuple[Sequence[se.Basic], Sequence[Vec], Sequence[Sequence[Sequence[se.Basic]]]], n: int) -> tuple[tuple[se.Basic, se.Basic], ...]:
    """(D_j, M_jj) for each coordinate, M_jj = s_jᵀ I^c s_j from the composite inertia of its node."""
    mass, first, inertia_c = composite
    out_pivots = []
    for j in range(n):
        k = owner[j]
        sw, sv = next((a, b) for jj, a, b in dofs[k] if jj == j)
        fv = _add3(_scale(mass[k], sv), _cross(sw, first[k]))
        nv = _add3(tuple(_dot(inertia_c[k][r], sw) for r in range(3)), _cross(first[k], sv))
        out_pivots.append((pivots[j], w(_dot(sw, nv) + _dot(sv, fv))))
    return tuple(out_pivots)
