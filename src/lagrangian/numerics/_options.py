"""The options of a run, in one frozen value checked once: what `simulate` hands to every route.

SciPy's ``solve_ivp`` keeps one signature for every method and hands the options on; so does
`simulate`: its keywords become a `SimulationOptions`, validated here (tolerances, the method's
name, the stabilization's name), and each route of the registry (`_methods`) reads the options
it honours and refuses, with a `SimulationError` naming the option and the fix, those it cannot.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import SimulationError

__all__ = [
    "BAUMGARTE",
    "BUILTIN",
    "METHODS",
    "RTOL_MIN",
    "SCIPY",
    "STABILIZATIONS",
    "SimulationOptions",
    "check_options",
    "default_tolerance",
]

#: The integrators compiled in C (`codegen/runtime/integrators.c`).
BUILTIN = ("dop853", "gauss-legendre")
#: SciPy's ``solve_ivp`` methods, driven by the compiled right-hand side.
SCIPY = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
#: The integration methods of `simulate`: the compiled ones (C), then SciPy's `solve_ivp` methods.
METHODS = BUILTIN + SCIPY
#: How the drift from complementary constraints is controlled (`_dae_run`).
STABILIZATIONS = ("projection", "baumgarte", "both", "none")
#: Default Baumgarte rates (α, β), in 1/time.
BAUMGARTE = (5.0, 5.0)


#: Smallest rtol, about 50 machine epsilons: a tighter local tolerance than this cannot be met by
#: a step in double precision (SciPy clips rtol at 100 epsilons; the built-in DOP853 still
#: converges at 1e-14).
RTOL_MIN = 1e-14
#: The drift tolerance when none is given: adaptive methods warn above min(1e3 rtol, 1e-6);
#: the symplectic method (no rtol) above 1e-6.
DEFAULT_TOLERANCE_FACTOR, DEFAULT_TOLERANCE_CAP = 1e3, 1e-6


@dataclass(frozen=True)
class SimulationOptions:
    """Every option of `simulate`, checked once when made (`check_options`).

    The fields are `simulate`'s keywords, plus three that only one route honours (``rest``,
    ``max_phases``, ``max_switches``); None leaves the route's default.  A route reads the options it
    honours and refuses the others it cannot ignore (`_methods.ROUTES`).

    Parameters
    ----------
    t_end : float
        As in `simulate`.
    t_start : float
        As in `simulate`.
    initial : mapping of str to float, optional
        As in `simulate`.
    parameters : mapping of str to float, optional
        As in `simulate`.
    method : str
        As in `simulate`.
    rtol : float
        As in `simulate`.
    atol : float
        As in `simulate`.
    dt : float, optional
        As in `simulate`.
    max_step : float, optional
        As in `simulate`.
    n_out : int, optional
        As in `simulate`.
    t_eval : array_like, optional
        As in `simulate`.
    events : sequence of EventSpec or str
        As in `simulate`.
    tolerance : float, optional
        As in `simulate`.
    max_steps : int
        As in `simulate`.
    progress : bool or callable
        As in `simulate`.
    backend : str
        As in `simulate`.
    stabilization : str, optional
        As in `simulate`.
    baumgarte : (float, float)
        As in `simulate`.
    stiffness_check : bool
        As in `simulate`.
    sensitivities : sequence of str or Sensitivities, optional
        As in `simulate`.
    inputs : dict or Feedback, optional
        As in `simulate`.
    rest : float, optional
        Unilateral contacts only (`_contact`).
    max_phases : int, optional
        Unilateral contacts only (`_contact`).
    max_switches : int, optional
        Exact Coulomb friction only (`_stickslip`).
    """

    t_end: float
    t_start: float = 0.0
    initial: Mapping[str, float] | None = None
    parameters: Mapping[str, float] | None = None
    method: str = "dop853"
    rtol: float = 1e-10
    atol: float = 1e-10
    dt: float | None = None
    max_step: float | None = None
    n_out: int | None = None
    t_eval: Any = None
    events: Sequence[Any] = ()
    tolerance: float | None = None
    max_steps: int = 100_000_000
    progress: bool | Callable[[float, float], None] = False
    backend: str = "auto"
    stabilization: str | None = None
    baumgarte: tuple[float, float] = BAUMGARTE
    stiffness_check: bool = True
    sensitivities: Any = None
    inputs: Any = None
    rest: float | None = None
    max_phases: int | None = None
    max_switches: int | None = None

    def __post_init__(self) -> None:
        check_options(self.rtol, self.atol, self.tolerance)
        if self.method not in METHODS:
            raise SimulationError(f"Unknown method `{self.method}`.", fix="use one of " + ", ".join(METHODS))
        if self.stabilization is not None and self.stabilization not in STABILIZATIONS:
            raise SimulationError(f"Unknown stabilization `{self.stabilization}`.",
                                  fix="use " + ", ".join(STABILIZATIONS))

    def but(self, **changes: Any) -> SimulationOptions:
        """The same options with ``changes`` (checked again).

        Parameters
        ----------
        **changes
            Options to change, by name.

        Returns
        -------
        SimulationOptions
            The same options with ``changes`` (checked again).
        """
        return dataclasses.replace(self, **changes)


def default_tolerance(method: str, rtol: float) -> float:
    """The drift above which a first integral gets a warning when no ``tolerance`` is given.

    min(1e3 rtol, 1e-6) for the adaptive methods (a drift a thousand times the local
    tolerance, or above a millionth, is accuracy lost, not round-off); 1e-6 for
    ``gauss-legendre``, whose energy error depends on dt, not on rtol.

    Parameters
    ----------
    method : str
        The integration method.
    rtol : float
        Its relative tolerance.

    Returns
    -------
    float
        The tolerance.
    """
    if method == "gauss-legendre":
        return DEFAULT_TOLERANCE_CAP
    return min(DEFAULT_TOLERANCE_FACTOR * rtol, DEFAULT_TOLERANCE_CAP)


def check_options(rtol: float, atol: float, tolerance: float | None) -> None:
    """Refuse tolerances that cannot work, before anything is compiled or run."""
    if not (rtol > 0 and atol > 0) or not (math.isfinite(rtol) and math.isfinite(atol)):
        raise SimulationError(f"rtol = {rtol:g} and atol = {atol:g}: both must be positive finite numbers.",
                              fix="e.g. rtol=1e-10, atol=1e-10")
    if rtol < RTOL_MIN:
        raise SimulationError(f"rtol = {rtol:g} is below {RTOL_MIN:.0e}, about 50 machine epsilons: no step of a "
                              f"double-precision integrator can be that accurate, so the step size would shrink "
                              f"to nothing.", fix=f"use rtol >= {RTOL_MIN:.0e} (e.g. 1e-13)")
    if tolerance is not None and not (tolerance > 0 and not math.isnan(tolerance)):
        raise SimulationError(f"The drift tolerance {tolerance:g} must be a positive number.",
                              fix="e.g. tolerance=1e-9 (--tolerance 1e-9), or leave it out for the default")
