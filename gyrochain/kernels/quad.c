/* The two-body quadratures of every model that has them, as the generator emits them: each
 * `model_`/`MODEL_` becomes the model's name, `#if MODEL_<FLAG>` sections are kept or dropped by
 * the model's facts, and the `@generated` line is replaced by the model's printed code
 * (printers/kernels.py).  Everything above the `@kernel` line is for compilers and linters only:
 * tests/unit/test_kernels.py compiles this file as it stands. */
#include "model_stub.h"
/* @kernel */

/* ---------------------------------------------------------------------------------------
 * The two-body quadratures (28)-(30).  psi = phi^1 is cyclic; with P(phi) = E(phi) J - K^2 and
 * D(phi) = A J - C^2 > 0 the motion obeys D phidot^2 = P, so phi moves where P > 0, between
 * two simple roots of P (libration) or all the way round (rotation).
 *
 * P is a trigonometric polynomial of degree 3 (J has degree 2, U, beta degree 1): its Fourier
 * coefficients come from 8 samples.  Its roots are found by a walk whose steps cannot pass one
 * (P(a + x) > P(a) - |P'(a)| x - L2 x^2/2 with L2 >= max |P''|).
 *
 * Libration: phi = r + s 2h sin^2(b/2) from each turning point r (s = +1 from phi_-, -1 from
 * phi_+), 0 <= b <= pi/2, 2h = phi_+ - phi_-.  Then dt/db = sqrt(D/P) h sin b is smooth up to
 * and through the turning point (b = 0): the 1/sqrt singularity of Phi is gone.  P near r is
 * computed as P(r + x) - P(r) by sine-of-half-difference formulas, without cancellation.
 * Rotation: phi = phi0 + dir u, 0 <= u <= 2 pi.  Each quarter (or the turn) is integrated by
 * adaptive Gauss-Kronrod 7/15 panels, which also tabulate t and psi for the inversion.
 * --------------------------------------------------------------------------------------- */
#define MODEL_QUAD_MAXP 64        /* panels per quarter period */
#define MODEL_QUAD_TOL 1e-13      /* Kronrod - Gauss estimate, relative, per quarter */
#define MODEL_WALK_MAX 100000
#define MODEL_PI 3.14159265358979323846

typedef struct {
    double a, b;      /* parameter interval */
    double v[3];      /* integrals over it of dt, dpsi_K = K dt / J, dpsi_C = C dphi / J */
    double w;         /* weighted error estimate */
    double cum[3];    /* integrals from the quarter's start to a */
} model_panel_;

typedef struct {
    const model_params *p;
    int kind;
    double E, k;          /* constants of the energy (23) and momentum (27) integrals */
    double c[7];          /* P = c0 + sum_j c[2j-1] cos(j phi) + c[2j] sin(j phi), j = 1..3 */
    double S, L2;         /* size of the terms of P, bound of |P''| */
    double r[2], h;       /* turning points phi_-, phi_+ and the half amplitude */
    double slope[2];      /* |P'| at the turning points */
    double phi0, dir;     /* start and sense */
    double phis, Ps, w, U; /* rotation: phi = phis + w sinh(b - U), 0 <= b <= 2U; P(phis) = Ps */
    double eps;           /* relative distance from the separatrix */
    int np[2];
    model_panel_ pan[2][MODEL_QUAD_MAXP];
    double tot[2][3];     /* integrals over each quarter (the turn: index 0) */
} model_orbit_;

/* J(phi), C(phi), A, U(phi), beta(phi) of the spec (generated). */
MODEL_FN static void model_quad_terms_(double phi, const model_params *p, double *out)
{
    (void)p;
    out[0] = phi; /* @generated quad_terms: this line becomes the model's printed J, C, A, U, beta */
}

/* P, P', P'' at phi from the Fourier coefficients. */
MODEL_FN static void model_pfour_(const double *c, double phi, double *d)
{
    const double c1 = cos(phi), s1 = sin(phi);
    double ck = c1, sk = s1, t;
    int j;
    d[0] = c[0];
    d[1] = 0.0;
    d[2] = 0.0;
    for (j = 1; j <= 3; ++j) {
        d[0] += c[2 * j - 1] * ck + c[2 * j] * sk;
        d[1] += j * (c[2 * j] * ck - c[2 * j - 1] * sk);
        d[2] -= j * j * (c[2 * j - 1] * ck + c[2 * j] * sk);
        t = ck * c1 - sk * s1;
        sk = sk * c1 + ck * s1;
        ck = t;
    }
}

/* P(r + x) - P(r) = sum_j 2 sin(j x/2) (c_sj cos j(r + x/2) - c_cj sin j(r + x/2)), accurate for small x. */
MODEL_FN static double model_pdelta_(const double *c, double r, double x)
{
    const double m = r + 0.5 * x, cm = cos(m), sm = sin(m);
    double ck = cm, sk = sm, t, sum = 0.0;
    int j;
    for (j = 1; j <= 3; ++j) {
        sum += 2.0 * sin(0.5 * j * x) * (c[2 * j] * ck - c[2 * j - 1] * sk);
        t = ck * cm - sk * sm;
        sk = sk * cm + ck * sm;
        ck = t;
    }
    return sum;
}

/* P(s + x) - P(s) - P'(s) sin x at a minimum s of P (P'(s) = 0 up to round-off, which this drops):
 * with p_j = c_sj cos js - c_cj sin js, q_j = c_cj cos js + c_sj sin js it is
 * sum_j (sin jx - j sin x) p_j - 2 sin^2(jx/2) q_j, and sin 2x - 2 sin x = -4 sin x sin^2(x/2),
 * sin 3x - 3 sin x = -4 sin^3 x: no term is linear in x, so nothing cancels near s. */
MODEL_FN static double model_pbump_(const double *c, double s, double x)
{
    const double cs = cos(s), ss = sin(s), sx = sin(x), h1 = sin(0.5 * x);
    const double c2 = cs * cs - ss * ss, s2 = 2.0 * ss * cs, c3 = c2 * cs - s2 * ss, s3 = s2 * cs + c2 * ss;
    const double h2 = sin(x), h3 = sin(1.5 * x);
    const double p2 = c[4] * c2 - c[3] * s2, p3 = c[6] * c3 - c[5] * s3;
    const double q1 = c[1] * cs + c[2] * ss, q2 = c[3] * c2 + c[4] * s2, q3 = c[5] * c3 + c[6] * s3;
    return -4.0 * sx * h1 * h1 * p2 - 4.0 * sx * sx * sx * p3 - 2.0 * (h1 * h1 * q1 + h2 * h2 * q2 + h3 * h3 * q3);
}

/* The first root of P from a (P(a) > 0) in the sense sig within dmax: returns 1 and *root, 0 when
 * P > 0 all the way, -1 when the walk does not converge.  *pmin, *argmin: the least local minimum
 * of P passed (located by bisection on P'). */
MODEL_FN static int model_walk_(const model_orbit_ *o, double a, double sig, double dmax, double *root, double *pmin, double *argmin)
{
    double d[3], dn[3], gone = 0.0, step, lo, hi, mid, dm[3];
    int it, i, last;
    model_pfour_(o->c, a, d);
    for (it = 0; it < MODEL_WALK_MAX; ++it) {
        if (!(d[0] > 0.0)) {
            *root = a;
            return 1;
        }
        step = 2.0 * d[0] / (fabs(d[1]) + sqrt(d[1] * d[1] + 2.0 * o->L2 * d[0]));
        last = gone + step >= dmax;
        if (last) {
            step = dmax - gone;
        } else if (step <= 4.0 * 2.220446049250313e-16 * (1.0 + fabs(a))) {
            *root = a + sig * step;
            return 1;
        }
        model_pfour_(o->c, a + sig * step, dn);
        if (sig * d[1] < 0.0 && sig * dn[1] > 0.0) {
            /* a local minimum of P between a and a + step (P > 0 there): bisect on P' */
            lo = a;
            hi = a + sig * step;
            for (i = 0; i < 60; ++i) {
                mid = 0.5 * (lo + hi);
                model_pfour_(o->c, mid, dm);
                if (sig * dm[1] < 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            model_pfour_(o->c, 0.5 * (lo + hi), dm);
            if (dm[0] < *pmin) {
                *pmin = dm[0];
                *argmin = 0.5 * (lo + hi);
            }
        }
        if (last) {
            return 0;
        }
        a += sig * step;
        gone += step;
        for (i = 0; i < 3; ++i) {
            d[i] = dn[i];
        }
    }
    return -1;
}

/* dt, dpsi_K, dpsi_C per unit parameter b of quarter q (the turn when rotating). */
MODEL_FN static int model_integrand_(const model_orbit_ *o, int q, double b, double *f, double *phi_out, double *g_out)
{
    double t[5], phi, dphi, P = 0.0, D, g, K, s2 = 0.0, x;
    if (o->kind == MODEL_ROTATION) {
        /* sinh map: a near-double root of P at phis (near the separatrix) becomes a smooth bump */
        x = o->w * sinh(b - o->U);
        phi = o->phis + x;
        dphi = o->w * cosh(b - o->U);
        P = o->Ps + model_pbump_(o->c, o->phis, x);
    } else {
        s2 = sin(0.5 * b);
        x = (q ? -2.0 : 2.0) * o->h * s2 * s2;   /* phi - r, kept apart: phi alone rounds it away */
        phi = o->r[q] + x;
        dphi = o->h * sin(b);
        if (s2 != 0.0) {
            P = model_pdelta_(o->c, o->r[q], x);
        }
    }
    model_quad_terms_(phi, o->p, t);
    D = t[2] * t[0] - t[1] * t[1];
    if (!(D > 0.0) || !(t[0] > 0.0)) {
        return MODEL_SINGULAR;
    }
    if (o->kind == MODEL_LIBRATION && s2 == 0.0) {
        g = sqrt(2.0 * D * o->h / o->slope[q]);
    } else if (P > 0.0) {
        g = sqrt(D / P) * dphi;
    } else {
        return MODEL_QUAD_FAILED;
    }
    K = o->k - t[4];
    f[0] = g;
    f[1] = K * g / t[0];
    f[2] = t[1] * dphi / t[0];
    if (phi_out) {
        *phi_out = phi;
    }
    if (g_out) {
        *g_out = g;
    }
    return isfinite(g) ? MODEL_OK : MODEL_QUAD_FAILED;
}

/* Gauss-Kronrod 7/15 on [a, b]: v = the three integrals, e = |K15 - G7| of each. */
MODEL_FN static int model_kronrod_(const model_orbit_ *o, int q, double a, double b, double *v, double *e)
{
    static const double xk[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
        0.864864423359769072789712788640926, 0.741531185599394439863864773280788, 0.586087235467691130294144845693013,
        0.405845151377397166906606412076961, 0.207784955007898467600689403773245, 0.0};
    static const double wk[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
        0.104790010322250183839876322541518, 0.140653259715525918745189590510238, 0.169004726639267902826583426598550,
        0.190350578064785409913256402421014, 0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
    static const double wg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
        0.381830050505118944950369775488975, 0.417959183673469387755102040816327};
    const double hw = 0.5 * (b - a), cx = 0.5 * (a + b);
    double f[15][3], vg[3] = {0.0, 0.0, 0.0}, asc, mean;
    int i, j, side, rc, m = 0;
    for (j = 0; j < 3; ++j) {
        v[j] = 0.0;
    }
    for (i = 0; i < 8; ++i) {
        for (side = (i == 7); side < 2; ++side, ++m) {
            rc = model_integrand_(o, q, cx + (side ? hw : -hw) * xk[i], f[m], 0, 0);
            if (rc) {
                return rc;
            }
            for (j = 0; j < 3; ++j) {
                v[j] += wk[i] * f[m][j];
                if (i % 2 == 1) {
                    vg[j] += wg[i / 2] * f[m][j];
                }
            }
        }
    }
    /* QUADPACK's estimate of the Kronrod error: |K15 - G7| scaled by its size against the
     * integrand's variation (the G7 difference itself overstates it by orders of magnitude) */
    for (j = 0; j < 3; ++j) {
        mean = 0.5 * v[j];
        asc = 0.0;
        for (i = 0, m = 0; i < 8; ++i) {
            for (side = (i == 7); side < 2; ++side, ++m) {
                asc += wk[i] * fabs(f[m][j] - mean);
            }
        }
        asc *= fabs(hw);
        e[j] = fabs((v[j] - vg[j]) * hw);
        if (asc != 0.0 && e[j] != 0.0) {
            mean = 200.0 * e[j] / asc;
            e[j] = asc * (mean < 1.0 ? pow(mean, 1.5) : 1.0);
        }
        v[j] *= hw;
    }
    return MODEL_OK;
}

/* Adaptive panels over [0, end] of quarter q; sorted, with cumulative integrals. */
MODEL_FN static int model_panels_(model_orbit_ *o, int q, double end, int start)
{
    model_panel_ *pan = o->pan[q], tmp;
    double e[3], err[3], size[3], ab[3], worst;
    int i, j, n = start, rc, pick;
    for (i = 0; i < n; ++i) {
        pan[i].a = end * i / n;
        pan[i].b = end * (i + 1) / n;
        rc = model_kronrod_(o, q, pan[i].a, pan[i].b, pan[i].v, e);
        if (rc) {
            return rc;
        }
        pan[i].w = e[0] + e[1] + e[2];
        for (j = 0; j < 3; ++j) {
            pan[i].cum[j] = e[j];   /* the error of each integral, until the panels are sorted */
        }
    }
    for (;;) {
        for (j = 0; j < 3; ++j) {
            err[j] = 0.0;
            size[j] = 0.0;
        }
        for (i = 0; i < n; ++i) {
            for (j = 0; j < 3; ++j) {
                err[j] += pan[i].cum[j];
                size[j] += fabs(pan[i].v[j]);
            }
        }
        if (err[0] <= MODEL_QUAD_TOL * size[0] && err[1] <= MODEL_QUAD_TOL * size[1] + 1e-300 &&
            err[2] <= MODEL_QUAD_TOL * size[2] + 1e-300) {
            break;
        }
        if (n == MODEL_QUAD_MAXP) {
            return MODEL_QUAD_FAILED;
        }
        pick = 0;
        worst = -1.0;
        for (i = 0; i < n; ++i) {
            double w = 0.0;
            for (j = 0; j < 3; ++j) {
                w += pan[i].cum[j] / (size[j] + 1e-300);
            }
            if (w > worst) {
                worst = w;
                pick = i;
            }
        }
        pan[n].a = 0.5 * (pan[pick].a + pan[pick].b);
        pan[n].b = pan[pick].b;
        pan[pick].b = pan[n].a;
        for (i = 0; i < 2; ++i) {
            model_panel_ *pp = i ? &pan[n] : &pan[pick];
            rc = model_kronrod_(o, q, pp->a, pp->b, pp->v, e);
            if (rc) {
                return rc;
            }
            for (j = 0; j < 3; ++j) {
                pp->cum[j] = e[j];
            }
        }
        ++n;
    }
    for (i = 1; i < n; ++i) {   /* insertion sort by a */
        tmp = pan[i];
        for (j = i - 1; j >= 0 && pan[j].a > tmp.a; --j) {
            pan[j + 1] = pan[j];
        }
        pan[j + 1] = tmp;
    }
    for (j = 0; j < 3; ++j) {
        ab[j] = 0.0;
    }
    for (i = 0; i < n; ++i) {
        for (j = 0; j < 3; ++j) {
            pan[i].cum[j] = ab[j];
            ab[j] += pan[i].v[j];
        }
    }
    for (j = 0; j < 3; ++j) {
        o->tot[q][j] = ab[j];
    }
    o->np[q] = n;
    return MODEL_OK;
}

/* The integrals from the start of quarter q to parameter b. */
MODEL_FN static int model_partial_(const model_orbit_ *o, int q, double b, double *v)
{
    const model_panel_ *pan = o->pan[q];
    double part[3], e[3];
    int lo = 0, hi = o->np[q] - 1, mid, j, rc;
    while (lo < hi) {
        mid = (lo + hi + 1) / 2;
        if (pan[mid].a <= b) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    rc = model_kronrod_(o, q, pan[lo].a, b, part, e);
    for (j = 0; j < 3; ++j) {
        v[j] = pan[lo].cum[j] + part[j];
    }
    return rc;
}

/* The parameter b of quarter q at which the time from its start is tau (Newton, bracketed). */
MODEL_FN static int model_invert_(const model_orbit_ *o, int q, double tau, double *b, double *v)
{
    const model_panel_ *pan = o->pan[q];
    double x, xn, lo_x, hi_x, F, g, f[3], e[3], part[3];
    int lo = 0, hi = o->np[q] - 1, mid, it, j, rc;
    while (lo < hi) {
        mid = (lo + hi + 1) / 2;
        if (pan[mid].cum[0] <= tau) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    lo_x = pan[lo].a;
    hi_x = pan[lo].b;
    x = lo_x + (hi_x - lo_x) * (tau - pan[lo].cum[0]) / pan[lo].v[0];
    x = x < lo_x ? lo_x : (x > hi_x ? hi_x : x);
    for (it = 0; it < 100; ++it) {
        rc = model_kronrod_(o, q, pan[lo].a, x, part, e);
        if (!rc) {
            rc = model_integrand_(o, q, x, f, 0, &g);
        }
        if (rc) {
            return rc;
        }
        F = pan[lo].cum[0] + part[0] - tau;
        if (F > 0.0) {
            hi_x = x;
        } else {
            lo_x = x;
        }
        xn = x - F / g;
        if (!(xn > lo_x && xn < hi_x)) {
            xn = 0.5 * (lo_x + hi_x);
        }
        if (fabs(xn - x) <= 4.0 * 2.220446049250313e-16 * fabs(x) || hi_x - lo_x <= 4.0 * 2.220446049250313e-16 * fabs(x)) {
            x = xn;
            break;
        }
        x = xn;
    }
    *b = x;
    rc = model_kronrod_(o, q, pan[lo].a, x, part, e);
    for (j = 0; j < 3; ++j) {
        v[j] = pan[lo].cum[j] + part[j];
    }
    return rc;
}

/* The motion from x0: constants, Fourier coefficients of P, turning points, panels. */
MODEL_FN static int model_orbit_init_(const double *x0, const model_params *p, model_orbit_ *o)
{
    double t[5], ej[8], kk[8], d[3], root, pmin, argmin, phi, D0, ang, e_end;
    const double phi0 = x0[1], phid0 = x0[3];
    int i, j, found, rc;
#if MODEL_HAS_PARAMS
    if (!p) {
        return MODEL_NO_PARAMS;
    }
#endif
    if (!model_all_finite_(x0, 4)) {
        return MODEL_NONFINITE;
    }
    o->p = p;
    o->kind = MODEL_LIBRATION;   /* until the walk finds no turning point */
    o->E = model_energy(x0, p);
    o->k = model_momentum(x0, p);
    o->S = 0.0;
    for (i = 0; i < 7; ++i) {
        o->c[i] = 0.0;
    }
    for (i = 0; i < 8; ++i) {
        phi = 2.0 * MODEL_PI * i / 8.0;
        model_quad_terms_(phi, p, t);
        ej[i] = 2.0 * (o->E + t[3]) * t[0];
        kk[i] = (o->k - t[4]) * (o->k - t[4]);
        if (fabs(ej[i]) + kk[i] > o->S) {
            o->S = fabs(ej[i]) + kk[i];
        }
        o->c[0] += (ej[i] - kk[i]) / 8.0;
        for (j = 1; j <= 3; ++j) {
            ang = j * phi;
            o->c[2 * j - 1] += (ej[i] - kk[i]) * cos(ang) / 4.0;
            o->c[2 * j] += (ej[i] - kk[i]) * sin(ang) / 4.0;
        }
    }
    if (!isfinite(o->S)) {
        return MODEL_NONFINITE;
    }
    /* make P(phi0) = D(phi0) phidot0^2 exactly (the samples carry rounding) */
    model_quad_terms_(phi0, p, t);
    D0 = t[2] * t[0] - t[1] * t[1];
    if (!(D0 > 0.0) || !(t[0] > 0.0)) {
        return MODEL_SINGULAR;
    }
    model_pfour_(o->c, phi0, d);
    o->c[0] += D0 * phid0 * phid0 - d[0];
    o->L2 = 0.0;
    for (j = 1; j <= 3; ++j) {
        o->L2 += j * j * (fabs(o->c[2 * j - 1]) + fabs(o->c[2 * j]));
    }
    o->eps = HUGE_VAL;
    o->phi0 = phi0;
    o->dir = phid0 >= 0.0 ? 1.0 : -1.0;
    o->np[0] = o->np[1] = 0;
    pmin = HUGE_VAL;
    argmin = phi0;
    model_pfour_(o->c, phi0, d);
    if (phid0 == 0.0) {
        /* phi0 is a turning point; the motion leaves it where P grows */
        if (!(fabs(d[1]) > MODEL_SEPARATRIX_TOL * o->S)) {
            o->kind = MODEL_STEADY;
            return MODEL_OK;
        }
        o->dir = d[1] > 0.0 ? 1.0 : -1.0;
        found = model_walk_(o, phi0 + o->dir * fabs(d[1]) / o->L2, o->dir, 2.0 * MODEL_PI, &root, &pmin, &argmin);
        if (found != 1) {
            return found == 0 ? MODEL_SEPARATRIX : MODEL_QUAD_FAILED;
        }
        o->r[o->dir > 0.0 ? 0 : 1] = phi0;
        o->r[o->dir > 0.0 ? 1 : 0] = root;
    } else {
        found = model_walk_(o, phi0, o->dir, 2.0 * MODEL_PI, &root, &pmin, &argmin);
        if (found < 0) {
            return MODEL_QUAD_FAILED;
        }
        if (found == 0) {
            o->kind = MODEL_ROTATION;
        } else {
            o->r[o->dir > 0.0 ? 1 : 0] = root;
            found = model_walk_(o, phi0, -o->dir, 2.0 * MODEL_PI, &root, &pmin, &argmin);
            if (found != 1) {
                return MODEL_QUAD_FAILED;
            }
            o->r[o->dir > 0.0 ? 0 : 1] = root;
        }
    }
    if (o->S > 0.0) {
        o->eps = pmin / o->S;
    }
    if (o->kind == MODEL_LIBRATION) {
        o->h = 0.5 * (o->r[1] - o->r[0]);
        for (i = 0; i < 2; ++i) {
            model_pfour_(o->c, o->r[i], d);
            o->slope[i] = fabs(d[1]);
            /* a dip of P beyond the turning point, P' x + P'' x^2/2: its depth */
            e_end = d[2] > 0.0 ? d[1] * d[1] / (2.0 * d[2] * o->S) : HUGE_VAL;
            if (e_end < o->eps) {
                o->eps = e_end;
            }
        }
    }
    if (o->eps < MODEL_SEPARATRIX_TOL) {
        return MODEL_SEPARATRIX;
    }
    if (o->kind == MODEL_ROTATION) {
        o->phis = argmin;
        model_pfour_(o->c, argmin, d);
        o->Ps = d[0];
        /* P ~ Ps + P'' x^2/2 near phis: the width of the bump */
        o->w = d[2] > 0.0 ? sqrt(2.0 * d[0] / d[2]) : 1.0;
        o->w = o->w < 1.0 ? o->w : 1.0;
        o->U = asinh(MODEL_PI / o->w);
        return model_panels_(o, 0, 2.0 * o->U, 8);
    }
    rc = model_panels_(o, 0, 0.5 * MODEL_PI, 4);
    if (!rc) {
        rc = model_panels_(o, 1, 0.5 * MODEL_PI, 4);
    }
    return rc;
}

MODEL_FN int model_quad_motion(const double *x0, const model_params *p, model_quad_info *info)
{
    model_orbit_ o;
    int rc = model_orbit_init_(x0, p, &o);
    if (rc) {
        return rc;
    }
    info->kind = o.kind;
    info->E = o.E;
    info->k = o.k;
    info->separatrix_distance = o.eps;
    if (o.kind == MODEL_LIBRATION) {
        info->phi_min = o.r[0];
        info->phi_max = o.r[1];
        info->period = 2.0 * (o.tot[0][0] + o.tot[1][0]);
        info->psi_advance = 2.0 * (o.tot[0][1] + o.tot[1][1]);
    } else if (o.kind == MODEL_ROTATION) {
        info->phi_min = o.phi0;
        info->phi_max = o.phi0 + o.dir * 2.0 * MODEL_PI;
        info->period = o.tot[0][0];
        info->psi_advance = o.tot[0][1] - o.dir * o.tot[0][2];
    } else {
        info->phi_min = info->phi_max = x0[1];
        info->period = 0.0;
        info->psi_advance = 0.0;
    }
    return MODEL_OK;
}

MODEL_FN int model_quad_period(const double *x0, const model_params *p, double *period)
{
    model_quad_info info;
    int rc = model_quad_motion(x0, p, &info);
    if (rc) {
        return rc;
    }
    if (info.kind == MODEL_STEADY) {
        return MODEL_NO_PERIOD;
    }
    *period = info.period;
    return MODEL_OK;
}

/* Phase time (from phi_- with phidot > 0) and psi gained, at the point with integrals v on
 * segment seg of a libration: 1 phi_- -> mid and 2 mid -> phi_+ (phidot > 0), 3 phi_+ -> mid and
 * 4 mid -> phi_- (phidot < 0).  psi gains K dt/J - C dphi/J: the C part flips with phidot. */
MODEL_FN static void model_lib_phase_(const model_orbit_ *o, int seg, const double *v, double *phase, double *psir)
{
    const double *Im = o->tot[0], *Ip = o->tot[1];
    const double up = Im[1] - Im[2] + Ip[1] - Ip[2];   /* psi gained over segments 1 and 2 */
    switch (seg) {
    case 1:
        *phase = v[0];
        *psir = v[1] - v[2];
        break;
    case 2:
        *phase = Im[0] + Ip[0] - v[0];
        *psir = up - v[1] + v[2];
        break;
    case 3:
        *phase = Im[0] + Ip[0] + v[0];
        *psir = up + v[1] + v[2];
        break;
    default:
        *phase = 2.0 * (Im[0] + Ip[0]) - v[0];
        *psir = 2.0 * (Im[1] + Ip[1]) - v[1] - v[2];
        break;
    }
}

MODEL_FN int model_quad_state(double t, const double *x0, const model_params *p, double *x)
{
    model_orbit_ o;
    double T, n, rem, tau, b, v[3], phase0, psir0, phase, psir, phi, g, f[3], tt[5], phid, b0;
    int rc = model_orbit_init_(x0, p, &o), seg, q;
    if (rc) {
        return rc;
    }
    if (!isfinite(t)) {
        return MODEL_NONFINITE;
    }
    if (o.kind == MODEL_STEADY) {
        x[0] = x0[0] + x0[2] * t;
        x[1] = x0[1];
        x[2] = x0[2];
        x[3] = 0.0;
        return MODEL_OK;
    }
    if (o.kind == MODEL_ROTATION) {
        /* one turn: b from 0 (phi = phis - pi) to 2U (phis + pi); the motion runs along b when
         * dir > 0 and against it when dir < 0, where the C part of psi flips */
        const double *I = o.tot[0], dpsi = I[1] - o.dir * I[2];
        double x0s = x0[1] - o.phis, turns;
        T = I[0];
        turns = floor((x0s + MODEL_PI) / (2.0 * MODEL_PI));
        x0s -= 2.0 * MODEL_PI * turns;
        b0 = o.U + asinh(x0s / o.w);
        rc = model_partial_(&o, 0, b0, v);
        if (rc) {
            return rc;
        }
        phase0 = o.dir > 0.0 ? v[0] : T - v[0];
        psir0 = o.dir > 0.0 ? v[1] - v[2] : I[1] - v[1] + I[2] - v[2];
        n = floor((phase0 + t) / T);
        rem = phase0 + t - n * T;
        rc = model_invert_(&o, 0, o.dir > 0.0 ? rem : T - rem, &b, v);
        if (!rc) {
            rc = model_integrand_(&o, 0, b, f, &phi, &g);
        }
        if (rc) {
            return rc;
        }
        psir = o.dir > 0.0 ? v[1] - v[2] : I[1] - v[1] + I[2] - v[2];
        x[0] = x0[0] + n * dpsi + psir - psir0;
        x[1] = phi + 2.0 * MODEL_PI * (turns + o.dir * n);
        phid = o.dir * o.w * cosh(b - o.U) / g;
    } else {
        const double *Im = o.tot[0], *Ip = o.tot[1];
        T = 2.0 * (Im[0] + Ip[0]);
        /* where x0 is in the period */
        q = x0[1] > 0.5 * (o.r[0] + o.r[1]);
        b0 = (q ? o.r[1] - x0[1] : x0[1] - o.r[0]) / (2.0 * o.h);
        b0 = 2.0 * asin(sqrt(b0 < 0.0 ? 0.0 : (b0 > 0.5 ? 0.5 : b0)));
        rc = model_partial_(&o, q, b0, v);
        if (rc) {
            return rc;
        }
        seg = q ? (x0[3] > 0.0 ? 2 : 3) : (x0[3] < 0.0 ? 4 : 1);
        model_lib_phase_(&o, seg, v, &phase0, &psir0);
        /* where x(t) is */
        n = floor((phase0 + t) / T);
        rem = phase0 + t - n * T;
        if (rem < Im[0]) {
            seg = 1;
            tau = rem;
        } else if (rem < Im[0] + Ip[0]) {
            seg = 2;
            tau = Im[0] + Ip[0] - rem;
        } else if (rem < Im[0] + 2.0 * Ip[0]) {
            seg = 3;
            tau = rem - Im[0] - Ip[0];
        } else {
            seg = 4;
            tau = T - rem;
        }
        q = seg == 2 || seg == 3;
        rc = model_invert_(&o, q, tau, &b, v);
        if (!rc) {
            rc = model_integrand_(&o, q, b, f, &phi, &g);
        }
        if (rc) {
            return rc;
        }
        model_lib_phase_(&o, seg, v, &phase, &psir);
        x[0] = x0[0] + n * 2.0 * (Im[1] + Ip[1]) + psir - psir0;
        x[1] = phi;
        phid = (seg <= 2 ? 1.0 : -1.0) * o.h * sin(b) / g;
    }
    model_quad_terms_(x[1], p, tt);
    x[2] = (o.k - tt[4] - tt[1] * phid) / tt[0];
    x[3] = phid;
    return MODEL_OK;
}

MODEL_FN int model_quad_functions(double phi, const double *x0, const model_params *p, double *out)
{
    double t[5], E, k, P, D;
#if MODEL_HAS_PARAMS
    if (!p) {
        return MODEL_NO_PARAMS;
    }
#endif
    if (!model_all_finite_(x0, 4) || !isfinite(phi)) {
        return MODEL_NONFINITE;
    }
    E = model_energy(x0, p);
    k = model_momentum(x0, p);
    model_quad_terms_(phi, p, t);
    out[0] = t[0];
    out[1] = t[1];
    out[2] = t[2];
    out[3] = 2.0 * (E + t[3]);
    out[4] = k - t[4];
    D = t[2] * t[0] - t[1] * t[1];
    P = out[3] * t[0] - out[4] * out[4];
    out[5] = P > 0.0 ? sqrt(D / P) : HUGE_VAL;
    return D > 0.0 ? MODEL_OK : MODEL_SINGULAR;
}
