"""A model with free bodies as floating trees: each free body the root of the bodies it carries.

`_recursive.tree_structure` reads a model as a tree hanging from R0.  A free body's frame B
comes from R0 through three Euler rotations, and its origin sits at (x, y, z) in R0: the
chain R0 → F1 → F2 → B.  For the quaternion route (`_floating`), that chain is cut off and B
becomes the root of its own tree, with the joints below it (a legged robot's legs) as they
were: its pose is given instead by the position r and the unit quaternion of the state.

This module does that surgery and checks that the route applies: every moving part of the
model hangs from a free body, the loads outside the recursion (joint torques, dampers, springs
between links...) act on joint coordinates only (their generalized forces on a free body's
six coordinates are zero), and couples and fields are written in R0 or in frames of the tree.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import symengine as se

from ..errors import DerivationError
from ..kinematics import Kinematics
from ..model import Assumptions, FreeJoint, JointDamper, Model, Torque, Vector, free_joints
from ._forces import LoadForces, generalized_forces
from ._tree import TreeStructure, _Node, tree_structure

__all__ = ["FloatingTree", "floating_trees"]

_ZERO = se.Integer(0)


@dataclass
class FloatingTree:
    """One free body and what hangs from it, re-rooted at its frame B.

    Attributes
    ----------
    joint : the free body's `FreeJoint` (its six coordinates in the model).
    nodes : the tree's nodes, parents first; node 0 is B (no parent, no rotation, no offset).
        Their ``rates`` and ``offset_rates`` are indexed by the local joint index.
    joints : the model coordinate index of each local joint, in model order.
    couples : (node, couple C⃗) of the torques and joint dampers acting on the tree's nodes.
    tau : Q_j of the loads outside the recursion, for each local joint.
    internal : whether every effort but uniform gravity is internal to the tree (then its
        angular momentum about its centre of mass is a first integral).
    """

    joint: FreeJoint
    nodes: list[_Node]
    joints: tuple[int, ...]
    couples: list[tuple[int, Vector]]
    tau: list[se.Basic]
    internal: bool


def _fail(model: Model, message: str, fix: str) -> DerivationError:
    return DerivationError(f"model `{model.name}`: {message}", fix=fix)


def _subtree(tree: TreeStructure, root: int) -> list[int]:
    """``root`` and its descendants, in the tree's order (parents first)."""
    keep, out = {root}, [root]
    for k in range(root + 1, len(tree.nodes)):
        if tree.nodes[k].parent in keep:
            keep.add(k)
            out.append(k)
    return out


def _check_chain(model: Model, kin: Kinematics, tree: TreeStructure, joint: FreeJoint, index: dict[str, int]
                 ) -> list[int]:
    """The node indices of F1, F2, B, checked to be three Euler rotations with (x, y, z) at F1."""
    chain = [index[f] for f in joint.frames]
    position = {c.name: k for k, c in enumerate(model.coordinates)}
    fix = "keep the free body's six coordinates for its own frame and centre (see `lagrangian.model._free`)"
    for k, (node, angle) in enumerate(zip((tree.nodes[i] for i in chain), joint.angles, strict=True)):
        j = position[angle]
        if node.rates != {j: 1} or se.expand(node.angle - kin.q[j]) != 0:
            raise _fail(model, f"the rotation of frame `{node.name}` of free body `{joint.body}` is not its angle "
                               f"`{angle}` alone", fix)
        if k and (node.offset_rates or any(c != 0 for c in node.offset)):
            raise _fail(model, f"frame `{node.name}` of free body `{joint.body}` is offset from its parent", fix)
        if k < 2 and tree.nodes[chain[k]].children != [chain[k + 1]]:
            other = next(c for c in tree.nodes[chain[k]].children if c != chain[k + 1])
            raise _fail(model, f"`{tree.nodes[other].name}` hangs from frame `{node.name}`, an intermediate frame of "
                               f"the Euler angles of free body `{joint.body}`: its place depends on the angles "
                               "themselves, which the quaternion route does not integrate",
                        "attach it to the free body's own frame (or to a frame below it)")
    first = tree.nodes[chain[0]]
    expected = {position[x]: tuple(se.Integer(int(a == b)) for b in range(3)) for a, x in enumerate(joint.translation)}
    if first.parent != 0 or first.offset_rates != expected or any(
            se.expand(c - kin.q[position[x]]) != 0 for c, x in zip(first.offset, joint.translation, strict=True)):
        raise _fail(model, f"the origin of the frame of free body `{joint.body}` is not at "
                           f"{' + '.join(f'{x} R0.{a}' for x, a in zip(joint.translation, 'xyz', strict=True))}", fix)
    return chain


def _local_nodes(tree: TreeStructure, members: list[int], local: dict[int, int]) -> list[_Node]:
    """The nodes of ``members`` re-indexed, the first one made a root (no rotation, no offset)."""
    new = {old: k for k, old in enumerate(members)}
    nodes = []
    for k, old in enumerate(members):
        node = tree.nodes[old]
        children = [new[c] for c in node.children if c in new]
        if k == 0:
            nodes.append(dataclasses.replace(node, parent=None, axis=None, angle=_ZERO, rates={}, offset=(_ZERO,) * 3,
                                             offset_rates={}, children=children))
            continue
        nodes.append(dataclasses.replace(
            node, parent=new[node.parent], children=children,  # type: ignore[index]
            rates={local[j]: a for j, a in node.rates.items()},
            offset_rates={local[j]: u for j, u in node.offset_rates.items()}))
    return nodes


def floating_trees(model: Model) -> tuple[Kinematics, tuple[FloatingTree, ...], TreeStructure, tuple[LoadForces, ...]]:
    """The floating trees of ``model`` (one per free body), with its kinematics and tree structure.

    Raises
    ------
    DerivationError
        When the quaternion route does not apply, saying why and what to change.
    """
    kin = Kinematics(model)
    tree = tree_structure(kin)
    if isinstance(tree, str):
        raise _fail(model, f"a model with a free body is integrated as a tree of bodies hanging from it, and this one "
                           f"is not a tree: {tree}", "remove the complementary constraints and the moving reference "
                           "frame, or describe the system without `free = true`")
    joints = free_joints(model)
    index = {node.name: k for k, node in enumerate(tree.nodes)}
    free_coordinates = {c for j in joints for c in j.coordinates}
    position = {c.name: k for k, c in enumerate(model.coordinates)}
    claimed: set[int] = set()
    out: list[FloatingTree] = []
    node_home: dict[int, tuple[int, int]] = {}  # old node -> (tree, new index)
    for joint in joints:
        chain = _check_chain(model, kin, tree, joint, index)
        claimed.update(chain)
        members = _subtree(tree, chain[2])
        claimed.update(members)
        used = sorted({j for k in members[1:] for j in (*tree.nodes[k].rates, *tree.nodes[k].offset_rates)})
        stray = [model.coordinates[j].name for j in used if model.coordinates[j].name in free_coordinates]
        if stray:
            raise _fail(model, f"coordinate `{stray[0]}` of a free body also moves a part below free body "
                               f"`{joint.body}`", "give that part a coordinate of its own")
        local = {j: k for k, j in enumerate(used)}
        for k, old in enumerate(members):
            node_home[old] = (len(out), k)
        out.append(FloatingTree(joint, _local_nodes(tree, members, local), tuple(used), [], [], True))
    for k, node in enumerate(tree.nodes):
        if k and k not in claimed and (node.rates or node.offset_rates):
            j = next(iter((*node.rates, *node.offset_rates)))
            raise _fail(model, f"`{node.name}` moves with `{model.coordinates[j].name}` but hangs from no free body: "
                               "with a free body, every moving part of the model is carried by one",
                        "attach it to a free body, or fix it (remove `free = true` to integrate the model as before)")
    owner = {}
    for t, ft in enumerate(out):
        for j in ft.joints:
            if j in owner:
                raise _fail(model, f"coordinate `{model.coordinates[j].name}` moves parts below two free bodies",
                            "give each free body's parts coordinates of their own")
            owner[j] = t
    # The couples (torques, joint dampers) on the nodes of each tree; R0 (node 0) takes its reactions.
    for at, couple in tree.couples:
        if at == 0:
            continue
        if at not in node_home:
            raise _fail(model, f"a couple acts on `{tree.nodes[at].name}`, which is not carried by a free body",
                        "apply it to a free body or a part below one")
        t, k = node_home[at]
        out[t].couples.append((k, couple))
    for load in model.loads:  # an effort with a side off the tree changes its angular momentum
        sides = ((load.on, load.reaction_on) if isinstance(load, Torque) else
                 load.bodies if isinstance(load, JointDamper) else ())
        trees = [node_home.get(index.get(s, 0) if s is not None else 0, (None,))[0] for s in sides]
        if trees and (None in trees or len(set(trees)) > 1):
            for side_tree in trees:
                if side_tree is not None:
                    out[side_tree].internal = False
    for load, _ in tree.gravity:  # a field on some of a tree's masses only has a moment about its centre of mass
        if load.on:
            for ft in out:
                massive = {n.name for n in ft.nodes[1:] if n.axis is None and (n.mass != 0 or n.inertia is not None)}
                if massive - set(load.on) and massive & set(load.on):
                    ft.internal = False
    # The loads outside the recursion: generalized forces on joint coordinates only.
    other = generalized_forces(kin, Assumptions(model), only=tree.other_loads)
    free_symbols = {kin.q[position[c]] for c in free_coordinates} | {kin.qd[position[c]] for c in free_coordinates}
    for ft in out:
        ft.tau = [_ZERO] * len(ft.joints)
    for forces in other:
        for i, Q in enumerate(forces.Q):
            if Q == 0:
                continue
            name = model.coordinates[i].name
            if name in free_coordinates or Q.free_symbols & free_symbols:
                raise _fail(model, f"load `{forces.name}` acts on a free body as a generalized force on `{name}` "
                                   f"(Q = {Q}): the quaternion route takes uniform gravity, couples, and efforts "
                                   "between the parts of a tree (joint torques, dampers)",
                            "write it as a couple (`torque = ...`), or remove `free = true` to integrate the model "
                            "in its coordinates")
            if i not in owner:  # pragma: no cover - every coordinate is free or a joint of a tree
                raise _fail(model, f"coordinate `{name}` drives nothing", "remove it")
            ft = out[owner[i]]
            ft.tau[ft.joints.index(i)] += Q
        if forces.potential is not None and forces.potential.free_symbols & free_symbols:
            raise _fail(model, f"the potential of load `{forces.name}` depends on a free body's coordinates",
                        "remove `free = true` to integrate the model in its coordinates")
    return kin, tuple(out), tree, other
