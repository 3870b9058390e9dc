"""What every part of the report shares: the derivation, its course form, the words, the notation.

`Context` holds them for one report, with the few ways the report writes things: engine
expressions in LaTeX (through the `SizeGate`, so that long ones are summarized), names of
bodies, points and frames, vectors, and displayed equations (cut into lines, folded when
long).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence

import symengine as se
import sympy

from ...analysis import FirstIntegral
from ...dynamics import EquationsOfMotion
from ...model import GALILEAN_FRAME, ORIGIN, Body, Particle, Vector
from .._course import CourseForm, _vector_row, course_form
from .._display_form import display_form
from .._notation import Notation, _axis_latex, _base_latex, _is_word
from .._text import notation
from . import size as _report_size
from .document import Block, Display, Equation, Fold, Math
from .full_forms import FullFormBook
from .joints import Joint, joints
from .size import FOLD_LINES, SizeGate, visible_width, wrap, wrap_latex, wrap_many
from .words import Words

__all__ = ["Context", "tex_name", "tex_text"]

#: Letters the report uses for its own quantities: a frame with such a name is written R_E, R_L…
_TAKEN = frozenset({"E", "L", "T", "U", "H", "K", "h", "M", "F", "Q"})


def tex_text(name: str) -> str:
    """A load or constraint name as text inside math: ``\\text{weight}``, ``my_load`` → ``\\text{my}\\_\\text{load}``.

    (``\\_`` inside ``\\text`` is not understood by every converter to MathML; between two
    ``\\text`` it is, and LaTeX accepts it in math mode.)
    """
    clean = re.sub(r"[\\{}$&#%^~]", "", name)
    return r"\_".join(rf"\text{{{part}}}" for part in clean.split("_") if part) or r"\text{?}"


def tex_name(name: str) -> str:
    """LaTeX of a body, point or frame name: S1 → S_{1}, G_S1 → G_{S_{1}}, an inner frame _S_2 → S''."""
    if name.startswith("_"):
        head, _, k = name[1:].rpartition("_")
        return tex_name(head) + "'" * int(k) if k.isdigit() else tex_name(name[1:])
    head, sep, tail = name.partition("_")
    if sep and head and tail and not all(_is_word(part) for part in name.split("_")):
        return f"{tex_name(head)}_{{{tex_name(tail)}}}"
    return _base_latex(name)  # upper_arm, a URDF link: one upright name


_SUBSCRIPTS = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


def coordinate_names(model) -> dict[str, tuple[str, str]]:
    """q₁, q₂, … for the coordinates when one of them is a word (a URDF joint, ``shoulder``): a dot over a word
    (``shoulderṫ``) is no notation.  Each decorated form gets its own entry (q̇₁, q̈₁, q₁*), and so does a constant
    named after a coordinate (the actuator ``tau_shoulder`` → τ₂).  Step 2 lists the names beside the q_k."""
    from .._notation import _is_word

    coordinates = [c.name for c in model.coordinates]
    if not any(_is_word(name.partition("_")[0]) for name in coordinates):
        return {}
    out: dict[str, tuple[str, str]] = {}
    for k, name in enumerate(coordinates, 1):
        sub = str(k).translate(_SUBSCRIPTS)
        out[name] = (f"q{sub}", f"q_{{{k}}}")
        out[f"{name}_dot"] = (f"q\u0307{sub}", rf"\dot{{q}}_{{{k}}}")
        out[f"{name}_ddot"] = (f"q\u0308{sub}", rf"\ddot{{q}}_{{{k}}}")
        out[f"{name}_star"] = (f"q{sub}*", f"q_{{{k}}}^{{*}}")
        for p in model.parameters:  # tau_shoulder → τ₂
            head, sep, tail = p.name.partition("_")
            if sep and tail == name:
                text, tex = Notation().symbol(head), Notation().symbol(head, latex=True)
                out[p.name] = (f"{text}{sub}", f"{tex}_{{{k}}}")
    return out


def report_notation(form: CourseForm, model, names: dict[str, tuple[str, str]] | None = None,
                    lang: str = "en") -> Notation:
    """The report's notation: masses before the other constants (m2 l1 l2, m g a), and forms a teacher would
    write (`display_form`); ``names`` writes some symbols otherwise (the multipliers, `multiplier_names`).
    French numbers take a decimal comma; a URDF robot's numbers (its masses, inertias, lengths) are decimals."""
    base = notation(form)
    masses = [p.name for p in model.parameters if (p.unit or "").replace(" ", "") == "kg"]
    order = tuple(masses) + tuple(p for p in base.parameters if p not in masses)
    constants = frozenset(order)
    return Notation(base.coordinates, order, rewrite=functools.partial(display_form, parameters=constants),
                    names=dict(names or {}), decimals=is_urdf(model), comma=lang == "fr")


#: SI units a model's parameters may be written in: then its numbers (a body's mass 8) are in SI units (8 kg).
_SI = {"m", "kg", "s", "rad", "N", "J", "W", "Pa", "kg m^2", "kg*m^2", "kg·m²", "m/s", "m/s^2", "m/s²", "rad/s",
       "N m", "N*m", "N·m", "N/m", "N s/m", "N*s/m", "kg/s", "1", ""}


def is_urdf(model) -> bool:
    """A robot read from a URDF file: its numbers are the file's decimals, in SI units."""
    return str(model.source or "").lower().endswith(".urdf")


#: Letters for the multipliers, the first one the model's symbols leave free (the bicycle's steer axis tilt is λ).
_MULTIPLIER_LETTERS = (("λ", r"\lambda"), ("μ", r"\mu"), ("ν", r"\nu"), ("Λ", r"\Lambda"))


def multiplier_names(eom: EquationsOfMotion) -> dict[str, tuple[str, str]]:
    """How a teacher names the multipliers: λ for a single complementary row, λ_1 … λ_k for several, numbered
    in the order of the model's constraints (the engine's rows).  The engine's names (``lambda_length``,
    ``lambda_rolling_x1``) stay those of the JSON and command-line outputs.

    When a parameter or coordinate of the model is already written λ, the next free letter is taken (μ, ν…).
    """
    rows = eom.constraints
    if not rows:
        return {}
    plain = Notation()
    own = [p.name for p in eom.model.parameters] + list(eom.coordinates)
    used = {plain.symbol(name, latex=True).split("_")[0] for name in own}
    text, tex = next(((t, x) for t, x in _MULTIPLIER_LETTERS if x not in used), _MULTIPLIER_LETTERS[-1])
    if len(rows) == 1:
        return {rows[0].multiplier.name: (text, tex)}
    return {r.multiplier.name: (f"{text}{k}", f"{tex}_{{{k}}}") for k, r in enumerate(rows, 1)}


class Context:
    """One report in the making: the derivation and how to write it in one language."""

    def __init__(self, eom: EquationsOfMotion, integrals: tuple[FirstIntegral, ...], lang: str,
                 source: str | None = None) -> None:
        self.eom = eom
        self.source = source if source is not None else eom.model.source
        self.model = eom.model
        self.kin = eom.kinematics
        self.integrals = integrals
        self.w = Words(lang)
        self.lang = lang
        self.gate = SizeGate(self.w.text("terms"), self.w.text("long expression"))
        self.form: CourseForm = course_form(eom, integrals, convert=self.gate)
        self.multiplier_names = multiplier_names(eom)
        self.coordinate_names = coordinate_names(eom.model)
        self.n: Notation = report_notation(self.form, self.model, {**self.coordinate_names, **self.multiplier_names},
                                           lang)
        self.book = FullFormBook(self.n, self.w.text("see"))
        reference = self.model.reference
        relative = reference is not None and not reference.is_galilean_frame
        self.ref = reference.frame if relative else GALILEAN_FRAME  # type: ignore[union-attr]
        self.origin = reference.origin if relative else ORIGIN  # type: ignore[union-attr]
        self.joints: tuple[Joint, ...] = joints(eom)
        self.bodies = {b.name for b in self.model.bodies}
        self.frames = {f.name for f in self.model.frames}
        units = [p.unit.strip() for p in self.model.parameters if p.unit is not None]
        #: The model is in SI units (a URDF, or every declared unit SI): its bare numbers get theirs (8 kg).
        self.si = is_urdf(self.model) or (bool(units) and all(u in _SI for u in units))

    def mass_tex(self, name: str) -> str:
        """A body's or particle's mass in formulas: its symbol (m, m1), or m_S when the model gives a number (a URDF's
        8), so that T reads ½ m_S V² and not ½ 8 V²."""
        elements: tuple[Body | Particle, ...] = (*self.model.bodies, *self.model.particles)
        mass = next(e.mass for e in elements if e.name == name)
        if mass.free_symbols:
            return self.tex(mass)
        return rf"m_{{{tex_name(name)}}}"

    def quantity(self, value: se.Basic, unit: str) -> str:
        """A number with its SI unit when the model is in SI units: 8 → ``8\\ \\mathrm{kg}``; a symbol as is."""
        text = self.tex(value)
        if value.free_symbols or not self.si or not unit:
            return text
        return rf"{text}\ \mathrm{{{unit}}}"

    # -- words and names ---------------------------------------------------------------------------
    @property
    def R(self) -> str:
        """LaTeX of the frame the equations are written in: R_{0} (or R)."""
        return self.name(self.ref)

    def name(self, name: str) -> str:
        """A point or frame in formulas; a frame named like a quantity of the report (E, L, T, U, H, K: the energy, the
        Lagrangian…) is written R_E, R_L…"""
        if name in _TAKEN and name in self.frames:
            return rf"R_{{{name}}}"
        if name in self.frames and re.fullmatch(r"R[A-Z][A-Za-z0-9]*", name):
            return rf"R_{{{name[1:]}}}"  # the bicycle's RB, RHg: R_B, R_Hg, as its axes x_B, x_Hg
        return tex_name(name)

    def _used_letters(self) -> set[str]:
        plain = Notation()
        own = [p.name for p in self.model.parameters] + list(self.eom.coordinates)
        shown = {plain.symbol(n, latex=True).split("_")[0] for n in own}
        shown |= {tex_name(x) for x in [*self.frames, *(p.name for p in self.model.points), *self.bodies,
                                          *(p.name for p in self.model.particles)]}
        shown |= {x[1].split("_")[0] for x in self.multiplier_names.values()}
        return shown

    def free_letter(self, *candidates: str) -> str:
        """The first of ``candidates`` that no symbol, point, body or frame of the model is written as."""
        used = self._used_letters()
        return next((x for x in candidates if x not in used), candidates[-1])

    def field_tex(self, load) -> str:
        """The vector of a uniform field: g⃗ when it is ± g along one axis (the weight), else another letter (the
        Foucault pendulum's attraction −g u + Ω² l u⊥ is not the apparent gravity g)."""
        comps = [x for _, cs in self.kin.frames.lift(load.field) for x in cs if x != 0]
        if len(comps) == 1 and comps[0].free_symbols == {se.Symbol("g")}:
            return r"\vec{g}"
        return rf"\vec{{{self.free_letter('a', 'b', 'h')}}}"

    @property
    def eigen(self) -> str:
        """The eigenvalues' letter: λ, or s when λ is taken (a multiplier, the latitude of Foucault's pendulum)."""
        return r"\lambda" if r"\lambda" not in self._used_letters() else "s"

    def load_name(self, name: str) -> str:
        """A load's name in the report's language (the engine's and usual names translated)."""
        return self.w.load(name)

    def load_tex(self, name: str) -> str:
        """A load's name as text inside math, in the report's language: ``\\text{poids}``."""
        return tex_text(self.w.load(name))

    def constraint_label(self, name: str) -> str:
        """A declared constraint as the prose names it: its description in the report's language (« la tige
        maintient OP = l »), else « la liaison k » by its rank in the model — never its identifier, which is
        the JSON's and the command line's."""
        from ...model import in_language

        for k, con in enumerate(self.model.constraints, 1):
            if con.name == name:
                return in_language(con.description, self.lang) or self.w.text("constraint number", k=str(k))
        return name

    def reaction_tex(self, name: str) -> str:
        """The reaction of the complementary constraint ``name`` in formulas: R_P at its point of application
        (R_I for the coin's contact, as the course writes R_O for the top's), else R_k by its rank in the model."""
        points = {r.constraint: r.point for r in self.eom.reactions if r.point is not None}
        at = points.get(name)
        if at is not None and list(points.values()).count(at) == 1:
            return rf"\vec{{R}}_{{{self.point_label(at)}}}"
        k = next((k for k, con in enumerate(self.model.constraints, 1) if con.name == name), 0)
        return rf"\vec{{R}}_{{{k}}}"

    @property
    def lam(self) -> str:
        """The multipliers' letter in LaTeX: λ, or the first one the model leaves free (`multiplier_names`)."""
        names = list(self.multiplier_names.values())
        return names[0][1].split("_")[0] if names else r"\lambda"

    def multiplier_sum(self, index: str = "i") -> str:
        """The generalized force of the complementary reactions on q_i: λ a_i with one multiplier,
        Σ_k λ_k a_{k,i} with several (λ_k multiplies +a_{k,i}, the engine's sign convention)."""
        if len(self.eom.constraints) == 1:
            return rf"{self.lam}\, a_{{{index}}}"
        return rf"\sum_{{k}} {self.lam}_{{k}}\, a_{{k,{index}}}"

    def is_constraint(self, name: str) -> bool:
        """Whether the effort ``name`` is the reaction of a declared constraint (not a given load)."""
        return any(con.name == name for con in self.model.constraints)

    def Q_nc(self, q: str) -> str:
        """Q_{q, nc}: the generalized force of the non-conservative efforts (seed: Q_{i efforts nonconservatifs})."""
        return rf"Q_{{{self.sym(q)},\,\mathrm{{nc}}}}"

    def Q_of(self, q: str, load: str) -> str:
        """Q_q(load): the generalized force of one load."""
        return rf"Q_{{{self.sym(q)}}}({self.load_tex(load)})"

    def m(self, latex: str) -> Math:
        return Math(latex)

    def point_label(self, name: str) -> str:
        """A body stands for its centre of mass: G, or G_{S_1} when there are several bodies."""
        if name in self.bodies:
            return "G" if len(self.model.bodies) == 1 else f"G_{{{tex_name(name)}}}"
        return tex_name(name)

    def element(self, name: str) -> str:
        """LaTeX of a body or particle in a formula: S, S_{1}, P."""
        return tex_name(name)

    # -- expressions ------------------------------------------------------------------------------
    def sym(self, name: str, deco: str = "") -> str:
        """q_i, q̇_i (``deco="dot"``), q̈_i or q_i* (``"star"``) of a coordinate, or a parameter, in LaTeX."""
        return self.n.symbol(name + (f"_{deco}" if deco else ""), latex=True)

    def ex(self, e: se.Basic) -> sympy.Basic:
        """An engine expression as the report prints it (a summary when too long)."""
        return self.gate(e)

    def tex(self, e: se.Basic | sympy.Basic) -> str:
        return self.n.latex(e if isinstance(e, sympy.Basic) else self.gate(e))

    def terms(self, v: Vector) -> tuple[tuple[sympy.Basic, str], ...]:
        """A vector as (component, axis name) terms, components as printed."""
        return _vector_row(self.eom, v, self.gate).terms

    def vector(self, v: Vector) -> str:
        """A vector in the course's form, ``a \\psi^{*} \\sin\\theta\\,\\vec{u} - a \\theta^{*}\\,\\vec{w}``."""
        return self.n.vector(_vector_row(self.eom, v, self.gate).terms, latex=True)

    def short_vector(self, v: Vector, width: int = 48) -> str:
        """A vector written in full, or as its first and last terms around ⋯ when wider than ``width``."""
        terms = self.terms(v)
        full = self.n.vector(terms, latex=True)
        if visible_width(full) <= width or len(terms) < 3:
            return full
        last = self.n.vector([terms[-1]], latex=True)
        last = "- " + last[1:].lstrip() if last.startswith("-") else "+ " + last
        return f"{self.n.vector([terms[0]], latex=True)} + \\cdots {last}"

    def vector_equation(self, head: str, terms: Sequence[tuple[sympy.Basic, str]]) -> Equation:
        """``head`` then a vector given by (component, axis) terms, cut between terms when too wide."""
        pieces = []
        for k, term in enumerate(terms):
            t = self.n.vector([term], latex=True)
            if k:
                t = "- " + t[1:].lstrip() if t.startswith("-") else "+ " + t
            pieces.append(t)
        return wrap_many(head, pieces or [r"\vec{0}"], " ")

    def axis(self, name: str) -> str:
        return _axis_latex(name)

    def basis(self, frame: str) -> str:
        return "(" + ", ".join(_axis_latex(a) for a in self.kin.frames.axes(frame)) + ")"

    def is_zero(self, e: se.Basic | sympy.Basic) -> bool:
        return e == 0

    @property
    def derive_command(self) -> str:
        """The command that prints every equation in full: ``lagrangian derive MODEL --json``."""
        import shlex

        source = self.source
        if source is None:
            return "lagrangian derive MODEL --json"
        return f"lagrangian derive {shlex.quote(str(source))} --json" if source else "lagrangian derive --json"

    def full(self, parts: Sequence[tuple[str, sympy.Basic]], label: str) -> list[Block]:
        """The full forms of the summaries in ``parts`` ((head, expression) pairs), to go under their equation.

        Call it before writing the equation: the summaries it numbers print as ⟨41 terms (see A.3)⟩.
        """
        return self.book.blocks(parts, label, self.w)

    # -- displayed equations -------------------------------------------------------------------------
    def equation(self, head: str, expr: sympy.Basic, tail: str = "") -> Equation:
        return wrap(self.n, head, expr, tail)

    def relation(self, head: str, left: sympy.Basic, right: sympy.Basic, tail: str = "") -> Equation:
        """``head left = right tail``, each side cut into lines when too wide."""
        lhs = self.n.latex(left)
        rhs = self.n.latex(right)
        whole = wrap_latex(head, f"{lhs} = {rhs}", tail)
        if len(whole.lines) == 1:
            return whole
        first = wrap_latex(head, lhs)
        second = wrap_latex("= ", rhs, tail)
        if visible_width(first.lines[-1] + " " + second.lines[0]) <= _report_size.LINE_WIDTH:
            return Equation(first.lines[:-1] + (first.lines[-1] + " " + second.lines[0],) + second.lines[1:])
        return Equation(first.lines + second.lines)

    def show(self, equations: Sequence[Equation], label: str) -> list[Block]:
        """Equations as displayed blocks; one longer than `FOLD_LINES` lines is shown by its start and folded."""
        out: list[Block] = []
        pending: list[Equation] = []
        for eq in equations:
            if len(eq.lines) <= FOLD_LINES:
                pending.append(eq)
                continue
            if pending:
                out.append(Display(tuple(pending)))
                pending = []
            out.append(Display((Equation((eq.lines[0] + r" \;\cdots",)),)))
            out.append(Fold(self.w.text("show full", label=label, k=str(len(eq.lines))), (Display((eq,)),)))
        if pending:
            out.append(Display(tuple(pending)))
        return out

    def many(self, blocks: list[Block], count: int, label: str, limit: int = 12) -> list[Block]:
        """``blocks`` as they are, or folded when they list more than ``limit`` items."""
        if count <= limit:
            return blocks
        return [Fold(self.w.text("show all", label=label, k=str(count)), tuple(blocks))]

    # -- values at t = 0 ----------------------------------------------------------------------------
    def initial_value(self, e: se.Basic) -> float | None:
        """``e`` at t = 0 with the model's parameter values and initial conditions, when all are given."""
        values: dict[se.Basic, se.Basic] = {self.kin.t: se.Integer(0)}
        for p in self.model.parameters:
            if p.value is not None:
                values[p.symbol] = se.Float(p.value)
        for c in self.model.coordinates:
            if c.initial is not None:
                values[c.symbol] = se.Float(c.initial)
            if c.rate is not None:
                values[c.rate_symbol] = se.Float(c.rate)
        try:
            return float(e.xreplace(values))
        except (TypeError, RuntimeError, ValueError):
            return None
