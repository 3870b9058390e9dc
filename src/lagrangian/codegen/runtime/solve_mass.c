/* lagrangian runtime: M x = F solved by Cholesky, for the model's n coordinates.
 *
 * Expects LG_N (n) and <math.h> before it.  Copied whole after the model's functions in the
 * compiled simulation (before integrators.c, whose lg_rhs and Gauss-Legendre steps call it)
 * and in the C export (`lagrangian export --to c`, which defines LG_N as its <NAME>_N): one
 * solve for both.  Returns 0, or 1 (LG_SINGULAR in integrators.c) where M is not positive
 * definite (Golub & Van Loan, Matrix Computations, Sec. 4.2).
 */

/* Solve M x = F in place (F becomes x) by Cholesky: M is symmetric positive definite
 * wherever the coordinates are regular, and a pivot that collapses relative to its
 * diagonal entry is exactly how a singular configuration (e.g. theta = 0 in Euler
 * angles) shows itself. */
static int lg_cholesky_solve(double *M, double *F, double *worst)
{
    const int n = LG_N;
    double inv[LG_N]; /* 1/L_jj: one division per column, the rest multiplications (divisions
                         are latency-bound and made half the solve's time for n = 10) */
    for (int j = 0; j < n; ++j) {
        double d = M[j * n + j];
        const double diag = fabs(d);
        for (int k = 0; k < j; ++k) d -= M[j * n + k] * M[j * n + k];
        if (!(d > 1e-13 * diag) || diag == 0.0) return 1;  /* LG_SINGULAR */
        if (d / diag < *worst) *worst = d / diag;
        d = sqrt(d);
        M[j * n + j] = d;
        const double r = 1.0 / d;
        inv[j] = r;
        for (int i = j + 1; i < n; ++i) {
            double s = M[i * n + j];
            for (int k = 0; k < j; ++k) s -= M[i * n + k] * M[j * n + k];
            M[i * n + j] = s * r;
        }
    }
    for (int i = 0; i < n; ++i) {
        double s = F[i];
        for (int k = 0; k < i; ++k) s -= M[i * n + k] * F[k];
        F[i] = s * inv[i];
    }
    for (int i = n - 1; i >= 0; --i) {
        double s = F[i];
        for (int k = i + 1; k < n; ++k) s -= M[k * n + i] * F[k];
        F[i] = s * inv[i];
    }
    return 0;  /* LG_DONE */
}
