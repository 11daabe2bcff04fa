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
 *   RK4     classical Runge-Kutta, order 4, fixed step.  A batch runs it MODEL_V_LANES
 *           trajectories at a time in lanes where the model has them (kernels/rk4_lanes.c), with
 *           the same operations, so each is the single call's bit for bit.
 *   RK4_LANES  the same with the lanes' own sine and cosine (kernels/trig.c, within 1 ulp of
 *           libm's, vectorised): a batch's lanes twice as fast again, a single call slower (it is
 *           the one-lane case); RK4 itself where the model has no lanes.
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

MODEL_FN static int model_eval_(MODEL_T(double t, )const double *x, const double *u, const model_params *p, double *xdot,
                            model_integrate_stats *st)
{
    st->n_rhs++;
    return model_rhs(MODEL_T_OR(t, 0.0), x, u, p, xdot);
}

#if MODEL_CANONICAL
/* GAUSS2_SYMPLECTIC's right side: Hamilton's equations in y = (phi, p), phi' = M^-1 (p - k(phi)),
 * p' = model_pdot.  One call costs MODEL_V_OPS_VELOCITIES + MODEL_V_OPS_PDOT ops. */
MODEL_FN static int model_eval_canonical_(const double *y, const double *u, const model_params *p, double *ydot,
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
MODEL_FN static void model_to_state_(const double *y, const model_params *p, double *x)
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
/* DOP853 of the state x (kernels/dop853.c; x += dx compensated, copies of the state) */
#define SYS_DIM MODEL_V_DIM
#define sys_add_ model_add_
#define sys_copy_ model_copy_
#define sys_ksum_ model_ksum_
#define sys_dop853_ model_dop853_
#define sys_eval_ model_eval_
#include "dop853.c"
#undef SYS_DIM
#undef sys_add_
#undef sys_copy_
#undef sys_ksum_
#undef sys_dop853_
#undef sys_eval_

/* DOP853's tolerances: finite, not negative, not both zero. */
MODEL_FN static int model_tolerances_ok_(double rtol, double atol)
{
    return rtol >= 0.0 && atol >= 0.0 && rtol + atol > 0.0 && rtol < HUGE_VAL && atol < HUGE_VAL;
}

/* The round-off level of GAUSS2's stage corrections at the state x (see GAUSS_FLOOR). */
MODEL_FN static double model_floor_(const double *x)
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
MODEL_FN static long model_nsteps_(double ta, double tb, double h)
{
    const double r = fabs(tb - ta) / fabs(h);
    double m = ceil(r * (1.0 - 1e-10));
    return m < 1.0 ? 1L : (long)m;
}

#if MODEL_LANES
/* RK4 in lanes (kernels/rk4_lanes.c): MODEL_V_LANES for a batch's trajectories, one for a single
 * RK4_LANES call; the model's right side for lanes is printed before this file (model_rhs_lanes_,
 * model_rhs_lane_). */
#define SYS_L 1
#define sys_rk4_lanes_ model_rk4_lane_
#define sys_rhs_lanes_ model_rhs_lane_
#include "rk4_lanes.c"
#undef SYS_L
#undef sys_rk4_lanes_
#undef sys_rhs_lanes_

#define SYS_L MODEL_V_LANES
#define sys_rk4_lanes_ model_rk4_lanes_
#define sys_rhs_lanes_ model_rhs_lanes_
#include "rk4_lanes.c"
#undef SYS_L
#undef sys_rk4_lanes_
#undef sys_rhs_lanes_

#endif
/* One classical RK4 step of size h from x: dx = the increment.  (inline: gcc -O3 inlines
 * model_fixed_ into NAME_integrate_grid, and this step then into neither without the hint, which
 * made a single RK4 call 1.2x slower at -O3 -march=native.) */
MODEL_FN static inline int model_rk4_step_(MODEL_T(double t0, )const double *x, double h, const double *u, const model_params *p,
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
MODEL_FN static int model_lu_(double *A, int *piv, int m)
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

MODEL_FN static void model_lu_solve_(const double *A, const int *piv, int m, double *b)
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
MODEL_FN static int model_gauss2_newton_(MODEL_T(double t0, )const double *x, double h, const double *u, const model_params *p,
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
MODEL_FN static int model_canonical_newton_(const double *y, double h, const double *u, const model_params *p,
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
MODEL_FN static int model_gauss2_step_(MODEL_T(double t0, )const double *x, double h, double hp, int method, const double *u,
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
MODEL_FN static int model_fixed_(int method, int nt, const double *tt, double h, long max_steps,
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

/* NAME_integrate_grid's checks and start: the stats reset, the arguments checked, X's row 0 set
 * and the others NaN, *max_steps the budget.  MODEL_OK when the integration can start.  inline:
 * gcc -O3 otherwise calls it, and one RK4 step by NAME_integrate costs ~100 instructions more
 * than before it was split off (bench/releases.py --instructions). */
MODEL_FN static inline int model_grid_start_(int method, int nt, const double *t, double h, double rtol, double atol,
                                  long *max_steps, const double *x0, const model_params *p, double *X,
                                  model_integrate_stats *st)
{
    int i, j;
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
        if (!model_tolerances_ok_(rtol, atol) || isnan(h)) {
            return MODEL_BAD_ARGUMENT;
        }
#if MODEL_CANONICAL
    } else if (method == MODEL_RK4 || method == MODEL_RK4_LANES || method == MODEL_GAUSS2 || method == MODEL_GAUSS2_FIXED
               || method == MODEL_GAUSS2_SYMPLECTIC) {
#else
    } else if (method == MODEL_RK4 || method == MODEL_RK4_LANES || method == MODEL_GAUSS2 || method == MODEL_GAUSS2_FIXED) {
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
    if (*max_steps <= 0) {
        *max_steps = MODEL_INTEGRATE_MAX_STEPS;
    }
    return MODEL_OK;
}

/* NAME_integrate_grid, inline in NAME_integrate too (a single step's call costs what it did). */
MODEL_FN static inline int model_grid_(int method, int nt, const double *t, double h, double rtol, double atol,
                                   long max_steps, const double *x0, const double *u, const model_params *p,
                                   double *X, model_integrate_stats *stats)
{
    model_integrate_stats local = {0.0, {0.0}, 0, 0, 0, 0, 0};  /* (every field is set below; initialised for the analysers) */
    model_integrate_stats *st = stats ? stats : &local;
    int code = model_grid_start_(method, nt, t, h, rtol, atol, &max_steps, x0, p, X, st);
    if (code != MODEL_OK) {
        return code;
    }
    if (method == MODEL_DOP853) {
        return model_dop853_(nt, t, h, rtol, atol, max_steps, u, p, X, st);
    }
#if MODEL_LANES
    if (method == MODEL_RK4_LANES) {
        double *Xl[1];
        model_integrate_stats *sl[1];
        Xl[0] = X;
        sl[0] = st;
        model_rk4_lane_(1, nt, t, h, max_steps, u, p, Xl, sl, &code);
        return code;
    }
#endif
    return model_fixed_(method == MODEL_RK4_LANES ? MODEL_RK4 : method, nt, t, h, max_steps, u, p, X, st);
}

MODEL_FN int model_integrate_grid(int method, int nt, const double *t, double h, double rtol, double atol,
                              long max_steps, const double *x0, const double *u, const model_params *p,
                              double *X, model_integrate_stats *stats)
{
    return model_grid_(method, nt, t, h, rtol, atol, max_steps, x0, u, p, X, stats);
}

#if MODEL_LANES
/* NAME_integrate_batch's RK4 (own 0) or RK4_LANES (own 1) when every trajectory has the same u and
 * p: MODEL_V_LANES trajectories at a time in lanes, the last ones alone, each the single call's
 * bits. */
MODEL_FN static int model_rk4_batch_(int own, int nb, int nt, const double *t, double h, long max_steps, const double *x0,
                                 const double *u, const model_params *p, double *X, int *codes)
{
    model_integrate_stats st;
    double *Xl[MODEL_V_LANES];
    int lane[MODEL_V_LANES], lc[MODEL_V_LANES], b, i, g = 0, failed = 0;
    long budget = max_steps;
    for (b = 0; b < nb; ++b) {
        double *Xb = X + (long)b * (nt > 0 ? nt : 0) * MODEL_V_DIM;
        budget = max_steps;
        codes[b] = model_grid_start_(MODEL_RK4, nt, t, h, 0.0, 0.0, &budget, x0 + (long)b * MODEL_V_DIM, p, Xb, &st);
        if (codes[b] != MODEL_OK) {
            continue;
        }
        lane[g] = b;
        Xl[g] = Xb;
        ++g;
        if (g == MODEL_V_LANES) {
            model_rk4_lanes_(own, nt, t, h, budget, u, p, Xl, 0, lc);
            for (i = 0; i < MODEL_V_LANES; ++i) {
                codes[lane[i]] = lc[i];
            }
            g = 0;
        }
    }
    for (i = 0; i < g; ++i) {
        if (own) {
            model_rk4_lane_(1, nt, t, h, budget, u, p, Xl + i, 0, codes + lane[i]);
        } else {
            codes[lane[i]] = model_integrate_grid(MODEL_RK4, nt, t, h, 0.0, 0.0, max_steps, x0 + (long)lane[i] * MODEL_V_DIM, u,
                                                       p, Xl[i], 0);
        }
    }
    for (b = 0; b < nb; ++b) {
        failed += codes[b] != MODEL_OK;
    }
    return failed;
}

#endif
MODEL_FN int model_integrate_batch(int method, int nb, int nt, const double *t, double h, double rtol, double atol,
                               long max_steps, const double *x0, const double *u, long u_stride,
                               const model_params *p, long p_stride, double *X, int *codes)
{
    int b, failed = 0;
    if (nb < 0 || !x0 || !X || !codes) {
        return -MODEL_BAD_ARGUMENT;
    }
#if MODEL_LANES
    if ((method == MODEL_RK4 || method == MODEL_RK4_LANES) && (!u || u_stride == 0) && (!p || p_stride == 0)) {
        return model_rk4_batch_(method == MODEL_RK4_LANES, nb, nt, t, h, max_steps, x0, u, p, X, codes);
    }
#endif
    for (b = 0; b < nb; ++b) {
        codes[b] = model_integrate_grid(method, nt, t, h, rtol, atol, max_steps, x0 + (long)b * MODEL_V_DIM,
                                             u ? u + (long)b * u_stride : 0, p ? p + (long)b * p_stride : 0,
                                             X + (long)b * (nt > 0 ? nt : 0) * MODEL_V_DIM, 0);
        failed += codes[b] != MODEL_OK;
    }
    return failed;
}

MODEL_FN int model_integrate(int method, double t0, double t1, double h, double rtol, double atol,
                         const double *x0, const double *u, const model_params *p, double *x1, long *n_rhs)
{
    model_integrate_stats st;
    double tt[2], X[MODEL_V_2DIM];
    int code;
    tt[0] = t0;
    tt[1] = t1;
    code = model_grid_(method, 2, tt, h, rtol, atol, 0, x0, u, p, X, &st);
    if (x1) {
        model_copy_(x1, code == 0 ? X + MODEL_V_DIM : st.x);
    }
    if (n_rhs) {
        *n_rhs = st.n_rhs;
    }
    return code;
}
/* ---------------------------------------------------------------------------------------
 * The discrete-time model: one classical RK4 step of length h with u held over it,
 *   xn = x + h/6 (k1 + 2 k2 + 2 k3 + k4),
 * the step of NAME_integrate's RK4 (bit for bit), and its exact Jacobian.
 * --------------------------------------------------------------------------------------- */
MODEL_FN static int model_step_args_(double t, const double *x, const model_params *p, double h, const double *xn)
{
    if (!x || !xn || !isfinite(t) || !isfinite(h)) {
        return MODEL_BAD_ARGUMENT;
    }
#if MODEL_HAS_PARAMS
    if (!p) {
        return MODEL_NO_PARAMS;
    }
#else
    (void)p;
#endif
    return MODEL_OK;
}

MODEL_FN int model_step(double t, const double *x, const double *u, const model_params *p, double h, double *xn)
{
    model_integrate_stats st = {0.0, {0.0}, 0, 0, 0, 0, 0};
    double dx[MODEL_V_DIM];
    int i, code;
    if ((code = model_step_args_(t, x, p, h, xn)) != MODEL_OK
        || (code = model_rk4_step_(MODEL_T(t, )x, h, u, p, dx, &st)) != MODEL_OK) {
        for (i = 0; xn && i < MODEL_V_DIM; ++i) {
            xn[i] = NAN;
        }
        return code;
    }
    for (i = 0; i < MODEL_V_DIM; ++i) {
        xn[i] = x[i] + dx[i];
    }
    return MODEL_OK;
}
#if MODEL_VARIATIONAL

/* A stage's point y = x + a h kp and dy = dy/dw (2n x MODEL_V_COLS, row-major; w = (x, u, h), and t
 * last when the model reads t) from the stage before (kp, dkp); the first stage's (kp NULL): y = x,
 * dy = [I 0 0]. */
MODEL_FN static void model_step_point_(const double *x, double h, double a, const double *kp, const double *dkp,
                                   double *y, double *dy)
{
    int i, c;
    for (i = 0; i < MODEL_V_DIM; ++i) {
        y[i] = x[i] + (kp ? a * h * kp[i] : 0.0);
        for (c = 0; c < MODEL_V_COLS; ++c) {
            dy[i * MODEL_V_COLS + c] = (c == i ? 1.0 : 0.0)
                + (kp ? a * h * dkp[i * MODEL_V_COLS + c] + (c == MODEL_V_HCOL ? a * kp[i] : 0.0) : 0.0);
        }
    }
}

/* A stage of the step's Jacobian: k = f(y) and, with dy = dy/dw (2n x MODEL_V_COLS, row-major),
 * dk = A dy + [0 B 0], A = [[0, I], [Dq, Dv]] and B = [[0], [Du]] the exact derivatives of
 * model_qdd_derivatives at y (written to the caller's Dq, Dv, Du); a model that reads t adds
 * [0; dphi''/dt] times the derivative of the stage's time t + ta h (ta: its node), in t and h. */
MODEL_FN static int model_step_stage_(MODEL_T(double t, double ta, )const double *y, const double *dy, const double *u,
                                  const model_params *p, double *k, double *dk, double *Dq, double *Dv, double *Du)
{
    int i, j, c, code;
    if ((code = model_qdd_derivatives(MODEL_T(t, )y, u, p, k + MODEL_V_N, Dq, Dv, Du)) != MODEL_OK) {  /* (Du: n x 1 unused when nu = 0) */
        return code;
    }
    for (i = 0; i < MODEL_V_N; ++i) {
        k[i] = y[MODEL_V_N + i];
    }
    for (c = 0; c < MODEL_V_COLS; ++c) {
        for (i = 0; i < MODEL_V_N; ++i) {
            double s = c >= MODEL_V_DIM && c < MODEL_V_DIM + MODEL_V_NU ? Du[i * MODEL_V_NU + c - MODEL_V_DIM] : 0.0;
            dk[i * MODEL_V_COLS + c] = dy[(MODEL_V_N + i) * MODEL_V_COLS + c];
            for (j = 0; j < MODEL_V_N; ++j) {
                s += Dq[i * MODEL_V_N + j] * dy[j * MODEL_V_COLS + c] + Dv[i * MODEL_V_N + j] * dy[(MODEL_V_N + j) * MODEL_V_COLS + c];
            }
            dk[(MODEL_V_N + i) * MODEL_V_COLS + c] = s;
        }
    }
#if MODEL_TIME_DEPENDENT
    {
        double Dt[MODEL_V_N];
        if ((code = model_time_derivative(t, y, u, p, 0, Dt)) != MODEL_OK) {
            return code;
        }
        for (i = 0; i < MODEL_V_N; ++i) {
            dk[(MODEL_V_N + i) * MODEL_V_COLS + MODEL_V_COLS - 1] += Dt[i];
            dk[(MODEL_V_N + i) * MODEL_V_COLS + MODEL_V_HCOL] += ta * Dt[i];
        }
    }
#endif
    return MODEL_OK;
}

/* xn and J = dxn/dw, w = (x, u, h[, t]) (2n x MODEL_V_COLS, row-major), by the chain rule through the
 * four stages */
MODEL_FN static int model_step_jacobian_(double t, const double *x, const double *u, const model_params *p, double h,
                                     double *xn, double *J)
{
    static const double a[4] = {0.0, 0.5, 0.5, 1.0}, b[4] = {1.0, 2.0, 2.0, 1.0};
    double y[MODEL_V_DIM], k[MODEL_V_DIM], s[MODEL_V_DIM];
    double dy[MODEL_V_DIM * MODEL_V_COLS], dk[MODEL_V_DIM * MODEL_V_COLS], ds[MODEL_V_DIM * MODEL_V_COLS];
    double Dq[MODEL_V_NN], Dv[MODEL_V_NN], Du[MODEL_V_NNU1];
    int i, c, st, code;
#if MODEL_TIME_DEPENDENT
#else
    (void)t;  /* (an autonomous model) */
#endif
    for (i = 0; i < MODEL_V_DIM; ++i) {
        s[i] = 0.0;
        for (c = 0; c < MODEL_V_COLS; ++c) {
            ds[i * MODEL_V_COLS + c] = 0.0;
        }
    }
    model_step_point_(x, h, 0.0, 0, 0, y, dy);
    for (st = 0; st < 4; ++st) {
        if ((code = model_step_stage_(MODEL_T(t + a[st] * h, a[st], )y, dy, u, p, k, dk, Dq, Dv, Du)) != MODEL_OK) {
            return code;
        }
        for (i = 0; i < MODEL_V_DIM; ++i) {
            s[i] += b[st] * k[i];
            for (c = 0; c < MODEL_V_COLS; ++c) {
                ds[i * MODEL_V_COLS + c] += b[st] * dk[i * MODEL_V_COLS + c];
            }
        }
        if (st < 3) {
            model_step_point_(x, h, a[st + 1], k, dk, y, dy);
        }
    }
    for (i = 0; i < MODEL_V_DIM; ++i) {
        xn[i] = x[i] + h / 6.0 * s[i];
        for (c = 0; c < MODEL_V_COLS; ++c) {
            J[i * MODEL_V_COLS + c] = (c == i ? 1.0 : 0.0) + h / 6.0 * ds[i * MODEL_V_COLS + c]
                                    + (c == MODEL_V_HCOL ? s[i] / 6.0 : 0.0);
        }
    }
    return MODEL_OK;
}

MODEL_FN int model_step_jacobian(double t, const double *x, const double *u, const model_params *p, double h, double *xn,
                             double *Ad, double *Bd, double *xn_h MODEL_T(, double *xn_t))
{
    double J[MODEL_V_DIM * MODEL_V_COLS], xs[MODEL_V_DIM];
    double *out = xn ? xn : xs;
    int i, c, code;
    if ((code = model_step_args_(t, x, p, h, out)) != MODEL_OK) {
        return code;
    }
    if (!model_all_finite_(x, MODEL_V_DIM)) {
        return MODEL_NONFINITE;
    }
    if ((code = model_step_jacobian_(t, x, u, p, h, out, J)) != MODEL_OK) {
        return code;
    }
    for (i = 0; i < MODEL_V_DIM; ++i) {
        for (c = 0; Ad && c < MODEL_V_DIM; ++c) {
            Ad[i * MODEL_V_DIM + c] = J[i * MODEL_V_COLS + c];
        }
        for (c = 0; Bd && c < MODEL_V_NU; ++c) {
            Bd[i * MODEL_V_NU + c] = J[i * MODEL_V_COLS + MODEL_V_DIM + c];
        }
        if (xn_h) {
            xn_h[i] = J[i * MODEL_V_COLS + MODEL_V_HCOL];
        }
#if MODEL_TIME_DEPENDENT
        if (xn_t) {
            xn_t[i] = J[i * MODEL_V_COLS + MODEL_V_COLS - 1];
        }
#endif
    }
    return model_all_finite_(out, MODEL_V_DIM) ? MODEL_OK : MODEL_NONFINITE;
}
#if MODEL_HESSIAN

/* ---------------------------------------------------------------------------------------
 * The second derivatives an optimiser's exact Hessian asks for: of lam . F, F the RK4 step with
 * w = (x, u, h), and t last when the model reads t, assembled from the step's own operations.  For a program of nodes v = phi(args)
 * the Hessian of lam . F is the sum over its nodes of J_args' (vbar . phi'') J_args, J_args the
 * derivative of the node's arguments in w and vbar the adjoint of its value (forward over
 * reverse, written out).  The nodes: the stages k_s = f(y_s, u[, t + a_s h]), whose curvature is
 * model_rhs_hessian's at the stage's adjoint kappa_s, the stage points y_s = x + a_s h k_{s-1}
 * and the step x + h/6 sum b_s k_s, bilinear in h and k.  Every first derivative is the exact
 * Jacobian of model_qdd_derivatives, every second one model_rhs_hessian's.
 * --------------------------------------------------------------------------------------- */

/* Z_s = d(y_s, u[, t + a_s h])/dw, entry (j, c): a stage's arguments in w */
MODEL_FN static double model_stage_z_(const double *Ys, double as, int j, int c)
{
    if (j < MODEL_V_DIM) {
        return Ys[j * MODEL_V_COLS + c];
    }
    if (j < MODEL_V_DIM + MODEL_V_NU) {
        return c == j ? 1.0 : 0.0;
    }
    return c == MODEL_V_COLS - 1 ? 1.0 : c == MODEL_V_HCOL ? as : 0.0;
}

MODEL_FN int model_step_hessian(double t, const double *x, const double *u, const model_params *p, double h,
                            const double *lam, double *H)
{
    static const double a[4] = {0.0, 0.5, 0.5, 1.0}, b[4] = {1.0, 2.0, 2.0, 1.0};
    double y[4][MODEL_V_DIM], k[4][MODEL_V_DIM], Y[4][MODEL_V_DIM * MODEL_V_COLS], K[4][MODEL_V_DIM * MODEL_V_COLS];
    double Dq[4][MODEL_V_NN], Dv[4][MODEL_V_NN], Du[4][MODEL_V_NNU1];
    double kap[MODEL_V_DIM], ybar[4][MODEL_V_DIM], Hs[MODEL_V_ZDIM * MODEL_V_ZDIM], T[MODEL_V_ZDIM * MODEL_V_COLS];
    double r[MODEL_V_COLS];
    int i, j, c, s, code;
    if ((code = model_step_args_(t, x, p, h, H)) != MODEL_OK) {
        return code;
    }
    if (!lam || !model_all_finite_(lam, MODEL_V_DIM)) {
        return lam ? MODEL_NONFINITE : MODEL_BAD_ARGUMENT;
    }
    if (!model_all_finite_(x, MODEL_V_DIM)) {
        return MODEL_NONFINITE;
    }
    /* forward: the stages, their points' derivatives Y_s = dy_s/dw and theirs K_s = dk_s/dw */
    for (s = 0; s < 4; ++s) {
        model_step_point_(x, h, a[s], s ? k[s - 1] : 0, s ? K[s - 1] : 0, y[s], Y[s]);
        if ((code = model_step_stage_(MODEL_T(t + a[s] * h, a[s], )y[s], Y[s], u, p, k[s], K[s], Dq[s], Dv[s], Du[s])) != MODEL_OK) {
            return code;
        }
    }
    for (i = 0; i < MODEL_V_COLS * MODEL_V_COLS; ++i) {
        H[i] = 0.0;
    }
    /* backward: kappa_s = h/6 b_s lam + a_{s+1} h ybar_{s+1}, ybar_s = A_s' kappa_s; each stage's curvature
     * Z_s' (kappa_s . f)'' Z_s, Z_s = d(y_s, u)/dw */
    for (s = 3; s >= 0; --s) {
        for (i = 0; i < MODEL_V_DIM; ++i) {
            kap[i] = h / 6.0 * b[s] * lam[i] + (s < 3 ? a[s + 1] * h * ybar[s + 1][i] : 0.0);
        }
        for (j = 0; j < MODEL_V_N; ++j) {
            double sq = 0.0, sv = kap[j];
            for (i = 0; i < MODEL_V_N; ++i) {
                sq += Dq[s][i * MODEL_V_N + j] * kap[MODEL_V_N + i];
                sv += Dv[s][i * MODEL_V_N + j] * kap[MODEL_V_N + i];
            }
            ybar[s][j] = sq;
            ybar[s][MODEL_V_N + j] = sv;
        }
        if ((code = model_rhs_hessian(t + a[s] * h, y[s], u, p, kap, Hs)) != MODEL_OK) {
            return code;
        }
        for (i = 0; i < MODEL_V_ZDIM; ++i) {  /* T = Hs Z_s */
            for (c = 0; c < MODEL_V_COLS; ++c) {
                double v = 0.0;
                for (j = 0; j < MODEL_V_ZDIM; ++j) {
                    v += Hs[i * MODEL_V_ZDIM + j] * model_stage_z_(Y[s], a[s], j, c);
                }
                T[i * MODEL_V_COLS + c] = v;
            }
        }
        for (i = 0; i < MODEL_V_COLS; ++i) {  /* H += Z_s' T */
            for (c = 0; c < MODEL_V_COLS; ++c) {
                double v = 0.0;
                for (j = 0; j < MODEL_V_ZDIM; ++j) {
                    v += model_stage_z_(Y[s], a[s], j, i) * T[j * MODEL_V_COLS + c];
                }
                H[i * MODEL_V_COLS + c] += v;
            }
        }
    }
    /* the bilinear nodes: r = sum_s a_s ybar_s' K_{s-1} + sum_s b_s/6 lam' K_s, into H's row and column of h
     * (the stages' times t + a_s h are linear: no curvature) */
    for (c = 0; c < MODEL_V_COLS; ++c) {
        double v = 0.0;
        for (s = 0; s < 4; ++s) {
            for (i = 0; i < MODEL_V_DIM; ++i) {
                v += b[s] / 6.0 * lam[i] * K[s][i * MODEL_V_COLS + c] + (s ? a[s] * ybar[s][i] * K[s - 1][i * MODEL_V_COLS + c] : 0.0);
            }
        }
        r[c] = v;
    }
    for (c = 0; c < MODEL_V_COLS; ++c) {
        H[MODEL_V_HCOL * MODEL_V_COLS + c] += r[c];
        H[c * MODEL_V_COLS + MODEL_V_HCOL] += r[c];
    }
    for (i = 0; i < MODEL_V_COLS; ++i) {  /* symmetric to round-off by construction; exactly so on return */
        for (c = 0; c < i; ++c) {
            H[i * MODEL_V_COLS + c] = H[c * MODEL_V_COLS + i] = 0.5 * (H[i * MODEL_V_COLS + c] + H[c * MODEL_V_COLS + i]);
        }
    }
    return model_all_finite_(H, MODEL_V_COLS * MODEL_V_COLS) ? MODEL_OK : MODEL_NONFINITE;
}
#endif
#endif
#if MODEL_PARAM_DERIVATIVES

/* ---------------------------------------------------------------------------------------
 * The step's derivatives in the symbolic parameters, by the chain rule through the stages:
 * dk/dp = A dy/dp + [0; dphi''/dp], A from model_qdd_derivatives and dphi''/dp from
 * model_param_derivatives at each stage's point (dx/dp = 0 at the start).
 * --------------------------------------------------------------------------------------- */
MODEL_FN int model_step_param_derivatives(double t, const double *x, const double *u, const model_params *p, double h,
                                      double *xn, double *dxn_dp)
{
    static const double a[4] = {0.0, 0.5, 0.5, 1.0}, b[4] = {1.0, 2.0, 2.0, 1.0};
    double y[MODEL_V_DIM], k[MODEL_V_DIM], s[MODEL_V_DIM], xs[MODEL_V_DIM];
    double dy[MODEL_V_DIM * MODEL_V_NP], dk[MODEL_V_DIM * MODEL_V_NP], ds[MODEL_V_DIM * MODEL_V_NP];
    double Dq[MODEL_V_NN], Dv[MODEL_V_NN], Dp[MODEL_V_NNP];
    double *out = xn ? xn : xs;
    int i, j, c, st, code;
    if ((code = model_step_args_(t, x, p, h, out)) != MODEL_OK) {
        return code;
    }
    if (!model_all_finite_(x, MODEL_V_DIM)) {
        return MODEL_NONFINITE;
    }
#if MODEL_TIME_DEPENDENT
#else
    (void)t;  /* (an autonomous model) */
#endif
    for (i = 0; i < MODEL_V_DIM; ++i) {
        y[i] = x[i];
        s[i] = 0.0;
        for (c = 0; c < MODEL_V_NP; ++c) {
            dy[i * MODEL_V_NP + c] = ds[i * MODEL_V_NP + c] = 0.0;
        }
    }
    for (st = 0; st < 4; ++st) {
        if ((code = model_qdd_derivatives(MODEL_T(t + a[st] * h, )y, u, p, k + MODEL_V_N, Dq, Dv, 0)) != MODEL_OK
            || (code = model_param_derivatives(MODEL_T(t + a[st] * h, )y, u, p, 0, Dp)) != MODEL_OK) {
            return code;
        }
        for (i = 0; i < MODEL_V_N; ++i) {
            k[i] = y[MODEL_V_N + i];
            for (c = 0; c < MODEL_V_NP; ++c) {
                double v = Dp[i * MODEL_V_NP + c];
                dk[i * MODEL_V_NP + c] = dy[(MODEL_V_N + i) * MODEL_V_NP + c];
                for (j = 0; j < MODEL_V_N; ++j) {
                    v += Dq[i * MODEL_V_N + j] * dy[j * MODEL_V_NP + c] + Dv[i * MODEL_V_N + j] * dy[(MODEL_V_N + j) * MODEL_V_NP + c];
                }
                dk[(MODEL_V_N + i) * MODEL_V_NP + c] = v;
            }
        }
        for (i = 0; i < MODEL_V_DIM; ++i) {
            s[i] += b[st] * k[i];
            for (c = 0; c < MODEL_V_NP; ++c) {
                ds[i * MODEL_V_NP + c] += b[st] * dk[i * MODEL_V_NP + c];
                if (st < 3) {
                    dy[i * MODEL_V_NP + c] = a[st + 1] * h * dk[i * MODEL_V_NP + c];
                }
            }
            if (st < 3) {
                y[i] = x[i] + a[st + 1] * h * k[i];
            }
        }
    }
    for (i = 0; i < MODEL_V_DIM; ++i) {
        out[i] = x[i] + h / 6.0 * s[i];
        for (c = 0; dxn_dp && c < MODEL_V_NP; ++c) {
            dxn_dp[i * MODEL_V_NP + c] = h / 6.0 * ds[i * MODEL_V_NP + c];
        }
    }
    return model_all_finite_(out, MODEL_V_DIM) ? MODEL_OK : MODEL_NONFINITE;
}
#endif
#if MODEL_VARIATIONAL

/* ---------------------------------------------------------------------------------------
 * The variational equations: y = (x, Phi), Phi the 2n x 2n fundamental matrix (row-major),
 *   x' = f(t, x),   Phi' = A(t, x) Phi,   A = [[0, I], [dqdd/dphi, dqdd/dphidot]],
 * A the exact derivative of the emitted phi'' (model_qdd_derivatives, whose phi'' is x's rate
 * too: one call a stage), integrated by DOP853 with one step-size control over all components,
 * so that Phi(t1) is the tangent map of the emitted dynamics at the tolerances given.
 * --------------------------------------------------------------------------------------- */
MODEL_FN static int model_eval_variational_(MODEL_T(double t, )const double *y, const double *u, const model_params *p,
                                   double *ydot, model_integrate_stats *st)
{
    double dq[MODEL_V_NN], dv[MODEL_V_NN];
    const double *Phi = y + MODEL_V_DIM;
    double *dPhi = ydot + MODEL_V_DIM;
    int i, j, k, code;
    st->n_rhs++;
    if ((code = model_qdd_derivatives(MODEL_T(t, )y, u, p, ydot + MODEL_V_N, dq, dv, 0)) != 0) {
        return code;
    }
    for (i = 0; i < MODEL_V_N; ++i) {
        ydot[i] = y[MODEL_V_N + i];
    }
    /* the upper rows: (d/dt) dphi = dphidot */
    for (i = 0; i < MODEL_V_N * MODEL_V_DIM; ++i) {
        dPhi[i] = Phi[MODEL_V_N * MODEL_V_DIM + i];
    }
    /* the lower rows: (d/dt) dphidot = dqdd/dphi dphi + dqdd/dphidot dphidot */
    for (i = 0; i < MODEL_V_N; ++i) {
        double *row = dPhi + (MODEL_V_N + i) * MODEL_V_DIM;
        for (j = 0; j < MODEL_V_DIM; ++j) {
            row[j] = 0.0;
        }
        for (k = 0; k < MODEL_V_N; ++k) {
            const double a = dq[i * MODEL_V_N + k], b = dv[i * MODEL_V_N + k];
            const double *top = Phi + k * MODEL_V_DIM, *bottom = Phi + (MODEL_V_N + k) * MODEL_V_DIM;
            for (j = 0; j < MODEL_V_DIM; ++j) {
                row[j] += a * top[j] + b * bottom[j];
            }
        }
    }
    return MODEL_OK;
}

/* DOP853 of (x, Phi) (kernels/dop853.c) */
#define SYS_DIM MODEL_V_VDIM
#define sys_add_ model_add_variational_
#define sys_copy_ model_copy_variational_
#define sys_ksum_ model_ksum_variational_
#define sys_dop853_ model_dop853_variational_
#define sys_eval_ model_eval_variational_
#include "dop853.c"
#undef SYS_DIM
#undef sys_add_
#undef sys_copy_
#undef sys_ksum_
#undef sys_dop853_
#undef sys_eval_

MODEL_FN int model_integrate_variational(double t0, double t1, double h, double rtol, double atol,
                                const double *x0, const double *u, const model_params *p,
                                double *x1, double *Phi, model_integrate_stats *stats)
{
    model_integrate_stats local = {0.0, {0.0}, 0, 0, 0, 0, 0};  /* (every field is set below; initialised for the analysers) */
    model_integrate_stats *st = stats ? stats : &local;
    double tt[2], Y[2 * MODEL_V_VDIM];
    int i, code;
    st->t = t0;
    st->n_rhs = st->n_steps = st->n_rejected = st->n_iter = st->n_newton = 0;
    for (i = 0; i < MODEL_V_DIM; ++i) {
        st->x[i] = NAN;
    }
    if (!x0 || !x1 || !Phi || !isfinite(t0) || !isfinite(t1) || isnan(h)
        || !model_tolerances_ok_(rtol, atol)) {
        return MODEL_BAD_ARGUMENT;
    }
#if MODEL_HAS_PARAMS
    if (!p) {
        return MODEL_NO_PARAMS;
    }
#else
    (void)p;
#endif
    if (!model_all_finite_(x0, MODEL_V_DIM) || !model_all_finite_(Phi, MODEL_V_DIM2)) {
        return MODEL_NONFINITE;
    }
    for (i = 0; i < MODEL_V_DIM; ++i) {
        Y[i] = x0[i];
        st->x[i] = x0[i];
    }
    for (i = 0; i < MODEL_V_DIM2; ++i) {
        Y[MODEL_V_DIM + i] = Phi[i];
    }
    code = MODEL_OK;
    if (t1 != t0) {
        tt[0] = t0;
        tt[1] = t1;
        code = model_dop853_variational_(2, tt, h, rtol, atol, MODEL_INTEGRATE_MAX_STEPS, u, p, Y, st);
    }
    if (code != MODEL_OK) {
        for (i = 0; i < MODEL_V_DIM; ++i) {
            x1[i] = st->x[i];  /* the last accepted state */
        }
        for (i = 0; i < MODEL_V_DIM2; ++i) {
            Phi[i] = NAN;
        }
        return code;
    }
    for (i = 0; i < MODEL_V_VDIM; ++i) {
        const double v = t1 != t0 ? Y[MODEL_V_VDIM + i] : Y[i];  /* the row of t1 */
        if (i < MODEL_V_DIM) {
            x1[i] = v;
        } else {
            Phi[i - MODEL_V_DIM] = v;
        }
    }
    return MODEL_OK;
}
#endif
