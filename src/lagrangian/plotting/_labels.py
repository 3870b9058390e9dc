"""Axis labels in the course's notation (ψ, θ̇, φ̈ ...) as matplotlib mathtext, with units."""

from __future__ import annotations

import re

from ..dynamics import EquationsOfMotion
from ..output import Notation

__all__ = ["symbol", "unit", "label", "words"]


def symbol(eom: EquationsOfMotion, name: str) -> str:
    """``theta_dot`` → ``$\\dot{\\theta}$``: the course's symbol for a coordinate, rate or monitor."""
    notation = Notation([c.name for c in eom.model.coordinates], [p.name for p in eom.model.parameters])
    tex = notation.symbol(name, latex=True)
    # \dot{\theta_{1}} puts the dot over the subscript in mathtext; the course writes θ̇₁.
    tex = re.sub(r"^\\(d?dot)\{(.+)_\{(\w+)\}\}$", r"\\\1{\2}_{\3}", tex)
    return f"${tex}$"


def _is_angle(eom: EquationsOfMotion, name: str) -> bool:
    """True when the coordinate turns a frame (it appears in a rotation's angle)."""
    coordinate = eom.model.coordinate(name)
    return any(f.rotation is not None and coordinate.symbol in f.rotation.angle.free_symbols
               for f in eom.model.frames)


def unit(eom: EquationsOfMotion, name: str, order: int = 0) -> str:
    """The unit of q_i (``order`` 0), q̇_i (1) or q̈_i (2): rad for an angle, else the declared unit."""
    base = "rad" if _is_angle(eom, name) else eom.model.coordinate(name).unit
    if not base:
        return ""
    return base + ("", "/s", "/s²")[order]


def label(eom: EquationsOfMotion, name: str, order: int = 0) -> str:
    """E.g. ``$\\dot{\\theta}$ (rad/s)``."""
    text = symbol(eom, name + ("", "_dot", "_ddot")[order])
    u = unit(eom, name, order)
    return f"{text} ({u})" if u else text


#: Titles, legends and captions of the figures, in English and in the course's French.
_WORDS = {
    "en": {
        "time series": "time series", "coordinates": "coordinates $q_i(t)$", "rates": r"rates $\dot{q}_i(t)$",
        "phase": "phase portraits", "energy": "energy",
        "energies": "kinetic energy $T$, potential energy $U$", "energies E": ", $E = T + U$",
        "drift": "relative drift of the first integrals ({method})", "conservation": "conservation",
        "exact": "0 (exact)", "tip": "tip of the axis {axis} of {body}", "tip path": "tip path",
        "sphere": "{tip} on the unit sphere", "circles": r"circles $\theta_1$ = {t1:.4g}, $\theta_2$ = {t2:.4g} rad",
        "analysis": "analysis", "simulation": "simulation",
        "roots": r"$\theta_1$, $\theta_2$: roots of the cubic in $u = \cos\theta$",
        "extremes": r"$\theta_1$, $\theta_2$: extreme $\theta$ of the simulation",
        "above": r"seen from above $z_0$: radius $\theta$ (°), angle $\psi - 90°$",
        "psi axis": r"$\psi$ of the axis (°)", "theta axis": r"$\theta$ of the axis (°)",
        "nutation": "nutation, {tip}", "force": "force",
        "reaction at": "reaction at the fixed point {point}", "reaction ground": "reaction of the ground",
        "given": "given",
        "caption time_series": "Coordinates q_i(t) and rates q̇_i(t)",
        "caption phase": "Phase portraits (q_i, q̇_i)",
        "caption apex_sphere": "Path of the tip of the axis on the unit sphere",
        "caption nutation": "Nutation: the tip of the axis seen from above z0, and θ against ψ",
        "caption drift": "Energies T, U, E and drift of the first integrals",
        "caption reaction": "Reaction {name}(t)",
    },
    "fr": {
        "time series": "évolution temporelle", "coordinates": "paramètres $q_i(t)$",
        "rates": r"vitesses $\dot{q}_i(t)$", "phase": "portraits de phase", "energy": "énergie",
        "energies": "énergie cinétique $T$, énergie potentielle $U$", "energies E": ", $E = T + U$",
        "drift": "dérive relative des intégrales premières ({method})", "conservation": "conservation",
        "exact": "0 (exacte)", "tip": "apex de l'axe {axis} de {body}", "tip path": "trajectoire de l'apex",
        "sphere": "{tip} sur la sphère unité",
        "circles": r"cercles $\theta_1$ = {t1:.4g}, $\theta_2$ = {t2:.4g} rad",
        "analysis": "analyse", "simulation": "simulation",
        "roots": r"$\theta_1$, $\theta_2$ : racines de la cubique en $u = \cos\theta$",
        "extremes": r"$\theta_1$, $\theta_2$ : $\theta$ extrêmes de la simulation",
        "above": r"vu de dessus (axe $z_0$) : rayon $\theta$ (°), angle $\psi - 90°$",
        "psi axis": r"$\psi$ de l'axe (°)", "theta axis": r"$\theta$ de l'axe (°)",
        "nutation": "nutation, {tip}", "force": "force",
        "reaction at": "réaction au point fixe {point}", "reaction ground": "réaction du sol",
        "given": "données",
        "caption time_series": "Paramètres q_i(t) et vitesses q̇_i(t)",
        "caption phase": "Portraits de phase (q_i, q̇_i)",
        "caption apex_sphere": "Trajectoire de l'apex sur la sphère unité",
        "caption nutation": "Nutation : l'apex vu de dessus (axe z0), et θ en fonction de ψ",
        "caption drift": "Énergies T, U_P, E et dérive des intégrales premières",
        "caption reaction": "Réaction {name}(t)",
    },
}


def words(lang: str = "en") -> dict[str, str]:
    """The figures' words in ``lang`` (``"en"`` or ``"fr"``; any other language gets English)."""
    return _WORDS.get(lang, _WORDS["en"])
