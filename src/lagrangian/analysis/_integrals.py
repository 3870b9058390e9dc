"""First integrals found automatically: conjugate momenta and the energy (or Jacobi) integral.

From L(q_i):  d/dt(∂T/∂q̇_i) = ∂T/∂q_i − ∂U/∂q_i + Q_i(nc).  So

* when ∂T/∂q_i − ∂U/∂q_i + Q_i(nc) ≡ 0 — q_i is *cyclic* (∂L/∂q_i = 0) and no
  non-conservative effort works on it — the momentum p_i = ∂T/∂q̇_i is constant
  (the seed's K for ψ and H for φ);
* with h = Σ q̇_i ∂L/∂q̇_i − L and L = T − U,  dh/dt = −∂L/∂t + Σ Q_i(nc) q̇_i, so when
  L does not depend on t and the non-conservative efforts do no work, h is constant.
  If T is homogeneous quadratic in q̇ (T = ½ q̇ᵀ M q̇) then h = T + U, the energy;
  otherwise h = T2 − T0 + U, the Painlevé–Jacobi integral.
* a generalized potential U_g(q, q̇) = U0 + Σ a_j q̇_j (the Lorentz force, `dynamics._forces`)
  belongs in L = T − U − U_g, its Q_i leaving Q(nc): h = T2 − T0 + U + U0 (the part linear in
  the rates does no work), and a coordinate absent from that L, with no other effort on it,
  keeps its canonical momentum ∂L/∂q̇_i = ∂T/∂q̇_i − a_i (Goldstein, §2.6 and §8.2).

"≡ 0" is decided by a randomized high-precision identity test (`_identity`), which
does not miss zeros that only appear after simplification.

**Inputs.**  A declared input u (``[inputs]``) is a symbol in the loads.  What holds depends
on what u does (`first_integrals`' ``inputs``): *off* (u = 0, the default, as `simulate` runs
a model) — the search runs on the equations with u = 0, so a Furuta pendulum's momentum about
its motor axis is found; *constant* — u is a parameter like any other; *varying* (an input in
time or a feedback u(t, q, q̇)) — u enters each Q_i pointwise, so the tests of the momenta,
of Noether's integrals and of the nonholonomic speeds hold for every value of u at once
(a symbol) and stay valid, while the energy test ∂L/∂t ≡ 0 does not see a u(t) inside U:
an energy-like integral is then kept only when no varying input is in T or U (and the
power test Σ Q_i q̇_i ≡ 0, with u a symbol, already drops it when u works).
"""

from __future__ import annotations

import dataclasses
from collections import OrderedDict
from collections.abc import Mapping
from dataclasses import dataclass

import symengine as se

from .._display import render
from .._identity import are_zero
from ..dynamics import EquationsOfMotion, admissible_integrals, rotating_frame
from ._noether import nonholonomic_integrals, symmetry_integrals

__all__ = ["INPUT_REGIMES", "FirstIntegral", "first_integrals", "input_regime", "inputs_off"]

#: What a declared input does during a motion (`first_integrals`' ``inputs``).
INPUT_REGIMES = ("off", "constant", "varying")


@dataclass(frozen=True, slots=True)
class FirstIntegral:
    """A quantity constant along every motion: ``expression`` = ``name`` (a constant).

    Parameters
    ----------
    name : str
        The constant's name.
    kind : str
        ``"momentum"``, ``"energy"``, ``"jacobi"``, ``"symmetry"`` (Noether) or ``"nonholonomic"``
        (a constant speed).
    expression : SymEngine expression
        The expression that stays equal to it.
    reason : str
        Why it is constant, in words.
    coordinate : str, optional
        The cyclic coordinate of a momentum integral.
    """

    name: str
    kind: str  # "momentum", "energy", "jacobi", "symmetry" (Noether) or "nonholonomic" (a constant speed)
    expression: se.Basic
    reason: str
    coordinate: str | None = None

    def _repr_latex_(self) -> str:
        """``expression = name`` as display math in the course's notation (Jupyter)."""
        return render(self, "latex")

    def _repr_markdown_(self) -> str:
        """The integral, then its kind and why it holds."""
        return render(self, "markdown")


#: The last derivations' integrals, by identity: `simulate` asks for them on every run, and the
#: symmetry tests cost tens of milliseconds.  The equations are immutable and held here, so an
#: identity cannot be reused while its entry lives.
_RECENT: OrderedDict[tuple, tuple[EquationsOfMotion, tuple[FirstIntegral, ...]]] = OrderedDict()
_RECENT_SIZE = 16


def first_integrals(eom: EquationsOfMotion, *,
                    inputs: Mapping[str, str] | None = None) -> tuple[FirstIntegral, ...]:
    """The first integrals of the motion that the structure of L guarantees.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations (`lagrangian.derive`).
    inputs : mapping of str to str, optional
        What each declared input does (module docstring): ``"off"`` (u = 0; the default for every
        input not named), ``"constant"`` or ``"varying"``.  The expressions of the integrals have
        the inputs that are off set to 0.

    Returns
    -------
    tuple of FirstIntegral
        The momenta of the cyclic coordinates, the energy or Jacobi integral, those of symmetries.

    Raises
    ------
    ValueError
        A name that is not a declared input, or an unknown regime.

    Examples
    --------
    For the seed's top: K (ψ cyclic), H (φ cyclic) and the energy T + U.
    """
    regime = input_regime(eom, inputs)
    key = (id(eom), tuple(sorted(regime.items())))
    hit = _RECENT.get(key)
    if hit is not None and hit[0] is eom:
        _RECENT.move_to_end(key)
        return hit[1]
    found = _with_inputs(eom, regime)
    _RECENT[key] = (eom, found)
    while len(_RECENT) > _RECENT_SIZE:
        _RECENT.popitem(last=False)
    return found


def input_regime(eom: EquationsOfMotion, inputs: Mapping[str, str] | None) -> dict[str, str]:
    """Every declared input of ``eom``'s model with its regime (``"off"`` unless given)."""
    declared = tuple(eom.model.inputs)
    regime = {u: "off" for u in declared}
    for name, what in (inputs or {}).items():
        if name not in regime:
            raise ValueError(f"`{name}` is not a declared input of `{eom.model.name}` "
                             f"(inputs: {', '.join(declared) or 'none'})")
        if what not in INPUT_REGIMES:
            raise ValueError(f"the regime of `{name}` must be one of {', '.join(INPUT_REGIMES)}, not {what!r}")
        regime[name] = what
    return regime


def _with_inputs(eom: EquationsOfMotion, regime: Mapping[str, str]) -> tuple[FirstIntegral, ...]:
    off = [u for u, what in regime.items() if what == "off"]
    varying = {se.Symbol(u) for u, what in regime.items() if what == "varying"}
    held = [u for u, what in regime.items() if what == "constant"]
    view = inputs_held(inputs_off(eom, off), held)
    found = _first_integrals(view)
    if varying:
        in_energy = (view.T.free_symbols | view.U.free_symbols) & varying
        if in_energy:
            found = tuple(fi for fi in found if fi.kind not in ("energy", "jacobi"))
    if view is eom:
        return found
    # What holds only because some input is off says so.
    held_on = {fi.name for fi in _first_integrals(eom)}
    names = ", ".join(f"{u} = 0" for u in off)
    return tuple(fi if fi.name in held_on else dataclasses.replace(fi, reason=f"{fi.reason} (with the inputs off: "
                                                                           f"{names})")
                 for fi in found)


def inputs_off(eom: EquationsOfMotion, off: list[str] | tuple[str, ...]) -> EquationsOfMotion:
    """``eom`` with the inputs ``off`` set to 0 in the loads, the equations, M and F (``eom`` itself
    when none of them appears).  The copy has no recursive form: it is for analysis, not for code."""
    zero = {se.Symbol(u): se.Integer(0) for u in off}
    if not zero:
        return eom
    present = set()
    for load in eom.loads:
        for q in load.Q:
            present |= q.free_symbols
        if load.potential is not None:
            present |= load.potential.free_symbols
    if not present & set(zero):
        return eom

    def sub(e: se.Basic) -> se.Basic:
        return e.xreplace(zero) if e.free_symbols & set(zero) else e

    loads = tuple(dataclasses.replace(f, Q=tuple(sub(q) for q in f.Q), virtual_power=sub(f.virtual_power),
                                      potential=None if f.potential is None else sub(f.potential))
                  for f in eom.loads)
    equations = tuple(dataclasses.replace(eq, dU_dq=sub(eq.dU_dq), Q_nc=sub(eq.Q_nc), rhs=sub(eq.rhs))
                      for eq in eom.equations)
    return dataclasses.replace(eom, loads=loads, equations=equations, F=tuple(sub(f) for f in eom.F),
                               M=tuple(tuple(sub(e) for e in row) for row in eom.M), recursive=None)


def inputs_held(eom: EquationsOfMotion, held: list[str] | tuple[str, ...]) -> EquationsOfMotion:
    """``eom`` with the loads driven only by the inputs ``held`` (constant along the motion) taken with
    the potential they then derive from (`LoadForces.held`, −τ θ of a constant torque): their Q_i move from
    Q_nc to −∂U/∂q_i, so the energy integral T + U − τ θ is found.  ``eom`` itself when none applies."""
    constant = {se.Symbol(u) for u in held}
    inputs = {p.symbol for p in eom.model.parameters if p.input}
    if not constant:
        return eom
    moved = [k for k, f in enumerate(eom.loads) if f.potential is None and f.held is not None
             and {s for q in f.Q for s in q.free_symbols} & inputs <= constant]
    if not moved:
        return eom
    loads = list(eom.loads)
    for k in moved:
        loads[k] = dataclasses.replace(loads[k], potential=loads[k].held)
    kin = eom.kinematics
    equations = tuple(dataclasses.replace(
        eq, dU_dq=eq.dU_dq + se.Add(*(eom.loads[k].held.diff(q) for k in moved)),
        Q_nc=eq.Q_nc - se.Add(*(eom.loads[k].Q[i] for k in moved)))
        for i, (eq, q) in enumerate(zip(eom.equations, kin.q, strict=True)))
    return dataclasses.replace(eom, loads=tuple(loads), equations=equations, recursive=None)


def _first_integrals(eom: EquationsOfMotion) -> tuple[FirstIntegral, ...]:
    kin = eom.kinematics
    out: list[FirstIntegral] = []
    residues = [eq.dT_dq - eq.dU_dq + eq.Q_nc for eq in eom.equations]
    cyclic_tests = [eq.dT_dq - eq.dU_dq for eq in eom.equations]
    zero = are_zero(residues + cyclic_tests)
    n = len(residues)
    for k, (coordinate, eq) in enumerate(zip(eom.model.coordinates, eom.equations, strict=True)):
        if not zero[k]:
            continue
        if zero[n + k]:
            why = f"{coordinate.name} is cyclic: ∂L/∂{coordinate.name} = 0 and Q_{coordinate.name}(nc) = 0"
        else:
            why = f"∂T/∂{coordinate.name} − ∂U/∂{coordinate.name} + Q_{coordinate.name}(nc) = 0"
        out.append(FirstIntegral(coordinate.momentum or f"p_{coordinate.name}", "momentum", eq.dT_dqd, why,
                                 coordinate.name))

    generalized = [f for f in eom.loads if getattr(f, "generalized", None) is not None]
    Ug = se.Add(*(f.generalized for f in generalized))  # U_g(q, q̇, t) of the generalized potentials
    Q_other = [se.Add(q, *(-f.Q[i] for f in generalized)) for i, q in enumerate(eom.Q_nc)]
    if generalized:  # canonical momenta: ∂(T − U − U_g)/∂q_i + Q_i(other) ≡ 0
        taken = {fi.coordinate for fi in out}
        tests = [eq.dT_dq - eq.dU_dq - Ug.diff(q) + Qo for eq, q, Qo in zip(eom.equations, kin.q, Q_other, strict=True)]
        for coordinate, eq, qd, ok in zip(eom.model.coordinates, eom.equations, kin.qd, are_zero(tests), strict=True):
            if ok and coordinate.name not in taken:
                c = coordinate.name
                out.append(FirstIntegral(coordinate.momentum or f"p_{c}", "momentum", eq.dT_dqd - Ug.diff(qd),
                                         f"{c} is cyclic in L = T − U − U_g (U_g the generalized potential) and "
                                         f"no other effort works on it: the canonical momentum ∂L/∂{c}_dot = "
                                         f"∂T/∂{c}_dot − ∂U_g/∂{c}_dot is constant", c))

    L = eom.T - eom.U - Ug
    power_nc = se.Add(*(q * qd for q, qd in zip(Q_other, kin.qd, strict=True)))
    T2 = se.Rational(1, 2) * se.Add(*(eom.M[i][j] * kin.qd[i] * kin.qd[j]
                                       for i in range(n) for j in range(n) if eom.M[i][j] != 0))
    explicit_t, no_work, homogeneous = are_zero([L.diff(kin.t), power_nc, eom.T - T2])
    # U + U0: the potential energy, with the rate-free part U0 = U_g − Σ q̇ ∂U_g/∂q̇ of the generalized potentials
    U = eom.U + se.expand(Ug - se.Add(*(qd * Ug.diff(qd) for qd in kin.qd))) if generalized else eom.U
    if explicit_t and no_work:
        condition = ("L does not depend on t explicitly" +
                     (" and the system is conservative" if eom.conservative
                      else " and the non-conservative efforts do no work"))
        if generalized:
            condition += " (the part of the generalized potential linear in the rates does none)"
        if homogeneous and rotating_frame(eom):  # seed, Remarque 3: energy relative to R, U with entrainment
            out.append(FirstIntegral("h", "jacobi", eom.T + U,
                                     f"Jacobi integral T(Σ/R) + U = cste in the rotating frame R, U including the "
                                     f"potential of the entrainment inertial forces: {condition}"))
        elif homogeneous:
            out.append(FirstIntegral("E", "energy", eom.T + U,
                                     f"energy integral T + U = cste: {condition}, T homogeneous quadratic in q̇"))
        else:
            T0 = eom.T.subs({qd: 0 for qd in kin.qd})
            out.append(FirstIntegral("h", "jacobi", T2 - T0 + U,
                                     f"Painlevé–Jacobi integral T2 − T0 + U = cste: {condition}, "
                                     "T not homogeneous in q̇"))
    # Reactions of complementary constraints may work on q_i or on the motion (docs/constraints.md).
    out = list(admissible_integrals(eom, out))
    # Integrals that no single coordinate shows: symmetries of the whole system (Noether), and the
    # speeds a nonholonomic model keeps (`_noether`); only those that are new.
    known = [fi.expression for fi in out]
    for name, J, why in symmetry_integrals(eom, known):
        out.append(FirstIntegral(name, "symmetry", J, why))
        known.append(J)
    for name, u, why in nonholonomic_integrals(eom, known):
        out.append(FirstIntegral(name, "nonholonomic", u, why))
    return tuple(out)
