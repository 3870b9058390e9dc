/* lagrangian runtime: the Cholesky factorisation A = L L^T and its solve, for any n.
 *
 * Expects <math.h> before it.  Copied whole into the code of a model with complementary
 * constraints (before dae.c, which factors M and the Schur complement S = A M^-1 A^T with it)
 * and into its C export (`lagrangian export --to c`): one factorisation for both.
 * lg_chol_factor overwrites the lower triangle of the row-major n x n matrix with L and returns
 * 0, or 1 where a pivot collapses below 1e-13 of its diagonal entry (the matrix is not positive
 * definite there: Golub & Van Loan, Matrix Computations, Sec. 4.2); *worst is lowered to the
 * smallest pivot ratio seen.  lg_chol_solve solves L L^T x = b in place.
 */

static int lg_chol_factor(double *M, int n, double *worst)
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

static void lg_chol_solve(const double *L, int n, double *b)
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
