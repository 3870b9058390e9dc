"""``lagrangian export MODEL --to numpy|c|jax|octave [-o DIR] [--set NAME=VALUE]``: standalone code for M q̈ = F.

Writes the directory atomically (`lagrangian.export`, docs/export.md): ``numpy`` writes one
module ``<name>.py`` needing only NumPy; ``c`` writes ``<name>.h`` and ``<name>.c`` needing only
libm; ``jax`` writes one module of jit-able, vmap-able ``jax.numpy`` functions; ``octave`` writes
``.m`` function files.  ``--set`` changes the parameters' default values written into the files.
"""

from __future__ import annotations

import argparse
from dataclasses import replace

from ..dynamics import derive
from ..model.spec import Model
from ..output import EXPORT_TARGETS, export
from ..output._export import check_target, model_identifier
from ._settings import SettingError, add_set_option, parse_settings
from ._source import MODEL_HELP, load_source

__all__ = ["register", "run"]

SUMMARY = "write standalone code of M q'' = F and the right-hand side\n(--to numpy | c | jax | octave)"


def register(sub: argparse._SubParsersAction) -> None:
    targets = ", ".join(EXPORT_TARGETS)
    p = sub.add_parser(
        "export", help="write the equations as standalone NumPy, C, JAX or Octave code",
        description="Write M(q, t), F(q, q', t) and the right-hand side y' = (q', q'') of the model as code that "
                    "needs nothing of lagrangian: --to numpy writes one module needing only NumPy (rhs batched over "
                    "states), --to c a header and a source needing only libm, --to jax one module of jit-able, "
                    "vmap-able jax.numpy functions, --to octave .m functions for Octave and MATLAB. Every file "
                    "names the model, the lagrangian version, the parameters with their defaults and the state "
                    "order. Every target has the constraint rows of a constrained model and solves for its "
                    "multipliers; the C export also has the first integrals. All refuse an exact stick/slip "
                    "contact (docs/export.md).")
    p.add_argument("model", nargs="?", help=MODEL_HELP)
    p.add_argument("--to", dest="target", required=True, metavar="TARGET", help=f"the target: {targets}")
    p.add_argument("-o", "--output-dir", dest="directory", metavar="DIR",
                   help="the directory to write (atomically; default: <model>_<target> in the current folder); "
                        "an existing one may hold only the files of an earlier export")
    add_set_option(p)
    p.set_defaults(run=run)


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
