"""The model a command works on: a model file, a zoo model by name, or the seed's top.

Every command takes the same MODEL argument: a TOML file, a robot's URDF file (``robot.urdf``,
read by `lagrangian.model.urdf.load_urdf`: each joint a coordinate, its effort an input; what it
skips is printed as ``file:line: note: ...`` on stderr), ``zoo:NAME[:N]`` for a model of
`lagrangian.model.zoo` (``zoo:lagrange_top``, ``zoo:planar_chain:40``,
``zoo:spatial_chain:5``), or nothing for the course's heavy symmetric top.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Callable

from ..errors import ModelError
from ..model import load_model, zoo
from ..model.spec import Model
from ..model.urdf import UrdfNote
from ._arguments.common import MODEL_HELP

__all__ = ["MODEL_HELP", "ZOO", "load_source"]

#: The zoo's models that ``zoo:NAME[:N]`` names, and whether they take a size N.
ZOO: dict[str, tuple[Callable[..., Model], bool]] = {
    "lagrange_top": (zoo.lagrange_top, False), "planar_chain": (zoo.planar_chain, True),
    "spatial_chain": (zoo.spatial_chain, True), "relative_chain": (zoo.relative_chain, True),
    "serial_arm": (zoo.serial_arm, True)}


def _zoo_model(name: str) -> Model:
    """``zoo:planar_chain:40`` → ``lagrangian.model.zoo.planar_chain(40)``."""
    _, _, rest = name.partition(":")
    key, _, size = rest.partition(":")
    known = ", ".join(f"zoo:{k}:N" if sized else f"zoo:{k}" for k, (_, sized) in ZOO.items())
    if key not in ZOO:
        raise ModelError(f"`{_short(name)}`: the zoo has no model `{_short(key)}`.", fix=f"use one of {known}")
    make, sized = ZOO[key]
    if not sized:
        if size:
            raise ModelError(f"`{name}`: `{key}` takes no size.", fix=f"write zoo:{key}")
        return make()
    # ASCII digits only: "²".isdigit() is true but int("²") fails; at most 3 digits before int().
    if not (size.isascii() and size.isdigit() and len(size) <= 3) or not 1 <= int(size) <= zoo.MAX_LINKS:
        raise ModelError(f"`{_short(name)}`: `{key}` needs a number of links N from 1 to {zoo.MAX_LINKS}.",
                         fix=f"write e.g. zoo:{key}:3 (digits 0-9, N ≤ {zoo.MAX_LINKS})")
    return make(int(size))


def _short(text: str) -> str:
    return text if len(text) <= 60 else f"{text[:40]} … {text[-10:]}"


def load_source(name: str | None) -> Model:
    """The model named on the command line (module docstring)."""
    if not name:
        return zoo.lagrange_top()
    if name.startswith("zoo:"):
        return _zoo_model(name)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", UrdfNote)
        model = load_model(name)
    for warning in caught:  # a URDF's notes, one line each; any other warning goes on as it came
        if issubclass(warning.category, UrdfNote):
            sys.stderr.write(f"{warning.message}\n")
        else:
            warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
    return model
