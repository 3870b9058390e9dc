"""`ensemble`: many motions of one model at once — on every local core, or on a Dask cluster.

    ds = lagrangian.ensemble("double_pendulum.toml", 10.0,
                             initial=lagrangian.grid(theta1=np.linspace(-3, 3, 100),
                                                     theta2=np.linspace(-3, 3, 100)),
                             events=flip_events(model), n_out=101)
    ds.event_time.min("event").plot()          # the flip-time map

The members (`_members`: arrays or a `grid`) are cut into chunks; each chunk is one call
of the compiled batch integrator (``lg_batch`` in `codegen/runtime/integrators.c`, driven by
`_batch.run_chunk`), which integrates its members one after another, each with its own
adaptive step, exactly as `simulate` integrates one motion: a member's result equals
`simulate` on that member to the last bit.  Per member, only summaries are kept by default
(min, max and final state, first event times, the drift of each first integral, a status);
``keep="trajectories"`` keeps the states at the output times too.

Where the chunks run
--------------------
Locally, in ``workers`` threads (default: every core this process may use).  Threads, not
processes: the compiled call releases the GIL (ctypes does), so the threads' C runs in
parallel, shares one loaded library and writes into NumPy arrays of this process; worker
processes would each load the library and send every chunk's results back through a pipe.
The Python share of a chunk (allocation, the NumPy reductions of the summaries) is small:
in CPU time a batched member costs about 0.6 of a `simulate` call on the top (1.13 ms
against 1.79 ms, ``benchmarks/ensemble.py``), the difference being `simulate`'s per-call
set-up and `Trajectory`.  Processes are still at hand, through Dask (below).
With ``scheduler`` (a ``tcp://host:8786`` address or a ``distributed.Client``), each chunk
is a Dask task: the `Kernel` (the generated C source and the run's settings) is sent to
every worker once, each worker compiles it once (or finds it in its cache) and keeps it.
A task lost with its worker is given to another worker by Dask's scheduler (up to
``distributed.scheduler.allowed-failures`` deaths, then ``KilledWorker``), a task that raises
is retried (``retries``); each chunk's result is gathered once and its rows are written by the
index of the chunk, so a chunk run again is never counted twice.

Results
-------
An ``xarray.Dataset`` (`_ensemble_store` describes the variables): dimension ``member``
with the swept names as coordinates, or the grid's own dimensions.  ``out="x.zarr"``
streams each finished chunk into a Zarr store (bounded memory for any number of members;
``resume=True`` finishes an interrupted one); ``out="x.nc"`` writes NetCDF at the end,
atomically.  Ctrl-C stops every chunk at its next step (well within a second), keeps the
finished members and raises `EnsembleInterrupted`.
"""

from __future__ import annotations

import hashlib
import math
import os
import signal
import sys
import threading
import time
from collections.abc import Sequence
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor
from concurrent.futures import wait as wait_threads
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import EnsembleInterrupted, OutputError, SimulationError
from ._batch import PENDING, Kernel, run_chunk
from ._control import control_block
from ._dae import constrained_source
from ._ensemble_store import Layout, MemorySink, ZarrSink
from ._free_simulate import free_source
from ._members import Grid, members
from ._ode import resolve
from ._options import BUILTIN, check_options
from ._progress import Reporter
from ._setup import EventSpec, memory_limit, momenta, output_times
from ._stickslip import exact_contact_model
from ._system import CompiledSystem

__all__ = ["EnsembleInterrupted", "connect_scheduler", "ensemble", "flip_events", "register_backend"]


def _jax_runner(eom, **options):
    """The ``"jax"`` backend (`_ensemble_jax.jax_runner`), imported when a run asks for it."""
    from ._ensemble_jax import jax_runner  # late: JAX and diffrax are optional, and slow to import

    return jax_runner(eom, **options)


#: Ensemble backends besides the compiled C one, by name: a function(eom, *, t_start, t_end,
#: t_out, rtol, atol, max_step, max_steps, keep) -> (key, run) with run(Y0, P, size) -> rows.
#: Listed here, explicitly: importing a module registers nothing (`register_backend` adds one).
BACKENDS: dict = {"jax": _jax_runner}


def register_backend(name: str, prepare) -> None:
    """Make ``backend=name`` available to `ensemble` (see `BACKENDS`): ``prepare`` as the ``"jax"`` one."""
    BACKENDS[name] = prepare

#: How long to try reaching a Dask scheduler before saying it cannot be reached.
CONNECT_TIMEOUT = "10s"
#: Largest memory (bytes) one chunk's output buffers may take.
CHUNK_MEMORY = 64 * 2**20


def flip_events(source) -> list[EventSpec]:
    """The "flip" events of a model: each angle coordinate q (the angle of a frame rotation) passing ±π.

    ``g = |q| − π``, rising: the first time the arm goes over the top (the double pendulum's
    flip-time map is the first of these times).

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion or CompiledSystem
        The model.

    Returns
    -------
    list of EventSpec
        One per angle coordinate.
    """
    eom = getattr(source, "eom", source)
    model = getattr(eom, "model", eom)
    angles = {str(f.rotation.angle) for f in model.frames if f.rotation is not None}
    names = [c.name for c in model.coordinates if c.name in angles]
    if not names:
        raise SimulationError(f"`{model.name}` has no angle coordinate (no frame turns by a coordinate), so "
                              "`flip` means nothing for it.", fix="give the event as an expression instead")
    return [EventSpec(f"flip_{name}", f"abs({name}) - pi", direction=1) for name in names]


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def ensemble(
    source,
    t_end: float,
    *,
    t_start: float = 0.0,
    initial=None,
    parameters=None,
    initial_names: Sequence[str] | None = None,
    parameter_names: Sequence[str] | None = None,
    n_out: int | None = None,
    t_eval=None,
    method: str = "dop853",
    rtol: float = 1e-10,
    atol: float = 1e-10,
    dt: float | None = None,
    max_step: float | None = None,
    max_steps: int = 10_000_000,
    stiffness_check: bool = True,
    events: Sequence[EventSpec | str] = (),
    keep: str = "summary",
    workers: int | None = None,
    chunk_size: int | None = None,
    scheduler=None,
    out: str | Path | None = None,
    resume: bool = False,
    progress=False,
    backend: str = "c",
    inputs=None,
):
    """Integrate many members of one model (module docstring) and return their results as an ``xarray.Dataset``.

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion or CompiledSystem
        A model file path, a `Model`, an `EquationsOfMotion` or a `CompiledSystem`.
    t_end : float
        The end of the time span, common to all members.
    t_start : float, optional
        Its start.
    initial : dict or array_like or Grid, optional
        The members' initial values: a dict of per-member arrays (scalars broadcast), a (members x
        names) array with ``initial_names``, or a `grid` (its axes are sorted into state and
        parameters by name).
    parameters : dict or array_like or Grid, optional
        The members' parameter values, likewise (with ``parameter_names``).
    initial_names : sequence of str, optional
        The columns of an ``initial`` array.
    parameter_names : sequence of str, optional
        The columns of a ``parameters`` array.
    n_out : int, optional
        As in `simulate`; the summaries are taken over the output times.
    t_eval : array_like, optional
        As in `simulate`.
    method : str, optional
        ``"dop853"`` or ``"gauss-legendre"``, the compiled integrators.
    rtol : float, optional
        As in `simulate`.
    atol : float, optional
        As in `simulate`.
    dt : float, optional
        As in `simulate`.
    max_step : float, optional
        As in `simulate`.
    max_steps : int, optional
        As in `simulate`.
    stiffness_check : bool, optional
        As in `simulate`: a member that dop853's stiffness test stops gets the status ``stiff`` (its
        summaries cover the part computed); the others go on.
    events : sequence of EventSpec or str, optional
        `EventSpec` items or expressions (``"theta_dot"``); their first time and their count are
        kept per member; a terminal event ends the member (status ``stopped``).
    keep : {"summary", "trajectories"}, optional
        ``"summary"`` (default; memory independent of the number of members) or ``"trajectories"``
        (also the state at every output time, variable ``trajectory``).
    workers : int, optional
        Local threads (default: every core); ignored with ``scheduler``.
    chunk_size : int, optional
        Members per compiled call / Dask task (default: a few chunks per worker).
    scheduler : str or distributed.Client, optional
        A Dask scheduler address (``"tcp://host:8786"``) or a ``distributed.Client``.
    out : str or Path, optional
        A ``.zarr`` store (written as chunks finish) or a ``.nc`` file (written at the end).
    resume : bool, optional
        Finish the pending members of an interrupted ``.zarr`` store.
    progress : bool or callable, optional
        True for a bar on standard error, or a callable(fraction, members done).
    backend : {"c", "jax"}, optional
        ``"c"`` (default: the compiled batch integrator) or ``"jax"`` (the JAX export's rhs vmapped
        over a chunk and integrated by diffrax's Dopri8: the GPU route, see `numerics._ensemble_jax`;
        no events or drift, no ``scheduler``, equal to the C path to the tolerance).
    inputs : dict or Feedback or sequence of Feedback, optional
        As in `simulate` (numbers, expressions, tables, a `Feedback`; not Python functions), the same
        for every member; or a sequence of `Feedback` values of one shape, one per member (each
        member's own gains: the law is compiled once, the gains follow the parameters).

    Returns
    -------
    xarray.Dataset
        One entry per member: its status, summaries, event times and counts (and trajectories).

    Raises
    ------
    SimulationError
        Bad members or options, a model the compiled integrators cannot run (complementary
        constraints, exact friction, no C compiler), a scheduler that cannot be reached.
    OutputError
        An output that exists (without ``resume``) or does not match the run to resume.
    EnsembleInterrupted
        Ctrl-C: the finished members are kept (in ``out``, and in ``.dataset``).
    """
    out_path = _validate_options(keep, method, rtol, atol, backend, events, scheduler, inputs, out, resume)
    # An unreachable scheduler is reported before anything is compiled or run.
    client, own_client = _client(scheduler) if scheduler is not None else (None, False)
    try:
        return _ensemble(source, t_end, t_start, initial, parameters, initial_names, parameter_names, n_out, t_eval,
                         method, rtol, atol, dt, max_step, max_steps, events, keep == "trajectories", workers,
                         chunk_size, client, out_path, resume, progress, backend, stiffness_check, inputs)
    finally:
        if own_client and client is not None:
            client.close()


def _validate_options(keep: str, method: str, rtol: float, atol: float, backend: str, events: Sequence[EventSpec | str],
                   scheduler: Any, inputs: Any, out: str | Path | None, resume: bool) -> Path | None:
    """Refuse bad options of `ensemble` before anything is compiled; the output's path (or None)."""
    if keep not in ("summary", "trajectories"):
        raise SimulationError(f"keep={keep!r}: use 'summary' or 'trajectories'.", fix="e.g. keep='summary'")
    if method not in BUILTIN:
        raise SimulationError(f"Ensembles run the compiled integrators, and `{method}` is not one of them.",
                              fix="use method='dop853' (adaptive) or method='gauss-legendre'")
    check_options(rtol, atol, None)
    if backend != "c":
        _check_backend(backend, method, events, scheduler)
        if inputs is not None:
            raise SimulationError(f"backend={backend!r} runs the model with its inputs off; inputs need the "
                                  "compiled C ensembles.", fix="use backend='c' (the default) with inputs")
    out_path = Path(out) if out is not None else None
    if out_path is not None and out_path.suffix not in (".zarr", ".nc"):
        raise OutputError(f"`{out_path}`: an ensemble is written to a Zarr store (.zarr) or a NetCDF file (.nc).",
                          fix="name it e.g. map.zarr or map.nc")
    if resume and (out_path is None or out_path.suffix != ".zarr"):
        raise SimulationError("resume finishes an interrupted Zarr store, so it needs out='....zarr'.",
                              fix="give the store the interrupted run wrote")
    _require("xarray", "xarray")
    if out_path is not None:
        for module in ("zarr",) if out_path.suffix == ".zarr" else ("h5netcdf", "h5py"):
            _require(module, "xarray, zarr, h5netcdf and h5py")
    return out_path


def _check_backend(backend: str, method: str, events, scheduler) -> None:
    if backend not in BACKENDS:
        raise SimulationError(f"backend={backend!r}: the ensemble backends are "
                              f"{', '.join(repr(b) for b in ('c', *BACKENDS))}.", fix="e.g. backend='c'")
    if method != "dop853" or events or scheduler is not None:
        raise SimulationError(f"backend={backend!r} integrates with an adaptive Dormand-Prince 8 method, without "
                              "events and without a Dask scheduler.",
                              fix="use method='dop853', no events and no scheduler, or backend='c'")


def _require(module: str, what: str) -> None:
    try:
        __import__(module)
    except ImportError:
        raise SimulationError(f"Ensembles need {what} ({module} is not installed).",
                              fix="pip install 'lagrangian[ensemble]'") from None


def connect_scheduler(scheduler):
    """A ``distributed.Client`` for ``scheduler`` (an address, or a Client given back as is).

    Parameters
    ----------
    scheduler : str or distributed.Client
        A Dask scheduler address, or a client.

    Returns
    -------
    client : distributed.Client
        The client.
    opened : bool
        Whether the client was opened here (the caller closes it then).

    Raises
    ------
    SimulationError
        Dask's distributed package missing, or the scheduler cannot be reached.
    """
    return _client(scheduler)


def _client(scheduler):
    try:
        from distributed import Client
    except ImportError:
        raise SimulationError("Running on a Dask cluster needs Dask's distributed package, which is not installed.",
                              fix="pip install 'lagrangian[distributed]'") from None
    if isinstance(scheduler, Client):
        return scheduler, False
    if not isinstance(scheduler, str):
        raise SimulationError(f"scheduler={scheduler!r}: give an address such as 'tcp://host:8786' or a "
                              "distributed.Client.", fix="e.g. scheduler='tcp://127.0.0.1:8786'")
    try:
        client = Client(scheduler, timeout=CONNECT_TIMEOUT, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise SimulationError(f"The Dask scheduler at `{scheduler}` cannot be reached ({exc}); nothing was run.",
                              fix="start one with `dask scheduler` (it prints its address, tcp://HOST:8786) and "
                                  "workers with `dask worker tcp://HOST:8786`, then give that address") from None
    return client, True


def _member_inputs(inputs):
    """(the law for the compiled system, the per-member feedbacks or None) of ``ensemble``'s ``inputs``."""
    from ..analysis import Feedback

    if isinstance(inputs, (list, tuple)):
        if not inputs or not all(isinstance(f, Feedback) for f in inputs):
            raise SimulationError("Per-member inputs are a sequence of Feedback values, one per member.",
                                  fix="e.g. inputs=[lqr(model, Q=q) for q in weights], or one law for all members")
        first = inputs[0]
        for f in inputs[1:]:
            if f.states != first.states or f.inputs != first.inputs:
                raise SimulationError("The members' feedbacks must have the same states and inputs (one compiled law "
                                      f"for all): {first.states}/{first.inputs} and {f.states}/{f.inputs} differ.",
                                      fix="design every member's feedback on the same states and inputs")
        return first, list(inputs)
    return inputs, None


def _kernel(system, specs, method, ctl, t_out, t_start, t_end) -> Kernel:
    integrals = tuple(system.integrals)
    return Kernel(
        source=system.generated.units, key=system.generated.key, n=system.n,
        n_params=len(system.parameters), n_constants=system._constants, monitors=tuple(system.monitors),
        integrals=integrals, momenta=tuple(momenta(system.eom, integrals).items()), events=tuple(system.events),
        ev_dir=tuple(int(s.direction) for s in specs), ev_terminal=tuple(int(s.terminal) for s in specs),
        method=method, ctl=tuple(float(v) for v in ctl), t_out=tuple(float(v) for v in t_out),
        t_start=float(t_start), t_end=float(t_end),
        law=tuple(float(v) for v in system.law.data()) if system._law_size else ())


def _ensemble(source, t_end, t_start, initial, parameters, initial_names, parameter_names, n_out, t_eval, method,
              rtol, atol, dt, max_step, max_steps, events, keep, workers, chunk_size, client, out_path, resume,
              progress, backend="c", stiffness_check=True, inputs=None):
    source, constrained = constrained_source(source)  # a file is read here, once
    if constrained is not None and any(c.unilateral for c in constrained.model.constraints):
        raise SimulationError("Ensembles run in compiled batches, and a model with unilateral contacts switches "
                              "its phases at impacts.", fix="use lagrangian.impact_sweep (or `lagrangian sweep`, "
                                                            "which runs it for such a model)")
    if constrained is not None or exact_contact_model(source) is not None:
        raise SimulationError("Ensembles run models without complementary constraints or exact (ε = 0) "
                              "friction; this one has them.", fix="use `simulate` for each motion of this model")

    if free_source(source) is not None:  # its Euler angles would meet their singularity, unsaid
        raise SimulationError("Ensembles integrate a model in its own coordinates, and this one has a free body, "
                              "whose Euler angles are singular somewhere: `simulate` integrates it on a unit "
                              "quaternion instead.", fix="use `simulate` for each motion of this model")
    specs = [EventSpec(e, e) if isinstance(e, str) else e for e in events]
    if backend != "c":
        system = resolve(source, [], "symengine")  # for its names only: no C compiler needed
        return _ensemble_backend(system, backend, t_end, t_start, initial, parameters, initial_names,
                                 parameter_names, n_out, t_eval, method, rtol, atol, max_step, max_steps, keep,
                                 chunk_size, out_path, resume, progress)
    law_inputs, feedbacks = _member_inputs(inputs)
    system = resolve(source, specs, "c", law_inputs)
    if not specs:
        specs = [EventSpec(name, name) for name in system.events]
    if system.backend != "c":
        raise SimulationError("Ensembles run in compiled C, and no C compiler was found.",
                              fix="install a C compiler (e.g. gcc)")
    if system.law.callables:
        raise SimulationError(f"The input `{system.law.callables[0].name}` is a Python function; ensembles run "
                              "compiled laws only (their members run in parallel, without Python).",
                              fix="write the input as an expression or an InputTable, or use simulate for each motion")
    group = members(system, initial, parameters, initial_names=initial_names, parameter_names=parameter_names)
    # Inputs held at a value other than 0 by some member are constant inputs (their integrals).
    driven = set(system.inputs)
    constant = [u for u in system.eom.model.inputs
                if u not in driven and np.any(group.P[:, system.parameters.index(u)] != 0)]
    if constant and any(system.regime[u] == "off" for u in constant):
        system = CompiledSystem(system.eom, events=list(system._events),
                                backend="c", inputs=system.law, constant_inputs=constant)
    if feedbacks is not None:
        if len(feedbacks) != group.count:
            raise SimulationError(f"{len(feedbacks)} feedbacks were given for {group.count} members.",
                                  fix="give one feedback per member, or one for all")
        group = replace(group, L=np.stack([system.law.data(f) for f in feedbacks]))
    n2 = 2 * system.n
    t_out = output_times(float(t_start), float(t_end), n_out, t_eval, 2 * n2 + len(system.monitors))
    ctl = control_block(method, float(t_start), float(t_end), t_out, rtol, atol, dt, max_step, max_steps,
                        stiffness_check=stiffness_check)
    kernel = _kernel(system, specs, method, ctl, t_out, t_start, t_end)

    count = group.count
    width = len(t_out) * (3 * n2 + max(len(system.monitors), 1)) * 8  # bytes per member in a chunk
    n_workers = _dask_workers(client) if client is not None else max(1, int(workers or _cores()))
    if chunk_size is None:
        chunk_size = max(1, min(256 if client is None else 4096, math.ceil(count / (4 * n_workers))))
    chunk_size = int(max(1, min(chunk_size, CHUNK_MEMORY // width or 1)))
    states = tuple(system.coordinates) + tuple(c + "_dot" for c in system.coordinates)
    run = {"model": kernel.key[:16], "members": _digest(group.Y0, group.P, *([] if group.L is None else [group.L])),
           "t_start": float(t_start),
           "t_end": float(t_end), "n_out": len(t_out), "t_out": _digest(t_out), "method": method, "rtol": rtol,
           "atol": atol, "dt": dt, "max_step": max_step, "max_steps": int(max_steps), "keep": keep,
           "events": [[s.name, str(s.expression), s.direction, bool(s.terminal)] for s in specs]}
    if not stiffness_check:  # only when off, so that stores written before the option still resume
        run["stiffness_check"] = False
    if system.law:  # likewise: only with inputs
        run["inputs"] = [repr(system.law.structure()), _digest(np.array(kernel.law))]
    grid_axes = tuple((name, len(values)) for name, values in group.grid.axes) if isinstance(group.grid, Grid) \
        else None
    layout = Layout(count, t_out, states, tuple(system.events), tuple(system.integrals), keep, group.swept,
                    grid_axes, run)
    sink, chunk_size = _open_sink(layout, out_path, chunk_size, resume)
    pending = sink.pending()
    chunks = [(a, min(a + chunk_size, count)) for a in range(0, count, chunk_size)
              if pending[a:min(a + chunk_size, count)].any()]
    reporter = _reporter(progress, count)
    done = int(count - pending.sum())
    stop = np.zeros(1)
    if client is not None:
        interrupted = _run_dask(client, kernel, group, chunks, keep, sink, reporter, done)
    else:
        interrupted = _run_threads(kernel, group, chunks, keep, sink, reporter, done, n_workers, stop)
    return _finish(sink, reporter, progress, interrupted, out_path)


def _ensemble_backend(system, backend, t_end, t_start, initial, parameters, initial_names, parameter_names, n_out,
                      t_eval, method, rtol, atol, max_step, max_steps, keep, chunk_size, out_path, resume, progress):
    """`ensemble` on a registered backend (`BACKENDS`): its chunks one after another, in this thread
    (the backend parallelises a chunk itself: vmap on a GPU); Ctrl-C between two chunks."""
    group = members(system, initial, parameters, initial_names=initial_names, parameter_names=parameter_names)
    n2 = 2 * system.n
    t_out = output_times(float(t_start), float(t_end), n_out, t_eval, 2 * n2)
    key, run_members = BACKENDS[backend](system.eom, t_start=float(t_start), t_end=float(t_end), t_out=t_out,
                                         rtol=rtol, atol=atol, max_step=max_step, max_steps=int(max_steps), keep=keep)
    count = group.count
    width = len(t_out) * 2 * n2 * 8  # bytes per member in a chunk
    chunk_size = int(max(1, min(chunk_size or 4096, count, CHUNK_MEMORY // width or 1)))
    states = tuple(system.coordinates) + tuple(c + "_dot" for c in system.coordinates)
    run = {"model": key[:16], "backend": backend, "members": _digest(group.Y0, group.P), "t_start": float(t_start),
           "t_end": float(t_end), "n_out": len(t_out), "t_out": _digest(t_out), "method": method, "rtol": rtol,
           "atol": atol, "max_step": max_step, "max_steps": int(max_steps), "keep": keep, "events": []}
    grid_axes = tuple((name, len(values)) for name, values in group.grid.axes) if isinstance(group.grid, Grid) \
        else None
    layout = Layout(count, t_out, states, (), (), keep, group.swept, grid_axes, run)
    sink, chunk_size = _open_sink(layout, out_path, chunk_size, resume)
    pending = sink.pending()
    reporter = _reporter(progress, count)
    done = int(count - pending.sum())
    interrupted = False
    try:
        for a in range(0, count, chunk_size):
            b = min(a + chunk_size, count)
            if pending[a:b].any():
                done = _write(sink, group, a, b, run_members(group.Y0[a:b], group.P[a:b], chunk_size), reporter,
                              done)
    except KeyboardInterrupt:
        interrupted = True  # the finished chunks are written; the store says which members are pending
    return _finish(sink, reporter, progress, interrupted, out_path)


def _open_sink(layout: Layout, out_path: Path | None, chunk_size: int, resume: bool):
    """(sink, chunk size): where the rows go, the memory a kept run needs checked first."""
    count, n2 = layout.count, len(layout.states)
    if layout.keep and (out_path is None or out_path.suffix != ".zarr"):
        need = 8.0 * count * len(layout.t_out) * n2
        if need > memory_limit():
            raise SimulationError(f"Keeping {count} trajectories of {len(layout.t_out)} times would take about "
                                  f"{need / 2**30:.1f} GiB of memory.",
                                  fix="stream them to a Zarr store (out='....zarr'), use fewer output times, or "
                                      "keep='summary'")
    if out_path is not None and out_path.suffix == ".zarr":
        sink = ZarrSink(out_path, layout, chunk_size, resume=resume)
        return sink, sink.chunk  # a resumed store keeps its own chunks, whatever this machine's cores
    if out_path is not None and (out_path.is_dir() or not out_path.parent.resolve().is_dir()):
        raise OutputError(f"`{out_path}` cannot be written: it is a folder, or its folder does not exist.",
                          fix="give a file name ending in .nc in an existing folder")
    return MemorySink(layout), chunk_size


def _finish(sink, reporter, progress, interrupted: bool, out_path: Path | None):
    """The run's Dataset (and its NetCDF file); `EnsembleInterrupted` after Ctrl-C."""
    count = sink.layout.count
    if reporter is not None:
        finished = int((~sink.pending()).sum())
        reporter.finish(finished, finished == count)
        if progress is True and finished < count:
            sys.stderr.write("\n")
    if interrupted:
        finished = int((~sink.pending()).sum())
        exc = EnsembleInterrupted(finished, count)
        exc.written = str(out_path) if out_path is not None and out_path.suffix == ".zarr" else None
        exc.dataset = sink.dataset() if isinstance(sink, MemorySink) else None
        raise exc
    if out_path is not None and out_path.suffix == ".nc":
        _write_netcdf(sink.dataset(flat=True), out_path)
    return sink.dataset()


def _digest(*arrays: np.ndarray) -> str:
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a, dtype=float).tobytes())
    return h.hexdigest()[:32]


def _write_netcdf(ds, path: Path) -> None:
    from .._atomic import write_atomic_with

    data = ds.to_netcdf(engine="h5netcdf")  # bytes: written beside the target, then moved over it
    write_atomic_with(path, lambda handle: handle.write(bytes(data)))


def members_bar(fraction: float, done: float) -> None:
    """A progress bar over members on standard error."""
    width = 30
    filled = int(width * fraction)
    sys.stderr.write(f"\r  [{'#' * filled}{'.' * (width - filled)}] {100 * fraction:5.1f} %  {int(done)} members")
    if fraction >= 1.0:
        sys.stderr.write("\n")
    sys.stderr.flush()


def _reporter(progress, count: int) -> Reporter | None:
    if not progress:
        return None
    return Reporter(members_bar if progress is True else progress, 0.0, float(count))


class _SigintStop:
    """While active (main thread only), Ctrl-C sets ``stop`` instead of raising: the chunks return
    at their next step and the finished rows are written before `EnsembleInterrupted` is raised,
    so a write is never cut in half."""

    def __init__(self, stop: np.ndarray) -> None:
        self.stop, self.hit = stop, False
        self.previous: Any = None  # the SIGINT handler replaced, given back on exit

    def __enter__(self) -> _SigintStop:
        if threading.current_thread() is threading.main_thread():
            self.previous = signal.signal(signal.SIGINT, self._handler)
        return self

    def _handler(self, signum, frame) -> None:
        self.hit = True
        self.stop[0] = 1.0

    def __exit__(self, *exc) -> None:
        if self.previous is not None:
            signal.signal(signal.SIGINT, self.previous)


def _write(sink, group, a: int, b: int, rows: dict, reporter, done: int) -> int:
    sink.write(a, b, rows)
    done += int(np.count_nonzero(rows["status"] != PENDING))
    if reporter is not None:
        reporter.update(done)
    return done


def _run_threads(kernel, group, chunks, keep, sink, reporter, done, n_workers, stop) -> bool:
    """Chunks in ``n_workers`` threads, at most two per thread in flight (bounded memory).

    The rows are written by the main thread, as chunks finish."""
    todo = list(reversed(chunks))
    with _SigintStop(stop) as guard, ThreadPoolExecutor(max_workers=n_workers,
                                                        thread_name_prefix="lagrangian-ensemble") as pool:
        running: dict = {}
        while todo or running:
            while todo and len(running) < 2 * n_workers and not guard.hit:
                a, b = todo.pop()
                running[pool.submit(run_chunk, kernel, group.Y0[a:b], group.P[a:b], keep, stop,
                                    None if group.L is None else group.L[a:b])] = (a, b)
            if not running:
                break
            finished, _ = wait_threads(list(running), timeout=0.1, return_when=FIRST_COMPLETED)
            try:
                for future in finished:
                    a, b = running.pop(future)
                    done = _write(sink, group, a, b, future.result(), reporter, done)
            except BaseException:
                stop[0] = 1.0  # the other chunks return at their next step instead of running on
                raise
            if guard.hit:
                todo = []
    return guard.hit


def _dask_workers(client) -> int:
    try:
        return max(1, len(client.scheduler_info().get("workers", {})))
    except Exception:  # noqa: BLE001 - a count for chunking only
        return 1


def _run_dask(client, kernel, group, chunks, keep, sink, reporter, done) -> bool:
    """Chunks as Dask tasks (run again when their worker dies), gathered and written here as they finish."""
    from distributed import wait as wait_dask

    token = hashlib.sha256(f"{kernel.key}{time.time_ns()}".encode()).hexdigest()[:12]
    kernel_future = client.scatter(kernel, broadcast=True, hash=False)
    window = 4 * _dask_workers(client)
    todo = list(reversed(list(enumerate(chunks))))
    running: dict = {}
    stop = np.zeros(1)
    with _SigintStop(stop) as guard:
        try:
            while todo or running:
                while todo and len(running) < window and not guard.hit:
                    i, (a, b) = todo.pop()
                    future = client.submit(run_chunk, kernel_future, group.Y0[a:b], group.P[a:b], keep, None,
                                           None if group.L is None else group.L[a:b],
                                           key=f"lagrangian-chunk-{token}-{i}", retries=3, pure=False)
                    running[future] = (a, b)
                if guard.hit or not running:
                    break
                try:
                    finished = wait_dask(list(running), timeout=0.1, return_when="FIRST_COMPLETED").done
                except TimeoutError:
                    finished = set()
                for future in finished:
                    a, b = running.pop(future)
                    try:
                        rows = future.result()
                    except Exception as exc:  # noqa: BLE001 - a task failed even after Dask's retries
                        raise SimulationError(f"A Dask task (members {a} to {b - 1}) failed: {exc}",
                                              fix="check the workers' logs; finished members are kept") from None
                    done = _write(sink, group, a, b, rows, reporter, done)
        finally:
            if running:
                client.cancel(list(running))
    return guard.hit
