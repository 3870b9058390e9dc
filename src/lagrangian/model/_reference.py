"""The frame the equations are written in: R(O'), moving relative to the Galilean R0.

Seed, Remarque 3: in a non-Galilean frame R(O') the Lagrange equations take T(Σ/R), and
the efforts gain, for every solid, the Coriolis inertial force −2 Ω(R/R0) ∧ V(P/R) dm
and the entrainment inertial force −[γ(O'/R0) + dΩ(R/R0)/dt ∧ O'P + Ω(R/R0) ∧ (Ω(R/R0)
∧ O'P)] dm.  Those need the motion of R relative to R0 to be *known*: here R is one of
the model's frames, whose chain of rotations from R0 depends on t and the parameters
only, and O' one of its points, whose position OO' depends on t and the parameters only.

A model file says so with::

    [reference]
    frame = "R1"      # the frame R the equations are written in
    origin = "A"      # its origin O' (default: O, the origin of R0)

This module holds the checks of `Reference` (declared in `spec`) (the builder calls them, with the
file and line of the declaration); the inertial forces are `lagrangian.dynamics`' work.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import symengine as se

from ..errors import ModelError
from .spec import ORIGIN, Frame, Location, Point, Reference

__all__ = ["INERTIAL_LOAD_NAMES", "check_reference", "read_reference"]

#: Names of the two loads the engine adds for a non-Galilean reference frame.
INERTIAL_LOAD_NAMES = ("Coriolis", "entrainment")


def _moving(expr_symbols: set[se.Basic], coordinates: Mapping[str, se.Basic]) -> str | None:
    """The first coordinate (or rate) name among ``expr_symbols``, if any."""
    names = sorted(name for name, s in coordinates.items() if s in expr_symbols)
    return names[0] if names else None


def check_reference(frame: Any, origin: Any, location: Location, *, frames: Sequence[Frame],
                    points: Mapping[str, Point], coordinates: Mapping[str, se.Basic],
                    loads: Mapping[str, Location]) -> Reference:
    """Check a declared reference frame and return it.

    Parameters
    ----------
    frame, origin : the names given for R and O'.
    location : where ``[reference]`` was declared (with the lines of ``frame`` and ``origin``).
    frames, points : the model's frames (parents first) and declared points (O included).
    coordinates : every coordinate and rate symbol by name (``theta``, ``theta_dot``).
    loads : where each load of the model is declared (the inertial loads' names must be free).

    Raises
    ------
    ModelError
        When R or O' is unknown, or when their motion relative to R0 is not prescribed
        (it depends on a coordinate), with the file and line of the offending key.
    """
    def fail(message: str, key: str, symbol: str, fix: str) -> ModelError:
        where = location.of(key)
        return ModelError(message, fix=fix, symbol=symbol, file=where.file, line=where.line)

    by_name = {f.name: f for f in frames}

    def turning(name: str) -> tuple[str, str] | None:
        """(coordinate, frame) when the chain of rotations from R0 to ``name`` depends on a coordinate."""
        step: Frame | None = by_name[name]
        while step is not None and step.rotation is not None:
            moving = _moving(step.rotation.angle.free_symbols, coordinates)
            if moving is not None:
                return moving, step.name
            step = by_name.get(step.parent) if step.parent is not None else None
        return None

    if not isinstance(frame, str) or frame not in by_name or frame.startswith("_"):
        known = ", ".join(f.name for f in frames if not f.name.startswith("_"))
        raise fail(f"the reference frame `{frame}` is not a declared frame, so its motion relative to R0 is "
                   "undefined", "frame", str(frame),
                   f"declare it under [frames] with a rotation from R0 that depends on t only "
                   f"(e.g. rotation = [\"Omega*t\", \"z\"]), or use one of: {known}")
    found = turning(frame)
    if found is not None:
        moving, through = found
        link = "" if through == frame else f" (through frame `{through.lstrip('_')}`)"
        raise fail(f"the reference frame `{frame}` turns with coordinate `{moving}`{link}: the motion of a "
                   "reference frame relative to R0 must be prescribed, a function of t only", "frame", moving,
                   "write the equations in a frame whose rotation from R0 is given (e.g. [\"Omega*t\", \"z\"]); "
                   "a frame that moves with the coordinates belongs to the system, not to the reference")
    if not isinstance(origin, str) or origin not in points:
        raise fail(f"the origin `{origin}` of the reference frame `{frame}` is not a declared point", "origin",
                   str(origin), "declare it under [points] with a position that depends on t only, or use O")
    position = points[origin].position
    mover = _moving(position.free_symbols(), coordinates)
    for piece in position.frames:
        found = turning(piece) if mover is None else None
        mover = found[0] if found is not None else mover
    if mover is not None:
        raise fail(f"the origin `{origin}` of the reference frame `{frame}` moves with coordinate `{mover}`: "
                   "the motion of O' relative to R0 must be prescribed, a function of t only", "origin", mover,
                   "choose an origin whose position OO' depends on t and the parameters only")
    for name in INERTIAL_LOAD_NAMES:
        if name in loads:
            where = loads[name]
            raise ModelError(f"a load is named `{name}`, the name of the inertial load that the reference frame "
                             f"`{frame}` adds", symbol=name, file=where.file, line=where.line,
                             fix=f"rename that load (`{name}` is reserved when [reference] is given)")
    return Reference(frame, origin)


def read_reference(table: Any, index: Mapping[tuple[str, ...], tuple[int, int]], source: str | None
                   ) -> tuple[str, str, Location]:
    """``(frame, origin, location)`` from the ``[reference]`` table of a model file.

    ``index`` maps each declared key path to its (line, value column), as the TOML reader
    finds them; unknown keys and missing ``frame`` are refused here.
    """
    header = index.get(("reference",), (None, 0))[0]
    if not isinstance(table, Mapping):
        raise ModelError("`reference` must be a table", fix='write it as [reference] with frame = "R"',
                         symbol="reference", file=source, line=header)
    for key in table:
        if key not in ("frame", "origin"):
            line = index.get(("reference", key), (header, 0))[0]
            raise ModelError(f"unknown key `{key}` in [reference]", symbol=key, file=source, line=line,
                             fix="the keys of [reference] are frame (the frame R) and origin (its origin O')")
    if "frame" not in table:
        raise ModelError("[reference] does not say which frame the equations are written in", symbol="reference",
                         file=source, line=header, fix='add frame = "R" (a frame declared under [frames])')
    keys = tuple((key, *index[("reference", key)]) for key in ("frame", "origin") if ("reference", key) in index)
    return table["frame"], table.get("origin", ORIGIN), Location(source, header, keys)
