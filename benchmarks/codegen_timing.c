/* Single-call timing harness for symgen's generated inverse dynamics (used by codegen_speed.py).
 *
 * Built together with the generated <module>.c as
 *   cc -O3 -march=native -std=c99 -DFUNC=symgen_<module>_inverse_dynamics -DNQ=.. -DNV=..
 *      codegen_timing.c <module>.c -lm
 * Usage: ./timer STATES COUNT REPEATS OUT
 *   STATES: float64 file q[COUNT][NQ], qd[COUNT][NV], qdd[COUNT][NV] (little endian)
 *   prints "median_ns min_ns" per call; writes tau[COUNT][NV] to OUT for the accuracy check.
 * With -DDERIVATIVES (derivative_speed.py) FUNC is a derivative function with three NV x NV
 * outputs (inverse_dynamics_derivatives (q, qd, qdd) or forward_dynamics_derivatives
 * (q, V_m, tau)), and OUT holds the three matrices of every state, row-major. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#ifdef DERIVATIVES
#define NOUT (3 * NV * NV)
int FUNC(const double *q, const double *qd, const double *qdd, double *a, double *b, double *c, double *cond);
#define CALL(q, qd, qdd, out) FUNC(q, qd, qdd, out, (out) + NV * NV, (out) + 2 * NV * NV, NULL)
#else
#define NOUT NV
int FUNC(const double *q, const double *qd, const double *qdd, double *tau, double *cond);
#define CALL(q, qd, qdd, out) FUNC(q, qd, qdd, out, NULL)
#endif

static double now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);  /* CPU time of this thread: time slices given to other processes are not counted */
    return 1e9 * (double)t.tv_sec + (double)t.tv_nsec;
}

static int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* One pass over all states; returns a checksum so nothing can be optimised away. */
static double pass(int count, const double *q, const double *qd, const double *qdd, double *tau)
{
    double sink = 0.0;
    for (int i = 0; i < count; ++i) {
        if (CALL(q + (size_t)i * NQ, qd + (size_t)i * NV, qdd + (size_t)i * NV, tau + (size_t)i * NOUT))
            sink += 1.0;
        sink += tau[(size_t)i * NOUT];
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
    size_t nq = (size_t)count * NQ, nv = (size_t)count * NV, nout = (size_t)count * NOUT;
    double *buf = malloc(sizeof(double) * (nq + 2 * nv + nout));
    double *q = buf, *qd = buf + nq, *qdd = qd + nv, *tau = qdd + nv;
    double *times = malloc(sizeof(double) * (size_t)repeats);
    FILE *f = fopen(argv[1], "rb");
    if (!f || fread(buf, sizeof(double), nq + 2 * nv, f) != nq + 2 * nv) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 2;
    }
    fclose(f);
    volatile double sink = pass(count, q, qd, qdd, tau); /* warm-up */
    int loops = 1; /* calibrate: one repeat lasts at least 20 ms */
    for (;;) {
        double t0 = now_ns();
        for (int k = 0; k < loops; ++k) sink += pass(count, q, qd, qdd, tau);
        if (now_ns() - t0 > 2e7 || loops > (1 << 20)) break;
        loops *= 2;
    }
    for (int r = 0; r < repeats; ++r) {
        double t0 = now_ns();
        for (int k = 0; k < loops; ++k) sink += pass(count, q, qd, qdd, tau);
        times[r] = (now_ns() - t0) / ((double)loops * count);
    }
    qsort(times, (size_t)repeats, sizeof(double), compare);
    printf("%.3f %.3f\n", times[repeats / 2], times[0]);
    f = fopen(argv[4], "wb");
    if (!f || fwrite(tau, sizeof(double), nout, f) != nout) return 2;
    fclose(f);
    free(times);
    free(buf);
    return sink == 12345.678 ? 1 : 0;
}
