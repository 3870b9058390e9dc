"""The Newton–Euler check as terminal text, in the course's notation: what ``lagrangian verify`` prints.

`verification_text` writes `lagrangian.analysis.verify`'s result: each body's vector theorems
(m γ(G) = ΣF + R, δ_P = ΣM_P + M_P(R)), each L(q_i) as those theorems projected on the directions
of q_i, both sides, ✓ or ✗; the reactions of the constraints (`lagrangian.analysis.reactions`);
the residuals along a simulated motion (`lagrangian.analysis.check_trajectory`).
`verification_failure` says the first disagreement in one sentence.  The numbers and expressions
come from the analysis; this module only writes them.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import symengine as se
import sympy

from ..errors import LagrangianError
from ..model import Torque, Vector
from ._course import reference_label, to_sympy
from ._notation import Notation

if TYPE_CHECKING:
    from ..analysis import Reaction, TrajectoryResiduals, Verification

__all__ = ["MAX_PRINTED", "verification_failure", "verification_text"]

#: Longest expression printed in full (characters); longer ones are summarized by their size.
MAX_PRINTED = 1500


class _Printer:
    """Expressions and vectors of one model in the course's notation."""

    def __init__(self, v: Verification) -> None:
        model = v.eom.model
        self.kin = v.eom.kinematics
        self.notation = Notation([c.name for c in model.coordinates], [p.name for p in model.parameters])
        #: The frame the theorems are written in: R0, or the reference frame R (with the inertial loads).
        self.frame = reference_label(model)

    def expr(self, e: se.Basic, *, full: bool = False) -> str:
        return self._short(self.notation.text(to_sympy(e)), full)

    @staticmethod
    def _short(text: str, full: bool = False) -> str:
        if full or len(text) <= MAX_PRINTED:
            return text
        return f"[{len(text)} characters; `lagrangian.analysis.verify` holds the expression]"

    def vector(self, v: Vector, frame: str | None = None) -> str:
        pieces = [(frame, self.kin.frames.express(v, frame))] if frame else list(self.kin.frames.lift(v))
        terms = []
        for f, comps in pieces:
            for c, axis in zip(comps, self.kin.frames.axes(f), strict=True):
                c = to_sympy(c)
                if c != 0:
                    terms.append((c, axis))
        return self._short(self.notation.vector(terms)) if terms else "0"

    def axes(self, frame: str) -> str:
        return ", ".join(self.kin.frames.axes(frame))


def verification_text(v: Verification, reactions: Sequence[Reaction] | LagrangianError | None = None,
                      along: TrajectoryResiduals | None = None, *, tolerance: float = 1e-9) -> str:
    """What ``lagrangian verify`` prints: the check ``v`` of every Lagrange equation by the Newton–Euler theorems.

    Parameters
    ----------
    v : Verification
        From `lagrangian.analysis.verify`.
    reactions : sequence of Reaction, or LagrangianError, optional
        The reactions of the constraints (`lagrangian.analysis.reactions`), or the error that
        stopped them (a body without its mass), written as the reason they are not computed; None: no section.
    along : TrajectoryResiduals, optional
        The residuals along a simulated motion (`lagrangian.analysis.check_trajectory`); None: no section.
    tolerance : float, optional
        The largest relative residual along the motion written as passing.

    Returns
    -------
    str
        The text, ending with the verdict ("All 3 Lagrange equations agree with the Newton–Euler theorems ✓").

    Examples
    --------
    >>> import lagrangian
    >>> from lagrangian.analysis import reactions, verify
    >>> v = verify(lagrangian.derive(lagrangian.lagrange_top()))            # doctest: +SKIP
    >>> print(lagrangian.output.verification_text(v, reactions(v)))         # doctest: +SKIP
    """
    p = _Printer(v)
    lines = _symbolic_report(v, p)
    if isinstance(reactions, LagrangianError):
        lines += ["", f"Constraint reactions: not computed: {reactions.message}.", f"  tip: {reactions.fix}"]
    elif reactions is not None:
        lines += _reaction_report(v, reactions, p)
    if along is not None:
        lines += _numeric_report(along, p, tolerance)
    failed, count = sum(not c.agrees for c in v.checks), len(v.checks)
    if failed:
        disagree = f"{failed} of the {count} Lagrange equations disagree" if count > 1 else \
            "The Lagrange equation disagrees"
        lines += ["", f"{disagree} with the Newton–Euler theorems ✗"]
    else:
        agree = f"All {count} Lagrange equations agree" if count > 1 else "The Lagrange equation agrees"
        lines += ["", f"{agree} with the Newton–Euler theorems ✓"]
    return "\n".join(lines) + "\n"


def verification_failure(v: Verification) -> str | None:
    """The first Lagrange equation of ``v`` that disagrees with the theorems, in one sentence.

    What ``lagrangian verify`` raises (exit code 5): the side that differs, both forms and their
    difference.

    Parameters
    ----------
    v : Verification
        From `lagrangian.analysis.verify`.

    Returns
    -------
    str or None
        The sentence; None when every equation agrees.
    """
    failed = [c for c in v.checks if not c.agrees]
    if not failed:
        return None
    p = _Printer(v)
    c = failed[0]
    side, ours, theirs = (("left side", c.newton_euler, c.lagrange) if not c.lhs_agrees
                          else ("right side", c.newton_euler_efforts, c.lagrange_efforts))
    return (f"L({c.coordinate}) does not agree with the {c.describe()}: its {side} is "
            f"`{p.expr(theirs)}`, the theorems give `{p.expr(ours)}` "
            f"(difference `{p.expr(sympy.expand(to_sympy(ours - theirs)))}`)"
            + (f"; {len(failed) - 1} other equation(s) disagree too." if len(failed) > 1 else "."))


def _symbolic_report(v: Verification, p: _Printer) -> list[str]:
    model = v.eom.model
    f = p.frame
    where = ("R0 Galilean" if f == "R0" else
             f"relative to {f}, not Galilean: the Coriolis and entrainment inertial efforts are among the loads")
    lines = [f"Newton–Euler check of {model.name} ({where})", "",
             "Vector theorems, body by body (R = constraint actions on it, M_P their moment):"]
    for th in v.theorems:
        efforts = " + ".join(th.efforts) if th.efforts else "0"
        if th.kind == "particle":
            lines.append(f"  {th.name} (particle): {p.expr(th.mass)} γ({th.name}/{f}) = {efforts} + R")
            continue
        at = th.point if th.point != th.name else "G"
        mass = (p.expr(th.mass) if model.body(th.name).mass_given
                else "m (not given: G is fixed)")  # m·0: the theorem holds whatever m
        lines.append(f"  {th.name} (body, moments at {at}): {mass} γ(G/{f}) = {efforts} + R;  "
                     f"δ_{at}({th.name}/{f}) = M_{at}({efforts}) + M_{at}(R)")
        lines.append(f"      σ_{at}({th.name}/{f}) = Π_{at}·Ω = {p.vector(th.angular_momentum)}")
    lines += ["", "Each L(q_i) is those theorems projected on the directions of q_i (∂V/∂q̇_i, ∂Ω/∂q̇_i). "
              "The constraints are perfect:", "their actions do no virtual work and drop out of every projection."]
    if v.virtual_power_loads:
        lines.append("Taken by their generalized forces (no force form): " + ", ".join(v.virtual_power_loads) + ".")
    lines.append("")
    for c in v.checks:
        q = p.notation.symbol(c.coordinate)
        direction = p.vector(c.direction) if c.direction is not None and c.axis is None else None
        mark = "✓" if c.agrees else "✗"
        lines.append(f"  L({q}) ⇔ {c.describe(direction)}:")
        lines.append(f"      {p.expr(c.newton_euler)} = {p.expr(c.newton_euler_efforts)} {mark}")
        if not c.lhs_agrees:
            lines.append(f"      ✗ but Γ_{q} = {p.expr(c.lagrange)}")
        if not c.rhs_agrees:
            lines.append(f"      ✗ but −∂U/∂{q} + Q_{q} = {p.expr(c.lagrange_efforts)}")
    return lines


def _reaction_report(v: Verification, rs: Sequence[Reaction], p: _Printer) -> list[str]:
    lines = ["", f"Constraint reactions (resultant theorem: what the given efforts leave of Σ m γ(G/{p.frame})):"]
    for r in rs:
        members = " + ".join(r.elements)
        masses = " + ".join(_mass_acceleration(v, p, n, alone=len(r.elements) == 1) for n in r.elements)
        couples = {load.name for load in v.eom.model.loads if isinstance(load, Torque)}
        forces = sorted({load for n in r.elements for load in v.element(n).efforts} - couples)
        if r.pinned is not None:
            lines.append(f"  {r.name}, the reaction of the fixed point {r.point} on {members}:")
        else:
            lines.append(f"  {r.name}, the resultant of the ground's constraint actions on {members}:")
        lines.append(f"      {r.name} = {masses} − ({' + '.join(forces) or '0'})")
        lines.append(f"          = {p.vector(r.force, r.frame)}    (in {r.frame}: {p.axes(r.frame)})")
        if r.pinned is None:
            continue
        if not r.transmits_moment:
            lines.append(f"      M_{r.point} = 0: {r.point} lets {r.pinned} turn about every axis (a ball joint), "
                         "so the moment theorem at it holds with the reaction's moment alone, which is zero.")
        else:
            o = r.point
            lines.append(f"      M_{o} = Σ δ_{o} − Σ M_{o}(given), the moment the joint transmits, has no "
                         f"component along the {r.free_rotations} axis(es) it lets {r.pinned} turn about "
                         "(a perfect joint)" + _across(r, p))
    return lines


def _mass_acceleration(v: Verification, p: _Printer, name: str, *, alone: bool) -> str:
    """``m γ(G/R0)`` for a lone body, ``m1 γ(G_S1/R0)`` in a group, ``m γ(P/R0)`` for a particle (R for R0
    when the equations are written in a reference frame R)."""
    th = v.element(name)
    point = name if th.kind == "particle" else ("G" if alone else f"G_{name}")
    return f"{p.expr(th.mass)} γ({point}/{p.frame})"


def _across(r: Reaction, p: _Printer) -> str:
    """``"; across x0: ..."`` when the free axes are one basis vector (a hinge), else ``"."``."""
    kin = p.kin
    axes = [list(kin.frames.lift(w)) for w in r.free_axes]
    first = axes[0]
    if r.free_rotations != 1 or len(first) != 1 or any(a != first for a in axes):
        return "."
    frame, comps = first[0]
    nonzero = [k for k, x in enumerate(comps) if x != 0]
    if len(nonzero) != 1:
        return "."
    k = nonzero[0]
    moment = list(kin.frames.express(r.moment, frame))
    moment[k] = se.Integer(0)
    return f"; across {kin.frames.axes(frame)[k]}: {p.vector(Vector({frame: tuple(moment)}))}."


def _numeric_report(res: TrajectoryResiduals, p: _Printer, tolerance: float) -> list[str]:
    lines = ["", f"Along a simulated motion (t from {res.t[0]:g} to {res.t[-1]:g}, {len(res.t)} states, "
             f"q̈ from the trajectory), largest relative residuals:"]
    for k, c in enumerate(res.coordinates):
        lines.append(f"  L({p.notation.symbol(c)}) projected: {np.max(res.projections[:, k], initial=0.0):.1e}")
    for name, values in res.resultant.items():
        lines.append(f"  Σ m γ(G) = Σ F + {name}: {np.max(values, initial=0.0):.1e}")
    for name, values in res.moment.items():
        lines.append(f"  moment theorem at the pin with {name}, on its free axes: {np.max(values, initial=0.0):.1e}")
    for name, h in res.reactions.items():
        size = np.linalg.norm(h.force, axis=1)
        k = int(np.argmax(size))
        lines.append(f"  {name}(t) in R0: at t = {h.t[0]:g}: ({', '.join(f'{x:.6g}' for x in h.force[0])}); "
                     f"largest |{name}| = {size[k]:.6g} at t = {h.t[k]:.6g}")
    what, worst = res.worst()
    if worst <= tolerance:
        lines.append(f"  all within {tolerance:g} ✓")
    else:
        lines.append(f"  {what} is off by {worst:.3g}, more than {tolerance:g} ✗")
    return lines
