/* lagrangian runtime: q'' and the multipliers of a model with complementary constraints.
 *
 * Copied whole after the generated code (`codegen/_codegen_dae.py`) and cholesky.c, the
 * generated code defining
 *   LGD_N, LGD_M, LGD_NM, LGD_NR     coordinates, constraint rows, monitors, reaction components
 *   lgd_parts(t, y, p, M, F, A, c, g, f)    M q'' = F + A^T lam, A q'' + c = 0, and the velocity and
 *                                           position residuals g, f of the rows
 *   lgd_monitors(t, y, p, out), lgd_reactions(t, y, lam, p, out)
 * The augmented system is solved through the Schur complement S = A M^-1 A^T (module docstring
 * of `_codegen_dae`): lam = S^-1 (-c - 2 alpha g - beta^2 f - A M^-1 F), q'' = M^-1 (F + A^T lam).
 */

/* dy = (q', q''), lam = multipliers; stab = (alpha, beta).  Returns 0, 1 (M singular),
 * 2 (S singular: rows dependent here) or 3 (non-finite result). */
static int lgd_rhs(double t, const double *y, const double *p, const double *stab, double *dy, double *lam,
                   double *worst)
{
    double M[LGD_N * LGD_N], F[LGD_N], A[LGD_M * LGD_N], c[LGD_M], g[LGD_M], f[LGD_M];
    double X[LGD_M * LGD_N], S[LGD_M * LGD_M];
    lgd_parts(t, y, p, M, F, A, c, g, f);
    if (lg_chol_factor(M, LGD_N, worst)) return 1;
    for (int k = 0; k < LGD_M; ++k) {
        for (int i = 0; i < LGD_N; ++i) X[k * LGD_N + i] = A[k * LGD_N + i];
        lg_chol_solve(M, LGD_N, X + k * LGD_N);          /* row k of X = M^-1 A_k^T */
    }
    lg_chol_solve(M, LGD_N, F);                           /* F <- M^-1 F */
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
    if (lg_chol_factor(S, LGD_M, &unused)) return 2;
    lg_chol_solve(S, LGD_M, lam);
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
