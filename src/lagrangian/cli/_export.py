"""``lagrangian export MODEL --to numpy|c|jax|octave [-o DIR] [--set NAME=VALUE]``: standalone code for M q̈ = F.

Writes the directory atomically (`lagrangian.export`, docs/export.md): ``numpy`` writes one
module ``<name>.py`` needing only NumPy; ``c`` writes ``<name>.h`` and ``<name>.c`` needing only
libm; ``jax`` writes one module of jit-able, vmap-able ``jax.numpy`` functions; ``octave`` writes
``.m`` function files.  ``--set`` changes the parameters' default values written into the files.
"""

from __future__ import annotations

import argparse
from dataclasses import replace

from ..codegen import check_target, export, model_identifier
from ..dynamics import derive
from ..model.spec import Model
from ._settings import SettingError, parse_settings
from ._source import load_source

__all__ = ["run"]

def _with_defaults(model: Model, values: dict[str, float]) -> Model:
    """The model with the parameter values given by ``--set`` (coordinates' values are refused)."""
    return replace(model, parameters=tuple(replace(p, value=values[p.name]) if p.name in values else p
                                           for p in model.parameters))


def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    parameters, initial = parse_settings(args.set, model)
    if initial:
        name = next(iter(initial))
        raise SettingError(f"`--set {name}=...`: an export has no initial state, only parameter defaults.",
                           fix="set parameters only (the state is an argument of the exported functions)")
    model = _with_defaults(model, parameters)
    directory = args.directory or f"{model_identifier(model.name)}_{args.target}"
    check_target(args.target)  # before the derivation, which may take a while
    paths = export(derive(model), args.target, directory)
    return "".join(f"wrote {path}\n" for path in paths)
