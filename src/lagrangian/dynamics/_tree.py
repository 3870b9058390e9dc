"""The kinematic tree of a model, as the recursive multibody algorithms walk it (`_recursive`).

Each frame F comes from its parent P by the rotation of angle α = Σ_j a_j q_j + b about an axis
e shared by P and F (x, y or z of P), and its origin O_F is O_P + d_F, where d_F (components in
P, affine in q with constant coefficients) is what every point below F has in P.  Each body or
particle is a leaf node below its frame at its own offset c.  Uniform gravity is handled by the
recursion; torques and joint dampers become couples on nodes; every other load keeps its Q_i
from the course's virtual power (`generalized_forces`).  A model that is not such a tree gets
the reason, for `derive` to fall back on the course's derivation or to say why.

References: Featherstone, *Rigid Body Dynamics Algorithms* (2008), ch. 4.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from itertools import pairwise
from typing import cast

import symengine as se

from ..errors import DerivationError
from ..kinematics import Kinematics
from ..model import GALILEAN_FRAME, Body, Gravity, JointDamper, Torque, Vector
from ..model.vectors import AXES
from ._energy import _transport, rigid_inertia
from ._forces import _q_of

__all__ = ["TreeStructure", "Vec", "model_depth", "require_tree", "tree_structure"]

#: A vector's three components in some frame's basis.
Vec = tuple[se.Basic, se.Basic, se.Basic]
_ZERO = se.Integer(0)
_ZERO3: Vec = (_ZERO, _ZERO, _ZERO)


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

    @property
    def up(self) -> int:
        """The parent's index, for a node below R0 (node 0, the root, has none)."""
        if self.parent is None:
            raise ValueError("R0, the root of the tree, has no parent")
        return self.parent


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
    """The kinematic tree of ``kin.model``, or the reason why the model is not one.

    The steps: `_frame_nodes` (a node per frame, its rotation Σ a_j q_j + b about a parent's axis),
    `_split_loads` (uniform gravity handled by the recursion, the other loads apart), `_add_leaves` (a
    leaf per body or particle, the offsets d of the frames on its path), `_couples` (torques and joint
    dampers acting as couples on nodes).
    """
    model = kin.model
    if model.constraints:
        return "it has complementary constraints"
    if model.reference is not None and not model.reference.is_galilean_frame:
        return "its equations are written in a moving reference frame"
    frames = _frame_nodes(kin)
    if isinstance(frames, str):
        return frames
    nodes, index, depth = frames
    gravity, other = _split_loads(kin)
    leaf_of = _add_leaves(kin, nodes, index, gravity)
    if isinstance(leaf_of, str):
        return leaf_of
    kept, couples = _couples(kin, other, index, leaf_of)
    return TreeStructure(nodes, max(depth.values(), default=0), tuple(gravity), tuple(kept), tuple(couples))


def _frame_nodes(kin: Kinematics) -> tuple[list[_Node], dict[str, int], dict[str, int]] | str:
    """A node per frame, parents first, each turning by α = Σ a_j q_j + b (constant a_j, b) about its
    parent's x, y or z; with the index of each frame's node and its depth (moving rotations from R0)."""
    index: dict[str, int] = {}
    nodes: list[_Node] = []
    depth: dict[str, int] = {}
    for frame in kin.model.frames:
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
    return nodes, index, depth


def _split_loads(kin: Kinematics) -> tuple[list[tuple[Gravity, Vec]], list[int]]:
    """The gravity loads of a uniform field (constant components in R0), with that field, which the
    recursion handles; and the indices of the other loads."""
    gravity: list[tuple[Gravity, Vec]] = []
    other: list[int] = []
    for k, load in enumerate(kin.model.loads):
        if isinstance(load, Gravity):
            g = kin.frames.express(load.field, GALILEAN_FRAME)
            if all(not (c.free_symbols & (set(kin.q) | set(kin.qd) | {kin.t})) for c in g):
                gravity.append((load, g))
                continue
        other.append(k)
    return gravity, other


def _add_leaves(kin: Kinematics, nodes: list[_Node], index: dict[str, int],
                gravity: Sequence[tuple[Gravity, Vec]]) -> dict[str, int] | str:
    """A leaf node per body or particle below its frame (a particle: the deepest frame its position uses),
    at its own offset c; on the way the offset d_F (affine in q, components in the parent) of each frame
    of its path from R0, which every point below F must share.  Returns each leaf's index, by name."""
    model = kin.model
    offset_set: set[int] = set()
    masses = [(b.name, b.frame, b.mass, b.center, b) for b in model.bodies]
    masses += [(p.name, None, p.mass, p.position, None) for p in model.particles]
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
        for frame, child in pairwise(path):
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
            nodes[c].offset = tuple(piece)
            nodes[c].offset_rates = {j: tuple(u) for j, u in rates.items()}
            offset_set.add(c)
        own = pieces.get(home, _ZERO3)
        rates = _affine(kin, own)
        if rates is None:
            return f"the position of `{name}` is not affine in the coordinates in frame `{home}`"
        leaf = _Node(name, index[home], offset=tuple(own), mass=mass, frame=home,
                     offset_rates={j: tuple(u) for j, u in rates.items()})
        if body is not None:
            leaf.inertia = _inertia_at_g(kin, body)
        leaf.gravity = tuple(k for k, (load, _) in enumerate(gravity) if not load.on or name in load.on)
        nodes[index[home]].children.append(len(nodes))
        leaf_of[name] = len(nodes)
        nodes.append(leaf)
    return leaf_of


def _inertia_at_g(kin: Kinematics, body: Body) -> tuple[Vec, Vec, Vec]:
    """Π_G in the body's basis."""
    _, pi_g = rigid_inertia(kin, body)  # checks the inertia (physical, at a point of the body)
    given = body.inertia
    if given.frame != body.frame and given.at != "G":
        # Given in a frame where it reads as in the body's (checked): moved to G with GP in
        # the body's components, which are constant (P is a point of the body, checked).
        gp = kin.frames.express(kin.position(given.at) - body.center, body.frame)
        pi_g = _transport(given.matrix, body.mass, gp, -1)
    return cast(tuple[Vec, Vec, Vec], pi_g)  # 3 × 3


def _couples(kin: Kinematics, other: Sequence[int], index: Mapping[str, int],
             leaf_of: Mapping[str, int]) -> tuple[list[int], list[tuple[int, Vector]]]:
    """The loads kept apart (their Q_i from `generalized_forces`), and the couples C⃗ on nodes: a torque
    on a body (its leaf) or a frame (its node) and its reaction, a joint damper's −c Ω(S2/S1) on S2
    and its opposite on S1; −C⃗ enters that node's Euler equation."""
    model = kin.model
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
    return kept, couples


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


def require_tree(kin: Kinematics) -> TreeStructure:
    """`tree_structure`, or a `DerivationError` saying why the recursive formulation does not apply."""
    tree = tree_structure(kin)
    if isinstance(tree, str):
        raise DerivationError(f"the recursive formulation needs a kinematic tree of rotations and translations, and "
                              f"model `{kin.model.name}` is not one: {tree}",
                              fix="use formulation='lagrange' (the course's derivation), or 'auto'")
    return tree
