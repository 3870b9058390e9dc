"""The C translation unit of a model with free bodies: its quaternion state, q̈, M, monitors, events.

The state is y = (positions, velocities, δ) of `dynamics._floating.FloatingForm`: per free
body r (3) and the unit quaternion e (4), then the joints' q; per free body v (3) and ω (3),
then the joints' q̇; and per free body δ, the largest |1 − |e|| met before a projection
(`lg_free_project`, called by the integrator after each accepted step: e ← e/|e|).  δ has a
zero derivative, so it costs the error control nothing and travels with the state to the
output rows: the drift of the quaternions' norm is reported from it.

The model-independent integrators (`_runtime`: ``integrators.c``, copied whole) follow as for
any model; with ``LG_FREE`` their right-hand side is `lg_free_rhs` and ``LG_PROJECT`` is
`lg_free_project` (no M q̈ = F to solve: q̈ comes from the articulated-body recursion).
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import symengine as se

from ..dynamics import FloatingForm
from ..errors import DerivationError
from ._cprint import c_sequence
from ._rewrite import Hoist
from ._runtime import dop853_defines, runtime_source

__all__ = ["FreeSource", "generate_free_c"]


@dataclass(frozen=True)
class FreeSource:
    """The C source of a model with free bodies and the layout of what it reads and writes.

    Parameters
    ----------
    source : str
        The translation unit.
    key : str
        Its SHA-256 (the compile cache's key).
    nq : int
        The length of the position part of the state.
    nv : int
        The length of its velocity part; the state has nq + nv + (free bodies) entries.
    monitors : tuple of str
        The monitor names, in the order of the C arrays.
    events : tuple of str
        The event names, in the order of the C arrays.
    constants : int
        How many hoisted constants follow the parameters in ``p``.
    """

    source: str
    key: str
    nq: int
    nv: int
    monitors: tuple[str, ...]
    events: tuple[str, ...]
    constants: int


#: What `_printer` gives: body(outputs, what, hot) -> the C lines that compute the outputs.
_Body = Callable[..., list[str]]


def _private_names(form: FloatingForm, params: tuple[str, ...]) -> tuple[dict[se.Basic, str], dict[str, str]]:
    """(the C name of each symbol: ``_y<i>``, ``_p<k>``, ``_t``, ``_w<k>``; {name: the array entry it reads})."""
    names: dict[se.Basic, str] = {}
    header: dict[str, str] = {}
    for i, s in enumerate((*form.positions, *form.velocities)):
        names[s] = f"_y{i}"
        header[f"_y{i}"] = f"y[{i}]"
    for k, name in enumerate(params):
        names[se.Symbol(name)] = f"_p{k}"
        header[f"_p{k}"] = f"p[{k}]"
    names[se.Symbol("t")] = "_t"
    header["_t"] = "t"
    for k, (sym, _) in enumerate(form.intermediates):
        names[sym] = f"_w{k}"
    return names, header


def _printer(form: FloatingForm, names: dict[se.Basic, str], hoist: Hoist) -> _Body:
    """The printer of a function's body: its outputs with the intermediates they need, the parameter-only
    coefficients hoisted into ``hoist`` in the integrator's functions (``hot``)."""
    lifted: dict[se.Basic, se.Basic] = {}

    def lift(expr: se.Basic) -> se.Basic:
        out = lifted.get(expr)
        if out is None:
            out = lifted[expr] = hoist(expr)
        return out

    def body(outputs: list[tuple[str, se.Basic]], what: str, hot: bool = True) -> list[str]:
        # Only the integrator's functions take the hoisted constants: for M and the monitors, evaluated at
        # the output times, the search costs more than it saves.
        move = lift if hot else (lambda e: e)
        defs = [(s, move(e)) for s, e in form.needed([e for _, e in outputs])]
        outs = [(target, move(e if isinstance(e, se.Basic) else se.Integer(0) + e)) for target, e in outputs]
        for _, e in defs + outs:
            unknown = [s for s in e.free_symbols if s not in names and s not in hoist.constants.values()]
            if unknown:
                raise DerivationError(f"{what} contains `{unknown[0]}`, which is neither a state variable, a "
                                      "parameter nor t.", fix="declare it as a parameter of the model")
        return c_sequence(defs, outs, names | {s: str(s) for s in hoist.constants.values()})

    return body


def _function_specs(form: FloatingForm, events: Sequence[tuple[str, se.Basic]],
                    body: _Body) -> list[tuple[str, list[str], list[str]]]:
    """(signature, body lines, closing lines) of q'' (`lg_free_rhs`), M and F, the monitors and the events."""
    nq, nv = len(form.positions), len(form.velocities)
    npiv, nt = len(form.pivots), len(form.trees)
    rhs_out = [(f"dy[{i}]", e) for i, e in enumerate(form.derivative)]
    rhs_out += [(f"piv[{2 * i + k}]", pair[k]) for i, pair in enumerate(form.pivots) for k in range(2)]
    mass_out = [(f"M[{i * nv + j}]", form.M[i][j]) for i in range(nv) for j in range(nv)]
    return [
        ("static int lg_free_rhs(double t, const double *y, const double *p, double *dy, double *worst)",
         [f"    double piv[{max(2 * npiv, 1)}];", *body(rhs_out, "q''")],
         [f"    for (int j = 0; j < {npiv}; ++j) {{",
          "        const double d = piv[2 * j], diag = fabs(piv[2 * j + 1]);",
          "        if (!(d > 1e-13 * diag) || diag == 0.0) return 1;  /* LG_SINGULAR */",
          "        if (d / diag < *worst) *worst = d / diag;",
          "    }",
          f"    for (int i = {nq + nv}; i < {nq + nv + nt}; ++i) dy[i] = 0.0;  /* the drift records do not move */",
          f"    for (int i = 0; i < {nq + nv}; ++i) if (!isfinite(dy[i])) return 2;  /* LG_NONFINITE */",
          "    return 0;"]),
        ("LG_COLD static void lg_mass_forces(double t, const double *y, const double *p, double *M, double *F)",
         body(mass_out, "M", hot=False),
         [f"    double dy[{nq + nv + nt}], worst = 1.0;",
          "    lg_free_rhs(t, y, p, dy, &worst);  /* the articulated-body accelerations, dy[nq..] */",
          f"    for (int i = 0; i < {nv}; ++i) {{",
          "        double s = 0.0;",
          f"        for (int j = 0; j < {nv}; ++j) s += M[i * {nv} + j] * dy[{nq} + j];",
          "        F[i] = s;  /* F = M q'': the forces that give those accelerations */",
          "    }"]),
        ("LG_COLD static void lg_monitors(double t, const double *y, const double *p, double *out)",
         body([(f"out[{k}]", e) for k, (_, e) in enumerate(form.monitors)], "a monitor", hot=False), []),
        ("static void lg_events(double t, const double *y, const double *p, double *g)",
         body([(f"g[{k}]", e) for k, (_, e) in enumerate(events)], "an event function"), []),
    ]


def _c_function(header: dict[str, str], signature: str, lines: list[str], extra: Sequence[str] = ()) -> str:
    """A C function: ``signature``, the entries of y, p and t its lines read (``header``), then its lines."""
    used = set(re.findall(r"\b_[ypkt]\w*", "\n".join(lines)))
    decls = [f"    const double {c} = {v};" for c, v in header.items() if c in used]
    decls.append("    (void)t; (void)y; (void)p;")
    return signature + " {\n" + "\n".join([*decls, *lines, *extra]) + "\n}\n"


def _projection(form: FloatingForm) -> str:
    """`lg_free_project`: each quaternion made unit, the largest |1 − |e|| met kept in its drift record."""
    nq, nv = len(form.positions), len(form.velocities)
    project = ["static void lg_free_project(double *y) {"]
    offset = 0
    for t, tree in enumerate(form.trees):
        e, record = offset + 3, nq + nv + t
        project += [(f"    {{ const double n = sqrt(y[{e}] * y[{e}] + y[{e + 1}] * y[{e + 1}] + y[{e + 2}] * y[{e + 2}]"
                     f" + y[{e + 3}] * y[{e + 3}]);"),
                    f"      if (fabs(n - 1.0) > y[{record}]) y[{record}] = fabs(n - 1.0);",
                    f"      if (n > 0.0) for (int i = {e}; i < {e + 4}; ++i) y[i] /= n; }}"]
        offset += 7 + len(tree.joints)
    project.append("}")
    return "\n".join(project) + "\n"


def _defines(form: FloatingForm, events: Sequence[tuple[str, se.Basic]], params: tuple[str, ...],
             constants: int) -> list[str]:
    """The opening comment and the ``#define`` lines the runtime reads (sizes, ``LG_FREE``, ``LG_PROJECT``)."""
    nq, nv, nt = len(form.positions), len(form.velocities), len(form.trees)
    return [
        f"/* Generated by lagrangian from the free-body equations of `{form.model.name}`. Do not edit. */",
        "#define LG_FREE 1",
        f"#define LG_N {nv}",
        f"#define LG_NY {nq + nv + nt}",
        f"#define LG_NM {len(form.monitors)}",
        f"#define LG_NE {len(events)}",
        f"#define LG_NP {len(params)}",
        f"#define LG_NK {constants}",
        "#define LG_PROJECT(y) lg_free_project(y)",
        # M and the monitors are evaluated at the output times only, never in the integrator's loop: compiled
        # without optimisation, the unit of a 12-joint quadruped takes 2.2 s of GCC's CPU instead of 3.3 s, and
        # its monitors cost 5 µs per output time instead of 0.5 µs (5 ms for 1001 outputs).
        "#if defined(__GNUC__) && !defined(__clang__)",
        '#define LG_COLD __attribute__((optimize("O0")))',
        "#else",
        "#define LG_COLD",
        "#endif",
        *(f"#define {k} {v}" for k, v in dop853_defines().items()),
    ]


def generate_free_c(form: FloatingForm, events: Sequence[tuple[str, se.Basic]] = ()) -> FreeSource:
    """Generate the C translation unit of ``form``.

    Parameters
    ----------
    form : FloatingForm
        The quaternion-state equations.
    events : sequence of (str, SymEngine expression), optional
        (name, g) in the state's symbols.

    Returns
    -------
    FreeSource
        The translation unit and its layout.

    Raises
    ------
    DerivationError
        When an expression holds a symbol that is not a state variable, a parameter or t.
    """
    params = tuple(p.name for p in form.model.parameters)
    nq, nv = len(form.positions), len(form.velocities)
    names, header = _private_names(form, params)
    hoist = Hoist([se.Symbol(name) for name in params])
    # the bodies first, so that every constant is hoisted
    specs = _function_specs(form, events, _printer(form, names, hoist))
    constant_lines = c_sequence([], [(f"k[{j}]", expr) for j, expr in enumerate(hoist.constants)], names)
    for k, sym in enumerate(hoist.constants.values()):
        header[str(sym)] = f"p[{len(params) + k}]"
    constants = _c_function(header, "void lg_constants(const double *p, double *k)", constant_lines).replace(
        " {\n", " {\n    const double t = 0.0; const double *y = 0;\n", 1)  # neither is read
    functions = [_c_function(header, *spec) for spec in specs]
    parts = [
        *_defines(form, events, params, len(hoist.constants)),
        "#include <math.h>",
        constants,
        *functions,
        _projection(form),
        runtime_source("integrators.c"),
    ]
    source = "\n".join(parts)
    return FreeSource(source, hashlib.sha256(source.encode("utf-8")).hexdigest(), nq, nv,
                      tuple(name for name, _ in form.monitors), tuple(name for name, _ in events),
                      len(hoist.constants))
