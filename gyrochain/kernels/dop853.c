/* DOP853, Dormand-Prince 8(5,3) with its 7th-order dense output (Hairer, Norsett, Wanner, Solving
 * ODE I, II.5-II.10, and their Fortran DOP853, whose coefficients and error norm these are), over a
 * system y' = sys_eval_(t, y) of SYS_DIM components whose first MODEL_V_DIM are the model's state x.
 * kernels/integrate.c prints it once per system it integrates (printers/kernels.py: the #define
 * lines before an #include of this file name the instance): the state x itself (model_dop853_),
 * and x with its fundamental matrix (model_dop853_variational_).  Compiled on its own (the
 * preamble below), it is the state's instance. */
#include "model_stub.h"
#ifndef SYS_DIM
#define SYS_DIM MODEL_V_DIM
#define sys_add_ model_add_
#define sys_copy_ model_copy_
#define sys_ksum_ model_ksum_
#define sys_dop853_ model_dop853_
#define sys_eval_ model_eval_stub_
#define MODEL_EPS 2.220446049250313e-16  /* kernels/integrate.c's */
MODEL_FN int model_eval_stub_(MODEL_T(double t, )const double *x, const double *u, const model_params *p, double *xdot,
                     model_integrate_stats *st);
#endif
/* @kernel */
/* x += dx with the running compensation cmp (Kahan): the low part each sum loses is carried on. */
MODEL_FN static void sys_add_(double *x, double *cmp, const double *dx)
{
    int i;
    for (i = 0; i < SYS_DIM; ++i) {
        const double y = dx[i] + cmp[i];
        const double s = x[i] + y;
        cmp[i] = (x[i] - s) + y;
        x[i] = s;
    }
}

MODEL_FN static void sys_copy_(double *dst, const double *src)
{
    int i;
    for (i = 0; i < SYS_DIM; ++i) {
        dst[i] = src[i];
    }
}

/* out = hs sum_{j < count} w_j k_j: a stage point's increment, or a dense-output coefficient. */
MODEL_FN static void sys_ksum_(const double *w, int count, double k[][SYS_DIM], double hs, double *out)
{
    int i, j;
    for (i = 0; i < SYS_DIM; ++i) {
        double acc = 0.0;
        for (j = 0; j < count; ++j) {
            acc += w[j] * k[j][i];
        }
        out[i] = hs * acc;
    }
}

/* DOP853 over the output times tt[0..nt-1] (monotone): steps chosen by the error estimate, output
 * times inside a step from the dense output.  h0 > 0 is the first step, else it is estimated. */
MODEL_FN static int sys_dop853_(int nt, const double *tt, double h0, double rtol, double atol, long max_steps,
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
    double k[16][SYS_DIM], x[SYS_DIM], cmp[SYS_DIM], y[SYS_DIM], dy[SYS_DIM], sc[SYS_DIM];
    const double tend = tt[nt - 1], dir = tend >= tt[0] ? 1.0 : -1.0;
    double t = tt[0], h, hmin, err, e3n, e5n, fac, s3, s5;
    int i, j, s, code, next = 1, rejected = 0, fail = 0;
    sys_copy_(x, X);
    for (i = 0; i < SYS_DIM; ++i) {
        cmp[i] = 0.0;
    }
    if ((code = sys_eval_(MODEL_T(t, )x, u, p, k[0], st)) != 0) {
        return code;
    }
    if (h0 > 0.0) {
        h = fmin(h0, fabs(tend - t));
    } else {
        /* the starting step of Hairer, Norsett, Wanner II.4 (one more evaluation) */
        double d0 = 0.0, d1 = 0.0, d2 = 0.0, h1;
        for (i = 0; i < SYS_DIM; ++i) {
            sc[i] = atol + fabs(x[i]) * rtol;
            d0 += (x[i] / sc[i]) * (x[i] / sc[i]);
            d1 += (k[0][i] / sc[i]) * (k[0][i] / sc[i]);
        }
        d0 = sqrt(d0 / SYS_DIM);
        d1 = sqrt(d1 / SYS_DIM);
        h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
        h = fmin(h, fabs(tend - t));
        for (i = 0; i < SYS_DIM; ++i) {
            y[i] = x[i] + dir * h * k[0][i];
        }
        if (sys_eval_(MODEL_T(t + dir * h, )y, u, p, k[1], st) == 0) {
            for (i = 0; i < SYS_DIM; ++i) {
                d2 += ((k[1][i] - k[0][i]) / sc[i]) * ((k[1][i] - k[0][i]) / sc[i]);
            }
            d2 = sqrt(d2 / SYS_DIM) / h;
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
            sys_ksum_(a[s], s, k, hs, dy);
            for (i = 0; i < SYS_DIM; ++i) {
                y[i] = x[i] + dy[i];
            }
            code = sys_eval_(MODEL_T(s == 12 ? tnew : t + c[s] * hs, )y, u, p, k[s], st);
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
        for (i = 0; i < SYS_DIM; ++i) {
            s3 = s5 = 0.0;
            for (j = 0; j < 13; ++j) {
                s3 += e3[j] * k[j][i];
                s5 += e5[j] * k[j][i];
            }
            sc[i] = atol + rtol * fmax(fabs(x[i]), fabs(y[i]));
            e3n += (s3 / sc[i]) * (s3 / sc[i]);
            e5n += (s5 / sc[i]) * (s5 / sc[i]);
        }
        err = (e3n == 0.0 && e5n == 0.0) ? 0.0 : fabs(hs) * e5n / sqrt((e5n + 0.01 * e3n) * SYS_DIM);
        if (!(err <= 1.0)) {
            /* rejected (also when err is NaN) */
            st->n_rejected++;
            rejected = 1;
            h = fabs(hs) * (err < HUGE_VAL ? fmax(0.2, 0.9 * pow(err, -0.125)) : 0.2);
            continue;
        }
        /* accepted: the output times inside the step from the dense output */
        if (next < nt && dir * (tt[next] - tnew) < 0.0) {
            double F[7][SYS_DIM];
            int r;
            for (s = 13; s < 16 && code == 0; ++s) {
                sys_ksum_(a[s], s, k, hs, sc);
                for (i = 0; i < SYS_DIM; ++i) {
                    sc[i] += x[i];
                }
                code = sys_eval_(MODEL_T(t + c[s] * hs, )sc, u, p, k[s], st);
            }
            if (code != 0) {
                return code;
            }
            for (i = 0; i < SYS_DIM; ++i) {
                F[0][i] = dy[i];
                F[1][i] = hs * k[0][i] - dy[i];
                F[2][i] = 2.0 * dy[i] - hs * (k[12][i] + k[0][i]);
            }
            for (r = 0; r < 4; ++r) {
                sys_ksum_(dd[r], 16, k, hs, F[3 + r]);
            }
            for (; next < nt && dir * (tt[next] - tnew) < 0.0; ++next) {
                const double th = (tt[next] - t) / hs, th1 = 1.0 - th;
                double *out = X + next * SYS_DIM;
                for (i = 0; i < SYS_DIM; ++i) {
                    double v = 0.0;
                    for (r = 6; r >= 0; --r) {
                        v = (v + F[r][i]) * ((6 - r) % 2 == 0 ? th : th1);
                    }
                    out[i] = x[i] + v;
                }
            }
        }
        sys_add_(x, cmp, dy);
        t = tnew;
        st->n_steps++;
        st->t = t;
        for (i = 0; i < MODEL_V_DIM; ++i) {
            st->x[i] = x[i];  /* the state: the first MODEL_V_DIM components */
        }
        for (; next < nt && tt[next] == t; ++next) {
            sys_copy_(X + next * SYS_DIM, x);
        }
        sys_copy_(k[0], k[12]);
        fac = err == 0.0 ? 10.0 : fmin(10.0, 0.9 * pow(err, -0.125));
        h = fabs(hs) * (rejected ? fmin(1.0, fac) : fac);
        rejected = 0;
        fail = 0;
    }
    return MODEL_OK;
}

