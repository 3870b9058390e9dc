"""Save a `Trajectory` as CSV (one column per quantity) or NPZ (NumPy arrays), atomically.

CSV starts with ``#`` comment lines (model, method, parameters, drift of the first
integrals), then a header row with `Trajectory.columns` and one row per output time,
every number with 17 significant digits so that nothing is lost on reading back.
NPZ holds every column the CSV has: ``t``, ``q``, ``qd``, ``qdd``, one ``monitor_<name>``
array per monitor, one ``extra_<name>`` array per extra column (reactions ``R_O_x0``...,
multipliers), ``table`` — all of them as one (N, k) array, in the order of ``columns`` —
``columns`` and a ``metadata`` JSON string.
"""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np

from .._atomic import check_destination, write_atomic_with
from ..errors import OutputError
from ._trajectory import Trajectory

__all__ = ["save_trajectory", "check_output_path", "FORMATS"]

FORMATS = (".csv", ".npz")


def _metadata(traj: Trajectory) -> dict:
    out = {
        "format": "lagrangian.trajectory", "version": 1, "model": traj.model_name, "method": traj.method,
        "coordinates": list(traj.coordinates), "parameters": dict(traj.parameters),
        "integrals": list(traj.integrals), "drift": dict(traj.drift), "steps": traj.steps,
        "rhs_calls": traj.rhs_calls, "status": traj.status,
        # A contact's event says more: its kind, the percussion, the energy before and after (`_contact_switch`).
        "events": [e.as_dict() if hasattr(e, "as_dict") else {"name": e.name, "t": e.t} for e in traj.events],
    }
    if traj.range_exits:  # where the motion left a declared range (`_ranges`)
        out["range_exits"] = [e.as_dict() for e in traj.range_exits]
    return out


def check_output_path(path: str | Path) -> Path:
    """Check, before a run, that ``path`` can take a trajectory: a known suffix, an existing, writable folder.

    Raises
    ------
    OutputError
        For another suffix, a missing or read-only folder, or a path that is a folder.
    """
    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise OutputError(f"Cannot tell the format of `{path}` from its suffix `{path.suffix}`.",
                          fix="name the output file `.csv` (a table) or `.npz` (NumPy arrays)")
    check_destination(path, name_fix="give a file name, e.g. traj.csv")
    return path


def save_trajectory(traj: Trajectory, path: str | Path) -> Path:
    """Write ``traj`` to ``path`` (``.csv`` or ``.npz``); an older file there is replaced only on success.

    Raises
    ------
    OutputError
        For another suffix, or when the file cannot be written (the old one is intact).
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        check_output_path(path)
    if suffix == ".csv":
        meta = _metadata(traj)
        header = "\n".join([
            f"lagrangian trajectory of `{traj.model_name}`, method {traj.method}, "
            f"{traj.steps} steps, {traj.rhs_calls} right-hand-side calls, {traj.status}",
            "parameters: " + ", ".join(f"{k} = {v!r}" for k, v in traj.parameters.items()),
            "conservation: " + (traj.drift_summary() or "no first integral"),
            "metadata: " + json.dumps(meta, ensure_ascii=False),
            ",".join(traj.columns()),
        ])

        def writer(handle):
            text = io.StringIO()
            np.savetxt(text, traj.table(), delimiter=",", fmt="%.17g", header=header, comments="# ")
            lines = text.getvalue().split("\n")
            # The last header line is the column names: written without the comment mark.
            n_header = header.count("\n") + 1
            lines[n_header - 1] = lines[n_header - 1][2:]
            handle.write("\n".join(lines).encode("utf-8"))
    else:
        def writer(handle):
            arrays = {"t": traj.t, "q": traj.q, "qd": traj.qd, "qdd": traj.qdd,
                      "columns": np.array(traj.columns()), "metadata": np.array(json.dumps(_metadata(traj)))}
            arrays.update({f"monitor_{name}": values for name, values in traj.monitors.items()})
            arrays.update({f"extra_{name}": np.asarray(values) for name, values in traj.extra.items()})
            arrays["table"] = traj.table()
            np.savez(handle, **arrays)
    try:
        write_atomic_with(path, writer)
    except OSError as exc:
        raise OutputError(f"Cannot write `{path}`: {exc.strerror or exc}.",
                          fix="check that the folder exists and is writable; the old file, if any, is unchanged") \
            from exc
    return path
