"""``lagrangian derive [MODEL.toml] [--latex | --json] [-o FILE]``."""

from __future__ import annotations

import argparse
import json

from .. import __version__
from ..analysis import first_integrals
from ..dynamics import derive
from ..output import course_form, derive_document, render_latex, render_text
from ._source import MODEL_HELP, load_source
from ..output._text import supplement

__all__ = ["register"]

SUMMARY = "derive and print the equations of motion of a model file\n" \
          "(with no file: the course's heavy symmetric top, the Lagrange top)"


def register(sub: argparse._SubParsersAction) -> None:
    d = sub.add_parser(
        "derive", help="derive the equations of motion of a model",
        description="Derive T, U, the generalized forces, the Lagrange equations L(q_i), the first integrals "
                    "and the matrix form M q'' = F of a model, and print them in the course's notation.",
    )
    d.add_argument("model", nargs="?", help=MODEL_HELP)
    fmt = d.add_mutually_exclusive_group()
    fmt.add_argument("--latex", action="store_true", help="print a LaTeX document instead of text")
    fmt.add_argument("--json", action="store_true",
                     help="print the versioned JSON document (schema lagrangian.derive/1, docs/derive-json.md)")
    d.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of standard output")
    d.set_defaults(run=run)


def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    eom = derive(model)
    form = course_form(eom, first_integrals(eom))
    if args.json:
        initial = {c.name: {"value": c.initial, "rate": c.rate} for c in model.coordinates}
        doc = derive_document(form, parameters=model.parameter_values, initial=initial, source=model.source,
                              package_version=__version__, eom=eom)
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
    extra = supplement(eom, form)
    if args.latex:
        return render_latex(form, extra)
    return render_text(form, extra)
