r"""Jupyter display of the engine's values: rendered math in the course's notation, always bounded.

`EquationsOfMotion`, `LagrangeEquation`, `FirstIntegral`, `LinearModel` and `Trajectory`
display themselves through ``_repr_latex_`` / ``_repr_markdown_`` / ``_repr_html_`` (IPython's
display protocol), which call `lagrangian._display.render`: it hands the value to `jupyter_repr`
(installed there by the package's face, this module imported on first display), which looks the
renderer up in `RENDERERS`.  Equations are printed as
``lagrangian derive --latex`` prints them (`Notation`: θ̈ is \ddot{\theta}, ψ̇² sinθ cosθ),
e.g. the top's

    L(θ):  A θ̈ − A ψ̇² sinθ cosθ + C ψ̇ sinθ (φ̇ + ψ̇ cosθ) = m g a sinθ     [Seed, section II].

Long expressions stay bounded by the report's rules (`_report.size`): an expression past
`MAX_OPS` operations, or met once `BUDGET` have been printed, shows as ⟨812 terms⟩; a wide
sum is cut into lines of `LINE_WIDTH`; an equation keeps at most `FOLD_LINES` lines.
"""

from __future__ import annotations

import html
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..analysis import FirstIntegral, LinearModel
from ..dynamics import EquationsOfMotion, LagrangeEquation
from ..numerics import Trajectory
from ._notation import Notation
from ._report.document import Equation
from ._report.size import FOLD_LINES, SizeGate, wrap_latex

__all__ = [
    "RENDERERS",
    "jupyter_repr",
    "equation_latex",
    "equations_latex",
    "equations_markdown",
    "integral_latex",
    "integral_markdown",
    "linear_model_latex",
    "trajectory_html",
    "trajectory_latex",
    "trajectory_markdown",
]

#: Largest state whose matrices A, B a linear model displays entry by entry.
MATRIX_MAX = 12


def _gate() -> SizeGate:
    return SizeGate("terms", "long expression")


def _bounded(eq: Equation) -> tuple[str, ...]:
    """At most `FOLD_LINES` lines; the rest is said, not printed."""
    if len(eq.lines) <= FOLD_LINES:
        return eq.lines
    more = len(eq.lines) - FOLD_LINES + 1
    return (*eq.lines[: FOLD_LINES - 1], rf"\ldots\ \text{{({more} more lines: see to\_sympy())}}")


def _aligned(rows: Sequence[tuple[str, ...]]) -> str:
    """Equations one under the other, continuation lines indented, as one ``$$ aligned $$`` block."""
    lines = []
    for eq in rows:
        lines.append(f"& {eq[0]}")
        lines += [rf"& \quad {line}" for line in eq[1:]]
    return "$$\n\\begin{aligned}\n" + " \\\\\n".join(lines) + "\n\\end{aligned}\n$$"


def _lagrange_rows(n: Notation, gate: SizeGate, equations) -> list[tuple[str, ...]]:
    rows = []
    for eq in equations:
        head = rf"L({n.symbol(eq.coordinate, latex=True)}):\quad "
        rows.append(_bounded(wrap_latex(head, n.latex(gate(eq.lhs)), f" = {n.latex(gate(eq.rhs))}")))
    return rows


def _notation(eom) -> Notation:
    return Notation(eom.coordinates, tuple(p.name for p in eom.model.parameters))


def equations_latex(eom) -> str:
    """The n Lagrange equations L(q_i) of ``eom`` (and its complementary rows ``f_k = 0``) as display math."""
    n, gate = _notation(eom), _gate()
    rows = _lagrange_rows(n, gate, eom.equations)
    for row in eom.constraints:
        rows.append(_bounded(wrap_latex("", n.latex(gate(row.expression)),
                                        rf" = 0 \quad \text{{({row.name.replace('_', ' ')})}}")))
    return _aligned(rows)


def equations_markdown(eom) -> str:
    """A heading line (the model, its coordinates) and the Lagrange equations."""
    n = _notation(eom)
    q = ", ".join(f"${n.symbol(c, latex=True)}$" for c in eom.coordinates)
    kind = "conservative, $L = T - U_P$" if eom.conservative else "non-conservative"
    extra = f", {len(eom.constraints)} complementary constraint rows" if eom.constraints else ""
    head = f"**{html.escape(eom.model.name)}**: {len(eom.coordinates)} Lagrange equations in {q} ({kind}{extra})"
    return head + "\n\n" + equations_latex(eom)


def _alone(exprs, coordinates: Sequence[str] = ()) -> Notation:
    """The notation of a value printed without its model: coordinates are the names with a rate among
    the symbols, parameters the other symbols (upper case first, then alphabetical)."""
    names = {str(s) for e in exprs for s in e.free_symbols}
    rated = {name.rsplit("_", 1)[0] for name in names if name.endswith(("_dot", "_ddot"))}
    coords = list(coordinates) + sorted(rated - set(coordinates))
    bare = {name for name in names if not name.endswith(("_dot", "_ddot"))} - set(coords) - {"t"}
    return Notation(tuple(coords), tuple(sorted(bare, key=lambda x: (not x[:1].isupper(), x))))


def equation_latex(eq) -> str:
    """One equation L(q_i): Γ_i = −∂U/∂q_i + Q_i(nc)."""
    return _aligned(_lagrange_rows(_alone((eq.lhs, eq.rhs), (eq.coordinate,)), _gate(), (eq,)))


def integral_latex(fi) -> str:
    """``expression = name``: the first integral and its constant."""
    n = _alone((fi.expression,), (fi.coordinate,) if fi.coordinate else ())
    name = n.symbol(fi.name, latex=True)
    return _aligned([_bounded(wrap_latex("", n.latex(_gate()(fi.expression)), f" = {name}"))])


def integral_markdown(fi) -> str:
    return f"{integral_latex(fi)}\n\n*{html.escape(fi.kind)}: {html.escape(fi.reason)}*"


def _matrix(n: Notation, gate: SizeGate, m) -> str:
    if m.rows == 0 or m.cols == 0:
        return r"\begin{bmatrix}\end{bmatrix}"
    def entry(e) -> str:
        return _num(float(e)) if e.is_Number else n.latex(gate(e))

    rows = [" & ".join(entry(m[i, j]) for j in range(m.cols)) for i in range(m.rows)]
    return r"\begin{bmatrix}" + r" \\ ".join(rows) + r"\end{bmatrix}"


def linear_model_latex(lm) -> str:
    """ẋ = A x + B u (x the perturbations of the state) with A, B written out (up to `MATRIX_MAX` states)."""
    n, gate = _notation(lm.eom), _gate()
    x = r"\begin{bmatrix}" + r" \\ ".join(n.symbol(s, latex=True) for s in lm.state) + r"\end{bmatrix}"
    u = r"\begin{bmatrix}" + r" \\ ".join(n.symbol(s, latex=True) for s in lm.inputs) + r"\end{bmatrix}"
    about = ", ".join(f"{n.symbol(k, latex=True)} = {n.latex(gate(v))}" for k, v in lm.point.items())
    if len(lm.state) > MATRIX_MAX:
        body = (r"\dot x = A\,x" + (r" + B\,u" if lm.inputs else "")
                + rf", \quad A \in \mathbb{{R}}^{{{lm.A.rows}\times{lm.A.cols}}}\ \text{{(see .numeric())}}")
    else:
        body = rf"\frac{{d}}{{dt}}{x} = {_matrix(n, gate, lm.A)}\,{x}"
        if lm.inputs:
            body += rf" + {_matrix(n, gate, lm.B)}\,{u}"
    return f"$$\n{body}\n$$\n\n" + (f"about ${about}$" if len(about) < 600 else "")


def _trajectory_rows(tr) -> list[tuple[str, str]]:
    rows = [("model", tr.model_name), ("t", f"{tr.t[0]:.6g} → {tr.t[-1]:.6g} ({len(tr.t)} points)"),
            ("method", f"{tr.method}, {tr.steps} steps, {tr.rhs_calls} right-hand sides"), ("status", tr.status)]
    for k, c in enumerate(tr.coordinates[:8]):
        rows.append((c, f"{tr.q[0, k]:.6g} → {tr.q[-1, k]:.6g}"))
    if len(tr.coordinates) > 8:
        rows.append(("…", f"{len(tr.coordinates) - 8} more coordinates"))
    if tr.integrals:
        rows.append(("relative drift", tr.drift_summary().replace(" relative drift", "")))
    if tr.events:
        rows.append(("events", str(len(tr.events))))
    rows += [("warning", w) for w in tr.warnings[:3]]
    return rows


def trajectory_html(tr) -> str:
    """A short summary table of a simulated motion."""
    cells = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th><td style='text-align:left'>"
                    f"{html.escape(v)}</td></tr>" for k, v in _trajectory_rows(tr))
    return f"<table><caption>Trajectory</caption>{cells}</table>"


def trajectory_markdown(tr) -> str:
    rows = [f"| {k} | {v.replace('|', '/')} |" for k, v in _trajectory_rows(tr)]
    return "\n".join(["| Trajectory | |", "|---|---|", *rows])


def trajectory_latex(tr) -> str:
    """The summary, with the coordinates in the course's letters (θ: initial → final)."""
    n = Notation(tr.coordinates)
    rows = [rf"t: & {tr.t[0]:.6g} \to {tr.t[-1]:.6g} & \text{{({len(tr.t)} points, {tr.method})}}"]
    for k, c in enumerate(tr.coordinates[:8]):
        rows.append(rf"{n.symbol(c, latex=True)}: & {_num(tr.q[0, k])} \to {_num(tr.q[-1, k])} &")
    for name in tr.integrals:
        rows.append(rf"{n.symbol(name, latex=True)}: & \text{{relative drift}} & {_num(tr.drift[name])}")
    return "$$\n\\begin{array}{lll}\n" + " \\\\\n".join(rows) + "\n\\end{array}\n$$"


def _num(x: float) -> str:
    text = f"{float(x):.4g}"
    if "e" in text:
        mantissa, exp = text.split("e")
        return rf"{mantissa} \times 10^{{{int(exp)}}}"
    return text if np.isfinite(x) else r"\text{" + text + "}"


#: The renderer of each value type and IPython form, for `jupyter_repr`.
RENDERERS: dict[tuple[type, str], Callable[[Any], str]] = {
    (EquationsOfMotion, "latex"): equations_latex,
    (EquationsOfMotion, "markdown"): equations_markdown,
    (LagrangeEquation, "latex"): equation_latex,
    (FirstIntegral, "latex"): integral_latex,
    (FirstIntegral, "markdown"): integral_markdown,
    (LinearModel, "latex"): linear_model_latex,
    (Trajectory, "html"): trajectory_html,
    (Trajectory, "markdown"): trajectory_markdown,
    (Trajectory, "latex"): trajectory_latex,
}


def jupyter_repr(value: object, form: str) -> str:
    """``value`` drawn for Jupyter as ``form`` (``"latex"``, ``"markdown"`` or ``"html"``): its ``_repr_*_``.

    A subclass is drawn as its nearest base in `RENDERERS` (an `OptimalTrajectory` as a `Trajectory`).

    Parameters
    ----------
    value : object
        An equation, the equations of motion, a first integral, a linear model or a trajectory.
    form : str
        ``"latex"``, ``"markdown"`` or ``"html"``.

    Returns
    -------
    str
        What the value's ``_repr_<form>_`` gives Jupyter.

    Raises
    ------
    KeyError
        A type or form that is not drawn (a programming error: each display method names a form that
        `RENDERERS` has for its type).
    """
    for cls in type(value).__mro__:
        renderer = RENDERERS.get((cls, form))
        if renderer is not None:
            return renderer(value)
    raise KeyError((type(value).__name__, form))
