"""Declaring non-conservative efforts: Rayleigh dissipation, joint dampers, Coulomb friction.

Three load kinds beyond the given forces of `spec` (seed: Q_i(non-conservative) holds
"all non-conservative efforts, given and constraint"):

``dissipation = "1/2*c*x_dot^2"``
    a Rayleigh function D(q, q̇, t); Q_i = −∂D/∂q̇_i.
``joint_damper = ["S1", "S2"], coefficient = "c"``
    viscous friction in the joint between two bodies (or a body and a frame): the couple
    −c Ω(S2/S1) on S2 and its opposite on S1.
``coulomb = "P", coefficient = "f", normal_force = "N"`` (and optionally
``surface_velocity``, ``normal``, ``regularization``, ``static_coefficient``)
    dry friction at the contact point P sliding on a surface: |T| ≤ f N, T against the
    sliding velocity; regularised unless ``regularization = 0`` (exact stick/slip in
    simulation, sticking while |T| ≤ f_s N, f_s = ``static_coefficient``, default f).  N must be *known* from the given forces (a block on a plane:
    m g cos α); a normal reaction that needs a multiplier is outside this load.

Here they are read and checked (names, expressions, the file and line of each mistake);
their generalized forces are `lagrangian.dynamics._friction`'s work.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import symengine as se

from .spec import CoulombFriction, Dissipation, JointDamper, Load, Location, Point

if TYPE_CHECKING:  # pragma: no cover
    from ._assemble import Assembler, Raw
    from ._toml import _Reader
    from .build import ModelBuilder

__all__ = ["FRICTION_KINDS", "TOML_KEYS", "DEFAULT_REGULARIZATION", "build_friction_load", "declare_from_toml"]

#: The builder's ``kind`` of each load declared here.
FRICTION_KINDS = ("dissipation", "joint_damper", "coulomb")
#: The keys each kind accepts in a model file's [loads] entry.
TOML_KEYS = {
    "dissipation": {"dissipation"},
    "joint_damper": {"joint_damper", "coefficient"},
    "coulomb": {"coulomb", "coefficient", "normal_force", "surface_velocity", "normal", "regularization",
                "static_coefficient"},
}
#: Default ε of the regularised Coulomb law T = −f N v/√(v² + ε²): a sliding speed (model
#: units, 1 mm/s in SI) below which the contact behaves as a very stiff viscous one.
DEFAULT_REGULARIZATION = se.Rational(1, 1000)


def build_friction_load(asm: Assembler, raw: Raw, points: Mapping[str, Point], bodies: set[str]) -> Load:
    """The checked load of declaration ``raw`` (kind in `FRICTION_KINDS`)."""
    d = raw.data
    kind = d["kind"]
    if kind == "dissipation":
        D = asm.expr(raw, "the dissipation function", d["function"], key="function")
        rates = {s for name, s in asm.symbols.items() if name.endswith("_dot")}
        if not D.free_symbols & rates:
            raise asm.error(raw, f"the dissipation function of `{raw.name}` depends on no rate q̇, so its "
                            "generalized forces Q_i = −∂D/∂q̇_i would all be zero", symbol=raw.name, key="function",
                            fix='write D in terms of the rates, e.g. dissipation = "1/2*c*x_dot^2"')
        joints = tuple(str(q) for q in d.get("joints", ()))
        known = {c for c in asm.symbols if c + "_dot" in asm.symbols}
        for q in joints:
            if q not in known:
                raise asm.error(raw, f"the dissipation function `{raw.name}` names `{q}` as one of its joints, "
                                "which is not a coordinate", symbol=q, key="joints",
                                fix="name the coordinates of the joints it acts in")
        return Dissipation(raw.name, D, joints)
    if kind == "joint_damper":
        ends = d["bodies"]
        if isinstance(ends, str) or not isinstance(ends, (tuple, list)) or len(ends) != 2:
            raise asm.error(raw, f"joint damper `{raw.name}` must join exactly two bodies, not `{ends}`",
                            symbol=raw.name, key="bodies", fix='e.g. joint_damper = ["S1", "S2"]')
        for n in ends:
            if n not in bodies and n not in asm.frame_names:
                raise asm.error(raw, f"joint damper `{raw.name}` acts on unknown body `{n}`", symbol=str(n),
                                key="bodies", fix="name two declared bodies, or a body and a frame (e.g. R0)")
        if ends[0] == ends[1]:
            raise asm.error(raw, f"joint damper `{raw.name}` joins `{ends[0]}` to itself", symbol=str(ends[0]),
                            key="bodies", fix="name the two bodies on either side of the joint")
        return JointDamper(raw.name, (str(ends[0]), str(ends[1])),
                           asm.expr(raw, "the coefficient", d["coefficient"], key="coefficient"))
    at = d["at"]
    if not isinstance(at, str) or at not in points:
        raise asm.error(raw, f"Coulomb friction `{raw.name}` acts at unknown point `{at}`", symbol=str(at), key="at",
                        fix="use a declared point, a body name (its centre G) or a particle name")
    normal = d["normal"]
    static = d.get("static_coefficient")
    eps = asm.expr(raw, "the regularization", d["regularization"], key="regularization")
    if eps.is_Number and float(eps) < 0:
        raise asm.error(raw, f"Coulomb friction `{raw.name}` has a negative regularization {eps}: it is a speed "
                             "below which the law is smoothed", symbol="regularization", key="regularization",
                        fix="give a positive speed (e.g. 1e-3), or 0 for the exact law with stick/slip")
    if static is not None and not eps.is_zero:
        raise asm.error(raw, f"Coulomb friction `{raw.name}` has a static_coefficient, which only the exact law "
                             "uses (sticking while |T| ≤ f_s N): the regularised law has no sticking phase",
                        symbol="static_coefficient", key="static_coefficient",
                        fix="write regularization = 0 for stick/slip with f_s, or leave static_coefficient out")
    return CoulombFriction(
        raw.name, at,
        asm.expr(raw, "the friction coefficient", d["coefficient"], key="coefficient"),
        asm.expr(raw, "the normal force", d["normal_force"], key="normal_force"),
        asm.expr(raw, "the surface velocity", d["surface_velocity"], vector=True, key="surface_velocity"),
        None if normal is None else asm.expr(raw, "the normal", normal, vector=True, key="normal"),
        eps,
        None if static is None else asm.expr(raw, "the static friction coefficient", static,
                                             key="static_coefficient"),
    )


def declare_from_toml(reader: _Reader, b: ModelBuilder, name: str, value: dict[str, Any], kind: str,
                      where: Location) -> None:
    """Hand a [loads] entry of kind ``kind`` (in `FRICTION_KINDS`) to the builder."""
    def need(key: str) -> Any:
        if key not in value:
            raise reader.fail(("loads", name), f"load `{name}` needs `{key}`", symbol=name, fix=f"add {key} = ...")
        return value[key]

    if kind == "dissipation":
        b.dissipation(name, value["dissipation"], location=where)
    elif kind == "joint_damper":
        b.joint_damper(name, reader.names(name, kind, value["joint_damper"]), coefficient=need("coefficient"),
                       location=where)
    else:
        b.coulomb_friction(name, value["coulomb"], coefficient=need("coefficient"),
                           normal_force=need("normal_force"), surface_velocity=value.get("surface_velocity", 0),
                           normal=value.get("normal"),
                           regularization=value.get("regularization", DEFAULT_REGULARIZATION),
                           static_coefficient=value.get("static_coefficient"), location=where)

