"""The top's analysis checked against a simulated motion: `simulation_check`.

`analysis.analyse_top` gives θ1, θ2, the nutation period and the mean precession rate from
the first integrals alone (the effective potential, the cubic in u = cosθ); here the same
numbers are read off a trajectory, which uses nothing but the equations of motion and the
initial state, so agreement checks both.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

from ..analysis import TopAnalysis
from ..dynamics import EquationsOfMotion
from ._simulate import EventSpec, simulate

__all__ = ["SimulationCheck", "simulation_check"]


@dataclass(frozen=True)
class SimulationCheck:
    """The analysis's numbers next to the same numbers read off a simulated motion.

    ``rows``: (name, analysis value, simulated values, largest difference, unit);
    ``t_end``: the simulated time; ``note``: why nothing could be compared, if so.

    Parameters
    ----------
    rows : tuple of (str, float, tuple of float, float, str)
        (name, analysis value, simulated values, largest difference, unit).
    t_end : float
        The simulated time.
    note : str
        Why nothing could be compared, if so.
    """

    rows: tuple[tuple[str, float, tuple[float, ...], float, str], ...]
    t_end: float
    note: str = ""


def simulation_check(eom: EquationsOfMotion, an: TopAnalysis, *, periods: float = 3.0,
                     rtol: float = 1e-12) -> SimulationCheck:
    """Simulate ``periods`` nutation periods and read θ1, θ2, T and ⟨ψ̇⟩ off the motion.

    The turning points are events q̇ = 0 of the remaining coordinate (rising: θ1, falling:
    θ2), located by the integrator's dense output; the period is the time between two
    θ1's; the mean precession is the precession angle gained over one period divided by it.
    Independent of the analysis: nothing but the equations of motion and the initial state.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    an : TopAnalysis
        The analysis to compare with.
    periods : float, optional
        How many nutation periods to simulate.
    rtol : float, optional
        The integrator's tolerances.

    Returns
    -------
    SimulationCheck
        The two sets of numbers, side by side.
    """
    red = an.reduction
    nut = an.nutation
    if nut is None or nut.steady:
        return SimulationCheck((), 0.0, "no nutation to compare (steady motion or no turning angles)")
    rate = red.coordinate + "_dot"
    t_end = periods * nut.period
    run = simulate(eom, t_end, initial=an.initial, parameters=an.parameters, rtol=rtol, atol=rtol, n_out=2,
                   events=[EventSpec("low", rate, direction=1), EventSpec("high", rate, direction=-1)])
    i, j = run.coordinates.index(red.coordinate), run.coordinates.index(red.precession)
    lows = [(e.t, e.q[i], e.q[j]) for e in run.events if e.name == "low"]
    highs = [e.q[i] for e in run.events if e.name == "high"]
    th = [(f"{red.coordinate}1", nut.theta1, tuple(q for _, q, _ in lows), "rad"),
          (f"{red.coordinate}2", nut.theta2, tuple(highs), "rad")]
    periods_sim = tuple(b[0] - a[0] for a, b in itertools.pairwise(lows))
    th.append(("nutation period", nut.period, periods_sim, "s"))
    mean = tuple((b[2] - a[2]) / (b[0] - a[0]) for a, b in itertools.pairwise(lows))
    th.append((f"mean ⟨{red.precession}_dot⟩", nut.mean_rates[red.precession], mean, "rad/s"))
    rows = tuple((name, value, sims, max((abs(x - value) for x in sims), default=math.nan), unit)
                 for name, value, sims, unit in th)
    note = "" if periods_sim else "fewer than two turning points were reached: simulate more periods"
    return SimulationCheck(rows, t_end, note)
