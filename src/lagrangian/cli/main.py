"""``lagrangian`` command line: one error boundary, nothing below it prints or exits.

    lagrangian derive [MODEL.toml] [--latex | --json] [-o FILE]

Exit codes: 0 success, 1 usage error (argparse), 2 bad model or derivation error,
3 output file could not be written.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path

from .. import __version__
from ..analysis import first_integrals
from ..dynamics import derive
from ..errors import LagrangianError, ModelError
from ..model import load_model
from ..model.zoo import lagrange_top
from ..output import course_form, derive_document, render_latex, render_text
from ._atomic import write_atomic

__all__ = ["main", "entrypoint"]

_DESCRIPTION = """\
Lagrange's equations of a mechanical system, derived the way the course does it:
principal parameters, virtual velocity field, T and U, generalized forces by virtual
power, the n Lagrange equations, first integrals, and M(q,t) q'' = F(q,q',t).

commands:
  derive    derive and print the equations of motion of a model file
            (with no file: the course's heavy symmetric top, the Lagrange top)

Run `lagrangian derive --help` for its options. Model file format: docs/model-format.md.
"""


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="lagrangian", description=_DESCRIPTION,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"lagrangian {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    d = sub.add_parser(
        "derive", help="derive the equations of motion of a model",
        description="Derive T, U, the generalized forces, the Lagrange equations L(q_i), the first integrals "
                    "and the matrix form M q'' = F of a model, and print them in the course's notation.",
    )
    d.add_argument("model", nargs="?", help="model file (TOML); default: the seed's Lagrange top")
    fmt = d.add_mutually_exclusive_group()
    fmt.add_argument("--latex", action="store_true", help="print a LaTeX document instead of text")
    fmt.add_argument("--json", action="store_true",
                     help="print the versioned JSON document (schema lagrangian.derive/1, docs/derive-json.md)")
    d.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of standard output")
    return parser


def _derive(args: argparse.Namespace) -> str:
    model = load_model(args.model) if args.model else lagrange_top()
    eom = derive(model)
    form = course_form(eom, first_integrals(eom))
    if args.json:
        initial = {c.name: {"value": c.initial, "rate": c.rate} for c in model.coordinates}
        doc = derive_document(form, parameters=model.parameter_values, initial=initial, source=model.source,
                              package_version=__version__)
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
    if args.latex:
        return render_latex(form)
    return render_text(form)


def _report(error: LagrangianError) -> str:
    if isinstance(error, ModelError):
        where = error.location
        lines = [f"{where}: error: {error.message}" if where else f"error: {error.message}"]
        if error.file and error.line:
            try:
                source = Path(error.file).read_text(encoding="utf-8").splitlines()[error.line - 1]
                gutter = f"  {error.line} | "
                lines.append(gutter + source)
                if error.column and 0 < error.column <= len(source) + 1:
                    lines.append(" " * (len(gutter) + error.column - 1) + "^")
            except (OSError, IndexError, UnicodeDecodeError):
                pass
    else:
        lines = [f"error: {error.message}"]
    if error.fix:
        lines.append(f"  tip: {error.fix}")
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (default: ``sys.argv[1:]``); return the exit code."""
    parser = _parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    try:
        text = _derive(args)
    except LagrangianError as exc:
        sys.stderr.write(_report(exc))
        return 2
    if args.output:
        try:
            write_atomic(args.output, text)
        except OSError as exc:
            sys.stderr.write(f"error: cannot write `{args.output}`: {exc.strerror or exc}\n")
            return 3
    else:
        sys.stdout.write(text)
    return 0


def entrypoint() -> None:
    """Console-script entry point."""
    raise SystemExit(main())
