/* embed_gimbal.c - a program that embeds a generated model with plain cc.
 *
 *   cc -std=c99 -O2 -I generated/gimbal examples/embed_gimbal.c generated/gimbal/gimbal.c -lm -o embed_gimbal
 *   ./embed_gimbal
 *
 * Integrates the balanced gyroscope in a Cardan suspension for 2 s with a fixed-step RK4
 * (the control-loop case) and prints the drift of the energy and momentum integrals.
 */
#include <math.h>
#include <stdio.h>

#include "gimbal.h"

static int rk4_step(double t, double h, double *x)
{
    double k1[2 * GIMBAL_N], k2[2 * GIMBAL_N], k3[2 * GIMBAL_N], k4[2 * GIMBAL_N], y[2 * GIMBAL_N];
    int i, code;
    if ((code = gimbal_rhs(t, x, NULL, NULL, k1)) != GIMBAL_OK) return code;
    for (i = 0; i < 2 * GIMBAL_N; ++i) y[i] = x[i] + 0.5 * h * k1[i];
    if ((code = gimbal_rhs(t + 0.5 * h, y, NULL, NULL, k2)) != GIMBAL_OK) return code;
    for (i = 0; i < 2 * GIMBAL_N; ++i) y[i] = x[i] + 0.5 * h * k2[i];
    if ((code = gimbal_rhs(t + 0.5 * h, y, NULL, NULL, k3)) != GIMBAL_OK) return code;
    for (i = 0; i < 2 * GIMBAL_N; ++i) y[i] = x[i] + h * k3[i];
    if ((code = gimbal_rhs(t + h, y, NULL, NULL, k4)) != GIMBAL_OK) return code;
    for (i = 0; i < 2 * GIMBAL_N; ++i) x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    return GIMBAL_OK;
}

int main(void)
{
    /* psi, phi (inner ring at 30 degrees), psi', phi' */
    double x[2 * GIMBAL_N] = {0.0, 0.5235987755982988, 1.0, 0.5};
    const double h = 1e-3;
    const double e0 = gimbal_energy(x, NULL), k0 = gimbal_momentum(x, NULL);
    double t = 0.0;
    int step, code;
    for (step = 0; step < 2000; ++step, t += h) {
        if ((code = rk4_step(t, h, x)) != GIMBAL_OK) {
            fprintf(stderr, "gimbal_rhs failed with code %d at t = %g\n", code, t);
            return 1;
        }
    }
    printf("t = %.3f  psi = %.12f  phi = %.12f\n", t, x[0], x[1]);
    printf("energy drift %.3e  momentum drift %.3e\n", fabs(gimbal_energy(x, NULL) - e0),
           fabs(gimbal_momentum(x, NULL) - k0));
    return 0;
}
