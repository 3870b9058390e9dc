"""`identify`: parameters of a model fitted to a measured motion, by the regressor or by simulation.

Two routes (`Identification.route`):

``"regressor"``
    when every coordinate is measured and the equations are linear in the parameters fitted
    (a robot's masses, first moments and inertias; a damping coefficient; a stiffness): linear
    least squares on Y(q, q̇, q̈, u) θ = −r₀ (`_linear`, `_regressor`), its base parameters
    (the identifiable combinations) by QR with column pivoting (`_base`).
``"shooting"``
    otherwise (a length, a parameter inside a sine, only some coordinates measured): nonlinear
    least squares on simulated motions, single or multiple shooting, the Jacobian from the
    forward sensitivities (`_shooting`).

``route="auto"`` (the default) takes the regressor when it applies.  Both return an
`Identification`: ``fit["l"]``, ``fit.std["l"]``, ``fit.base``, ``fit.residuals``, ``fit.covariance``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ..dynamics import EquationsOfMotion, derive
from ..errors import IdentificationError, SimulationError
from ..model import load_model
from ..model.spec import Model
from ..model.urdf import load_urdf
from ._data import Measurements, read_measurements
from ._filter import SavitzkyGolay
from ._regressor import built_for
from ._result import Identification
from ._shooting import Shooting

__all__ = ["DEFICIENT", "ROUTES", "identify"]

ROUTES = ("auto", "regressor", "shooting")
#: The default derivative filter and shooting options (frozen values, shared).
DEFAULT_DERIVATIVES = SavitzkyGolay()
DEFAULT_SHOOTING = Shooting()
#: What to do when the parameters are identifiable only in combinations: refuse (naming them), or
#: estimate the combinations (the base parameters).
DEFICIENT = ("error", "base")


def identify(
    source,
    data,
    parameters: Sequence[str],
    *,
    route: str = "auto",
    values: Mapping[str, float] | None = None,
    inputs: Mapping[str, float] | None = None,
    guess: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    initial: Mapping[str, float] | None = None,
    columns: Sequence[str] | None = None,
    noise: Mapping[str, float] | None = None,
    derivatives: SavitzkyGolay = DEFAULT_DERIVATIVES,
    shooting: Shooting = DEFAULT_SHOOTING,
    deficient: str = "error",
    seed: int = 0,
) -> Identification:
    """Fit ``parameters`` of a model to a measured motion (module docstring).

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion
        A model file (TOML, or URDF: read with its links' inertial parameters as parameters,
        `load_urdf(..., inertial_parameters=True)`), a `Model` or an `EquationsOfMotion`.
    data : Trajectory or xarray.Dataset or str or Path or dict
        The measurements: a `Trajectory`, an ``xarray.Dataset``, a CSV file or a dict of arrays, keyed
        by ``t`` and the measured coordinates (``theta``), rates (``theta_dot``), accelerations
        (``theta_ddot``) and inputs (`lagrangian.identification.read_measurements`).
    parameters : sequence of str
        The names to fit.
    route : {"auto", "regressor", "shooting"}, optional
        How to fit.
    values : mapping of str to float, optional
        Values of the parameters not fitted (default the model's).
    inputs : mapping of str to float, optional
        Constant values of inputs that the data does not hold (an input acting on the model must be
        measured or given here).
    guess : mapping of str to float, optional
        First values of the fitted parameters for shooting (default the model's).
    bounds : mapping of str to (float, float), optional
        Name → (lower, upper) for shooting (default: the declared signs, e.g. positive).
    initial : mapping of str to float, optional
        First values of unmeasured initial coordinates and rates for shooting (default the model's
        initial state).
    columns : sequence of str, optional
        The data columns to use (default all).
    noise : mapping of str to float, optional
        Measured column → its noise standard deviation (shooting; default estimated).
    derivatives : SavitzkyGolay, optional
        How q̇ and q̈ are estimated from q for the regressor.
    shooting : Shooting, optional
        Segments, tolerances and evaluations of the shooting route.
    deficient : {"error", "base"}, optional
        ``"error"`` (default) refuses parameters identifiable only in combinations, naming the
        combinations; ``"base"`` estimates the combinations (the base parameters).
    seed : int, optional
        Seed of the random states that find the base parameters.

    Returns
    -------
    Identification
        The estimates, their standard errors and covariance, the residuals.

    Raises
    ------
    IdentificationError
        Unreadable data (a NaN, times that do not increase, unknown columns), an unknown parameter
        or one that is an input, an input neither measured nor given, an unidentifiable set
        (naming the identifiable combinations), a route that does not apply, a record that does
        not excite the parameters.

    Examples
    --------
    >>> fit = lagrangian.identify("pendulum.toml", "swing.csv", ["l"])   # doctest: +SKIP
    >>> fit["l"], fit.std["l"]                                             # doctest: +SKIP
    (0.4998, 0.0003)
    """
    if route not in ROUTES:
        raise IdentificationError(f"Unknown route `{route}`.", fix="use one of " + ", ".join(ROUTES))
    if deficient not in DEFICIENT:
        raise IdentificationError(f"deficient={deficient!r} is not one of {', '.join(DEFICIENT)}.",
                                  fix="deficient='error' (refuse) or 'base' (estimate the combinations)")
    eom = _equations(source)
    model = eom.model
    if model.constraints:
        raise IdentificationError(
            f"`{model.name}` keeps complementary constraints (a differential-algebraic system), which identify "
            "does not fit yet.", fix="describe the system with principal coordinates only (the constraints solved)")
    fitted = _fitted(model, parameters)
    meas = read_measurements(data, model, columns=columns)
    base = _values(model, fitted, meas, values, inputs)
    rng = np.random.default_rng(seed)
    names = [p.name for p in model.parameters]
    all_measured = all(c in meas.states for c in eom.coordinates)
    if route != "shooting" and all_measured:
        from ._linear import fit_regressor
        from ._regressor import regressor_of

        regressor = regressor_of(eom, fitted)
        p = np.array([base[name] if base[name] is not None else 1.0 for name in names])
        nonlinear = regressor.linear_in(p, rng)
        if not nonlinear:
            return fit_regressor(eom, meas, fitted, p, regressor, derivatives=derivatives, deficient=deficient,
                                 rng=rng)
        if route == "regressor":
            raise IdentificationError(f"The equations of motion are not linear in {', '.join(nonlinear)}, so the "
                                      "regressor does not apply.",
                                      fix="fit by simulation (route='shooting'), or fit parameters the equations are "
                                          "linear in (e.g. m l² rather than l)")
    elif route == "regressor":
        missing = ", ".join(c for c in eom.coordinates if c not in meas.states)
        raise IdentificationError(f"The regressor needs every coordinate measured, and {missing} "
                                  f"{'is' if ',' not in missing else 'are'} not.", fix="use route='shooting'")
    return _shoot(eom, meas, fitted, base, guess, bounds, initial, noise, derivatives, shooting)


def _equations(source) -> EquationsOfMotion:
    if isinstance(source, EquationsOfMotion):
        return source
    if isinstance(source, (str, Path)):
        path = Path(source)
        model = load_urdf(path, inertial_parameters=True) if path.suffix.lower() == ".urdf" else load_model(path)
        return derive(model)
    if isinstance(source, Model):
        return derive(source)
    from ..numerics import CompiledSystem

    if isinstance(source, CompiledSystem):
        built_for(source.eom).setdefault("system", source)
        return source.eom
    raise IdentificationError(f"identify() takes a model file, a Model or an EquationsOfMotion, not a "
                              f"{type(source).__name__}.", fix="give the model the data was measured on")


def _fitted(model: Model, parameters: Sequence[str]) -> list[str]:
    if isinstance(parameters, str):
        parameters = [parameters]
    fitted = list(parameters)
    if not fitted:
        raise IdentificationError("No parameter to fit was given.", fix="name the parameters, e.g. ['m', 'l']")
    known = {p.name: p for p in model.parameters}
    for name in fitted:
        if fitted.count(name) > 1:
            raise IdentificationError(f"The parameter `{name}` is given twice.", fix="name each parameter once")
        if name not in known:
            hint = ""
            if model.source and str(model.source).lower().endswith(".urdf"):
                hint = "; a URDF's inertial parameters are named m_<link>, mx_<link>, ..., Izz_<link> " \
                       "(load_urdf(path, inertial_parameters=True))"
            raise IdentificationError(f"`{name}` is not a parameter of `{model.name}`{hint}.",
                                      fix="the parameters are " + ", ".join(p.name for p in model.parameters
                                                                             if not p.input))
        if known[name].input:
            raise IdentificationError(f"`{name}` is an input of `{model.name}`: it is measured, not fitted.",
                                      fix=f"give its samples as a column `{name}` of the data, and fit parameters")
    return fitted


def _values(model: Model, fitted: Sequence[str], meas: Measurements, values: Mapping[str, float] | None,
            inputs: Mapping[str, float] | None) -> dict[str, float | None]:
    """Every parameter's value (None for a fitted one without a value); inputs checked."""
    values, inputs = dict(values or {}), dict(inputs or {})
    known = {p.name: p for p in model.parameters}
    for name in values:
        if name not in known or known[name].input:
            raise IdentificationError(f"`{name}` (in values) is not a parameter of `{model.name}`.",
                                      fix="the parameters are " + ", ".join(p.name for p in model.parameters
                                                                             if not p.input))
        if name in fitted:
            raise IdentificationError(f"`{name}` is both fitted and given a value.",
                                      fix="give its first value as guess={...} instead")
    for name in inputs:
        if name not in known or not known[name].input:
            raise IdentificationError(f"`{name}` (in inputs) is not an input of `{model.name}`.",
                                      fix="the inputs are " + (", ".join(model.inputs) or "(none)"))
        if name in meas.inputs:
            raise IdentificationError(f"The input `{name}` is both measured and given a constant value.",
                                      fix="keep one of the two")
    out: dict[str, float | None] = {}
    for p in model.parameters:
        if p.input:
            if p.name in meas.inputs:
                out[p.name] = 0.0  # set sample by sample
            elif p.name in inputs:
                out[p.name] = float(inputs[p.name])
            else:
                raise IdentificationError(
                    f"The input `{p.name}` is neither in the measurements ({meas.source}) nor given.",
                    fix=f"add its samples as a column `{p.name}`, or give its constant value (inputs={{'{p.name}': 0}}, "
                        f"--input {p.name}=0)")
            continue
        value = values.get(p.name, model.parameter_values.get(p.name))
        if value is None and p.name not in fitted:
            raise IdentificationError(f"The parameter `{p.name}` has no value and is not fitted.",
                                      fix=f"give it (values={{'{p.name}': ...}}, --set {p.name}=...) or fit it")
        out[p.name] = None if value is None else float(value)
    return out


def _shoot(eom, meas, fitted, base, guess, bounds, initial, noise, derivatives, shooting) -> Identification:
    from ..numerics import CompiledSystem, control_block, sensitivity_system
    from ._shooting import fit_shooting, noise_levels

    model = eom.model
    guess = dict(guess or {})
    for name in guess:
        if name not in fitted:
            raise IdentificationError(f"`{name}` has a guess but is not fitted.", fix="fitted: " + ", ".join(fitted))
    theta0 = []
    for name in fitted:
        value = guess.get(name, base[name])
        if value is None:
            raise IdentificationError(f"The parameter `{name}` has no value to start the fit from.",
                                      fix=f"give a first guess (guess={{'{name}': ...}}, --guess {name}=...)")
        theta0.append(float(value))
    lower, upper = _bounds(model, fitted, bounds)
    # one compiled system per set of equations (and with it its sensitivity libraries): a second fit of
    # the same model generates nothing again
    built = built_for(eom)
    system = built.get("system")
    if system is None:
        system = built["system"] = CompiledSystem(eom)
    sens = sensitivity_system(system, fitted)
    numbers = {name: (v if v is not None else theta0[fitted.index(name)]) for name, v in base.items()}
    numbers.update({name: v for name, v in zip(fitted, theta0, strict=True)})
    p = system.parameter_vector({k: v for k, v in numbers.items() if k in system.parameters})
    segments = shooting.count(len(meas.t))
    from ._shooting import segment_bounds

    starts = segment_bounds(len(meas.t), segments)
    states = [*eom.coordinates, *(c + "_dot" for c in eom.coordinates)]
    rates = {}
    for c in eom.coordinates:
        if c in meas.states and c + "_dot" not in meas.states:
            rates[c + "_dot"] = derivatives.derivatives(meas.t, meas.states[c])[1] if len(meas.t) >= \
                derivatives.window else np.gradient(meas.states[c], meas.t)
    first = _initial(eom, meas, rates, initial)
    # a first simulation from the guess fills in what is not measured at the later segments' starts
    from ._shooting import input_tables

    ctl = control_block("dop853", float(meas.t[0]), float(meas.t[-1]), meas.t, shooting.rtol, shooting.atol, None,
                        None, 10_000_000, None, True)
    run = sens.run(p, first, [], meas.t, float(meas.t[-1]), ctl=ctl, inputs=input_tables(system, meas))
    simulated = run.y if len(run.t) == len(meas.t) else None
    y0 = np.empty((segments, len(states)))
    for s, i in enumerate(starts[:-1]):
        for k, name in enumerate(states):
            if name in meas.states:
                y0[s, k] = meas.states[name][i]
            elif name in rates:
                y0[s, k] = rates[name][i]
            elif s == 0 or simulated is None:
                y0[s, k] = first[k]
            else:
                y0[s, k] = simulated[i, k]
    sigma = _noise(meas, noise) or noise_levels(meas, derivatives)
    span = float(meas.t[-1] - meas.t[0]) / segments
    scale = np.empty(len(states))
    for k, name in enumerate(states):
        # the continuity defects are measured against the noise: a defect of CONTINUITY_WEIGHT⁻¹ σ costs
        # as much as a misfit of σ, so that the segments join far below what the data can see
        if name in sigma:
            scale[k] = sigma[name]
        elif name.endswith("_dot") and name[:-4] in sigma:
            scale[k] = sigma[name[:-4]] / span  # a rate's defect shifts the coordinate by about that over a segment
        else:
            column = simulated[:, k] if simulated is not None else np.array([first[k]])
            scale[k] = 1e-6 * (float(np.ptp(column)) + abs(float(first[k])) + 1e-300)
    try:
        return fit_shooting(system, sens, meas, fitted, p, np.array(theta0), y0, lower, upper, options=shooting,
                            noise=sigma, estimate_noise=noise is None, scale=scale)
    except SimulationError as exc:
        raise IdentificationError(f"A simulation failed during the fit: {exc.message}",
                                  fix="give better guesses or bounds (the parameters may have left the physical "
                                      "range)") from None


def _initial(eom: EquationsOfMotion, meas: Measurements, rates: Mapping[str, np.ndarray],
             initial: Mapping[str, float] | None) -> np.ndarray:
    """The first estimate of y(t0): measured, derived, given, or the model's."""
    initial = dict(initial or {})
    states = [*eom.coordinates, *(c + "_dot" for c in eom.coordinates)]
    for name in initial:
        if name not in states:
            raise IdentificationError(f"`{name}` (in initial) is neither a coordinate nor a rate.",
                                      fix="initial values are given for " + ", ".join(states))
    out = np.empty(len(states))
    coords = {c.name: c for c in eom.model.coordinates}
    for k, name in enumerate(states):
        if name in meas.states:
            out[k] = meas.states[name][0]
        elif name in rates:
            out[k] = rates[name][0]
        elif name in initial:
            out[k] = float(initial[name])
        else:
            c = coords[name[:-4]] if name.endswith("_dot") else coords[name]
            value = c.rate if name.endswith("_dot") else c.initial
            if value is None:
                raise IdentificationError(f"`{name}` is not measured and has no initial value to start from.",
                                          fix=f"give one (initial={{'{name}': ...}})")
            out[k] = float(value)
    return out


def _noise(meas: Measurements, noise: Mapping[str, float] | None) -> dict[str, float] | None:
    if noise is None:
        return None
    out = {}
    for name in meas.states:
        if name not in noise:
            raise IdentificationError(f"The noise level of the measured column `{name}` is not given.",
                                      fix="give every measured column's standard deviation, or none (estimated)")
        value = float(noise[name])
        if not (value > 0 and np.isfinite(value)):
            raise IdentificationError(f"The noise level of `{name}` is {value}: it must be a positive number.",
                                      fix="give its standard deviation")
        out[name] = value
    return out


def _bounds(model: Model, fitted: Sequence[str], bounds: Mapping[str, tuple[float, float]] | None
            ) -> tuple[np.ndarray, np.ndarray]:
    bounds = dict(bounds or {})
    lower = np.full(len(fitted), -np.inf)
    upper = np.full(len(fitted), np.inf)
    signs = {p.name: p.sign for p in model.parameters}
    for k, name in enumerate(fitted):
        sign = signs.get(name)
        if sign in ("positive", "nonnegative"):
            lower[k] = 0.0
        elif sign in ("negative", "nonpositive"):
            upper[k] = 0.0
    for name, pair in bounds.items():
        if name not in fitted:
            raise IdentificationError(f"`{name}` has bounds but is not fitted.", fix="fitted: " + ", ".join(fitted))
        low, high = (float(x) for x in pair)
        if not low < high:
            raise IdentificationError(f"The bounds of `{name}` ({low}, {high}) are reversed or empty.",
                                      fix="give (lower, upper) with lower < upper")
        k = list(fitted).index(name)
        lower[k], upper[k] = low, high
    return lower, upper
