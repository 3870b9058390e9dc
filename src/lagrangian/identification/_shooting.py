"""Identification by simulation: nonlinear least squares on the measured motion, single or multiple shooting.

The unknowns are the parameters θ and the state x_s = y(t_s) at the start of each of S
segments of the record (S = 1: single shooting).  Each segment is simulated from x_s with θ,
and the residuals are

    (y_k(t_i; θ, x_s) − ŷ_k(t_i)) / σ_k        for every measured column k and sample t_i,
    w (y(t_{s+1}⁻; θ, x_s) − x_{s+1}) / c       at each inner boundary (continuity),

σ_k the column's noise level, c each state's scale and w = `CONTINUITY_WEIGHT`: with the
segments tied by a stiff penalty, a long or unstable record (a pendulum over many periods, a
chaotic double pendulum) is fitted piece by piece and its defects vanish at the optimum (Bock
& Plitt, *IFAC* 1984; Bock, *Numerical treatment of inverse problems*, 1987).  The Jacobian is
exact: the forward sensitivities ∂y/∂θ and ∂y/∂x_s of each segment, integrated with it
(`lagrangian.numerics._sensitivity`).  `scipy.optimize.least_squares` (trust-region
reflective) minimizes; the covariance of the estimates is σ̂² (JᵀJ)⁻¹ at the optimum, with the
noise levels σ_k re-estimated from the residuals (Bard, *Nonlinear Parameter Estimation*, 1974,
§7-5).

Measured inputs enter the simulations by linear interpolation between their samples
(`input_tables`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import IdentificationError, SimulationError
from ..numerics import CompiledSystem, SensitivityColumn, SensitivitySystem, control_block
from ._data import Measurements
from ._filter import SavitzkyGolay
from ._result import BaseEstimate, Identification

__all__ = ["Shooting", "fit_shooting", "input_tables", "noise_levels"]

#: Weight of the continuity defects against the data residuals (each already divided by its scale).
CONTINUITY_WEIGHT = 1e3
#: Samples per segment below which multiple shooting does not cut the record further.
MIN_SEGMENT = 20
#: Most segments chosen automatically.
MAX_SEGMENTS = 20


@dataclass(frozen=True)
class Shooting:
    """How `identify` simulates the record.

    Parameters
    ----------
    segments : int, optional
        1: single shooting; None: about one per `MIN_SEGMENT` samples, at most `MAX_SEGMENTS`.
    rtol : float
        The integrator's relative tolerance.
    atol : float
        Its absolute tolerance.
    max_evaluations : int
        The most residual evaluations.
    """

    segments: int | None = None
    rtol: float = 1e-9
    atol: float = 1e-9
    max_evaluations: int = 200

    def count(self, samples: int) -> int:
        if self.segments is not None:
            if not (isinstance(self.segments, int) and 1 <= self.segments <= samples // 2):
                raise IdentificationError(f"segments = {self.segments!r}: it must be a whole number from 1 to half "
                                          f"the samples ({samples // 2}).", fix="e.g. segments=1 (single shooting)")
            return self.segments
        return int(min(max(samples // MIN_SEGMENT, 1), MAX_SEGMENTS))


def input_tables(system: CompiledSystem, meas: Measurements) -> tuple[list[int], np.ndarray, np.ndarray] | None:
    """The measured inputs as tables the compiled run interpolates linearly: (parameter indices, t, values).

    The one place where measured inputs reach a simulation: with tabulated inputs in `simulate`, this
    is what becomes an input table there.
    """
    if not meas.inputs:
        return None
    names = list(meas.inputs)
    index = [system.parameters.index(name) for name in names]
    return index, meas.t, np.column_stack([meas.inputs[name] for name in names])


def noise_levels(meas: Measurements, derivatives: SavitzkyGolay) -> dict[str, float]:
    """Each measured column's noise level, from its residuals about local polynomial fits.

    For white noise of standard deviation σ the residuals of a least-squares fit of degree d on w
    samples have variance σ² (1 − (d + 1)/w), hence the correction.  Floored at 1e-9 of the column's
    spread (a noise-free record would otherwise get an infinite weight).
    """
    out = {}
    count = len(meas.t)
    window = derivatives.window if count >= derivatives.window else count - (1 - count % 2)
    filt = SavitzkyGolay(window, max(min(derivatives.order, window - 2), 2))
    for name, values in meas.states.items():
        smooth = filt.derivatives(meas.t, values)[0]
        spread = float(np.std(values)) or 1.0
        sigma = float(np.std(values - smooth)) / np.sqrt(max(1 - (filt.order + 1) / filt.window, 0.1))
        out[name] = max(sigma, 1e-9 * spread)
    return out


class _Problem:
    """The residuals and the Jacobian of a multiple-shooting fit (module docstring)."""

    def __init__(self, system: CompiledSystem, sens: SensitivitySystem, meas: Measurements, fitted: Sequence[str],
                 p_base: np.ndarray, bounds: list[int], options: Shooting, sigma: Mapping[str, float],
                 scale: np.ndarray) -> None:
        self.system, self.sens, self.meas = system, sens, meas
        self.fitted = list(fitted)
        self.n2 = 2 * system.n
        self.P = len(fitted)
        self.p_base = p_base
        self.bounds = bounds  # sample index of each segment's start, then the last sample
        self.options = options
        self.states = [*system.coordinates, *(c + "_dot" for c in system.coordinates)]
        self.measured = [(self.states.index(name), name) for name in self.states if name in meas.states]
        self.sigma = dict(sigma)
        self.scale = scale  # each state's scale for the continuity defects
        self.columns = [SensitivityColumn(name, system.parameters.index(name), None) for name in fitted] + \
                       [SensitivityColumn(f"{s}(t0)", None, k) for k, s in enumerate(self.states)]
        self.tables = input_tables(system, meas)
        self.cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
        self.last_error: SimulationError | None = None

    @property
    def segments(self) -> int:
        return len(self.bounds) - 1

    def unpack(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return x[: self.P], x[self.P:].reshape(self.segments, self.n2)

    def parameter_vector(self, theta: np.ndarray) -> np.ndarray:
        values = {name: float(v) for name, v in zip(self.fitted, theta, strict=True)}
        p = self.p_base.copy()
        for name, v in values.items():
            p[self.system.parameters.index(name)] = v
        if len(p) > len(self.system.parameters):  # the hoisted constants follow the values
            self.system._lib.lg_constants(p.ctypes.data, p[len(self.system.parameters):].ctypes.data)
        return p

    def simulate(self, x: np.ndarray, *, sensitivities: bool = True) -> list:
        theta, starts = self.unpack(x)
        p = self.parameter_vector(theta)
        t = self.meas.t
        runs = []
        for s in range(self.segments):
            a, b = self.bounds[s], self.bounds[s + 1]
            last = s == self.segments - 1
            t_out = t[a: b + 1] if last else t[a: b]
            ctl = control_block("dop853", float(t[a]), float(t[b]), t_out, self.options.rtol, self.options.atol,
                                None, None, 10_000_000, None, True)
            run = self.sens.run(p, starts[s], self.columns if sensitivities else [], t_out, float(t[b]), ctl=ctl,
                                inputs=self.tables)
            if run.code != 0 or len(run.t) != len(t_out):
                raise SimulationError(f"the simulation of samples {a + 1} to {b + 1} stopped at t = {ctl[0]:.6g} "
                                      f"(status {run.code})", t=float(ctl[0]))
            runs.append(run)
        return runs

    def evaluate(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        key = x.tobytes()
        if key in self.cache:
            return self.cache[key]
        runs = self.simulate(x)
        _, starts = self.unpack(x)
        N, P, n2 = len(self.meas.t), self.P, self.n2
        k = len(self.measured)
        rows = N * k + (self.segments - 1) * n2
        r = np.empty(rows)
        J = np.zeros((rows, len(x)))
        for s, run in enumerate(runs):
            a = self.bounds[s]
            for c, (i, name) in enumerate(self.measured):
                sl = slice(a * k + c, (a + len(run.t)) * k + c, k)  # rows of column c at the segment's samples
                sigma = self.sigma[name]
                r[sl] = (run.y[:, i] - self.meas.states[name][a: a + len(run.t)]) / sigma
                J[sl, :P] = run.S[:, :P, i] / sigma
                J[sl, P + s * n2: P + (s + 1) * n2] = run.S[:, P:, i] / sigma
            if s < self.segments - 1:
                base = N * k + s * n2
                end = run.z[:n2]
                S_end = run.z[n2:].reshape(len(self.columns), n2)  # (columns, n2)
                w = CONTINUITY_WEIGHT / self.scale
                r[base: base + n2] = w * (end - starts[s + 1])
                J[base: base + n2, :P] = (w[:, None] * S_end[:P].T)
                J[base: base + n2, P + s * n2: P + (s + 1) * n2] = w[:, None] * S_end[P:].T
                J[base: base + n2, P + (s + 1) * n2: P + (s + 2) * n2] = -np.diag(w)
        if len(self.cache) > 4:
            self.cache.clear()
        self.cache[key] = (r, J)
        return r, J

    def residuals(self, x: np.ndarray) -> np.ndarray:
        try:
            return self.evaluate(x)[0]
        except SimulationError as exc:  # a trial step into a region the model cannot run: a bad step
            self.last_error = exc
            N, k = len(self.meas.t), len(self.measured)
            return np.full(N * k + (self.segments - 1) * self.n2, 1e8)

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        return self.evaluate(x)[1]


def segment_bounds(samples: int, segments: int) -> list[int]:
    """Sample indices where the segments start, then the last sample."""
    return [round(k * (samples - 1) / segments) for k in range(segments)] + [samples - 1]


def fit_shooting(system: CompiledSystem, sens: SensitivitySystem, meas: Measurements, fitted: Sequence[str],
                 p_base: np.ndarray, guess: np.ndarray, y0_guess: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                 *, options: Shooting, noise: Mapping[str, float], estimate_noise: bool, scale: np.ndarray
                 ) -> Identification:
    """Fit ``fitted`` (and the state at each segment's start) to ``meas`` (module docstring).

    ``y0_guess`` (S, 2n): a first estimate of the state at each segment's start; ``lower``/``upper``:
    bounds on θ; ``noise``: each measured column's standard deviation, re-estimated from the residuals
    when ``estimate_noise``; ``scale``: each state's scale for the continuity defects.
    """
    from scipy.optimize import least_squares

    N = len(meas.t)
    bounds = segment_bounds(N, len(y0_guess))
    sigma = dict(noise)
    problem = _Problem(system, sens, meas, fitted, p_base, bounds, options, sigma, scale)
    x0 = np.concatenate([guess, np.asarray(y0_guess).ravel()])
    free_lower = np.concatenate([lower, np.full(x0.size - len(guess), -np.inf)])
    free_upper = np.concatenate([upper, np.full(x0.size - len(guess), np.inf)])
    x0 = np.clip(x0, np.nextafter(free_lower, np.inf), np.nextafter(free_upper, -np.inf))
    try:
        problem.evaluate(x0)
    except SimulationError as exc:
        raise IdentificationError(f"The model cannot be simulated from the initial guess: {exc.message}.",
                                  fix="give a better guess (guess={...}, --guess NAME=VALUE) or check the data") from None
    total = 0
    for _ in range(2 if estimate_noise else 1):  # the second pass with the noise levels of the first's residuals
        sol = least_squares(problem.residuals, x0, jac=problem.jacobian, bounds=(free_lower, free_upper),
                            method="trf", x_scale="jac", ftol=1e-12, xtol=1e-12, gtol=1e-12,
                            max_nfev=options.max_evaluations)
        total += int(sol.nfev)
        x0 = sol.x
        if estimate_noise:
            r, _ = problem.evaluate(sol.x)
            k = len(problem.measured)
            data = r[: N * k].reshape(N, k)
            for c, (_, name) in enumerate(problem.measured):
                problem.sigma[name] = max(float(np.sqrt(np.mean((data[:, c] * problem.sigma[name]) ** 2))),
                                          1e-300)
            problem.cache.clear()
    r, J = problem.evaluate(sol.x)
    return _result(system, problem, sol, r, J, total)


def _result(system: CompiledSystem, problem: _Problem, sol, r: np.ndarray, J: np.ndarray,
            evaluations: int) -> Identification:
    meas, P, N = problem.meas, problem.P, len(problem.meas.t)
    k = len(problem.measured)
    data_rows = N * k
    dof = max(data_rows - J.shape[1] + (problem.segments - 1) * problem.n2, 1)
    s2 = float(r[:data_rows] @ r[:data_rows]) / dof
    theta, starts = problem.unpack(sol.x)
    typical = np.concatenate([np.where(theta != 0, np.abs(theta), 1.0), np.tile(problem.scale, problem.segments)])
    cov, condition, null = _covariance(J, s2, typical)
    std = np.sqrt(np.abs(np.diag(cov)))
    fitted = problem.fitted
    unidentified = [name for k, name in enumerate(fitted) if null[k]]
    if unidentified:
        raise IdentificationError(
            f"The record does not determine {', '.join(unidentified)}: the residuals do not change along some "
            f"combination of {'it' if len(unidentified) == 1 else 'them'} (and of the initial states) at the fit.",
            fix="fit fewer parameters (fix the others at known values), measure more of the state, or use a richer "
                "motion")
    hidden = [name for k, name in enumerate(problem.states) if null[P + k]]
    data = r[:data_rows].reshape(N, k)
    residuals = np.column_stack([data[:, c] * problem.sigma[name] for c, (_, name) in enumerate(problem.measured)])
    names_cov = tuple(fitted) + tuple(f"{s}(t{j})" for j in range(problem.segments) for s in problem.states)
    defects = r[data_rows:]
    notes = [(f"{problem.segments} segment{'s' if problem.segments > 1 else ''} "
              f"({'multiple' if problem.segments > 1 else 'single'} shooting), {evaluations} evaluations")]
    if len(defects):
        notes.append(f"largest continuity defect between segments {np.max(np.abs(defects)) / CONTINUITY_WEIGHT:.1e} "
                     "of the noise level")
    if meas.inputs:
        notes.append(f"inputs {', '.join(meas.inputs)} interpolated linearly between samples")
    if hidden:
        notes.append(f"{', '.join(hidden)} at t0 not determined by the record (the measured motion does not depend on "
                     "{}): kept at {}".format("it" if len(hidden) == 1 else "them",
                                             "its first value" if len(hidden) == 1 else "their first values"))
    status = "converged" if sol.status > 0 else f"not converged after {evaluations} evaluations ({sol.message})"
    return Identification(
        model_name=system.eom.model.name, route="shooting", parameters=tuple(fitted),
        estimates={name: float(v) for name, v in zip(fitted, theta, strict=True)},
        std={name: float(s) for name, s in zip(fitted, std[:P], strict=True)},
        base=tuple(BaseEstimate(name, {name: 1.0}, float(v), float(s)) for name, v, s in zip(fitted, theta, std[:P], strict=True)),
        covariance=cov, covariance_names=names_cov, t=meas.t, residuals=residuals,
        residual_names=tuple(name for _, name in problem.measured),
        sigma={name: float(np.sqrt(np.mean(residuals[:, c] ** 2))) for c, (_, name) in enumerate(problem.measured)},
        status=status, iterations=evaluations, condition=condition,
        initial={s: float(v) for s, v in zip(problem.states, starts[0], strict=True)}, notes=tuple(notes))


#: Singular values of the column-scaled Jacobian below this fraction of the largest are its null space.
NULL_TOLERANCE = 1e-10


def _covariance(J: np.ndarray, s2: float, typical: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
    """(σ̂² (JᵀJ)⁺, condition number, which unknowns the null space moves) from the SVD of J, columns scaled.

    A direction that the residuals do not see (the position of a cyclic coordinate that is not
    measured; a mass that cancels out of q̈) has no variance: its unknowns get no standard deviation
    (NaN), and the others the covariance of the directions that are seen.  ``typical``: each unknown's
    size, so that a column whose effect on the residuals, ‖J_k‖ × typical_k, is round-off counts as zero
    before the columns are scaled to unit norm.
    """
    norms = np.linalg.norm(J, axis=0)
    effect = norms * typical
    dead = effect <= 1e-9 * effect.max(initial=0.0)
    norms = np.where(dead | (norms == 0), 1.0, norms)
    live = np.flatnonzero(~dead)
    _, s, Vt = np.linalg.svd(J[:, live] / norms[live], full_matrices=False)
    keep = s > NULL_TOLERANCE * s[0]
    V = np.zeros((J.shape[1], int(keep.sum())))
    V[live] = Vt[keep].T / norms[live][:, None]
    cov = s2 * (V / s[keep] ** 2) @ V.T
    null = Vt[~keep]
    moved = dead.copy()
    if len(null):
        moved[live] |= np.abs(null).max(axis=0) > 1e-6
    cov[moved, :] = np.nan
    cov[:, moved] = np.nan
    condition = float(s[0] / s[keep][-1])
    return cov, condition, moved
