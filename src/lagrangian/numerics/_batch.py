"""One chunk of ensemble members integrated in one compiled call, and its per-member summaries.

A `Kernel` is everything a process needs to integrate members of one model: the
generated C source (compiled once per process and cached on disk, `_compile`), the
integrator's control block (`_simulate.control_block`, the same as `simulate`'s), the
output grid and the events.  It holds no SymPy or ctypes object, so it pickles to a Dask
worker in one message; the worker compiles (or loads from its cache) the library once and
keeps it (`_library`).

`run_chunk(kernel, Y0, P)` calls ``lg_batch`` (``codegen/runtime/integrators.c``): each member runs exactly
as `simulate`'s single call would, so its result is the same to the last bit, and the
summaries are then reduced with NumPy over the chunk:

* ``state_min``, ``state_max`` over the output times, ``state_final`` where the run ended
  (the terminal event, the end time, or the last good state of a failed member);
* ``event_time`` (first occurrence, NaN when none) and ``event_count`` of each event;
* ``drift`` of each first integral, max|I(t) − I(t0)| / S over the output times with the
  scale S of `_trajectory.conservation` (so it equals ``simulate(...).drift``);
* ``status`` (`STATUS`), ``t_final``, ``steps``, ``rhs_calls``.

Memory is the chunk's outputs only (members × n_out × (2·2n + monitors) numbers), whatever
the number of members.
"""

from __future__ import annotations

import ctypes
import threading
from dataclasses import dataclass

import numpy as np

from ._compile import compile_library

__all__ = ["PENDING", "STATUS", "Kernel", "run_chunk"]

#: The status of a member (the CF ``flag_values`` / ``flag_meanings`` of the ``status`` variable).
STATUS = {
    -1: "pending",          # not computed (yet): an interrupted sweep, to be finished with resume
    0: "ok",                # reached t_end
    1: "stopped",           # a terminal event ended it
    2: "blow-up",           # the state stopped being finite
    3: "step-limit",        # max_steps reached
    4: "singular",          # the mass matrix became singular
    5: "step-underflow",    # the step size fell below the resolution of t
    6: "no-convergence",    # the implicit stages of gauss-legendre did not converge
    7: "stiff",             # dop853's stiffness test stopped it (an implicit method is needed)
}
PENDING = -1
# C status (``codegen/runtime/integrators.c``) -> member status
_FROM_C = {0: 0, 4: 1, 2: 2, 5: 3, 1: 4, 3: 5, 6: 6, 8: 7}
_INTERRUPTED = 7
_B_SIZE = 6  # lg_batch's info row: status, t, steps, nfev, rows, pivot


@dataclass(frozen=True)
class Kernel:
    """What a process needs to integrate members of one model (module docstring); picklable."""

    source: tuple[str, ...]  # the translation units (`codegen.GeneratedSource.units`)
    key: str
    n: int
    n_params: int
    n_constants: int
    monitors: tuple[str, ...]
    integrals: tuple[str, ...]
    momenta: tuple[tuple[str, int], ...]   # integral name -> coordinate index of its momentum
    events: tuple[str, ...]
    ev_dir: tuple[int, ...]
    ev_terminal: tuple[int, ...]
    method: str
    ctl: tuple[float, ...]
    t_out: tuple[float, ...]
    t_start: float
    t_end: float
    #: The inputs' law's numbers (`_input_code`), the same for every member unless a chunk gives its own.
    law: tuple[float, ...] = ()


_libraries: dict[str, ctypes.CDLL] = {}
_lock = threading.Lock()
_P = ctypes.c_void_p


def _library(kernel: Kernel) -> ctypes.CDLL:
    """The kernel's compiled library, built or loaded once per process (then taken from memory)."""
    with _lock:
        lib = _libraries.get(kernel.key)
        if lib is None:
            lib = compile_library(kernel.source, kernel.key)
            lib.lg_batch.restype = ctypes.c_int
            lib.lg_batch.argtypes = [ctypes.c_int, ctypes.c_int, _P, _P, _P, _P, ctypes.c_int, ctypes.c_double,
                                     ctypes.c_double, _P, _P, _P, _P, _P, _P, _P, _P, _P]
            _libraries[kernel.key] = lib
        return lib


def run_chunk(kernel: Kernel, Y0: np.ndarray, P: np.ndarray, keep: bool = False,
              stop: np.ndarray | None = None, L: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Integrate the members ``Y0`` (m, 2n), ``P`` (m, n_params) in one C call; their summaries.

    ``L`` (m, law size): each member's numbers of the inputs' law (its feedback gains), else the
    kernel's ``law`` for all.

    ``keep``: also return ``state`` (m, n_out, 2n), NaN after a member's end.  ``stop``: a
    one-number array; setting it non-zero from another thread stops the call at the next
    step (the members not finished then have status ``pending``).  ctypes releases the GIL
    for the call, so threads running chunks run in parallel.
    """
    lib = _library(kernel)
    m, n2 = len(Y0), 2 * kernel.n
    t_out = np.asarray(kernel.t_out, dtype=float)
    n_out, nm, ne = len(t_out), max(len(kernel.monitors), 1), max(len(kernel.events), 1)
    Y0 = np.ascontiguousarray(Y0, dtype=float)
    Pext = np.zeros((m, kernel.n_params + kernel.n_constants + len(kernel.law)))
    Pext[:, : kernel.n_params] = P
    if kernel.law:
        Pext[:, kernel.n_params + kernel.n_constants:] = kernel.law if L is None else L
    ctl = np.asarray(kernel.ctl, dtype=float)
    Y_fin = np.empty((m, n2))
    Y_out = np.full((m, n_out, n2), np.nan)
    mon = np.full((m, n_out, nm), np.nan)
    mom = np.full((m, n_out, n2), np.nan)
    ev = np.zeros((m, ne, 2 + n2))
    info = np.full((m, _B_SIZE), np.nan)
    info[:, 0] = -1.0
    ev_dir = np.array(kernel.ev_dir or (0,), dtype=np.intc)
    ev_term = np.array(kernel.ev_terminal or (0,), dtype=np.intc)
    stop = np.zeros(1) if stop is None else stop
    ptr = _ptr
    lib.lg_batch(0 if kernel.method == "dop853" else 1, m, ptr(ctl), ptr(Y0), ptr(Pext), ptr(t_out), n_out,
                 kernel.t_end, kernel.t_start, ptr(ev_dir), ptr(ev_term), ptr(Y_fin), ptr(Y_out), ptr(mon),
                 ptr(mom), ptr(ev), ptr(info), ptr(stop))
    return summarize(kernel, Y0, Pext, Y_out, mon, mom, ev, info, Y_fin, keep)


def _ptr(a: np.ndarray) -> int:
    return a.ctypes.data


def summarize(kernel: Kernel, Y0, Pext, Y_out, mon, mom, ev, info, Y_fin, keep: bool) -> dict[str, np.ndarray]:
    """The per-member summaries of a chunk (module docstring), vectorised over its members."""
    m = len(Y0)
    code = info[:, 0]
    status = np.full(m, PENDING, dtype=np.int8)
    for c, s in _FROM_C.items():
        status[code == c] = s
    done = status != PENDING
    with np.errstate(invalid="ignore"):
        out: dict[str, np.ndarray] = {
            "status": status,
            "t_final": np.where(done, info[:, 1], np.nan),
            "steps": np.where(done, info[:, 2], 0).astype(np.int64),
            "rhs_calls": np.where(done, info[:, 3], 0).astype(np.int64),
            "conditioning": np.where(done, info[:, 5], np.nan),
            "state_min": np.fmin.reduce(Y_out, axis=1),
            "state_max": np.fmax.reduce(Y_out, axis=1),
            "state_final": np.where(done[:, None], Y_fin, np.nan),
        }
    ne = len(kernel.events)
    counts = ev[:, :ne, 0]
    out["event_count"] = counts.astype(np.int64)
    out["event_time"] = np.where(counts > 0, ev[:, :ne, 1], np.nan)
    out["drift"] = _drift(kernel, mon, mom)
    for name in ("state_min", "state_max", "event_time", "drift"):
        out[name][~done] = np.nan
    out["event_count"][~done] = 0
    if keep:
        Y_out[~done] = np.nan
        out["state"] = Y_out
    return out


def _drift(kernel: Kernel, mon: np.ndarray, mom: np.ndarray) -> np.ndarray:
    """(m, integrals): `_trajectory.conservation`'s relative drift, over the members at once.

    S = max(max|I|, max m(t)) with m = |T| + |U| for an energy-like integral and
    Σ_j |M_kj q̇_j| + |I − Σ_j M_kj q̇_j| for the momentum p_k; rows after a member's end are
    NaN and ignored (fmax).  S = 1 when it is 0 or not finite, as in `drift_scale`.
    """
    names = kernel.monitors
    integrals = kernel.integrals
    momenta = dict(kernel.momenta)
    n = kernel.n
    T = mon[..., names.index("T_total" if "T" in integrals else "T")] if ("T_total" in names or "T" in names) \
        else None
    U = mon[..., names.index("U_total" if "U" in integrals else "U")] if ("U_total" in names or "U" in names) \
        else None
    drift = np.empty((len(mon), len(integrals)))
    with np.errstate(invalid="ignore"):
        for j, name in enumerate(integrals):
            values = mon[..., names.index(name)]
            scale = np.fmax.reduce(np.abs(values), axis=1)
            if name in momenta:
                k = momenta[name]
                magnitude = mom[..., k] + np.abs(values - mom[..., n + k])
                scale = np.fmax(scale, np.fmax.reduce(np.abs(magnitude), axis=1))
            elif T is not None and U is not None:
                scale = np.fmax(scale, np.fmax.reduce(np.abs(T) + np.abs(U), axis=1))
            scale = np.where((scale > 0) & np.isfinite(scale), scale, 1.0)
            drift[:, j] = np.fmax.reduce(np.abs(values - values[:, :1]), axis=1) / scale
    return drift
