//! # pcsim-capi
//!
//! The C API of the real-time catenary for rig software written in C or C++
//! (`include/pcsim.h`): build it from a case file or a preset and a window length, step it with
//! the measured contact force and pantograph position, read the wire's height, velocity and
//! lateral position, save and restore its state, free it. It only translates the core's
//! real-time session ([`pcsim_core::session::RealtimeSession`]), which owns the step contract:
//! the input checks, save, step, soundness and roll-back, the state format. Standard library
//! only (as the FMU, for the same reasons: no panic may cross the boundary, every pointer is
//! checked).
//!
//! - Errors come back as a status (`PCSIM_OK` = 0, else an error code) and, where a message
//!   buffer is given, a NUL-terminated message that names the field or input.
//! - `pcsim_rt_step` allocates nothing; a refused input or a rolled-back step leaves the
//!   catenary unchanged, and `pcsim_rt_last_refusal` says why.
//! - Every entry point runs under `catch_unwind`: a panic gives `PCSIM_ERR_INTERNAL` and marks
//!   the handle unusable.
//!
//! `tests/suite/header.rs` checks `include/pcsim.h` against the signatures below, so that the two
//! cannot drift apart.

#![deny(clippy::undocumented_unsafe_blocks, clippy::missing_safety_doc)]
// No production function over 100 lines (clippy.toml's threshold; issue 52): a long function
// is split into named parts. Tests are exempt (a scenario reads best whole).
#![cfg_attr(not(test), deny(clippy::too_many_lines))]

use std::ffi::{c_char, c_int, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

use pcsim_core::session::{Coupling, RealtimeSession, Refusal, SessionState};

/// Success.
pub const PCSIM_OK: c_int = 0;
/// A bad argument (NULL pointer, a value out of range, a buffer too small).
pub const PCSIM_ERR_ARGUMENT: c_int = 1;
/// The case could not be read or is invalid.
pub const PCSIM_ERR_CASE: c_int = 2;
/// The step's input was refused (not finite, the force beyond the case's bound, outside the
/// model or the window, too fast); the catenary is unchanged.
pub const PCSIM_ERR_INPUT: c_int = 3;
/// A saved state from another case, window or version, or damaged.
pub const PCSIM_ERR_STATE: c_int = 4;
/// An internal error (a panic was caught); the handle is unusable, free it.
pub const PCSIM_ERR_INTERNAL: c_int = 5;
/// The step gave a non-finite or implausible state and was rolled back; the catenary is
/// unchanged.
pub const PCSIM_ERR_ROLLED_BACK: c_int = 6;

/// The opaque handle.
pub struct PcsimRt {
    rt: RealtimeSession,
    /// A state buffer for saves and restores (allocated once).
    state: SessionState,
    /// Why the last step was not taken (`None` after a step that was).
    last_refusal: Option<Refusal>,
    failed: bool,
}

/// Write `msg` into the caller's buffer (truncated, always NUL-terminated when `len > 0`).
///
/// # Safety
/// `buf` is NULL or points to at least `len` writable bytes.
unsafe fn put_message(buf: *mut c_char, len: usize, msg: &str) {
    if buf.is_null() || len == 0 {
        return;
    }
    let bytes = msg.as_bytes();
    let n = bytes.len().min(len - 1);
    // SAFETY: `buf` is non-NULL and holds `len` bytes (the caller's contract); `n < len`, so
    // both the copy and the terminating NUL stay inside it, and a Rust string never overlaps a
    // caller's buffer.
    unsafe {
        std::ptr::copy_nonoverlapping(bytes.as_ptr() as *const c_char, buf, n);
        *buf.add(n) = 0;
    }
}

/// The library's version, a static NUL-terminated string.
#[no_mangle]
pub extern "C" fn pcsim_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr() as *const c_char
}

/// Build the real-time catenary (hardware in the loop: force and position are inputs) of a case
/// and a window length (m). `case_name` is a preset name (`is_file` = 0) or the path of a case file
/// (`is_file` ≠ 0). On error returns NULL and writes the message into `err` (`err_len` bytes).
///
/// # Safety
/// `case_name` is NULL or a NUL-terminated string; `err` is NULL or holds `err_len` writable
/// bytes.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_new(
    case_name: *const c_char,
    is_file: c_int,
    window_m: f64,
    err: *mut c_char,
    err_len: usize,
) -> *mut PcsimRt {
    let r = catch_unwind(|| -> Result<*mut PcsimRt, String> {
        // SAFETY: NULL or NUL-terminated (the caller's contract).
        let name = unsafe { caller_str(case_name, "case_name") }?;
        let case = if is_file != 0 {
            // The core's bounded read: `/dev/zero` is refused at the limit, not read forever.
            let read = std::fs::File::open(&name).and_then(|f| {
                pcsim_core::input::read_text_limited(f, pcsim_core::input::MAX_INPUT_BYTES)
            });
            pcsim_core::input::case_from_file(&name, read)
        } else {
            pcsim_core::input::case_from_preset(&name)
        }
        .map_err(|e| e.to_string())?;
        let rt = RealtimeSession::new(&case, window_m, Coupling::Hil).map_err(|e| e.to_string())?;
        let state = rt.state([0.0; 4]);
        Ok(Box::into_raw(Box::new(PcsimRt {
            rt,
            state,
            last_refusal: None,
            failed: false,
        })))
    });
    let msg = match r {
        Ok(Ok(p)) => return p,
        Ok(Err(m)) => m,
        Err(_) => "internal error (panic caught)".to_string(),
    };
    // SAFETY: `err` holds `err_len` bytes or is NULL (the caller's contract).
    unsafe { put_message(err, err_len, &msg) };
    std::ptr::null_mut()
}

/// A string from the caller, copied (NULL is an error naming `what`).
///
/// # Safety
/// `p` is NULL or a NUL-terminated string valid for the call.
unsafe fn caller_str(p: *const c_char, what: &str) -> Result<String, String> {
    if p.is_null() {
        return Err(format!("{what}: NULL pointer"));
    }
    // SAFETY: non-NULL (checked) and NUL-terminated (this function's contract); only copied.
    Ok(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

/// Run `f` on a usable handle under `catch_unwind`.
///
/// # Safety
/// `h` is NULL or a handle from `pcsim_rt_new` not yet freed, used by no other thread meanwhile.
unsafe fn with(h: *mut PcsimRt, f: impl FnOnce(&mut PcsimRt) -> c_int) -> c_int {
    if h.is_null() {
        return PCSIM_ERR_ARGUMENT;
    }
    // SAFETY: a live handle with no other user (the caller's contract).
    let h = unsafe { &mut *h };
    if h.failed {
        return PCSIM_ERR_INTERNAL;
    }
    match catch_unwind(AssertUnwindSafe(|| f(h))) {
        Ok(s) => s,
        Err(_) => {
            h.failed = true;
            PCSIM_ERR_INTERNAL
        }
    }
}

/// A read-only view of a handle (NULL gives `None`).
///
/// # Safety
/// `h` is NULL or a live handle from `pcsim_rt_new` that no thread changes meanwhile.
unsafe fn view<'a>(h: *const PcsimRt) -> Option<&'a PcsimRt> {
    // SAFETY: NULL or live and unchanged while borrowed (the caller's contract).
    unsafe { h.as_ref() }
}

/// Write `v` through `p` unless it is NULL.
///
/// # Safety
/// `p` is NULL or points to a writable `f64`.
unsafe fn put(p: *mut f64, v: f64) {
    // SAFETY: NULL or writable (the caller's contract).
    if let Some(r) = unsafe { p.as_mut() } {
        *r = v;
    }
}

/// One fixed step with the contact force (N, pushing the wire up) and the pantograph's track
/// position (m), under the core session's contract. Writes the contact-wire height (m),
/// vertical velocity (m/s) and the contact point's lateral position (m, 0 for a vertical-only
/// case) at the contact point; any output pointer may be NULL. Allocates nothing. A refused
/// input gives `PCSIM_ERR_INPUT`, a rolled-back step `PCSIM_ERR_ROLLED_BACK`; both leave the
/// catenary unchanged, and `pcsim_rt_last_refusal` gives the reason.
///
/// # Safety
/// `rt` is NULL or a live handle used by no other thread meanwhile; each output pointer is NULL
/// or points to a writable `double`.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_step(
    rt: *mut PcsimRt,
    force_n: f64,
    track_position_m: f64,
    height_m: *mut f64,
    velocity_m_s: *mut f64,
    lateral_m: *mut f64,
) -> c_int {
    // SAFETY: the handle's contract is the caller's, passed on.
    unsafe {
        with(rt, |h| match h.rt.step(force_n, track_position_m) {
            Ok(o) => {
                h.last_refusal = None;
                // Each pointer is NULL or writable (the caller's contract; inside the unsafe
                // block above).
                put(height_m, o.wire_height_m);
                put(velocity_m_s, o.wire_velocity_m_s);
                put(lateral_m, o.lateral_m);
                PCSIM_OK
            }
            Err(e) => {
                h.last_refusal = Some(e);
                status_of(&e)
            }
        })
    }
}

fn status_of(e: &Refusal) -> c_int {
    match e {
        Refusal::Input(_) => PCSIM_ERR_INPUT,
        Refusal::RolledBack { .. } => PCSIM_ERR_ROLLED_BACK,
    }
}

/// Why the last `pcsim_rt_step` was not taken: its status (`PCSIM_ERR_INPUT` or
/// `PCSIM_ERR_ROLLED_BACK`) with the reason in `msg` (it starts with the reason's code, e.g.
/// `input refused (force_out_of_bound): …`), or `PCSIM_OK` when it was taken.
///
/// # Safety
/// `rt` is NULL or a live handle; `msg` is NULL or holds `msg_len` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_last_refusal(
    rt: *const PcsimRt,
    msg: *mut c_char,
    msg_len: usize,
) -> c_int {
    // SAFETY: the handle's contract is the caller's, passed on.
    let Some(h) = (unsafe { view(rt) }) else {
        return PCSIM_ERR_ARGUMENT;
    };
    match &h.last_refusal {
        None => PCSIM_OK,
        Some(e) => {
            // SAFETY: `msg` holds `msg_len` bytes or is NULL (the caller's contract).
            unsafe { put_message(msg, msg_len, &e.to_string()) };
            status_of(e)
        }
    }
}

/// Check an input without stepping: `PCSIM_OK`, or `PCSIM_ERR_INPUT` with the reason in `err`.
///
/// # Safety
/// `h` is NULL or a live handle used by no other thread meanwhile; `err` is NULL or holds
/// `err_len` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_check_input(
    h: *mut PcsimRt,
    force_n: f64,
    track_position_m: f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: the handle's contract is the caller's, passed on.
    unsafe {
        with(h, |h| {
            match h.rt.check_input(force_n, track_position_m, h.rt.dt_s()) {
                Ok(()) => PCSIM_OK,
                Err(e) => {
                    // SAFETY: `err` holds `err_len` bytes or is NULL (the caller's contract).
                    put_message(err, err_len, &Refusal::Input(e).to_string());
                    PCSIM_ERR_INPUT
                }
            }
        })
    }
}

/// The fixed time step, s (NaN for a NULL handle).
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_dt(h: *const PcsimRt) -> f64 {
    // SAFETY: the handle's contract is the caller's, passed on.
    unsafe { view(h) }.map_or(f64::NAN, |h| h.rt.dt_s())
}

/// The track position the window was built around (the case's start), m.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_start_position(h: *const PcsimRt) -> f64 {
    // SAFETY: the handle's contract is the caller's, passed on.
    unsafe { view(h) }.map_or(f64::NAN, |h| h.rt.start_position_m())
}

/// The size in bytes of a saved state of this catenary (0 for a NULL handle).
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_state_size(h: *const PcsimRt) -> usize {
    // SAFETY: the handle's contract is the caller's, passed on.
    unsafe { view(h) }.map_or(0, |h| h.rt.state_size())
}

/// Save the state into `buf` (`len` ≥ `pcsim_rt_state_size`) in the core's one state format:
/// the window's place, every modal coordinate, the last input and output, a checksum; restoring
/// it continues bit for bit. `*written` (when not NULL) receives the state's length in bytes: on
/// a line of several tension lengths the windows differ in size, so a state may be shorter than
/// `pcsim_rt_state_size` (restore takes either length).
///
/// # Safety
/// `h` is NULL or a live handle used by no other thread meanwhile; `buf` is NULL or holds `len`
/// writable bytes; `written` is NULL or points to a writable `size_t`.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_save(
    h: *mut PcsimRt,
    buf: *mut u8,
    len: usize,
    written: *mut usize,
) -> c_int {
    // SAFETY: the handle's contract is the caller's, passed on.
    unsafe {
        with(h, |h| {
            if buf.is_null() {
                return PCSIM_ERR_ARGUMENT;
            }
            h.rt.save_into(&mut h.state, [0.0; 4]);
            // Sized by the state, never by the caller's `len` (a huge `len` must not allocate).
            let b = RealtimeSession::state_bytes(&h.state);
            if b.len() > len {
                return PCSIM_ERR_ARGUMENT;
            }
            // SAFETY: `buf` holds `len ≥ b.len()` writable bytes (the caller's contract) and
            // cannot overlap the fresh vector.
            std::ptr::copy_nonoverlapping(b.as_ptr(), buf, b.len());
            if !written.is_null() {
                // SAFETY: `written` points to a writable `size_t` (the caller's contract).
                *written = b.len();
            }
            PCSIM_OK
        })
    }
}

/// Restore a state saved by `pcsim_rt_save` of the same case, window and version (else
/// `PCSIM_ERR_STATE` with the reason in `err`: another configuration or format version,
/// truncated, or damaged by even one byte; the catenary is unchanged). `len` is the length
/// `pcsim_rt_save` wrote, or any length up to `pcsim_rt_state_size` (the buffer it was saved
/// into): the state's own header says how much of it is the state.
///
/// # Safety
/// `h` is NULL or a live handle used by no other thread meanwhile; `buf` is NULL or holds `len`
/// readable bytes; `err` is NULL or holds `err_len` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_restore(
    h: *mut PcsimRt,
    buf: *const u8,
    len: usize,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: the handle's contract is the caller's, passed on.
    unsafe {
        with(h, |h| {
            if buf.is_null() {
                put_message(err, err_len, "NULL buffer");
                return PCSIM_ERR_ARGUMENT;
            }
            // SAFETY: `buf` holds `len` readable bytes (the caller's contract), read only here.
            let bytes = std::slice::from_raw_parts(buf, len);
            match h.rt.state_from_bytes(bytes).and_then(|s| h.rt.restore(&s)) {
                Ok(()) => PCSIM_OK,
                Err(m) => {
                    // SAFETY: `err` holds `err_len` bytes or is NULL (the caller's contract).
                    put_message(err, err_len, &m);
                    PCSIM_ERR_STATE
                }
            }
        })
    }
}

/// Free the catenary (NULL is a no-op).
///
/// # Safety
/// `h` is NULL or a handle from `pcsim_rt_new` not yet freed; it is not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_free(h: *mut PcsimRt) {
    if h.is_null() {
        return;
    }
    // SAFETY: a handle from `Box::into_raw` in `pcsim_rt_new`, freed once (the caller's
    // contract).
    let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(h) })));
}
