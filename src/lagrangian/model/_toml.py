"""Read a model file (TOML, with the standard library's `tomllib`) into a `Model`.

The file's tables map onto the course's vocabulary::

    [model]        name, description
    [parameters]   m = 1.0   or   m = { value = 1.0, unit = "kg", description = "mass" }
    [coordinates]  theta = { initial = 0.5, rate = 0.0, momentum = "K" }
    [frames]       R1 = { from = "R0", rotation = ["psi", "z"], axes = ["u", "v", "z0"] }
    [points]       A = "l*R1.x"   or   B = { from = "A", position = "l*R2.x" }
    [bodies.S]     frame, mass, center, fixed_point, inertia = { at, frame, diagonal | matrix }
    [particles.P]  mass, position
    [loads]        weight = { gravity = "-g*R0.z" }, push = { force = "...", at = "P" }, ...

See ``docs/model-format.md`` for every key.  `tomllib` gives no positions for
values, so the line of each declaration is found by scanning the text for its key.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import ModelError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib
from .build import ModelBuilder
from .spec import Location, Model

__all__ = ["load_model", "parse_model"]

_TABLES = ("model", "parameters", "coordinates", "frames", "points", "bodies", "particles", "loads")
_LOAD_KINDS = {
    "gravity": {"gravity", "on"},
    "force": {"force", "at"},
    "torque": {"torque", "on", "reaction_on"},
    "spring": {"spring", "stiffness", "rest_length"},
    "damper": {"damper", "coefficient"},
    "potential": {"potential"},
    "generalized_force": {"generalized_force"},
}


def load_model(path: str | Path) -> Model:
    """Read and check the model file at ``path``.

    Raises
    ------
    ModelError
        With the file, line and symbol of the problem, and how to fix it.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ModelError(f"model file `{path}` does not exist", file=str(path),
                         fix="check the path, or run `lagrangian derive` with no file for the seed's top") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelError(f"cannot read model file `{path}`: {exc}", file=str(path)) from None
    return parse_model(text, source=str(path))


def parse_model(text: str, *, source: str | None = None) -> Model:
    """Read a model from TOML ``text`` (``source`` names it in error messages)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        msg = str(exc)
        m = re.search(r"\(at line (\d+), column (\d+)\)", msg)
        line = int(m.group(1)) if m else None
        column = int(m.group(2)) if m else None
        core = re.sub(r"\s*\(at line \d+, column \d+\)", "", msg)
        fix = "correct the TOML syntax"
        if "overwrite" in core.lower() or "duplicate" in core.lower():
            fix = "each name may be declared once in a table (a frame has one parent)"
        raise ModelError(f"TOML syntax error: {core}", file=source, line=line, column=column, fix=fix) from None
    return _Reader(text, data, source).read()


class _Reader:
    def __init__(self, text: str, data: dict[str, Any], source: str | None) -> None:
        self.lines = text.splitlines()
        self.data = data
        self.source = source
        self.index = _key_lines(self.lines)

    def at(self, *path: str) -> Location:
        """The line declaring ``path`` (the longest known prefix of it)."""
        for k in range(len(path), 0, -1):
            line = self.index.get(tuple(path[:k]))
            if line is not None:
                return Location(self.source, line)
        return Location(self.source, None)

    def fail(self, path: tuple[str, ...], message: str, *, fix: str | None = None, symbol: str | None = None) -> ModelError:
        loc = self.at(*path)
        return ModelError(message, fix=fix, symbol=symbol, file=loc.file, line=loc.line)

    def table(self, name: str) -> dict[str, Any]:
        value = self.data.get(name, {})
        if not isinstance(value, dict):
            raise self.fail((name,), f"`{name}` must be a table", fix=f"write it as [{name}]")
        return value

    def entry(self, table: str, name: str, value: Any, allowed: set[str], shorthand: str) -> dict[str, Any]:
        """An entry given either as a table with ``allowed`` keys, or as a bare value for ``shorthand``."""
        if not isinstance(value, dict):
            return {shorthand: value}
        unknown = set(value) - allowed
        if unknown:
            key = sorted(unknown)[0]
            raise self.fail((table, name, key), f"unknown key `{key}` in {table} `{name}`", symbol=key,
                            fix="the keys allowed here are " + ", ".join(sorted(allowed)))
        return value

    def read(self) -> Model:
        for key in self.data:
            if key not in _TABLES:
                raise self.fail((key,), f"unknown table `[{key}]`", symbol=key,
                                fix="the tables are " + ", ".join(f"[{t}]" for t in _TABLES))
        meta = self.table("model")
        b = ModelBuilder(str(meta.get("name", Path(self.source).stem if self.source else "model")),
                         str(meta.get("description", "")), source=self.source)
        for name, value in self.table("parameters").items():
            v = self.entry("parameters", name, value, {"value", "unit", "description"}, "value")
            b.parameter(name, v.get("value"), unit=v.get("unit"), description=v.get("description"),
                        location=self.at("parameters", name))
        for name, value in self.table("coordinates").items():
            v = self.entry("coordinates", name, value,
                           {"initial", "rate", "momentum", "unit", "description"}, "initial")
            b.coordinate(name, v.get("initial"), v.get("rate"), momentum=v.get("momentum"), unit=v.get("unit"),
                         description=v.get("description"), location=self.at("coordinates", name))
        for name, value in self.table("frames").items():
            v = self.entry("frames", name, value, {"from", "rotation", "axes"}, "from")
            b.frame(name, v.get("from"), rotation=v.get("rotation"), axes=v.get("axes"),
                    location=self.at("frames", name))
        for name, value in self.table("points").items():
            v = self.entry("points", name, value, {"from", "position"}, "position")
            if "position" not in v:
                raise self.fail(("points", name), f"point `{name}` has no position", symbol=name,
                                fix='e.g. A = "l*R1.x" or A = { from = "B", position = "l*R1.x" }')
            b.point(name, v["position"], relative_to=v.get("from", "O"), location=self.at("points", name))
        for name, value in self.table("bodies").items():
            v = self.entry("bodies", name, value,
                           {"frame", "mass", "center", "center_from", "inertia", "fixed_point"}, "frame")
            for key in ("frame", "mass", "center"):
                if key not in v:
                    raise self.fail(("bodies", name), f"body `{name}` has no `{key}`", symbol=name,
                                    fix=f"add `{key} = ...` to [bodies.{name}]")
            b.body(name, frame=v["frame"], mass=v["mass"], center=v["center"], center_from=v.get("center_from", "O"),
                   inertia=v.get("inertia"), fixed_point=v.get("fixed_point"), location=self.at("bodies", name))
        for name, value in self.table("particles").items():
            v = self.entry("particles", name, value, {"mass", "position", "from"}, "position")
            for key in ("mass", "position"):
                if key not in v:
                    raise self.fail(("particles", name), f"particle `{name}` has no `{key}`", symbol=name,
                                    fix=f"add `{key} = ...` to [particles.{name}]")
            b.particle(name, mass=v["mass"], position=v["position"], relative_to=v.get("from", "O"),
                       location=self.at("particles", name))
        for name, value in self.table("loads").items():
            self.load(b, name, value)
        return b.build()

    def load(self, b: ModelBuilder, name: str, value: Any) -> None:
        where = self.at("loads", name)
        if not isinstance(value, dict):
            raise self.fail(("loads", name), f"load `{name}` must be a table", symbol=name,
                            fix='e.g. weight = { gravity = "-g*R0.z" }')
        kinds = [k for k in _LOAD_KINDS if k in value]
        if len(kinds) != 1:
            raise self.fail(("loads", name), f"load `{name}` must have exactly one of the keys "
                            + ", ".join(f"`{k}`" for k in _LOAD_KINDS), symbol=name,
                            fix='e.g. weight = { gravity = "-g*R0.z" }')
        kind = kinds[0]
        self.entry("loads", name, value, _LOAD_KINDS[kind], kind)
        if kind == "gravity":
            b.gravity(name, value["gravity"], on=_names(value.get("on", ())), location=where)
        elif kind == "force":
            if "at" not in value:
                raise self.fail(("loads", name), f"force `{name}` has no point of application", symbol=name,
                                fix='add at = "P"')
            b.force(name, value["force"], at=value["at"], location=where)
        elif kind == "torque":
            if "on" not in value:
                raise self.fail(("loads", name), f"torque `{name}` does not say which body it acts on",
                                symbol=name, fix='add on = "S"')
            b.torque(name, value["torque"], on=value["on"], reaction_on=value.get("reaction_on"), location=where)
        elif kind == "spring":
            b.spring(name, _names(value["spring"]), stiffness=_required(self, name, value, "stiffness"),
                     rest_length=value.get("rest_length", 0), location=where)
        elif kind == "damper":
            b.damper(name, _names(value["damper"]), coefficient=_required(self, name, value, "coefficient"),
                     location=where)
        elif kind == "potential":
            b.potential(name, value["potential"], location=where)
        else:
            comps = value["generalized_force"]
            if not isinstance(comps, Mapping):
                raise self.fail(("loads", name), f"`generalized_force` of `{name}` must map coordinates to "
                                "expressions", symbol=name, fix='e.g. { generalized_force = { x = "-c*x_dot" } }')
            b.generalized_force(name, comps, location=where)


def _required(reader: _Reader, name: str, value: dict[str, Any], key: str) -> Any:
    if key not in value:
        raise reader.fail(("loads", name), f"load `{name}` needs `{key}`", symbol=name, fix=f"add {key} = ...")
    return value[key]


def _names(value: Any) -> tuple[str, ...]:
    if isinstance(value, str):
        return (value,)
    return tuple(str(v) for v in value)


_HEADER = re.compile(r"^\s*\[\[?\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")
_KEY = re.compile(r"^\s*((?:[A-Za-z0-9_\-]+|\"[^\"]*\"|'[^']*')(?:\s*\.\s*(?:[A-Za-z0-9_\-]+|\"[^\"]*\"|'[^']*'))*)\s*=")


def _split_key(key: str) -> tuple[str, ...]:
    parts = re.findall(r"\"([^\"]*)\"|'([^']*)'|([A-Za-z0-9_\-]+)", key)
    return tuple(a or b or c for a, b, c in parts)


def _key_lines(lines: list[str]) -> dict[tuple[str, ...], int]:
    """Map each table header and ``key =`` line to its 1-based line number.

    Keys inside inline tables are found too (``R1 = { from = "R0" }`` records both
    ``frames.R1`` and ``frames.R1.from``) on the line where they appear.
    """
    index: dict[tuple[str, ...], int] = {}
    current: tuple[str, ...] = ()
    for number, line in enumerate(lines, start=1):
        header = _HEADER.match(line)
        if header:
            current = _split_key(header.group(1))
            index.setdefault(current, number)
            continue
        key = _KEY.match(line)
        if key:
            path = current + _split_key(key.group(1))
            index.setdefault(path, number)
            # inline table keys on the same line
            for inner in re.finditer(r"[{,]\s*([A-Za-z0-9_\-]+)\s*=", line):
                index.setdefault(path + (inner.group(1),), number)
    return index
