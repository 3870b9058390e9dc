/* lagrangian runtime: forward sensitivities, integrated with the state by DOP853.
 *
 * Appended, once per model and set of parameters, after the model's generated code,
 * integrators.c (whose lg_rhs, lg_mass_forces, lg_constants, lg_dop_stiff, lg_pace_hopeless,
 * DOP853's step-size control and tableau it uses), cholesky.c (lg_chol_factor, lg_chol_solve:
 * M factorised once per evaluation) and the generated
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
    double pivot = 1.0;   /* lg_rhs has reported M's conditioning (or the articulated-body pivots') */
    if (lg_chol_factor(M, LG_N, &pivot)) return LG_SINGULAR;
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
        lg_chol_solve(M, LG_N, b);
        for (int i = 0; i < LG_N; ++i) {
            dS[i] = S[LG_N + i];
            dS[LG_N + i] = b[i];
            if (!isfinite(b[i])) return LG_NONFINITE;
        }
    }
    return LG_DONE;
}

/* lg_dop853_run on z (no events), its arithmetic on y unchanged.  work: (LG_DOP_STAGES_EXT +
 * LG_DOP_POWER + 4) * nz doubles, p: LG_NP + LG_NK doubles (a working copy: inputs are set in it). */
int lg_sens_dop853(double *ctl, double *z, double *p, int ns, const int *col, const double *t_out, int n_out,
                   int *i_out, double *Z_out, double t_stop, int n_inputs, const int *input_index, int rows,
                   const double *input_times, const double *input_values, double *work)
{
    static const double A[LG_DOP_STAGES_EXT][LG_DOP_STAGES_EXT] = LG_DOP_A;
    static const double B[LG_DOP_STAGES] = LG_DOP_B;
    static const double C[LG_DOP_STAGES_EXT] = LG_DOP_C;
    static const double D[LG_DOP_POWER - 3][LG_DOP_STAGES_EXT] = LG_DOP_D;
    const volatile double *stop = ctl + C_STOP;
    const int nz = LG_NY * (1 + ns);
    const int ne = ctl[C_SENS_ERR] != 0.0 ? nz : LG_NY;   /* components in the error norm */
    lg_sens_table tab = {n_inputs, input_index, rows, input_times, input_values, 0};
    double *K[LG_DOP_STAGES_EXT], *Fd[LG_DOP_POWER];
    for (int s = 0; s < LG_DOP_STAGES_EXT; ++s) K[s] = work + (long)s * nz;
    for (int i = 0; i < LG_DOP_POWER; ++i) Fd[i] = work + (long)(LG_DOP_STAGES_EXT + i) * nz;
    double *y_new = work + (long)(LG_DOP_STAGES_EXT + LG_DOP_POWER) * nz;
    double *y_stage = y_new + nz, *scale = y_stage + nz, *y_old = scale + nz;
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
        double d1;
        const double h0 = lg_dop_start_trial(ne, nz, z, K[0], rtol, atol, t_stop - t, scale, y_stage, &d1);
        status = lg_sens_f(t + h0, y_stage, p, &tab, ns, col, K[1], &ctl[C_PIVOT]);
        ctl[C_NFEV] += 1;
        if (status) return status;
        h_abs = lg_dop_start_step(ne, h0, d1, K[0], K[1], scale);
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
            if (lg_dop_accept(lg_dop_error_norm(ne, h, z, y_new, K, rtol, atol), &rejected, &h_abs, ctl)) break;
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
