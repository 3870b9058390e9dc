"""Read an optimal-control problem file (TOML) into a `Problem`.

The format (docs/optimal-control.md)::

    [problem]      model (path, relative to this file), t_end (a number or "free"), t_start, nodes,
                   method, objective (a word, or the [objective] table), path (a list of comparisons)
    [parameters]   overrides of the model's values:        m = 0.3
    [initial]      values at t0, by column:                theta = "pi"
    [final]        values at the final time:               theta = 0
    [bounds]       column (or t_end) = [low, high]:         F = [-20, 20]
    [objective]    effort, time, running, terminal, track, track_weights
    [path]         named path constraints:                 rail = "-2 <= x <= 2"
    [solver]       tolerance, max_iterations, hessian, t_guess, guess

Text is TOML read by the standard library's `tomllib` (nesting checked first, as for model files)
and expressions by the model grammar, never evaluated.  Errors name the file and the line.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import ProblemError
from ..model import check_nesting
from ._problem import Problem

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["load_problem", "locate", "parse_problem"]

_TABLES = ("problem", "parameters", "initial", "final", "bounds", "objective", "path", "solver")
_PROBLEM_KEYS = ("model", "t_end", "t_start", "nodes", "method", "objective", "path")
_SOLVER_KEYS = ("tolerance", "max_iterations", "hessian", "t_guess", "guess")
_HEADER = re.compile(r"^\s*\[\s*([A-Za-z0-9_.\-]+)\s*\]")
_KEY = re.compile(r"^\s*([A-Za-z0-9_\-]+|\"[^\"]*\")\s*=")


def load_problem(path: str | Path) -> Problem:
    """Read the problem file at ``path`` (module docstring).

    Parameters
    ----------
    path : str or Path
        The problem file.

    Returns
    -------
    Problem
        The problem it states.

    Raises
    ------
    ProblemError
        With the file and the line: a missing file, bad TOML, an unknown table or key, a value of
        the wrong kind.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ProblemError(f"problem file `{path}` does not exist", file=str(path),
                           fix="check the path (examples/optimal/ holds problems to start from)") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ProblemError(f"cannot read problem file `{path}`: {exc}", file=str(path)) from None
    return parse_problem(text, source=str(path))


def parse_problem(text: str, *, source: str | None = None) -> Problem:
    """Read a problem from TOML ``text``; ``source`` names the file (and its folder anchors ``model``)."""
    check_nesting(text, source)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        line = re.search(r"at line (\d+)", str(exc))
        raise ProblemError(f"TOML syntax error: {re.sub(r' [(]at line.*[)]', '', str(exc))}", file=source,
                           line=int(line.group(1)) if line else None,
                           fix="correct the TOML syntax of this line (strings in quotes, `key = value`)") from None
    lines = text.splitlines()

    def fail(message: str, table: str, key: str | None = None, fix: str | None = None) -> ProblemError:
        return ProblemError(message, file=source, line=_line_of(lines, table, key), symbol=key, fix=fix)

    for table, value in data.items():
        if table not in _TABLES:
            raise fail(f"unknown table `[{table}]` in a problem file", table,
                       fix="the tables are " + ", ".join(f"[{t}]" for t in _TABLES))
        if not isinstance(value, Mapping):
            raise fail(f"`{table}` must be a table ([{table}])", table)
    head = data.get("problem", {})
    for key in head:
        if key not in _PROBLEM_KEYS:
            raise fail(f"unknown key `{key}` in [problem]", "problem", key, fix="the keys are " + ", ".join(_PROBLEM_KEYS))
    solver = data.get("solver", {})
    for key in solver:
        if key not in _SOLVER_KEYS:
            raise fail(f"unknown key `{key}` in [solver]", "solver", key, fix="the keys are " + ", ".join(_SOLVER_KEYS))
    for key in ("model", "t_end"):
        if key not in head:
            raise fail(f"[problem] needs `{key}`", "problem", None,
                       fix="model = \"the_model.toml\"" if key == "model" else "t_end = 2.0 (or \"free\")")
    model = head["model"]
    if not isinstance(model, str) or not model:
        raise fail("`model` must be the path of a model file (text)", "problem", "model")
    if source is not None and not Path(model).is_absolute():
        model = str(Path(source).parent / model)
    if "objective" in head and "objective" in data:
        raise fail("the objective is given twice: `objective` in [problem] and the table [objective]", "objective",
                   fix="keep one of them")
    path_constraints: Any = head.get("path", [])
    if "path" in data:
        if "path" in head:
            raise fail("path constraints are given twice: `path` in [problem] and the table [path]", "path",
                       fix="keep one of them")
        path_constraints = list(data["path"].values())
    if not isinstance(path_constraints, list) or not all(isinstance(p, str) for p in path_constraints):
        raise fail("path constraints are comparisons written as text, e.g. \"x^2 + y^2 <= 1\"", "problem", "path")
    for table in ("initial", "final", "bounds", "parameters"):
        for key, value in data.get(table, {}).items():
            ok = (isinstance(value, list) and len(value) == 2) if table == "bounds" else \
                isinstance(value, (int, float, str)) and not isinstance(value, bool)
            if table == "parameters":
                ok = isinstance(value, (int, float)) and not isinstance(value, bool)
            if not ok:
                kind = "a pair [low, high]" if table == "bounds" else "a number" + (
                    "" if table == "parameters" else " or an expression of the parameters")
                raise fail(f"`{key}` in [{table}] must be {kind}, not {value!r}", table, key)
    fields: dict[str, Any] = {
        "model": model, "t_end": head["t_end"], "initial": data.get("initial", {}), "final": data.get("final", {}),
        "bounds": {k: tuple(v) for k, v in data.get("bounds", {}).items()},
        "objective": data.get("objective", head.get("objective", "effort")), "path": path_constraints,
        "parameters": data.get("parameters", {}), "source": source,
        **{k: head[k] for k in ("t_start", "nodes", "method") if k in head},
        **{k: solver[k] for k in _SOLVER_KEYS if k in solver},
    }
    try:
        return Problem(**fields)
    except ProblemError as exc:
        raise locate(exc, source, lines) from None


def locate(error: ProblemError, source: str | None, lines: list[str] | None = None) -> ProblemError:
    """``error`` with the file and the line of its symbol in the problem file ``source`` (when it names one)."""
    if source is None or error.line is not None:
        return error
    if lines is None:
        try:
            lines = Path(source).read_text(encoding="utf-8").splitlines()
        except (OSError, UnicodeDecodeError):
            return error
    error.file = source
    if error.symbol and error.table is not None:
        error.line = _line_of(lines, error.table, error.symbol, exact=True)
    elif error.symbol:
        for table in _TABLES:
            line = _line_of(lines, table, error.symbol, exact=True)
            if line is not None:
                error.line = line
                break
    return error


def _line_of(lines: list[str], table: str, key: str | None, exact: bool = False) -> int | None:
    """The 1-based line of ``key = `` in ``[table]`` (of the table's header without a key), or None."""
    current = None
    header = None
    for number, line in enumerate(lines, start=1):
        match = _HEADER.match(line)
        if match:
            current = match.group(1)
            if current == table:
                header = number
            continue
        if current == table and key is not None:
            found = _KEY.match(line)
            if found and found.group(1).strip('"') == key:
                return number
    return None if exact or (key is not None and header is None) else header
