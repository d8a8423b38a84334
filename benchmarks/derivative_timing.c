/* Single-call timing harness for symgen's generated derivative functions (used by
 * derivative_speed.py): inverse_dynamics_derivatives (q, qd, qdd) or forward_dynamics_derivatives
 * (q, V_m, tau), each with three NV x NV outputs.
 *
 * Built together with the generated <module>.c as
 *   cc -O3 -march=native -std=c99 -DFUNC=symgen_<module>_<function> -DNQ=.. -DNV=..
 *      derivative_timing.c <module>.c -lm
 * Usage: ./timer STATES COUNT REPEATS OUT
 *   STATES: float64 file x1[COUNT][NQ], x2[COUNT][NV], x3[COUNT][NV] (little endian)
 *   prints "median_ns min_ns" per call; writes the three matrices of every state, row-major,
 *   to OUT for the comparison with Pinocchio. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define BLOCK (3 * NV * NV)

int FUNC(const double *x1, const double *x2, const double *x3, double *a, double *b, double *c, double *cond);

static double now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return 1e9 * (double)t.tv_sec + (double)t.tv_nsec;
}

static int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double pass(int count, const double *x1, const double *x2, const double *x3, double *out)
{
    double sink = 0.0;
    for (int i = 0; i < count; ++i) {
        double *o = out + (size_t)i * BLOCK;
        if (FUNC(x1 + (size_t)i * NQ, x2 + (size_t)i * NV, x3 + (size_t)i * NV, o, o + NV * NV, o + 2 * NV * NV, NULL))
            sink += 1.0;
        sink += o[0];
    }
    return sink;
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: %s STATES COUNT REPEATS OUT\n", argv[0]);
        return 2;
    }
    int count = atoi(argv[2]), repeats = atoi(argv[3]);
    size_t nq = (size_t)count * NQ, nv = (size_t)count * NV, nout = (size_t)count * BLOCK;
    double *buf = malloc(sizeof(double) * (nq + 2 * nv + nout));
    double *x1 = buf, *x2 = buf + nq, *x3 = x2 + nv, *out = x3 + nv;
    double *times = malloc(sizeof(double) * (size_t)repeats);
    FILE *f = fopen(argv[1], "rb");
    if (!f || fread(buf, sizeof(double), nq + 2 * nv, f) != nq + 2 * nv) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 2;
    }
    fclose(f);
    volatile double sink = pass(count, x1, x2, x3, out); /* warm-up */
    int loops = 1; /* calibrate: one repeat lasts at least 20 ms */
    for (;;) {
        double t0 = now_ns();
        for (int k = 0; k < loops; ++k) sink += pass(count, x1, x2, x3, out);
        if (now_ns() - t0 > 2e7 || loops > (1 << 20)) break;
        loops *= 2;
    }
    for (int r = 0; r < repeats; ++r) {
        double t0 = now_ns();
        for (int k = 0; k < loops; ++k) sink += pass(count, x1, x2, x3, out);
        times[r] = (now_ns() - t0) / ((double)loops * count);
    }
    qsort(times, (size_t)repeats, sizeof(double), compare);
    printf("%.3f %.3f\n", times[repeats / 2], times[0]);
    f = fopen(argv[4], "wb");
    if (!f || fwrite(out, sizeof(double), nout, f) != nout) return 2;
    fclose(f);
    free(times);
    free(buf);
    return sink == 12345.678 ? 1 : 0;
}
