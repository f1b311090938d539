/* A HIL loop in C over pcsim's real-time catenary: read time, contact force and pantograph
 * position (relative to the case's start) from a CSV (the input format of `pcsim hil`), step the
 * catenary once per row, print time, wire height, wire velocity and the status with full
 * precision. A row the catenary refuses (or rolls back) is printed with its reason's code and no
 * height, and the exit status is then 1 (as `pcsim hil`).
 *
 *   cc examples/c/hil_loop.c -Iinclude -Ltarget/release -lpcsim_capi -o hil_loop
 *   LD_LIBRARY_PATH=target/release ./hil_loop syt-7.0-9.8 215 in.csv > out.csv */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
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
    printf("time_s,wire_height_m,wire_velocity_m_s,status\n");
    double t, force, x, h, v, dt = pcsim_rt_dt(rt), x0 = pcsim_rt_start_position(rt);
    long k = 0, refused = 0;
    while (fgets(line, sizeof line, in)) {
        /* strtod reads "nan" and "inf" too: the catenary, not the reader, refuses them. */
        char *p = line, *e;
        t = strtod(p, &e); if (e == p || *e != ',') break; p = e + 1;
        force = strtod(p, &e); if (e == p || *e != ',') break; p = e + 1;
        x = strtod(p, &e); if (e == p) break;
        int s = pcsim_rt_step(rt, force, x0 + x, &h, &v, NULL);
        k++;
        if (s != PCSIM_OK) {
            pcsim_rt_last_refusal(rt, err, sizeof err);
            /* The reason's code is the word in parentheses: "input refused (too_fast): ...". */
            char code[64] = "refused";
            const char *a = strchr(err, '('), *b = a ? strchr(a, ')') : NULL;
            if (a && b && b - a - 1 < (long)sizeof code) { memcpy(code, a + 1, b - a - 1); code[b - a - 1] = 0; }
            if (refused++ == 0) fprintf(stderr, "row %ld not stepped (%d): %s\n", k + 1, s, err);
            printf("%.17g,,,%s\n", t + dt, code);
            continue;
        }
        printf("%.17g,%.17g,%.17g,ok\n", t + dt, h, v);
    }
    fclose(in);
    pcsim_rt_free(rt);
    return refused ? 1 : 0;
}
