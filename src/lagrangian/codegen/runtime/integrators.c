/* lagrangian runtime: the model-independent half of a compiled system.
 *
 * This file is copied whole, once per model, after the generated model code and solve_mass.c
 * (lg_cholesky_solve), the model code defining
 *   LG_N (n coordinates), LG_NM (monitors), LG_NE (event functions), and
 *   lg_mass_forces(t, y, p, M, F)      M (n x n, row-major) and F of  M q'' = F
 *   lg_monitors(t, y, p, out)          first integrals, T, U
 *   lg_events(t, y, p, g)              event functions g_k(t, y)
 *   lg_hamilton_mass(t, y, p, M, b)    M and b = dT/dq' at q' = 0 (only q is read from y)
 *   lg_hamilton_force(t, y, p, g)      g = dT/dq - dU/dq + Q(nc)
 * with y = (q_1..q_n, q'_1..q'_n) and p the parameter values.  A model with free bodies
 * (LG_FREE, `codegen/_free_codegen.py`) defines instead LG_NY, its own state (positions with unit
 * quaternions, velocities, and a record of the quaternions' drift), lg_free_rhs and
 * lg_free_project (LG_PROJECT: the quaternions put back on |e| = 1 after each accepted
 * step); it has no Hamilton form, so no Gauss-Legendre method and no ensembles.  Nothing here calls
 * back into Python: a whole integration runs in C, which is what makes a 10^4-step run
 * cost milliseconds rather than the ~100 ms that Python's per-call overhead would add.
 *
 * Integrators:
 *   lg_dop853  Dormand & Prince's explicit Runge-Kutta 8(5,3) with step-size control and
 *              the 7th-order dense output (Hairer, Norsett & Wanner, Solving ODEs I,
 *              Sec. II.5 and II.6), transcribed from SciPy's DOP853 (same coefficients,
 *              emitted from scipy.integrate._ivp.dop853_coefficients, same error norm
 *              and step-size rule), so the two can be checked against each other.
 *   lg_gauss   the 2-stage Gauss-Legendre collocation method (order 4) applied to
 *              Hamilton's equations in (q, p), p = dT/dq': symplectic, so the energy of a
 *              conservative system oscillates without drifting on long runs
 *              (Hairer, Lubich & Wanner, Geometric Numerical Integration, Sec. II.1, VI.4).
 *
 * Status codes (the Python side turns them into messages):
 *   0 reached t_stop   1 mass matrix singular   2 non-finite state   3 step size underflow
 *   4 terminal event   5 too many steps         6 implicit stage did not converge
 *   7 interrupted      8 stiff (dop853's stiffness test, see lg_dop_stiff)
 */
#include <math.h>
#include <string.h>

#ifndef LG_NY
#define LG_NY (2 * LG_N)
#endif
/* An inputs' law (`numerics/_input_code.py`) defines its block of p (LG_NX numbers after the constants) and
 * the times where its tables jump (LG_NBREAK of them, at law[LG_BREAKS]); none by default. */
#ifndef LG_NX
#define LG_NX 0
#endif
#ifndef LG_NBREAK
#define LG_NBREAK 0
#endif

enum { LG_DONE = 0, LG_SINGULAR = 1, LG_NONFINITE = 2, LG_UNDERFLOW = 3, LG_EVENT = 4,
       LG_MAXSTEPS = 5, LG_NOCONVERGE = 6, LG_INTERRUPTED = 7, LG_STIFF = 8 };

/* Control block shared with Python (doubles, so one array carries it):
 * [0] t  [1] h (0: choose)  [2] rtol  [3] atol  [4] max_step  [5] nfev  [6] accepted steps
 * [7] rejected steps  [8] fixed step (0: adaptive)  [9] max steps  [10] events found
 * [11] event capacity  [12] worst relative pivot seen (Cholesky)
 * [13] stop request: set non-zero by another thread (Ctrl-C); the run returns LG_INTERRUPTED
 *      at its next step, so it is read through a volatile pointer on every step.
 * [14] stiffness test every this many accepted steps (dop853's NSTIFF; 0: never)
 * [15] [16] [17] the test's state: consecutive stiff steps (IASTI), non-stiff ones (NONSTI), last h|lambda|
 * [18] [19] [20] the pace check's state (lg_pace_hopeless): t at its last window's start, windows in a
 *      row that projected past max steps, the step count that ends the window
 * [21] the steps the run would have needed, when the pace check stopped it (0 otherwise) */
enum { C_T, C_H, C_RTOL, C_ATOL, C_MAXSTEP, C_NFEV, C_STEPS, C_REJECTED, C_FIXED, C_MAXSTEPS, C_NEV,
       C_EVCAP, C_PIVOT, C_STOP, C_NSTIFF, C_IASTI, C_NONSTI, C_HLAMB, C_PACE_T, C_PACE_OVER, C_PACE_END,
       C_PROJECTED, C_SIZE };

/* Accepted steps per window of the pace check. */
#define LG_PACE_WINDOW 1048576.0

/* The pace check: is a run that cannot reach t_stop within max steps already plain?
 *
 * A run limited by accuracy on a motion far faster than its span (an undamped spring of
 * 1e17 N/m over 0.3 s needs some 4e8 steps) is not stiff, so the stiffness test lets it go on;
 * it used to crawl for minutes until max steps stopped it with the same error this gives
 * at once.  At the end of every window of LG_PACE_WINDOW accepted steps, the steps still
 * needed at the window's mean step are projected; two windows in a row past max steps stop
 * the run (a transient's small steps, which later grow, rarely fill two windows).  A fixed
 * step knows its count from the start.  Returns 1 when hopeless, the projection in ctl. */
static int lg_pace_hopeless(double *ctl, double t, double t_stop, double fixed_h)
{
    const double steps = ctl[C_STEPS];
    if (steps < ctl[C_PACE_END]) return 0;   /* one comparison on every other step */
    if (steps == 0.0) {                       /* the first step: the first window starts */
        ctl[C_PACE_T] = t;
        ctl[C_PACE_END] = LG_PACE_WINDOW;
        if (fixed_h > 0.0) {
            const double needed = ceil((t_stop - t) / fixed_h - 1e-9);
            ctl[C_PACE_END] = INFINITY;
            if (needed > ctl[C_MAXSTEPS]) { ctl[C_PROJECTED] = needed; return 1; }
        }
        return 0;
    }
    ctl[C_PACE_END] = steps + LG_PACE_WINDOW;
    if (t == ctl[C_PACE_T]) return 0;
    const double needed = steps + (t_stop - t) / ((t - ctl[C_PACE_T]) / LG_PACE_WINDOW);
    ctl[C_PACE_T] = t;
    ctl[C_PACE_OVER] = needed > ctl[C_MAXSTEPS] ? ctl[C_PACE_OVER] + 1 : 0.0;
    if (ctl[C_PACE_OVER] < 2) return 0;
    ctl[C_PROJECTED] = needed;
    return 1;
}

static int lg_stop_requested(const volatile double *stop)
{
    return *stop != 0.0;
}

/* y' = (q', q'') with q'' from M q'' = F, never from a symbolic inverse.  A kinematic tree
 * whose coordinates each drive one joint (LG_ABA) has lg_aba instead: the articulated-body
 * algorithm, O(n), its pivots D_j checked against M_jj as the Cholesky pivots are. */
static int lg_rhs(double t, const double *y, const double *p, double *dy, double *worst)
{
#if defined(LG_FREE)
    return lg_free_rhs(t, y, p, dy, worst);
#else
#ifdef LG_ABA
    double F[LG_N], piv[2 * LG_N];
    lg_aba(t, y, p, F, piv);
    for (int j = 0; j < LG_N; ++j) {
        const double d = piv[2 * j], diag = fabs(piv[2 * j + 1]);
        if (!(d > 1e-13 * diag) || diag == 0.0) return LG_SINGULAR;
        if (d / diag < *worst) *worst = d / diag;
    }
#else
    double M[LG_N * LG_N], F[LG_N];
    lg_mass_forces(t, y, p, M, F);
    int status = lg_cholesky_solve(M, F, worst);
    if (status) return status;
#endif
    for (int i = 0; i < LG_N; ++i) {
        dy[i] = y[LG_N + i];
        dy[LG_N + i] = F[i];
        if (!isfinite(F[i]) || !isfinite(dy[i])) return LG_NONFINITE;
    }
    return LG_DONE;
#endif
}

/* ---- batched evaluation, for benchmarks, monitors and vectorised use ---------------- */

int lg_eval_rhs(int count, const double *t, const double *Y, const double *p, double *dY)
{
    double worst = 1.0;
    for (int k = 0; k < count; ++k) {
        int status = lg_rhs(t[k], Y + (long)k * LG_NY, p, dY + (long)k * LG_NY, &worst);
        if (status) return status;
    }
    return LG_DONE;
}

void lg_eval_mass_forces(int count, const double *t, const double *Y, const double *p, double *M, double *F)
{
    for (int k = 0; k < count; ++k)
        lg_mass_forces(t[k], Y + (long)k * LG_NY, p, M + (long)k * LG_N * LG_N, F + (long)k * LG_N);
}

void lg_eval_monitors(int count, const double *t, const double *Y, const double *p, double *out)
{
    for (int k = 0; k < count; ++k)
        lg_monitors(t[k], Y + (long)k * LG_NY, p, out + (long)k * (LG_NM > 0 ? LG_NM : 1));
}

void lg_eval_events(int count, const double *t, const double *Y, const double *p, double *out)
{
    for (int k = 0; k < count; ++k)
        lg_events(t[k], Y + (long)k * LG_NY, p, out + (long)k * (LG_NE > 0 ? LG_NE : 1));
}

int lg_dimensions(int *out)
{
    out[0] = LG_N;
    out[1] = LG_NM;
    out[2] = LG_NE;
    return 0;
}

/* ---- event location, shared by both integrators -------------------------------------
 * Between two accepted steps the solution is a known polynomial (dense output); an event
 * g_k = 0 is a sign change of g_k along it, located by the Illinois variant of regula
 * falsi to 4 ulp of t. */
typedef void (*lg_interp_fn)(const void *ctx, double t, double *y);

static double lg_locate(const void *ctx, lg_interp_fn interp, const double *p, int k,
                        double ta, double ga, double tb, double gb, double *y)
{
    double g[LG_NE > 0 ? LG_NE : 1];
    int side = 0;
    for (int it = 0; it < 200 && fabs(tb - ta) > 4e-16 * fmax(fabs(ta), fabs(tb)) + 1e-300; ++it) {
        double tm = (ta * gb - tb * ga) / (gb - ga);
        if (!(tm > fmin(ta, tb) && tm < fmax(ta, tb))) tm = 0.5 * (ta + tb);
        interp(ctx, tm, y);
        lg_events(tm, y, p, g);
        if (g[k] == 0.0) { ta = tb = tm; break; }
        if ((g[k] > 0) == (gb > 0)) {
            tb = tm; gb = g[k];
            if (side == -1) ga *= 0.5;
            side = -1;
        } else {
            ta = tm; ga = g[k];
            if (side == 1) gb *= 0.5;
            side = 1;
        }
    }
    const double tr = (fabs(ga) < fabs(gb)) ? ta : tb;
    interp(ctx, tr, y);
    return tr;
}

/* After a step from (t0, g0) to (t1, g1): record events; return 1 when a terminal one fired
 * (then ctl[C_T] and y are moved back to it). ev_dir: +1 rising only, -1 falling, 0 both.
 * The crossings of one step are recorded in time order, and none past the first terminal
 * one: the run ends there, so a later crossing in the same step never happened. */
static int lg_check_events(const void *ctx, lg_interp_fn interp, const double *p, double *ctl,
                           const int *ev_dir, const int *ev_terminal, double *ev_out,
                           double t0, const double *g0, double t1, const double *g1, double *y_new)
{
    int fired_terminal = 0;
    double t_first = t1;
    int found = 0;
    int which[LG_NE > 0 ? LG_NE : 1];
    double when[LG_NE > 0 ? LG_NE : 1];
    double where[(LG_NE > 0 ? LG_NE : 1) * LG_NY];
    for (int k = 0; k < LG_NE; ++k) {
        const int up = g0[k] < 0 && g1[k] >= 0, down = g0[k] > 0 && g1[k] <= 0;
        if (!((up && ev_dir[k] >= 0) || (down && ev_dir[k] <= 0))) continue;
        double *y_k = where + (long)found * LG_NY;
        double te = lg_locate(ctx, interp, p, k, t0, g0[k], t1, g1[k], y_k);
        which[found] = k;
        when[found] = te;
        ++found;
        if (ev_terminal[k] && te <= t_first) {
            fired_terminal = 1;
            t_first = te;
            memcpy(y_new, y_k, LG_NY * sizeof(double));
        }
    }
    for (int done = 0; done < found; ++done) {  /* selection by time: a handful of events */
        int next = -1;
        for (int j = 0; j < found; ++j)
            if (which[j] >= 0 && (next < 0 || when[j] < when[next])) next = j;
        if (fired_terminal && when[next] > t_first) break;
        if (ctl[C_EVCAP] < 0) {
            /* first-occurrence mode (ensembles): row k of ev_out is event k's count and the time
             * and state of its first occurrence, so memory does not grow with the events. */
            double *row = ev_out + (long)which[next] * (2 + LG_NY);
            if (row[0] == 0.0) {
                row[1] = when[next];
                memcpy(row + 2, where + (long)next * LG_NY, LG_NY * sizeof(double));
            }
            row[0] += 1.0;
            ctl[C_NEV] += 1;
            which[next] = -1;
            continue;
        }
        int slot = (int)ctl[C_NEV];
        if (slot < (int)ctl[C_EVCAP]) {
            double *row = ev_out + (long)slot * (2 + LG_NY);
            row[0] = which[next];
            row[1] = when[next];
            memcpy(row + 2, where + (long)next * LG_NY, LG_NY * sizeof(double));
            ctl[C_NEV] = slot + 1;
        }
        which[next] = -1;
    }
    if (fired_terminal) ctl[C_T] = t_first;
    return fired_terminal;
}

/* ---- DOP853 -------------------------------------------------------------------------- */

typedef struct {
    double t_old, h;
    double y_old[LG_NY];
    double F[LG_DOP_POWER][LG_NY];
} lg_dop_dense;

/* y(t) on the last step: SciPy's Dop853DenseOutput, a Horner scheme in x and 1 - x. */
static void lg_dop_interp(const void *ctx, double t, double *y)
{
    const lg_dop_dense *d = (const lg_dop_dense *)ctx;
    const double x = (t - d->t_old) / d->h;
    for (int j = 0; j < LG_NY; ++j) {
        double s = 0.0;
        for (int i = 0; i < LG_DOP_POWER; ++i) {
            s += d->F[LG_DOP_POWER - 1 - i][j];
            s *= (i % 2 == 0) ? x : 1.0 - x;
        }
        y[j] = d->y_old[j] + s;
    }
}

/* Hairer's stiffness detection, as in dop853.f (Hairer, Norsett & Wanner, Solving ODEs I,
 * Sec. IV.2; the IASTI/NONSTI/HLAMB block after an accepted step).  The last stage (c = 1,
 * state y12, slope f12) and the new state y1 with its slope f1 give
 *     h|lambda| ~ h ||f1 - f12|| / ||y1 - y12||,
 * an estimate of h times the dominant eigenvalue of the Jacobian.  Above 6.1 (the edge of
 * DOP853's stability domain) the step is limited by stability, not accuracy.  Tested every
 * NSTIFF accepted steps, then at every step while suspected: 15 such steps in a row declare
 * the problem stiff; 6 non-stiff ones clear the suspicion.  Returns 1 when stiff. */
static int lg_dop_stiff(double *ctl, double h, const double *f1, const double *f12, const double *y1,
                        const double *y12)
{
    const double nstiff = ctl[C_NSTIFF];
    if (!(nstiff > 0) || (fmod(ctl[C_STEPS], nstiff) != 0.0 && !(ctl[C_IASTI] > 0))) return 0;
    double num = 0.0, den = 0.0;
    for (int j = 0; j < LG_NY; ++j) {
        num += (f1[j] - f12[j]) * (f1[j] - f12[j]);
        den += (y1[j] - y12[j]) * (y1[j] - y12[j]);
    }
    if (den > 0.0) ctl[C_HLAMB] = fabs(h) * sqrt(num / den);
    if (ctl[C_HLAMB] > 6.1) {
        ctl[C_NONSTI] = 0;
        ctl[C_IASTI] += 1;
        return ctl[C_IASTI] >= 15;
    }
    ctl[C_NONSTI] += 1;
    if (ctl[C_NONSTI] == 6) ctl[C_IASTI] = 0;
    return 0;
}

/* DOP853's step-size control, shared by lg_dop853_run and the sensitivities' lg_sens_dop853
 * (sensitivity.c), which look at the first m components of their state (m = LG_NY, or the
 * state with its sensitivities); SciPy's DOP853 and select_initial_step, step for step. */

/* The root mean square of v / scale over m components. */
static double lg_rms(int m, const double *v, const double *scale)
{
    double s = 0.0;
    for (int j = 0; j < m; ++j) s += (v[j] / scale[j]) * (v[j] / scale[j]);
    return sqrt(s / m);
}

/* Hairer's starting step (Solving ODEs I, Sec. II.4), first half: h0 from |y| and |f0| with the
 * weights scale = atol + |y| rtol, at most span; y1 = y + h0 f0 (all n components) is where the
 * caller evaluates f1, and *d1 = |f0| goes on to lg_dop_start_step. */
static double lg_dop_start_trial(int m, int n, const double *y, const double *f0, double rtol, double atol,
                                 double span, double *scale, double *y1, double *d1)
{
    for (int j = 0; j < m; ++j) scale[j] = atol + fabs(y[j]) * rtol;
    const double d0 = lg_rms(m, y, scale);
    *d1 = lg_rms(m, f0, scale);
    double h0 = (d0 < 1e-5 || *d1 < 1e-5) ? 1e-6 : 0.01 * d0 / *d1;
    h0 = fmin(h0, span);
    for (int j = 0; j < n; ++j) y1[j] = y[j] + h0 * f0[j];
    return h0;
}

/* The second half: the first step from |f1 - f0| / h0, an estimate of |y''|, for an error of
 * order 8 (the exponent 1/9). */
static double lg_dop_start_step(int m, double h0, double d1, const double *f0, const double *f1,
                                const double *scale)
{
    double s = 0.0;
    for (int j = 0; j < m; ++j) {
        const double d = (f1[j] - f0[j]) / scale[j];
        s += d * d;
    }
    const double d2 = sqrt(s / m) / h0;
    const double h1 = (fmax(d1, d2) <= 1e-15) ? fmax(1e-6, h0 * 1e-3) : pow(0.01 / fmax(d1, d2), 1.0 / 9.0);
    return fmin(100 * h0, h1);
}

/* The error norm of a trial step of size h from y to y_new, over m components: the 5th- and
 * 3rd-order estimates err5 = E5.K, err3 = E3.K, each over atol + max(|y|, |y_new|) rtol, combined
 * as |h| |err5|^2 / sqrt((|err5|^2 + 0.01 |err3|^2) m) (Hairer's dop853.f, SciPy's
 * DOP853._estimate_error_norm).  K[r] is the slope of stage r, K[LG_DOP_STAGES] the one at y_new. */
static double lg_dop_error_norm(int m, double h, const double *y, const double *y_new, double *const *K,
                                double rtol, double atol)
{
    static const double E3[LG_DOP_STAGES + 1] = LG_DOP_E3;
    static const double E5[LG_DOP_STAGES + 1] = LG_DOP_E5;
    double n5 = 0.0, n3 = 0.0;
    for (int j = 0; j < m; ++j) {
        const double scale = atol + fmax(fabs(y[j]), fabs(y_new[j])) * rtol;
        double a5 = 0.0, a3 = 0.0;
        for (int r = 0; r <= LG_DOP_STAGES; ++r) { a5 += E5[r] * K[r][j]; a3 += E3[r] * K[r][j]; }
        const double err5 = a5 / scale, err3 = a3 / scale;
        n5 += err5 * err5;
        n3 += err3 * err3;
    }
    return (n5 == 0.0 && n3 == 0.0) ? 0.0 : fabs(h) * n5 / sqrt((n5 + 0.01 * n3) * m);
}

/* Accept the trial step (error_norm < 1: 1 returned) or reject it (0), and scale *h_abs for the
 * next try by 0.9 error_norm^(-1/8), within [0.2, 10], and not up after a rejection of the same
 * step; a rejection is counted in ctl and remembered in *rejected. */
static int lg_dop_accept(double error_norm, int *rejected, double *h_abs, double *ctl)
{
    if (error_norm < 1.0) {
        double factor = (error_norm == 0.0) ? 10.0 : fmin(10.0, 0.9 * pow(error_norm, -1.0 / 8.0));
        if (*rejected) factor = fmin(1.0, factor);
        *h_abs *= factor;
        return 1;
    }
    *h_abs *= fmax(0.2, 0.9 * pow(error_norm, -1.0 / 8.0));
    *rejected = 1;
    ctl[C_REJECTED] += 1;
    return 0;
}

/* Integrate from ctl[C_T] to t_stop, writing y at each t_out[*i_out..] <= t_stop into
 * Y_out.  Re-entrant: Python calls it chunk by chunk (for progress reports) with the
 * same ctl, y and i_out. */
static int lg_dop853_run(double *ctl, const volatile double *stop, double *y, const double *p,
                         const double *t_out, int n_out, int *i_out, double *Y_out, double t_stop,
                         const int *ev_dir, const int *ev_terminal, double *ev_out)
{
    static const double A[LG_DOP_STAGES_EXT][LG_DOP_STAGES_EXT] = LG_DOP_A;
    static const double B[LG_DOP_STAGES] = LG_DOP_B;
    static const double C[LG_DOP_STAGES_EXT] = LG_DOP_C;
    static const double D[LG_DOP_POWER - 3][LG_DOP_STAGES_EXT] = LG_DOP_D;

    double K[LG_DOP_STAGES_EXT][LG_NY];
    double *Ks[LG_DOP_STAGES + 1];   /* the slopes the error norm reads */
    for (int s = 0; s <= LG_DOP_STAGES; ++s) Ks[s] = K[s];
    double y_new[LG_NY], y_stage[LG_NY], scale[LG_NY];
    double g0[LG_NE > 0 ? LG_NE : 1], g1[LG_NE > 0 ? LG_NE : 1];
    lg_dop_dense dense;
    double t = ctl[C_T];
    const double rtol = ctl[C_RTOL], atol = ctl[C_ATOL], max_step = ctl[C_MAXSTEP];
    const int fixed = ctl[C_FIXED] != 0.0;
    /* Steps shorter than 1e-14 of the span can never finish it (10^14 steps): an underflow, as is a
     * step below the resolution of t.  Near t = 0 that resolution alone is a denormal, and a damping
     * of 1e308 made steps of 1e-309 s crawl until max_steps (found by tools/fuzz.py --format urdf). */
    const double span_floor = 1e-14 * fabs(t_stop - t);
    int status;

    if (t >= t_stop) return LG_DONE;
    status = lg_rhs(t, y, p, K[0], &ctl[C_PIVOT]);
    ctl[C_NFEV] += 1;
    if (status) return status;
    if (LG_NE > 0) lg_events(t, y, p, g0);
    while (*i_out < n_out && t_out[*i_out] <= t) {   /* outputs at the start time */
        memcpy(Y_out + (long)(*i_out) * LG_NY, y, sizeof y_new);
        ++*i_out;
    }

    double h_abs = ctl[C_H];
    if (h_abs <= 0.0) {   /* Hairer's starting step, as in SciPy's select_initial_step */
        double d1;
        const double h0 = lg_dop_start_trial(LG_NY, LG_NY, y, K[0], rtol, atol, t_stop - t, scale, y_stage, &d1);
        status = lg_rhs(t + h0, y_stage, p, K[1], &ctl[C_PIVOT]);
        ctl[C_NFEV] += 1;
        if (status) return status;
        h_abs = lg_dop_start_step(LG_NY, h0, d1, K[0], K[1], scale);
    }

    while (t < t_stop) {
        if (ctl[C_STEPS] >= ctl[C_MAXSTEPS] || lg_pace_hopeless(ctl, t, t_stop, fixed ? h_abs : 0.0)) {
            ctl[C_T] = t; ctl[C_H] = h_abs; return LG_MAXSTEPS;
        }
        if (lg_stop_requested(stop)) { ctl[C_T] = t; ctl[C_H] = h_abs; return LG_INTERRUPTED; }
        const double min_step = fmax(10 * fabs(nextafter(t, INFINITY) - t), span_floor);
        if (h_abs > max_step) h_abs = max_step;
        if (!fixed && h_abs < min_step) h_abs = min_step;
        int rejected = 0, overflowed = 0;
        double h, t_new;
        for (;;) {
            /* a step that only ever overflowed is a blow-up, reported as one */
            if (!fixed && h_abs < min_step) { ctl[C_T] = t; ctl[C_H] = h_abs; return overflowed ? LG_NONFINITE : LG_UNDERFLOW; }
            t_new = t + h_abs;
            if (t_new > t_stop) t_new = t_stop;
            h = t_new - t;
            for (int s = 1; s < LG_DOP_STAGES; ++s) {
                for (int j = 0; j < LG_NY; ++j) {
                    double acc = 0.0;
                    for (int r = 0; r < s; ++r) acc += A[s][r] * K[r][j];
                    y_stage[j] = y[j] + h * acc;
                }
                status = lg_rhs(t + C[s] * h, y_stage, p, K[s], &ctl[C_PIVOT]);
                ctl[C_NFEV] += 1;
                if (status) break;
            }
            if (!status) {
                for (int j = 0; j < LG_NY; ++j) {
                    double acc = 0.0;
                    for (int r = 0; r < LG_DOP_STAGES; ++r) acc += B[r] * K[r][j];
                    y_new[j] = y[j] + h * acc;
                }
                status = lg_rhs(t_new, y_new, p, K[LG_DOP_STAGES], &ctl[C_PIVOT]);
                ctl[C_NFEV] += 1;
            }
            /* A trial step whose stages overflow is too long (an error estimate of infinity, as
             * SciPy's would be): rejected, the step cut by the largest factor, 0.2. */
            if (status == LG_NONFINITE && !fixed) {
                h_abs *= 0.2;
                rejected = overflowed = 1;
                ctl[C_REJECTED] += 1;
                continue;
            }
            if (status) { ctl[C_T] = t; ctl[C_H] = h_abs; return status; }
            overflowed = 0;
            if (fixed) break;
            if (lg_dop_accept(lg_dop_error_norm(LG_NY, h, y, y_new, Ks, rtol, atol), &rejected, &h_abs, ctl)) break;
        }
        ctl[C_STEPS] += 1;
#ifdef LG_PROJECT
        LG_PROJECT(y_new);  /* back on the constraint manifold (|e| = 1) before the step is used */
#endif
        /* dop853.f returns IDID = -4 with the state at the start of the step (y_stage holds the
         * last stage's state, K[STAGES - 1] its slope, K[STAGES] the slope at y_new) */
        if (!fixed && lg_dop_stiff(ctl, h, K[LG_DOP_STAGES], K[LG_DOP_STAGES - 1], y_new, y_stage)) {
            ctl[C_T] = t; ctl[C_H] = h_abs; return LG_STIFF;
        }

        const int need_dense = (*i_out < n_out && t_out[*i_out] <= t_new) || LG_NE > 0;
        if (need_dense) {
            /* three extra stages, then the interpolation coefficients (SciPy's
             * DOP853._dense_output_impl). */
            for (int s = LG_DOP_STAGES + 1; s < LG_DOP_STAGES_EXT; ++s) {
                for (int j = 0; j < LG_NY; ++j) {
                    double acc = 0.0;
                    for (int r = 0; r < s; ++r) acc += A[s][r] * K[r][j];
                    y_stage[j] = y[j] + h * acc;
                }
                status = lg_rhs(t + C[s] * h, y_stage, p, K[s], &ctl[C_PIVOT]);
                ctl[C_NFEV] += 1;
                if (status) { ctl[C_T] = t; ctl[C_H] = h_abs; return status; }
            }
            dense.t_old = t;
            dense.h = h;
            for (int j = 0; j < LG_NY; ++j) {
                const double dy = y_new[j] - y[j];
                dense.y_old[j] = y[j];
                dense.F[0][j] = dy;
                dense.F[1][j] = h * K[0][j] - dy;
                dense.F[2][j] = 2 * dy - h * (K[LG_DOP_STAGES][j] + K[0][j]);
                for (int i = 0; i < LG_DOP_POWER - 3; ++i) {
                    double acc = 0.0;
                    for (int r = 0; r < LG_DOP_STAGES_EXT; ++r) acc += D[i][r] * K[r][j];
                    dense.F[3 + i][j] = h * acc;
                }
            }
        }
        int terminal = 0;
        if (LG_NE > 0) {
            lg_events(t_new, y_new, p, g1);
            terminal = lg_check_events(&dense, lg_dop_interp, p, ctl, ev_dir, ev_terminal, ev_out,
                                       t, g0, t_new, g1, y_new);
            if (terminal) t_new = ctl[C_T];
            memcpy(g0, g1, sizeof g0);
        }
        while (*i_out < n_out && t_out[*i_out] <= t_new) {
            double *row = Y_out + (long)(*i_out) * LG_NY;
            if (t_out[*i_out] == t_new && !terminal) memcpy(row, y_new, sizeof y_new);
            else lg_dop_interp(&dense, t_out[*i_out], row);
            ++*i_out;
        }
        t = t_new;
        memcpy(y, y_new, sizeof y_new);
        memcpy(K[0], K[LG_DOP_STAGES], sizeof K[0]);
        ctl[C_T] = t;
        ctl[C_H] = h_abs;
        if (terminal) return LG_EVENT;
    }
    return LG_DONE;
}

static int lg_gauss_run(double *ctl, const volatile double *stop, double *y, const double *p,
                        const double *t_out, int n_out, int *i_out, double *Y_out, double t_stop,
                        const int *ev_dir, const int *ev_terminal, double *ev_out, double t_origin);

/* One run from ctl[C_T] to t_stop (method 0: dop853, 1: gauss-legendre).  With an inputs' law whose
 * tables jump (LG_NBREAK > 0), the run stops at every breakpoint and starts again there: no step
 * straddles a jump of u or of its derivatives, and between two breakpoints the law reads the piece
 * of that interval (its hint, law[0], is a time inside it), so the last stage of a step that ends on
 * a sample of a zero-order hold still sees the value before the jump.  p is the caller's array
 * (writable: the hint is written there, and set back to NaN at the end). */
static int lg_run(int method, double *ctl, const volatile double *stop, double *y, double *p, const double *t_out,
                  int n_out, int *i_out, double *Y_out, double t_stop, const int *ev_dir, const int *ev_terminal,
                  double *ev_out, double t_origin)
{
#if LG_NBREAK > 0
    double *law = p + LG_NP + LG_NK;
    const double *breaks = law + LG_BREAKS;
    int j = 0, status = LG_DONE;
    while (j < LG_NBREAK && breaks[j] <= ctl[C_T]) ++j;
    for (;;) {
        const double end = (j < LG_NBREAK && breaks[j] < t_stop) ? breaks[j] : t_stop;
        law[0] = 0.5 * (ctl[C_T] + end);
        status = method == 0
            ? lg_dop853_run(ctl, stop, y, p, t_out, n_out, i_out, Y_out, end, ev_dir, ev_terminal, ev_out)
            : lg_gauss_run(ctl, stop, y, p, t_out, n_out, i_out, Y_out, end, ev_dir, ev_terminal, ev_out, t_origin);
        if (status != LG_DONE || end >= t_stop) break;
        ++j;
    }
    law[0] = NAN;
    return status;
#else
    return method == 0
        ? lg_dop853_run(ctl, stop, y, p, t_out, n_out, i_out, Y_out, t_stop, ev_dir, ev_terminal, ev_out)
        : lg_gauss_run(ctl, stop, y, p, t_out, n_out, i_out, Y_out, t_stop, ev_dir, ev_terminal, ev_out, t_origin);
#endif
}

int lg_dop853(double *ctl, double *y, const double *p, const double *t_out, int n_out, int *i_out,
              double *Y_out, double t_stop, const int *ev_dir, const int *ev_terminal, double *ev_out)
{
    return lg_run(0, ctl, ctl + C_STOP, y, (double *)p, t_out, n_out, i_out, Y_out, t_stop, ev_dir, ev_terminal,
                  ev_out, 0.0);
}

#ifndef LG_FREE
/* ---- Gauss-Legendre in (q, p) -------------------------------------------------------- */

/* z = (q, p) -> z' = (q', p'): q' from M q' = p - b, p' = dT/dq - dU/dq + Q(nc) at (q, q'). */
static int lg_hamilton_rhs(double t, const double *z, const double *p, double *dz, double *qd_out, double *worst)
{
    double M[LG_N * LG_N], b[LG_N], g[LG_N], qd[LG_N], y[LG_NY];
    lg_hamilton_mass(t, z, p, M, b);
    for (int i = 0; i < LG_N; ++i) qd[i] = z[LG_N + i] - b[i];
    int status = lg_cholesky_solve(M, qd, worst);
    if (status) return status;
    for (int i = 0; i < LG_N; ++i) { y[i] = z[i]; y[LG_N + i] = qd[i]; }
    lg_hamilton_force(t, y, p, g);
    for (int i = 0; i < LG_N; ++i) {
        dz[i] = qd[i];
        dz[LG_N + i] = g[i];
        if (!isfinite(qd[i]) || !isfinite(g[i])) return LG_NONFINITE;
    }
    if (qd_out) memcpy(qd_out, qd, sizeof qd);
    return LG_DONE;
}

/* (q, q') -> (q, p) with p = M q' + b. */
static void lg_to_momenta(double t, const double *y, const double *p, double *z)
{
    double M[LG_N * LG_N], b[LG_N];
    lg_hamilton_mass(t, y, p, M, b);
    for (int i = 0; i < LG_N; ++i) {
        double s = b[i];
        for (int k = 0; k < LG_N; ++k) s += M[i * LG_N + k] * y[LG_N + k];
        z[i] = y[i];
        z[LG_N + i] = s;
    }
}

typedef struct {
    double t0, h;
    double y0[LG_NY], dy0[LG_NY], y1[LG_NY], dy1[LG_NY];
} lg_hermite;

/* Cubic Hermite interpolation of (q, q') between two steps: order 4, as the method. */
static void lg_hermite_interp(const void *ctx, double t, double *y)
{
    const lg_hermite *d = (const lg_hermite *)ctx;
    const double s = (t - d->t0) / d->h, s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    for (int j = 0; j < LG_NY; ++j)
        y[j] = h00 * d->y0[j] + h10 * d->h * d->dy0[j] + h01 * d->y1[j] + h11 * d->h * d->dy1[j];
}

/* Fixed step ctl[C_H]; step k ends at t0 + k h exactly (no accumulated round-off), so an
 * output grid that is a multiple of h is hit without interpolation.  ctl[C_RTOL] is the
 * tolerance of the fixed-point iteration of the stages. */
static int lg_gauss_run(double *ctl, const volatile double *stop, double *y, const double *p,
                        const double *t_out, int n_out, int *i_out, double *Y_out, double t_stop,
                        const int *ev_dir, const int *ev_terminal, double *ev_out, double t_origin)
{
    static const double r3 = 1.7320508075688772935;   /* sqrt(3) */
    const double a11 = 0.25, a12 = 0.25 - r3 / 6, a21 = 0.25 + r3 / 6, a22 = 0.25;
    const double c1 = 0.5 - r3 / 6, c2 = 0.5 + r3 / 6;
    const double h = ctl[C_H], tol = ctl[C_RTOL];
    double z[LG_NY], k1[LG_NY], k2[LG_NY], z1[LG_NY], z2[LG_NY], n1[LG_NY], n2[LG_NY], qd[LG_N];
    double g0[LG_NE > 0 ? LG_NE : 1], g1[LG_NE > 0 ? LG_NE : 1];
    lg_hermite herm;
    double t = ctl[C_T];
    int status;

    if (t >= t_stop) return LG_DONE;
    lg_to_momenta(t, y, p, z);
    status = lg_hamilton_rhs(t, z, p, k1, NULL, &ctl[C_PIVOT]);
    ctl[C_NFEV] += 1;
    if (status) return status;
    memcpy(k2, k1, sizeof k1);
    if (LG_NE > 0) lg_events(t, y, p, g0);
    while (*i_out < n_out && t_out[*i_out] <= t) {
        memcpy(Y_out + (long)(*i_out) * LG_NY, y, sizeof z);
        ++*i_out;
    }
    while (t < t_stop) {
        if (ctl[C_STEPS] >= ctl[C_MAXSTEPS] || lg_pace_hopeless(ctl, t, t_stop, h)) { ctl[C_T] = t; return LG_MAXSTEPS; }
        if (lg_stop_requested(stop)) { ctl[C_T] = t; return LG_INTERRUPTED; }
        const double k_index = floor((t - t_origin) / h + 0.5) + 1.0;
        double t_new = t_origin + k_index * h;
        if (t_new > t_stop) t_new = t_stop;
        const double hh = t_new - t;
        /* stages by fixed-point iteration, started from the last step's slopes */
        int converged = 0;
        for (int it = 0; it < 100; ++it) {
            for (int j = 0; j < LG_NY; ++j) {
                z1[j] = z[j] + hh * (a11 * k1[j] + a12 * k2[j]);
                z2[j] = z[j] + hh * (a21 * k1[j] + a22 * k2[j]);
            }
            status = lg_hamilton_rhs(t + c1 * hh, z1, p, n1, NULL, &ctl[C_PIVOT]);
            if (!status) status = lg_hamilton_rhs(t + c2 * hh, z2, p, n2, NULL, &ctl[C_PIVOT]);
            ctl[C_NFEV] += 2;
            if (status) { ctl[C_T] = t; return status; }
            double change = 0.0;
            for (int j = 0; j < LG_NY; ++j) {
                const double sc = tol * (1.0 + fabs(z[j]));
                change = fmax(change, fabs(hh * (n1[j] - k1[j])) / sc);
                change = fmax(change, fabs(hh * (n2[j] - k2[j])) / sc);
            }
            memcpy(k1, n1, sizeof k1);
            memcpy(k2, n2, sizeof k2);
            if (change <= 1.0) { converged = 1; break; }
        }
        if (!converged) { ctl[C_T] = t; return LG_NOCONVERGE; }
        for (int j = 0; j < LG_NY; ++j) herm.y0[j] = y[j];
        /* y'(t) before the step, for the interpolant */
        status = lg_rhs(t, y, p, herm.dy0, &ctl[C_PIVOT]);
        if (status) { ctl[C_T] = t; return status; }
        for (int j = 0; j < LG_NY; ++j) z[j] += hh * 0.5 * (k1[j] + k2[j]);
        status = lg_hamilton_rhs(t_new, z, p, n1, qd, &ctl[C_PIVOT]);
        ctl[C_NFEV] += 2;
        if (status) { ctl[C_T] = t; return status; }
        for (int i = 0; i < LG_N; ++i) { y[i] = z[i]; y[LG_N + i] = qd[i]; }
        status = lg_rhs(t_new, y, p, herm.dy1, &ctl[C_PIVOT]);
        if (status) { ctl[C_T] = t; return status; }
        memcpy(herm.y1, y, sizeof herm.y1);
        herm.t0 = t;
        herm.h = hh;
        ctl[C_STEPS] += 1;
        int terminal = 0;
        if (LG_NE > 0) {
            double y_event[LG_NY];
            lg_events(t_new, y, p, g1);
            terminal = lg_check_events(&herm, lg_hermite_interp, p, ctl, ev_dir, ev_terminal, ev_out,
                                       t, g0, t_new, g1, y_event);
            if (terminal) { t_new = ctl[C_T]; memcpy(y, y_event, sizeof y_event); }
            memcpy(g0, g1, sizeof g0);
        }
        while (*i_out < n_out && t_out[*i_out] <= t_new) {
            double *row = Y_out + (long)(*i_out) * LG_NY;
            if (t_out[*i_out] == t_new) memcpy(row, y, sizeof z);
            else lg_hermite_interp(&herm, t_out[*i_out], row);
            ++*i_out;
        }
        t = t_new;
        ctl[C_T] = t;
        if (terminal) return LG_EVENT;
    }
    return LG_DONE;
}

int lg_gauss(double *ctl, double *y, const double *p, const double *t_out, int n_out, int *i_out,
             double *Y_out, double t_stop, const int *ev_dir, const int *ev_terminal, double *ev_out,
             double t_origin)
{
    return lg_run(1, ctl, ctl + C_STOP, y, (double *)p, t_out, n_out, i_out, Y_out, t_stop, ev_dir, ev_terminal,
                  ev_out, t_origin);
}

/* ---- ensembles: many members in one call ----------------------------------------------
 * lg_batch integrates `count` members one after another, each exactly as one lg_dop853 /
 * lg_gauss call of `simulate` would (same control block ctl0, same output grid, its own
 * adaptive step), so a member's result is bit for bit the single run's.  Per member k:
 *   Y0[k]   (2n)            initial state; Y_fin[k] receives the state where the run ended
 *   P[k]    (LG_NP + LG_NK + LG_NX) the parameter values; the hoisted constants p[LG_NP..] are
 *                           computed here (lg_constants), once per member; then the inputs' law
 *   Y_out[k] (n_out x 2n)  the state at the output times (rows after the end are left as given)
 *   mon[k]  (n_out x NM)    the monitors (first integrals, T, U) at those rows
 *   mom[k]  (n_out x 2n)    for each row i: (sum_j |M_ij q'_j|, sum_j M_ij q'_j), the terms of
 *                           the momenta p_i = dT/dq'_i, for the scale of their drift
 *   ev[k]   (NE x (2 + 2n)) first-occurrence rows of the events (count, time, state)
 *   info[k] (6)             status, t reached, accepted steps, rhs calls, rows written,
 *                           worst relative pivot
 * `stop` is read at every step of every member (Ctrl-C, from another thread): the member
 * being integrated returns LG_INTERRUPTED and the later ones are not started (info[k][0]
 * keeps its initial value, -1).  The batch holds no Python state, so several threads can
 * run batches of the same library at once (the Python side calls it with the GIL released). */
enum { B_STATUS, B_T, B_STEPS, B_NFEV, B_ROWS, B_PIVOT, B_SIZE };

int lg_batch(int method, int count, const double *ctl0, const double *Y0, double *P, const double *t_out,
             int n_out, double t_stop, double t_origin, const int *ev_dir, const int *ev_terminal,
             double *Y_fin, double *Y_out, double *mon, double *mom, double *ev, double *info,
             const double *stop)
{
    const int np = LG_NP + LG_NK + LG_NX, nm = LG_NM > 0 ? LG_NM : 1;
    for (int k = 0; k < count; ++k) {
        if (lg_stop_requested(stop)) return LG_INTERRUPTED;
        double ctl[C_SIZE];
        memcpy(ctl, ctl0, sizeof ctl);
        ctl[C_EVCAP] = -1.0;
        double *p = P + (long)k * np, *y = Y_fin + (long)k * LG_NY, *rows = Y_out + (long)k * n_out * LG_NY;
        double *evk = ev + (long)k * (LG_NE > 0 ? LG_NE : 1) * (2 + LG_NY);
        if (LG_NK > 0) lg_constants(p, p + LG_NP);
        memcpy(y, Y0 + (long)k * LG_NY, LG_NY * sizeof(double));
        int i_out = 0, status;
        status = lg_run(method, ctl, stop, y, p, t_out, n_out, &i_out, rows, t_stop, ev_dir, ev_terminal, evk,
                        t_origin);
        double *out = info + (long)k * B_SIZE;
        for (int i = 0; i < i_out; ++i) {
            const double *row = rows + (long)i * LG_NY;
            double M[LG_N * LG_N], F[LG_N];
            lg_monitors(t_out[i], row, p, mon + ((long)k * n_out + i) * nm);
            lg_mass_forces(t_out[i], row, p, M, F);
            double *m = mom + ((long)k * n_out + i) * LG_NY;
            for (int a = 0; a < LG_N; ++a) {
                double s = 0.0, s_abs = 0.0;
                for (int b = 0; b < LG_N; ++b) {
                    const double term = M[a * LG_N + b] * row[LG_N + b];
                    s += term;
                    s_abs += fabs(term);
                }
                m[a] = s_abs;
                m[LG_N + a] = s;
            }
        }
        out[B_STATUS] = status;
        out[B_T] = ctl[C_T];
        out[B_STEPS] = ctl[C_STEPS];
        out[B_NFEV] = ctl[C_NFEV];
        out[B_ROWS] = i_out;
        out[B_PIVOT] = ctl[C_PIVOT];
        if (status == LG_INTERRUPTED) return LG_INTERRUPTED;
    }
    return LG_DONE;
}
#endif  /* LG_FREE */
