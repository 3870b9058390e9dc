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

__all__ = ["save_trajectory", "load_trajectory", "check_output_path", "FORMATS"]

FORMATS = (".csv", ".npz")


def _metadata(traj: Trajectory) -> dict:
    out = {
        "format": "lagrangian.trajectory", "version": 1, "model": traj.model_name, "method": traj.method,
        "coordinates": list(traj.coordinates), "parameters": dict(traj.parameters),
        "integrals": list(traj.integrals), "drift": dict(traj.drift), "steps": traj.steps,
        "rhs_calls": traj.rhs_calls, "status": traj.status,
        # A contact's event says more: its kind, the percussion, the energy before and after (`_contact_switch`).
        "events": [e.as_dict() if hasattr(e, "as_dict") else {"name": e.name, "t": e.t} for e in traj.events],
        "extra": list(traj.extra),  # the columns after the monitors: reactions, multipliers
    }
    if traj.range_exits:  # where the motion left a declared range (`_ranges`)
        out["range_exits"] = [e.as_dict() for e in traj.range_exits]
    if traj.quaternion_drift:  # free bodies: the largest |1 - |e|| before each projection (`_free_simulate`)
        out["quaternion_drift"] = dict(traj.quaternion_drift)
    return out


def check_output_path(path: str | Path) -> Path:
    """Check, before a run, that ``path`` can take a trajectory: a known suffix, an existing, writable folder.

    Parameters
    ----------
    path : str or Path
        The file to be written.

    Returns
    -------
    Path
        The path.

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

    Parameters
    ----------
    traj : Trajectory
        The trajectory.
    path : str or Path
        The file to write.

    Returns
    -------
    Path
        The path written.

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


def load_trajectory(path: str | Path) -> Trajectory:
    """Read a trajectory written by `save_trajectory` (``.csv`` or ``.npz``): t, q, q̇, q̈, monitors, extra columns.

    The file's metadata gives the coordinates, parameters, method and drift; nothing in it is
    executed (NPZ is read with ``allow_pickle=False``, CSV as numbers and one JSON line).

    Parameters
    ----------
    path : str or Path
        The file to read.

    Returns
    -------
    Trajectory
        The trajectory it holds.

    Raises
    ------
    OutputError
        A missing or unreadable file, or one that is not a lagrangian trajectory.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    fix = "give a file written by `lagrangian simulate -o FILE.csv|.npz` or `save_trajectory`"
    if suffix not in FORMATS:
        raise OutputError(f"Cannot tell the format of `{path}` from its suffix `{path.suffix}`.", fix=fix)
    try:
        if suffix == ".npz":
            with np.load(path, allow_pickle=False) as data:
                meta = json.loads(str(data["metadata"]))
                columns = [str(c) for c in data["columns"]]
                table = np.asarray(data["table"], dtype=float)
        else:
            text = path.read_text(encoding="utf-8")
            lines = text.splitlines()
            found = next((ln for ln in lines if ln.startswith("# metadata: ")), None)
            if found is None:
                raise ValueError("no `# metadata:` line")
            meta = json.loads(found[len("# metadata: "):])
            header = next(k for k, ln in enumerate(lines) if not ln.startswith("#"))
            columns = lines[header].split(",")
            table = np.loadtxt(io.StringIO("\n".join(lines[header + 1:])), delimiter=",", ndmin=2)
    except FileNotFoundError:
        raise OutputError(f"The trajectory file `{path}` does not exist.", fix=fix) from None
    except (OSError, ValueError, KeyError, StopIteration, json.JSONDecodeError) as exc:
        raise OutputError(f"`{path}` is not a trajectory that can be read: {exc}.", fix=fix) from None
    if meta.get("format") != "lagrangian.trajectory" or not isinstance(meta.get("coordinates"), list):
        raise OutputError(f"`{path}` is not a lagrangian trajectory (its metadata says otherwise).", fix=fix)
    coords = tuple(str(c) for c in meta["coordinates"])
    if table.shape[1] != len(columns) or columns[0] != "t":
        raise OutputError(f"`{path}` has {table.shape[1]} columns of numbers but names {len(columns)}.", fix=fix)
    col = {name: table[:, k] for k, name in enumerate(columns)}

    def block(suffix: str) -> np.ndarray:
        try:
            return np.column_stack([col[c + suffix] for c in coords]) if coords else np.zeros((len(table), 0))
        except KeyError as exc:
            raise OutputError(f"`{path}` has no column `{exc.args[0]}`.", fix=fix) from None

    known = {"t", *coords, *(c + "_dot" for c in coords), *(c + "_ddot" for c in coords)}
    integrals = tuple(str(i) for i in meta.get("integrals", []))
    rest = [c for c in columns if c not in known]
    extra_names = set(meta["extra"]) if isinstance(meta.get("extra"), list) else {
        c for c in rest if c.startswith(("R_", "M_")) and c not in integrals}  # files written before "extra"
    monitors = {c: col[c] for c in rest if c not in extra_names}
    extra = {c: col[c] for c in rest if c in extra_names}
    return Trajectory(model_name=str(meta.get("model", "")), coordinates=coords,
                      parameters={str(k): float(v) for k, v in dict(meta.get("parameters", {})).items()},
                      t=col["t"].copy(), q=block(""), qd=block("_dot"), qdd=block("_ddot"), monitors=monitors,
                      integrals=integrals, drift={str(k): float(v) for k, v in dict(meta.get("drift", {})).items()},
                      method=str(meta.get("method", "")), steps=int(meta.get("steps", 0)),
                      rhs_calls=int(meta.get("rhs_calls", 0)), status=str(meta.get("status", "completed")),
                      extra=extra)
