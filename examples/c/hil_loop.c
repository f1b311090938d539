/* A HIL loop in C over pcsim's real-time catenary: read time, contact force and pantograph
 * position (relative to the case's start) from a CSV (the input format of `pcsim hil`), step the
 * catenary once per row, print time, wire height and wire velocity with full precision.
 *
 *   cc examples/c/hil_loop.c -Iinclude -Ltarget/release -lpcsim_capi -o hil_loop
 *   LD_LIBRARY_PATH=target/release ./hil_loop syt-7.0-9.8 215 in.csv > out.csv */
#include <stdio.h>
#include <stdlib.h>
#include "pcsim.h"

int main(int argc, char **argv) {
    if (argc != 4) { fprintf(stderr, "usage: %s PRESET WINDOW_M INPUT.csv\n", argv[0]); return 2; }
    char err[512];
    PcsimRt *rt = pcsim_rt_new(argv[1], 0, atof(argv[2]), err, sizeof err);
    if (!rt) { fprintf(stderr, "pcsim: %s\n", err); return 1; }
    FILE *in = fopen(argv[3], "r");
    if (!in) { perror(argv[3]); pcsim_rt_free(rt); return 1; }
    char line[256];
    if (!fgets(line, sizeof line, in)) { fprintf(stderr, "empty input\n"); return 1; } /* header */
    printf("time_s,wire_height_m,wire_velocity_m_s\n");
    double t, force, x, h, v, dt = pcsim_rt_dt(rt), x0 = pcsim_rt_start_position(rt);
    long k = 0;
    while (fscanf(in, "%lf,%lf,%lf", &t, &force, &x) == 3) {
        int s = pcsim_rt_step(rt, force, x0 + x, &h, &v, NULL);
        if (s != PCSIM_OK) {
            pcsim_rt_check_input(rt, force, x0 + x, err, sizeof err);
            fprintf(stderr, "row %ld refused (%d): %s\n", k + 2, s, err);
            pcsim_rt_free(rt);
            return 1;
        }
        k++;
        printf("%.17g,%.17g,%.17g\n", k * dt, h, v);
    }
    fclose(in);
    pcsim_rt_free(rt);
    return 0;
}
