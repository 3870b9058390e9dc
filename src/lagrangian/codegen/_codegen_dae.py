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
the constraint manifold, the monitors, and the reaction components (linear in λ).  The
solve itself is the C runtime's (`_runtime`: ``cholesky.c`` and ``dae.c``, copied whole).
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass

import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import DerivationError
from ._cprint import c_block
from ._runtime import runtime_source

__all__ = ["GeneratedDAE", "generate_dae_c"]


@dataclass(frozen=True)
class GeneratedDAE:
    """The C source of a constrained model and the sizes of what it reads and writes.

    Parameters
    ----------
    source : str
        The translation unit.
    key : str
        Its SHA-256 (the compile cache's key).
    n : int
        The number of coordinates; y = (q, q̇).
    m : int
        The number of complementary rows; λ has length m.
    monitors : int
        The number of monitor expressions.
    reactions : int
        The number of reaction components.
    """

    source: str
    key: str
    n: int
    m: int
    monitors: int
    reactions: int




def generate_dae_c(eom: EquationsOfMotion, monitors: Sequence[se.Basic],
                   reactions: Sequence[se.Basic]) -> GeneratedDAE:
    """The C translation unit of ``eom`` with its complementary constraints.

    Parameters
    ----------
    eom : EquationsOfMotion
        Equations of motion with at least one complementary row (``eom.constraints``).
    monitors : sequence of SymEngine expressions
        Expressions of (q, q̇, t) evaluated by ``lgd_eval_monitors``.
    reactions : sequence of SymEngine expressions
        Expressions of (q, q̇, λ, t) evaluated by ``lgd_eval_reactions``.

    Returns
    -------
    GeneratedDAE
        The translation unit and its sizes.

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
        runtime_source("cholesky.c"),
        runtime_source("dae.c"),
    ])
    return GeneratedDAE(source, hashlib.sha256(source.encode("utf-8")).hexdigest(), n, m, len(monitors),
                        len(reactions))
