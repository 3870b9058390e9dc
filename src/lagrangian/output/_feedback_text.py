"""An LQR state feedback as terminal text: what ``lagrangian lqr`` prints, for library users too (`feedback_text`).

The law u = u* − K (x − x*), the point x* and the inputs u* that hold it, K row by row, the
weights Q and R, the eigenvalues of A and of A − B K and the verdict.  The numbers come from
`lagrangian.analysis.lqr` (its `Feedback`); this module only writes them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..analysis import Feedback

__all__ = ["feedback_text"]


def _number(v: float) -> str:
    """6 significant digits, 0 written 0."""
    return f"{v:.6g}" if v != 0 else "0"


def _complex(z: complex) -> str:
    """``-0.765745 +0.489942i``, or the real part alone where the imaginary one is rounding."""
    return _number(z.real) if abs(z.imag) < 1e-12 * max(1.0, abs(z)) else f"{z.real:.6g} {z.imag:+.6g}i"


def feedback_text(fb: Feedback) -> str:
    """What ``lagrangian lqr`` prints: the feedback ``fb`` made by `lagrangian.analysis.lqr`.

    The point x*, the inputs u*, the gain K of u = u* − K (x − x*) row by row (one row per input,
    one entry per state), the weights (``diag(...)`` when Q and R are diagonal, else the matrices),
    the eigenvalues of A (open loop) and of A − B K (closed loop), by increasing real part, and
    the verdict on the closed loop.

    Parameters
    ----------
    fb : Feedback
        From `lagrangian.analysis.lqr` (or `Feedback.load`).

    Returns
    -------
    str
        The text, ending with a newline.

    Examples
    --------
    >>> import lagrangian
    >>> eom = lagrangian.derive(lagrangian.load_model("examples/inverted_pendulum_cart.toml"))  # doctest: +SKIP
    >>> print(lagrangian.output.feedback_text(lagrangian.lqr(eom, {"x": 0, "theta": 0})))       # doctest: +SKIP
    """
    lines = [f"{fb.model}: LQR state feedback u = u* - K (x - x*)",
             "point x*: " + ", ".join(f"{s} = {_number(v)}" for s, v in zip(fb.states, fb.x_star, strict=True)),
             "inputs u*: " + ", ".join(f"{u} = {_number(v)}" for u, v in zip(fb.inputs, fb.u_star, strict=True)),
             "gain K:"]
    width = max(len(s) for s in fb.states)
    for i, u in enumerate(fb.inputs):
        lines.append(f"  row of {u}:")
        lines += [f"    {s:<{width}}  {_number(k)}" for k, s in zip(fb.K[i], fb.states, strict=True)]
    diag = np.allclose(fb.Q, np.diag(np.diag(fb.Q))) and np.allclose(fb.R, np.diag(np.diag(fb.R)))
    if diag:
        q = ", ".join(f"{s}: {_number(v)}" for s, v in zip(fb.states, np.diag(fb.Q), strict=True))
        r = ", ".join(f"{u}: {_number(v)}" for u, v in zip(fb.inputs, np.diag(fb.R), strict=True))
        lines.append(f"weights: Q = diag({q}), R = diag({r})")
    else:
        lines.append(f"weights: Q = {np.array2string(fb.Q, precision=6)}, R = {np.array2string(fb.R, precision=6)}")
    open_loop = np.linalg.eigvals(fb.A)
    lines.append("open-loop eigenvalues (A): " + ", ".join(_complex(z) for z in sorted(open_loop, key=lambda z: z.real)))
    lines.append("closed-loop eigenvalues (A - B K): "
                 + ", ".join(_complex(z) for z in sorted(fb.eigenvalues, key=lambda z: z.real)))
    lines.append("verdict: " + ("the closed loop is asymptotically stable about the point (linearized)" if fb.stable
                                else "NOT stable"))
    return "\n".join(lines) + "\n"
