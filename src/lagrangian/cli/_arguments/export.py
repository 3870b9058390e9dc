"""``lagrangian export``: its arguments (its work: `lagrangian.cli._export`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_set_option, command

__all__ = ["SUMMARY", "TARGETS", "register"]

#: The names of `lagrangian.codegen.EXPORT_TARGETS`, for the help (a test holds them equal; `--to` is checked
#: by the export itself).
TARGETS = ("numpy", "c", "jax", "octave")

SUMMARY = "write standalone code of M q'' = F and the right-hand side\n(--to numpy | c | jax | octave)"


def register(sub: argparse._SubParsersAction) -> None:
    targets = ", ".join(TARGETS)
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
    p.set_defaults(run=command("export"))
