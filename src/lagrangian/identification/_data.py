"""Measured motions for identification: read from a Trajectory, an xarray Dataset, a CSV file or arrays.

Every source becomes one `Measurements`: the sample times t (strictly increasing, finite)
and, by name, the columns measured at those times — coordinates (``theta``), rates
(``theta_dot``), accelerations (``theta_ddot``) and inputs (``F``, ``tau_elbow``).  Any
subset of the coordinates may be measured; a missing value (NaN, an empty CSV field), a time
that does not increase or a column that names nothing of the model is refused with the column
and the row.

CSV files are read as numbers only (Python's ``csv`` module and ``float`` on ASCII decimals):
one header line of names, ``#`` comment lines (those of ``lagrangian simulate --out``) skipped.
"""

from __future__ import annotations

import csv
import io
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import IdentificationError
from ..model.spec import Model

__all__ = ["MIN_SAMPLES", "Measurements", "read_measurements"]

#: Fewest samples a record may have.
MIN_SAMPLES = 5
#: A number of a CSV file: a plain ASCII decimal, or nan/inf (refused later as not finite, with its row);
#: Python's ``float`` alone would also take ``1_0`` and non-ASCII digits.
_NUMBER = re.compile(r"[+-]?(?:(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|nan|inf|infinity)", re.IGNORECASE)
#: Columns a simulation writes besides its states (`lagrangian simulate -o run.csv`): T, U, the first
#: integrals (E, H, K, momenta p_q, Noether's J_...) and the reactions and multipliers (R_..., lambda_...).
#: A record read whole (no ``columns``) sets them aside: they are outputs of the model, not measurements.
_SIMULATION_OUTPUTS = re.compile(r"(?:T|U|E|H|K|(?:p|J|R|lambda)_\w+)")
#: Largest CSV file read (bytes): a measured record, not a data lake.
MAX_CSV_BYTES = 512 * 2**20


@dataclass(frozen=True)
class Measurements:
    """A measured record: ``t`` (N,) and each measured column (N,) by name.

    Parameters
    ----------
    t : ndarray of shape (N,)
        The sample times.
    states : mapping of str to ndarray
        Coordinate or rate name (``theta``, ``theta_dot``) → samples.
    accelerations : mapping of str to ndarray
        Coordinate name → measured q̈ samples (``theta_ddot`` columns).
    inputs : mapping of str to ndarray
        Input name → samples of the input applied.
    source : str
        What the record came from, for messages.
    """

    t: np.ndarray
    states: Mapping[str, np.ndarray]
    accelerations: Mapping[str, np.ndarray]
    inputs: Mapping[str, np.ndarray]
    source: str

    def __len__(self) -> int:
        return len(self.t)


def read_measurements(data, model: Model, *, columns: Sequence[str] | None = None) -> Measurements:
    """The `Measurements` of ``data`` for ``model`` (module docstring).

    Parameters
    ----------
    data : Trajectory or xarray.Dataset or str or Path or mapping of str to array_like
        A `lagrangian.numerics.Trajectory`, an ``xarray.Dataset`` (a ``t`` or ``time`` coordinate, one
        variable per column), a path to a CSV file, or a mapping of ``"t"`` and column names to 1-D
        arrays.
    model : Model
        The model whose coordinates and inputs the columns name.
    columns : sequence of str, optional
        The columns to use (``t`` is always used); default all of them, except, in a file that
        `lagrangian simulate` wrote, the columns it computes besides the states (T, U, first
        integrals such as E or p_x, reactions ``R_...``, multipliers ``lambda_...``).  A Trajectory
        gives its q, q̇ (and its input columns when it has any) unless ``columns`` says otherwise.

    Returns
    -------
    Measurements
        The record, checked.

    Raises
    ------
    IdentificationError
        No ``t``, too few samples, a value that is not a finite number, times that do not
        strictly increase, columns of different lengths, or a column that is neither a
        coordinate, a rate, an acceleration nor an input of the model.
    """
    inputs = [p.name for p in model.parameters if p.input]
    table, source = _table(data, columns, inputs)
    if "t" not in table:
        raise IdentificationError(f"The measurements ({source}) have no column `t` (the sample times).",
                                  fix="name the time column `t`")
    coords = [c.name for c in model.coordinates]
    wanted = table if columns is None else {k: v for k, v in table.items() if k in set(columns) | {"t"}}
    if columns is not None:
        missing = [c for c in columns if c not in table]
        if missing:
            raise IdentificationError(f"The measurements ({source}) have no column `{missing[0]}`.",
                                      fix="the columns are " + ", ".join(table))
    unknown = [k for k in wanted if k != "t" and k not in coords and not (k.endswith("_dot") and k[:-4] in coords)
               and not (k.endswith("_ddot") and k[:-5] in coords) and k not in inputs]
    if columns is None and unknown and all(_SIMULATION_OUTPUTS.fullmatch(k) for k in unknown):
        # A simulation's file read whole: its q, q̇, q̈ and inputs are the record, the rest is set aside.
        wanted = {k: v for k, v in wanted.items() if k not in unknown}
        unknown = []
    if unknown:
        raise IdentificationError(
            f"The column `{unknown[0]}` of the measurements ({source}) is neither a coordinate, a rate, an "
            f"acceleration nor an input of `{model.name}`.",
            fix=f"rename or drop it, or choose the columns to use (columns=[...], --columns); the coordinates are "
                f"{', '.join(coords)}, the inputs {', '.join(inputs) or '(none)'}")
    arrays = {k: _vector(k, v, source) for k, v in wanted.items()}
    t = arrays.pop("t")
    for name, values in arrays.items():
        if len(values) != len(t):
            raise IdentificationError(f"The column `{name}` has {len(values)} samples and `t` {len(t)} ({source}).",
                                      fix="give every column one value per sample time")
    if len(t) < MIN_SAMPLES:
        raise IdentificationError(f"The measurements ({source}) have {len(t)} samples, fewer than {MIN_SAMPLES}.",
                                  fix="give a longer record")
    step = np.diff(t)
    if np.any(~(step > 0)):
        k = int(np.flatnonzero(~(step > 0))[0])
        raise IdentificationError(f"The sample times do not increase at row {k + 2} ({source}): t = {float(t[k]):.9g} "
                                  f"then {float(t[k + 1]):.9g}.", fix="sort the samples by time and remove repeated times")
    states = {k: v for k, v in arrays.items() if k in coords or (k.endswith("_dot") and k[:-4] in coords)}
    accelerations = {k[:-5]: v for k, v in arrays.items() if k.endswith("_ddot") and k[:-5] in coords}
    measured_inputs = {k: v for k, v in arrays.items() if k in inputs}
    if not states:
        raise IdentificationError(f"The measurements ({source}) hold no coordinate nor rate of `{model.name}`.",
                                  fix="measure at least one of " + ", ".join(coords))
    return Measurements(t, states, accelerations, measured_inputs, source)


def _vector(name: str, values, source: str) -> np.ndarray:
    try:
        out = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise IdentificationError(f"The column `{name}` of the measurements ({source}) is not numbers.",
                                  fix="give numbers (decimal, one per sample)") from None
    if out.ndim != 1:
        raise IdentificationError(f"The column `{name}` of the measurements ({source}) has shape {out.shape}, not "
                                  "one value per sample.", fix="give a 1-D array per column")
    bad = np.flatnonzero(~np.isfinite(out))
    if len(bad):
        raise IdentificationError(f"The column `{name}` holds {out[bad[0]]} at row {bad[0] + 1} ({source}): every "
                                  "sample must be a finite number.",
                                  fix="remove the rows with missing values (NaN) or fill them in")
    return out


def _table(data, columns: Sequence[str] | None, inputs: Sequence[str]) -> tuple[dict[str, object], str]:
    """Column name → values, and a description of the source."""
    from ..numerics import Trajectory

    if isinstance(data, Trajectory):
        table: dict[str, object] = {"t": data.t}
        for k, c in enumerate(data.coordinates):
            table[c] = data.q[:, k]
            table[c + "_dot"] = data.qd[:, k]
        for name, values in data.extra.items():
            table[name] = values
        if columns is None:  # its q, q̇ and inputs (the monitors and reactions are not measurements)
            keep = {"t", *data.coordinates, *(c + "_dot" for c in data.coordinates), *inputs}
            table = {k: v for k, v in table.items() if k in keep}
        return table, f"trajectory of `{data.model_name}`"
    if isinstance(data, (str, Path)):
        return _read_csv(Path(data)), f"`{data}`"
    try:
        import xarray as xr
    except ImportError:  # pragma: no cover - xarray is a dependency
        xr = None
    if xr is not None and isinstance(data, xr.Dataset):
        time = "t" if "t" in data.coords or "t" in data.variables else "time" if "time" in data.coords else None
        if time is None:
            raise IdentificationError("The xarray Dataset has no coordinate `t` (or `time`) of sample times.",
                                      fix="name the time coordinate `t`")
        table = {"t": data[time].values}
        for key, var in data.data_vars.items():
            if var.dims != (time,):
                raise IdentificationError(f"The variable `{key}` of the Dataset has dimensions {var.dims}, not "
                                          f"({time},).", fix="select one record (e.g. ds.sel(member=0))")
            table[str(key)] = var.values
        return table, "the xarray Dataset"
    if isinstance(data, Mapping):  # after xarray's Dataset, which is a Mapping of its variables
        return {str(k): v for k, v in data.items()}, "the arrays given"
    raise IdentificationError(f"The measurements are a {type(data).__name__}, which identify does not read.",
                              fix="give a Trajectory, an xarray Dataset, a CSV file or a dict of arrays")


def _read_csv(path: Path) -> dict[str, object]:
    """A CSV file of numbers with one header line (``#`` lines skipped), column name → array."""
    try:
        if path.stat().st_size > MAX_CSV_BYTES:
            raise IdentificationError(f"`{path}` is larger than {MAX_CSV_BYTES // 2**20} MB.",
                                      fix="give a measured record of reasonable size")
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise IdentificationError(f"The measurements file `{path}` does not exist.", fix="check the path") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise IdentificationError(f"The measurements file `{path}` cannot be read: {exc}.",
                                  fix="give a UTF-8 CSV file") from None
    lines = [line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise IdentificationError(f"`{path}` holds no header line.", fix="start with a line of column names: t,theta")
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = [h.strip() for h in rows[0]]
    if len(set(header)) != len(header):
        twice = next(h for h in header if header.count(h) > 1)
        raise IdentificationError(f"The column `{twice}` appears twice in `{path}`.", fix="name each column once")
    values = np.full((len(rows) - 1, len(header)), math.nan)
    for i, row in enumerate(rows[1:]):
        if len(row) != len(header):
            raise IdentificationError(f"Line {i + 2} of the data of `{path}` has {len(row)} fields, the header "
                                      f"{len(header)}.", fix="give one value per column on every line")
        for j, field in enumerate(row):
            field = field.strip()
            if not field:
                continue  # a missing value: NaN, refused with its row by `_vector`
            if not _NUMBER.fullmatch(field):
                raise IdentificationError(f"`{field[:40]}` (line {i + 2} of the data, column `{header[j]}` of "
                                          f"`{path}`) is not a number.", fix="give decimal numbers")
            values[i, j] = float(field)
    return {name: values[:, j] for j, name in enumerate(header)}
