/* lagrangian runtime: forward sensitivities, integrated with the state by DOP853.
 *
 * Appended, once per model and set of parameters, after the model's generated code and
 * integrators.c (whose lg_rhs, lg_mass_forces, lg_constants, lg_rms, lg_dop_stiff,
 * lg_pace_hopeless and the DOP853 tableau it uses), and after the generated
 *   LG_NV                          2n + the number of parameters differentiated
 *   lg_sens_jacobian(t, y, p, a, J) J (n x LG_NV, row-major) = d(F - M a)/d(y, p_sel) at a fixed
 *
 * The sensitivity S = dy/dx of the state y = (q, q') to a parameter or an initial value x
 * obeys the variational equations (Hairer, Norsett & Wanner, Solving ODEs I, Sec. I.14)
 *     dS/dt = (df/dy) S + df/dx,     f = (q', q''),   M q'' = F,
 * where, differentiating M q'' = F with q'' held, dq''/dx = M^{-1} (dF/dx - d(M a)/dx |_{a = q''}):
 * M is factorised once per evaluation, and each column costs one product with J and one solve.
 * S(t0) is 0 for a parameter and the unit vector e_i for the initial value y_i(t0).
 *
 * The augmented state z = (y, S_1, ..., S_ns) is integrated by the same Runge-Kutta steps as y.
 * `errors` (ctl[C_SENS_ERR]) chooses what the step-size control looks at:
 *   0  y alone: the steps are those of a plain run, so y is the plain run's bit for bit, and S is
 *      the exact derivative of that numerical solution along the same steps (Runge-Kutta methods
 *      commute with differentiation: "internal numerical differentiation", Bock 1981), which is
 *      what a Gauss-Newton fit needs to agree with its residuals;
 *   1  y and S together (CVODES's errconS): S also meets rtol/atol, at the price of more steps.
 *
 * Inputs measured at sample times (identification) are set into p by linear interpolation of a
 * table at every evaluation (lg_sens_set_inputs); the steps end on the table's times, where the
 * interpolant has a kink, so that each step integrates a smooth right-hand side.
 */

#define C_SENS_ERR C_PROJECTED   /* reused slot (21): 1 puts S in the error norm; read before the run */

typedef struct {
    int count;              /* input columns (0: none) */
    const int *index;       /* parameter index of each column */
    int rows;
    const double *times;    /* increasing, rows */
    const double *values;   /* rows x count */
    int cursor;
} lg_sens_table;

static void lg_sens_set_inputs(lg_sens_table *tab, double t, double *p)
{
    if (tab->count == 0) return;
    const double *tt = tab->times;
    const int last = tab->rows - 1;
    int i = tab->cursor;
    while (i > 0 && t < tt[i]) --i;
    while (i < last && t >= tt[i + 1]) ++i;
    tab->cursor = i;
    for (int c = 0; c < tab->count; ++c) {
        double v;
        if (i >= last || t <= tt[0]) v = tab->values[(long)(t <= tt[0] ? 0 : last) * tab->count + c];
        else {
            const double w = (t - tt[i]) / (tt[i + 1] - tt[i]);
            v = (1.0 - w) * tab->values[(long)i * tab->count + c] + w * tab->values[(long)(i + 1) * tab->count + c];
        }
        p[tab->index[c]] = v;
    }
    if (LG_NK > 0) lg_constants(p, p + LG_NP);
}

/* The next table time after t (a step must end there), or t_stop. */
static double lg_sens_break(const lg_sens_table *tab, double t, double t_stop)
{
    if (tab->count == 0) return t_stop;
    int i = tab->cursor;
    while (i > 0 && tab->times[i] > t) --i;
    while (i < tab->rows && tab->times[i] <= t) ++i;
    return (i < tab->rows && tab->times[i] < t_stop) ? tab->times[i] : t_stop;
}

/* Cholesky factor in place (lower triangle), with lg_cholesky_solve's pivot test. */
static int lg_sens_factor(double *M)
{
    const int n = LG_N;
    for (int j = 0; j < n; ++j) {
        double d = M[j * n + j];
        const double diag = fabs(d);
        for (int k = 0; k < j; ++k) d -= M[j * n + k] * M[j * n + k];
        if (!(d > 1e-13 * diag) || diag == 0.0) return LG_SINGULAR;
        d = sqrt(d);
        M[j * n + j] = d;
        for (int i = j + 1; i < n; ++i) {
            double s = M[i * n + j];
            for (int k = 0; k < j; ++k) s -= M[i * n + k] * M[j * n + k];
            M[i * n + j] = s / d;
        }
    }
    return LG_DONE;
}

static void lg_sens_solve(const double *L, double *b)
{
    const int n = LG_N;
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

/* z' for z = (y, S_1..S_ns); col[k] is the parameter of column k (its index among the LG_NV - 2n
 * differentiated ones), or -1 for an initial value. */
static int lg_sens_f(double t, const double *z, double *p, lg_sens_table *tab, int ns, const int *col,
                     double *dz, double *worst)
{
    lg_sens_set_inputs(tab, t, p);
    int status = lg_rhs(t, z, p, dz, worst);
    if (status || ns == 0) return status;
    double M[LG_N * LG_N], F[LG_N], J[LG_N * LG_NV];
    lg_mass_forces(t, z, p, M, F);
    status = lg_sens_factor(M);
    if (status) return status;
    lg_sens_jacobian(t, z, p, dz + LG_N, J);
    for (int k = 0; k < ns; ++k) {
        const double *S = z + (long)LG_NY * (k + 1);
        double *dS = dz + (long)LG_NY * (k + 1);
        double b[LG_N];
        for (int i = 0; i < LG_N; ++i) {
            const double *row = J + (long)i * LG_NV;
            double s = col[k] >= 0 ? row[LG_NY + col[k]] : 0.0;
            for (int j = 0; j < LG_NY; ++j) s += row[j] * S[j];
            b[i] = s;
        }
        lg_sens_solve(M, b);
        for (int i = 0; i < LG_N; ++i) {
            dS[i] = S[LG_N + i];
            dS[LG_N + i] = b[i];
            if (!isfinite(b[i])) return LG_NONFINITE;
        }
    }
    return LG_DONE;
}

static double lg_sens_rms(int m, const double *v, const double *scale)
{
    double s = 0.0;
    for (int j = 0; j < m; ++j) s += (v[j] / scale[j]) * (v[j] / scale[j]);
    return sqrt(s / m);
}

/* lg_dop853_run on z (no events), its arithmetic on y unchanged.  work: (LG_DOP_STAGES_EXT +
 * LG_DOP_POWER + 6) * nz doubles, p: LG_NP + LG_NK doubles (a working copy: inputs are set in it). */
int lg_sens_dop853(double *ctl, double *z, double *p, int ns, const int *col, const double *t_out, int n_out,
                   int *i_out, double *Z_out, double t_stop, int n_inputs, const int *input_index, int rows,
                   const double *input_times, const double *input_values, double *work)
{
    static const double A[LG_DOP_STAGES_EXT][LG_DOP_STAGES_EXT] = LG_DOP_A;
    static const double B[LG_DOP_STAGES] = LG_DOP_B;
    static const double C[LG_DOP_STAGES_EXT] = LG_DOP_C;
    static const double E3[LG_DOP_STAGES + 1] = LG_DOP_E3;
    static const double E5[LG_DOP_STAGES + 1] = LG_DOP_E5;
    static const double D[LG_DOP_POWER - 3][LG_DOP_STAGES_EXT] = LG_DOP_D;
    const volatile double *stop = ctl + C_STOP;
    const int nz = LG_NY * (1 + ns);
    const int ne = ctl[C_SENS_ERR] != 0.0 ? nz : LG_NY;   /* components in the error norm */
    lg_sens_table tab = {n_inputs, input_index, rows, input_times, input_values, 0};
    double *K[LG_DOP_STAGES_EXT], *Fd[LG_DOP_POWER];
    for (int s = 0; s < LG_DOP_STAGES_EXT; ++s) K[s] = work + (long)s * nz;
    for (int i = 0; i < LG_DOP_POWER; ++i) Fd[i] = work + (long)(LG_DOP_STAGES_EXT + i) * nz;
    double *y_new = work + (long)(LG_DOP_STAGES_EXT + LG_DOP_POWER) * nz;
    double *y_stage = y_new + nz, *scale = y_stage + nz, *err5 = scale + nz, *err3 = err5 + nz, *y_old = err3 + nz;
    double t = ctl[C_T], t_old = t, h_dense = 0.0;
    const double rtol = ctl[C_RTOL], atol = ctl[C_ATOL], max_step = ctl[C_MAXSTEP];
    const int fixed = ctl[C_FIXED] != 0.0;
    const double span_floor = 1e-14 * fabs(t_stop - t);
    int status;
    ctl[C_SENS_ERR] = 0.0;

    if (t >= t_stop) return LG_DONE;
    status = lg_sens_f(t, z, p, &tab, ns, col, K[0], &ctl[C_PIVOT]);
    ctl[C_NFEV] += 1;
    if (status) return status;
    while (*i_out < n_out && t_out[*i_out] <= t) {
        memcpy(Z_out + (long)(*i_out) * nz, z, nz * sizeof(double));
        ++*i_out;
    }

    double h_abs = ctl[C_H];
    if (h_abs <= 0.0) {   /* Hairer's starting step, on the components of the error norm */
        double d0, d1, d2, h0, h1;
        for (int j = 0; j < ne; ++j) scale[j] = atol + fabs(z[j]) * rtol;
        d0 = lg_sens_rms(ne, z, scale);
        d1 = lg_sens_rms(ne, K[0], scale);
        h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
        h0 = fmin(h0, t_stop - t);
        for (int j = 0; j < nz; ++j) y_stage[j] = z[j] + h0 * K[0][j];
        status = lg_sens_f(t + h0, y_stage, p, &tab, ns, col, K[1], &ctl[C_PIVOT]);
        ctl[C_NFEV] += 1;
        if (status) return status;
        for (int j = 0; j < ne; ++j) err5[j] = K[1][j] - K[0][j];
        d2 = lg_sens_rms(ne, err5, scale) / h0;
        h1 = (fmax(d1, d2) <= 1e-15) ? fmax(1e-6, h0 * 1e-3) : pow(0.01 / fmax(d1, d2), 1.0 / 9.0);
        h_abs = fmin(100 * h0, h1);
    }

    while (t < t_stop) {
        if (ctl[C_STEPS] >= ctl[C_MAXSTEPS] || lg_pace_hopeless(ctl, t, t_stop, fixed ? h_abs : 0.0)) {
            ctl[C_T] = t; ctl[C_H] = h_abs; return LG_MAXSTEPS;
        }
        if (lg_stop_requested(stop)) { ctl[C_T] = t; ctl[C_H] = h_abs; return LG_INTERRUPTED; }
        const double min_step = fmax(10 * fabs(nextafter(t, INFINITY) - t), span_floor);
        const double t_end = lg_sens_break(&tab, t, t_stop);
        if (h_abs > max_step) h_abs = max_step;
        if (!fixed && h_abs < min_step) h_abs = min_step;
        int rejected = 0, overflowed = 0;
        double h, t_new;
        for (;;) {
            if (!fixed && h_abs < min_step) { ctl[C_T] = t; ctl[C_H] = h_abs; return overflowed ? LG_NONFINITE : LG_UNDERFLOW; }
            t_new = t + h_abs;
            if (t_new > t_end) t_new = t_end;
            h = t_new - t;
            for (int s = 1; s < LG_DOP_STAGES; ++s) {
                for (int j = 0; j < nz; ++j) {
                    double acc = 0.0;
                    for (int r = 0; r < s; ++r) acc += A[s][r] * K[r][j];
                    y_stage[j] = z[j] + h * acc;
                }
                status = lg_sens_f(t + C[s] * h, y_stage, p, &tab, ns, col, K[s], &ctl[C_PIVOT]);
                ctl[C_NFEV] += 1;
                if (status) break;
            }
            if (!status) {
                for (int j = 0; j < nz; ++j) {
                    double acc = 0.0;
                    for (int r = 0; r < LG_DOP_STAGES; ++r) acc += B[r] * K[r][j];
                    y_new[j] = z[j] + h * acc;
                }
                status = lg_sens_f(t_new, y_new, p, &tab, ns, col, K[LG_DOP_STAGES], &ctl[C_PIVOT]);
                ctl[C_NFEV] += 1;
            }
            if (status == LG_NONFINITE && !fixed) {
                h_abs *= 0.2;
                rejected = overflowed = 1;
                ctl[C_REJECTED] += 1;
                continue;
            }
            if (status) { ctl[C_T] = t; ctl[C_H] = h_abs; return status; }
            overflowed = 0;
            if (fixed) break;
            for (int j = 0; j < ne; ++j) {
                scale[j] = atol + fmax(fabs(z[j]), fabs(y_new[j])) * rtol;
                double a5 = 0.0, a3 = 0.0;
                for (int r = 0; r <= LG_DOP_STAGES; ++r) { a5 += E5[r] * K[r][j]; a3 += E3[r] * K[r][j]; }
                err5[j] = a5 / scale[j];
                err3[j] = a3 / scale[j];
            }
            double n5 = 0.0, n3 = 0.0, error_norm;
            for (int j = 0; j < ne; ++j) { n5 += err5[j] * err5[j]; n3 += err3[j] * err3[j]; }
            error_norm = (n5 == 0.0 && n3 == 0.0) ? 0.0 : fabs(h) * n5 / sqrt((n5 + 0.01 * n3) * ne);
            if (error_norm < 1.0) {
                double factor = (error_norm == 0.0) ? 10.0 : fmin(10.0, 0.9 * pow(error_norm, -1.0 / 8.0));
                if (rejected) factor = fmin(1.0, factor);
                h_abs *= factor;
                break;
            }
            h_abs *= fmax(0.2, 0.9 * pow(error_norm, -1.0 / 8.0));
            rejected = 1;
            ctl[C_REJECTED] += 1;
        }
        ctl[C_STEPS] += 1;
        if (!fixed && lg_dop_stiff(ctl, h, K[LG_DOP_STAGES], K[LG_DOP_STAGES - 1], y_new, y_stage)) {
            ctl[C_T] = t; ctl[C_H] = h_abs; return LG_STIFF;
        }

        if (*i_out < n_out && t_out[*i_out] <= t_new) {
            for (int s = LG_DOP_STAGES + 1; s < LG_DOP_STAGES_EXT; ++s) {
                for (int j = 0; j < nz; ++j) {
                    double acc = 0.0;
                    for (int r = 0; r < s; ++r) acc += A[s][r] * K[r][j];
                    y_stage[j] = z[j] + h * acc;
                }
                status = lg_sens_f(t + C[s] * h, y_stage, p, &tab, ns, col, K[s], &ctl[C_PIVOT]);
                ctl[C_NFEV] += 1;
                if (status) { ctl[C_T] = t; ctl[C_H] = h_abs; return status; }
            }
            t_old = t;
            h_dense = h;
            for (int j = 0; j < nz; ++j) {
                const double dy = y_new[j] - z[j];
                y_old[j] = z[j];
                Fd[0][j] = dy;
                Fd[1][j] = h * K[0][j] - dy;
                Fd[2][j] = 2 * dy - h * (K[LG_DOP_STAGES][j] + K[0][j]);
                for (int i = 0; i < LG_DOP_POWER - 3; ++i) {
                    double acc = 0.0;
                    for (int r = 0; r < LG_DOP_STAGES_EXT; ++r) acc += D[i][r] * K[r][j];
                    Fd[3 + i][j] = h * acc;
                }
            }
            while (*i_out < n_out && t_out[*i_out] <= t_new) {
                double *row = Z_out + (long)(*i_out) * nz;
                if (t_out[*i_out] == t_new) memcpy(row, y_new, nz * sizeof(double));
                else {   /* SciPy's Dop853DenseOutput, as lg_dop_interp */
                    const double x = (t_out[*i_out] - t_old) / h_dense;
                    for (int j = 0; j < nz; ++j) {
                        double s = 0.0;
                        for (int i = 0; i < LG_DOP_POWER; ++i) {
                            s += Fd[LG_DOP_POWER - 1 - i][j];
                            s *= (i % 2 == 0) ? x : 1.0 - x;
                        }
                        row[j] = y_old[j] + s;
                    }
                }
                ++*i_out;
            }
        }
        t = t_new;
        memcpy(z, y_new, nz * sizeof(double));
        memcpy(K[0], K[LG_DOP_STAGES], nz * sizeof(double));
        ctl[C_T] = t;
        ctl[C_H] = h_abs;
    }
    return LG_DONE;
}

/* Jacobian of F - M a at many points (the identification's consistency checks and tests). */
void lg_sens_eval_jacobian(int count, const double *t, const double *Y, const double *A_, const double *p,
                           double *J)
{
    for (int k = 0; k < count; ++k)
        lg_sens_jacobian(t[k], Y + (long)k * LG_NY, p, A_ + (long)k * LG_N, J + (long)k * LG_N * LG_NV);
}

int lg_sens_dimensions(int *out)
{
    out[0] = LG_N;
    out[1] = LG_NV;
    return 0;
}
