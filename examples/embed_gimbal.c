/* embed_gimbal.c - a program that embeds a generated model with plain cc.
 *
 *   cc -std=c99 -O2 -I generated/gimbal examples/embed_gimbal.c generated/gimbal/gimbal.c -lm -o embed_gimbal
 *   ./embed_gimbal
 *
 * Integrates the balanced gyroscope in a Cardan suspension for 2 s as a control loop would: one
 * call of the emitted fixed-step RK4 per 1 ms period (u would change between calls; the gimbal
 * has no torques, so it is NULL).  Prints the state, the drift of the energy and momentum
 * integrals, and the same 2 s in one call of the adaptive DOP853.
 */
#include <math.h>
#include <stdio.h>

#include "gimbal.h"

int main(void)
{
    /* psi, phi (inner ring at 30 degrees), psi', phi' */
    const double x0[2 * GIMBAL_N] = {0.0, 0.5235987755982988, 1.0, 0.5};
    double x[2 * GIMBAL_N], xa[2 * GIMBAL_N];
    const double h = 1e-3;
    const double e0 = gimbal_energy(x0, NULL), k0 = gimbal_momentum(x0, NULL);
    long n_rhs = 0, n;
    int i, step, code;
    for (i = 0; i < 2 * GIMBAL_N; ++i) {
        x[i] = x0[i];
    }
    for (step = 0; step < 2000; ++step) {
        code = gimbal_integrate(GIMBAL_RK4, step * h, (step + 1) * h, h, 0.0, 0.0, x, NULL, NULL, x, &n);
        if (code != GIMBAL_OK) {
            fprintf(stderr, "gimbal_integrate failed with code %d at t = %g\n", code, step * h);
            return 1;
        }
        n_rhs += n;
    }
    printf("t = %.3f  psi = %.12f  phi = %.12f  (RK4, %ld rhs)\n", 2000 * h, x[0], x[1], n_rhs);
    printf("energy drift %.3e  momentum drift %.3e\n", fabs(gimbal_energy(x, NULL) - e0),
           fabs(gimbal_momentum(x, NULL) - k0));
    code = gimbal_integrate(GIMBAL_DOP853, 0.0, 2.0, 0.0, 1e-10, 1e-10, x0, NULL, NULL, xa, &n_rhs);
    if (code != GIMBAL_OK) {
        fprintf(stderr, "gimbal_integrate (DOP853) failed with code %d\n", code);
        return 1;
    }
    printf("DOP853: psi = %.12f  phi = %.12f  (%ld rhs)\n", xa[0], xa[1], n_rhs);
    return 0;
}
