"""``lagrangian derive [MODEL.toml] [--latex | --json] [--expanded | --intermediates] [-o FILE]``.

A robot (a model derived in the recursive form, `dynamics._recursive`) has expanded
entries of thousands of terms (2 MB of text and 40–50 s at 7 joints, more than 5 minutes for the Panda):
its text and LaTeX show the course's view with every long expression summarized as
⟨24 terms⟩ (the report's `SizeGate`), ``--expanded`` prints them in full, and
``--intermediates`` prints T, U, M and F over the named intermediates the compiled code
computes (linear in the joints), each intermediate with its formula.
"""

from __future__ import annotations

import argparse
import json

from .. import __version__
from ..analysis import first_integrals
from ..dynamics import EquationsOfMotion, derive
from ..errors import DerivationError
from ..output import (
    SizeGate,
    course_form,
    derive_document,
    needed_intermediates,
    render_intermediates,
    render_latex,
    render_text,
    supplement,
)
from ._settings import SettingError
from ._source import load_source

__all__ = ["run"]

def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    eom = derive(model)
    robot = eom.formulation == "recursive"
    if args.intermediates:
        if args.latex or args.json:
            raise SettingError("--intermediates prints text only.",
                               fix="leave out --latex/--json, or --intermediates (the JSON has every expression)")
        if not robot:
            raise DerivationError(f"model `{model.name}` is derived by the course's route, without intermediates",
                                  fix="leave out --intermediates (its expressions are printed in full)")
        return render_intermediates(eom)
    # A robot's course view, summarized (JSON always has every expression in full).
    gate = SizeGate("terms", "long expression") if robot and not args.expanded and not args.json else None
    form = course_form(eom, first_integrals(eom), **({"convert": gate} if gate is not None else {}))
    if args.json:
        initial = {c.name: {"value": c.initial, "rate": c.rate} for c in model.coordinates}
        doc = derive_document(form, parameters=model.parameter_values, initial=initial, source=model.source,
                              package_version=__version__, eom=eom)
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
    extra = supplement(eom, form)
    if args.latex:
        text = render_latex(form, extra)
        if gate is not None and gate.summaries:
            text = text.replace(r"\end{document}", _note(eom, gate, latex=True) + "\n\\end{document}")
        return text
    text = render_text(form, extra)
    if gate is not None and gate.summaries:
        text = text.rstrip("\n") + "\n\n" + _note(eom, gate) + "\n"
    return text


def _note(eom: EquationsOfMotion, gate: SizeGate, *, latex: bool = False) -> str:
    """What the summaries stand for, and where the full expressions are."""
    assert eom.recursive is not None
    count = len(needed_intermediates(eom.recursive))
    text = (f"{len(gate.summaries)} long expressions are summarized as ⟨N terms⟩: the expanded entries of a robot in "
            f"relative joint angles grow several-fold per joint. `lagrangian derive --expanded` prints them in full "
            f"(slow), --json holds them all, and `lagrangian derive --intermediates` prints T, U, M and F over the "
            f"{count} named intermediates the compiled code computes.")
    if latex:
        text = (text.replace("⟨N terms⟩", r"$\langle N\ \text{terms}\rangle$").replace("`", "")
                .replace("--", "-{}-"))
    return text
