"""``lagrangian simulate MODEL.toml --t-end 10 [--set NAME=VALUE ...] [--input NAME=VALUE ...] [--feedback FILE.json]
[--out traj.csv|traj.npz] [--plot [DIR]]``.

Everything that can be checked before the run is (the output's suffix and folder, the plot
folder, ffmpeg for an MP4), so that a bad option never costs a run or an older file.
"""

from __future__ import annotations

import argparse
import io
import shutil
import sys
import time
from pathlib import Path

from .._atomic import check_destination
from ..dynamics import derive
from ..errors import Interrupted, OutputError, SimulationError
from ..numerics import EventSpec, check_output_path, compile_system, save_trajectory, simulate
from ._input_option import parse_inputs
from ._settings import parse_settings
from ._source import load_source

__all__ = ["run"]

def plot_folder(args: argparse.Namespace) -> Path | None:
    """The --plot folder: DIR, or ``<model stem>_plots`` (``plots`` for the built-in top) for a bare --plot."""
    if args.plot is None:
        return None
    if args.plot:
        return Path(args.plot)
    return Path(f"{Path(args.model).stem}_plots") if args.model else Path("plots")


def _ffmpeg() -> str | None:
    """An ffmpeg executable: matplotlib's setting or the PATH, else the imageio-ffmpeg package's (when installed)."""
    import matplotlib

    found = shutil.which(matplotlib.rcParams["animation.ffmpeg_path"]) or shutil.which("ffmpeg")
    if found:
        return found
    try:
        import imageio_ffmpeg
    except ImportError:
        return None
    try:
        return imageio_ffmpeg.get_ffmpeg_exe()
    except (RuntimeError, OSError):
        return None


def _check_outputs(args: argparse.Namespace, plots: Path | None) -> None:
    """Refuse, before the run, the outputs that would fail after it."""
    if args.out:
        check_output_path(args.out)
    if args.view:
        if Path(args.view).suffix.lower() not in (".html", ".htm"):
            raise OutputError(f"`--view {args.view}`: the view is an HTML page.", fix="name it e.g. motion.html")
        check_destination(args.view, name_fix="give a file name after --view")
    if plots is None:
        return
    if plots.exists() and not plots.is_dir():
        raise OutputError(f"`--plot {plots}`: `{plots}` is a file, not a folder.",
                          fix="give a folder for the plots (a bare --plot goes after the model file)")
    try:
        import matplotlib
    except ImportError as exc:
        raise SimulationError(f"Plots need matplotlib ({exc}).", fix="pip install 'lagrangian[plot]'") from None
    if args.animation == "mp4":
        ffmpeg = _ffmpeg()
        if ffmpeg is None:
            raise OutputError("Writing an MP4 needs ffmpeg, which is not installed.",
                              fix="install ffmpeg (or `pip install imageio-ffmpeg`), or use --animation gif")
        matplotlib.rcParams["animation.ffmpeg_path"] = ffmpeg


def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    parameters, initial = parse_settings(args.set, model)
    inputs = parse_inputs(args.input, model, time_column=args.input_time_column, feedback=args.feedback,
                          switch_at=args.switch_at)
    plots = plot_folder(args)
    _check_outputs(args, plots)
    eom = derive(model)
    events = [EventSpec(text, text) for text in args.event]
    events += [EventSpec(f"stop: {text}", text, terminal=True) for text in args.stop_when]
    # simulate compiles events in, sends constrained models to its DAE path and free bodies to their quaternions
    free = any(b.free for b in model.bodies)
    system = eom if events or eom.constraints or free else compile_system(eom, inputs=inputs)
    progress = sys.stderr.isatty() if args.progress is None else args.progress
    start = time.perf_counter()
    try:
        traj = simulate(system, args.t_end, t_start=args.t_start, initial=initial,
                        parameters=parameters, method=args.method, rtol=args.rtol, atol=args.atol, dt=args.dt,
                        n_out=args.n_out, events=events, tolerance=args.tolerance, progress=progress,
                        stabilization=args.stabilization, stiffness_check=args.stiffness_check, inputs=inputs)
    except Interrupted as exc:
        # Ctrl-C: what was computed is kept in the file asked for, its header saying
        # "interrupted ... (partial)"; `main` prints the one line and exits 130.
        if args.out and exc.trajectory is not None:
            exc.written = str(save_trajectory(exc.trajectory, args.out))
        raise
    except SimulationError as exc:
        # Stopped early (stiff equations, max steps): the part computed so far is kept the same way.
        if args.out and exc.trajectory is not None:
            written = save_trajectory(exc.trajectory, args.out)
            exc.message += f" The part computed so far is in {written} (marked partial)."
        raise
    elapsed = time.perf_counter() - start
    # What the reactions are for: the course's pin and contact reactions (R_O of the top). A
    # robot's only one is the ground's wrench on the whole arm, whose expanded Newton–Euler
    # formula grows steeply with the joints (seconds at 12): asked for, not by default.
    reactions = args.reactions if args.reactions is not None else eom.formulation != "recursive" and not free
    left_out = ""
    if reactions and args.reactions is None:
        # Asked for by default only: a value they alone need (a ring's mass a gyroscope leaves out) does not stop
        # the simulation; one line says what they would need.
        traj, left_out = _with_reactions_if_possible(traj, eom)
    elif reactions:
        traj = _with_reactions(traj, eom)
    lines = [
        (f"{model.name}: t from {traj.t[0]:g} to {traj.t[-1]:g} with {traj.method}, {traj.steps} steps, "
         f"{traj.rhs_calls} right-hand-side calls, {elapsed * 1e3:.1f} ms"),
        "conservation: " + (traj.drift_summary() or "no first integral to monitor"),
    ]
    applied = describe_inputs(inputs, model)
    if applied:
        lines.insert(1, "inputs: " + applied)
    constraint = {k[len("drift_"):]: v for k, v in traj.drift.items() if k.startswith("drift_")}
    if constraint:
        lines.append("constraint drift (max residual): "
                     + ", ".join(f"{name} {value:.1e}" for name, value in constraint.items()))
    if args.reactions is None and not reactions and not free:
        lines.append("reactions: not computed for a kinematic tree (the ground's wrench on it); --reactions adds "
                     "them")
    if left_out:
        lines.append(left_out)
    lines += [f"warning: {w}" for w in traj.warnings]
    if traj.events:
        lines.append(f"events: {len(traj.events)} — " + ", ".join(f"{e.name} at t = {e.t:.9g}" for e in traj.events[:8])
                     + (" ..." if len(traj.events) > 8 else ""))
    if traj.status != "completed":
        lines.append(f"status: {traj.status}")
    outputs: list[str] = []
    if args.out:
        outputs.append(str(save_trajectory(traj, args.out)))
    if args.view:
        from ..view3d import view

        outputs.append(str(view(traj, eom).save(args.view)))
    if plots is not None:
        figures = _plots(traj, eom, plots, args.animation)
        lines.append(f"plots: {len(figures)} files in {plots}/")
        outputs += [str(p) for p in figures]
    if outputs:
        lines.append("wrote " + ", ".join(outputs))
    summary = "\n".join(lines) + "\n"
    if args.out or plots is not None or args.view:
        return summary
    # No file asked for: the table goes to standard output, the summary to standard error.
    sys.stderr.write(summary)
    text = io.StringIO()
    columns = traj.columns()
    text.write(",".join(columns) + "\n")
    row_format = ",".join(["%.17g"] * len(columns)) + "\n"  # one formatting per row: a third of the time
    for row in traj.table().tolist():
        text.write(row_format % tuple(row))
    return text.getvalue()


def describe_inputs(inputs, model) -> str:
    """``F = 2*sin(3*t), G = feedback`` for the summary: the inputs given, then the model's [controls]."""
    from ..analysis import Feedback
    from ..numerics import Switch

    parts = []
    given = dict(inputs or {})
    for name in model.inputs:
        value = given.get(name)
        if isinstance(value, Feedback):
            parts.append(f"{name} = u* - K (x - x*) (feedback)")
        elif isinstance(value, Switch):
            before, _ = value.sources
            parts.append(f"{name} = {before!r} until t = {value.at[0]:g}, then u* - K (x - x*) (feedback)")
        elif value is not None:
            parts.append(f"{name} = {value!r}" if not isinstance(value, str) else f"{name} = {value}")
        elif name in dict(model.controls):
            parts.append(f"{name} = {dict(model.controls)[name]} ([controls])")
    return ", ".join(parts)


def _with_reactions(traj, eom):
    """The trajectory with each reaction's force (and transmitted moment) as extra columns."""
    from dataclasses import replace

    from ..errors import LagrangianError
    from ..numerics import reaction_columns_along

    try:
        columns = reaction_columns_along(eom, traj)
    except LagrangianError as exc:  # a mass or a value only the reactions need
        exc.fix = (exc.fix + "; " if exc.fix else "") + "or simulate without the reactions: --no-reactions"
        raise
    return replace(traj, extra={**traj.extra, **columns})


def _with_reactions_if_possible(traj, eom):
    """(trajectory with the reactions, "") or, when they need values the model leaves out, (trajectory, the one
    line saying which): the bodies without a mass (their weight bears on their axle), or the error's own words."""
    from dataclasses import replace

    from ..errors import LagrangianError
    from ..numerics import reaction_columns_along

    try:
        columns = reaction_columns_along(eom, traj)
    except LagrangianError as exc:
        missing = [b.name for b in eom.model.bodies if not b.mass_given]
        if missing and "mass of body" in exc.message:
            names = ", ".join(f"`{name}`" for name in missing)
            what = "the mass of body" if len(missing) == 1 else "the masses of bodies"
            return traj, (f"reactions: not computed: they need {what} {names}, which the model leaves out (give "
                          f'mass = "..." under [bodies.{missing[0]}]; the motion does not need it)')
        return traj, f"reactions: not computed: {exc.message}" + (f" ({exc.fix})" if exc.fix else "")
    return replace(traj, extra={**traj.extra, **columns}), ""


def _plots(traj, eom, directory: Path, animation: str) -> list:
    try:
        from ..plotting import save_plots
    except ImportError as exc:  # matplotlib missing: the plotting package says how to install it
        raise SimulationError(f"Plots need matplotlib ({exc}).", fix="pip install 'lagrangian[plot]'") from None
    if animation == "none":
        return save_plots(traj, eom, directory, animation=False)
    return save_plots(traj, eom, directory, animation_format=animation)
