"""``lagrangian linearize MODEL --at theta=3.14159 [--at x=0] [--set NAME=VALUE] [--inputs tau] [--symbolic v]
[--json] [-o FILE]``: the equations of motion linearized about an equilibrium or a steady motion.

Prints M, D, G, K, N (M δq̈ + (D + G) δq̇ + (K + N) δq = B u) and the state space ẋ = A x + B u,
with the eigenvalues and the stability verdict when every parameter has a value; ``--json``
prints the versioned document ``lagrangian.linearize`` (docs/small-motions.md).
"""

from __future__ import annotations

import argparse
import json

from .. import __version__
from ..dynamics import derive
from ..output import linear_text, linearize_document
from ._point import linearize_from_args
from ._source import load_source

__all__ = ["run"]

def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    eom = derive(model)
    lin = linearize_from_args(args, model, eom)
    stability = modes = None
    if not lin.symbols:
        stability, modes = lin.stability(), lin.modes()
    if args.json:
        doc = linearize_document(lin, source=model.source, package_version=__version__, stability=stability,
                                 modes=modes)
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
    return linear_text(lin, stability, modes)
