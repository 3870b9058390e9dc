"""Axis labels in the course's notation (ψ, θ̇, φ̈ ...) as matplotlib mathtext, with units."""

from __future__ import annotations

import re

from ..dynamics import EquationsOfMotion
from ..output import Notation

__all__ = ["symbol", "unit", "label"]


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
