"""``lagrangian modes MODEL --at ... [--set NAME=VALUE] [--sweep NAME=a:b:step] [--plot DIR] [--json] [-o FILE]``.

The eigenvalues of the linearized motion with their natural frequencies, periods, damping
ratios and mode shapes, and the stability verdict; ``--sweep`` follows them along one
parameter (A(v) compiled once) and gives the values where stability changes, found by root
finding; ``--plot DIR`` draws Re λ and Im λ against the parameter (Meijaard et al. 2007,
fig. 3, for the bicycle) and the mode shapes.  Nothing is written when anything fails.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from .. import __version__
from ..dynamics import derive
from ..errors import OutputError
from ..model.spec import Model
from ..output import linearize_document, modes_text, sweep_text
from ._arguments.modes import ANIMATIONS_MAX
from ._point import linearize_from_args
from ._settings import SettingError, plain_number
from ._source import load_source

__all__ = ["SWEEP_MAX", "parse_sweep", "run"]

#: Largest coordinate amplitude of an animated mode (rad or the coordinate's unit).
AMPLITUDE = 0.1

#: Most points a sweep may have (a 10⁶-point sweep of a 4 × 4 A takes seconds; more is a typo).
SWEEP_MAX = 1_000_000


def parse_sweep(text: str, model: Model) -> tuple[str, np.ndarray]:
    """``"v=0:10:0.01"`` → ("v", [0, 0.01, ..., 10]): b is included when it falls on the grid.

    Raises
    ------
    SettingError
        Bad form, a NAME that is not a parameter, numbers that are not finite, a step that is
        not positive, a range with no point (b < a), or more than `SWEEP_MAX` points.
    """
    name, sep, rng = text.partition("=")
    name = name.strip()
    parts = rng.split(":")
    if not sep or not name or len(parts) != 3:
        raise SettingError(f"`--sweep {text}` is not of the form NAME=a:b:step.",
                           fix="write e.g. `--sweep v=0:10:0.01`")
    params = [p.name for p in model.parameters]
    if name not in params:
        what = "a coordinate" if name in [c.name for c in model.coordinates] else "not a name"
        raise SettingError(f"`--sweep {text}`: `{name}` is {what} of `{model.name}`; a sweep follows a parameter.",
                           fix="the parameters are " + (", ".join(params) or "(none)"))
    try:
        a, b, step = (plain_number(x) for x in parts)
    except ValueError:
        raise SettingError(f"`--sweep {text}`: a, b and step must be plain decimal numbers.",
                           fix="write e.g. `--sweep v=0:10:0.01`") from None
    if not all(math.isfinite(x) for x in (a, b, step)):
        raise SettingError(f"`--sweep {text}`: a, b and step must be finite.", fix="write e.g. `--sweep v=0:10:0.01`")
    if step <= 0:
        raise SettingError(f"`--sweep {text}`: the step {parts[2]} is not positive.",
                           fix=f"give a positive step, e.g. `--sweep {name}={parts[0]}:{parts[1]}:0.01`")
    if b < a:
        raise SettingError(f"`--sweep {text}`: the range from {parts[0]} to {parts[1]} has no point (b < a).",
                           fix=f"write the smaller bound first: `--sweep {name}={parts[1]}:{parts[0]}:{parts[2]}`")
    count = math.floor((b - a) / step * (1 + 1e-12) + 1e-9) + 1
    if count > SWEEP_MAX:
        raise SettingError(f"`--sweep {text}` has {count} points, more than {SWEEP_MAX}.",
                           fix="use a larger step")
    return name, a + step * np.arange(count)


def _check_plot_folder(folder: Path) -> None:
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"`--plot {folder}`: `{folder}` is a file, not a folder.", fix="give a folder for the plots")
    try:
        import matplotlib  # noqa: F401
    except ImportError as exc:
        raise OutputError(f"Plots need matplotlib ({exc}).", fix="pip install 'lagrangian[plot]'") from None


def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    sweep_name, values = parse_sweep(args.sweep, model) if args.sweep else (None, None)
    if sweep_name is not None and any(s.partition("=")[0].strip() == sweep_name for s in args.set):
        raise SettingError(f"`{sweep_name}` is both swept and given a value with `--set`.", fix="drop the `--set`")
    folder = Path(args.plot) if args.plot else None
    if args.animate and folder is None:
        raise SettingError("`--animate` writes its GIF files into the --plot folder.", fix="add --plot DIR")
    if folder is not None:
        _check_plot_folder(folder)
    eom = derive(model)
    from ..analysis import eigenvalue_sweep as sweep_of

    if sweep_name is None or values is None:  # no --sweep
        lin = lin_point = linearize_from_args(args, model, eom)
        swept = None
    else:
        lin = linearize_from_args(args, model, eom, symbolic=(sweep_name,))
        swept = sweep_of(lin, sweep_name, values)
        # The modes at the point are those at the model's value of the parameter, else at the sweep's start.
        value = model.parameter_values.get(sweep_name)
        lin_point = lin if not lin.symbols else None
        at_value = float(value) if value is not None else float(values[0])
    if lin_point is not None:
        stability, modes = lin_point.stability(), lin_point.modes()
    else:
        stability, modes = lin.stability(**{sweep_name: at_value}), lin.modes(**{sweep_name: at_value})
    text = modes_text(lin, stability, modes)
    if swept is not None:
        if lin.symbols:
            text = text.replace("\nStability:", f"\n(modes at {sweep_name} = {at_value:g})\nStability:", 1)
        unit = next((p.unit or "" for p in model.parameters if p.name == sweep_name), "")
        text += sweep_text(lin, swept, unit)
    written = _plots(lin, modes, swept, folder, args.lang) if folder is not None else []
    if args.animate:
        at = {sweep_name: at_value} if lin.symbols else {}
        written += _animations(lin, modes, folder, at)  # type: ignore[arg-type]
    if args.json:
        doc = linearize_document(lin, source=model.source, package_version=__version__, stability=stability,
                                 modes=modes, sweep=swept, modes_at={sweep_name: at_value} if lin.symbols else None)
        out = json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
    else:
        out = text + ("wrote " + ", ".join(str(p) for p in written) + "\n" if written else "")
    return out


def _plots(lin, modes, swept, folder: Path, lang: str) -> list[Path]:
    """Draw every figure first, then write them: a failure while drawing leaves the folder as it was."""
    from ..plotting import plot_eigenvalue_sweep, plot_mode_shapes, save_figure

    figures = []
    if swept is not None:
        figures.append(("eigenvalues.png", plot_eigenvalue_sweep(swept, lin.eom, lang=lang)))
    if modes.modes or modes.pulsations:
        figures.append(("mode_shapes.png", plot_mode_shapes(modes, lin.eom, lang=lang)))
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"Cannot create the folder `{folder}`: {exc.strerror or exc}.",
                          fix="check the path and its permissions") from None
    return [save_figure(fig, folder / name) for name, fig in figures]


def _animations(lin, modes, folder: Path, values: dict) -> list[Path]:
    """``mode_K.gif`` for each mode K as the text numbers them (a conjugate pair once)."""
    from ..plotting import animate, mode_trajectory

    out: list[Path] = []
    seen: list[complex] = []
    for index, mode in enumerate(modes.modes):
        z = mode.eigenvalue
        if z.imag != 0 and any(abs(z.conjugate() - s) <= 1e-9 * max(1.0, abs(z)) for s in seen):
            continue
        seen.append(z)
        if len(seen) > ANIMATIONS_MAX:
            break
        trajectory = mode_trajectory(lin, index, amplitude=AMPLITUDE, **values)
        out.append(animate(trajectory, lin.eom, folder / f"mode_{len(seen)}.gif", frames=60))
    return out
