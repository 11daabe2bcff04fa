/* furuta_lqr.c - the Furuta pendulum balanced by LQR at 1 kHz with the emitted RK4, in float: one
 * call of furuta_integrate per 1 ms control period, u = -K (x - x*) with the angles wrapped, from
 * 0.2 rad off upright for 4 s; the state every 0.5 s.  K (lqr_gain.h, four floats FURUTA_K) is the
 * discrete LQR gain of examples/furuta_lqr.py.  Built for the Cortex-M4 (examples/embed/m4/README.md)
 * and for the host from the same source: their outputs are compared by tests/tools/test_m4.py. */
#include <stdio.h>

#include "furuta.h"
#include "lqr_gain.h"

static float wrap(float a)
{
    const float pi = 3.14159265358979f;
    while (a > pi) {
        a -= 2.0f * pi;
    }
    while (a < -pi) {
        a += 2.0f * pi;
    }
    return a;
}

int main(void)
{
    static const float K[4] = FURUTA_K;
    const float upright[4] = {0.0f, 3.14159265358979f, 0.0f, 0.0f};
    const float h = 1e-3f;
    float x[4] = {0.0f, 3.14159265358979f - 0.2f, 0.0f, 0.0f};
    int k, i;
    for (k = 0; k < 4000; ++k) {
        float u[1] = {0.0f}, e[4];
        long n_rhs = 0;
        int code;
        for (i = 0; i < 4; ++i) {
            e[i] = x[i] - upright[i];
        }
        e[0] = wrap(e[0]);
        e[1] = wrap(e[1]);
        for (i = 0; i < 4; ++i) {
            u[0] -= K[i] * e[i];
        }
        code = furuta_integrate(FURUTA_RK4, (float)k * h, (float)(k + 1) * h, h, 0.0f, 0.0f, x, u, NULL, x, &n_rhs);
        if (code != FURUTA_OK) {
            printf("furuta_integrate returned %d at step %d\n", code, k);
            return 1;
        }
        if ((k + 1) % 500 == 0) {
            printf("t %.3f x %.9g %.9g %.9g %.9g u %.9g\n", (double)((float)(k + 1) * h), (double)x[0], (double)x[1],
                   (double)x[2], (double)x[3], (double)u[0]);
        }
    }
    return 0;
}
