/* The integrators of every model (RK4, DOP853 with dense output, GAUSS2 with simplified Newton,
 * GAUSS2_SYMPLECTIC), as the generator emits them: each `model_`/`MODEL_` becomes the model's
 * name, `MODEL_V_<value>` its number (sizes, op counts), `MODEL_T(args)` the time arguments of a
 * time-dependent model (nothing otherwise), and `#if MODEL_<FLAG>` sections are kept or dropped by
 * the model's facts (printers/kernels.py).  Everything above the `@kernel` line is for compilers
 * only: tests/models/test_kernels_compile.py compiles this file as it stands. */
#include "model_stub.h"
/* @kernel */

/* ---------------------------------------------------------------------------------------
 * Integrators: NAME_integrate and NAME_integrate_grid, written once over model_rhs.
 *   RK4     classical Runge-Kutta, order 4, fixed step.
 *   DOP853  Dormand-Prince 8(5,3), adaptive, with the 7th-order dense output (Hairer, Norsett,
 *           Wanner, Solving ODE I, II.5-II.10, and their Fortran DOP853, whose coefficients and
 *           error norm these are).
 *   GAUSS2  2-stage Gauss-Legendre collocation, order 4, symmetric (time-reversible), fixed step;
 *           the stage equations are solved by fixed-point iteration until the correction stops
#if MODEL_NEWTON
 *           decreasing (round-off), or, where the sweeps contract too slowly to pay (long
 *           steps), by simplified Newton with the exact Jacobian (stats n_newton counts those steps);
#if MODEL_CANONICAL
 *           GAUSS2_FIXED is the fixed-point iteration alone. *   GAUSS2_SYMPLECTIC  the same collocation on Hamilton's variables y = (phi, p), p = dL/dphidot:
#else
 *           GAUSS2_FIXED is the fixed-point iteration alone. * The state updates x += dx are compensated (Kahan), so round-off does not drift over 1e7 steps
#endif
#else
#if MODEL_CANONICAL
 *           decreasing (round-off). *   GAUSS2_SYMPLECTIC  the same collocation on Hamilton's variables y = (phi, p), p = dL/dphidot:
#else
 *           decreasing (round-off). * The state updates x += dx are compensated (Kahan), so round-off does not drift over 1e7 steps
#endif
#endif
#if MODEL_CANONICAL
 *           Gauss methods are symplectic in canonical variables (not in (phi, phidot), where M(phi)
 *           makes the change of variables nonlinear), so the energy error stays bounded where
 *           GAUSS2 drifts on a system without a reversing symmetry, and p1 (the momentum (27)) is
 *           kept to round-off.  Fixed-point sweeps only; one evaluation costs
 *           MODEL_V_OPS_CANONICAL ops against GAUSS2's MODEL_V_OPS_QDD. * The state updates x += dx are compensated (Kahan), so round-off does not drift over 1e7 steps
#endif
 * (do not compile with -ffast-math, which removes the compensation).  A stage that meets a
 * singular M or a non-finite value ends a fixed-step run with that code and the last good state;
 * DOP853 retries the step smaller first, and returns the code only when the step underflows
 * (the motion runs into the singular configuration).
 * --------------------------------------------------------------------------------------- */
#ifndef MODEL_INTEGRATE_MAX_STEPS
#define MODEL_INTEGRATE_MAX_STEPS 100000000L  /* default budget of steps (max_steps <= 0) */
#endif
#define MODEL_GAUSS_MAXIT 100                   /* fixed-point iterations per step */
/* A correction that stops decreasing below GAUSS_FLOOR times the largest |x_i| (at least 1) is
 * round-off: a component computed with cancellation (a small momentum, a small phi'') has a floor
 * above EPS, and an angle that has turned many times is known only to its ulp. */
#define MODEL_GAUSS_FLOOR 1e-12
#define MODEL_EPS 2.220446049250313e-16
#if MODEL_NEWTON
/* What a simplified Newton solve of GAUSS2's stages costs, in fixed-point sweeps (2 rhs each): the
 * Jacobian (MODEL_V_OPS_QDD_DERIVATIVES ops), the LU of the MODEL_V_DIM x MODEL_V_DIM matrix and ~3 iterations, against
 * MODEL_V_OPS_QDD ops per rhs.  Newton is used when more sweeps than this are still needed. */
#define MODEL_NEWTON_SWEEPS MODEL_V_NEWTON_SWEEPS
#if MODEL_CANONICAL
/* The same for GAUSS2_SYMPLECTIC: its Jacobian by MODEL_V_DIM forward differences of the canonical right
 * side, the LU of the MODEL_V_2DIM x MODEL_V_2DIM matrix and ~4 iterations. */
#define MODEL_NEWTON_SWEEPS_CANONICAL MODEL_V_NEWTON_SWEEPS_CANONICAL
#endif
#endif

static int model_eval_(MODEL_T(double t, )const double *x, const double *u, const model_params *p, double *xdot,
                            model_integrate_stats *st)
{
    st->n_rhs++;
    return model_rhs(MODEL_T_OR(t, 0.0), x, u, p, xdot);
}

#if MODEL_CANONICAL
/* GAUSS2_SYMPLECTIC's right side: Hamilton's equations in y = (phi, p), phi' = M^-1 (p - k(phi)),
 * p' = model_pdot.  One call costs MODEL_V_OPS_VELOCITIES + MODEL_V_OPS_PDOT ops. */
static int model_eval_canonical_(const double *y, const double *u, const model_params *p, double *ydot,
                                      model_integrate_stats *st)
{
    double x[MODEL_V_DIM];
    int i, code;
    st->n_rhs++;
    for (i = 0; i < MODEL_V_N; ++i) {
        x[i] = y[i];
    }
    if ((code = model_velocities(y, y + MODEL_V_N, p, x + MODEL_V_N)) != 0) {
        return code;
    }
    for (i = 0; i < MODEL_V_N; ++i) {
        ydot[i] = x[MODEL_V_N + i];
    }
    return model_pdot(x, u, p, ydot + MODEL_V_N);
}

/* (phi, p) -> (phi, phidot); NaN where phidot cannot be had (a singular M). */
static void model_to_state_(const double *y, const model_params *p, double *x)
{
    int i;
    for (i = 0; i < MODEL_V_N; ++i) {
        x[i] = y[i];
    }
    if (model_velocities(y, y + MODEL_V_N, p, x + MODEL_V_N) != 0) {
        for (i = 0; i < MODEL_V_N; ++i) {
            x[MODEL_V_N + i] = NAN;
        }
    }
}

#endif
/* x += dx with the running compensation cmp (Kahan): the low part each sum loses is carried on. */
static void model_add_(double *x, double *cmp, const double *dx)
{
    int i;
    for (i = 0; i < MODEL_V_DIM; ++i) {
        const double y = dx[i] + cmp[i];
        const double s = x[i] + y;
        cmp[i] = (x[i] - s) + y;
        x[i] = s;
    }
}

static void model_copy_(double *dst, const double *src)
{
    int i;
    for (i = 0; i < MODEL_V_DIM; ++i) {
        dst[i] = src[i];
    }
}

/* The round-off level of GAUSS2's stage corrections at the state x (see GAUSS_FLOOR). */
static double model_floor_(const double *x)
{
    double big = 1.0;
    int i;
    for (i = 0; i < MODEL_V_DIM; ++i) {
        big = fmax(big, fabs(x[i]));
    }
    return MODEL_GAUSS_FLOOR * big;
}

/* The steps of a fixed-step method between two output times: the largest count m with
 * |tb - ta| / m <= |h| (to a relative 1e-10, so that h = T/m gives m steps of T/m). */
static long model_nsteps_(double ta, double tb, double h)
{
    const double r = fabs(tb - ta) / fabs(h);
    double m = ceil(r * (1.0 - 1e-10));
    return m < 1.0 ? 1L : (long)m;
}

/* One classical RK4 step of size h from x: dx = the increment. */
static int model_rk4_step_(MODEL_T(double t0, )const double *x, double h, const double *u, const model_params *p,
                                double *dx, model_integrate_stats *st)
{
    double k[4][MODEL_V_DIM], y[MODEL_V_DIM];
    int i, s, code;
    static const double cs[3] = {0.5, 0.5, 1.0};
    if ((code = model_eval_(MODEL_T(t0, )x, u, p, k[0], st)) != 0) {
        return code;
    }
    for (s = 1; s < 4; ++s) {
        for (i = 0; i < MODEL_V_DIM; ++i) {
            y[i] = x[i] + cs[s - 1] * h * k[s - 1][i];
        }
        if ((code = model_eval_(MODEL_T(t0 + cs[s - 1] * h, )y, u, p, k[s], st)) != 0) {
            return code;
        }
    }
    for (i = 0; i < MODEL_V_DIM; ++i) {
        dx[i] = h / 6.0 * (k[0][i] + 2.0 * (k[1][i] + k[2][i]) + k[3][i]);
    }
    return MODEL_OK;
}

#if MODEL_NEWTON
/* LU with partial pivoting of the m x m row-major A, in place; piv the row order.  0 when a pivot
 * is zero (the Newton matrix is singular: h far too long). */
static int model_lu_(double *A, int *piv, int m)
{
    int i, j, k, r;
    for (k = 0; k < m; ++k) {
        double big = 0.0;
        r = k;
        for (i = k; i < m; ++i) {
            if (fabs(A[i * m + k]) > big) {
                big = fabs(A[i * m + k]);
                r = i;
            }
        }
        if (!(big > 0.0)) {
            return 0;
        }
        piv[k] = r;
        if (r != k) {
            for (j = 0; j < m; ++j) {
                const double tmp = A[k * m + j];
                A[k * m + j] = A[r * m + j];
                A[r * m + j] = tmp;
            }
        }
        for (i = k + 1; i < m; ++i) {
            const double l = A[i * m + k] / A[k * m + k];
            A[i * m + k] = l;
            for (j = k + 1; j < m; ++j) {
                A[i * m + j] -= l * A[k * m + j];
            }
        }
    }
    return 1;
}

static void model_lu_solve_(const double *A, const int *piv, int m, double *b)
{
    int i, j;
    for (i = 0; i < m; ++i) {
        const double tmp = b[piv[i]];
        b[piv[i]] = b[i];
        b[i] = tmp;
        for (j = 0; j < i; ++j) {
            b[i] -= A[i * m + j] * b[j];
        }
    }
    for (i = m - 1; i >= 0; --i) {
        for (j = i + 1; j < m; ++j) {
            b[i] -= A[i * m + j] * b[j];
        }
        b[i] /= A[i * m + i];
    }
}

/* GAUSS2's stage equations by simplified Newton, for long steps where the fixed-point sweeps
 * converge slowly or not at all.  The position increments are linear in the velocity ones,
 * Zq_s = h (c_s v + sum_j a_sj Zv_j), so Newton runs on Zv alone (2n unknowns) with the exact
 * Jacobian Dq = d phi''/d phi, Dv = d phi''/d phidot of model_qdd_derivatives at the step's start:
 *   sum_k (delta_sk I - h a_sk Dv - h^2 (A^2)_sk Dq) dZv_k = -(Zv_s - h sum_j a_sj phi''_j). */
static int model_gauss2_newton_(MODEL_T(double t0, )const double *x, double h, const double *u, const model_params *p,
                                     double Z[2][MODEL_V_DIM], double F[2][MODEL_V_DIM], model_integrate_stats *st)
{
    static const double a[2][2] = {{0.25, -0.038675134594812866}, {0.5386751345948129, 0.25}};
    static const double c[2] = {0.21132486540518713, 0.7886751345948129};
    double Dq[MODEL_V_NN], Dv[MODEL_V_NN], J[MODEL_V_DIM2], G[MODEL_V_DIM], Zv[MODEL_V_DIM], Y[MODEL_V_DIM];
    double d, dprev = HUGE_VAL;
    const double floor = model_floor_(x);
    int piv[MODEL_V_DIM], i, j, s, r, it, code;
    if ((code = model_qdd_derivatives(MODEL_T(t0, )x, u, p, 0, Dq, Dv, 0)) != 0) {
        return code;
    }
    for (s = 0; s < 2; ++s) {
        for (r = 0; r < 2; ++r) {
            const double A2 = a[s][0] * a[0][r] + a[s][1] * a[1][r];
            for (i = 0; i < MODEL_V_N; ++i) {
                for (j = 0; j < MODEL_V_N; ++j) {
                    J[(s * MODEL_V_N + i) * MODEL_V_DIM + r * MODEL_V_N + j] = (s == r && i == j ? 1.0 : 0.0)
                        - h * a[s][r] * Dv[i * MODEL_V_N + j] - h * h * A2 * Dq[i * MODEL_V_N + j];
                }
            }
        }
    }
    if (!model_lu_(J, piv, MODEL_V_DIM)) {
        return MODEL_NO_CONVERGENCE;
    }
    for (s = 0; s < 2; ++s) {
        for (i = 0; i < MODEL_V_N; ++i) {
            Zv[s * MODEL_V_N + i] = Z[s][MODEL_V_N + i];
        }
    }
    for (it = 1;; ++it) {
        for (s = 0; s < 2; ++s) {
            for (i = 0; i < MODEL_V_N; ++i) {
                Y[i] = x[i] + h * (c[s] * x[MODEL_V_N + i] + a[s][0] * Zv[i] + a[s][1] * Zv[MODEL_V_N + i]);
                Y[MODEL_V_N + i] = x[MODEL_V_N + i] + Zv[s * MODEL_V_N + i];
            }
            if ((code = model_eval_(MODEL_T(t0 + c[s] * h, )Y, u, p, F[s], st)) != 0) {
                return code;
            }
        }
        for (s = 0; s < 2; ++s) {
            for (i = 0; i < MODEL_V_N; ++i) {
                G[s * MODEL_V_N + i] = -(Zv[s * MODEL_V_N + i] - h * (a[s][0] * F[0][MODEL_V_N + i] + a[s][1] * F[1][MODEL_V_N + i]));
            }
        }
        model_lu_solve_(J, piv, MODEL_V_DIM, G);
        st->n_iter++;
        d = 0.0;
        for (s = 0; s < 2; ++s) {
            for (i = 0; i < MODEL_V_N; ++i) {
                const double sc = fabs(x[MODEL_V_N + i]) + fabs(Zv[s * MODEL_V_N + i]) + 1e-300;
                const double e = fabs(G[s * MODEL_V_N + i]) / sc;
                d = e > d ? e : d;
                Zv[s * MODEL_V_N + i] += G[s * MODEL_V_N + i];
            }
        }
        if (!(d < HUGE_VAL)) {
            return MODEL_NO_CONVERGENCE;
        }
        if (d <= MODEL_EPS || (it >= 2 && d >= dprev && dprev <= floor)) {
            break;
        }
        if (it >= 30 || (it >= 4 && d > 0.9 * dprev && d > 1e-12)) {
            return MODEL_NO_CONVERGENCE;  /* hardly contracting: the caller goes back to the sweeps */
        }
        dprev = d;
    }
    /* the stage increments of the full state, for the next step's guess */
    for (s = 0; s < 2; ++s) {
        for (i = 0; i < MODEL_V_N; ++i) {
            Z[s][i] = h * (c[s] * x[MODEL_V_N + i] + a[s][0] * Zv[i] + a[s][1] * Zv[MODEL_V_N + i]);
            Z[s][MODEL_V_N + i] = Zv[s * MODEL_V_N + i];
        }
    }
    st->n_newton++;
    return MODEL_OK;
}
#if MODEL_CANONICAL

/* GAUSS2_SYMPLECTIC's stage equations by simplified Newton on all 2 x 2n increments (in (phi, p) the
 * position increments are not linear in the others).  J = d g/d y at the step's start by forward
 * differences of the canonical right side g (the converged solution does not depend on J, only the
 * rate does: differences are accurate enough and need nothing that is not emitted):
 *   sum_k (delta_sk I - h a_sk J) dZ_k = -(Z_s - h sum_j a_sj g(y + Z_j)). */
static int model_canonical_newton_(const double *y, double h, const double *u, const model_params *p,
                                        double Z[2][MODEL_V_DIM], double F[2][MODEL_V_DIM], model_integrate_stats *st)
{
    static const double a[2][2] = {{0.25, -0.038675134594812866}, {0.5386751345948129, 0.25}};
    double J[MODEL_V_DIM2], N[MODEL_V_4DIM2], G[MODEL_V_2DIM], Y[MODEL_V_DIM], g0[MODEL_V_DIM], g1[MODEL_V_DIM];
    double d, dprev = HUGE_VAL;
    const double floor = model_floor_(y);
    int piv[MODEL_V_2DIM], i, j, s, r, it, code;
    if ((code = model_eval_canonical_(y, u, p, g0, st)) != 0) {
        return code;
    }
    for (j = 0; j < MODEL_V_DIM; ++j) {
        const double e = 1.4901161193847656e-08 * fmax(fabs(y[j]), 1.0);
        model_copy_(Y, y);
        Y[j] += e;
        if ((code = model_eval_canonical_(Y, u, p, g1, st)) != 0) {
            return code;
        }
        for (i = 0; i < MODEL_V_DIM; ++i) {
            J[i * MODEL_V_DIM + j] = (g1[i] - g0[i]) / (Y[j] - y[j]);
        }
    }
    for (s = 0; s < 2; ++s) {
        for (r = 0; r < 2; ++r) {
            for (i = 0; i < MODEL_V_DIM; ++i) {
                for (j = 0; j < MODEL_V_DIM; ++j) {
                    N[(s * MODEL_V_DIM + i) * MODEL_V_2DIM + r * MODEL_V_DIM + j] = (s == r && i == j ? 1.0 : 0.0)
                        - h * a[s][r] * J[i * MODEL_V_DIM + j];
                }
            }
        }
    }
    if (!model_lu_(N, piv, MODEL_V_2DIM)) {
        return MODEL_NO_CONVERGENCE;
    }
    for (it = 1;; ++it) {
        for (s = 0; s < 2; ++s) {
            for (i = 0; i < MODEL_V_DIM; ++i) {
                Y[i] = y[i] + Z[s][i];
            }
            if ((code = model_eval_canonical_(Y, u, p, F[s], st)) != 0) {
                return code;
            }
        }
        for (s = 0; s < 2; ++s) {
            for (i = 0; i < MODEL_V_DIM; ++i) {
                G[s * MODEL_V_DIM + i] = -(Z[s][i] - h * (a[s][0] * F[0][i] + a[s][1] * F[1][i]));
            }
        }
        model_lu_solve_(N, piv, MODEL_V_2DIM, G);
        st->n_iter++;
        d = 0.0;
        for (s = 0; s < 2; ++s) {
            for (i = 0; i < MODEL_V_DIM; ++i) {
                const double sc = fabs(y[i]) + fabs(Z[s][i]) + 1e-300;
                const double e = fabs(G[s * MODEL_V_DIM + i]) / sc;
                d = e > d ? e : d;
                Z[s][i] += G[s * MODEL_V_DIM + i];
            }
        }
        if (!(d < HUGE_VAL)) {
            return MODEL_NO_CONVERGENCE;
        }
        if (d <= MODEL_EPS || (it >= 2 && d >= dprev && dprev <= floor)) {
            break;
        }
        if (it >= 30 || (it >= 4 && d > 0.9 * dprev && d > 1e-12)) {
            return MODEL_NO_CONVERGENCE;  /* hardly contracting: the caller goes back to the sweeps */
        }
        dprev = d;
    }
    st->n_newton++;  /* F is g at the Z before the last (round-off) correction, as the sweeps leave it */
    return MODEL_OK;
}
#endif
#endif

/* One GAUSS2 step of size h from x.  Stage increments Z_i = h sum_j a_ij f(x + Z_j), nodes
 * c = 1/2 -+ sqrt(3)/6; dx = h (F_1 + F_2) / 2.  F holds the stage derivatives of the previous
 * step, of size hp (0: none; F = f(x) then), and on return those of this one.  The starting
 * guess extrapolates the previous step's collocation polynomial w (w(0) = 0, w(c_i) = Z_i):
 * Z_i = w(1 + c_i h/hp) - w(1) (Hairer, Lubich, Wanner, Geometric Numerical Integration VIII.6). */
static int model_gauss2_step_(MODEL_T(double t0, )const double *x, double h, double hp, int method, const double *u,
                                   const model_params *p, double F[2][MODEL_V_DIM], double *dx, model_integrate_stats *st)
{
    static const double a11 = 0.25, a12 = -0.038675134594812866, a21 = 0.5386751345948129, a22 = 0.25;
    static const double c1 = 0.21132486540518713, c2 = 0.7886751345948129;
    double Z[2][MODEL_V_DIM], Y[MODEL_V_DIM], L[3][2];
    double d, dprev = HUGE_VAL;
    const double floor = model_floor_(x);
#if MODEL_CANONICAL_NEWTON
    int i, s, it, code, newton = method == MODEL_GAUSS2 || method == MODEL_GAUSS2_SYMPLECTIC;
#else
    int i, s, it, code, newton = method == MODEL_GAUSS2;
#endif
    if (hp != 0.0) {
        /* Lagrange weights of (Z_1, Z_2) at theta = 1 + c_1 r, 1 + c_2 r, 1 */
        const double r = h / hp, th[3] = {1.0 + c1 * r, 1.0 + c2 * r, 1.0};
        for (s = 0; s < 3; ++s) {
            L[s][0] = th[s] * (th[s] - c2) / (c1 * (c1 - c2));
            L[s][1] = th[s] * (th[s] - c1) / (c2 * (c2 - c1));
        }
    }
    for (i = 0; i < MODEL_V_DIM; ++i) {
        if (hp != 0.0) {
            const double z0 = hp * (a11 * F[0][i] + a12 * F[1][i]), z1 = hp * (a21 * F[0][i] + a22 * F[1][i]);
            const double w1 = L[2][0] * z0 + L[2][1] * z1;
            Z[0][i] = L[0][0] * z0 + L[0][1] * z1 - w1;
            Z[1][i] = L[1][0] * z0 + L[1][1] * z1 - w1;
        } else {
            Z[0][i] = c1 * h * F[0][i];
            Z[1][i] = c2 * h * F[0][i];
        }
    }
    for (it = 1;; ++it) {
        for (s = 0; s < 2; ++s) {
            for (i = 0; i < MODEL_V_DIM; ++i) {
                Y[i] = x[i] + Z[s][i];
            }
#if MODEL_CANONICAL
            code = method == MODEL_GAUSS2_SYMPLECTIC ? model_eval_canonical_(Y, u, p, F[s], st)
                                                       : model_eval_(Y, u, p, F[s], st);
#else
            code = model_eval_(MODEL_T(t0 + (s == 0 ? c1 : c2) * h, )Y, u, p, F[s], st);
#endif
            if (code != 0) {
                return code;
            }
        }
        st->n_iter++;
        /* the correction, relative to the size of x and Z, component by component */
        d = 0.0;
        for (i = 0; i < MODEL_V_DIM; ++i) {
            const double z0 = h * (a11 * F[0][i] + a12 * F[1][i]);
            const double z1 = h * (a21 * F[0][i] + a22 * F[1][i]);
            const double sc = fabs(x[i]) + fabs(z0) + fabs(z1) + 1e-300;
            const double e = fmax(fabs(z0 - Z[0][i]), fabs(z1 - Z[1][i])) / sc;
            d = e > d ? e : d;
            Z[0][i] = z0;
            Z[1][i] = z1;
        }
        if (!(d < HUGE_VAL)) {
            return MODEL_NO_CONVERGENCE;
        }
        if (d <= MODEL_EPS || (it >= 2 && d >= dprev && dprev <= floor)) {
            break;  /* at round-off: exact to the last bit, or no longer decreasing */
        }
#if MODEL_NEWTON
        if (newton && it >= 2) {
            /* the sweeps still needed at the observed rate, against Newton's cost in sweeps */
            const double rate = d / dprev;
#if MODEL_CANONICAL
            const int canonical = method == MODEL_GAUSS2_SYMPLECTIC;
            if (rate >= 1.0 || log(MODEL_EPS / d) / log(rate) > (canonical ? MODEL_NEWTON_SWEEPS_CANONICAL : MODEL_NEWTON_SWEEPS)) {
                code = canonical ? model_canonical_newton_(x, h, u, p, Z, F, st) : model_gauss2_newton_(x, h, u, p, Z, F, st);
#else
            if (rate >= 1.0 || log(MODEL_EPS / d) / log(rate) > MODEL_NEWTON_SWEEPS) {
                code = model_gauss2_newton_(MODEL_T(t0, )x, h, u, p, Z, F, st);
#endif
                if (code == MODEL_OK) {
                    break;
                }
                if (code != MODEL_NO_CONVERGENCE) {
                    return code;
                }
                newton = 0;  /* Newton did not converge from here: the sweeps go on from Z (F is recomputed) */
            }
        }
#else
        (void)newton;
#endif
        if (it >= MODEL_GAUSS_MAXIT) {
            return MODEL_NO_CONVERGENCE;
        }
        dprev = d;
    }
    for (i = 0; i < MODEL_V_DIM; ++i) {
        dx[i] = 0.5 * h * (F[0][i] + F[1][i]);
    }
    return MODEL_OK;
}

#if MODEL_CANONICAL
/* RK4 or GAUSS2 over the output times tt[0..nt-1]: steps of at most |h|, uniform between two
 * output times (so output times that are multiples of h keep the step constant).  GAUSS2_SYMPLECTIC
 * steps y = (phi, p) and gives (phi, phidot) at the output times and in st->x. */
#else
/* RK4 or GAUSS2 over the output times tt[0..nt-1]: steps of at most |h|, uniform between two
 * output times (so output times that are multiples of h keep the step constant). */
#endif
static int model_fixed_(int method, int nt, const double *tt, double h, long max_steps,
                             const double *u, const model_params *p, double *X,
                             model_integrate_stats *st)
{
    double x[MODEL_V_DIM], cmp[MODEL_V_DIM], dx[MODEL_V_DIM], F[2][MODEL_V_DIM], hp = 0.0;
    long k, m;
    int i, j, code = MODEL_OK;
#if MODEL_CANONICAL
    const int canonical = method == MODEL_GAUSS2_SYMPLECTIC;
    double ylast[MODEL_V_DIM];
#endif
    model_copy_(x, X);
    for (i = 0; i < MODEL_V_DIM; ++i) {
        cmp[i] = 0.0;
    }
#if MODEL_CANONICAL
    if (canonical) {
        if ((code = model_momenta(X, p, x + MODEL_V_N)) != 0) {
            return code;
        }
        model_copy_(ylast, x);
        code = model_eval_canonical_(x, u, p, F[0], st);
    } else if (method != MODEL_RK4) {
        code = model_eval_(x, u, p, F[0], st);
    }
    if (code != 0) {
        return code;  /* F[0] = f(x): the first step's guess (F[1] is read from the second on) */
    }
#else
    if (method != MODEL_RK4) {
        if ((code = model_eval_(MODEL_T(tt[0], )x, u, p, F[0], st)) != 0) {
            return code;  /* F[0] = f(x): the first step's guess (F[1] is read from the second on) */
        }
    }
#endif
    for (j = 1; j < nt && code == 0; ++j) {
        const double ta = tt[j - 1], hs = (tt[j] - ta) / (double)(m = model_nsteps_(ta, tt[j], h));
        for (k = 0; k < m; ++k) {
            if (st->n_steps >= max_steps) {
                code = MODEL_TOO_MANY_STEPS;
                break;
            }
#if MODEL_TIME_DEPENDENT
            const double tk = ta + (double)k * hs;
            code = method == MODEL_RK4 ? model_rk4_step_(tk, x, hs, u, p, dx, st)
                                         : model_gauss2_step_(tk, x, hs, hp, method, u, p, F, dx, st);
#else
            code = method == MODEL_RK4 ? model_rk4_step_(x, hs, u, p, dx, st)
                                         : model_gauss2_step_(x, hs, hp, method, u, p, F, dx, st);
#endif
            if (code != 0) {
                break;
            }
            model_add_(x, cmp, dx);
            hp = hs;
            if (!model_all_finite_(x, MODEL_V_DIM)) {
                code = MODEL_NONFINITE;  /* st->x keeps the last finite state */
                break;
            }
            st->n_steps++;
            st->t = k + 1 == m ? tt[j] : ta + (double)(k + 1) * hs;
#if MODEL_CANONICAL
            model_copy_(canonical ? ylast : st->x, x);
#else
            model_copy_(st->x, x);
#endif
        }
        if (code == 0) {
#if MODEL_CANONICAL
            if (canonical) {
                model_to_state_(x, p, X + j * MODEL_V_DIM);
            } else {
                model_copy_(X + j * MODEL_V_DIM, x);
            }
#else
            model_copy_(X + j * MODEL_V_DIM, x);
#endif
        }
    }
#if MODEL_CANONICAL
    if (canonical && st->n_steps > 0) {
        model_to_state_(ylast, p, st->x);  /* (before the first step st->x is x0 as given) */
    }
#endif
    return code;
}

/* out = hs sum_{j < count} w_j k_j: a stage point's increment, or a dense-output coefficient. */
static void model_ksum_(const double *w, int count, double k[][MODEL_V_DIM], double hs, double *out)
{
    int i, j;
    for (i = 0; i < MODEL_V_DIM; ++i) {
        double acc = 0.0;
        for (j = 0; j < count; ++j) {
            acc += w[j] * k[j][i];
        }
        out[i] = hs * acc;
    }
}

/* DOP853 over the output times tt[0..nt-1] (monotone): steps chosen by the error estimate, output
 * times inside a step from the dense output.  h0 > 0 is the first step, else it is estimated. */
static int model_dop853_(int nt, const double *tt, double h0, double rtol, double atol, long max_steps,
                              const double *u, const model_params *p, double *X,
                              model_integrate_stats *st)
{
#if MODEL_TIME_DEPENDENT
    /* the stage times t + c_i h: c_i = the row sums of a (Hairer's DOP853) */
    static const double c[16] = {0.0, 0.052600151958767735, 0.07890022793815160, 0.11835034190722740,
                                 0.28164965809277260, 0.3333333333333333, 0.25, 0.3076923076923077,
                                 0.6512820512820513, 0.6, 0.8571428571428571, 1.0, 1.0, 0.1, 0.2,
                                 0.7777777777777778};
#else
    /* the stage times c_i are not needed: the model is autonomous (u constant over the call) */
#endif
    /* a[i][j], j < i: rows 0-11 the steps' stages, 12 the solution (b; its f is the next k0),
       13-15 the extra stages of the dense output */
    static const double a[16][16] = {
        {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.05260015195876773, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.0197250569845379, 0.0591751709536137, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.02958758547680685, 0.0, 0.08876275643042054, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.2413651341592667, 0.0, -0.8845494793282861, 0.924834003261792, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.037037037037037035, 0.0, 0.0, 0.17082860872947386, 0.12546768756682242, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.037109375, 0.0, 0.0, 0.17025221101954405, 0.06021653898045596, -0.017578125, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.03709200011850479, 0.0, 0.0, 0.17038392571223998, 0.10726203044637328, -0.015319437748624402, 0.008273789163814023, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.6241109587160757, 0.0, 0.0, -3.3608926294469414, -0.868219346841726, 27.59209969944671, 20.154067550477894, -43.48988418106996, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.47766253643826434, 0.0, 0.0, -2.4881146199716677, -0.590290826836843, 21.230051448181193, 15.279233632882423, -33.28821096898486, -0.020331201708508627, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {-0.9371424300859873, 0.0, 0.0, 5.186372428844064, 1.0914373489967295, -8.149787010746927, -18.52006565999696, 22.739487099350505, 2.4936055526796523, -3.0467644718982196, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {2.273310147516538, 0.0, 0.0, -10.53449546673725, -2.0008720582248625, -17.9589318631188, 27.94888452941996, -2.8589982771350235, -8.87285693353063, 12.360567175794303, 0.6433927460157636, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.054293734116568765, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, 0.3111643669578199, -0.1521609496625161, 0.20136540080403034, 0.04471061572777259, 0.0, 0.0, 0.0, 0.0},
        {0.056167502283047954, 0.0, 0.0, 0.0, 0.0, 0.0, 0.25350021021662483, -0.2462390374708025, -0.12419142326381637, 0.15329179827876568, 0.00820105229563469, 0.007567897660545699, -0.008298, 0.0, 0.0, 0.0},
        {0.03183464816350214, 0.0, 0.0, 0.0, 0.0, 0.028300909672366776, 0.053541988307438566, -0.05492374857139099, 0.0, 0.0, -0.00010834732869724932, 0.0003825710908356584, -0.00034046500868740456, 0.1413124436746325, 0.0, 0.0},
        {-0.42889630158379194, 0.0, 0.0, 0.0, 0.0, -4.697621415361164, 7.683421196062599, 4.06898981839711, 0.3567271874552811, 0.0, 0.0, 0.0, -0.0013990241651590145, 2.9475147891527724, -9.15095847217987, 0.0},
    };
    static const double e3[13] = {-0.18980075407240762, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, -0.4226823213237919, -0.1521609496625161, 0.20136540080403034, 0.02265179219836082, 0.0};
    static const double e5[13] = {0.01312004499419488, 0.0, 0.0, 0.0, 0.0, -1.2251564463762044, -0.4957589496572502, 1.6643771824549864, -0.35032884874997366, 0.3341791187130175, 0.08192320648511571, -0.022355307863886294, 0.0};
    static const double dd[4][16] = {
        {-8.428938276109013, 0.0, 0.0, 0.0, 0.0, 0.5667149535193777, -3.0689499459498917, 2.38466765651207, 2.117034582445028, -0.871391583777973, 2.2404374302607883, 0.6315787787694688, -0.08899033645133331, 18.148505520854727, -9.194632392478356, -4.436036387594894},
        {10.427508642579134, 0.0, 0.0, 0.0, 0.0, 242.28349177525817, 165.20045171727028, -374.5467547226902, -22.113666853125306, 7.733432668472264, -30.674084731089398, -9.332130526430229, 15.697238121770845, -31.139403219565178, -9.35292435884448, 35.81684148639408},
        {19.985053242002433, 0.0, 0.0, 0.0, 0.0, -387.0373087493518, -189.17813819516758, 527.8081592054236, -11.57390253995963, 6.8812326946963, -1.0006050966910838, 0.7777137798053443, -2.778205752353508, -60.19669523126412, 84.32040550667716, 11.99229113618279},
        {-25.69393346270375, 0.0, 0.0, 0.0, 0.0, -154.18974869023643, -231.5293791760455, 357.6391179106141, 93.40532418362432, -37.45832313645163, 104.0996495089623, 29.8402934266605, -43.53345659001114, 96.32455395918828, -39.17726167561544, -149.72683625798564},
    };
    double k[16][MODEL_V_DIM], x[MODEL_V_DIM], cmp[MODEL_V_DIM], y[MODEL_V_DIM], dy[MODEL_V_DIM], sc[MODEL_V_DIM];
    const double tend = tt[nt - 1], dir = tend >= tt[0] ? 1.0 : -1.0;
    double t = tt[0], h, hmin, err, e3n, e5n, fac, s3, s5;
    int i, j, s, code, next = 1, rejected = 0, fail = 0;
    model_copy_(x, X);
    for (i = 0; i < MODEL_V_DIM; ++i) {
        cmp[i] = 0.0;
    }
    if ((code = model_eval_(MODEL_T(t, )x, u, p, k[0], st)) != 0) {
        return code;
    }
    if (h0 > 0.0) {
        h = fmin(h0, fabs(tend - t));
    } else {
        /* the starting step of Hairer, Norsett, Wanner II.4 (one more evaluation) */
        double d0 = 0.0, d1 = 0.0, d2 = 0.0, h1;
        for (i = 0; i < MODEL_V_DIM; ++i) {
            sc[i] = atol + fabs(x[i]) * rtol;
            d0 += (x[i] / sc[i]) * (x[i] / sc[i]);
            d1 += (k[0][i] / sc[i]) * (k[0][i] / sc[i]);
        }
        d0 = sqrt(d0 / MODEL_V_DIM);
        d1 = sqrt(d1 / MODEL_V_DIM);
        h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
        h = fmin(h, fabs(tend - t));
        for (i = 0; i < MODEL_V_DIM; ++i) {
            y[i] = x[i] + dir * h * k[0][i];
        }
        if (model_eval_(MODEL_T(t + dir * h, )y, u, p, k[1], st) == 0) {
            for (i = 0; i < MODEL_V_DIM; ++i) {
                d2 += ((k[1][i] - k[0][i]) / sc[i]) * ((k[1][i] - k[0][i]) / sc[i]);
            }
            d2 = sqrt(d2 / MODEL_V_DIM) / h;
            h1 = (d1 <= 1e-15 && d2 <= 1e-15) ? fmax(1e-6, 1e-3 * h) : pow(0.01 / fmax(d1, d2), 0.125);
            h = fmin(fmin(100.0 * h, h1), fabs(tend - t));
        }
    }
    while (next < nt) {
        double hs, tnew;
        if (st->n_steps + st->n_rejected >= max_steps) {
            return MODEL_TOO_MANY_STEPS;
        }
        hmin = 10.0 * MODEL_EPS * fmax(fabs(t), 1e-300);
        if (h < hmin) {
            return fail ? fail : MODEL_STEP_UNDERFLOW;
        }
        tnew = t + dir * h;
        if (dir * (tnew - tend) >= 0.0) {
            tnew = tend;
        }
        hs = tnew - t;  /* signed */
        code = 0;
        for (s = 1; s <= 12 && code == 0; ++s) {
            /* stages 1-11, then s = 12: the solution y and its f (the next step's k0) */
            model_ksum_(a[s], s, k, hs, dy);
            for (i = 0; i < MODEL_V_DIM; ++i) {
                y[i] = x[i] + dy[i];
            }
            code = model_eval_(MODEL_T(s == 12 ? tnew : t + c[s] * hs, )y, u, p, k[s], st);
        }
        if (code == MODEL_SINGULAR || code == MODEL_NONFINITE) {
            /* a stage left the domain: the step was too long, or the motion ends here */
            fail = code;
            st->n_rejected++;
            rejected = 1;
            h = 0.25 * fabs(hs);
            continue;
        }
        if (code != 0) {
            return code;
        }
        e3n = e5n = 0.0;
        for (i = 0; i < MODEL_V_DIM; ++i) {
            s3 = s5 = 0.0;
            for (j = 0; j < 13; ++j) {
                s3 += e3[j] * k[j][i];
                s5 += e5[j] * k[j][i];
            }
            sc[i] = atol + rtol * fmax(fabs(x[i]), fabs(y[i]));
            e3n += (s3 / sc[i]) * (s3 / sc[i]);
            e5n += (s5 / sc[i]) * (s5 / sc[i]);
        }
        err = (e3n == 0.0 && e5n == 0.0) ? 0.0 : fabs(hs) * e5n / sqrt((e5n + 0.01 * e3n) * MODEL_V_DIM);
        if (!(err <= 1.0)) {
            /* rejected (also when err is NaN) */
            st->n_rejected++;
            rejected = 1;
            h = fabs(hs) * (err < HUGE_VAL ? fmax(0.2, 0.9 * pow(err, -0.125)) : 0.2);
            continue;
        }
        /* accepted: the output times inside the step from the dense output */
        if (next < nt && dir * (tt[next] - tnew) < 0.0) {
            double F[7][MODEL_V_DIM];
            int r;
            for (s = 13; s < 16 && code == 0; ++s) {
                model_ksum_(a[s], s, k, hs, sc);
                for (i = 0; i < MODEL_V_DIM; ++i) {
                    sc[i] += x[i];
                }
                code = model_eval_(MODEL_T(t + c[s] * hs, )sc, u, p, k[s], st);
            }
            if (code != 0) {
                return code;
            }
            for (i = 0; i < MODEL_V_DIM; ++i) {
                F[0][i] = dy[i];
                F[1][i] = hs * k[0][i] - dy[i];
                F[2][i] = 2.0 * dy[i] - hs * (k[12][i] + k[0][i]);
            }
            for (r = 0; r < 4; ++r) {
                model_ksum_(dd[r], 16, k, hs, F[3 + r]);
            }
            for (; next < nt && dir * (tt[next] - tnew) < 0.0; ++next) {
                const double th = (tt[next] - t) / hs, th1 = 1.0 - th;
                double *out = X + next * MODEL_V_DIM;
                for (i = 0; i < MODEL_V_DIM; ++i) {
                    double v = 0.0;
                    for (r = 6; r >= 0; --r) {
                        v = (v + F[r][i]) * ((6 - r) % 2 == 0 ? th : th1);
                    }
                    out[i] = x[i] + v;
                }
            }
        }
        model_add_(x, cmp, dy);
        t = tnew;
        st->n_steps++;
        st->t = t;
        model_copy_(st->x, x);
        for (; next < nt && tt[next] == t; ++next) {
            model_copy_(X + next * MODEL_V_DIM, x);
        }
        model_copy_(k[0], k[12]);
        fac = err == 0.0 ? 10.0 : fmin(10.0, 0.9 * pow(err, -0.125));
        h = fabs(hs) * (rejected ? fmin(1.0, fac) : fac);
        rejected = 0;
        fail = 0;
    }
    return MODEL_OK;
}

int model_integrate_grid(int method, int nt, const double *t, double h, double rtol, double atol,
                              long max_steps, const double *x0, const double *u, const model_params *p,
                              double *X, model_integrate_stats *stats)
{
    model_integrate_stats local;
    model_integrate_stats *st = stats ? stats : &local;
    int i, j, code;
    st->t = 0.0;
    st->n_rhs = st->n_steps = st->n_rejected = st->n_iter = st->n_newton = 0;
    for (i = 0; i < MODEL_V_DIM; ++i) {
        st->x[i] = NAN;
    }
    if (!t || !x0 || !X || nt < 1 || !isfinite(t[0])) {
        return MODEL_BAD_ARGUMENT;
    }
    for (j = 1; j < nt; ++j) {
        /* finite and monotone, one direction */
        if (!isfinite(t[j]) || (t[j] - t[j - 1]) * (t[nt - 1] - t[0]) < 0.0) {
            return MODEL_BAD_ARGUMENT;
        }
    }
    if (method == MODEL_DOP853) {
        if (!(rtol >= 0.0 && atol >= 0.0 && rtol + atol > 0.0 && rtol < HUGE_VAL && atol < HUGE_VAL) || isnan(h)) {
            return MODEL_BAD_ARGUMENT;
        }
#if MODEL_CANONICAL
    } else if (method == MODEL_RK4 || method == MODEL_GAUSS2 || method == MODEL_GAUSS2_FIXED               || method == MODEL_GAUSS2_SYMPLECTIC) {
#else
    } else if (method == MODEL_RK4 || method == MODEL_GAUSS2 || method == MODEL_GAUSS2_FIXED) {
#endif
        if (!(h != 0.0 && fabs(h) < HUGE_VAL)) {
            return MODEL_BAD_ARGUMENT;
        }
    } else {
        return MODEL_BAD_ARGUMENT;
    }
#if MODEL_HAS_PARAMS
    if (!p) {
        return MODEL_NO_PARAMS;
    }
#else
    (void)p;
#endif

    if (!model_all_finite_(x0, MODEL_V_DIM)) {
        return MODEL_NONFINITE;
    }
    for (i = nt * MODEL_V_DIM - 1; i >= MODEL_V_DIM; --i) {
        X[i] = NAN;  /* rows not reached stay NaN */
    }
    model_copy_(X, x0);
    model_copy_(st->x, x0);
    st->t = t[0];
    if (max_steps <= 0) {
        max_steps = MODEL_INTEGRATE_MAX_STEPS;
    }
    if (method == MODEL_DOP853) {
        code = model_dop853_(nt, t, h, rtol, atol, max_steps, u, p, X, st);
    } else {
        code = model_fixed_(method, nt, t, h, max_steps, u, p, X, st);
    }
    return code;
}

int model_integrate_batch(int method, int nb, int nt, const double *t, double h, double rtol, double atol,
                               long max_steps, const double *x0, const double *u, long u_stride,
                               const model_params *p, long p_stride, double *X, int *codes)
{
    int b, failed = 0;
    if (nb < 0 || !x0 || !X || !codes) {
        return -MODEL_BAD_ARGUMENT;
    }
    for (b = 0; b < nb; ++b) {
        codes[b] = model_integrate_grid(method, nt, t, h, rtol, atol, max_steps, x0 + (long)b * MODEL_V_DIM,
                                             u ? u + (long)b * u_stride : 0, p ? p + (long)b * p_stride : 0,
                                             X + (long)b * (nt > 0 ? nt : 0) * MODEL_V_DIM, 0);
        failed += codes[b] != MODEL_OK;
    }
    return failed;
}

int model_integrate(int method, double t0, double t1, double h, double rtol, double atol,
                         const double *x0, const double *u, const model_params *p, double *x1, long *n_rhs)
{
    model_integrate_stats st;
    double tt[2], X[MODEL_V_2DIM];
    int code;
    tt[0] = t0;
    tt[1] = t1;
    code = model_integrate_grid(method, 2, tt, h, rtol, atol, 0, x0, u, p, X, &st);
    if (x1) {
        model_copy_(x1, code == 0 ? X + MODEL_V_DIM : st.x);
    }
    if (n_rhs) {
        *n_rhs = st.n_rhs;
    }
    return code;
}
