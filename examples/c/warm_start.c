/* The README's warm-start pattern, as a program: build the real-time catenary of a case, save its
 * state into a buffer of pcsim_rt_state_size bytes, step it, restore the saved state, step it the
 * same way again, and check that both passes end bit for bit at the same height and velocity.
 * On a line of several tension lengths the windows differ in size: the saved state may be shorter
 * than pcsim_rt_state_size (pcsim_rt_save says how long), and restore takes either length.
 *
 *   cc examples/c/warm_start.c -Iinclude target/release/libpcsim_capi.a -lm -lpthread -ldl -o warm_start
 *   ./warm_start en50318-2018-like-simple 240 8000        (exit 0: restored bit for bit) */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "pcsim.h"

/* Step n times with a varying force from step k0; the last height and velocity in out[2]. */
static int drive(PcsimRt *rt, long k0, long n, double out[2]) {
    double dt = pcsim_rt_dt(rt), x0 = pcsim_rt_start_position(rt), lateral;
    for (long k = k0; k < k0 + n; k++) {
        double t = (k + 1) * dt;
        double force = 90.0 + 15.0 * sin(7.3 * t);
        if (pcsim_rt_step(rt, force, x0 + 222.0 / 3.6 * t, &out[0], &out[1], &lateral) != PCSIM_OK)
            return 1;
    }
    return 0;
}

int main(int argc, char **argv) {
    if (argc != 4) { fprintf(stderr, "usage: %s PRESET WINDOW_M STEPS\n", argv[0]); return 2; }
    char err[512];
    PcsimRt *rt = pcsim_rt_new(argv[1], 0, atof(argv[2]), err, sizeof err);
    if (!rt) { fprintf(stderr, "pcsim: %s\n", err); return 1; }
    long steps = atol(argv[3]);
    size_t n = pcsim_rt_state_size(rt), used = 0;
    uint8_t *warm = malloc(n);
    double a[2], b[2];
    if (!warm || drive(rt, 0, 100, a) != 0) return 1;
    if (pcsim_rt_save(rt, warm, n, &used) != PCSIM_OK) { fprintf(stderr, "save failed\n"); return 1; }
    /* Right after the save, with the whole buffer (the README's `n`). */
    if (pcsim_rt_restore(rt, warm, n, err, sizeof err) != PCSIM_OK) { fprintf(stderr, "restore(n): %s\n", err); return 1; }
    if (drive(rt, 100, steps, a) != 0) { fprintf(stderr, "a step was refused\n"); return 1; }
    if (pcsim_rt_restore(rt, warm, used, err, sizeof err) != PCSIM_OK) { fprintf(stderr, "restore(used): %s\n", err); return 1; }
    if (drive(rt, 100, steps, b) != 0) { fprintf(stderr, "a step was refused\n"); return 1; }
    int same = memcmp(a, b, sizeof a) == 0;
    printf("state %zu of %zu bytes; after %ld steps height %.17g m, again %.17g m: %s\n", used, n, steps,
           a[0], b[0], same ? "bit for bit" : "DIFFERENT");
    free(warm);
    pcsim_rt_free(rt);
    return same ? 0 : 1;
}
