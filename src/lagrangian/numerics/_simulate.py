"""`simulate`: one entry for every model and method, as SciPy's ``solve_ivp`` is one entry for its methods.

`simulate` gathers its keywords into one `SimulationOptions` (checked once), reads the model
once, checks the declared signs of the parameters, lets the registry (`_methods.ROUTES`) pick
the route the model needs and runs it, then checks the motion against the declared ranges
(`_ranges`).  `simulate_contact` and `simulate_stick_slip` are the same entry with the route
named, and the keywords that only that route honours.

The routes are: the compiled ODE (`_ode`: DOP853 and Gauss–Legendre in C, SciPy's methods),
the constrained DAE with projection (`_dae_run`), exact Coulomb friction by stick/slip phases
(`_stickslip`), unilateral contacts by phases between impacts (`_contact`), free bodies on
unit quaternions (`_free_simulate`), and the sensitivities ∂y/∂x (`_sensitivity`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..dynamics import EquationsOfMotion, derive
from ..model import check_sign, load_model
from ..model.spec import Model
from ._control import CONTROL_SIZE, STIFFNESS_TEST_PERIOD, control_block
from ._methods import check_route_options, route_for
from ._options import BAUMGARTE, BUILTIN, METHODS, SCIPY, SimulationOptions, default_tolerance
from ._ranges import watch_ranges
from ._setup import EventSpec, initial_state
from ._stickslip import exact_contact_model
from ._trajectory import Trajectory

if TYPE_CHECKING:
    from ._sensitivity import Sensitivities

__all__ = ["BUILTIN", "CONTROL_SIZE", "METHODS", "SCIPY", "STIFFNESS_TEST_PERIOD", "EventSpec", "SimulationOptions",
           "control_block", "default_tolerance", "initial_state", "run", "simulate", "simulate_contact",
           "simulate_stick_slip"]


def simulate(
    source,
    t_end: float,
    *,
    t_start: float = 0.0,
    initial: Mapping[str, float] | None = None,
    parameters: Mapping[str, float] | None = None,
    method: str = "dop853",
    rtol: float = 1e-10,
    atol: float = 1e-10,
    dt: float | None = None,
    max_step: float | None = None,
    n_out: int | None = None,
    t_eval=None,
    events: Sequence[EventSpec | str] = (),
    tolerance: float | None = None,
    max_steps: int = 100_000_000,
    progress: bool | Callable[[float, float], None] = False,
    backend: str = "auto",
    stabilization: str | None = None,
    baumgarte: tuple[float, float] = BAUMGARTE,
    stiffness_check: bool = True,
    sensitivities: Sequence[str] | Sensitivities | None = None,
    inputs=None,
    rest: float | None = None,
    max_phases: int | None = None,
    max_switches: int | None = None,
) -> Trajectory:
    """Integrate the equations of motion from t_start to t_end.

    The options are checked once (`SimulationOptions`); the model picks its route from the
    registry (`_methods.ROUTES`: free bodies, unilateral contacts, exact Coulomb friction,
    complementary constraints, plain M q̈ = F), and an option its route cannot honour is
    refused with a `SimulationError` that names it.

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion or CompiledSystem
        A model file path, a `Model`, an `EquationsOfMotion` or a `CompiledSystem`.
    t_end : float
        The end of the time span.
    t_start : float, optional
        Its start (the span must increase).
    initial : mapping of str to float, optional
        Overrides of q_i(t0) (``"theta": 0.3``) and q̇_i(t0) (``"phi_dot": 80``).
    parameters : mapping of str to float, optional
        Overrides of the parameter values (``"g": 1.62``).
    method : str, optional
        ``"dop853"``, ``"gauss-legendre"`` or a SciPy method name (`_ode`); the model's route
        (`_methods.ROUTES`) says which of them it runs.
    rtol : float, optional
        The relative local error tolerance of the adaptive methods.
    atol : float, optional
        Their absolute local error tolerance.
    dt : float, optional
        A fixed step.  ``"gauss-legendre"``: default 1/10 of the output spacing, halved (at most
        `GAUSS_HALVINGS` times, the run restarted) while its implicit stages do not converge; a dt
        smaller than the spacing is rounded down so that a whole number of steps fills it, a larger
        one is used as it is (the outputs are interpolated between steps).  With ``"dop853"`` it
        switches to fixed steps.
    max_step : float, optional
        The largest step the adaptive methods may take (for short events between output times).
    n_out : int, optional
        The number of evenly spaced output times (default 1001).
    t_eval : array_like, optional
        The output times, instead of ``n_out``.
    events : sequence of EventSpec or str, optional
        `EventSpec` items or expression strings; each crossing is recorded.
    tolerance : float, optional
        The drift tolerance of the first integrals; a larger drift adds a warning.  Default:
        `default_tolerance` (min(1e3 rtol, 1e-6); 1e-6 for ``gauss-legendre``).
    max_steps : int, optional
        The most steps a run may take; reaching it stops the run with a `SimulationError`.
    progress : bool or callable, optional
        True for a progress bar on standard error, or a callable(fraction, t), called at most every
        0.1 s (from a second thread for the built-in methods) and once at the end.  The result does
        not depend on it.
    backend : {"auto", "c", "symengine"}, optional
        How a model is compiled when ``source`` is not yet a `CompiledSystem`: C when a compiler
        exists ("auto"), or SymEngine's evaluation (no compiled integrators then).
    stabilization : str, optional
        For models with complementary constraints only, how the drift from the constraints is
        controlled (``"projection"``, ``"baumgarte"``, ``"both"``, ``"none"``); see
        `numerics._dae_run`.
    baumgarte : (float, float), optional
        Baumgarte's rates (α, β), with ``stabilization``.
    stiffness_check : bool, optional
        ``"dop853"`` only: Hairer's stiffness test (as in dop853.f), which stops the run with a
        `SimulationError` once the step is limited by stability rather than accuracy (h|λ| > 6.1 for
        15 steps in a row), where an implicit method (``"Radau"``) is the tool.  False integrates a
        knowingly stiff problem explicitly all the same.
    sensitivities : sequence of str or Sensitivities, optional
        Parameter names and initial values (``["l", "m", "theta(t0)"]``, or a
        `lagrangian.numerics.Sensitivities`): ∂y(t)/∂x for each, integrated with the state
        (``dop853`` only; `numerics._sensitivity`), as the columns ``d(theta)/d(l)``...;
        ``trajectory.sensitivity("l")`` has shape (N, 2n).
    inputs : dict or Feedback, optional
        What the declared inputs do (`lagrangian.numerics._inputs`): a dict by input name of numbers,
        expressions (``"2*sin(3*t)"``, ``"-k1*x - k2*x_dot"``), `InputTable` values, or Python
        functions ``u(t, y)`` (the slow path); or a `Feedback` (``lagrangian.lqr``), the closed loop
        compiled in.  Inputs not named follow the model's ``[controls]``, else stay at their value
        (0).  The applied inputs are columns of the result (``traj.column("F")``).
    rest : float, optional
        Models with unilateral contacts only (`simulate_contact`).
    max_phases : int, optional
        Models with unilateral contacts only (`simulate_contact`).
    max_switches : int, optional
        Models with an exact Coulomb contact only (`simulate_stick_slip`).

    Returns
    -------
    Trajectory
        With the drift of every first integral (``trajectory.drift_summary()``).

    Raises
    ------
    SimulationError
        Missing or non-finite values, a time span that does not increase or is not finite,
        tolerances that cannot be met, an output grid too large for memory, a singular mass
        matrix (before or during the run: never a silent NaN), step-size underflow, overflow,
        stiff equations (``stiffness_check``) or ``max_steps`` reached; for the last two its
        ``trajectory`` is the part computed so far (status ``"... (partial)"``), or None; an
        option the model's route does not honour.
    """
    options = SimulationOptions(
        t_end, t_start=t_start, initial=initial, parameters=parameters, method=method, rtol=rtol, atol=atol, dt=dt,
        max_step=max_step, n_out=n_out, t_eval=t_eval, events=events, tolerance=tolerance, max_steps=max_steps,
        progress=progress, backend=backend, stabilization=stabilization, baumgarte=baumgarte,
        stiffness_check=stiffness_check, sensitivities=sensitivities, inputs=inputs, rest=rest,
        max_phases=max_phases, max_switches=max_switches)
    return run(source, options)


def simulate_contact(source, t_end: float, **options: Any) -> Trajectory:
    """`simulate` of a model with unilateral contacts, by smooth phases between impacts (`_contact`).

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion
        A model file, a `Model`, or its equations, with at least one ``unilateral`` constraint.
    t_end : float
        The end of the time span.
    **options
        As for `simulate`.  ``method`` must be ``"dop853"`` and ``dt`` None (phases end at events),
        ``stabilization`` None or ``"projection"`` (the closed contacts are kept by projection); and,
        for this route only: ``rest``, the last approach speed, relative to the first of a geometric
        series of impacts, at which the accumulation is summed and the contacts closed (default
        1e-6; `_contact_switch`), ``max_phases``, the most smooth phases a run may have (default
        1 000 000).

    Returns
    -------
    Trajectory
        On the requested grid, with the contact columns and `ContactEvent` events.

    Raises
    ------
    ModelError
        No unilateral contact.
    SimulationError
        As `simulate`'s contacts route (`_contact.run_contact`).
    """
    return run(source, SimulationOptions(t_end, **options), route="contact")


def simulate_stick_slip(source, t_end: float, **options: Any) -> Trajectory:
    """`simulate` of a model with one exact Coulomb contact, by stick and slip phases (`_stickslip`).

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion
        A model file, a `Model`, or its equations, whose contact has ``regularization = 0``.
    t_end : float
        The end of the time span.
    **options
        As for `simulate` (``dt`` and ``gauss-legendre`` are refused: the phases end at events, not
        on a fixed grid); ``stabilization``, ``baumgarte``: the drift control of the stuck phases;
        for this route only, ``max_switches``: the most phases a run may have (default 100 000).

    Returns
    -------
    Trajectory
        On the requested grid, with the extra columns ``mode_<load>``, ``friction_<load>``,
        ``sliding_<load>`` and the switching events ``stick_<load>``, ``slip_<load>``.

    Raises
    ------
    ModelError
        No single exact contact, or no fixed sliding direction.
    SimulationError
        As `simulate`; also a negative N, f > f_s, an endless chattering of short phases.
    """
    return run(source, SimulationOptions(t_end, **options), route="stick-slip")


def run(source, options: SimulationOptions, route: str | None = None) -> Trajectory:
    """`simulate` with its options made: the model read once, its route picked (or the one named) and run.

    Declared signs and ranges (`model._assumptions`): values that break a sign are refused, and the
    motion is checked against the ranges and the signs the derivation used (`_ranges`).
    """
    if isinstance(source, (str, Path)):
        source = load_model(source)  # read once
    model = source if isinstance(source, Model) else getattr(getattr(source, "eom", source), "model", None)
    watched = model is not None and (any(c.range is not None for c in model.coordinates)
                                     or any(p.sign is not None for p in model.parameters))
    if watched:
        check_sign(model, options.parameters or {})  # type: ignore[arg-type]
        if isinstance(source, Model) and exact_contact_model(source) is None:
            source = derive(source)  # derived here once, for the signs it used
    chosen, taken = route_for(source, options, route)
    check_route_options(chosen, options)
    traj = chosen.run(taken, options, run)
    if not watched:
        return traj
    eom = source if isinstance(source, EquationsOfMotion) else getattr(source, "eom", None)
    return watch_ranges(model, traj, eom.assumptions if isinstance(eom, EquationsOfMotion) else ())  # type: ignore[arg-type]
