/* furuta_dlqr.c - the Furuta pendulum balanced upright by a discrete-time LQR designed and run in
 * plain C99 on the generated model alone (specs/furuta.toml, gyrochain generate):
 *
 *   1. furuta_step_jacobian gives Ad = dxn/dx and Bd = dxn/du of the 1 ms RK4 step the controller
 *      runs, exactly, at the upright equilibrium x* = (0, pi, 0, 0);
 *   2. the discrete algebraic Riccati equation P = Q + Ad' P Ad - Ad' P Bd (R + Bd' P Bd)^-1 Bd' P Ad
 *      is solved by the structure-preserving doubling algorithm (below: quadratic convergence, no
 *      eigenvalue solver), and the gain is K = (R + Bd' P Bd)^-1 Bd' P Ad;
 *   3. the closed loop u = -K (x - x*), the angles wrapped, runs for 5 s on furuta_step from 0.2 rad
 *      off upright through three disturbances: the pendulum struck at t = 1 s (its rate jumps by
 *      +1 rad/s) and at t = 2.5 s (-1.5 rad/s), and a constant torque of 0.02 N m added to the
 *      motor's from t = 3.5 s on.
 *
 * It prints K, the largest tilt after each disturbance and the state at the end; the exit status is
 * 0 when the pendulum ends within 1e-3 rad of upright, 1 when it falls.  With the argument "open"
 * the loop runs without the controller (the pendulum falls: status 1).
 *
 *   gyrochain generate specs/furuta.toml
 *   cc -std=c99 -O2 -I generated/furuta examples/furuta_dlqr.c generated/furuta/furuta.c -lm -o furuta_dlqr
 *   ./furuta_dlqr
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "furuta.h"

#define N 4 /* the state: arm angle, pendulum angle, their rates */
#define M 1 /* the input: the motor's torque on the arm */
#define PI 3.14159265358979323846

/* the weights: arm angle, pendulum angle, their rates; the motor torque */
static const double Qw[N] = {1.0, 10.0, 0.1, 0.1};
static const double Rw = 10.0;

/* C = A B (all N x N, row-major); C may not be A or B */
static void mul(const double *A, const double *B, double *C)
{
    int i, j, k;
    for (i = 0; i < N; ++i) {
        for (j = 0; j < N; ++j) {
            double s = 0.0;
            for (k = 0; k < N; ++k) {
                s += A[i * N + k] * B[k * N + j];
            }
            C[i * N + j] = s;
        }
    }
}

/* X = A^-1 B by Gaussian elimination with partial pivoting (A, B N x N; A is overwritten);
 * returns 0 when A is singular */
static int solve(double *A, const double *B, double *X)
{
    int i, j, k;
    memcpy(X, B, sizeof(double) * N * N);
    for (k = 0; k < N; ++k) {
        int p = k;
        for (i = k + 1; i < N; ++i) {
            if (fabs(A[i * N + k]) > fabs(A[p * N + k])) {
                p = i;
            }
        }
        if (A[p * N + k] == 0.0) {
            return 0;
        }
        for (j = 0; j < N; ++j) {
            double t = A[k * N + j];
            A[k * N + j] = A[p * N + j];
            A[p * N + j] = t;
            t = X[k * N + j];
            X[k * N + j] = X[p * N + j];
            X[p * N + j] = t;
        }
        for (i = k + 1; i < N; ++i) {
            const double l = A[i * N + k] / A[k * N + k];
            for (j = 0; j < N; ++j) {
                A[i * N + j] -= l * A[k * N + j];
                X[i * N + j] -= l * X[k * N + j];
            }
        }
    }
    for (k = N - 1; k >= 0; --k) {
        for (j = 0; j < N; ++j) {
            double s = X[k * N + j];
            for (i = k + 1; i < N; ++i) {
                s -= A[k * N + i] * X[i * N + j];
            }
            X[k * N + j] = s / A[k * N + k];
        }
    }
    return 1;
}

/* The stabilising solution P of the DARE by the structure-preserving doubling algorithm
 * (Chu, Fan, Lin and Wang, Int. J. Control 77 (2004)): from A0 = Ad, G0 = Bd R^-1 Bd', H0 = Q,
 *   W = I + G H,  A <- A W^-1 A,  G <- G + A W^-1 G A',  H <- H + A' H W^-1 A,
 * H converges quadratically to P.  Returns the iterations taken, or -1. */
static int dare(const double *Ad, const double *Bd, double *P)
{
    double A[N * N], G[N * N], H[N * N], W[N * N], T[N * N], S[N * N], X[N * N], I[N * N];
    int i, j, it;
    for (i = 0; i < N; ++i) {
        for (j = 0; j < N; ++j) {
            A[i * N + j] = Ad[i * N + j];
            G[i * N + j] = Bd[i] * Bd[j] / Rw; /* Bd is N x 1 */
            H[i * N + j] = i == j ? Qw[i] : 0.0;
            I[i * N + j] = i == j ? 1.0 : 0.0;
        }
    }
    for (it = 1; it <= 100; ++it) {
        double change = 0.0, size = 0.0;
        double WiA[N * N], WiG[N * N], At[N * N], An[N * N], Gn[N * N], Hn[N * N];
        mul(G, H, T);
        for (i = 0; i < N * N; ++i) {
            W[i] = I[i] + T[i];
        }
        memcpy(S, W, sizeof S);
        if (!solve(S, A, WiA)) {
            return -1;
        }
        memcpy(S, W, sizeof S);
        if (!solve(S, G, WiG)) {
            return -1;
        }
        for (i = 0; i < N; ++i) {
            for (j = 0; j < N; ++j) {
                At[i * N + j] = A[j * N + i];
            }
        }
        mul(A, WiA, An);      /* A W^-1 A */
        mul(A, WiG, T);       /* A W^-1 G */
        mul(T, At, X);        /* A W^-1 G A' */
        mul(H, WiA, T);       /* H W^-1 A */
        mul(At, T, S);        /* A' H W^-1 A */
        for (i = 0; i < N * N; ++i) {
            Gn[i] = G[i] + X[i];
            Hn[i] = H[i] + S[i];
            change = fmax(change, fabs(S[i]));
            size = fmax(size, fabs(Hn[i]));
        }
        for (i = 0; i < N; ++i) {  /* G and H stay symmetric: keep them so against round-off */
            for (j = 0; j < i; ++j) {
                Gn[i * N + j] = Gn[j * N + i] = 0.5 * (Gn[i * N + j] + Gn[j * N + i]);
                Hn[i * N + j] = Hn[j * N + i] = 0.5 * (Hn[i * N + j] + Hn[j * N + i]);
            }
        }
        memcpy(A, An, sizeof A);
        memcpy(G, Gn, sizeof G);
        memcpy(H, Hn, sizeof H);
        if (change <= 1e-14 * size) {
            memcpy(P, H, sizeof H);
            return it;
        }
    }
    return -1;
}

static double wrap(double a)
{
    return a - 2.0 * PI * floor((a + PI) / (2.0 * PI));
}

int main(int argc, char **argv)
{
    const double h = 1e-3, upright[N] = {0.0, PI, 0.0, 0.0};
    const int open = argc > 1 && strcmp(argv[1], "open") == 0;
    double x[N] = {0.0, PI - 0.2, 0.0, 0.0}, Ad[N * N], Bd[N * M], P[N * N], K[N], tilt = 0.0;
    double PB[N], r = Rw;
    int i, j, k, it, code, phase = 0;
    if ((code = furuta_step_jacobian(0.0, upright, NULL, NULL, h, NULL, Ad, Bd, NULL)) != FURUTA_OK) {
        printf("furuta_step_jacobian returned %d\n", code);
        return 2;
    }
    if ((it = dare(Ad, Bd, P)) < 0) {
        printf("the Riccati equation has no stabilising solution\n");
        return 2;
    }
    for (i = 0; i < N; ++i) {  /* K = (R + Bd' P Bd)^-1 Bd' P Ad */
        PB[i] = 0.0;
        for (j = 0; j < N; ++j) {
            PB[i] += P[i * N + j] * Bd[j];
        }
        r += Bd[i] * PB[i];
    }
    for (j = 0; j < N; ++j) {
        K[j] = 0.0;
        for (i = 0; i < N; ++i) {
            K[j] += PB[i] * Ad[i * N + j] / r;
        }
    }
    printf("Riccati: %d doubling steps\nK = %.12g %.12g %.12g %.12g\n", it, K[0], K[1], K[2], K[3]);
    for (k = 0; k < 5000; ++k) {
        const double t = k * h;
        double u[M] = {0.0}, e[N];
        if (k == 1000 || k == 2500 || k == 3500) {
            printf("largest tilt before t = %.1f s: %.3e rad\n", t, tilt);
            tilt = 0.0;
            phase++;
        }
        if (k == 1000) {
            x[3] += 1.0;
        }
        if (k == 2500) {
            x[3] -= 1.5;
        }
        for (i = 0; i < N; ++i) {
            e[i] = x[i] - upright[i];
        }
        e[0] = wrap(e[0]);
        e[1] = wrap(e[1]);
        for (i = 0; i < N && !open; ++i) {
            u[0] -= K[i] * e[i];
        }
        u[0] += phase == 3 ? 0.02 : 0.0;
        if ((code = furuta_step(t, x, u, NULL, h, x)) != FURUTA_OK) {
            printf("furuta_step returned %d at t = %.3f s\n", code, t);
            return 1;
        }
        tilt = fmax(tilt, fabs(wrap(x[1] - PI)));
    }
    printf("largest tilt after t = 3.5 s: %.3e rad\n", tilt);
    printf("at t = 5 s: arm %.6f rad, tilt %.3e rad, rates %.3e %.3e rad/s\n", x[0], wrap(x[1] - PI), x[2], x[3]);
    return fabs(wrap(x[1] - PI)) < 1e-3 ? 0 : 1;
}
