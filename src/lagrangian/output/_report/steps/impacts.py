"""Unilateral contacts in the report: the one-sided constraint in step 1, and the theorem of percussions.

A contact's gap g_k(q) ≥ 0 is written with its complementarity (λ_k ≥ 0 while closed, λ_k g_k = 0)
where step 1 lists the constraints (`contact_note`).  After the first integrals, the section
"Chocs : théorème des percussions" / "Impacts: the theorem of percussions" (`impacts_section`)
states what an impact does in Lagrange's impulsive form — M(q)(q̇⁺ − q̇⁻) = Σ_k P_k a_k, Newton's
law ġ⁺ = −e ġ⁻, the complementarity of simultaneous impacts, Coulomb's bound with friction and
the energy lost — with the coefficients of each contact and, when the report has a simulation,
its contact events (time, contact, percussion, energy before and after).
"""

from __future__ import annotations

from collections.abc import Sequence

from ....model import Constraint
from ..build import Context
from ..document import Block, Display, Equation, Math, Para, Section, Table
from ..words import Words

__all__ = ["closed_note", "contact_note", "has_contacts", "impacts_section", "integrals_note"]

_PHRASES: dict[str, tuple[str, str]] = {
    "impacts": ("Chocs : théorème des percussions", "Impacts: the theorem of percussions"),
    "unilateral": (
        ("Cette liaison est unilatérale : l'écart {g} reste positif ou nul. Tant que le contact est fermé "
        "({g0}), c'est une liaison complémentaire holonome dont le multiplicateur {lam} est la réaction normale, "
        "qui pousse sans jamais tirer : {cond}. Le contact s'ouvre (décollage) quand {lam} s'annule et se "
        "referme par un choc quand {g} s'annule avec {gdot}."),
        ("This constraint is unilateral: the gap {g} stays positive or zero. While the contact is closed ({g0}) it "
        "is a complementary holonomic constraint whose multiplier {lam} is the normal reaction, which pushes and "
        "never pulls: {cond}. The contact opens (lift-off) when {lam} vanishes, and closes again through an "
        "impact when {g} vanishes with {gdot}.")),
    "percussion intro": (
        ("Pendant un choc de durée infiniment petite, les paramètres {q} ne varient pas et les efforts finis "
        "(pesanteur, ressorts, réactions bilatérales régulières) ont une percussion nulle. En intégrant les "
        "équations de Lagrange {L} sur la durée du choc, il ne reste que les percussions {P} des liaisons "
        "unilatérales qui se ferment (théorème des percussions sous la forme de Lagrange) :"),
        ("During an impact of vanishing duration the parameters {q} do not change, and the finite forces "
        "(gravity, springs, regular bilateral reactions) have no percussion. Integrating Lagrange's equations "
        "{L} over the impact leaves only the percussions {P} of the unilateral constraints that close (the "
        "theorem of percussions in Lagrange's form):")),
    "newton": (
        ("Chaque contact fermé au choc obéit à la loi de Newton, de coefficient de restitution {e} (0 : choc mou, "
        "1 : choc élastique) ; quand plusieurs contacts se ferment ensemble, les percussions sont la solution du "
        "problème de complémentarité linéaire :"),
        ("Each contact closed at the impact obeys Newton's law, with the restitution coefficient {e} (0: plastic, "
        "1: elastic); when several contacts close together, the percussions solve the linear complementarity "
        "problem:")),
    "friction": (
        ("Avec frottement de Coulomb au contact, la percussion tangentielle est bornée, {bound} : le contact "
        "adhère ({stick}) ou glisse à l'opposé de sa vitesse de glissement. Fermé, il adhère tant que sa "
        "réaction tangentielle reste dans le cône, {cone}."),
        ("With Coulomb friction at the contact, the tangential percussion is bounded, {bound}: the contact sticks "
        "({stick}) or slides against its sliding velocity. Closed, it sticks as long as its tangential reaction "
        "stays within the cone, {cone}.")),
    "energy": (
        "L'énergie cinétique perdue au choc en résulte (sans frottement) ; elle est nulle pour {e1} :",
        "The kinetic energy lost at the impact follows (without friction); it vanishes for {e1}:"),
    "closed": (("Les équations des liaisons unilatérales ne valent que tant que leur contact est fermé, avec "
               "{cond} ; les multiplicateurs dépendent des contacts fermés dans chaque phase du mouvement, que la "
               "simulation détermine (la commande lagrangian simulate les donne le long du mouvement)."),
               ("The equations of the unilateral constraints hold only while their contact is closed, with {cond}; "
               "the multipliers depend on which contacts are closed in each phase of the motion, which the "
               "simulation finds (the command lagrangian simulate gives them along the motion).")),
    "between impacts": (("Avec des liaisons unilatérales, ces intégrales premières valent entre deux chocs : un choc "
                        "conserve les positions mais change les vitesses (section suivante)."),
                        ("With unilateral constraints these first integrals hold between two impacts: an impact "
                        "keeps the positions but changes the velocities (next section).")),
    "coefficients": ("Contacts du système :", "Contacts of the system:"),
    "contact": ("contact", "contact"),
    "gap": ("écart", "gap"),
    "restitution": ("restitution", "restitution"),
    "friction coefficient": ("frottement", "friction"),
    "none": ("aucun", "none"),
    "events": ("Événements de contact de la simulation :", "Contact events of the simulation:"),
    "time": ("instant", "time"),
    "kind": ("événement", "event"),
    "percussion": ("percussion", "percussion"),
    "impact": ("choc", "impact"),
    "liftoff": ("décollage", "lift-off"),
    "touchdown": ("contact", "touch-down"),
    "rest": ("repos (accumulation des chocs)", "rest (accumulation of impacts)"),
    "more events": ("… et {k} autres événements.", "… and {k} more events."),
}


class _Words(Words):
    """The phrases of this section (kept here, beside their only user)."""

    def template(self, key: str) -> str:
        pair = _PHRASES.get(key)
        return pair[self._index] if pair is not None else super().template(key)


#: Most contact events listed in the report's table.
EVENTS_SHOWN = 40


def has_contacts(c: Context) -> bool:
    return any(con.unilateral for con in c.model.constraints)


def contact_note(c: Context, con: Constraint) -> list[Block]:
    """Step 1: the complementarity of the contact ``con`` (module docstring)."""
    w = _Words(c.lang)
    row = next(r for r in c.eom.constraints if r.name == con.name)
    g, lam = c.tex(row.expression), c.tex(row.multiplier)
    return [Para(w("unilateral", g=Math(rf"g = {g}"), g0=Math(r"g = 0"), lam=Math(lam),
                   cond=Math(rf"{lam} \geq 0,\; g \geq 0,\; {lam}\, g = 0"), gdot=Math(r"\dot{g} < 0")))]


def closed_note(c: Context) -> list[Block]:
    """Step 7: a contact's row holds while it is closed; its multiplier is ≥ 0."""
    w = _Words(c.lang)
    return [Para(w("closed", cond=Math(r"\lambda_{k} \geq 0")), style="note")]


def integrals_note(c: Context) -> list[Block]:
    """After the first integrals: they hold between impacts."""
    return [Para(_Words(c.lang)("between impacts"), style="note")]


def _theorem(c: Context, w: _Words, friction: bool) -> list[Block]:
    qi = r"q_{i}"
    dT = r"\frac{\partial T}{\partial \dot{q}_{i}}"
    blocks: list[Block] = [
        Para(w("percussion intro", q=Math(qi), L=Math(rf"L({qi})"), P=Math(r"P_{k} = \int \lambda_{k}\,dt"))),
        Display((Equation(((rf"\left[{dT}\right]_{{t^{{-}}}}^{{t^{{+}}}} = \sum_{{k}} P_{{k}}\, a_{{k,i}}"
                           r"\quad\Longleftrightarrow\quad M(q)\left(\dot{q}^{+} - \dot{q}^{-}\right) = "
                           r"A^{\mathsf{T}} P"),)),)),
        Para(w("newton", e=Math(r"e_{k}"))),
        Display((Equation(((r"\dot{g}_{k} = a_{k}\,\dot{q} + b_{k},\qquad P_{k} \geq 0,\qquad "
                           r"\dot{g}_{k}^{+} + e_{k}\,\dot{g}_{k}^{-} \geq 0,\qquad "
                           r"P_{k}\left(\dot{g}_{k}^{+} + e_{k}\,\dot{g}_{k}^{-}\right) = 0"),)),)),
    ]
    if friction:
        blocks.append(Para(w("friction", bound=Math(r"\left|P_{t,k}\right| \leq \mu_{k} P_{k}"),
                             stick=Math(r"w_{k}^{+} = 0"), cone=Math(r"\left|\lambda_{t,k}\right| \leq \mu_{k} "
                                                                   r"\lambda_{k}"))))
    blocks += [
        Para(w("energy", e1=Math(r"e_{k} = 1"))),
        Display((Equation(((r"T^{+} - T^{-} = \tfrac{1}{2} \sum_{k} P_{k}\left(\dot{g}_{k}^{+} + \dot{g}_{k}^{-}\right)"
                           r" = -\tfrac{1}{2} \sum_{k} \left(1 - e_{k}\right) P_{k} \left|\dot{g}_{k}^{-}\right|"
                           r" \leq 0"),)),)),
    ]
    return blocks


def _coefficients(c: Context, w: _Words) -> Table:
    rows = []
    for con in c.model.constraints:
        if not con.unilateral:
            continue
        row = next(r for r in c.eom.constraints if r.name == con.name)
        mu = (Math(c.tex(con.friction)),) if con.friction is not None else (w.text("none"),)
        rows.append(((c.constraint_label(con.name),), (Math(rf"{c.tex(row.expression)} \geq 0"),),
                     (Math(c.tex(con.restitution)),), mu))
    header = tuple((w.text(k),) for k in ("contact", "gap", "restitution", "friction coefficient"))
    return Table(header, tuple(rows))


def _events(c: Context, w: _Words, events: Sequence) -> list[Block]:
    rows = []
    contact = [e for e in events if getattr(e, "kind", "") in ("impact", "liftoff", "touchdown", "rest")]
    for e in contact[:EVENTS_SHOWN]:
        P = w.number(e.percussion) if e.kind == "impact" else "—"
        E = (f"{w.number(e.energy_before)} → {w.number(e.energy_after)}"
             if e.kind in ("impact", "rest") else "—")
        rows.append(((w.number(e.t),), (w.text(e.kind),), (c.constraint_label(e.contact),), (P,), (E,)))
    if not rows:
        return []
    header = ((w.text("time"), " ", Math("t")), (w.text("kind"),), (w.text("contact"),),
              (w.text("percussion"), " ", Math("P")), (Math(r"E^{-} \to E^{+}"),))
    blocks: list[Block] = [Para(w("events")), Table(header, tuple(rows))]
    if len(contact) > EVENTS_SHOWN:
        blocks.append(Para(w("more events", k=str(len(contact) - EVENTS_SHOWN)), style="note"))
    return blocks


def impacts_section(c: Context, events: Sequence = ()) -> Section:
    """The theorem of percussions, the contacts' coefficients, and the contact events of a simulation."""
    w = _Words(c.lang)
    friction = any(con.unilateral and con.friction is not None for con in c.model.constraints)
    blocks = _theorem(c, w, friction)
    blocks += [Para(w("coefficients")), _coefficients(c, w)]
    blocks += _events(c, w, events)
    return Section("impacts", w.text("impacts"), tuple(blocks))
