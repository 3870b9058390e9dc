"""The registry of `simulate`'s routes: which models each takes, which options it honours, how it runs.

SciPy's ``solve_ivp`` looks its method up in ``METHODS`` and hands every solver the same
options; `simulate` looks its route up here.  A model decides the route (free bodies are
integrated on unit quaternions, unilateral contacts by phases between impacts, exact Coulomb
friction by stick/slip phases, complementary constraints as a differential-algebraic system,
everything else as M q̈ = F), and the first route of `ROUTES` that takes the model runs it;
asking for sensitivities picks their route before any other.  The method is then one of the
route's `Route.methods`.

Each route declares the options it honours beyond the ones every route reads (`COMMON`); an
option that only some routes honour (`ROUTE_ONLY`) given to another is refused here, naming
the option and the fix.  The refusals that depend on values (a method, fixed steps, a
stabilization) are the route's own ``check_*_options``, run before anything is compiled.

No route imports this module: a route that runs phases by `simulate` (stick/slip) receives
the pipeline as an argument (`Runner`), so the simulators form no import circle.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..errors import SimulationError
from ._contact import contact_model, run_contact
from ._dae import ConstrainedSystem, constrained_source
from ._dae_run import run_dae
from ._free_simulate import free_source, run_free
from ._ode import run_ode
from ._options import METHODS, SCIPY, SimulationOptions
from ._stickslip import exact_contact_model, run_stick_slip
from ._trajectory import Trajectory

__all__ = ["COMMON", "ROUTES", "ROUTE_ONLY", "Route", "Runner", "check_route_options", "method_table", "route_for"]

#: How a route runs a smooth phase by the whole of `simulate` (stick/slip's sliding phases).
Runner = Callable[[object, SimulationOptions], Trajectory]

#: The options every route reads.
COMMON = ("t_start", "initial", "parameters", "rtol", "atol", "max_step", "n_out", "t_eval", "tolerance",
          "max_steps", "progress", "backend")
#: Options that only some routes honour: given to another route, they are refused.
ROUTE_ONLY = ("sensitivities", "rest", "max_phases", "max_switches")


@dataclass(frozen=True)
class Route:
    """One way `simulate` integrates a model.

    Contract:

    1. ``takes(source, options)`` returns what ``run`` integrates (the source itself, or its
       model, equations or compiled system), or None when the route is not for this model;
       it raises nothing for a model it does not take.
    2. ``run(taken, options, simulate)`` refuses, with a `SimulationError` naming the option
       and the fix, a value it cannot honour, before anything is compiled; ``simulate`` is the
       whole pipeline, for a route that runs phases by it.
    3. ``methods`` are the method names it runs; ``options`` the options it honours beyond
       `COMMON` (``events`` included when it locates events); ``inputs`` what inputs it takes.
    """

    name: str
    models: str
    methods: tuple[str, ...]
    options: tuple[str, ...]
    inputs: str
    takes: Callable[[object, SimulationOptions], object | None]
    run: Callable[[object, SimulationOptions, Runner], Trajectory]


def _sensitivities(source: object, options: SimulationOptions, simulate: Runner) -> Trajectory:
    from ._sensitivity import run_sensitivities  # late: only a run that asks for sensitivities needs it

    return run_sensitivities(source, options)


def _constrained(source: object, options: SimulationOptions) -> object | None:
    source, eom = constrained_source(source)
    if eom is None:
        return None
    return source if isinstance(source, ConstrainedSystem) else eom


ROUTES: tuple[Route, ...] = (
    Route("sensitivities", "M q̈ = F, asked for ∂y/∂x (`sensitivities=`)", ("dop853",),
          ("dt", "stiffness_check", "sensitivities"), "none (give constant ones as parameters)",
          lambda source, options: source if options.sensitivities is not None else None, _sensitivities),
    Route("free", "free bodies (integrated on unit quaternions)", ("dop853", *SCIPY),
          ("events", "dt", "stiffness_check"), "constant",
          lambda source, options: free_source(source),
          lambda source, options, simulate: run_free(source, options)),
    Route("contact", "unilateral contacts (smooth phases between impacts)", ("dop853",),
          ("events", "stiffness_check", "stabilization", "rest", "max_phases"), "constant",
          lambda source, options: contact_model(source),
          lambda source, options, simulate: run_contact(source, options)),
    Route("stick-slip", "one exact Coulomb contact (stick and slip phases)", ("dop853", *SCIPY),
          ("events", "stiffness_check", "stabilization", "baumgarte", "max_switches"), "constant",
          lambda source, options: exact_contact_model(source), run_stick_slip),
    Route("dae", "complementary constraints (a differential-algebraic system)", ("dop853", *SCIPY),
          ("events", "stabilization", "baumgarte"), "all",
          _constrained, lambda source, options, simulate: run_dae(source, options)),
    Route("ode", "M q̈ = F, every other model", METHODS,
          ("events", "dt", "stiffness_check"), "all",
          lambda source, options: constrained_source(source)[0],
          lambda source, options, simulate: run_ode(source, options)),
)
_BY_NAME = {route.name: route for route in ROUTES}


def route_for(source: object, options: SimulationOptions, name: str | None = None) -> tuple[Route, object]:
    """(the route, what it integrates): the first route of `ROUTES` that takes ``source``, or the one named.

    A route named but not taking ``source`` gets ``source`` itself, and says why it cannot run it.
    """
    if name is not None:
        route = _BY_NAME[name]
        taken = route.takes(source, options)
        return route, source if taken is None else taken
    for route in ROUTES:
        taken = route.takes(source, options)
        if taken is not None:
            return route, taken
    raise AssertionError("the ODE route takes every model")  # pragma: no cover


def check_route_options(route: Route, options: SimulationOptions) -> None:
    """Refuse an option that only other routes honour (`ROUTE_ONLY`), naming the routes that do."""
    for option in ROUTE_ONLY:
        if getattr(options, option) is None or option in route.options:
            continue
        takers = [r for r in ROUTES if option in r.options]
        raise SimulationError(
            f"The option `{option}` applies to models with {' or '.join(r.models for r in takers)}; this one "
            f"takes the `{route.name}` route ({route.models}).", fix=f"leave `{option}` out")


def _methods_text(methods: tuple[str, ...]) -> str:
    if methods == METHODS:
        return "`dop853`, `gauss-legendre`, SciPy's"
    if methods == ("dop853", *SCIPY):
        return "`dop853`, SciPy's"
    return ", ".join(f"`{m}`" for m in methods)


def method_table() -> str:
    """The registry as a Markdown table (route → models → methods → options), as docs/simulation.md shows it."""
    lines = ["| route | models | methods | options beyond the common ones | inputs |",
             "|---|---|---|---|---|"]
    lines += [f"| `{route.name}` | {route.models} | {_methods_text(route.methods)} | "
              f"{', '.join(f'`{o}`' for o in route.options)} | {route.inputs} |" for route in ROUTES]
    return "\n".join(lines)
