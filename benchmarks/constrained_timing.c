/* Single-call timing harness for symgen's generated forward dynamics (used by constrained_forward.py).
 *
 * Relies only on the generated function's public signature
 *   int FUNC(const double *q, const double *V_m, const double *tau, [const double *eta_m,]
 *            double *dV_m, [double *eta_f,] double *cond);
 * (eta_m present when NE > 0, eta_f when NF > 0), built together with the generated <module>.c as
 *   cc -O3 -march=native -std=c99 -DFUNC=symgen_<module>_forward_dynamics -DNQ=.. -DNM=.. -DNT=..
 *      -DNE=.. -DNF=.. constrained_timing.c <module>.c -lm
 * With -DDERIVATIVES (constrained_derivatives.py) FUNC is <module>_forward_dynamics_derivatives of a
 * scene without eta_m, its prototype from the generated header (-include <module>.h), and
 * -DNOUT=.. -D'DERIV_ARGS(o)=o, o + .., ...' place its output matrices in one block of NOUT doubles
 * per state, written to OUT in place of dV_m and eta_f.
 * Usage: ./timer STATES COUNT REPEATS OUT
 *   STATES: float64 q[COUNT][NQ], V_m[COUNT][NM], tau[COUNT][NT], eta_m[COUNT][NE]
 *   prints "median_ns min_ns" per call; writes dV_m[COUNT][NM] then eta_f[COUNT][NF] to OUT. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#ifdef DERIVATIVES
#if NE > 0
#error "the derivative timing takes no eta_m"
#endif
#define NRES NOUT
#define CALL(i) FUNC(q + (i) * NQ, vm + (i) * NM, tau + (i) * NT, DERIV_ARGS(dvm + (i) * NOUT), NULL)
#elif NE > 0 && NF > 0
int FUNC(const double *q, const double *V_m, const double *tau, const double *eta_m, double *dV_m, double *eta_f,
         double *cond);
#define CALL(i) FUNC(q + (i) * NQ, vm + (i) * NM, tau + (i) * NT, eta_m + (i) * NE, dvm + (i) * NM, \
                     eta_f + (i) * NF, NULL)
#elif NE > 0
int FUNC(const double *q, const double *V_m, const double *tau, const double *eta_m, double *dV_m, double *cond);
#define CALL(i) FUNC(q + (i) * NQ, vm + (i) * NM, tau + (i) * NT, eta_m + (i) * NE, dvm + (i) * NM, NULL)
#elif NF > 0
int FUNC(const double *q, const double *V_m, const double *tau, double *dV_m, double *eta_f, double *cond);
#define CALL(i) FUNC(q + (i) * NQ, vm + (i) * NM, tau + (i) * NT, dvm + (i) * NM, eta_f + (i) * NF, NULL)
#else
int FUNC(const double *q, const double *V_m, const double *tau, double *dV_m, double *cond);
#define CALL(i) FUNC(q + (i) * NQ, vm + (i) * NM, tau + (i) * NT, dvm + (i) * NM, NULL)
#endif
#ifndef NRES
#define NRES (NM + NF)
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

static const double *q, *vm, *tau, *eta_m;
static double *dvm, *eta_f;

/* One pass over all states; returns a checksum so nothing can be optimised away. */
static double pass(size_t count)
{
    double sink = 0.0;
    for (size_t i = 0; i < count; ++i) {
        if (CALL(i)) sink += 1.0;
        sink += dvm[i * NRES];
    }
    return sink;
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: %s STATES COUNT REPEATS OUT\n", argv[0]);
        return 2;
    }
    size_t count = (size_t)atoi(argv[2]);
    int repeats = atoi(argv[3]);
    size_t nin = count * (NQ + NM + NT + NE), nout = count * NRES;
    double *buf = malloc(sizeof(double) * (nin + nout + 1));
    double *times = malloc(sizeof(double) * (size_t)repeats);
    q = buf;
    vm = q + count * NQ;
    tau = vm + count * NM;
    eta_m = tau + count * NT;
    dvm = buf + nin;
    eta_f = dvm + count * NM;
    FILE *f = fopen(argv[1], "rb");
    if (!f || fread(buf, sizeof(double), nin, f) != nin) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 2;
    }
    fclose(f);
    volatile double sink = pass(count); /* warm-up */
    int loops = 1;                      /* calibrate: one repeat lasts at least 20 ms */
    for (;;) {
        double t0 = now_ns();
        for (int k = 0; k < loops; ++k) sink += pass(count);
        if (now_ns() - t0 > 2e7 || loops > (1 << 20)) break;
        loops *= 2;
    }
    for (int r = 0; r < repeats; ++r) {
        double t0 = now_ns();
        for (int k = 0; k < loops; ++k) sink += pass(count);
        times[r] = (now_ns() - t0) / ((double)loops * (double)count);
    }
    qsort(times, (size_t)repeats, sizeof(double), compare);
    printf("%.3f %.3f\n", times[repeats / 2], times[0]);
    f = fopen(argv[4], "wb");
    if (!f || fwrite(dvm, sizeof(double), nout, f) != nout) return 2;
    fclose(f);
    free(times);
    free(buf);
    return sink == 12345.678 ? 1 : 0;
}
