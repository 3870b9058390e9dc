"""C code for systems with complementary constraints: q̈ and λ from the augmented equations.

Along a motion the complementary rows hold at acceleration level (holonomic rows
differentiated twice, nonholonomic rows once):  A q̈ + c = 0, so with the Lagrange
equations M q̈ = F + Aᵀλ

    [ M  −Aᵀ ] [ q̈ ]   [ F                  ]
    [ A   0  ] [ λ  ] = [ −c − 2α g − β² f   ]

where g = A q̇ + b and f (holonomic rows only) are the velocity and position residuals:
α = β = 0 is the exact index reduction, α, β > 0 Baumgarte's stabilisation (J.
Baumgarte, Comput. Methods Appl. Mech. Eng. 1, 1972), which turns a drift away from the
constraints into a damped oscillation.  The system is solved through the Schur complement,
with two Cholesky factorizations — M = LLᵀ (positive definite wherever the coordinates
are regular) and S = A M⁻¹ Aᵀ (positive definite while the rows are independent):

    λ = S⁻¹ (−c − 2α g − β² f − A M⁻¹ F),     q̈ = M⁻¹ (F + Aᵀ λ).

The generated file also evaluates the parts (M, F, A, c, g, f) for the projection onto
the constraint manifold, the monitors, and the reaction components (linear in λ).
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass

import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import DerivationError
from ._cprint import c_block

__all__ = ["GeneratedDAE", "generate_dae_c"]


@dataclass(frozen=True)
class GeneratedDAE:
    """The C source of a constrained model and the sizes of what it reads and writes.

    Attributes
    ----------
    source, key : the translation unit and its SHA-256 (the compile cache's key).
    n, m : coordinates and complementary rows; y = (q, q̇), λ of length m.
    monitors : number of monitor expressions; reactions : number of reaction components.
    """

    source: str
    key: str
    n: int
    m: int
    monitors: int
    reactions: int


_RUNTIME = r"""
/* ---- model-independent part: Cholesky solves and the Schur complement ---------------- */
static int lgd_chol(double *M, int n, double *worst)
{
    for (int j = 0; j < n; ++j) {
        double d = M[j * n + j];
        const double diag = fabs(d);
        for (int k = 0; k < j; ++k) d -= M[j * n + k] * M[j * n + k];
        if (!(d > 1e-13 * diag) || diag == 0.0) return 1;
        if (d / diag < *worst) *worst = d / diag;
        d = sqrt(d);
        M[j * n + j] = d;
        for (int i = j + 1; i < n; ++i) {
            double s = M[i * n + j];
            for (int k = 0; k < j; ++k) s -= M[i * n + k] * M[j * n + k];
            M[i * n + j] = s / d;
        }
    }
    return 0;
}

static void lgd_chol_solve(const double *L, int n, double *b)
{
    for (int i = 0; i < n; ++i) {
        double s = b[i];
        for (int k = 0; k < i; ++k) s -= L[i * n + k] * b[k];
        b[i] = s / L[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) {
        double s = b[i];
        for (int k = i + 1; k < n; ++k) s -= L[k * n + i] * b[k];
        b[i] = s / L[i * n + i];
    }
}

/* dy = (q', q''), lam = multipliers; stab = (alpha, beta).  Returns 0, 1 (M singular),
 * 2 (S singular: rows dependent here) or 3 (non-finite result). */
static int lgd_rhs(double t, const double *y, const double *p, const double *stab, double *dy, double *lam,
                   double *worst)
{
    double M[LGD_N * LGD_N], F[LGD_N], A[LGD_M * LGD_N], c[LGD_M], g[LGD_M], f[LGD_M];
    double X[LGD_M * LGD_N], S[LGD_M * LGD_M];
    lgd_parts(t, y, p, M, F, A, c, g, f);
    if (lgd_chol(M, LGD_N, worst)) return 1;
    for (int k = 0; k < LGD_M; ++k) {
        for (int i = 0; i < LGD_N; ++i) X[k * LGD_N + i] = A[k * LGD_N + i];
        lgd_chol_solve(M, LGD_N, X + k * LGD_N);          /* row k of X = M^-1 A_k^T */
    }
    lgd_chol_solve(M, LGD_N, F);                           /* F <- M^-1 F */
    for (int k = 0; k < LGD_M; ++k) {
        double r = -c[k] - 2.0 * stab[0] * g[k] - stab[1] * stab[1] * f[k];
        for (int i = 0; i < LGD_N; ++i) r -= A[k * LGD_N + i] * F[i];
        lam[k] = r;
        for (int l = 0; l < LGD_M; ++l) {
            double s = 0.0;
            for (int i = 0; i < LGD_N; ++i) s += A[k * LGD_N + i] * X[l * LGD_N + i];
            S[k * LGD_M + l] = s;
        }
    }
    double unused = 1.0;
    if (lgd_chol(S, LGD_M, &unused)) return 2;
    lgd_chol_solve(S, LGD_M, lam);
    for (int i = 0; i < LGD_N; ++i) {
        double a = F[i];
        for (int k = 0; k < LGD_M; ++k) a += X[k * LGD_N + i] * lam[k];
        dy[i] = y[LGD_N + i];
        dy[LGD_N + i] = a;
        if (!isfinite(a)) return 3;
    }
    return 0;
}

int lgd_eval_rhs(int count, const double *t, const double *Y, const double *p, const double *stab, double *dY,
                 double *LAM, double *worst)
{
    for (int k = 0; k < count; ++k) {
        int status = lgd_rhs(t[k], Y + (long)k * 2 * LGD_N, p, stab, dY + (long)k * 2 * LGD_N,
                             LAM + (long)k * LGD_M, worst);
        if (status) return status;
    }
    return 0;
}

void lgd_eval_parts(int count, const double *t, const double *Y, const double *p, double *M, double *F,
                    double *A, double *c, double *g, double *f)
{
    for (int k = 0; k < count; ++k)
        lgd_parts(t[k], Y + (long)k * 2 * LGD_N, p, M + (long)k * LGD_N * LGD_N, F + (long)k * LGD_N,
                  A + (long)k * LGD_M * LGD_N, c + (long)k * LGD_M, g + (long)k * LGD_M, f + (long)k * LGD_M);
}

void lgd_eval_monitors(int count, const double *t, const double *Y, const double *p, double *out)
{
    for (int k = 0; k < count; ++k)
        lgd_monitors(t[k], Y + (long)k * 2 * LGD_N, p, out + (long)k * (LGD_NM > 0 ? LGD_NM : 1));
}

void lgd_eval_reactions(int count, const double *t, const double *Y, const double *LAM, const double *p,
                        double *out)
{
    for (int k = 0; k < count; ++k)
        lgd_reactions(t[k], Y + (long)k * 2 * LGD_N, LAM + (long)k * LGD_M, p,
                      out + (long)k * (LGD_NR > 0 ? LGD_NR : 1));
}

int lgd_dimensions(int *out)
{
    out[0] = LGD_N;
    out[1] = LGD_M;
    out[2] = LGD_NM;
    out[3] = LGD_NR;
    return 0;
}
"""


def generate_dae_c(eom: EquationsOfMotion, monitors: Sequence[se.Basic],
                   reactions: Sequence[se.Basic]) -> GeneratedDAE:
    """The C translation unit of ``eom`` with its complementary constraints.

    Parameters
    ----------
    eom : equations of motion with at least one complementary row (``eom.constraints``).
    monitors : expressions of (q, q̇, t) evaluated by ``lgd_eval_monitors``.
    reactions : expressions of (q, q̇, λ, t) evaluated by ``lgd_eval_reactions``.

    Raises
    ------
    DerivationError
        When an expression holds a symbol that is not a coordinate, rate, parameter,
        multiplier or t.
    """
    rows = eom.constraints
    n, m = len(eom.q), len(rows)
    if m == 0:
        raise DerivationError("generate_dae_c needs complementary constraints", fix="use generate_c")
    private: dict[se.Basic, se.Symbol] = {}
    header: dict[str, str] = {}
    for i, s in enumerate((*eom.q, *eom.qd)):
        private[s] = se.Symbol(f"_y{i}")
        header[f"_y{i}"] = f"y[{i}]"
    for k, p in enumerate(eom.model.parameters):
        private[se.Symbol(p.name)] = se.Symbol(f"_p{k}")
        header[f"_p{k}"] = f"p[{k}]"
    private[eom.t] = se.Symbol("_t")
    header["_t"] = "t"
    lam_header: dict[str, str] = {}
    for k, row in enumerate(rows):
        private[row.multiplier] = se.Symbol(f"_l{k}")
        lam_header[f"_l{k}"] = f"lam[{k}]"
    names = {sym: str(sym) for sym in private.values()}

    def rename(expr: se.Basic, what: str, allow_lambda: bool = False) -> se.Basic:
        expr = expr if isinstance(expr, se.Basic) else se.Integer(0) + expr
        allowed = set(private) if allow_lambda else set(private) - {r.multiplier for r in rows}
        unknown = [s for s in expr.free_symbols if s not in allowed]
        if unknown:
            raise DerivationError(f"{what} contains `{unknown[0]}`, which is neither a coordinate, a rate, a "
                                  "parameter nor t.", fix="declare it as a parameter of the model")
        return expr.xreplace(private)

    def function(signature: str, outputs: list[tuple[str, se.Basic]], what: str, with_lambda: bool = False) -> str:
        body = c_block([(target, rename(e, what, with_lambda)) for target, e in outputs], names)
        inputs = dict(header, **(lam_header if with_lambda else {}))
        decls = [f"    const double {c} = {v}; (void){c};" for c, v in inputs.items()]
        return signature + " {\n" + "\n".join([*decls, *body]) + "\n}\n"

    parts = [(f"M[{i * n + j}]", eom.M[i][j]) for i in range(n) for j in range(n)]
    parts += [(f"F[{i}]", eom.F[i]) for i in range(n)]
    parts += [(f"A[{k * n + i}]", row.coefficients[i]) for k, row in enumerate(rows) for i in range(n)]
    parts += [(f"c[{k}]", row.bias) for k, row in enumerate(rows)]
    parts += [(f"g[{k}]", row.velocity) for k, row in enumerate(rows)]
    parts += [(f"f[{k}]", row.expression if row.kind == "holonomic" else se.Integer(0)) for k, row in enumerate(rows)]
    source = "\n".join([
        f"/* Generated by lagrangian: `{eom.model.name}` with complementary constraints. Do not edit. */",
        f"#define LGD_N {n}",
        f"#define LGD_M {m}",
        f"#define LGD_NM {len(monitors)}",
        f"#define LGD_NR {len(reactions)}",
        "#include <math.h>",
        function("static void lgd_parts(double t, const double *y, const double *p, double *M, double *F, "
                 "double *A, double *c, double *g, double *f)", parts, "M q'' = F + A^T lambda, A q'' + c = 0"),
        function("static void lgd_monitors(double t, const double *y, const double *p, double *out)",
                 [(f"out[{k}]", e) for k, e in enumerate(monitors)], "a monitor"),
        function("static void lgd_reactions(double t, const double *y, const double *lam, const double *p, "
                 "double *out)", [(f"out[{k}]", e) for k, e in enumerate(reactions)], "a reaction", True),
        _RUNTIME,
    ])
    return GeneratedDAE(source, hashlib.sha256(source.encode("utf-8")).hexdigest(), n, m, len(monitors),
                        len(reactions))
