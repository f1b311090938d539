/* Time per step of pcsim's real-time catenary through the C API and through both FMUs' entry
 * points (dlopen of libpcsim_fmu.so, no host in between), 200 000 steps each, HIL, syt-7.0-9.8,
 * 215 m window. Prints median and 99th percentile per path.
 *
 *   cc -O2 examples/c/bench_step.c -Iinclude -Ltarget/release -lpcsim_capi -ldl -o bench_step
 *   LD_LIBRARY_PATH=target/release taskset -c 0 ./bench_step target/release/libpcsim_fmu.so */
#define _POSIX_C_SOURCE 199309L
#include <dlfcn.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "pcsim.h"

#define N 25000
static double ns[N];

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e9 + t.tv_nsec;
}
static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
static void report(const char *what) {
    qsort(ns, N, sizeof ns[0], cmp);
    printf("%-28s median %.2f us  p99 %.2f us\n", what, ns[N / 2] / 1e3, ns[N * 99 / 100] / 1e3);
}

typedef void *(*inst2_t)(const char *, int, const char *, const char *, const void *, int, int);
typedef int (*f_t)(void *);
typedef int (*setup2_t)(void *, int, double, double, int, double);
typedef int (*setreal_t)(void *, const uint32_t *, size_t, const double *);
typedef int (*do2_t)(void *, double, double, int);
typedef void *(*inst3_t)(const char *, const char *, const char *, bool, bool, bool, bool, const uint32_t *, size_t, void *, void *, void *);
typedef int (*enter3_t)(void *, bool, double, double, bool, double);
typedef int (*set64_t)(void *, const uint32_t *, size_t, const double *, size_t);
typedef int (*do3_t)(void *, double, double, bool, bool *, bool *, bool *, double *);

static const char *TOKEN = "{6b1e4f0a-2c3d-4e5f-8a9b-0c1d2e3f4a5c}";

int main(int argc, char **argv) {
    if (argc != 2) { fprintf(stderr, "usage: %s libpcsim_fmu.so\n", argv[0]); return 2; }
    char err[256];
    PcsimRt *rt = pcsim_rt_new("syt-7.0-9.8", 0, 215.0, err, sizeof err);
    if (!rt) { fprintf(stderr, "%s\n", err); return 1; }
    double dt = pcsim_rt_dt(rt), x0 = pcsim_rt_start_position(rt), h, v, v_ms = 222.0 / 3.6;
    for (int k = 0; k < N; k++) {
        double t = (k + 1) * dt, f = 85.0 + 15.0 * sin(7.3 * t);
        double a = now();
        if (pcsim_rt_step(rt, f, x0 + v_ms * t, &h, &v, NULL) != PCSIM_OK) { fprintf(stderr, "C API step %d refused\n", k); return 1; }
        ns[k] = now() - a;
    }
    report("C API pcsim_rt_step");
    pcsim_rt_free(rt);

    void *lib = dlopen(argv[1], RTLD_NOW);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 1; }
    uint32_t vrs[2] = {1, 2};
    inst2_t inst2 = (inst2_t)dlsym(lib, "fmi2Instantiate");
    void *c2 = inst2("b2", 1, TOKEN, "", NULL, 0, 0);
    ((setup2_t)dlsym(lib, "fmi2SetupExperiment"))(c2, 0, 0, 0, 0, 0);
    ((f_t)dlsym(lib, "fmi2EnterInitializationMode"))(c2);
    ((f_t)dlsym(lib, "fmi2ExitInitializationMode"))(c2);
    setreal_t setr = (setreal_t)dlsym(lib, "fmi2SetReal");
    do2_t do2 = (do2_t)dlsym(lib, "fmi2DoStep");
    for (int k = 0; k < N; k++) {
        double t = k * dt, in[2] = {85.0 + 15.0 * sin(7.3 * t), v_ms * (t + dt)};
        double a = now();
        setr(c2, vrs, 2, in);
        if (do2(c2, t, dt, 1) != 0) { fprintf(stderr, "fmi2DoStep %d refused\n", k); return 1; }
        ns[k] = now() - a;
    }
    report("FMI 2.0 fmi2SetReal+DoStep");
    inst3_t inst3 = (inst3_t)dlsym(lib, "fmi3InstantiateCoSimulation");
    void *c3 = inst3("b3", TOKEN, "", false, false, false, false, NULL, 0, NULL, NULL, NULL);
    ((enter3_t)dlsym(lib, "fmi3EnterInitializationMode"))(c3, false, 0, 0, false, 0);
    ((f_t)dlsym(lib, "fmi3ExitInitializationMode"))(c3);
    set64_t set64 = (set64_t)dlsym(lib, "fmi3SetFloat64");
    do3_t do3 = (do3_t)dlsym(lib, "fmi3DoStep");
    bool e1, e2, e3;
    double last;
    for (int k = 0; k < N; k++) {
        double t = k * dt, in[2] = {85.0 + 15.0 * sin(7.3 * t), v_ms * (t + dt)};
        double a = now();
        set64(c3, vrs, 2, in, 2);
        if (do3(c3, t, dt, true, &e1, &e2, &e3, &last) != 0) { fprintf(stderr, "fmi3DoStep %d refused\n", k); return 1; }
        ns[k] = now() - a;
    }
    report("FMI 3.0 fmi3SetFloat64+DoStep");
    return 0;
}
