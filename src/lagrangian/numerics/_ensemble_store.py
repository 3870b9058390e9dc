"""Where an ensemble's results go: memory, or a Zarr store written chunk by chunk.

Both hold the same flat layout, one row per member (dimension ``member``):

* ``status`` (int8, CF ``flag_values``/``flag_meanings``: ``pending``, ``ok``, ``stopped``,
  ``blow-up``, ``step-limit``, ``singular``, ...), ``t_final``, ``steps``, ``rhs_calls``,
  ``conditioning``;
* ``state_min``, ``state_max``, ``state_final`` (member, state), ``state`` being the
  coordinates then the rates (``theta``, ..., ``theta_dot``, ...);
* ``event_time``, ``event_count`` (member, event); ``drift`` (member, integral);
* ``trajectory`` (member, time, state) when the trajectories are kept;
* the swept names (``theta1``, ``g``, ...) as coordinates along ``member``.

A Zarr store is created whole at the start, every member ``pending``; each finished chunk
writes its rows, ``status`` last, so a store cut off at any moment (Ctrl-C, a killed job)
opens with ``xarray.open_zarr`` and its ``status`` says which members are done: `resume`
finishes the pending ones.  Its attributes record what was run (``lagrangian_run``, a
JSON fingerprint), so a resume with different settings is refused.  A grid's shape is
recorded too (``lagrangian_grid``): `open_ensemble` gives the grid's own dimensions back.
"""

from __future__ import annotations

import json
import shutil
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import OutputError
from ._batch import PENDING, STATUS

__all__ = ["Layout", "MemorySink", "ZarrSink", "to_dataset", "open_ensemble", "unflatten"]


@dataclass(frozen=True)
class Layout:
    """The shape of an ensemble's results (module docstring)."""

    count: int
    t_out: np.ndarray
    states: tuple[str, ...]
    events: tuple[str, ...]
    integrals: tuple[str, ...]
    keep: bool
    swept: dict
    grid: tuple[tuple[str, int], ...] | None
    run: dict

    def variables(self) -> dict[str, tuple[tuple[str, ...], tuple[int, ...], str, object]]:
        """name -> (dims, shape, dtype, fill value)."""
        N, S = self.count, len(self.states)
        out: dict[str, tuple[tuple[str, ...], tuple[int, ...], str, object]] = {
            "status": (("member",), (N,), "int8", PENDING),
            "t_final": (("member",), (N,), "float64", np.nan),
            "steps": (("member",), (N,), "int64", 0),
            "rhs_calls": (("member",), (N,), "int64", 0),
            "conditioning": (("member",), (N,), "float64", np.nan),
            "state_min": (("member", "state"), (N, S), "float64", np.nan),
            "state_max": (("member", "state"), (N, S), "float64", np.nan),
            "state_final": (("member", "state"), (N, S), "float64", np.nan),
        }
        if self.events:
            out["event_time"] = (("member", "event"), (N, len(self.events)), "float64", np.nan)
            out["event_count"] = (("member", "event"), (N, len(self.events)), "int64", 0)
        if self.integrals:
            out["drift"] = (("member", "integral"), (N, len(self.integrals)), "float64", np.nan)
        if self.keep:
            out["trajectory"] = (("member", "time", "state"), (N, len(self.t_out), S), "float64", np.nan)
        return out

    def attributes(self) -> dict[str, dict]:
        status = {"flag_values": list(STATUS), "flag_meanings": " ".join(STATUS.values()),
                  "long_name": "how the member's integration ended"}
        return {
            "status": status,
            "t_final": {"long_name": "time the member's integration reached"},
            "state_min": {"long_name": "smallest value over the output times"},
            "state_max": {"long_name": "largest value over the output times"},
            "state_final": {"long_name": "state where the integration ended"},
            "event_time": {"long_name": "time of the event's first occurrence (NaN: none)"},
            "event_count": {"long_name": "number of occurrences of the event"},
            "drift": {"long_name": "relative drift of the first integral, max|I(t) - I(t0)| / S"},
            "conditioning": {"long_name": "smallest relative pivot of the mass matrix met"},
            "trajectory": {"long_name": "state at the output times"},
        }

    def coords(self) -> dict:
        coords: dict[str, Any] = {"member": np.arange(self.count), "time": self.t_out,
                  "state": np.array(self.states, dtype=object)}
        if self.events:
            coords["event"] = np.array(self.events, dtype=object)
        if self.integrals:
            coords["integral"] = np.array(self.integrals, dtype=object)
        for name, values in self.swept.items():
            coords[name] = ("member", np.asarray(values, dtype=float))
        return coords

    def global_attrs(self) -> dict:
        attrs = {"lagrangian_run": json.dumps(self.run, sort_keys=True)}
        if self.grid is not None:
            attrs["lagrangian_grid"] = json.dumps([list(axis) for axis in self.grid])
        return attrs


_RENAME = {"state": "trajectory"}  # run_chunk's name -> the Dataset's


class MemorySink:
    """All members' rows in NumPy arrays."""

    def __init__(self, layout: Layout) -> None:
        self.layout = layout
        self.arrays = {name: np.full(shape, fill, dtype=dtype)
                       for name, (_, shape, dtype, fill) in layout.variables().items()}

    def pending(self) -> np.ndarray:
        return self.arrays["status"] == PENDING

    def write(self, start: int, stop: int, rows: dict[str, np.ndarray]) -> None:
        for name, values in rows.items():
            name = _RENAME.get(name, name)
            if name in self.arrays:
                self.arrays[name][start:stop] = values

    def dataset(self, flat: bool = False):
        return to_dataset(self.layout, self.arrays, flat=flat)


def to_dataset(layout: Layout, arrays: dict, *, flat: bool = False):
    """The Dataset of ``arrays`` (name -> flat rows); with a grid's dimensions unless ``flat``."""
    import xarray as xr

    attrs = layout.attributes()
    variables = layout.variables()
    data = {name: xr.Variable(variables[name][0], arrays[name], attrs=attrs.get(name, {})) for name in variables}
    ds = xr.Dataset(data, coords=layout.coords(), attrs=layout.global_attrs())
    return ds if flat else unflatten(ds)


def unflatten(ds):
    """A flat ensemble Dataset (dimension ``member``) with a grid's own dimensions, when it came from a grid."""
    import xarray as xr

    text = ds.attrs.get("lagrangian_grid")
    if not text:
        return ds
    axes = [(str(name), int(size)) for name, size in json.loads(text)]
    names = [name for name, _ in axes]
    shape = tuple(size for _, size in axes)
    out = {}
    for name, var in ds.data_vars.items():
        if var.dims and var.dims[0] == "member":
            out[name] = xr.Variable(tuple(names) + var.dims[1:], _data(var).reshape(shape + var.shape[1:]),
                                    attrs=var.attrs)
        else:
            out[name] = var.variable
    coords = {name: ds[name].values for name in ds.coords if "member" not in ds[name].dims}
    for axis, (name, _size) in enumerate(axes):
        flat = np.asarray(ds[name].values).reshape(shape)
        coords[name] = flat[(0,) * axis + (slice(None),) + (0,) * (len(shape) - axis - 1)]
    for name in ds.coords:  # swept names that are not grid axes: along the grid
        if name not in coords and name != "member" and ds[name].dims == ("member",):
            coords[name] = (tuple(names), np.asarray(ds[name].values).reshape(shape))
    return xr.Dataset(out, coords=coords, attrs=dict(ds.attrs))


def _data(var):
    """The variable's array: a NumPy array, or a Dask array left lazy (it reshapes lazily too)."""
    data = var.data
    return data if hasattr(data, "dask") else np.asarray(var.values)


class ZarrSink:
    """Rows written into a Zarr store as chunks finish (module docstring)."""

    def __init__(self, path: Path, layout: Layout, chunk: int, *, resume: bool) -> None:
        import zarr

        self.path, self.layout = Path(path), layout
        if resume:
            if not self.path.exists():
                raise OutputError(f"`{path}` does not exist, so there is nothing to resume.",
                                  fix="run the sweep without --resume first")
            self.group = zarr.open_group(str(self.path), mode="r+")
            recorded = self.group.attrs.get("lagrangian_run")
            if not isinstance(recorded, str):  # absent, or not the JSON text `_create` writes
                raise OutputError(f"`{path}` is not a store written by `lagrangian sweep`.",
                                  fix="give the store the interrupted sweep wrote")
            if json.loads(recorded) != json.loads(json.dumps(layout.run, sort_keys=True)):
                old, new = json.loads(recorded), layout.run
                differ = sorted(k for k in set(old) | set(new) if old.get(k) != new.get(k))
                raise OutputError(f"`{path}` was written by a different sweep ({', '.join(differ)} differ), so it "
                                  f"cannot be resumed with these settings.",
                                  fix="repeat the original command with --resume, or write to a new store")
        else:
            if self.path.exists():
                raise OutputError(f"`{path}` already exists.",
                                  fix="add --resume to finish an interrupted sweep in it, or remove it / choose "
                                      "another name")
            self._create(chunk)
            self.group = zarr.open_group(str(self.path), mode="r+")
        self.arrays: dict[str, Any] = {name: self.group[name] for name in layout.variables()}  # zarr arrays
        self.chunk = int(self.arrays["status"].chunks[0])

    def _create(self, chunk: int) -> None:
        import xarray as xr
        import zarr

        # Built beside the target and moved into place: the store appears whole or not at all.
        tmp = self.path.with_name(f".{self.path.name}.creating")
        shutil.rmtree(tmp, ignore_errors=True)
        try:
            xr.Dataset(coords=self.layout.coords(), attrs=self.layout.global_attrs()).to_zarr(
                str(tmp), mode="w", consolidated=False)
            group = zarr.open_group(str(tmp), mode="r+")
            attrs = self.layout.attributes()
            swept = " ".join(self.layout.swept)
            for name, (dims, shape, dtype, fill) in self.layout.variables().items():
                chunks = (min(chunk, shape[0]),) + shape[1:]
                extra = {"coordinates": swept} if swept else {}
                group.create_array(name, shape=shape, chunks=chunks, dtype=dtype, fill_value=fill,
                                   dimension_names=list(dims), attributes={**attrs.get(name, {}), **extra})
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # "consolidated metadata is not part of Zarr 3": xarray reads it
                zarr.consolidate_metadata(str(tmp))
            tmp.rename(self.path)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise

    def pending(self) -> np.ndarray:
        return np.asarray(self.arrays["status"][:]) == PENDING

    def write(self, start: int, stop: int, rows: dict[str, np.ndarray]) -> None:
        for name, values in rows.items():
            name = _RENAME.get(name, name)
            if name in self.arrays and name != "status":
                self.arrays[name][start:stop] = values
        self.arrays["status"][start:stop] = rows["status"]  # last: a member is done once its status says so

    def dataset(self):
        return open_ensemble(self.path, load=False)


def open_ensemble(path, *, load: bool = True):
    """The ensemble in a Zarr store (``.zarr``) or NetCDF file (``.nc``), with a grid's own dimensions.

    ``load=False`` leaves a Zarr store's variables lazy when Dask is installed (they are
    read when used), for stores larger than memory.  ``xarray.open_zarr`` /
    ``xarray.open_dataset`` read the same files as they are: one ``member`` dimension, the
    swept names as its coordinates.

    Parameters
    ----------
    path : str or Path
        The store or file.
    load : bool, optional
        ``load=False`` leaves a Zarr store's variables lazy when Dask is installed (they are read
        when used), for stores larger than memory.

    Returns
    -------
    xarray.Dataset
        The ensemble.
    """
    import xarray as xr

    path = Path(path)
    if path.suffix == ".nc":
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            return unflatten(ds.load())
    try:
        import dask  # noqa: F401  (open_zarr is lazy through Dask)
        lazy = not load
    except ImportError:
        lazy = False
    ds = xr.open_zarr(str(path))
    return unflatten(ds if lazy else ds.load())
