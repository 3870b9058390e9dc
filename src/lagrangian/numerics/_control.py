"""The compiled integrators' control block, their status codes, and the interruptible call.

`control_block` lays out the doubles `codegen/runtime/integrators.c` reads (tolerances, steps, the stop
request); `simulate`, `ensemble`, the contact phases and the sensitivities all start their C
runs from it, so a member of an ensemble starts exactly as `simulate` starts its run.
`interruptible` makes the one C call in a worker thread so that Ctrl-C reaches the main thread
at once and sets the stop request.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

import numpy as np

from ..errors import SimulationError

__all__ = ["CONTROL_SIZE", "C_STOP", "GAUSS_HALVINGS", "INTERRUPTED", "STATUS", "STIFF", "STIFFNESS_TEST_PERIOD", "control_block", "gauss_step",
           "interruptible"]

STATUS = {
    1: "the mass matrix M became singular",
    2: "the state stopped being finite (overflow)",
    3: "the step size fell below the resolution of t, or below 1e-14 of the time span (step size underflow)",
    5: "the maximum number of steps was reached",
    6: "the implicit stages of the Gauss-Legendre step did not converge",
}
STIFF = 8  # LG_STIFF: dop853's stiffness test fired (`codegen/runtime/integrators.c`, lg_dop_stiff)
#: dop853's NSTIFF: the stiffness test runs every this many accepted steps (then at every step while
#: the problem looks stiff), as in Hairer's dop853.f.
STIFFNESS_TEST_PERIOD = 1000
#: Doubles in the control block, C_SIZE in `codegen/runtime/integrators.c` (`lg_batch` copies that many from it).
CONTROL_SIZE = 22
INTERRUPTED = 7  # LG_INTERRUPTED: the stop request ctl[C_STOP] was seen
C_STOP = 13

#: How many times gauss-legendre's default step is halved when its implicit stages do not converge
#: (or the state overflows): 1/10 of the output spacing is too long for a fast spin or a stiff spring.
GAUSS_HALVINGS = 10


def gauss_step(t_start: float, t_end: float, t_out: np.ndarray, dt: float | None) -> float:
    """gauss-legendre's fixed step: ``dt``, or 1/10 of the output spacing; rounded to fill the spacing."""
    spacing = np.min(np.diff(t_out)) if len(t_out) > 1 else t_end - t_start
    if dt is None:
        dt = spacing / 10
    uniform = len(t_out) > 1 and np.allclose(np.diff(t_out), spacing, rtol=1e-12, atol=0)
    # A dt below the output spacing is rounded down so that whole steps fill it (the outputs
    # fall on steps); a larger one is honoured, the outputs interpolated between steps.
    return spacing / np.ceil(spacing / dt - 1e-9) \
        if uniform and abs(t_out[0] - t_start) < 1e-15 and dt <= spacing else dt


def control_block(method: str, t_start: float, t_end: float, t_out: np.ndarray, rtol: float, atol: float,
                  dt: float | None, max_step: float | None, max_steps: int, h: float | None = None,
                  stiffness_check: bool = True) -> np.ndarray:
    """The C integrators' control block (``codegen/runtime/integrators.c``) at the start of a run.

    One place for it, so that `ensemble` starts each member exactly as `simulate` starts
    its run (same first step, same fixed step of ``gauss-legendre``; ``h`` overrides that
    step when `simulate` halves it).

    Parameters
    ----------
    method : str
        ``"dop853"`` or ``"gauss-legendre"``.
    t_start : float
        The start of the run.
    t_end : float
        Its end.
    t_out : ndarray
        The output times.
    rtol : float
        The relative tolerance.
    atol : float
        The absolute tolerance.
    dt : float or None
        A fixed step, or None.
    max_step : float or None
        The largest step, or None.
    max_steps : int
        The most steps.
    h : float, optional
        Overrides the fixed step of ``gauss-legendre``.
    stiffness_check : bool, optional
        Whether dop853 runs Hairer's stiffness test.

    Returns
    -------
    ndarray
        The control block, as the C integrators read it.
    """
    if dt is not None and not dt > 0:
        raise SimulationError(f"dt = {dt} must be positive.", fix="give a positive step, e.g. dt=1e-3")
    ctl = np.zeros(CONTROL_SIZE)
    ctl[0] = t_start
    ctl[14] = STIFFNESS_TEST_PERIOD if stiffness_check else 0.0
    ctl[2], ctl[3] = rtol, atol
    ctl[4] = np.inf if max_step is None else float(max_step)
    ctl[9] = float(max_steps)
    ctl[12] = 1.0
    if method == "gauss-legendre":
        ctl[1] = gauss_step(t_start, t_end, t_out, dt) if h is None else h
        ctl[2] = 1e-14  # stage iteration tolerance: converged to round-off, so symplecticity holds
    elif dt is not None:
        ctl[1], ctl[8] = float(dt), 1.0
    return ctl

def interruptible(call: Callable[[], int], ctl: np.ndarray) -> int:
    """``call()`` (a compiled run) in a worker thread; Ctrl-C meanwhile asks it to stop at its next step.

    The main thread only waits: a signal's Python handler runs in the main thread, and not
    before a C call made there returns, so the run itself must not be made there.
    """
    result: list = []
    done = threading.Event()

    def run() -> None:
        try:
            result.append(call())
        finally:
            done.set()

    # Waiting on an Event, not on `Thread.join`: before Python 3.13 an interrupted join marks
    # the thread finished, and a second join would return while the run still writes.
    threading.Thread(target=run, name="lagrangian-run", daemon=True).start()
    try:
        done.wait()  # interruptible: KeyboardInterrupt arrives here within milliseconds
    except KeyboardInterrupt:
        ctl[C_STOP] = 1.0
        done.wait()
    return result[0]
