/* pcsim.h: the C API of pcsim's real-time catenary (a moving-window pantograph-catenary model)
 * for rig software written in C or C++. Link with -lpcsim_capi (libpcsim_capi.so or .a, built by
 * `cargo build --release`; the static library also needs -lm -lpthread -ldl).
 *
 * Units are SI. Every function returns PCSIM_OK (0) or an error code; functions that can fail
 * for a reason worth reading take a caller buffer for the message. pcsim_rt_step allocates
 * nothing, and no call lets a panic cross into C (a caught one gives PCSIM_ERR_INTERNAL and the
 * handle must be freed). Handles are independent: several may step in several threads.
 *
 * This header is checked against the library's Rust signatures by crates/pcsim-capi/tests. */
#ifndef PCSIM_H
#define PCSIM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PCSIM_OK 0
#define PCSIM_ERR_ARGUMENT 1 /* NULL pointer, value out of range, buffer too small */
#define PCSIM_ERR_CASE 2     /* the case could not be read or is invalid */
#define PCSIM_ERR_INPUT 3    /* the step's input was refused; the catenary is unchanged */
#define PCSIM_ERR_STATE 4    /* a saved state of another case, window or version, or damaged */
#define PCSIM_ERR_INTERNAL 5 /* a panic was caught; free the handle */
#define PCSIM_ERR_ROLLED_BACK 6 /* the step gave an unsound state and was rolled back; unchanged */

typedef struct PcsimRt PcsimRt;

/* The library's version (static string). */
const char *pcsim_version(void);

/* Build the real-time catenary (hardware in the loop) of a preset (is_file = 0, e.g.
 * "syt-7.0-9.8") or a case file (is_file != 0) with a window of window_m metres. NULL on error,
 * with the message in err (err_len bytes, NUL-terminated). */
PcsimRt *pcsim_rt_new(const char *case_name, int is_file, double window_m, char *err, size_t err_len);

/* One fixed step: contact force (N, pushing the wire up) and pantograph track position (m) in;
 * contact-wire height (m), vertical velocity (m/s) and lateral position (m) at the contact point
 * out (any output pointer may be NULL). No allocation. The step contract (README, "The real-time
 * step contract"): an input that is not finite, whose force lies beyond the case's bound, whose
 * position lies outside the model or the window, or that moves too fast gives PCSIM_ERR_INPUT; a
 * step that gives an unsound state is rolled back (PCSIM_ERR_ROLLED_BACK). Either way the
 * catenary is unchanged. */
int pcsim_rt_step(PcsimRt *rt, double force_n, double track_position_m, double *height_m, double *velocity_m_s, double *lateral_m);

/* Why the last pcsim_rt_step was not taken: its status with the reason in msg (starting with the
 * reason's code, e.g. "input refused (force_out_of_bound): ..."), or PCSIM_OK if it was taken. */
int pcsim_rt_last_refusal(const PcsimRt *rt, char *msg, size_t msg_len);

/* Why an input would be refused (PCSIM_ERR_INPUT with the message), or PCSIM_OK. */
int pcsim_rt_check_input(PcsimRt *rt, double force_n, double track_position_m, char *err, size_t err_len);

/* The fixed time step, s, and the track position of the first input (the case's start), m. */
double pcsim_rt_dt(const PcsimRt *rt);
double pcsim_rt_start_position(const PcsimRt *rt);

/* Save the state into buf (at least pcsim_rt_state_size bytes; *written, when not NULL, receives
 * the bytes written: on a line the windows differ in size, so a state may be shorter); restore
 * takes that length or any length up to pcsim_rt_state_size, and continues bit for bit. */
size_t pcsim_rt_state_size(const PcsimRt *rt);
int pcsim_rt_save(PcsimRt *rt, uint8_t *buf, size_t len, size_t *written);
int pcsim_rt_restore(PcsimRt *rt, const uint8_t *buf, size_t len, char *err, size_t err_len);

/* Free the catenary (NULL is a no-op). */
void pcsim_rt_free(PcsimRt *rt);

#ifdef __cplusplus
}
#endif

#endif /* PCSIM_H */
