"""`lqr`: the linear-quadratic regulator about an equilibrium or a steady motion.

About a point x* held by the inputs u* (`holding_inputs` where they are needed), the
linearization δẋ = A δx + B δu (`linearize`) and the weights Q ⪰ 0, R ≻ 0 define the cost

    J = ∫₀^∞ (δxᵀ Q δx + δuᵀ R δu) dt,

minimized by the state feedback δu = −K δx with K = R⁻¹ Bᵀ P, P the stabilizing solution of
the continuous algebraic Riccati equation

    Aᵀ P + P A − P B R⁻¹ Bᵀ P + Q = 0

(Kalman, Bol. Soc. Mat. Mexicana 5 (1960) 102–119; Anderson & Moore, *Optimal Control: Linear
Quadratic Methods*, §3.3).  It exists when (A, B) is stabilizable: every mode the inputs cannot
move (Popov–Belevitch–Hautus: wᵀ A = λ wᵀ and wᵀ B = 0) is asymptotically stable.  The law
applied to the nonlinear system is u = u* − K (x − x*(t)), a `Feedback`; about a steady motion the
coordinates that move advance along it, x*(t) = x* + ẋ* t.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..dynamics import EquationsOfMotion, derive
from ..model import load_model
from ..model.spec import Model
from ._feedback import ControlError, Feedback
from ._linear_model import LinearizationError
from ._linearize import holding_inputs, linearize

__all__ = ["lqr", "uncontrollable_modes", "weights"]

#: A mode is not moved by the inputs when the smallest singular value of [A − λI, B] is below this
#: fraction of the pair's scale (the PBH rank test in floating point).
PBH_RTOL = 1e-9


def _eom(source: Any) -> EquationsOfMotion:
    if isinstance(source, EquationsOfMotion):
        return source
    if isinstance(source, Model):
        return derive(source)
    if isinstance(source, (str, Path)):
        return derive(load_model(source))
    eom = getattr(source, "eom", None)  # a compiled system
    if isinstance(eom, EquationsOfMotion):
        return eom
    raise TypeError("lqr() takes a model file, a Model or an EquationsOfMotion")


def weights(value: Any, names: Sequence[str], what: str, *, definite: bool) -> np.ndarray:
    """A weight matrix from a matrix, a diagonal (sequence) or a dict by name (the identity elsewhere).

    Raises
    ------
    ControlError
        A shape that does not match ``names``, an unknown name, a matrix that is not symmetric,
        not finite, not positive semidefinite (``definite``: not positive definite).
    """
    k = len(names)
    if value is None:
        W = np.eye(k)
    elif isinstance(value, Mapping):
        W = np.eye(k)
        for name, v in value.items():
            if name not in names:
                raise ControlError(f"`{name}` in {what} is not one of its names ({', '.join(names)}).",
                                   fix=f"weight the names of {what}'s rows: " + ", ".join(names))
            W[names.index(name), names.index(name)] = _number(v, f"{what}[{name}]")
    else:
        try:
            a = np.array(value, dtype=float)
        except (TypeError, ValueError):
            raise ControlError(f"{what} must be numbers (a matrix, a diagonal or a dict by name).",
                               fix=f"e.g. {what}=np.diag([...]) or {what}={{'{names[0]}': 10}}") from None
        if a.ndim == 0 and k == 1:
            a = a.reshape(1)
        if a.ndim == 1 and a.shape == (k,):
            W = np.diag(a)
        elif a.shape == (k, k):
            W = a
        else:
            raise ControlError(f"{what} has shape {a.shape}; it must be {k}×{k}, or a diagonal of {k} numbers "
                               f"({', '.join(names)}).", fix=f"give one weight per name: {', '.join(names)}")
    if not np.all(np.isfinite(W)):
        raise ControlError(f"{what} holds a number that is not finite.", fix="give finite weights")
    if not np.allclose(W, W.T, rtol=1e-12, atol=1e-12 * max(1.0, float(np.abs(W).max()))):
        raise ControlError(f"{what} is not symmetric.", fix=f"give a symmetric {what} (only (W + Wᵀ)/2 counts)")
    W = (W + W.T) / 2
    w = np.linalg.eigvalsh(W)
    scale = max(1.0, float(np.abs(w).max(initial=0.0)))
    if definite and not w.min() > 1e-12 * scale:
        raise ControlError(f"{what} must be positive definite (its smallest eigenvalue is {w.min():.3g}): every "
                           "input must cost something, or the optimal gain is infinite.",
                           fix=f"give positive weights, e.g. {what}=1")
    if not definite and w.min() < -1e-12 * scale:
        raise ControlError(f"{what} must be positive semidefinite (its smallest eigenvalue is {w.min():.3g}): a "
                           "negative weight rewards moving away from the point.",
                           fix=f"give weights ≥ 0, e.g. {what}={{'{names[0]}': 10}}")
    return W


def _number(v: Any, what: str) -> float:
    if isinstance(v, bool):
        raise ControlError(f"{what} must be a number, not {v!r}.", fix="give a number")
    try:
        return float(v)
    except (TypeError, ValueError):
        raise ControlError(f"{what} must be a number, not {v!r}.", fix="give a number") from None


def uncontrollable_modes(A: np.ndarray, B: np.ndarray) -> list[tuple[complex, np.ndarray]]:
    """(λ, w) of each mode the inputs cannot move: wᵀ(A − λI) = 0 and wᵀB = 0 (the PBH test)."""
    n = A.shape[0]
    scale = max(1.0, float(np.linalg.norm(A, 2)), float(np.linalg.norm(B, 2)))
    out: list[tuple[complex, np.ndarray]] = []
    for lam in np.linalg.eigvals(A):
        if any(abs(lam - seen) < 1e-9 * scale for seen, _ in out):
            continue
        M = np.hstack([A - lam * np.eye(n), B.astype(complex)])  # wᴴ M = 0: w the left singular vector of σ_min
        u, s, _ = np.linalg.svd(M)
        if s[-1] < PBH_RTOL * scale:
            out.append((complex(lam), u[:, -1]))
    return out


def _describe(A: np.ndarray, lam: complex, w: np.ndarray, states: Sequence[str]) -> str:
    """The states the mode moves: those of its left eigenvector w (what the inputs cannot reach) and of
    its right eigenvector (the motion itself; for a double λ = 0, a coordinate and its rate)."""
    v = np.linalg.svd(A - lam * np.eye(len(A)))[2][-1].conj()
    weight = np.maximum(np.abs(w) / np.abs(w).max(), np.abs(v) / np.abs(v).max())
    return ", ".join(s for s, a in zip(states, weight, strict=True) if a > 0.1)


def lqr(source: Any, at: Mapping[str, Any] | None = None, *, Q: Any = None, R: Any = None,
        inputs: Sequence[str] | None = None, parameters: Mapping[str, float] | None = None) -> Feedback:
    """The LQR state feedback u = u* − K (x − x*) about an equilibrium or a steady motion (module docstring).

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion
        A model file, a `Model` or an `EquationsOfMotion`.
    at : mapping of str to object, optional
        The point, as for `linearize` (every coordinate; rates 0 unless given; inputs' values u*
        optional); None: the model's ``[operating_point]``.  Inputs not given take the values that
        hold the point (`holding_inputs`) when the model keeps no constraint complementary (else 0).
    Q : array_like or mapping of str to float, optional
        The weight of δx: a matrix, a diagonal, or a dict by state name (the identity elsewhere);
        default the identity.
    R : array_like or mapping of str to float, optional
        The weight of δu, likewise by input name.
    inputs : sequence of str, optional
        The inputs u (default: the model's declared inputs).
    parameters : mapping of str to float, optional
        Parameter values overriding the model's; every parameter needs a value.

    Returns
    -------
    Feedback
        K, x*, u*, A, B, Q, R and the closed-loop eigenvalues (those of A − B K).

    Raises
    ------
    ControlError
        No input, a parameter without a value, bad weights, or a pair (A, B) that is not
        stabilizable (the mode the inputs cannot move is named).
    LinearizationError
        A point that is not an equilibrium or a steady motion that inputs can hold.

    Examples
    --------
    >>> fb = lqr("examples/inverted_pendulum_cart.toml", {"x": 0, "theta": 0}, Q={"theta": 10})  # doctest: +SKIP
    >>> fb.stable                                                                                # doctest: +SKIP
    True
    """
    from scipy.linalg import solve_continuous_are

    eom = _eom(source)
    model = eom.model
    inputs = tuple(model.inputs if inputs is None else inputs)
    if not inputs:
        raise ControlError(f"`{model.name}` declares no input, so there is nothing to feed back.",
                           fix="declare the actuators' magnitudes under [inputs] (e.g. F = { unit = \"N\" }) and "
                               "use them in loads")
    if at is None:
        at = dict(model.operating_point)
        if not at:
            raise LinearizationError("no point was given and the model has no [operating_point].",
                                     fix="give every coordinate a value, e.g. `at={'theta': 0}` (`--at theta=0`)")
    at = dict(at)
    held: dict[str, float] = {}
    if not eom.constraints and any(u not in at for u in inputs):
        held = holding_inputs(eom, at, parameters=parameters, inputs=inputs)
    lin = linearize(eom, {**at, **held}, parameters=parameters, inputs=inputs)
    if lin.symbols:
        names = ", ".join(str(s) for s in lin.symbols)
        raise ControlError(f"the parameters {names} have no value, so the gains cannot be computed.",
                           fix="give them values in the model file or with parameters= (--set NAME=VALUE)")
    A, B = lin.numeric()
    states = lin.state
    Qm = weights(Q, states, "Q", definite=False)
    Rm = weights(R, inputs, "R", definite=True)
    for lam, w in uncontrollable_modes(A, B):
        if lam.real >= -1e-9 * max(1.0, abs(lam)):
            raise ControlError(
                f"the pair (A, B) is not stabilizable: the mode λ = {_complex(lam)} (in {_describe(A, lam, w, states)}) is "
                f"not moved by the inputs {', '.join(inputs)} (wᵀB = 0 for its left eigenvector w) and does not "
                "decay by itself, so no feedback of these inputs can hold the point.",
                fix="act on that motion with another input, or linearize a model without the coordinates the "
                    "inputs cannot reach")
    try:
        P = solve_continuous_are(A, B, Qm, Rm)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ControlError(f"the Riccati equation has no stabilizing solution ({exc}).",
                           fix="weight every unstable motion in Q (a mode Q does not see is left as it is)") from None
    K = np.linalg.solve(Rm, B.T @ P)
    closed = np.linalg.eigvals(A - B @ K)
    if not np.all(closed.real < 0):
        worst = closed[np.argmax(closed.real)]
        raise ControlError(f"the LQR gain leaves the closed-loop eigenvalue {_complex(worst)}, not stable: Q does "
                           "not see an unstable motion.",
                           fix="weight every state in Q (Q positive definite, e.g. the identity)")
    point = lin.point
    x_star = np.array([float(point[name]) for name in states])
    u_star = np.array([float(point[u]) if u in point else 0.0 for u in inputs])
    # Along a steady motion the moving coordinates advance: x*(t) = x* + ẋ* t.
    rate = np.array([float(point.get(name + "_dot", 0.0)) if name in eom.coordinates else 0.0 for name in states])
    values = {k: float(v) for k, v in lin.values.items() if k not in inputs}
    return Feedback(model.name, states, inputs, K, x_star, u_star, A, B, Qm, Rm, closed, values, rate)


def _complex(z: complex) -> str:
    return f"{z.real:.6g}" if abs(z.imag) < 1e-12 * max(1.0, abs(z)) else f"{z.real:.6g} {z.imag:+.6g}i"
