"""The C of an `InputLaw`: the inputs computed inside the right-hand side, no Python per step.

The model's functions (`codegen._codegen`) read an input u like a parameter, p[i_u].  With a law, they
are compiled under other names (``lg_model_mass_forces``, ...; the `prelude` renames them with
macros) and the names the integrators call become wrappers (the `epilogue`) that copy the
parameters, write u(t, y) into the copy and call the model's function with it::

    static void lg_mass_forces(t, y, p, M, F) { double pu[NP + NK]; lg_apply_inputs(t, y, p, pu);
                                                lg_model_mass_forces(t, y, pu, M, F); }

Hamilton's M and b = ∂T/∂q̇ (``lg_hamilton_mass``) are not wrapped: the inputs are load
magnitudes, in F and U, never in M (`_check`).

The law's numbers follow the parameters and the hoisted constants: p = [parameters (LG_NP) |
constants (LG_NK) | law (LG_NX)], the law's block laid out by `InputLaw.layout`:

    law[0]         the hint: a time inside the interval the integrator is in (NaN outside a run);
                   a table reads the piece of that interval, even at its right end
    law[1]         the address of the Python callback, its bits read as a double (the slow path)
    K, x*, u*, ẋ*  the feedback's gain (m × nx, row-major), point, inputs, and the rates of the point's
                   coordinates along a steady motion (x*(t) = x* + ẋ* t)
    tables         per table: times (N), values (N), then for "quadratic" and "cubic" the (N − 1) × 4
                   coefficients of its polynomial pieces
    switches       per `Switch`: its switching times
    breaks         the sorted breakpoints of every table and switch: the integrators stop and start there

A switch evaluates each of its sources into a local (``v<j>_<k>``) and keeps the one of the phase that
the hint (else t) is in.
"""

from __future__ import annotations

from dataclasses import dataclass

import symengine as se

from ..codegen import c_block
from ..dynamics import EquationsOfMotion
from ..errors import SimulationError
from ._inputs import InputLaw, InputSource

__all__ = ["WRAPPED", "LawCode", "law_code"]

#: The model functions a law wraps, with their extra arguments (``lg_aba`` only where it exists).
WRAPPED = (
    ("lg_mass_forces", "double *M, double *F", "M, F"),
    ("lg_monitors", "double *out", "out"),
    ("lg_events", "double *g", "g"),
    ("lg_hamilton_force", "double *g", "g"),
    ("lg_aba", "double *qdd, double *piv", "qdd, piv"),
)

#: A table's kind in C: a hold, a line, or a polynomial piece per sample interval (quadratic and cubic alike).
_KIND = {"zoh": 0, "linear": 1, "quadratic": 2, "cubic": 2}

# Binary search for the interval of `s` (the hint, or t), then the piece of that interval at t.
_TABLE = r"""
/* u(t) of a table (lagrangian.numerics._input_table): tab = times[n], values[n], polynomial pieces[n-1][4]
 * (kind 2: quadratic or cubic).
 * The interval is the one holding `hint` when given (the integrator's current interval between two
 * restarts at the samples), else the one holding t; outside the samples the end values are held. */
static double lg_table(const double *tab, int n, int kind, double t, double hint)
{
    const double *ts = tab, *v = tab + n;
    const double s = isnan(hint) ? t : hint;
    if (s < ts[0]) return v[0];
    if (s >= ts[n - 1]) return v[n - 1];
    int lo = 0, hi = n - 1;               /* ts[lo] <= s < ts[hi] */
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (ts[mid] <= s) lo = mid; else hi = mid;
    }
    if (kind == 0) return v[lo];
    const double d = t - ts[lo];
    if (kind == 1) return v[lo] + d * (v[lo + 1] - v[lo]) / (ts[lo + 1] - ts[lo]);
    const double *c = tab + 2 * n + 4 * lo;
    return ((c[0] * d + c[1]) * d + c[2]) * d + c[3];
}
"""


@dataclass(frozen=True)
class LawCode:
    """C text around the model's functions: ``prelude`` before them, ``epilogue`` after; ``size`` the
    law's block of p (LG_NX), ``inputs`` the driven inputs' parameter indices in the order of u."""

    prelude: str
    epilogue: str
    size: int
    inputs: tuple[int, ...]


def _check(eom: EquationsOfMotion, law: InputLaw) -> None:
    driven = {se.Symbol(s.name) for s in law.driven}
    for row in eom.M:
        for e in row:
            hit = e.free_symbols & driven
            if hit:
                raise SimulationError(f"The input `{min(map(str, hit))}` appears in the mass matrix M; an input "
                                      "that varies must be the magnitude of a load (a force or a torque).",
                                      fix="use the input in a load, or give it a constant value")


def _private_symbols(eom: EquationsOfMotion,
                     params: list[str]) -> tuple[dict[se.Basic, se.Basic], dict[se.Basic, str]]:
    """(each symbol of t, the state and the parameters → its private symbol, private symbol → the C it reads)."""
    private: dict[se.Basic, se.Basic] = {eom.t: se.Symbol("_t")}
    names: dict[se.Basic, str] = {se.Symbol("_t"): "t"}
    for i, s in enumerate((*eom.q, *eom.qd)):
        private[s] = se.Symbol(f"_y{i}")
        names[private[s]] = f"y[{i}]"
    for k, name in enumerate(params):
        private[se.Symbol(name)] = se.Symbol(f"_p{k}")
        names[private[se.Symbol(name)]] = f"p[{k}]"
    return private, names


class _Leaves:
    """The C of the law's leaves, gathered in order: expressions for the CSE block (``outputs``), the
    other sources as statements (``lines``)."""

    def __init__(self, eom: EquationsOfMotion, law: InputLaw, private: dict[se.Basic, se.Basic]) -> None:
        n = len(eom.q)
        self.coordinates = eom.coordinates
        self.private = private
        self.lay = law.layout()
        self.index = {c: i for i, c in enumerate(eom.coordinates)}
        self.index.update({c + "_dot": n + i for i, c in enumerate(eom.coordinates)})
        self.callables = list(law.callables)
        self.fb = law.feedback
        self.outputs: list[tuple[str, se.Basic]] = []
        self.lines: list[str] = []

    def leaf(self, target: str, key: str, s: InputSource) -> None:
        """The C that writes the source ``s`` (``key`` in the law's leaves) into ``target`` (an expression
        joins the CSE block)."""
        lay, fb, index, private = self.lay, self.fb, self.index, self.private
        if s.kind == "constant":
            self.lines.append(f"    {target} = {float(s.value)!r};")
        elif s.kind == "expression":
            self.outputs.append((target, s.value.xreplace({k: v for k, v in private.items()
                                                           if k in s.value.free_symbols})))
        elif s.kind == "table":
            table = s.value
            self.lines.append(f"    {target} = lg_table(law + {lay['table:' + key]}, {len(table.t)}, "
                              f"{_KIND[table.interpolation]}, t, law[0]);  /* {s.name}: {table.interpolation} table */")
        elif s.kind == "feedback":
            assert fb is not None
            i = fb.inputs.index(s.name)
            nx = len(fb.states)
            terms = " + ".join(f"law[{lay['K'] + i * nx + k}] * (y[{index[x]}] - law[{lay['x_star'] + k}]"
                               + (f" - law[{lay['x_rate'] + k}] * t)" if x in self.coordinates else ")")
                               for k, x in enumerate(fb.states))
            self.lines.append(f"    {target} = law[{lay['u_star'] + i}] - ({terms});  "
                              f"/* {s.name} = u* - K (x - x*(t)) */")
        else:
            self.lines.append(f"    {target} = uc[{self.callables.index(s)}];  /* {s.name}: a Python function */")


def _switch(leaves: _Leaves, j: int, s: InputSource, locals_: list[str]) -> str:
    """The C of the switch ``s`` driving u[j]: each source into a local ``v<j>_<k>`` (named in ``locals_``),
    then the selection of the phase's one."""
    sources = s.value.sources
    for k, piece in enumerate(sources):
        locals_.append(f"v{j}_{k}")
        leaves.leaf(f"v{j}_{k}", f"{s.name}#{k}", piece)
    at = leaves.lay["switch:" + s.name]
    chosen = f"v{j}_{len(sources) - 1}"
    for k in reversed(range(len(sources) - 1)):
        chosen = f"(s < law[{at + k}] ? v{j}_{k} : {chosen})"
    return (f"    {{  /* {s.name}: a switch, the source of the phase the hint (else t) is in */\n"
            f"        const double s = isnan(law[0]) ? t : law[0];\n"
            f"        u[{j}] = {chosen};\n    }}")


def _inputs_body(eom: EquationsOfMotion, law: InputLaw, params: list[str]) -> list[str]:
    """The statements of ``lg_inputs``: locals, the Python callback's call, the CSE block, the other leaves,
    the switches' selections."""
    private, names = _private_symbols(eom, params)
    leaves = _Leaves(eom, law, private)
    locals_: list[str] = []
    selections: list[str] = []
    for j, s in enumerate(law.driven):
        if s.kind != "switch":
            leaves.leaf(f"u[{j}]", s.name, s)
            continue
        selections.append(_switch(leaves, j, s, locals_))
    body = c_block(leaves.outputs, names, prefix="w") if leaves.outputs else []
    declared = [f"    double {', '.join(locals_)};"] if locals_ else []
    call = []
    if leaves.callables:
        call = [f"    double uc[{len(leaves.callables)}];",
                "    lg_user_fn fn;",
                "    memcpy(&fn, law + 1, sizeof fn);",
                "    fn(t, y, uc);"]
    return [*declared, *call, *body, *leaves.lines, *selections]


def _wrappers() -> list[str]:
    """The functions the integrators call (`WRAPPED`): the model's own, called with u written into p."""
    wrappers = []
    for name, extra, args in WRAPPED:
        text = (f"static void {name}(double t, const double *y, const double *p, {extra})\n{{\n"
                "    double pu[LG_NP + LG_NK > 0 ? LG_NP + LG_NK : 1];\n"
                "    lg_apply_inputs(t, y, p, pu);\n"
                f"    lg_model_{name[3:]}(t, y, pu, {args});\n}}\n")
        wrappers.append(f"#ifdef LG_ABA\n{text}#endif\n" if name == "lg_aba" else text)
    return wrappers


def law_code(eom: EquationsOfMotion, law: InputLaw) -> LawCode:
    """The C of ``law`` for the model of ``eom`` (module docstring)."""
    _check(eom, law)
    params = [p.name for p in eom.model.parameters]
    n = len(eom.q)
    lay = law.layout()
    driven = law.driven
    # The expressions, renamed to private symbols and printed with shared subexpressions.
    inputs_body = _inputs_body(eom, law, params)
    slots = tuple(params.index(s.name) for s in driven)
    nu = max(len(driven), 1)
    prelude = "\n".join([
        "/* ---- the inputs' law (lagrangian.numerics._input_code): the model's functions under other names ---- */",
        "#include <string.h>",
        *(f"#define {name} lg_model_{name[3:]}" for name, _, _ in WRAPPED),
        "",
    ])
    apply = "\n".join(f"    pu[{k}] = u[{j}];" for j, k in enumerate(slots))
    epilogue = "\n".join([
        *(f"#undef {name}" for name, _, _ in WRAPPED),
        f"#define LG_NU {len(driven)}",
        f"#define LG_NX {lay['size']}",
        f"#define LG_NBREAK {len(law.breakpoints)}",
        f"#define LG_BREAKS {lay['breaks']}",
        "typedef void (*lg_user_fn)(double t, const double *y, double *u);",
        _TABLE,
        "/* u (the driven inputs, in order) at (t, y); law = the law's block of p */",
        "static void lg_inputs(double t, const double *y, const double *p, double *u)\n{",
        "    const double *law = p + LG_NP + LG_NK;",
        "    (void)t; (void)y; (void)law;",
        *inputs_body,
        "}\n",
        "static void lg_apply_inputs(double t, const double *y, const double *p, double *pu)\n{",
        f"    double u[{nu}];",
        "    if (LG_NP + LG_NK > 0) memcpy(pu, p, (LG_NP + LG_NK) * sizeof(double));",
        "    lg_inputs(t, y, p, u);",
        apply,
        "}\n",
        *_wrappers(),
        "int lg_eval_inputs(int count, const double *t, const double *Y, const double *p, double *U)\n{",
        "    for (int k = 0; k < count; ++k)",
        f"        lg_inputs(t[k], Y + (long)k * {2 * n}, p, U + (long)k * {nu});",
        "    return 0;\n}\n",
    ])
    return LawCode(prelude, epilogue, lay["size"], slots)
