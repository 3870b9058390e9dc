"""The ``c`` export: ``<name>.h`` and ``<name>.c`` that need nothing but libm (`lagrangian.export`).

M and F are those of the in-package library (`codegen._rewrite.mass_forces_form`): each
body's γ⁰(G) and dσ⁰/dt computed once, and the coefficients that hold only parameters
(``(m2 + m3) l1 l2``) lifted into ``<name>_constants(p, k)``, evaluated once per parameter
set; ``<name>_rhs_k(t, y, p, k, out)`` takes them, ``<name>_rhs(t, y, p, out)`` computes
them on each call.  Expressions are printed by the package's own C printer
(`codegen._cprint.c_block`, common subexpressions shared by SymEngine's ``cse``).

q̈ is solved from M q̈ = F by a Cholesky factorisation M = L Lᵀ (the package's own
routine, ``runtime/solve_mass.c``, copied whole): M is symmetric positive definite for a
mechanical system described by independent coordinates (T = ½ q̇ᵀ M q̇ > 0 for q̇ ≠ 0; Golub &
Van Loan, *Matrix Computations*, §4.2); where it is not, the accelerations are NaN.  With
complementary constraints, M q̈ = F + Aᵀλ and A q̈ + c = 0 are solved through the Schur
complement S = A M⁻¹ Aᵀ as in the package (`codegen._codegen_dae`; ``runtime/cholesky.c``,
copied whole), with Baumgarte's rates (α, β) optional.  The first integrals (`lagrangian.first_integrals`) and the
constraint rows (A, b, c, f) are functions of their own.
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from typing import final

import symengine as se

from .._cprint import c_block
from .._rewrite import MassForcesForm
from .._runtime import runtime_source
from .base import AbstractTarget, ExportedSymbols

__all__ = ["CTarget", "c_files", "integral_functions"]


def _string(text: str) -> str:
    """A C string literal of ``text`` (JSON's escapes are valid C for ASCII output)."""
    return json.dumps(text, ensure_ascii=True)


def _comment(text: str) -> str:
    """``text`` inside a C comment: ASCII (JSON's escapes), no comment terminator."""
    return json.dumps(text, ensure_ascii=True)[1:-1].replace("*/", "* /")


def _double(value: float | None) -> str:
    return "NAN" if value is None else repr(float(value))


def _inputs(symbols: ExportedSymbols) -> dict[str, str]:
    """{private name: the array entry it reads}: ``_y3`` is y[3], ``_p1`` p[1], ``_k0`` k[0], ``_t`` t."""
    inputs = {str(s): f"y[{i}]" for i, s in enumerate(symbols.y)}
    inputs.update({str(s): f"p[{k}]" for k, s in enumerate(symbols.p)})
    inputs[str(symbols.t)] = "t"
    if symbols.fast is not None:
        inputs.update({str(sym): f"k[{j}]" for j, (sym, _) in enumerate(symbols.fast.constants)})
    return inputs


def _function(signature: str, comment: str, stages: Sequence[Sequence[tuple[str, se.Basic]]],
              inputs: dict[str, str], unused: str = "(void)t; (void)y; (void)p;", after: str = "",
              returns: str = "") -> str:
    """A C function computing ``stages`` in turn (the targets of one stage may be read by the next).

    The inputs it reads are first copied into ``const`` locals (``const double _y3 = y[3];``), as in
    the package's code: read through a pointer after a store to an output array, they would be
    reloaded (the arrays may alias).  ``unused`` and ``after`` (put after the first stage) silence
    -Wunused for what a model may not read.
    """
    names = {se.Symbol(name): name for name in inputs}
    body = []
    for j, stage in enumerate(stages):
        names.update({sym: str(sym) for _, e in stage for sym in e.free_symbols if str(sym).startswith("_s")})
        body += c_block(list(stage), names, prefix="xyz"[j])
        if j == 0 and after:
            body.append("    " + after)
    used = set(re.findall(r"\b_[ypkt]\w*", "\n".join(body)))
    decls = [f"    const double {c} = {v};" for c, v in inputs.items() if c in used]
    if returns:
        body.append(f"    return {returns};")
    return f"/* {comment} */\n{signature} {{\n    {unused}\n" + "\n".join([*decls, *body]) + "\n}\n"


def _solve_mass(up: str) -> str:
    """The package's solve of M x = F (``runtime/solve_mass.c``: ``lg_cholesky_solve``), for n = ``<NAME>_N``."""
    return f"#define LG_N {up}_N\n" + runtime_source("solve_mass.c")


def _header(symbols: ExportedSymbols, banner: str) -> str:
    ident, n, m = symbols.identifier, symbols.n, len(symbols.rows)
    up = ident.upper()
    nk = len(symbols.fast.constants) if symbols.fast else 0
    param_names = ", ".join(_string(k) for k in symbols.parameters) or "0"
    defaults = ", ".join(_double(v) for v in symbols.defaults) or "0.0"
    integral_names = ", ".join(_string(name) for name, _ in symbols.integrals) or "0"
    row_names = ", ".join(_string(r.name) for r in symbols.rows) or "0"
    row_kinds = ", ".join(_string(r.kind) for r in symbols.rows) or "0"
    multipliers = ", ".join(_string(r.multiplier) for r in symbols.rows) or "0"
    one_by_one = "".join(f"double {fn}(double t, const double *y, const double *p);  /* {_comment(name)} */\n"
                         for fn, (name, _) in zip(integral_functions(symbols), symbols.integrals, strict=True))
    constrained = "" if not m else f"""
/* With the {m} complementary constraint row(s): M q'' = F + A^T lam and A q'' + c = -2 alpha g - beta^2 f
   (g = A q' + b, the velocity residual; f, the position residual of holonomic rows): alpha = beta = 0 is
   the exact index reduction, alpha, beta > 0 Baumgarte's stabilisation (1/time).  out = y' (2n entries),
   lam = the multipliers ({up}_NC entries, in the order of {ident}_multiplier_names); returns 0, 1 where M
   is not positive definite, 2 where the rows are dependent (out and lam are then NAN). */
int {ident}_rhs_multipliers(double t, const double *y, const double *p, const double *k, double alpha,
                            double beta, double *out, double *lam);
"""
    return banner + f"""#ifndef {up}_EXPORT_H
#define {up}_EXPORT_H

#include <math.h>

/* Number of coordinates n (the state y has 2n components), of parameters, of derived constants
   (k, computed from p by {ident}_constants), of first integrals and of complementary constraint rows. */
#define {up}_N {n}
#define {up}_NP {len(symbols.parameters)}
#define {up}_NK {nk}
#define {up}_NI {len(symbols.integrals)}
#define {up}_NC {m}

/* Parameter names and default values, in the order of the p array ({up}_NP entries). */
static const char *const {ident}_parameter_names[] = {{{param_names}}};
static const double {ident}_parameter_defaults[] = {{{defaults}}};

/* State names, in the order of y: coordinates, then their rates. */
static const char *const {ident}_state_names[] = {{{", ".join(_string(s) for s in symbols.state)}}};

/* First integrals (constant along every motion, lagrangian.first_integrals), in the order of
   {ident}_first_integrals' output ({up}_NI entries). */
static const char *const {ident}_integral_names[] = {{{integral_names}}};

/* Complementary constraint rows ({up}_NC): name, kind ("holonomic" or "nonholonomic"), multiplier. */
static const char *const {ident}_constraint_names[] = {{{row_names}}};
static const char *const {ident}_constraint_kinds[] = {{{row_kinds}}};
static const char *const {ident}_multiplier_names[] = {{{multipliers}}};

/* The parameter-only coefficients of M and F, k ({up}_NK entries; pass an array of at least one):
   compute them once per parameter set for {ident}_rhs_k. */
void {ident}_constants(const double *p, double *k);

/* M(q, t), row-major n*n, at state y (only q is read). */
void {ident}_mass_matrix(double t, const double *y, const double *p, double *M);

/* F(q, q', t), n entries{" (without the constraints' A^T lam)" if m else ""}. */
void {ident}_forcing(double t, const double *y, const double *p, double *F);

/* out = y' = (q', q''), 2n entries{", q'' and the multipliers solved exactly (alpha = beta = 0)" if m else
                                    ", q'' solved from M q'' = F (Cholesky)"}; NAN where M is not
   positive definite.  {ident}_rhs computes k on every call; in a loop over states with fixed p, call
   {ident}_constants once and {ident}_rhs_k. */
void {ident}_rhs(double t, const double *y, const double *p, double *out);
void {ident}_rhs_k(double t, const double *y, const double *p, const double *k, double *out);
{constrained}
/* The first integrals at state y, {up}_NI entries (out must hold at least one), and each on its own. */
void {ident}_first_integrals(double t, const double *y, const double *p, double *out);
{one_by_one}
/* The complementary constraint rows (none when {up}_NC is 0): A (NC x n, row-major), b, c and f (NC each)
   with A q' + b = 0 and A q'' + c = 0 along a motion, f(q, t) = 0 for a holonomic row (0 for a
   nonholonomic one). */
void {ident}_constraint_rows(double t, const double *y, const double *p, double *A, double *b, double *c,
                             double *f);

#endif
"""


def integral_functions(symbols: ExportedSymbols) -> list[str]:
    """The C name of each first integral's own function: ``<name>_integral_<K>``, the integral's name
    made an identifier (``p_psi``; non-identifier characters become ``_``), numbered when two coincide."""
    out: list[str] = []
    for name, _ in symbols.integrals:
        base = re.sub(r"[^0-9A-Za-z_]", "_", name.encode("ascii", "replace").decode())
        candidate, k = f"{symbols.identifier}_integral_{base}", 2
        while candidate in out:
            candidate, k = f"{symbols.identifier}_integral_{base}_{k}", k + 1
        out.append(candidate)
    return out


def _banner(symbols: ExportedSymbols) -> str:
    """The comment that opens both files: where they come from, the equations, the state and parameters."""
    ident, m = symbols.identifier, len(symbols.rows)
    return (f"/* Generated by lagrangian {symbols.version} from the equations of motion of the model\n"
            f" * `{symbols.name}`: M(q, t) q'' = F(q, q', t){' + A^T lam' if m else ''}. Do not edit; regenerate\n"
            " * with `lagrangian export --to c`. Depends on nothing but libm (link with -lm).\n"
            f" * State order: y = ({', '.join(symbols.state)}).\n"
            f" * Parameters: p in the order of {ident}_parameter_names (defaults in {ident}_parameter_defaults;"
            " NAN: no default). */\n")


def _parts_and_constants(symbols: ExportedSymbols, fast: MassForcesForm, names: dict[str, str]) -> tuple[str, str]:
    """(``<name>_parts``: M and F given the constants k, ``<name>_constants``: k from the parameters)."""
    ident = symbols.identifier
    shared = [(f"const double {sym}", e) for sym, e in fast.shared]
    M_out = [(f"M[{j}]", e) for j, e in enumerate(fast.M)]
    F_out = [(f"F[{i}]", e) for i, e in enumerate(fast.F)]
    parts = _function(f"static void {ident}_parts(double t, const double *y, const double *p, const double *k, "
                      "double *M, double *F)", "M and F, with the constants k",
                      [shared, M_out + F_out], names, "(void)t; (void)y; (void)p; (void)k;",
                      " ".join(f"(void){sym};" for sym, _ in fast.shared))
    constants = _function(f"void {ident}_constants(const double *p, double *k)",
                          "the parameter-only coefficients, once per parameter set",
                          [[(f"k[{j}]", e) for j, (_, e) in enumerate(fast.constants)]], names,
                          "(void)p; (void)k;")
    return parts, constants


def _public_functions(ident: str, up: str) -> str:
    """``<name>_mass_matrix``, ``<name>_forcing`` and ``<name>_rhs``: the constants computed on each call."""
    nk = f"{up}_NK > 0 ? {up}_NK : 1"
    return f"""/* M(q, t), row-major */
void {ident}_mass_matrix(double t, const double *y, const double *p, double *M) {{
    double k[{nk}], F[{up}_N];
    {ident}_constants(p, k);
    {ident}_parts(t, y, p, k, M, F);
}}

/* F(q, q', t) */
void {ident}_forcing(double t, const double *y, const double *p, double *F) {{
    double k[{nk}], M[{up}_N * {up}_N];
    {ident}_constants(p, k);
    {ident}_parts(t, y, p, k, M, F);
}}

void {ident}_rhs(double t, const double *y, const double *p, double *out) {{
    double k[{nk}];
    {ident}_constants(p, k);
    {ident}_rhs_k(t, y, p, k, out);
}}
"""


def _unconstrained_solve(ident: str, up: str) -> str:
    """``<name>_rhs_k`` without constraint rows: M q'' = F solved by Cholesky (``solve_mass.c``)."""
    return _solve_mass(up) + f"""
/* y' = (q', q''): M q'' = F solved by Cholesky. */
void {ident}_rhs_k(double t, const double *y, const double *p, const double *k, double *out) {{
    double M[{up}_N * {up}_N], F[{up}_N], worst = 1.0;
    int i;
    {ident}_parts(t, y, p, k, M, F);
    for (i = 0; i < {up}_N; ++i) out[i] = y[{up}_N + i];
    if (lg_cholesky_solve(M, F, &worst)) {{  /* not positive definite (or NaN): no acceleration */
        for (i = 0; i < {up}_N; ++i) out[{up}_N + i] = NAN;
        return;
    }}
    for (i = 0; i < {up}_N; ++i) out[{up}_N + i] = F[i];
}}
"""


def _constrained_solve(ident: str, up: str) -> str:
    """``<name>_rhs_multipliers`` and ``<name>_rhs_k`` with constraint rows: the Schur complement
    S = A M⁻¹ Aᵀ (``cholesky.c``), with Baumgarte's rates."""
    return runtime_source("cholesky.c") + f"""
/* [M -A^T; A 0] [q''; lam] = [F; -c - 2 alpha g - beta^2 f] through the Schur complement S = A M^-1 A^T:
   lam = S^-1 (-c - 2 alpha g - beta^2 f - A M^-1 F), q'' = M^-1 (F + A^T lam). */
int {ident}_rhs_multipliers(double t, const double *y, const double *p, const double *k, double alpha,
                            double beta, double *out, double *lam) {{
    double M[{up}_N * {up}_N], F[{up}_N], A[{up}_NC * {up}_N], b[{up}_NC], c[{up}_NC], f[{up}_NC];
    double X[{up}_NC * {up}_N], S[{up}_NC * {up}_NC], worst = 1.0;
    int i, r, l, status = 0;
    {ident}_parts(t, y, p, k, M, F);
    {ident}_constraint_rows(t, y, p, A, b, c, f);
    for (i = 0; i < {up}_N; ++i) out[i] = y[{up}_N + i];
    if (lg_chol_factor(M, {up}_N, &worst)) status = 1;
    if (!status) {{
        for (r = 0; r < {up}_NC; ++r) {{
            for (i = 0; i < {up}_N; ++i) X[r * {up}_N + i] = A[r * {up}_N + i];
            lg_chol_solve(M, {up}_N, X + r * {up}_N);          /* row r of X = M^-1 A_r^T */
        }}
        lg_chol_solve(M, {up}_N, F);                           /* F <- M^-1 F */
        for (r = 0; r < {up}_NC; ++r) {{
            double g = b[r], rhs = -c[r];
            for (i = 0; i < {up}_N; ++i) g += A[r * {up}_N + i] * y[{up}_N + i];
            rhs -= 2.0 * alpha * g + beta * beta * f[r];
            for (i = 0; i < {up}_N; ++i) rhs -= A[r * {up}_N + i] * F[i];
            lam[r] = rhs;
            for (l = 0; l < {up}_NC; ++l) {{
                double s = 0.0;
                for (i = 0; i < {up}_N; ++i) s += A[r * {up}_N + i] * X[l * {up}_N + i];
                S[r * {up}_NC + l] = s;
            }}
        }}
        if (lg_chol_factor(S, {up}_NC, &worst)) status = 2;
    }}
    if (status) {{
        for (i = 0; i < {up}_N; ++i) out[{up}_N + i] = NAN;
        for (r = 0; r < {up}_NC; ++r) lam[r] = NAN;
        return status;
    }}
    lg_chol_solve(S, {up}_NC, lam);
    for (i = 0; i < {up}_N; ++i) {{
        double a = F[i];
        for (r = 0; r < {up}_NC; ++r) a += X[r * {up}_N + i] * lam[r];
        out[{up}_N + i] = a;
    }}
    return 0;
}}

/* y' = (q', q''), the constraints held exactly at acceleration level (alpha = beta = 0). */
void {ident}_rhs_k(double t, const double *y, const double *p, const double *k, double *out) {{
    double lam[{up}_NC];
    {ident}_rhs_multipliers(t, y, p, k, 0.0, 0.0, out, lam);
}}
"""


def _integrals_source(symbols: ExportedSymbols, names: dict[str, str]) -> str:
    """``<name>_first_integrals`` (all of them into ``out``), then each integral's own function."""
    ident = symbols.identifier
    integrals = _function(f"void {ident}_first_integrals(double t, const double *y, const double *p, double *out)",
                          "the first integrals, in the order of " + f"{ident}_integral_names",
                          [[(f"out[{j}]", e) for j, (_, e) in enumerate(symbols.integrals)]], names,
                          "(void)t; (void)y; (void)p; (void)out;")
    integrals += "".join(
        "\n" + _function(f"double {fn}(double t, const double *y, const double *p)",
                         f"the first integral {_comment(name)}", [[("const double value", e)]], names,
                         returns="value")
        for fn, (name, e) in zip(integral_functions(symbols), symbols.integrals, strict=True))
    return integrals


def _constraint_rows_source(symbols: ExportedSymbols, names: dict[str, str]) -> str:
    """``<name>_constraint_rows``: A (row-major), b, c and f of the complementary constraint rows."""
    ident, n = symbols.identifier, symbols.n
    rows = [(f"A[{r * n + i}]", a) for r, row in enumerate(symbols.rows) for i, a in enumerate(row.A)]
    rows += [(f"{v}[{r}]", getattr(row, v)) for v in "bcf" for r, row in enumerate(symbols.rows)]
    return _function(
        f"void {ident}_constraint_rows(double t, const double *y, const double *p, double *A, double *b, double *c, "
        "double *f)", "A q' + b = 0, A q'' + c = 0, f(q, t) = 0 (holonomic rows)", [rows], names,
        "(void)t; (void)y; (void)p; (void)A; (void)b; (void)c; (void)f;")


def c_files(symbols: ExportedSymbols) -> dict[str, str]:
    """{``<name>.h``: header, ``<name>.c``: source} (module docstring, docs/export.md)."""
    if symbols.fast is None:
        raise ValueError("the C target prints the in-package form of M and F: exported_symbols(eom, 'c') gives it")
    ident = symbols.identifier
    up = ident.upper()
    banner = _banner(symbols)
    names = _inputs(symbols)
    parts, constants = _parts_and_constants(symbols, symbols.fast, names)
    solve = _constrained_solve(ident, up) if symbols.rows else _unconstrained_solve(ident, up)
    source = "\n".join([banner + f'#include "{ident}.h"\n', constants, parts, _public_functions(ident, up), solve,
                        _integrals_source(symbols, names), _constraint_rows_source(symbols, names)])
    return {f"{ident}.h": _header(symbols, banner), f"{ident}.c": source}


@final
class CTarget(AbstractTarget):
    """``<name>.h`` and ``<name>.c``, C99 needing only libm (module docstring)."""

    name = "c"
    in_package_form = True

    def files(self, symbols: ExportedSymbols) -> dict[str, str]:
        return c_files(symbols)
