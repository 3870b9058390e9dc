"""From the equations of motion to one C file: the model's M, F, monitors and events.

The generated functions evaluate M(q, t) and F(q, q̇, t) of M q̈ = F (never M⁻¹), in the
package's C form of them (`_rewrite.mass_forces_form`), the first integrals and T, U as
monitors, the event functions, and, for the symplectic integrator, Hamilton's form
p = ∂T/∂q̇ = M q̇ + b, ṗ = ∂T/∂q − ∂U/∂q + Q(nc).  Each function shares its common
subexpressions (SymEngine's ``cse``).  The model-independent C runtime (`_runtime`:
``solve_mass.c`` and ``integrators.c``, copied whole) follows, so a whole run is one C call.

Parameter values are an input array, not constants folded into the code: changing
``m`` or ``g`` (``--set g=1.62``) reuses the compiled library.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import DerivationError
from ._cparts import PART_MACROS, Part, function_text, part_unit, units_of
from ._cprint import c_block, c_sequence
from ._rewrite import Hoist, mass_forces_form
from ._runtime import dop853_defines, runtime_source

__all__ = ["GeneratedSource", "generate_c", "monitor_expressions"]

#: The functions that run once per output sample (the monitors: first integrals, T, U) or once per
#: parameter set (the hoisted constants), not at each step: their parts are cold (`_cparts.COLD_UNIT`).
COLD_FUNCTIONS = ("lg_monitors", "lg_constants")


@dataclass(frozen=True)
class GeneratedSource:
    """The C source of a model, and the order of everything it reads and writes.

    Parameters
    ----------
    source : str
        The complete translation unit.
    key : str
        SHA-256 of ``units`` (of ``source`` when it is the only unit: the compile cache's key).
    n : int
        The number of coordinates; the state is y = (q_1..q_n, q̇_1..q̇_n).
    parameters : tuple of str
        The parameter names, in the order of the ``p`` array.
    monitors : tuple of str
        The monitor names (first integrals, then ``T`` and ``U``).
    events : tuple of str
        The event names, in the order of the event functions.
    constants : int
        How many precomputed constants follow the parameters in ``p``.
    units : tuple of str
        The same code as translation units compiled in parallel and linked (`_cparts`): the first
        holds all but the parts of the long functions, each other one part; ``(source,)`` when no
        function is long enough to be cut.
    """

    source: str
    key: str
    n: int
    parameters: tuple[str, ...]
    monitors: tuple[str, ...]
    events: tuple[str, ...]
    constants: int = 0
    units: tuple[str, ...] = ()


def monitor_expressions(eom: EquationsOfMotion, integrals: Sequence, *,
                        recursive: bool = False) -> list[tuple[str, se.Basic]]:
    """The monitors' expressions: each first integral, then T and U (under other names if taken).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    integrals : sequence of FirstIntegral
        The first integrals to monitor.
    recursive : bool, optional
        With ``recursive``, T and U are those of ``eom.recursive``, over its intermediates.

    Returns
    -------
    list of (str, SymEngine expression)
        (name, expression) of each monitor.
    """
    out = [(fi.name, fi.expression) for fi in integrals]
    taken = {name for name, _ in out}
    energies = (eom.recursive.T, eom.recursive.U) if recursive and eom.recursive is not None else (eom.T, eom.U)
    for name, expr in zip(("T", "U"), energies, strict=True):
        out.append((name if name not in taken else f"{name}_total", expr))
    return out


def generate_c(
    eom: EquationsOfMotion,
    integrals: Sequence | Callable[[], Sequence] = (),
    events: Sequence[tuple[str, se.Basic]] = (),
    law=None,
    *,
    on_unit: Callable[[str], object] | None = None,
) -> GeneratedSource:
    """Generate the C translation unit of ``eom``.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations of motion (`lagrangian.derive`).
    integrals : sequence of FirstIntegral, or callable, optional
        The first integrals to monitor (`lagrangian.first_integrals`), or a function that finds them:
        for a robot's recursive form it is called after M and F are written, so that a build
        compiles their parts while the integrals are sought (`on_unit`).
    events : sequence of (str, SymEngine expression), optional
        (name, g) pairs; an event occurs where g(t, q, q̇) changes sign.
    law : LawCode, optional
        The inputs' law (`numerics._input_code.LawCode`): its C goes around the model's functions.
    on_unit : callable, optional
        Called with each unit of a long function's part (one of ``units[1:]``) as soon as it is
        written, before the rest is generated: a build can start compiling it meanwhile.

    Returns
    -------
    GeneratedSource
        The translation unit and the order of what it reads and writes.

    Raises
    ------
    DerivationError
        When an expression holds a symbol that is neither a coordinate, a rate, a
        parameter nor t (it would have no value at run time).
    """
    params = tuple(p.name for p in eom.model.parameters)
    # Every free symbol gets a private name: `_y3` is y[3], `_p1` is p[1], `_t` is t.
    private: dict[se.Basic, se.Symbol] = {}
    header: dict[str, str] = {}
    for i, s in enumerate((*eom.q, *eom.qd)):
        private[s] = se.Symbol(f"_y{i}")
        header[f"_y{i}"] = f"y[{i}]"
    for k, name in enumerate(params):
        private[se.Symbol(name)] = se.Symbol(f"_p{k}")
        header[f"_p{k}"] = f"p[{k}]"
    private[eom.t] = se.Symbol("_t")
    header["_t"] = "t"

    #: Symbols printed under their own C name, not renamed: the recursive form's intermediates and
    #: the hoisted constants (one `xreplace` with a map of thousands would cost more than the rest).
    named: dict[se.Basic, str] = {}

    renamed: dict[se.Basic, se.Basic] = {}

    def rename(expr: se.Basic, what: str) -> se.Basic:
        expr = expr if isinstance(expr, se.Basic) else se.Integer(0) + expr
        out = renamed.get(expr)
        if out is not None:
            return out
        unknown = [s for s in expr.free_symbols if s not in private and s not in named]
        if unknown:
            raise DerivationError(
                f"{what} contains `{unknown[0]}`, which is neither a coordinate, a rate, a parameter nor t.",
                fix="declare it as a parameter of the model")
        # Only the symbols it holds: `xreplace` converts its whole map on every call.
        out = renamed[expr] = expr.xreplace({s: private[s] for s in expr.free_symbols if s in private})
        return out

    parts: list[Part] = []  # the long functions' parts (`_cparts`), in order

    def function(signature: str, outputs, what: str, definitions=None, preamble=()) -> str:
        # `outputs` is one list of (target, expression), or several computed in turn
        # (the first defining names the next use); `definitions`, named intermediates
        # (symbol, expression) the outputs use, each defined before its first use.
        stages = outputs if outputs and isinstance(outputs[0], list) else [outputs]
        names = {sym: str(sym) for sym in private.values()} | named
        if definitions is not None:
            body = c_sequence([(sym, rename(e, what)) for sym, e in definitions],
                              [(tg, rename(e, what)) for tg, e in outputs], names)
        else:
            body = [line for k, stage in enumerate(stages)
                    for line in c_block([(tg, rename(e, what)) for tg, e in stage], names, prefix="xyz"[k])]
        written = len(parts)
        text = function_text(signature, header, body, parts, preamble,
                             cold=any(f" {name}(" in signature for name in COLD_FUNCTIONS))
        if on_unit is not None:
            for part in parts[written:]:
                on_unit(part_unit(part))
        return text

    if eom.recursive is not None:
        return _generate_recursive(eom, integrals, events, named, header, function, law, parts)
    form = mass_forces_form(eom)
    for k, (sym, _) in enumerate(form.shared):
        private[sym] = se.Symbol(f"_s{k}")
    for k, (sym, _) in enumerate(form.constants):
        private[sym] = sym
        header[str(sym)] = f"p[{len(params) + k}]"
    M_out = [(f"M[{k}]", e) for k, e in enumerate(form.M)]
    F_out = [(f"F[{i}]", e) for i, e in enumerate(form.F)]
    S_out = [(f"const double _s{k}", e) for k, (_, e) in enumerate(form.shared)]
    constants = [(f"k[{j}]", expr) for j, (_, expr) in enumerate(form.constants)]
    monitors = monitor_expressions(eom, integrals() if callable(integrals) else integrals)
    zero = se.Integer(0)
    rates_zero = {s: zero for s in eom.qd}
    b = [se.diff(eom.T, s).xreplace(rates_zero) for s in eom.qd]
    g = [eq.dT_dq - eq.dU_dq + eq.Q_nc for eq in eom.equations]

    return _assemble(eom, monitors, events, params, constants, parts, [
        function("static void lg_mass_forces(double t, const double *y, const double *p, double *M, double *F)",
                 [S_out, M_out + F_out], "M q'' = F"),
        function("static void lg_monitors(double t, const double *y, const double *p, double *out)",
                 [(f"out[{k}]", e) for k, (_, e) in enumerate(monitors)], "a first integral"),
        function("static void lg_events(double t, const double *y, const double *p, double *g)",
                 [(f"g[{k}]", e) for k, (_, e) in enumerate(events)], "an event function"),
        function("static void lg_hamilton_mass(double t, const double *y, const double *p, double *M, double *b)",
                 M_out + [(f"b[{i}]", e) for i, e in enumerate(b)], "dT/dq'"),
        function("static void lg_hamilton_force(double t, const double *y, const double *p, double *g)",
                 [(f"g[{i}]", e) for i, e in enumerate(g)], "dT/dq - dU/dq + Q"),
    ], function, law)


def _generate_recursive(eom: EquationsOfMotion, integrals: Sequence | Callable[[], Sequence], events: Sequence[tuple[str, se.Basic]],
                        named: dict, header: dict, function, law=None, parts: list[Part] | None = None
                        ) -> GeneratedSource:
    """`generate_c` for an ``eom`` with a recursive form: each function defines the intermediates it
    needs, in order, as ``const double`` locals, then its outputs; CSE runs on both.

    Nothing is expanded: M, F and Hamilton's ∂(T − U)/∂q stay written in the link velocities,
    accelerations, forces and composite inertias of `dynamics._recursive`, so the source
    grows about linearly (F) and quadratically (M) with the number of joints.
    """
    rec = eom.recursive
    if rec is None:
        raise ValueError("generate_c dispatches here for an eom with a recursive form only")
    n = len(eom.q)
    params = tuple(p.name for p in eom.model.parameters)
    for k, (sym, _) in enumerate(rec.intermediates):
        named[sym] = f"_w{k}"
    # Inputs are not hoisted: an input law (`numerics._input_code`) overwrites them state by state.
    hoist = Hoist([se.Symbol(p.name) for p in eom.model.parameters if not p.input])
    M = [rec.M[i][j] for i in range(n) for j in range(n)]
    monitors: list[tuple[str, se.Basic]] = []

    def monitor_outputs() -> list[tuple[str, se.Basic]]:
        # Given as a function, the first integrals are found only now, after M and F are written:
        # a build compiles M and F's parts meanwhile (`generate_c`).
        monitors.extend(monitor_expressions(eom, integrals() if callable(integrals) else integrals, recursive=True))
        return [(f"out[{k}]", e) for k, (_, e) in enumerate(monitors)]

    hoisted: dict[se.Basic, se.Basic] = {}

    def lifted(expr: se.Basic) -> se.Basic:
        out = hoisted.get(expr)
        if out is None:
            out = hoisted[expr] = hoist(expr)
        return out

    def with_intermediates(outputs: list[tuple[str, se.Basic]]):
        defs = [(s, lifted(e)) for s, e in rec.needed([e for _, e in outputs])]
        return defs, [(target, lifted(e)) for target, e in outputs]

    Outputs = list[tuple[str, se.Basic]]
    bodies: list[tuple[str, Outputs | Callable[[], Outputs], str]] = [
        ("static void lg_mass_forces(double t, const double *y, const double *p, double *M, double *F)",
         [(f"M[{k}]", e) for k, e in enumerate(M)] + [(f"F[{i}]", e) for i, e in enumerate(rec.F)], "M q'' = F"),
        ("static void lg_monitors(double t, const double *y, const double *p, double *out)",
         monitor_outputs, "a first integral"),
        ("static void lg_events(double t, const double *y, const double *p, double *g)",
         [(f"g[{k}]", e) for k, (_, e) in enumerate(events)], "an event function"),
        ("static void lg_hamilton_force(double t, const double *y, const double *p, double *g)",
         [(f"g[{i}]", e) for i, e in enumerate(rec.dL_dq)], "dT/dq - dU/dq + Q"),
    ]

    def written(signature: str, staged: tuple[list, list], what: str) -> str:
        # Each function is written as soon as its intermediates are found and lifted, so that the units
        # of its parts reach a build (`on_unit`) while the next function is being prepared.  The constants
        # hoisted so far get their names first: p[LG_NP + k], k in the order `hoist` made them.
        for k, sym in enumerate(hoist.constants.values()):
            if sym not in named:
                named[sym] = str(sym)
                header[str(sym)] = f"p[{len(params) + k}]"
        defs, outs = staged
        return function(signature, outs, what, defs)

    functions = [written(signature, with_intermediates(outputs() if callable(outputs) else outputs), what)
                 for signature, outputs, what in bodies]
    aba: list[str] = []
    if rec.qdd is not None:
        # The articulated-body algorithm: q'' in O(n), M neither formed nor factorised.  Its backward
        # pass and its forward pass are two functions: what the second reads of the first (each
        # joint's U/D, u/D, c and the cos/sin of its angle) goes through an array, instead of some
        # 13 values a joint staying live across one straight-line function, which made the C
        # compiler's register allocation the larger part of its time (arm, n = 30: 7 s of 14).
        position = {sym: k for k, (sym, _) in enumerate(rec.intermediates)}
        forward = rec.needed(rec.qdd, after=rec.qdd_forward)
        reads = {sym for e in (*rec.qdd, *(e for _, e in forward)) for sym in e.free_symbols}
        carried = sorted((sym for sym in reads if position.get(sym, rec.qdd_forward) < rec.qdd_forward),
                         key=position.__getitem__)
        slots = [se.Symbol(f"_carry{k}") for k in range(len(carried))]
        for k, slot in enumerate(slots):
            named[slot] = f"carry[{k}]"
        arguments = "double t, const double *y, const double *p"
        functions.append(written(f"LG_NOINLINE static void lg_aba_backward({arguments}, double *carry, double *piv)",
                                 with_intermediates([(f"carry[{k}]", sym) for k, sym in enumerate(carried)]
                                                    + [(f"piv[{2 * i + k}]", pair[k])
                                                       for i, pair in enumerate(rec.pivots) for k in range(2)]),
                                 "q''"))
        functions.append(written(f"LG_NOINLINE static void lg_aba_forward({arguments}, const double *carry, "
                                 "double *qdd)",
                                 (list(zip(carried, slots, strict=True)) + [(sym, lifted(e)) for sym, e in forward],
                                  [(f"qdd[{i}]", lifted(e)) for i, e in enumerate(rec.qdd)]), "q''"))
        aba = [("static void lg_aba(double t, const double *y, const double *p, double *qdd, double *piv) {\n"
                f"    double carry[{max(len(carried), 1)}];\n"
                "    lg_aba_backward(t, y, p, carry, piv);\n    lg_aba_forward(t, y, p, carry, qdd);\n}\n")]
    constants = [(f"k[{j}]", expr) for j, expr in enumerate(hoist.constants)]
    # M is lg_mass_forces' (F is dropped: the symplectic integrator asks for M alone far less often
    # than compiling a second copy of the composite inertias would cost); T is homogeneous
    # quadratic in q̇ for a tree with no time in it, so b = ∂T/∂q̇ at q̇ = 0 is 0.
    hamilton_mass = (
        "static void lg_hamilton_mass(double t, const double *y, const double *p, double *M, double *b) {\n"
        f"    double F[{n}], yq[{2 * n}];\n"
        f"    for (int i = 0; i < {n}; i++) {{ yq[i] = y[i]; yq[{n} + i] = 0.0; b[i] = 0.0; }}\n"
        "    lg_mass_forces(t, yq, p, M, F);  /* only q is read from y */\n}\n")
    if aba:  # the two halves stay apart (their one caller would inline them)
        aba = ["#define LG_ABA 1", *functions[4:], *aba]
    return _assemble(eom, monitors, events, params, constants, [] if parts is None else parts,
                     [*functions[:3], hamilton_mass, functions[3], *aba], function, law)


def _assemble(eom: EquationsOfMotion, monitors, events, params, constants, parts: list[Part],
              functions: list[str], function, law=None) -> GeneratedSource:
    """The translation unit: dimensions, DOP853's tableau, the constants, the model's functions, the integrators.

    The long functions' parts (`_cparts`) come first; ``units`` has them each in a unit of its own.
    """
    n = len(eom.q)
    # `lg_constants`: t and y are read by no constant (they are parameter-only), but declared for the names.
    constants_text = function("void lg_constants(const double *p, double *k)", constants, "a constant",
                              preamble=["    const double t = 0.0; const double *y = 0;"])
    head = [
        f"/* Generated by lagrangian from the equations of motion of `{eom.model.name}`. Do not edit. */",
        f"#define LG_N {n}",
        f"#define LG_NM {len(monitors)}",
        f"#define LG_NE {len(events)}",
        f"#define LG_NP {len(params)}",
        f"#define LG_NK {len(constants)}",
        *(f"#define {k} {v}" for k, v in dop853_defines().items()),
        "#include <math.h>",
        "#if defined(__GNUC__)\n#define LG_NOINLINE __attribute__((noinline))\n#else\n#define LG_NOINLINE\n#endif",
    ]
    rest = [
        "/* The parameter-only subexpressions, p[LG_NP + j] = k[j], computed once per parameter set. */",
        constants_text,
        *([law.prelude] if law is not None else []),
        *functions,
        *([law.epilogue] if law is not None else []),
        runtime_source("solve_mass.c"),
        runtime_source("integrators.c"),
    ]
    if parts:
        source = "\n".join([*head, PART_MACROS["source"], *(part.text for part in parts), *rest])
        main = "\n".join([*head, PART_MACROS["unit"], *(part.declaration + ";" for part in parts), *rest])
        units = units_of(parts, main)
    else:
        source = "\n".join([*head, *rest])
        units = (source,)
    return GeneratedSource(
        source=source,
        key=hashlib.sha256("\n/* ---- unit ---- */\n".join(units).encode("utf-8")).hexdigest(),
        units=units,
        n=n,
        parameters=params,
        monitors=tuple(name for name, _ in monitors),
        events=tuple(name for name, _ in events),
        constants=len(constants),
    )
