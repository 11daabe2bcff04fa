/* RK4 of SYS_L trajectories in lock-step: their output times, step, u and p shared, their states
 * side by side (x[i * SYS_L + l] is component i of lane l), so that every statement of a step is
 * a loop over the lanes that a compiler vectorises, and the right side is sys_rhs_lanes_
 (the model's right side printed for SYS_L lanes).  Each lane takes exactly the steps,
 * operations and checks that one trajectory takes alone in model_fixed_, in the same order, so its
 * bits do not depend on SYS_L: kernels/integrate.c prints it for MODEL_V_LANES lanes (a batch's)
 * and for one (a single MODEL_RK4_LANES call), and a trajectory of a batch is the single call's bit
 * for bit.  Compiled on its own (the preamble), it is the batch's instance. */
#include "model_stub.h"
#ifndef SYS_L
#define SYS_L MODEL_V_LANES
#define sys_rk4_lanes_ model_rk4_lanes_
#define sys_rhs_lanes_ model_rhs_lanes_
#define model_nsteps_ model_nsteps_stub_
MODEL_FN long model_nsteps_stub_(double ta, double tb, double h);  /* kernels/integrate.c's */
#endif
/* @kernel */
/* RK4 over the output times tt[0..nt-1] (steps as model_fixed_ takes them) for SYS_L
 * trajectories: lane l starts from row 0 of X[l] and fills its rows j < nt; code[l] is its
 * result, st[l] its statistics (and last finite state) when st is not NULL.  own: the sines and
 * cosines from kernels/trig.c (MODEL_RK4_LANES), else libm's (MODEL_RK4, model_fixed_'s bits). */
MODEL_FN static void sys_rk4_lanes_(int own, int nt, const double *tt, double h, long max_steps, const double *u,
                           const model_params *p, double *const *X, model_integrate_stats *const *st, int *code)
{
    static const double cs[3] = {0.5, 0.5, 1.0};
    double x[MODEL_V_DIM * SYS_L], cmp[MODEL_V_DIM * SYS_L], y[MODEL_V_DIM * SYS_L], k[4][MODEL_V_DIM * SYS_L], fin[SYS_L];
    int fail[SYS_L], sc[SYS_L], nev[SYS_L], live[SYS_L];
    int i, j, l, s, bad, nlive = SYS_L;
    long kk, m, steps = 0;
    for (l = 0; l < SYS_L; ++l) {
        for (i = 0; i < MODEL_V_DIM; ++i) {
            x[i * SYS_L + l] = X[l][i];
            cmp[i * SYS_L + l] = 0.0;
        }
        code[l] = MODEL_OK;
        live[l] = 1;
    }
    for (j = 1; j < nt && nlive > 0; ++j) {
        const double ta = tt[j - 1], hs = (tt[j] - ta) / (double)(m = model_nsteps_(ta, tt[j], h));
        for (kk = 0; kk < m && nlive > 0; ++kk) {
#if MODEL_TIME_DEPENDENT
            const double tk = ta + (double)kk * hs;
#endif
            if (steps >= max_steps) {
                for (l = 0; l < SYS_L; ++l) {
                    code[l] = live[l] ? MODEL_TOO_MANY_STEPS : code[l];
                    live[l] = 0;
                }
                nlive = 0;
                break;
            }
            /* the four stages; a lane's first failing stage ends it (fail[l] its code, nev[l] the
             * evaluations it made, as one trajectory alone stops at that stage) */
            sys_rhs_lanes_(MODEL_T(tk, )own, x, u, p, k[0], fail);
            for (l = 0; l < SYS_L; ++l) {
                nev[l] = 1;
            }
            for (s = 1; s < 4; ++s) {
                for (i = 0; i < MODEL_V_DIM * SYS_L; ++i) {
                    y[i] = x[i] + cs[s - 1] * hs * k[s - 1][i];
                }
                sys_rhs_lanes_(MODEL_T(tk + cs[s - 1] * hs, )own, y, u, p, k[s], sc);
                for (l = 0; l < SYS_L; ++l) {
                    if (fail[l] == MODEL_OK) {
                        fail[l] = sc[l];
                        nev[l] = s + 1;
                    }
                }
            }
            /* x + dx compensated (model_add_'s operations) into y and k[0] until each lane is
             * known to go on */
            for (i = 0; i < MODEL_V_DIM * SYS_L; ++i) {
                const double dx = hs / 6.0 * (k[0][i] + 2.0 * (k[1][i] + k[2][i]) + k[3][i]);
                const double yy = dx + cmp[i];
                const double sum = x[i] + yy;
                y[i] = (x[i] - sum) + yy;
                k[0][i] = sum;
            }
            ++steps;
            /* every lane live, no stage failed, the new state finite: the common step */
            for (l = 0; l < SYS_L; ++l) {
                fin[l] = 0.0;  /* 0 when lane l's new state is finite, NaN otherwise */
            }
            for (i = 0; i < MODEL_V_DIM; ++i) {
                for (l = 0; l < SYS_L; ++l) {
                    fin[l] += k[0][i * SYS_L + l] - k[0][i * SYS_L + l];
                }
            }
            bad = nlive != SYS_L;
            for (l = 0; l < SYS_L; ++l) {
                bad |= fail[l] != MODEL_OK || !(fin[l] == 0.0);
            }
            if (!bad) {
                for (i = 0; i < MODEL_V_DIM * SYS_L; ++i) {
                    x[i] = k[0][i];
                    cmp[i] = y[i];
                }
            }
            for (l = 0; l < SYS_L && (st || bad); ++l) {
                if (!live[l]) {
                    continue;
                }
                if (st) {
                    st[l]->n_rhs += nev[l];
                }
                if (fail[l] == MODEL_OK && fin[l] == 0.0) {
                    for (i = 0; bad && i < MODEL_V_DIM; ++i) {
                        x[i * SYS_L + l] = k[0][i * SYS_L + l];
                        cmp[i * SYS_L + l] = y[i * SYS_L + l];
                    }
                    if (st) {
                        st[l]->n_steps++;
                        st[l]->t = kk + 1 == m ? tt[j] : ta + (double)(kk + 1) * hs;
                        for (i = 0; i < MODEL_V_DIM; ++i) {
                            st[l]->x[i] = x[i * SYS_L + l];
                        }
                    }
                } else {
                    code[l] = fail[l] != MODEL_OK ? fail[l] : MODEL_NONFINITE;  /* st keeps the last finite state */
                    live[l] = 0;
                    --nlive;
                }
            }
        }
        for (l = 0; l < SYS_L; ++l) {
            if (live[l]) {
                for (i = 0; i < MODEL_V_DIM; ++i) {
                    X[l][j * MODEL_V_DIM + i] = x[i * SYS_L + l];
                }
            }
        }
    }
}
