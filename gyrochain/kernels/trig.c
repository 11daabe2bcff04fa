/* Sine and cosine without libm, for the lanes of RK4 (kernels/rk4_lanes.c): every statement is
 * plain arithmetic on one element, so a compiler vectorises the loop over four arguments (gcc at
 * -O2), where four calls of libm's sin and cos cannot be.  Within 1 ulp of libm's (tests/models/
 * test_trig.py compares 10^8 random arguments); |a| >= 1e6, infinities and NaN go to libm.
 *
 * The reduction a = j pi/2 + r, |r| <= pi/4 (j the nearest integer to a 2/pi, found by adding and
 * subtracting 1.5 * 2^52, which rounds to an integer in round-to-nearest), in Cody and Waite's
 * manner with pi/2 split into four parts (their sum is pi/2 to 7e-49): the first three carry
 * 31, 32 and 28 bits, so j times each is exact for |j| < 2^21; the differences are summed
 * exactly (Knuth's two-sum), and r = rh + rl in two doubles.  Then sin r and cos r by their Taylor
 * series to r^17 and r^16 (the first terms left out are below 2^-63 and 2^-58 of the result for
 * |r| <= pi/4), with rl's first-order terms, and the quadrant j mod 4 chooses which and with what
 * sign.  It needs double arithmetic as C99 says it (FLT_EVAL_METHOD 0, as on x86-64 and ARM64)
 * and no -ffast-math; with other evaluation libm is
 * used throughout. */
#include "model_stub.h"
#include <float.h>
/* @kernel */
#if FLT_EVAL_METHOD == 0
#define MODEL_ROUND_ 6755399441055744.0  /* 1.5 * 2^52: x + it - it rounds x to an integer */

/* sin a[i] and cos a[i] for i < 4, the reduction and polynomials above (|a| < 1e6). */
static void model_sincos4_(const double *restrict a, double *restrict s, double *restrict c)
{
    int i;
    for (i = 0; i < 4; ++i) {
        const double j = (a[i] * 0.63661977236758134 + MODEL_ROUND_) - MODEL_ROUND_;
        const double f = (j * 0.25 - 0.375 + MODEL_ROUND_) - MODEL_ROUND_;  /* floor(j / 4) */
        const double y1 = a[i] - j * 1.5707963267341256;                       /* exact */
        const double w2 = j * 6.077100506303966e-11;                            /* exact */
        const double y2 = y1 - w2;
        const double b2 = y2 - y1;
        const double e2 = (y1 - (y2 - b2)) - (w2 + b2);                         /* y1 - w2 = y2 + e2 */
        const double w3 = j * 2.0222662487111665e-21;
        const double y3 = y2 - w3;
        const double b3 = y3 - y2;
        const double e3 = (y2 - (y3 - b3)) - (w3 + b3);                         /* y2 - w3 = y3 + e3 */
        const double lo = (e2 + e3) - j * 8.4784276603689e-32;
        const double rh = y3 + lo;
        const double rl = lo - (rh - y3);
        const double q = j - 4.0 * f;                                           /* j mod 4 */
        const double z = rh * rh;
        const double ps = -0.16666666666666666 + z * (0.008333333333333333 + z * (-0.0001984126984126984
                        + z * (2.7557319223985893e-06 + z * (-2.505210838544172e-08 + z * (1.6059043836821613e-10
                        + z * (-7.647163731819816e-13 + z * 2.8114572543455206e-15))))));
        const double pc = 0.041666666666666664 + z * (-0.001388888888888889 + z * (2.48015873015873e-05
                        + z * (-2.755731922398589e-07 + z * (2.08767569878681e-09 + z * (-1.1470745597729725e-11
                        + z * 4.779477332387385e-14)))));
        const double hz = 0.5 * z;
        const double w = 1.0 - hz;
        const double sr = rh + (rh * z * ps + rl * (1.0 - hz));
        const double cr = w + (((1.0 - w) - hz) + (z * z * pc - rh * rl));
        const double odd = (q == 1.0 || q == 3.0) ? 1.0 : 0.0;
        const double ss = odd != 0.0 ? cr : sr;
        const double cc = odd != 0.0 ? sr : cr;
        const double sa = q >= 2.0 ? -ss : ss;
        s[i] = a[i] == 0.0 ? a[i] : sa;  /* sin(-0) = -0 */
        c[i] = (q == 1.0 || q == 2.0) ? -cc : cc;
    }
}
#endif

/* s[i] = sin a[i], c[i] = cos a[i] for i < count, a multiple of 4. */
static void model_sincos_(const double *a, double *s, double *c, int count)
{
    int i, far = 0;
#if FLT_EVAL_METHOD == 0
    for (i = 0; i < count; i += 4) {
        model_sincos4_(a + i, s + i, c + i);
    }
    for (i = 0; i < count; ++i) {
        far |= !(fabs(a[i]) < 1e6);
    }
    for (i = 0; far && i < count; ++i) {
        if (!(fabs(a[i]) < 1e6)) {
            s[i] = sin(a[i]);
            c[i] = cos(a[i]);
        }
    }
#else
    (void)far;
    for (i = 0; i < count; ++i) {
        s[i] = sin(a[i]);
        c[i] = cos(a[i]);
    }
#endif
}
