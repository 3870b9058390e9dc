"""Identification through the regressor: weighted linear least squares on Y θ = −r₀.

At each sample the equations of motion give n equations Y(q, q̇, q̈, u) θ + r₀ = 0
(`_regressor`); stacked over the record, θ is their least-squares solution.  The steps
(Gautier, *J. Robot. Syst.* 8, 1991; Khalil & Dombre 2002, §12.4):

1. q̇ and q̈ where they are not measured: local polynomial derivatives of q (`_filter`), the
   ends of the record (half a window each) left out;
2. the base parameters (`_base`), from Y at random states (what the model can identify,
   whatever the record): an unidentifiable set is refused, naming the combinations, unless the
   combinations themselves are asked for (``deficient="base"``);
3. ordinary least squares on the base columns, then each coordinate's equations weighted by
   1/σ_i, σ_i the standard deviation of its residuals (the equations of a heavy joint and of a
   light one do not have the same error), and solved again;
4. the covariance σ̂² (Y_wᵀ Y_w)⁻¹ of the weighted problem, σ̂² = ‖r_w‖² / (m − r).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..dynamics import EquationsOfMotion
from ..errors import IdentificationError
from ._base import BaseParameters, base_parameters
from ._data import Measurements
from ._filter import SavitzkyGolay
from ._regressor import Regressor
from ._result import BaseEstimate, Identification

__all__ = ["CONDITION_LIMIT", "fit_regressor", "sample_arrays"]

#: A weighted base regressor of the record with a larger condition number than this does not
#: determine the combinations: the motion did not excite them.
CONDITION_LIMIT = 1e10
#: Random states used to find the base parameters (per parameter).
STATES_PER_PARAMETER = 6


def sample_arrays(eom: EquationsOfMotion, meas: Measurements, derivatives: SavitzkyGolay
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[str]]:
    """(indices kept, y (N, 2n), q̈ (N, n), t, notes): the states and accelerations at the samples.

    Raises
    ------
    IdentificationError
        When a coordinate is not measured (the regressor needs every q).
    """
    coords = list(eom.coordinates)
    missing = [c for c in coords if c not in meas.states]
    if missing:
        raise IdentificationError(
            f"The regressor needs every coordinate measured, and `{missing[0]}` is not ({meas.source}).",
            fix="measure it, or fit by simulation (route='shooting'), which takes any subset of the coordinates")
    N, n = len(meas.t), len(coords)
    q = np.column_stack([meas.states[c] for c in coords])
    qd = np.empty((N, n))
    qdd = np.empty((N, n))
    derived = []
    for i, c in enumerate(coords):
        if c in meas.accelerations and c + "_dot" in meas.states:
            qd[:, i], qdd[:, i] = meas.states[c + "_dot"], meas.accelerations[c]
            continue
        if c + "_dot" in meas.states:
            qd[:, i] = meas.states[c + "_dot"]
            qdd[:, i] = derivatives.derivatives(meas.t, qd[:, i])[1]
            derived.append(f"{c}_ddot")
        else:
            _, qd[:, i], qdd[:, i] = derivatives.derivatives(meas.t, q[:, i])
            derived.append(f"{c}_dot, {c}_ddot")
        if c in meas.accelerations:
            qdd[:, i] = meas.accelerations[c]
    notes = []
    keep = np.arange(N)
    if derived:
        trim = derivatives.trim
        keep = keep[trim: N - trim]
        notes.append(f"{'; '.join(derived)} estimated by local polynomial fits (Savitzky-Golay, window "
                     f"{derivatives.window}, order {derivatives.order}); the first and last {trim} samples left out")
        # Least squares assumes the regressor Y(q, q̇, q̈) exact and the error in τ only; noise in the
        # derivatives enters Y itself (errors in variables), which biases the estimates, more as the noise
        # grows against the motion.  Shooting compares the motion itself and has no such bias.
        notes.append("the regressor is built from these estimates: noise in them biases the least-squares fit "
                     "(errors in variables); with noisy records, check against route='shooting' "
                     "(--route shooting)")
    return keep, np.hstack([q, qd]), qdd, meas.t, notes


def parameter_matrix(parameters: Sequence[str], base: np.ndarray, meas: Measurements, rows: np.ndarray
                     ) -> np.ndarray:
    """The parameter vector of each sample of ``rows``: ``base`` with the measured inputs' samples set."""
    P = np.tile(base, (len(rows), 1))
    for name, values in meas.inputs.items():
        P[:, parameters.index(name)] = values[rows]
    return P


def fit_regressor(eom: EquationsOfMotion, meas: Measurements, fitted: Sequence[str], values: np.ndarray,
                  regressor: Regressor, *, derivatives: SavitzkyGolay, deficient: str,
                  rng: np.random.Generator) -> Identification:
    """Fit ``fitted`` to ``meas`` by the regressor (module docstring); ``values``: every parameter's value
    (θ's entries a reference point, inputs not measured at their constant)."""
    keep, y, qdd, t, notes = sample_arrays(eom, meas, derivatives)
    names = list(regressor.parameters)
    theta0 = np.array([values[names.index(f)] for f in fitted])
    P = parameter_matrix(names, values, meas, keep)
    r, Y = regressor.evaluate(t[keep], y[keep], qdd[keep], P)
    r0 = r - np.einsum("nij,j->ni", Y, theta0)
    n = regressor.n
    # Y θ = −r₀ with r₀ ≡ 0 is solved by θ = 0: nothing sets the parameters' scale (a free motion determines
    # masses only up to a common factor, without a known force or a known mass)
    if not np.abs(r0).max(initial=0.0) > 1e-10 * np.abs(r).max(initial=0.0):
        raise IdentificationError(
            f"The equations are homogeneous in {', '.join(fitted)}: with nothing else in them (no measured input, "
            "no known mass, spring or weight acting), the motion determines these parameters only up to a common "
            "factor.", fix="measure an input (a force, a torque) or keep a parameter known (values={...}) to set "
                           "the scale, or fit ratios (e.g. g/l) instead")
    base = structural_base(regressor, fitted, values, y[keep], meas, keep, rng)
    if not base.full and deficient != "base":
        raise unidentifiable(base)
    cols = list(base.independent)
    K = base.matrix()
    A = Y[:, :, cols]  # (N, n, r): the base regressor of the record
    b = -r0
    # 1. ordinary least squares, 2. each coordinate's equations weighted by its residuals' spread
    theta_b, *_ = np.linalg.lstsq(A.reshape(-1, len(cols)), b.reshape(-1), rcond=None)
    resid = b - A @ theta_b
    sigma = np.sqrt(np.mean(resid ** 2, axis=0))
    sigma = np.where(sigma > 0, sigma, max(float(sigma.max(initial=0.0)), 1e-300))
    Aw = (A / sigma[None, :, None]).reshape(-1, len(cols))
    bw = (b / sigma[None, :]).reshape(-1)
    condition = float(np.linalg.cond(Aw)) if len(cols) else 1.0
    if not condition < CONDITION_LIMIT:
        raise IdentificationError(
            f"The record does not excite every identifiable combination: the weighted regressor's condition "
            f"number is {condition:.2e} (above {CONDITION_LIMIT:.0e}).",
            fix="use a richer motion (larger, faster, with every joint moving), or fit fewer parameters")
    theta_b, *_ = np.linalg.lstsq(Aw, bw, rcond=None)
    resid_w = bw - Aw @ theta_b
    dof = max(len(bw) - len(cols), 1)
    s2 = float(resid_w @ resid_w) / dof
    cov = s2 * np.linalg.inv(Aw.T @ Aw)
    std_b = np.sqrt(np.diag(cov))
    residuals = (b - A @ theta_b)
    estimates, std, combos = {}, {}, []
    for k, j in enumerate(cols):
        coefficients = {fitted[i]: float(K[k, i]) for i in np.flatnonzero(K[k])}
        combos.append(BaseEstimate(base.combination(k), coefficients, float(theta_b[k]), float(std_b[k])))
        if len(coefficients) == 1:
            estimates[fitted[j]] = float(theta_b[k])
            std[fitted[j]] = float(std_b[k])
    eq_names = tuple(f"{c} equation" for c in eom.coordinates)
    return Identification(
        model_name=eom.model.name, route="regressor", parameters=tuple(fitted), estimates=estimates, std=std,
        base=tuple(combos), covariance=cov, covariance_names=tuple(b.text for b in combos), t=t[keep],
        residuals=residuals, residual_names=eq_names,
        sigma={name: float(np.sqrt(np.mean(residuals[:, i] ** 2))) for i, name in enumerate(eq_names)},
        status="converged" if base.full else f"rank deficient: {base.rank} identifiable combinations of "
                                             f"{len(fitted)} parameters",
        iterations=2, condition=condition, notes=tuple(notes) + ((f"{len(keep)} samples × {n} equations",)))


def structural_base(regressor: Regressor, fitted: Sequence[str], values: np.ndarray, y: np.ndarray,
                    meas: Measurements, rows: np.ndarray, rng: np.random.Generator) -> BaseParameters:
    """The base parameters of the model (not of the record): Y at configurations of the record with
    random rates and accelerations, so that what the motion happened not to excite is not mistaken for
    what the equations cannot show."""
    n = regressor.n
    count = max(STATES_PER_PARAMETER * len(fitted) // max(n, 1), 8)
    pick = rng.integers(0, len(rows), count)
    states = y[pick].copy()
    scale = np.maximum(np.std(y[:, n:], axis=0), 1.0)
    states[:, n:] = rng.normal(size=(count, n)) * scale
    states[:, :n] += rng.normal(scale=1e-3, size=(count, n))
    a = rng.normal(size=(count, n)) * scale
    P = parameter_matrix(list(regressor.parameters), values, meas, rows[pick])
    _, Y = regressor.evaluate(0.0, states, a, P)
    return base_parameters(Y.reshape(-1, len(fitted)), fitted)


def unidentifiable(base: BaseParameters) -> IdentificationError:
    """The error of a parameter set that the equations determine only in combinations."""
    names = base.names
    alone = base.alone()
    lost = [names[j] for j in base.zero]
    combos = [c for c in base.combinations() if c not in alone]
    parts = []
    if lost:
        parts.append(f"{', '.join(f'`{x}`' for x in lost)} {'does' if len(lost) == 1 else 'do'} not act on the motion")
    if combos:
        parts.append("the identifiable combinations are " + "; ".join(f"`{c}`" for c in combos))
    return IdentificationError(
        f"The parameters {', '.join(names)} are not all identifiable (rank {base.rank} of {len(names)}): "
        + "; ".join(parts) + (f"; identifiable on their own: {', '.join(alone)}" if alone else "") + ".",
        fix="fit the combinations instead (deficient='base', --base), or fix the others at known values")


def values_vector(parameters: Sequence[str], values: Mapping[str, float]) -> np.ndarray:
    return np.array([float(values[name]) for name in parameters])
