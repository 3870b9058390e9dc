"""``--input NAME=VALUE`` and ``--feedback FILE.json``: what the inputs do during ``lagrangian simulate``.

VALUE is one of

* a plain decimal number: the input held there (``--input F=2.5``);
* ``@FILE[:COLUMN[:KIND]]``: samples from a CSV file with a header row — the column COLUMN
  (default: the input's name) against the time column (``--input-time-column``, default ``t``),
  read between samples by KIND, ``zoh``, ``linear`` (default), ``quadratic`` or ``cubic``
  (``--input F=@run.csv:force:zoh``);
* anything else: an expression in the model grammar of t, the coordinates, their rates
  ``<q>_dot`` and the parameters (``--input 'F=2*sin(3*t)'``), read by the model's own parser,
  never evaluated as Python.

``--feedback FILE.json`` (written by ``lagrangian lqr ... -o FILE.json``) closes the loop
u = u* − K (x − x*) on the inputs it computes; ``--input`` gives the others.  With ``--switch-at
TIME`` the feedback takes over at TIME: before it, its inputs follow their ``--input`` (0 where none
is given) — a swing-up's table, then the catch (`lagrangian.Switch`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..model.spec import Model
from ._arguments.common import add_input_options
from ._settings import SettingError, plain_number

__all__ = ["add_input_options", "parse_inputs"]

#: The interpolations of a table (`InputTable`), said in the help and the messages.
_KINDS = ("zoh", "linear", "quadratic", "cubic")
_KIND_LIST = "|".join(_KINDS)


def _table_spec(name: str, spec: str) -> tuple[Path, str, str]:
    """(path, column, interpolation) of ``@FILE[:COLUMN[:KIND]]``, the file found by trying the splits."""
    candidates = [(spec, name, "linear")]
    parts = spec.rsplit(":", 2)
    if len(parts) >= 2:
        candidates.append((":".join(parts[:-1]), parts[-1], "linear"))
    if len(parts) == 3:
        candidates.append((parts[0], parts[1], parts[2]))
    for path, column, kind in reversed(candidates):
        if Path(path).is_file():
            if kind not in _KINDS:
                raise SettingError(f"`--input {name}=@{spec}`: `{kind}` is not an interpolation.",
                                   fix=f"use one of {', '.join(_KINDS)}, e.g. --input F=@run.csv:F:zoh")
            return Path(path), column or name, kind
    raise SettingError(f"`--input {name}=@{spec}`: no file `{candidates[0][0] if len(parts) == 1 else parts[0]}`.",
                       fix=f"give an existing CSV file: --input NAME=@FILE[:COLUMN[:{_KIND_LIST}]]")


def parse_inputs(values: Sequence[str], model: Model, *, time_column: str = "t",
                 feedback: str | None = None, switch_at: float | None = None) -> dict[str, Any] | None:
    """The ``inputs=`` of `simulate` from ``--input``, ``--feedback`` and ``--switch-at`` (None when none
    is given).

    Raises
    ------
    SettingError
        Bad form, a name that is not a declared input, given twice, a value that is not finite,
        a CSV file that does not exist, an unknown interpolation, ``--switch-at`` without ``--feedback``
        or not finite.
    ControlError, SimulationError
        A feedback file or a table that cannot be read.
    """
    from ..analysis import Feedback
    from ..numerics import InputTable, Switch

    if switch_at is not None:
        if feedback is None:
            raise SettingError(f"`--switch-at {switch_at:g}` says when a feedback takes over, and no --feedback is given.",
                               fix="add --feedback FILE.json (written by lagrangian lqr ... -o FILE.json)")
        if not math.isfinite(switch_at):
            raise SettingError(f"`--switch-at {switch_at}` is not a finite time.", fix="give the time of the switch")
        before = parse_inputs(values, model, time_column=time_column) or {}
        fb = Feedback.load(feedback)
        after = parse_inputs((), model, feedback=feedback) or {}
        for name in fb.inputs:
            after[name] = Switch(before.pop(name, 0.0), fb, at=switch_at)
        return {**before, **after}
    declared = list(model.inputs)
    out: dict[str, Any] = {}
    if feedback is not None:
        fb = Feedback.load(feedback)
        for u in fb.inputs:
            if u not in declared:
                raise SettingError(f"The feedback `{feedback}` computes `{u}`, which is not an input of `{model.name}`.",
                                   fix="design the feedback on this model: lagrangian lqr MODEL ... -o FILE.json")
            out[u] = fb
    for item in values:
        name, sep, text = item.partition("=")
        name, text = name.strip(), text.strip()
        if not sep or not name or not text:
            raise SettingError(f"`--input {item}` is not of the form NAME=VALUE.",
                               fix="e.g. --input F=2.5, --input 'F=2*sin(3*t)' or --input F=@run.csv")
        if name not in declared:
            params = [p.name for p in model.parameters]
            raise SettingError(f"`{name}` in `--input {item}` is not a declared input of `{model.name}`"
                               + (" (it is a parameter)" if name in params else "") + ".",
                               fix=(f"give parameter values with --set {name}=VALUE" if name in params else
                                    "the inputs are " + (", ".join(declared) or "(none: declare them under [inputs])")))
        if name in out:
            raise SettingError(f"The input `{name}` is given twice" + (" (also by --feedback)." if feedback else "."),
                               fix="give each input once")
        if text.startswith("@"):
            path, column, kind = _table_spec(name, text[1:])
            out[name] = InputTable.from_csv(path, column, time_column=time_column, interpolation=kind)
            continue
        try:
            value = plain_number(text)
        except ValueError:
            out[name] = text  # an expression: read by the model grammar in `simulate`
            continue
        if not math.isfinite(value):
            raise SettingError(f"In `--input {item}`, the value {text} is not finite.", fix=f"give `{name}` a finite value")
        out[name] = value
    return out if out or feedback is not None else None
