"""Small motions as terminal text, in the course's notation: M, D, G, K, N, A, B, eigenvalues, ω, T, ζ, verdict.

What ``lagrangian linearize`` and ``lagrangian modes`` print, for library users too: `linear_text`,
`modes_text` and `sweep_text`.  The numbers come from the linearization
(`lagrangian.analysis.linearize`), its modes and its stability; this module only writes them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import symengine as se

from ._notation import Notation

if TYPE_CHECKING:
    from ..analysis import LinearModel, Modes, Stability, Sweep

__all__ = ["eigenvalue", "linear_text", "modes_text", "number", "sweep_text"]

#: Entries of a printed matrix wider than this are listed one per line instead.
CELL_MAX = 40


def number(x: float) -> str:
    """A number as the tables print it: 9 significant digits, −0 written 0."""
    if x == 0:
        return "0"
    return f"{x:.9g}".replace("-", "−")


def eigenvalue(z: complex, *, pair: bool = False) -> str:
    """``−0.5 ± 4.41 i`` (``pair``: the conjugate pair), ``4.05``, ``4.43 i``."""
    scale = max(abs(z), 1.0)
    re_ = 0.0 if abs(z.real) < 1e-12 * scale else z.real
    im = 0.0 if abs(z.imag) < 1e-12 * scale else z.imag
    if im == 0:
        return number(re_)
    sign = "±" if pair else ("+" if im > 0 else "−")
    if re_ == 0:
        return f"{'±' if pair else ('' if im > 0 else '−')}{number(abs(im))} i"
    return f"{number(re_)} {sign} {number(abs(im))} i"


def _notation(lin: LinearModel) -> Notation:
    model = lin.eom.model
    return Notation([c.name for c in model.coordinates], [p.name for p in model.parameters])


def _cell(n: Notation, e: se.Basic) -> str:
    if not e.free_symbols:
        return number(float(complex(e).real))
    return n.text(e._sympy_())


def _is_zero(m: se.DenseMatrix) -> bool:
    return all(m[i, j] == 0 for i in range(m.rows) for j in range(m.cols))


def _matrix(n: Notation, name: str, m: se.DenseMatrix, indent: str = "  ") -> list[str]:
    """``name = [ ... ]`` as aligned rows, or entry by entry when an entry is long; ``0`` for a zero matrix."""
    if m.rows == 0 or m.cols == 0:
        return [f"{indent}{name} = (empty: {m.rows} × {m.cols})"]
    if _is_zero(m):
        return [f"{indent}{name} = 0"]
    cells = [[_cell(n, m[i, j]) for j in range(m.cols)] for i in range(m.rows)]
    widest = max(len(c) for row in cells for c in row)
    if widest > CELL_MAX:
        out = [f"{indent}{name} ({m.rows} × {m.cols}), nonzero entries:"]
        out += [f"{indent}  {name}[{i + 1},{j + 1}] = {cells[i][j]}" for i in range(m.rows) for j in range(m.cols)
                if m[i, j] != 0]
        return out
    head = f"{indent}{name} = "
    out = []
    for i, row in enumerate(cells):
        text = "  ".join(c.rjust(widest) for c in row)
        out.append((head if i == 0 else " " * len(head)) + f"[ {text} ]")
    return out


def _point_text(n: Notation, lin: LinearModel) -> str:
    parts = []
    for name, value in lin.point.items():
        v = number(float(complex(value).real)) if value.is_Number else n.text(value._sympy_())  # π stays π
        parts.append(f"{n.symbol(name)} = {v}")
    return ", ".join(parts)


def _vector(n: Notation, names: Sequence[str], prefix: str = "δ") -> str:
    return "(" + ", ".join(prefix + n.symbol(x) for x in names) + ")"


def linear_text(lin: LinearModel, stability: Stability | None = None, modes: Modes | None = None) -> str:
    """What ``lagrangian linearize`` prints: the linearized equations about the point, eigenvalues, verdict.

    The eigenvalues and the verdict are shown when no parameter is left symbolic.

    Parameters
    ----------
    lin : LinearModel
        From `lagrangian.linearize`.
    stability : Stability, optional
        ``lin.stability()``, computed here when not given and ``lin`` has no symbol left (with
        symbols left, the text says which values to give).
    modes : Modes, optional
        ``lin.modes()``, likewise.

    Returns
    -------
    str
        The text.

    Examples
    --------
    >>> import lagrangian
    >>> eom = lagrangian.derive(lagrangian.load_model("examples/simple_pendulum.toml"))  # doctest: +SKIP
    >>> print(lagrangian.output.linear_text(lagrangian.linearize(eom, {"theta": 0})))  # doctest: +SKIP
    """
    if not lin.symbols:
        stability = lin.stability() if stability is None else stability
        modes = lin.modes() if modes is None else modes
    n = _notation(lin)
    model = lin.eom.model
    kind = "a steady motion" if lin.steady else "an equilibrium"
    lines = [f"{model.name} — small motions about {kind}", f"Point: {_point_text(n, lin)}"]
    if lin.residual:
        lines.append(f"  (residual force at the point: {lin.residual:.2g} of the forces' scale)")
    if lin.values:
        lines.append("Values: " + ", ".join(f"{n.symbol(k)} = {number(v)}" for k, v in lin.values.items()
                                            if k not in {str(s) for s in lin.symbols}))
    if lin.symbols:
        lines.append("Kept symbolic: " + ", ".join(n.symbol(str(s)) for s in lin.symbols))
    if lin.dependent_coordinates or lin.dependent_speeds:
        lines.append("Dependent coordinates: " + (", ".join(n.symbol(c) for c in lin.dependent_coordinates) or "none")
                     + "; dependent speeds: " + (", ".join(n.symbol(c) for c in lin.dependent_speeds) or "none"))
        lines.append(f"  ({lin.choice})")
    if lin.ignorable:
        lines.append("Ignorable (zero columns of A): " + ", ".join(n.symbol(c) for c in lin.ignorable))
    inputs = ", ".join(n.symbol(u) for u in lin.inputs) or "none"
    lines += [f"State x = {_vector(n, lin.state)}; inputs u = ({inputs})", ""]
    so = lin.second_order
    if so is not None:
        lines.append(f"Second-order form, q = {_vector(n, so.coordinates, '')}:")
        lines.append("  M δq̈ + (D + G) δq̇ + (K + N) δq = B u   (D, K symmetric; G, N skew)")
        for key in ("M", "D", "G", "K", "N"):
            lines += _matrix(n, key, getattr(so, key))
        if so.B.cols:
            lines += _matrix(n, "B", so.B)
        lines.append("")
    elif lin.second_order_reason:
        lines += [f"No second-order form: {lin.second_order_reason}.", ""]
    lines.append("State space: ẋ = A x + B u")
    lines += _matrix(n, "A", lin.A)
    lines += _matrix(n, "B", lin.B) if lin.B.cols else ["  B: no input (--inputs NAME to add one)"]
    lines.append("")
    if stability is None:
        symbols = ", ".join(str(s) for s in lin.symbols)
        lines.append(f"Eigenvalues and stability: give values to {symbols} (drop --symbolic, or use "
                     f"`lagrangian modes ... --sweep {lin.symbols[0]}=a:b:step`).")
        return "\n".join(lines) + "\n"
    neutral = modes is not None and bool(modes.neutral)
    zero = modes.zero if modes is not None else None
    secular = zero is not None and zero.secular
    lam = np.asarray(stability.eigenvalues)
    if secular and zero is not None:
        lines.append("Eigenvalues of A: " + (_eigen_list(lam) + ", and " if lam.size else "")
                     + f"0, defective (Jordan blocks of sizes {', '.join(map(str, zero.blocks))} once "
                       "the ignorable coordinates are set aside)")
    else:
        lines.append(("Eigenvalues of A, the neutral ones (0) set aside: " if neutral else "Eigenvalues of A: ")
                     + _eigen_list(lam))
    if modes is not None and modes.neutral:
        lines.append("  set aside (eigenvalue 0):" if not secular else "  eigenvalue 0:")
        lines += [f"    {n.symbol(x) if x != 'momentum' else 'a momentum'}: {why}" for x, why in modes.neutral]
    if modes is not None and modes.pulsations:
        lines.append("Pulsations (K φ = ω² M φ): " + ", ".join(f"ω{_sub(k)} = {number(w)} rad/s"
                                                               for k, w in enumerate(modes.pulsations, 1)))
    lines.append(f"Stability: {stability.verdict} — {stability.reason}")
    return "\n".join(lines) + "\n"


_SUBSCRIPTS = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


def _sub(k: int) -> str:
    return str(k).translate(_SUBSCRIPTS)


def _pairs(lam: np.ndarray) -> list[tuple[complex, bool]]:
    """Eigenvalues with each conjugate pair written once: (λ with Im λ ≥ 0, is a pair)."""
    out: list[tuple[complex, bool]] = []
    used = [False] * len(lam)
    scale = max(1.0, float(np.abs(lam).max(initial=0.0)))
    for i, z in enumerate(lam):
        if used[i]:
            continue
        used[i] = True
        if abs(z.imag) > 1e-12 * scale:
            for j in range(i + 1, len(lam)):
                if not used[j] and abs(lam[j] - np.conj(z)) <= 1e-9 * scale:
                    used[j] = True
                    out.append((complex(z.real, abs(z.imag)), True))
                    break
            else:
                out.append((complex(z), False))
        else:
            out.append((complex(z), False))
    return out


def _eigen_list(lam: np.ndarray) -> str:
    if lam.size == 0:
        return "none (every direction is neutral)"
    return ", ".join(eigenvalue(z, pair=p) for z, p in _pairs(lam))


def modes_text(lin: LinearModel, stability: Stability | None = None, modes: Modes | None = None,
               **values: float) -> str:
    """What ``lagrangian modes`` prints: the essential modes, the conservative pulsations, the verdict.

    The essential eigenvalues come with ω, T, ζ and mode shapes.

    Parameters
    ----------
    lin : LinearModel
        From `lagrangian.linearize`.
    stability : Stability, optional
        ``lin.stability(**values)``, computed here when not given.
    modes : Modes, optional
        ``lin.modes(**values)``, computed here when not given.
    **values : float
        The parameters ``lin`` keeps symbolic, when ``stability`` or ``modes`` is computed here.

    Returns
    -------
    str
        The text.
    """
    stability = lin.stability(**values) if stability is None else stability
    modes = lin.modes(**values) if modes is None else modes
    n = _notation(lin)
    model = lin.eom.model
    lines = [f"{model.name} — modes about {'a steady motion' if lin.steady else 'an equilibrium'}",
             f"Point: {_point_text(n, lin)}"]
    if lin.values:
        lines.append("Values: " + ", ".join(f"{n.symbol(k)} = {number(v)}" for k, v in lin.values.items()))
    lines += [f"State x = {_vector(n, lin.state)}; essential motion: {_vector(n, modes.essential)}", ""]
    if modes.neutral:
        lines.append("Set aside (eigenvalue 0):" if not (modes.zero is not None and modes.zero.secular)
                     else "Eigenvalue 0 (defective: see the verdict):")
        lines += [f"  {n.symbol(x) if x != 'momentum' else 'a momentum'}: {why}" for x, why in modes.neutral]
        lines.append("")
    lines.append("Eigenvalues λ, natural frequency ω = |λ|, damping ratio ζ = −Re λ/|λ|, period T = 2π/|Im λ|:")
    if not modes.modes:
        lines.append("  none but 0 (defective)" if modes.zero is not None and modes.zero.secular
                     else "  none: every direction is neutral")
    seen: list[complex] = []
    k = 0
    for mode in modes.modes:
        z = mode.eigenvalue
        if z.imag != 0 and any(abs(z.conjugate() - s) <= 1e-9 * max(1.0, abs(z)) for s in seen):
            continue  # its conjugate is written
        seen.append(z)
        k += 1
        pair = abs(z.imag) > 1e-12 * max(1.0, abs(z))
        lam = eigenvalue(complex(z.real, abs(z.imag)), pair=pair)
        period = f"T = {number(mode.period)} s" if mode.period else "aperiodic"
        zeta = 0.0 if abs(mode.damping_ratio) < 1e-12 else mode.damping_ratio  # rounding of a pure imaginary λ
        lines.append(f"  λ{_sub(k)} = {lam}:  ω = {number(mode.frequency)} rad/s, ζ = {number(zeta)}, "
                     f"{period}")
        shape = ", ".join(f"{n.symbol(x)}: {_shape(v)}" for x, v in mode.shape.items() if not x.endswith("_dot"))
        lines.append(f"      shape: {shape}")
    if modes.pulsations:
        lines += ["", "Pulsations of the conservative system (det(K − ω² M) = 0):"]
        for k, (w, phi) in enumerate(zip(modes.pulsations, modes.shapes or (), strict=True), 1):
            big = max(phi.values(), key=abs, default=1.0) or 1.0  # the largest component becomes +1
            shape = ", ".join(f"{n.symbol(x)}: {number(v / big)}" for x, v in phi.items())
            period = f", T = {number(2 * math.pi / w)} s" if w > 0 else ""
            lines.append(f"  ω{_sub(k)} = {number(w)} rad/s{period};  φ{_sub(k)} = ({shape})")
    lines += ["", f"Stability: {stability.verdict} — {stability.reason}"]
    return "\n".join(lines) + "\n"


def _shape(v: complex) -> str:
    """A mode-shape component: real when it is (up to rounding), else modulus ∠ phase."""
    scale = max(abs(v), 1e-300)
    if abs(v.imag) <= 1e-9 * max(scale, 1.0):
        return number(v.real)
    return f"{number(abs(v))} ∠ {math.degrees(math.atan2(v.imag, v.real)):.4g}°"


#: What each kind of change in a sweep means, in words.
_CHANGES = {"stability lost": "stability lost (an eigenvalue crosses into Re λ > 0)",
            "stability gained": "stability gained (the last eigenvalue with Re λ > 0 crosses back)",
            "eigenvalues become complex": "two real eigenvalues merge and become a complex pair",
            "eigenvalues become real": "a complex pair meets the real axis and becomes two real eigenvalues",
            "becomes asymptotically stable": "becomes asymptotically stable (every Re λ < 0)",
            "asymptotic stability lost": "asymptotic stability lost (an eigenvalue reaches the imaginary axis)"}


def sweep_text(lin: LinearModel, sweep: Sweep, unit: str = "") -> str:
    """What ``lagrangian modes --sweep`` adds: where stability changes along the sweep, and each verdict's ranges.

    Parameters
    ----------
    lin : LinearModel
        The linearization swept.
    sweep : Sweep
        From `lagrangian.analysis.eigenvalue_sweep`.
    unit : str, optional
        The parameter's unit.

    Returns
    -------
    str
        The text.
    """
    n = _notation(lin)
    p = n.symbol(sweep.parameter)
    values = np.asarray(sweep.values, dtype=float)
    u = f" {unit}" if unit else ""
    lines = ["", f"Sweep of {p} from {number(values[0])} to {number(values[-1])}{u} ({len(values)} values):"]
    if not sweep.changes:
        lines.append("  no change of stability or of the eigenvalues' nature in this range")
    for c in sweep.changes:
        lines.append(f"  {p} = {c.value:.12g}{u}: {_CHANGES.get(c.kind, c.kind)}")
    stable = np.asarray(sweep.stable, dtype=float)
    ranges = _ranges(values, stable)
    if ranges:
        lines.append("Verdict on the grid: " + "; ".join(f"{what} for {p} in [{number(a)}, {number(b)}]"
                                                         for what, a, b in ranges))
    return "\n".join(lines) + "\n"


def _ranges(values: np.ndarray, stable: np.ndarray) -> list[tuple[str, float, float]]:
    names = {1.0: "every Re λ < 0 (asymptotically stable)", 0.0: "some Re λ > 0 (unstable)"}
    out: list[tuple[str, float, float]] = []
    for x, s in zip(values, stable, strict=True):
        what = "largest Re λ = 0" if math.isnan(s) else names[float(s)]
        if out and out[-1][0] == what:
            out[-1] = (what, out[-1][1], float(x))
        else:
            out.append((what, float(x), float(x)))
    return out
