//! # pcsim-capi
//!
//! The C API of the real-time catenary for rig software written in C or C++
//! (`include/pcsim.h`): build it from a case file or a preset and a window length, step it with
//! the measured contact force and pantograph position, read the wire's height, velocity and
//! lateral position, save and restore its state, free it. A thin layer over
//! [`pcsim_core::solve::realtime::RealtimeCatenary`], standard library only (as the FMU, for the
//! same reasons: no panic may cross the boundary, every pointer is checked).
//!
//! - Errors come back as a status (`PCSIM_OK` = 0, else an error code) and, where a message
//!   buffer is given, a NUL-terminated message that names the field or input.
//! - `pcsim_rt_step` allocates nothing; a refused input leaves the catenary unchanged.
//! - Every entry point runs under `catch_unwind`: a panic gives `PCSIM_ERR_INTERNAL` and marks
//!   the handle unusable.
//!
//! `tests/header.rs` checks `include/pcsim.h` against the signatures below, so that the two
//! cannot drift apart.

#![allow(clippy::missing_safety_doc)]

use std::ffi::{c_char, c_int, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

use pcsim_core::input::case::Case;
use pcsim_core::presets;
use pcsim_core::solve::realtime::{Coupling, RealtimeCatenary, Snapshot};
use pcsim_core::solve::state::ByteReader;

/// Success.
pub const PCSIM_OK: c_int = 0;
/// A bad argument (NULL pointer, a value out of range, a buffer too small).
pub const PCSIM_ERR_ARGUMENT: c_int = 1;
/// The case could not be read or is invalid.
pub const PCSIM_ERR_CASE: c_int = 2;
/// The step's input was refused (not finite, outside the model, behind the window, too fast);
/// the catenary is unchanged.
pub const PCSIM_ERR_INPUT: c_int = 3;
/// A saved state from another case, window or version, or damaged.
pub const PCSIM_ERR_STATE: c_int = 4;
/// An internal error (a panic was caught); the handle is unusable, free it.
pub const PCSIM_ERR_INTERNAL: c_int = 5;

/// The opaque handle.
pub struct PcsimRt {
    rt: RealtimeCatenary,
    /// A snapshot buffer for saves and restores (allocated once).
    snap: Snapshot,
    fingerprint: u64,
    failed: bool,
}

const MAGIC: &[u8; 8] = b"PCSIMRT1";

fn fnv1a64(data: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// Write `msg` into the caller's buffer (truncated, always NUL-terminated when `len > 0`).
fn put_message(buf: *mut c_char, len: usize, msg: &str) {
    if buf.is_null() || len == 0 {
        return;
    }
    let bytes = msg.as_bytes();
    let n = bytes.len().min(len - 1);
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
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_new(
    case_name: *const c_char,
    is_file: c_int,
    window_m: f64,
    err: *mut c_char,
    err_len: usize,
) -> *mut PcsimRt {
    let r = catch_unwind(|| -> Result<*mut PcsimRt, String> {
        if case_name.is_null() {
            return Err("case_name: NULL pointer".into());
        }
        let name = unsafe { CStr::from_ptr(case_name) }
            .to_string_lossy()
            .into_owned();
        let (mut c, text): (Case, String) = if is_file != 0 {
            let text =
                std::fs::read_to_string(&name).map_err(|e| format!("case file {name}: {e}"))?;
            let c = Case::from_toml_str(&text)
                .map_err(|e| format!("case file {name}: {e}"))?
                .0;
            (c, text)
        } else {
            let p = presets::find(&name).map_err(|e| e.to_string())?;
            (
                Case::from_toml_str(p.toml).map_err(|e| e.to_string())?.0,
                p.toml.to_string(),
            )
        };
        c.pantographs.truncate(1);
        let rt = RealtimeCatenary::new(&c, window_m, Coupling::Hil).map_err(|e| e.to_string())?;
        let fingerprint =
            fnv1a64(format!("{}|{}|{:e}", env!("CARGO_PKG_VERSION"), text, window_m).as_bytes());
        let snap = rt.snapshot();
        Ok(Box::into_raw(Box::new(PcsimRt {
            rt,
            snap,
            fingerprint,
            failed: false,
        })))
    });
    match r {
        Ok(Ok(p)) => p,
        Ok(Err(m)) => {
            put_message(err, err_len, &m);
            std::ptr::null_mut()
        }
        Err(_) => {
            put_message(err, err_len, "internal error (panic caught)");
            std::ptr::null_mut()
        }
    }
}

/// Run `f` on a usable handle under `catch_unwind`.
fn with(h: *mut PcsimRt, f: impl FnOnce(&mut PcsimRt) -> c_int) -> c_int {
    if h.is_null() {
        return PCSIM_ERR_ARGUMENT;
    }
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

/// One fixed step with the contact force (N, pushing the wire up) and the pantograph's track
/// position (m). Writes the contact-wire height (m), vertical velocity (m/s) and the contact
/// point's lateral position (m, 0 for a vertical-only case) at the contact point; any output
/// pointer may be NULL. Allocates nothing. A refused input gives `PCSIM_ERR_INPUT` and leaves
/// the catenary unchanged.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_step(
    rt: *mut PcsimRt,
    force_n: f64,
    position_m: f64,
    height_m: *mut f64,
    velocity_m_s: *mut f64,
    lateral_m: *mut f64,
) -> c_int {
    with(rt, |h| {
        let dt = h.rt.dt_s();
        if h.rt.check_input(force_n, position_m, dt).is_err() {
            return PCSIM_ERR_INPUT;
        }
        h.rt.set_input(force_n, position_m);
        let o = h.rt.step();
        unsafe {
            if !height_m.is_null() {
                *height_m = o.wire_height_m;
            }
            if !velocity_m_s.is_null() {
                *velocity_m_s = o.wire_velocity_m_s;
            }
            if !lateral_m.is_null() {
                *lateral_m = o.lateral_m;
            }
        }
        PCSIM_OK
    })
}

/// The message of the last refused input of `pcsim_rt_step` is not kept (the step allocates
/// nothing); this checks an input and writes why it would be refused. `PCSIM_OK` if it is fine.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_check_input(
    h: *mut PcsimRt,
    force_n: f64,
    position_m: f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    with(h, |h| {
        match h.rt.check_input(force_n, position_m, h.rt.dt_s()) {
            Ok(()) => PCSIM_OK,
            Err(e) => {
                put_message(err, err_len, &e.to_string());
                PCSIM_ERR_INPUT
            }
        }
    })
}

/// The fixed time step, s (NaN for a NULL handle).
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_dt(h: *const PcsimRt) -> f64 {
    if h.is_null() {
        return f64::NAN;
    }
    unsafe { &*h }.rt.dt_s()
}

/// The track position the window was built around (the case's start), m.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_start_position(h: *const PcsimRt) -> f64 {
    if h.is_null() {
        return f64::NAN;
    }
    unsafe { &*h }.rt.start_position_m()
}

/// The size in bytes of a saved state of this catenary.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_state_size(h: *const PcsimRt) -> usize {
    if h.is_null() {
        return 0;
    }
    let h = unsafe { &*h };
    let mut b = Vec::new();
    h.snap.write_bytes(&mut b);
    MAGIC.len() + 8 + b.len()
}

/// Save the state into `buf` (`len` ≥ `pcsim_rt_state_size`): the window's place, every modal
/// coordinate, the last input; restoring it continues bit for bit.
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_save(h: *mut PcsimRt, buf: *mut u8, len: usize) -> c_int {
    with(h, |h| {
        if buf.is_null() {
            return PCSIM_ERR_ARGUMENT;
        }
        h.rt.save(&mut h.snap);
        // Sized by the state, never by the caller's `len` (a huge `len` must not allocate).
        let mut b = Vec::new();
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&h.fingerprint.to_le_bytes());
        h.snap.write_bytes(&mut b);
        if b.len() > len {
            return PCSIM_ERR_ARGUMENT;
        }
        unsafe { std::ptr::copy_nonoverlapping(b.as_ptr(), buf, b.len()) };
        PCSIM_OK
    })
}

/// Restore a state saved by `pcsim_rt_save` of the same case, window and version (else
/// `PCSIM_ERR_STATE` with the reason in `err`; the catenary is unchanged).
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_restore(
    h: *mut PcsimRt,
    buf: *const u8,
    len: usize,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    with(h, |h| {
        if buf.is_null() {
            put_message(err, err_len, "NULL buffer");
            return PCSIM_ERR_ARGUMENT;
        }
        let bytes = unsafe { std::slice::from_raw_parts(buf, len) };
        let mut r = ByteReader::new(bytes);
        let res = (|| -> Result<Snapshot, String> {
            if r.bytes(8)? != MAGIC {
                return Err("not a pcsim real-time state".into());
            }
            if r.u64()? != h.fingerprint {
                return Err("the state belongs to another case, window or pcsim version".into());
            }
            let s = h.rt.snapshot_from_bytes(&mut r)?;
            if !r.is_done() {
                return Err("trailing bytes".into());
            }
            Ok(s)
        })();
        match res {
            Ok(s) => {
                h.rt.restore(&s);
                PCSIM_OK
            }
            Err(m) => {
                put_message(err, err_len, &format!("state refused: {m}"));
                PCSIM_ERR_STATE
            }
        }
    })
}

/// Free the catenary (NULL is a no-op).
#[no_mangle]
pub unsafe extern "C" fn pcsim_rt_free(h: *mut PcsimRt) {
    if h.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(h) })));
}
