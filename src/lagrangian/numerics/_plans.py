"""What `compile_system` finds before the C compiler runs, kept between runs: its plans.

A compiled library is found in the cache (`_compile`) by the SHA-256 of its C source, so a run
that finds it has still derived the first integrals and generated the source: for the Lagrange
top, 0.5 s of a 0.9 s ``lagrangian simulate``, most of it loading the SymPy and SciPy that these
steps use; for the 30-joint arm, 1.7 s of generation.  A plan records what the compiled system
needs besides the library: the names of its first integrals and monitors, the number of
constants hoisted into ``p``, and the key and number of units of its library.  The next run with
the same equations loads the library directly; the first integrals themselves (expressions) and
the C source are then made only if asked for (`CompiledSystem.first_integrals`, ``.source``).

The equations are named, not read: a plan is kept only for equations made by `derive`
(``EquationsOfMotion.derived_with``), and its key is the SHA-256 of what they are a function of:

* the package's code: each file's path, size and modification time (the test Python applies to
  its own bytecode), the package version and SymEngine's;
* the model (``repr``: every field, the expressions in SymEngine's exact form) and the
  formulation asked of `derive` and found by it;
* the compiled system's options: the inputs' regime, the inputs' law (its generated C) and the
  events (names and expressions).

Plans are JSON (data, never code), in the compile cache's private folder, each with its SHA-256
in a sidecar file, read only when private and matching, as the libraries are (`_compile`).  A plan
that cannot be used (missing, refused, malformed, or naming a library that is gone) is ignored:
the system is then made from the equations as if there were none, and the plan written anew.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import sys
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import symengine as se

from .. import __version__
from ..dynamics import EquationsOfMotion
from ._compile import _digest, _sidecar, _usable_cache, _why_not_verified

__all__ = ["Plan", "plan_key", "read_plan", "write_plan"]

#: The version of the plan files' layout (a change makes older plans unused, never misread).
LAYOUT = 1
#: The package files whose changes make new plans.
_CODE_SUFFIXES = (".py", ".c", ".h", ".json", ".toml")
_HEX = re.compile(r"[0-9a-f]{64}")


@dataclass(frozen=True)
class Plan:
    """A compiled system's names and its library's key (module docstring)."""

    integrals: tuple[str, ...]
    monitors: tuple[str, ...]
    constants: int
    library: str
    units: int


@cache
def code_identity() -> str:
    """SHA-256 of the package's files (path, size, modification time), its version and SymEngine's."""
    root = str(Path(__file__).resolve().parents[1])
    entries = []
    folders = [root]
    while folders:
        with os.scandir(folders.pop()) as found:
            for entry in found:
                if entry.is_dir(follow_symlinks=False):
                    if entry.name != "__pycache__":
                        folders.append(entry.path)
                elif entry.name.endswith(_CODE_SUFFIXES):
                    info = entry.stat()
                    entries.append(f"{entry.path[len(root):]} {info.st_size} {info.st_mtime_ns}")
    text = "\n".join([__version__, se.__version__, sys.platform, *sorted(entries)])
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def plan_key(eom: EquationsOfMotion, regime: Mapping[str, str], law: str | None,
             events: Sequence[tuple[str, se.Basic]]) -> str | None:
    """The key of the plan of ``eom`` compiled with these options; None when ``eom`` was not made by `derive`.

    ``law`` is the C text of the inputs' law (None without one).
    """
    if eom.derived_with is None:
        return None
    described = json.dumps({
        "layout": LAYOUT, "code": code_identity(), "model": repr(eom.model),
        "formulation": [eom.derived_with, eom.formulation], "regime": sorted(regime.items()), "law": law,
        "events": [[name, str(expr)] for name, expr in events],
    })
    return hashlib.sha256(described.encode("utf-8")).hexdigest()


def _path(key: str) -> Path:
    return _usable_cache() / f"plan_{key[:32]}.json"


def read_plan(key: str) -> Plan | None:
    """The plan stored under ``key`` when there is one that passes the cache's checks, else None."""
    path = _path(key)
    try:
        if not path.is_file() or _why_not_verified(path) is not None:
            return None
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return None
    return _plan_of(doc, key)


def _plan_of(doc: object, key: str) -> Plan | None:
    """The `Plan` of a plan file's content, or None unless every field is as `write_plan` writes it."""
    if not isinstance(doc, dict) or doc.get("layout") != LAYOUT or doc.get("key") != key:
        return None
    names = [doc.get("integrals"), doc.get("monitors")]
    constants, units = doc.get("constants"), doc.get("units")
    if not all(isinstance(v, list) and all(isinstance(s, str) for s in v) for v in names):
        return None
    if not (type(constants) is int and type(units) is int and constants >= 0 and units >= 0) \
            or not isinstance(doc.get("library"), str):
        return None
    if not _HEX.fullmatch(doc["library"]) or units < 1:
        return None
    return Plan(tuple(names[0]), tuple(names[1]), constants, doc["library"], units)  # type: ignore[arg-type]


def write_plan(key: str, plan: Plan) -> None:
    """Store ``plan`` under ``key``, atomically, with its checksum; a cache that cannot be written is left as is."""
    path = _path(key)
    doc = {"layout": LAYOUT, "key": key, "integrals": list(plan.integrals), "monitors": list(plan.monitors),
           "constants": plan.constants, "library": plan.library, "units": plan.units}
    try:
        with tempfile.TemporaryDirectory(dir=path.parent) as tmp:
            written, digest = Path(tmp) / "plan.json", Path(tmp) / "plan.sha256"
            written.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
            digest.write_text(_digest(written) + "\n", encoding="ascii")
            os.chmod(written, 0o600)
            os.chmod(digest, 0o600)
            # The plan first, its checksum second (as a library and its checksum, `_compile`).
            os.replace(written, path)
            os.replace(digest, _sidecar(path))
    except OSError:
        pass  # a plan only saves time: without it the next run makes the system from the equations
