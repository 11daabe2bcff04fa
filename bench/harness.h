/* Common timing harness of bench/speed.py: one forward-dynamics implementation per program.
 * The including file defines bench_setup() (returns the number of bodies n) and
 * bench_qdd(x, qdd); it may define BENCH_NOUT(n), the number of outputs of bench_qdd (default n;
 * n * 2n for a Jacobian).
 * stdin: K states x (2N numbers each).  stdout: the outputs for each state (for the correctness
 * check against the reference model), then "ns <median> <min>" per call over repeated sweeps. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 199309L
#endif
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double bench_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int bench_cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

#define BENCH_K 64
#define BENCH_NMAX 128
#define BENCH_REPEATS 21
#ifndef BENCH_NOUT
#define BENCH_NOUT(n) (n)
#endif

int main(void)
{
    static double xs[BENCH_K][2 * BENCH_NMAX], out[2 * BENCH_NMAX * BENCH_NMAX], times[BENCH_REPEATS];
    volatile double sink = 0.0;
    long sweeps, r, i;
    int k, j, K = 0;
    double t0, budget;
    const int BENCH_N = bench_setup();
    if (BENCH_N < 1 || BENCH_N > BENCH_NMAX) {
        return 2;
    }
    while (K < BENCH_K) {
        for (j = 0; j < 2 * BENCH_N; ++j) {
            if (scanf("%lf", &xs[K][j]) != 1) {
                goto done;
            }
        }
        ++K;
    }
done:
    if (K == 0) {
        return 1;
    }
    for (k = 0; k < K; ++k) {
        if (bench_qdd(xs[k], out) != 0) {
            printf("error\n");
        }
        for (j = 0; j < BENCH_NOUT(BENCH_N); ++j) {
            printf("%.17g ", out[j]);
        }
        printf("\n");
    }
    /* sweeps per repeat: about 20 ms of work */
    t0 = bench_now();
    for (k = 0; k < K; ++k) {
        bench_qdd(xs[k], out);
    }
    budget = bench_now() - t0;
    sweeps = (long)(0.02 / (budget > 1e-9 ? budget : 1e-9)) + 1;
    if (getenv("BENCH_SWEEPS") != NULL) { /* a fixed count: instructions per call under callgrind */
        sweeps = atol(getenv("BENCH_SWEEPS"));
    }
    for (r = 0; r < BENCH_REPEATS; ++r) {
        t0 = bench_now();
        for (i = 0; i < sweeps; ++i) {
            for (k = 0; k < K; ++k) {
                bench_qdd(xs[k], out);
                sink += out[BENCH_N - 1];
            }
        }
        times[r] = (bench_now() - t0) / (double)(sweeps * K) * 1e9;
    }
    qsort(times, BENCH_REPEATS, sizeof(double), bench_cmp);
    printf("ns %.1f %.1f\n", times[BENCH_REPEATS / 2], times[0]);
    return 0;
}
