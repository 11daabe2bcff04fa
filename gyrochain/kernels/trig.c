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
#define MODEL_ROUND_ 6755399441055744.0  /* 1.5 * 2^52: x + it - it rounds x to an integer */

/* the blocks of 4 and 1 arguments (kernels/sincos.c) */
#define SYS_W 4
#define sys_sincos_block_ model_sincos4_
#include "sincos.c"
#undef SYS_W
#undef sys_sincos_block_

#define SYS_W 1
#define sys_sincos_block_ model_sincos1_
#include "sincos.c"
#undef SYS_W
#undef sys_sincos_block_

/* s[i] = sin a[i], c[i] = cos a[i] for i < count: in blocks of four (vectorised: the throughput of
 * a batch's lanes), and one by one where there are fewer than eight (independent scalar chains: the
 * latency of a single trajectory's right side, where a vector of two is slower). */
MODEL_FN static void model_sincos_(const double *a, double *s, double *c, int count)
{
    int i = 0, far = 0;
    if (FLT_EVAL_METHOD != 0) {  /* (a constant: one branch is compiled) */
        for (i = 0; i < count; ++i) {
            s[i] = sin(a[i]);
            c[i] = cos(a[i]);
        }
        return;
    }
    for (; count >= 8 && i + 4 <= count; i += 4) {
        model_sincos4_(a + i, s + i, c + i);
    }
    for (; i < count; ++i) {
        model_sincos1_(a + i, s + i, c + i);
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
}
