/* The block of kernels/trig.c: sin and cos of SYS_W arguments, each element by the same
 * statements, so that a block of four and a block of one give the same bits (with floating-point
 * contraction off, as -std=c99 has it).  kernels/trig.c prints it for 4 and 1; compiled on its own
 * (the preamble) it is the block of four. */
#include "model_stub.h"
#ifndef SYS_W
#define SYS_W 4
#define sys_sincos_block_ model_sincos4_
#define MODEL_ROUND_ 6755399441055744.0
#endif
/* @kernel */
/* sin a[i] and cos a[i] for i < SYS_W, the reduction and polynomials of kernels/trig.c (|a| < 1e6). */
MODEL_FN static void sys_sincos_block_(const double *MODEL_RESTRICT_ a, double *MODEL_RESTRICT_ s, double *MODEL_RESTRICT_ c)
{
    int i;
    for (i = 0; i < SYS_W; ++i) {
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
        const double lo = (e2 + e3) - j * 8.4784276603689e-32;               /* r = y3 + lo */
        const double q = j - 4.0 * f;                                           /* j mod 4 */
        const double z = y3 * y3;
        const double z2 = z * z;
        const double z4 = z2 * z2;
        /* the Taylor polynomials of (sin r - r) / r^3 and (cos r - 1 + r^2/2) / r^4 in z = r^2, by
         * Estrin's scheme (pairs, then pairs of pairs: a shorter chain of dependent operations
         * than Horner's, for one lane whose time is that chain) */
        const double ps = (-0.16666666666666666 + z * 0.008333333333333333)
                        + z2 * (-0.0001984126984126984 + z * 2.7557319223985893e-06)
                        + z4 * ((-2.505210838544172e-08 + z * 1.6059043836821613e-10)
                                + z2 * (-7.647163731819816e-13 + z * 2.8114572543455206e-15));
        const double pc = (0.041666666666666664 + z * -0.001388888888888889)
                        + z2 * (2.48015873015873e-05 + z * -2.755731922398589e-07)
                        + z4 * ((2.08767569878681e-09 + z * -1.1470745597729725e-11) + z2 * 4.779477332387385e-14);
        const double hz = 0.5 * z;
        const double w = 1.0 - hz;
        /* sin(y3 + lo) = y3 + y3^3 ps + lo (1 - y3^2/2), cos(y3 + lo) = 1 - y3^2/2 + y3^4 pc - y3 lo,
         * the rounding of w = 1 - hz carried */
        const double sr = y3 + (y3 * z * ps + lo * (1.0 - hz));
        const double cr = w + (((1.0 - w) - hz) + (z2 * pc - y3 * lo));
        const double odd = (q == 1.0 || q == 3.0) ? 1.0 : 0.0;
        const double ss = odd != 0.0 ? cr : sr;
        const double cc = odd != 0.0 ? sr : cr;
        const double sa = q >= 2.0 ? -ss : ss;
        s[i] = a[i] == 0.0 ? a[i] : sa;  /* sin(-0) = -0 */
        c[i] = (q == 1.0 || q == 2.0) ? -cc : cc;
    }
}
