"""The report's section "Petits mouvements au voisinage d'une position d'équilibre" (opt-in).

About the point q0 (an equilibrium, or a steady motion), q = q0 + δq with δq small; keeping
the first-order terms of Lagrange's equations gives

    M δq̈ + (D + G) δq̇ + (K + N) δq = B u

written here coordinate by coordinate, with the parameters as letters (a second linearization
that keeps every parameter symbolic; the numbers when that one cannot be made).  Then the
pulsations — ω0² = K/M for one coordinate (g/l for the simple pendulum), the roots of
det(K − ω² M) = 0 otherwise — and the stability argument: Lagrange–Dirichlet (K = ∂²U_P/∂q²
positive definite: U_P has a strict minimum, the equilibrium is stable), the gyroscopic
theorems, or the eigenvalues of A (Lyapunov's first method).  The linearization itself is
`lagrangian.analysis.linearize`; this module only writes it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import symengine as se
import sympy
from symengine.lib.symengine_wrapper import sympy2symengine

from ....analysis import pulsations_squared
from ....errors import LagrangianError
from ..build import Context
from ..document import Block, Display, Equation, Items, Math, Para, Runs, Section
from ..size import LINE_WIDTH, visible_width, wrap_many
from .precession import precession_blocks

__all__ = ["as_linear_model", "small_motions_section"]

#: Most coordinates for which the matrices M and K are displayed as well as the equations.
MATRIX_MAX = 3
#: Longest coefficient (characters of its text) written in letters: past it (the bicycle's
#: reduced K, 10⁴ characters an entry) the equations are written with the numbers, which a reader
#: can use, and nothing slower than a matrix product is spent on the letters.
LETTERS_MAX_CHARS = 1500


def as_linear_model(eom: Any, small_motions: Any) -> Any:
    """A `LinearModel` from what ``report(..., small_motions=...)`` was given: one, or a point {name: value}."""
    from ....analysis import LinearModel, linearize

    if isinstance(small_motions, LinearModel):
        return small_motions
    if isinstance(small_motions, Mapping):
        return linearize(eom, dict(small_motions))
    if small_motions is True:
        return linearize(eom)  # the model's [operating_point]
    raise TypeError("small_motions is a LinearModel (lagrangian.linearize), a point {coordinate: value} or True "
                    f"(the model's [operating_point]), not {type(small_motions).__name__}")


def _symbolic(lin: Any) -> Any:
    """The same linearization with every parameter as a letter, or None when it cannot be made (a point that is
    an equilibrium for the given values only, e.g. cos θ0 = g/(R Ω²) given as a number)."""
    from ....analysis import linearize

    if lin.symbols and len(lin.symbols) == len([p for p in lin.eom.model.parameters if p.name not in lin.inputs]):
        return lin
    keep = [p.name for p in lin.eom.model.parameters if p.name not in lin.inputs]
    at = {c: lin.point[c] for c in lin.eom.coordinates}
    at.update({s: lin.point[s] for s in lin.speeds})
    try:
        return linearize(lin.eom, at, symbolic=tuple(keep), inputs=lin.inputs,
                         independent_speeds=lin.speeds if lin.dependent_speeds else None,
                         dependent_coordinates=lin.dependent_coordinates or None)
    except (LagrangianError, ArithmeticError, RuntimeError, ValueError, TypeError):  # then the numbers are shown
        return None


def _numeric(lin: Any) -> Any:
    """``lin`` with numbers for its symbols (the model's values), or None when some symbol has no value."""
    from ....analysis import linearize

    if not lin.symbols:
        return lin
    at = {c: lin.point[c] for c in lin.eom.coordinates}
    at.update({s: lin.point[s] for s in lin.speeds})
    try:
        out = linearize(lin.eom, at, parameters=lin.values, inputs=lin.inputs,
                        independent_speeds=lin.speeds if lin.dependent_speeds else None,
                        dependent_coordinates=lin.dependent_coordinates or None)
    except (LagrangianError, ArithmeticError, RuntimeError, ValueError, TypeError):
        return None
    return None if out.symbols else out


def _positive(lin: Any) -> Any:
    """``lin``'s second-order form with each entry simplified assuming the parameters whose value is positive are
    (a spring of rest length l0 gives k, not k (l0³ − (l0²)^{3/2} + l0² |l0|)/l0³)."""
    so = lin.second_order
    positive = {sympy.Symbol(p.name): sympy.Symbol(p.name, positive=True)
                for p in lin.eom.model.parameters if p.value is not None and p.value > 0}
    back = {v: k for k, v in positive.items()}

    def tidy(e: se.Basic) -> se.Basic:
        if not e.free_symbols or len(str(e)) > LETTERS_MAX_CHARS:
            return e
        x = e._sympy_().xreplace(positive)
        y = sympy.factor(sympy.cancel(x)).xreplace(back)
        return sympy2symengine(y) if len(str(y)) < len(str(e)) else e

    def matrix(m: se.DenseMatrix) -> se.DenseMatrix:
        if m.rows == 0 or m.cols == 0:
            return m
        return se.DenseMatrix([[tidy(m[i, j]) for j in range(m.cols)] for i in range(m.rows)])

    return dataclasses.replace(so, **{k: matrix(getattr(so, k)) for k in ("M", "D", "G", "K", "N", "B")})


def _longest(so: Any) -> int:
    """The length of the longest coefficient of the second-order form, as text."""
    return max((len(str(m[i, j])) for m in (so.M, so.D, so.G, so.K, so.N, so.B)
                for i in range(m.rows) for j in range(m.cols)), default=0)


def _var(c: Context, name: str, deco: str = "") -> str:
    return r"\delta " + c.sym(name, deco)


def _terms(c: Context, pairs: list[tuple[se.Basic, str]]) -> list[str]:
    r"""Σ coefficient · variable as signed LaTeX terms: ``m l^{2}\,\delta\ddot{\theta}``, ``+ m g l\,\delta\theta``."""
    out: list[str] = []
    for coef, var in pairs:
        if coef == 0:
            continue
        e = c.ex(coef)
        neg = bool(getattr(e, "could_extract_minus_sign", lambda: False)())
        if neg:
            e = -e
        if e == 1:
            body = var
        else:
            text = c.n.latex(e)
            body = (rf"\left({text}\right)" if isinstance(e, sympy.Add) else text) + r"\," + var
        out.append(("-" if neg else "") + body if not out else ("- " if neg else "+ ") + body)
    return out or ["0"]


def _is_zero(m: se.DenseMatrix) -> bool:
    return all(m[i, j] == 0 for i in range(m.rows) for j in range(m.cols))


def _equations(c: Context, so: Any, inputs: tuple[str, ...]) -> list[Equation]:
    q = so.coordinates
    rows = []
    for i in range(len(q)):
        pairs = [(so.M[i, j], _var(c, x, "ddot")) for j, x in enumerate(q)]
        pairs += [(so.D[i, j] + so.G[i, j], _var(c, x, "dot")) for j, x in enumerate(q)]
        pairs += [(so.K[i, j] + so.N[i, j], _var(c, x)) for j, x in enumerate(q)]
        rhs = _terms(c, [(so.B[i, k], c.sym(u)) for k, u in enumerate(inputs)]) if so.B.cols else ["0"]
        left = _terms(c, pairs)
        rows.append(wrap_many("", left[:-1] + [left[-1] + " = " + rhs[0]] + rhs[1:], " "))
    return rows


def _pmatrix(c: Context, name: str, m: se.DenseMatrix) -> str:
    rows = [" & ".join(c.tex(m[i, j]) if m[i, j] != 0 else "0" for j in range(m.cols)) for i in range(m.rows)]
    return rf"{name} = \begin{{pmatrix}} " + r" \\ ".join(rows) + r" \end{pmatrix}"


def _numbers(lin: Any, m: se.DenseMatrix) -> np.ndarray:
    return np.array([[float(complex(m[i, j]).real) for j in range(m.cols)] for i in range(m.rows)])


def _point(c: Context, lin: Any) -> Runs:
    parts = []
    for name, value in lin.point.items():
        parts.append(Math(f"{c.sym(name[:-4], 'dot') if name.endswith('_dot') else c.sym(name)} = "
                          f"{c.w.number(float(complex(value).real)) if value.is_Number else c.tex(value)}"))
    return c.w.join(parts)


def _pulsations(c: Context, so: Any, modes: Any, at: Mapping) -> list[Block]:
    w = c.w
    blocks: list[Block] = []
    if not modes.pulsations:
        return blocks
    if len(modes.pulsations) == 1 and so is not None and so.M.rows == 1 and so.K[0, 0] != 0:
        ratio = sympy.factor(sympy.cancel(so.K[0, 0]._sympy_() / so.M[0, 0]._sympy_()))
        omega = modes.pulsations[0]
        blocks.append(Para(w("small one pulsation", q=Math(_var(c, so.coordinates[0]))), ))
        blocks.append(Display((Equation((rf"\omega_{{0}}^{{2}} = {c.n.latex(ratio)}",)),)))
        blocks.append(Para(w("small omega value", omega=Math(rf"\omega_{{0}} = {w.number(omega)}\ \mathrm{{rad/s}}"),
                             T=Math(rf"T_{{0}} = \frac{{2\pi}}{{\omega_{{0}}}} = {w.number(2 * math.pi / omega)}"
                                    r"\ \mathrm{s}"))))
        return blocks
    blocks.append(Para(w("small pulsations", det=Math(r"\det\left(K - \omega^{2} M\right) = 0"))))
    letters = _letters(c, so, modes, at) if so is not None else None
    items = []
    for k, om in enumerate(modes.pulsations, 1):
        T = rf",\quad T_{{{k}}} = {w.number(2 * math.pi / om)}\ \mathrm{{s}}" if om > 0 else ""
        closed = rf"\omega_{{{k}}}^{{2}} = {c.n.latex(letters[k - 1])},\quad " if letters else ""
        items.append((Math(rf"{closed}\omega_{{{k}}} = {w.number(om)}\ \mathrm{{rad/s}}{T}"),))
    blocks.append(Items(tuple(items)))
    return blocks


def _letters(c: Context, so: Any, modes: Any, at: Mapping) -> list[sympy.Basic] | None:
    """The nonzero roots ω² of det(K − ω² M) = 0 in letters, in the order of ``modes.pulsations`` (matched by their
    values at ``at``: the parameters' values, θ0's), or None (too large, or not conservative)."""
    if any(not _is_zero(getattr(so, k)) for k in ("D", "G", "N")):
        return None
    M = sympy.Matrix([[so.M[i, j]._sympy_() for j in range(so.M.cols)] for i in range(so.M.rows)])
    K = sympy.Matrix([[so.K[i, j]._sympy_() for j in range(so.K.cols)] for i in range(so.K.rows)])
    positive = [p.name for p in c.model.parameters if p.value is not None and p.value > 0]
    roots = pulsations_squared(M, K, positive)
    if not roots or len(roots) != len(modes.pulsations):
        return None
    try:
        values = [float(r.xreplace(at)) for r in roots]
    except (TypeError, ValueError):
        return None
    order = []
    for om in modes.pulsations:
        k = min(range(len(values)), key=lambda j: abs(values[j] - om * om))
        if abs(values[k] - om * om) > 1e-6 * max(1.0, om * om) or k in order:
            return None
        order.append(k)
    return [roots[k] for k in order]


def _eigenvalue(w: Any, z: complex) -> str:
    scale = max(1.0, abs(z))
    re_ = 0.0 if abs(z.real) < 1e-12 * scale else z.real
    im = 0.0 if abs(z.imag) < 1e-12 * scale else z.imag
    unit = r"\ \mathrm{s^{-1}}"  # the eigenvalues of A are rates: 1/s
    if im == 0:
        return w.number(re_) + unit
    if re_ == 0:
        return rf"\pm {w.number(abs(im))}\,i" + unit
    return rf"\left({w.number(re_)} \pm {w.number(abs(im))}\,i\right)" + unit


def _eigenvalues(c: Context, lam: np.ndarray) -> Runs:
    shown: list[str] = []
    for z in lam:
        text = _eigenvalue(c.w, complex(z))
        if text not in shown:
            shown.append(text)
    return c.w.join([Math(rf"{c.eigen} = {t}") for t in shown])


def _essential_KG(lin: Any, modes: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """K and G on the essential coordinates (the neutral ones set aside), when the form is second order."""
    so = lin.second_order
    if so is None or lin.symbols:
        return None
    idx = [i for i, q in enumerate(so.coordinates) if q in modes.essential]
    if not idx:
        return None
    return _numbers(lin, so.K)[np.ix_(idx, idx)], _numbers(lin, so.G)[np.ix_(idx, idx)]


def _stability(c: Context, lin: Any, stability: Any, modes: Any) -> list[Block]:
    """The argument that decides: Lagrange–Dirichlet, the gyroscopic theorems, or an eigenvalue."""
    w = c.w
    lam = np.asarray(stability.eigenvalues)
    kmin = None
    gyroscopic = False
    KG = _essential_KG(lin, modes)
    if KG is not None:
        K_e, G_e = KG
        kmin = float(np.linalg.eigvalsh((K_e + K_e.T) / 2).min())
        gyroscopic = bool(np.any(np.abs(G_e) > 1e-10 * max(1.0, float(np.abs(K_e).max(initial=0.0)))))
    K = Math(r"K = \left.\frac{\partial^{2} U_P}{\partial q\,\partial q}\right|_{q_{0}}")
    verdict = stability.verdict
    set_aside = [x for x, why in modes.neutral if x != "momentum" and not x.endswith("_dot")]
    if verdict == "stable":
        key = "small kelvin tait" if gyroscopic else ("small lagrange dirichlet neutral" if set_aside
                                                      else "small lagrange dirichlet")
    elif verdict == "stable to first order":
        key = "small gyroscopic" if gyroscopic and kmin is not None and kmin < 0 else "small first order stable"
    elif verdict == "unstable":
        key = "small unstable no minimum" if kmin is not None and kmin < 0 else "small unstable"
    elif verdict == "asymptotically stable":
        key = "small asymptotic"
    elif verdict == "unstable (secular growth)":
        key = "small secular"
    else:
        key = "small marginal"
    worst = complex(lam[np.argmax(lam.real)]) if lam.size else 0j
    blocks: list[Block] = []
    neutral = [x for x, why in modes.neutral if x != "momentum" and "Jordan chain" not in why]
    momenta = sum(1 for x, _ in modes.neutral if x == "momentum")
    if neutral or momenta:
        names: list[Any] = [Math(c.sym(x[:-4], "dot") if x.endswith("_dot") else c.sym(x)) for x in neutral]
        if momenta:
            names.append(w.text("small momenta", k=str(momenta)) if momenta > 1 else w.text("small momentum"))
        blocks.append(Para(w("small neutral" if len(names) > 1 else "small neutral one", names=w.join(names))))
    if lam.size:
        listed = "small eigenvalues left" if modes.neutral else "small eigenvalues"
        blocks.append(Para(w(listed, lam=_eigenvalues(c, lam))))
    zero = modes.zero
    chain = {}
    if key == "small secular" and zero is not None:
        def var(x: str) -> Math:
            return Math(_var(c, x[:-4], "dot") if x.endswith("_dot") else _var(c, x))
        chain = {"k": str(max(zero.blocks)), "start": var(zero.start), "end": var(zero.end),
                 "t": Math("t" if zero.growth == 1 else f"t^{{{zero.growth}}}")}
    essential = [Math(c.sym(x)) for x in modes.essential if not x.endswith("_dot")]
    blocks.append(Para(w(key, K=K, U=Math("U_P"), q0=Math("q_{0}"), lam=Math(rf"{c.eigen} = {_eigenvalue(w, worst)}"),
                         kmin=Math(w.number(kmin if kmin is not None else 0.0)), names=w.join(essential), **chain)))
    return blocks


def _closed(lin: Any, num: Any) -> tuple[Any, Any] | None:
    """(the closed-form point, its second-order form as SymEngine matrices) when the point is a closed-form
    equilibrium that holds for some values only (cos θ0 = g/(R Ω²)), else None."""
    from ....analysis import SecondOrderForm, closed_point

    if num is None or lin.steady or num.second_order is None:
        return None
    point = {q: float(complex(num.point[q]).real) for q in lin.eom.coordinates}
    closed = closed_point(lin.eom, point, num.values)
    if closed is None:
        return None

    def matrix(m: sympy.Matrix) -> se.DenseMatrix:
        return se.DenseMatrix([[sympy2symengine(m[i, j]) for j in range(m.cols)] for i in range(m.rows)])

    form = SecondOrderForm(closed.coordinates, *(matrix(getattr(closed, k)) for k in ("M", "D", "G", "K", "N")),
                           se.zeros(len(closed.coordinates), 0))
    return closed, form


def _defined(c: Context, lin: Any, inputs: bool) -> Para:
    """What M, D, G, K, N (and B) are."""
    w = c.w
    slots = {k: Math(k) for k in ("M", "D", "G", "K", "N")}
    if lin.dependent_speeds:
        runs = w("small matrices defined reduced", dqd=Math(r"\delta\dot{q}"), dq=Math(r"\delta q"), **slots)
    else:
        runs = w("small matrices defined", q0=Math("q_{0}"), dF=Math(r"-\partial F/\partial \dot{q}"),
                 dFq=Math(r"-\partial F/\partial q"), KU=Math(r"K = \partial^{2} U_P/\partial q^{2}"), **slots)
    if inputs:
        runs = runs + w("small B defined", B=Math(r"B" if lin.dependent_speeds else r"B = \partial F/\partial u"),
                        u=Math("u"))
    return Para(runs)


def _closed_point_para(c: Context, closed: Any) -> Para:
    """θ0 = arccos(g/(R Ω²)), i.e. cos θ0 = g/(R Ω²); it exists only if R Ω² > g; g = R Ω² cos θ0 is used."""
    w = c.w
    defs = w.join([Math(rf"{c.sym(q)}_{{0}} = {c.n.latex(closed.definitions[q])}") for q in closed.definitions])
    rels = w.join([Math(_relation(c, closed.relations[q])) for q in closed.relations])
    parts: dict[str, Any] = {"defs": defs, "rels": rels}
    key = "small closed point"
    if closed.condition is not None:
        key += " condition"
        parts["cond"] = Math(_relation(c, closed.condition))
    if closed.eliminated:
        key += " eliminated"
        parts["subs"] = w.join([Math(rf"{c.n.latex(p)} = {c.n.latex(v)}") for p, v in closed.eliminated.items()])
    return Para(w(key, **parts))


_RELATIONS = {sympy.Equality: "=", sympy.StrictGreaterThan: ">", sympy.GreaterThan: r"\geq",
              sympy.StrictLessThan: "<", sympy.LessThan: r"\leq", sympy.Unequality: r"\neq"}


def _relation(c: Context, rel: sympy.Basic) -> str:
    """``cos θ0 = g/(R Ω²)``, ``R Ω² > g``, or the parts of an And joined by commas, in LaTeX."""
    if isinstance(rel, sympy.And):
        return r",\ ".join(_relation(c, x) for x in rel.args)
    op = _RELATIONS.get(type(rel))
    if op is None:
        return c.n.latex(rel)
    plain = {s: sympy.Symbol(s.name) for s in rel.free_symbols}
    return f"{c.n.latex(rel.lhs.xreplace(plain))} {op} {c.n.latex(rel.rhs.xreplace(plain))}"


def small_motions_section(c: Context, lin: Any) -> Section:
    """The section: the point, the linearized equations, the pulsations, the stability argument."""
    w = c.w
    sym = _symbolic(lin)
    num = _numeric(lin)
    longest = _longest(sym.second_order) if sym is not None and sym.second_order is not None else 0
    long = longest > LETTERS_MAX_CHARS
    if long:
        sym = None
    closed = _closed(lin, num) if sym is None and not long else None
    shown = sym if sym is not None and sym.second_order is not None else (num or lin)
    intro = "small intro steady" if lin.steady else "small intro"
    blocks: list[Block] = [Para(w(intro, point=_point(c, lin), dq=Math(r"q = q_{0} + \delta q")))]
    if lin.dependent_coordinates or lin.dependent_speeds:
        names = [Math(c.sym(x)) for x in lin.dependent_coordinates] + \
                [Math(c.sym(x[:-4], "dot")) for x in lin.dependent_speeds]
        blocks.append(Para(w("small dependent", names=w.join(names))))
    if closed is not None:
        blocks.append(_closed_point_para(c, closed[0]))
    so = closed[1] if closed is not None else _positive(shown) if shown is sym else shown.second_order
    letters = closed is not None or shown is sym
    if so is not None:
        form = r"M\,\delta\ddot{q} + (D + G)\,\delta\dot{q} + (K + N)\,\delta q = " + (r"B\,u" if so.B.cols else "0")
        blocks.append(Para(w("small equations", form=Math(form))))
        blocks += c.show(_equations(c, so, tuple(lin.inputs)), w.text("small title"))
        matrices = [_pmatrix(c, "M", so.M), _pmatrix(c, "K", so.K)]
        if 2 <= len(so.coordinates) <= MATRIX_MAX and all(_is_zero(getattr(so, k)) for k in ("D", "G", "N")) \
                and all(visible_width(m) <= LINE_WIDTH for m in matrices):
            blocks.append(Para(w("small matrices")))
            blocks.append(Display(tuple(Equation((m,)) for m in matrices)))
        blocks.append(_defined(c, lin, bool(so.B.cols)))
        if not letters:
            note = w("small numeric long", n=w.number(longest)) if long else w("small numeric")
            blocks.append(Para(note, style="note"))
    else:
        blocks.append(Para(w("small first order", x=Math(r"\dot{x} = A\,x"), why=lin.second_order_reason)))
    if num is None:  # a symbol without a value: no eigenvalue, no verdict
        blocks.append(Para(w("small no values", names=w.join([Math(c.sym(str(x))) for x in lin.symbols]))))
    else:
        stability, modes = num.stability(), num.modes()
        at: dict[sympy.Basic, float] = {sympy.Symbol(k): v for k, v in num.values.items()}
        if closed is not None:
            at.update({s: float(complex(num.point[q]).real) for q, s in closed[0].symbols.items()})
        blocks += _pulsations(c, so if letters else None, modes, at)
        blocks += _stability(c, num, stability, modes)
    blocks += precession_blocks(c, so)  # Larmor: the turning plane of oscillation (Foucault's pendulum)
    return Section("small motions", w.text("small title steady" if lin.steady else "small title"), tuple(blocks))
