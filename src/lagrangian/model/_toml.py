"""Read a model file (TOML, with the standard library's `tomllib`) into a `Model`.

The file's tables map onto the course's vocabulary::

    [model]        name, title, description (a text, or one per language: { fr = "…", en = "…" })
    [parameters]   m = 1.0   or   m = { value = 1.0, unit = "kg", description = "mass" }
    [coordinates]  theta = { initial = 0.5, rate = 0.0, momentum = "K" }
    [frames]       R1 = { from = "R0", rotation = ["psi", "z"], axes = ["u", "v", "z0"] }
    [points]       A = "l*R1.x"   or   B = { from = "A", position = "l*R2.x" }
    [bodies.S]     frame, mass, center, fixed_point, free, inertia = { at, frame, diagonal | matrix }
    [particles.P]  mass, position
    [loads]        weight = { gravity = "-g*R0.z" }, push = { force = "...", at = "P" }, ...
    [controls]     F = "-k1*x - k2*x_dot"   (a law per declared input, run by `simulate`)
    [shapes]       S = { kind = "disk", radius = "r", color = "#d62728" }   (how it looks: `_shapes`)

See ``docs/model-format.md`` for every key.  `tomllib` gives no positions for
values, so the line of each declaration is found by scanning the text for its key.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Iterator, Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from ..errors import ModelError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib
from ._assumptions import SIGNS
from ._constraints import read_constraint
from ._friction import FRICTION_KINDS, TOML_KEYS, declare_from_toml
from ._operating_point import located
from ._reference import read_reference
from ._shapes import declare_shapes_from_toml
from ._texts import LANGUAGES, Text
from ._toml_guard import check_nesting
from .build import ModelBuilder
from .spec import Location, Model
from .urdf import load_urdf

__all__ = ["load_model", "parse_model"]

_TABLES = ("model", "parameters", "inputs", "coordinates", "frames", "points", "bodies", "particles", "loads",
           "constraints", "reference", "operating_point", "controls", "shapes")
_LOAD_KINDS = {
    "gravity": {"gravity", "on"},
    "force": {"force", "at"},
    "torque": {"torque", "on", "reaction_on"},
    "spring": {"spring", "stiffness", "rest_length"},
    "damper": {"damper", "coefficient"},
    "potential": {"potential"},
    "generalized_force": {"generalized_force"},
    **TOML_KEYS,  # dissipation, joint_damper, coulomb (`_friction`)
}


def load_model(path: str | PathLike[str]) -> Model:
    """Read and check the model file at ``path``: TOML, or a URDF robot when it ends in ``.urdf``.

    A ``.urdf`` file is read by `lagrangian.model.urdf.load_urdf` (see ``docs/urdf.md``), so
    every command and function that takes a model file takes a robot's URDF too.

    Parameters
    ----------
    path : str or PathLike
        The model file.

    Returns
    -------
    Model
        The checked model.

    Raises
    ------
    ModelError
        With the file, line and symbol of the problem, and how to fix it.
    """
    path = Path(path)
    if path.suffix.lower() == ".urdf":
        return load_urdf(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ModelError(f"model file `{path}` does not exist", file=str(path),
                         fix="check the path, or run `lagrangian derive` with no file for the seed's top") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelError(f"cannot read model file `{path}`: {exc}", file=str(path)) from None
    return parse_model(text, source=str(path))


def parse_model(text: str, *, source: str | None = None) -> Model:
    """Read a model from TOML ``text`` (``source`` names it in error messages).

    Parameters
    ----------
    text : str
        A TOML model.
    source : str, optional
        Names the text in error messages.

    Returns
    -------
    Model
        The checked model.
    """
    check_nesting(text, source)  # before tomllib, which recurses on nested arrays
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise _syntax_error(text, str(exc), source) from None
    except RecursionError:  # pragma: no cover - check_nesting refuses such files first
        raise ModelError("the file is nested too deeply to be read", file=source,
                         fix="remove the extra brackets") from None
    lines = text.splitlines()
    try:
        return _Reader(lines, data, source).read()
    except ModelError as exc:
        if exc.line is not None and exc.source_line is None and 0 < exc.line <= len(lines):
            exc.source_line = lines[exc.line - 1]
        raise


def _syntax_error(text: str, msg: str, source: str | None) -> ModelError:
    """A `ModelError` for tomllib's message ``msg``, naming the key declared twice when that is the problem."""
    m = re.search(r"\(at line (\d+), column (\d+)\)", msg)
    line = int(m.group(1)) if m else None
    column = int(m.group(2)) if m else None
    core = re.sub(r"\s*\(at line \d+, column \d+\)", "", msg)
    lines = text.splitlines()
    if m is None and "end of document" in msg:  # tomllib gives no line there: the construct left open has one
        core = re.sub(r"\s*\(at end of document\)", "", core)
        line, column = _left_open(text)
        core += " (at the end of the file)" if column is None else " (still open at the end of the file)"
    source_line = lines[line - 1] if line is not None and 0 < line <= len(lines) else None
    where: dict[str, Any] = dict(file=source, line=line, column=column, source_line=source_line)
    # The key (or table) declared on the offending line, and where it was declared before.
    path: tuple[str, ...] = ()
    if line is not None:
        for decl, number, _, inner in _declarations(lines[:line]):
            if number == line and not inner:
                path = decl
    symbol = path[-1] if path else None
    first = _first_lines(lines[: line - 1]).get(path, (None,))[0] if (path and line is not None) else None
    inline = re.match(r"Duplicate inline table key '(.*)'", core)
    if inline:
        key = inline.group(1)
        return ModelError(f"key `{key}` is given twice in the same inline table", symbol=key,
                          fix=f"keep one `{key} = ...`", **where)
    if first is not None and ("twice" in core or "overwrite" in core.lower() or "redefine" in core):
        lines_text = f"lines {first} and {line}"
        if len(path) == 2 and path[0] == "frames":
            message = (f"frame `{symbol}` is defined twice ({lines_text}); a frame has exactly one parent, "
                       "so it is declared once")
            fix = f"keep a single definition of `{symbol}`, with its one parent (`from`) and its rotation"
        else:
            table = f"[{'.'.join(path[:-1])}]" if len(path) > 1 else "the file"
            message = f"`{symbol}` is declared twice in {table} ({lines_text})"
            fix = f"declare `{symbol}` once: remove or rename one of the two"
        return ModelError(message, symbol=symbol, fix=fix, **where)
    return ModelError(f"TOML syntax error: {core}", symbol=symbol,
                      fix="correct the TOML syntax of this line (strings in quotes, `key = value`, "
                      "tables as [name])", **where)


def _left_open(text: str) -> tuple[int | None, int | None]:
    """The line and column where the string, array, inline table or header still open at the end starts.

    For tomllib's errors "at end of document" (an unterminated string, an unclosed array):
    one linear pass over the text that follows strings (basic, literal, multi-line, with
    escapes), comments and brackets.  With nothing left open, the last line that is not blank
    (and no column).
    """
    opened: list[tuple[int, int]] = []  # brackets not closed yet: (line, column)
    string: tuple[str, int, int] | None = None  # the delimiter of the open string, where it starts
    line, col, i, n = 1, 1, 0, len(text)
    while i < n:
        ch = text[i]
        if string is not None:
            delim = string[0]
            if ch == "\\" and delim in ('"', '"""'):
                i += 2
                col += 2
                continue
            if text.startswith(delim, i):
                i += len(delim)
                col += len(delim)
                string = None
                continue
            if ch == "\n" and len(delim) == 1:  # a one-line string ends at the line's end (tomllib says so)
                string = None
        elif ch == "#":
            while i < n and text[i] != "\n":
                i += 1
            continue
        elif ch in "\"'":
            delim = ch * 3 if text.startswith(ch * 3, i) else ch
            string = (delim, line, col)
            i += len(delim)
            col += len(delim)
            continue
        elif ch in "[{":
            opened.append((line, col))
        elif ch in "]}" and opened:
            opened.pop()
        if ch == "\n":
            line, col = line + 1, 1
        else:
            col += 1
        i += 1
    if string is not None:
        return string[1], string[2]
    if opened:
        return opened[-1]
    lines = text.splitlines()
    last = max((k for k, t in enumerate(lines, 1) if t.strip()), default=None)
    return last, None


_SINGULAR = {"parameters": "parameter", "inputs": "input", "coordinates": "coordinate", "frames": "frame",
             "points": "point",
             "bodies": "body", "particles": "particle", "loads": "load", "constraints": "constraint"}
#: TOML keys whose builder name differs, by table.
_RENAME = {
    "frames": {"from": "parent"},
    "points": {"from": "relative_to"},
    "particles": {"from": "relative_to"},
    "loads": {"gravity": "field", "spring": "ends", "damper": "ends", "potential": "energy",
              "generalized_force": "components", "dissipation": "function", "joint_damper": "bodies",
              "coulomb": "at"},
}


class _Reader:
    def __init__(self, lines: list[str], data: dict[str, Any], source: str | None) -> None:
        self.lines = lines
        self.data = data
        self.source = source
        self.index = _first_lines(self.lines)

    def at(self, *path: str) -> Location:
        """The line declaring ``path`` (the longest known prefix of it).

        A table known only through a sub-table (``[bodies.S.inertia]`` with no ``[bodies.S]``)
        is placed at the first line of that sub-table.
        """
        for k in range(len(path), 0, -1):
            prefix = tuple(path[:k])
            hit = self.index.get(prefix)
            if hit is None:
                below = [line for key, (line, _) in self.index.items() if key[:k] == prefix]
                hit = (min(below), 0) if below else None
            if hit is not None:
                return Location(self.source, hit[0])
        return Location(self.source, None)

    def located(self, table: str, name: str, value: Any, shorthand: str) -> Location:
        """Where entry ``name`` of ``table`` is declared, with the line (and value column) of each of its keys."""
        loc = self.at(table, name)
        entries = value if isinstance(value, dict) else {shorthand: value}
        rename = _RENAME.get(table, {})
        keys = []
        for key, v in entries.items():
            path = (table, name, key) if isinstance(value, dict) else (table, name)
            hit = self.index.get(path)
            if hit is None:
                continue
            line, column = hit
            text = self.lines[line - 1]
            # The column is kept only where the file spells the string exactly (no escapes).
            if not (column and isinstance(v, str) and text[column - 1:column - 1 + len(v)] == v
                    and text[column - 1 + len(v):column + len(v)] == text[column - 2]):
                column = 0
            keys.append((rename.get(key, key), line, column))
        return Location(loc.file, loc.line, tuple(keys))

    def fail(self, path: tuple[str, ...], message: str, *, fix: str | None = None,
             symbol: str | None = None) -> ModelError:
        loc = self.at(*path)
        return ModelError(message, fix=fix, symbol=symbol, file=loc.file, line=loc.line)

    def table(self, name: str) -> dict[str, Any]:
        value = self.data.get(name, {})
        if not isinstance(value, dict):
            raise self.fail((name,), f"`{name}` must be a table", fix=f"write it as [{name}]")
        return value

    def text(self, path: tuple[str, ...], value: Any) -> Any:
        """A text given as a string, or as a table of languages (``{ fr = "…", en = "…" }``) read into a `Text`;
        anything else is returned as it is, for the caller to refuse."""
        if not isinstance(value, dict):
            return value
        unknown = sorted(set(value) - set(LANGUAGES))
        if unknown or not value:
            raise self.fail(path, f"`{path[-1]}` has unknown language `{unknown[0]}`" if unknown
                            else f"`{path[-1]}` is an empty table", symbol=path[-1],
                            fix='give the text in French and/or English, e.g. { fr = "masse", en = "mass" }')
        for lang, text in value.items():
            if not isinstance(text, str) or not text.strip():
                raise self.fail(path, f"`{path[-1]}.{lang}` must be text, not `{text}`", symbol=path[-1],
                                fix=f'write it in quotes, e.g. {lang} = "..."')
        return Text({lang: value[lang] for lang in LANGUAGES if lang in value})

    def entry(self, table: str, name: str, value: Any, allowed: set[str], shorthand: str) -> dict[str, Any]:
        """An entry given either as a table with ``allowed`` keys, or as a bare value for ``shorthand``;
        its description may be a table of languages."""
        if not isinstance(value, dict):
            return {shorthand: value}
        if "description" in allowed and isinstance(value.get("description"), dict):
            value = {**value, "description": self.text((table, name, "description"), value["description"])}
        unknown = set(value) - allowed
        if unknown:
            key = sorted(unknown)[0]
            raise self.fail((table, name, key), f"unknown key `{key}` in {_SINGULAR[table]} `{name}`", symbol=key,
                            fix="the keys allowed here are " + ", ".join(sorted(allowed)))
        return value

    def read(self) -> Model:
        for key in self.data:
            if key not in _TABLES:
                raise self.fail((key,), f"unknown table `[{key}]`", symbol=key,
                                fix="the tables are " + ", ".join(f"[{t}]" for t in _TABLES))
        meta = dict(self.table("model"))
        for key, value in meta.items():
            if key not in ("name", "description", "title"):
                raise self.fail(("model", key), f"unknown key `{key}` in [model]", symbol=key,
                                fix="the keys allowed in [model] are name, title and description")
            if key != "name":
                meta[key] = value = self.text(("model", key), value)
            if not isinstance(value, str):
                raise self.fail(("model", key), f"`{key}` in [model] must be text, not `{value}`", symbol=key,
                                fix=f'write it in quotes, e.g. {key} = "..."')
        b = ModelBuilder(meta.get("name", Path(self.source).stem if self.source else "model"),
                         meta.get("description", ""), source=self.source, title=meta.get("title"))
        for name, value in self.table("parameters").items():
            v = self.entry("parameters", name, value, {"value", "unit", "description", *SIGNS}, "value")
            b.parameter(name, v.get("value"), unit=v.get("unit"), description=v.get("description"),
                        **{sign: v.get(sign) for sign in SIGNS},
                        location=self.located("parameters", name, value, "value"))
        for name, value in self.table("inputs").items():
            if not isinstance(value, (dict, str)):
                raise self.fail(("inputs", name), f"input `{name}` must be a table, not `{value}`", symbol=name,
                                fix=f'e.g. {name} = {{ description = "hip torque", unit = "N*m" }}, or {name} = {{}}')
            v = self.entry("inputs", name, value, {"unit", "description"}, "description")
            b.input(name, unit=v.get("unit"), description=v.get("description"),
                    location=self.located("inputs", name, value, "description"))
        for name, value in self.table("coordinates").items():
            v = self.entry("coordinates", name, value,
                           {"initial", "rate", "momentum", "unit", "description", "range"}, "initial")
            b.coordinate(name, v.get("initial"), v.get("rate"), momentum=v.get("momentum"), unit=v.get("unit"),
                         description=v.get("description"), range=v.get("range"),
                         location=self.located("coordinates", name, value, "initial"))
        for name, value in self.table("frames").items():
            v = self.entry("frames", name, value, {"from", "rotation", "axes"}, "from")
            b.frame(name, v.get("from"), rotation=v.get("rotation"), axes=v.get("axes"),
                    location=self.located("frames", name, value, "from"))
        for name, value in self.table("points").items():
            v = self.entry("points", name, value, {"from", "position"}, "position")
            if "position" not in v:
                raise self.fail(("points", name), f"point `{name}` has no position", symbol=name,
                                fix='e.g. A = "l*R1.x" or A = { from = "B", position = "l*R1.x" }')
            b.point(name, v["position"], relative_to=v.get("from", "O"),
                    location=self.located("points", name, value, "position"))
        for name, value in self.table("bodies").items():
            v = self.entry("bodies", name, value,
                           {"frame", "mass", "center", "from", "center_from", "inertia", "fixed_point", "free", "shape"}, "frame")
            for key in ("frame", "center"):  # `mass` may be left out where it cannot enter (`Assembler.bodies`)
                if key not in v:
                    raise self.fail(("bodies", name), f"body `{name}` has no `{key}`", symbol=name,
                                    fix=f"add `{key} = ...` to [bodies.{name}]")
            # `from` gives G from another point, as for points and particles; `center_from` is its older spelling.
            if "from" in v and "center_from" in v:
                raise self.fail(("bodies", name, "center_from"), f"body `{name}` gives both `from` and `center_from`, "
                                "two spellings of the point its center is measured from", symbol=name,
                                fix="keep `from` (`center_from` is its older spelling)")
            b.body(name, frame=v["frame"], mass=v.get("mass"), center=v["center"],
                   center_from=v.get("from", v.get("center_from", "O")),
                   inertia=v.get("inertia"), fixed_point=v.get("fixed_point"), free=v.get("free", False),
                   location=self.located("bodies", name, value, "frame"))
        for name, value in self.table("particles").items():
            v = self.entry("particles", name, value, {"mass", "position", "from", "shape"}, "position")
            for key in ("mass", "position"):
                if key not in v:
                    raise self.fail(("particles", name), f"particle `{name}` has no `{key}`", symbol=name,
                                    fix=f"add `{key} = ...` to [particles.{name}]")
            b.particle(name, mass=v["mass"], position=v["position"], relative_to=v.get("from", "O"),
                       location=self.located("particles", name, value, "position"))
        for name, value in self.table("loads").items():
            self.load(b, name, value)
        for name, value in self.table("constraints").items():
            read_constraint(self, b, name, value)
        if "operating_point" in self.data:
            self.operating_point(b)
        if "controls" in self.data:
            self.controls(b)
        if "reference" in self.data:
            frame, origin, where = read_reference(self.data["reference"], self.index, self.source)
            b.reference(frame, origin=origin, location=where)
        declare_shapes_from_toml(self, b)
        return b.build()

    def operating_point(self, b: ModelBuilder) -> None:
        """``[operating_point]``: values by coordinate or rate name, and the lists ``independent``, ``dependent``."""
        table = self.table("operating_point")
        keys = {}
        for key in table:
            hit = self.index.get(("operating_point", key))
            if hit is not None:
                line, column = hit
                value = table[key]
                text = self.lines[line - 1]
                if not (column and isinstance(value, str) and text[column - 1:column - 1 + len(value)] == value):
                    column = 0
                keys[key] = (line, column)
        where = located(self.source, self.at("operating_point").line, keys)
        values = {k: v for k, v in table.items() if k not in ("independent", "dependent")}
        b.operating_point(values, independent=table.get("independent"), dependent=table.get("dependent"),
                          location=where)

    def controls(self, b: ModelBuilder) -> None:
        """``[controls]``: a law (an expression in quotes) per declared input, with each key's line and column."""
        table = self.table("controls")
        keys = {}
        for key, value in table.items():
            hit = self.index.get(("controls", key))
            if hit is not None:
                line, column = hit
                text = self.lines[line - 1]
                if not (column and isinstance(value, str) and text[column - 1:column - 1 + len(value)] == value):
                    column = 0
                keys[key] = (line, column)
        b.controls(table, location=located(self.source, self.at("controls").line, keys))

    def names(self, load: str, key: str, value: Any) -> tuple[str, ...]:
        """A name or a list of names (the ends of a spring, the bodies gravity acts on)."""
        if isinstance(value, str):
            return (value,)
        if isinstance(value, list) and all(isinstance(v, str) for v in value):
            return tuple(value)
        raise self.fail(("loads", load, key), f"`{key}` of load `{load}` must be a name or a list of names, "
                        f"not `{value}`", symbol=load, fix=f'e.g. {key} = ["A", "B"]')

    def load(self, b: ModelBuilder, name: str, value: Any) -> None:
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
        where = self.located("loads", name, value, kind)
        if kind == "gravity":
            b.gravity(name, value["gravity"], on=self.names(name, "on", value.get("on", [])), location=where)
        elif kind == "force":
            if "at" not in value:
                raise self.fail(("loads", name), f"force `{name}` has no point of application", symbol=name,
                                fix='add at = "P"')
            b.force(name, value["force"], at=value["at"], location=where)
        elif kind == "torque":
            if "on" not in value:
                raise self.fail(("loads", name), f"torque `{name}` does not say which body or frame it acts on",
                                symbol=name, fix='add on = "S"')
            b.torque(name, value["torque"], on=value["on"], reaction_on=value.get("reaction_on"), location=where)
        elif kind == "spring":
            b.spring(name, self.names(name, kind, value["spring"]),
                     stiffness=_required(self, name, value, "stiffness"),
                     rest_length=value.get("rest_length", 0), location=where)
        elif kind == "damper":
            b.damper(name, self.names(name, kind, value["damper"]),
                     coefficient=_required(self, name, value, "coefficient"), location=where)
        elif kind == "potential":
            b.potential(name, value["potential"], location=where)
        elif kind in FRICTION_KINDS:
            declare_from_toml(self, b, name, value, kind, where)
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


_HEADER = re.compile(r"^\s*\[\[?\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")
_KEY = re.compile(r"^\s*((?:[A-Za-z0-9_\-]+|\"[^\"]*\"|'[^']*')(?:\s*\.\s*(?:[A-Za-z0-9_\-]+|\"[^\"]*\"|'[^']*'))*)\s*=")


def _split_key(key: str) -> tuple[str, ...]:
    parts = re.findall(r"\"([^\"]*)\"|'([^']*)'|([A-Za-z0-9_\-]+)", key)
    return tuple(a or b or c for a, b, c in parts)


def _value_column(line: str, end: int) -> int:
    """1-based column of the first character of a one-line string value starting after ``end``, else 0."""
    rest = line[end:]
    start = end + len(rest) - len(rest.lstrip())
    quote = line[start:start + 1]
    if quote in ('"', "'") and line[start:start + 3] != quote * 3:
        return start + 2
    return 0


def _declarations(lines: list[str]) -> Iterator[tuple[tuple[str, ...], int, int, bool]]:
    """Yield ``(path, line, value column, inner)`` for each table header and ``key =`` line.

    Keys inside inline tables are found too (``R1 = { from = "R0" }`` yields both
    ``frames.R1`` and ``frames.R1.from``, the latter with ``inner`` true) on the line
    where they appear.
    """
    current: tuple[str, ...] = ()
    for number, line in enumerate(lines, start=1):
        header = _HEADER.match(line)
        if header:
            current = _split_key(header.group(1))
            yield current, number, 0, False
            continue
        key = _KEY.match(line)
        if key:
            path = current + _split_key(key.group(1))
            yield path, number, _value_column(line, key.end()), False
            # inline table keys on the same line
            for inner in re.finditer(r"[{,]\s*([A-Za-z0-9_\-]+)\s*=", line):
                yield path + (inner.group(1),), number, _value_column(line, inner.end()), True


def _first_lines(lines: list[str]) -> dict[tuple[str, ...], tuple[int, int]]:
    """Map each declared path to the 1-based line (and value column) of its first declaration."""
    index: dict[tuple[str, ...], tuple[int, int]] = {}
    for path, number, column, _ in _declarations(lines):
        index.setdefault(path, (number, column))
    return index
