/* Single-call timing harness for symgen's generated adaptive control law (used by control_speed.py).
 *
 * Built together with the generated <module>.c as
 *   cc -O3 -march=native -std=c99 -DFUNC=symgen_<module>_control -DNQ=.. -DNV=.. -DNP=..
 *      control_timing.c <module>.c -lm
 * (NP: number of uncertain parameters, the length of P_hat; 0 when the function has no P_hat).
 * Usage: ./timer STATES COUNT REPEATS OUT
 *   STATES: float64 file q[COUNT][NQ], V_m[COUNT][NV], V_mr[COUNT][NV], dV_mr[COUNT][NV],
 *           P_hat[COUNT][NP] (little endian)
 *   prints "median_ns min_ns" per call; writes tau[COUNT][NV] to OUT for the accuracy check. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#if NP > 0
int FUNC(const double *q, const double *v_m, const double *v_mr, const double *dv_mr, const double *p_hat,
         double *tau, double *cond);
#define CALL(i) FUNC(q + (size_t)(i) * NQ, v_m + (size_t)(i) * NV, v_mr + (size_t)(i) * NV, \
                     dv_mr + (size_t)(i) * NV, p_hat + (size_t)(i) * NP, tau + (size_t)(i) * NV, NULL)
#else
int FUNC(const double *q, const double *v_m, const double *v_mr, const double *dv_mr, double *tau, double *cond);
#define CALL(i) FUNC(q + (size_t)(i) * NQ, v_m + (size_t)(i) * NV, v_mr + (size_t)(i) * NV, \
                     dv_mr + (size_t)(i) * NV, tau + (size_t)(i) * NV, NULL)
#endif

static const double *q, *v_m, *v_mr, *dv_mr, *p_hat;
static double *tau;

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
static double pass(int count)
{
    double sink = 0.0;
    for (int i = 0; i < count; ++i) {
        if (CALL(i)) sink += 1.0;
        sink += tau[(size_t)i * NV];
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
    size_t nq = (size_t)count * NQ, nv = (size_t)count * NV, np = (size_t)count * NP;
    size_t total = nq + 3 * nv + np;
    double *buf = malloc(sizeof(double) * (total + nv + 1));
    double *times = malloc(sizeof(double) * (size_t)repeats);
    q = buf;
    v_m = buf + nq;
    v_mr = v_m + nv;
    dv_mr = v_mr + nv;
    p_hat = dv_mr + nv;
    tau = buf + total;
    FILE *f = fopen(argv[1], "rb");
    if (!f || fread(buf, sizeof(double), total, f) != total) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 2;
    }
    fclose(f);
    volatile double sink = pass(count); /* warm-up */
    int loops = 1; /* calibrate: one repeat lasts at least 20 ms */
    for (;;) {
        double t0 = now_ns();
        for (int k = 0; k < loops; ++k) sink += pass(count);
        if (now_ns() - t0 > 2e7 || loops > (1 << 20)) break;
        loops *= 2;
    }
    for (int r = 0; r < repeats; ++r) {
        double t0 = now_ns();
        for (int k = 0; k < loops; ++k) sink += pass(count);
        times[r] = (now_ns() - t0) / ((double)loops * count);
    }
    qsort(times, (size_t)repeats, sizeof(double), compare);
    printf("%.3f %.3f\n", times[repeats / 2], times[0]);
    f = fopen(argv[4], "wb");
    if (!f || fwrite(tau, sizeof(double), nv, f) != nv) return 2;
    fclose(f);
    free(times);
    free(buf);
    return sink == 12345.678 ? 1 : 0;
}
