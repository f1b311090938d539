//! The C API under load: thousands of instantiations without memory growth, independent
//! handles in threads, save and restore bit for bit, refused inputs and states.

use pcsim_capi::*;
use std::ffi::CString;

fn new(window: f64) -> *mut PcsimRt {
    let name = CString::new("syt-7.0-9.8").unwrap();
    let mut err = [0i8; 256];
    let h = unsafe { pcsim_rt_new(name.as_ptr(), 0, window, err.as_mut_ptr(), err.len()) };
    assert!(!h.is_null());
    h
}

/// Step `n` times with a varying force from step `k0`; the last height and velocity.
fn run(h: *mut PcsimRt, k0: usize, n: usize) -> (f64, f64) {
    run_phase(h, k0, n, 0.0)
}

fn run_phase(h: *mut PcsimRt, k0: usize, n: usize, phase: f64) -> (f64, f64) {
    let (dt, x0) = unsafe { (pcsim_rt_dt(h), pcsim_rt_start_position(h)) };
    let (mut y, mut v) = (0.0, 0.0);
    for k in k0..k0 + n {
        let t = (k + 1) as f64 * dt;
        let f = 90.0 + 15.0 * (7.3 * t + phase).sin();
        let s = unsafe {
            pcsim_rt_step(
                h,
                f,
                x0 + 222.0 / 3.6 * t,
                &mut y,
                &mut v,
                std::ptr::null_mut(),
            )
        };
        assert_eq!(s, PCSIM_OK);
    }
    (y, v)
}

fn rss_kib() -> usize {
    let s = std::fs::read_to_string("/proc/self/statm").unwrap();
    let pages: usize = s.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4
}

#[test]
fn ten_thousand_instantiations_do_not_grow_the_memory() {
    let cycle = || {
        let h = new(120.0);
        run(h, 0, 5);
        unsafe { pcsim_rt_free(h) };
    };
    for _ in 0..1000 {
        cycle();
    }
    let after_1k = rss_kib();
    for _ in 0..9000 {
        cycle();
    }
    let after_10k = rss_kib();
    // The allocator keeps some pages; a leak of one handle per cycle would be ~9000 × 100 kB.
    assert!(
        after_10k < after_1k + 8 * 1024,
        "RSS grew from {after_1k} kB to {after_10k} kB over 9000 cycles"
    );
}

#[test]
fn four_handles_in_four_threads_match_serial_runs() {
    let serial: Vec<(f64, f64)> = (0..4)
        .map(|i| {
            let h = new(215.0);
            let r = run_phase(h, 0, 3000, i as f64);
            unsafe { pcsim_rt_free(h) };
            r
        })
        .collect();
    let threaded: Vec<(f64, f64)> = std::thread::scope(|s| {
        let hs: Vec<_> = (0..4)
            .map(|i| {
                s.spawn(move || {
                    let h = new(215.0);
                    let r = run_phase(h, 0, 3000, i as f64);
                    unsafe { pcsim_rt_free(h) };
                    r
                })
            })
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (a, b) in serial.iter().zip(&threaded) {
        assert_eq!(a.0.to_bits(), b.0.to_bits());
        assert_eq!(a.1.to_bits(), b.1.to_bits());
    }
}

#[test]
fn save_and_restore_continue_bit_for_bit_and_foreign_states_are_refused() {
    let h = new(215.0);
    run(h, 0, 1000);
    let n = unsafe { pcsim_rt_state_size(h) };
    let mut buf = vec![0u8; n];
    assert_eq!(
        unsafe { pcsim_rt_save(h, buf.as_mut_ptr(), n, std::ptr::null_mut()) },
        PCSIM_OK
    );
    let a = run(h, 1000, 1000);
    let mut err = [0i8; 256];
    assert_eq!(
        unsafe { pcsim_rt_restore(h, buf.as_ptr(), n, err.as_mut_ptr(), err.len()) },
        PCSIM_OK
    );
    let b = run(h, 1000, 1000);
    assert_eq!(a.0.to_bits(), b.0.to_bits());
    // Into a fresh handle: the same again.
    let h2 = new(215.0);
    assert_eq!(
        unsafe { pcsim_rt_restore(h2, buf.as_ptr(), n, err.as_mut_ptr(), err.len()) },
        PCSIM_OK
    );
    let c = run(h2, 1000, 1000);
    assert_eq!(a.0.to_bits(), c.0.to_bits());
    // Another window's state, a damaged one, a short buffer: refused, the catenary unchanged.
    let h3 = new(240.0);
    let s = unsafe { pcsim_rt_restore(h3, buf.as_ptr(), n, err.as_mut_ptr(), err.len()) };
    assert_eq!(s, PCSIM_ERR_STATE);
    let msg = unsafe { std::ffi::CStr::from_ptr(err.as_ptr()) }
        .to_string_lossy()
        .into_owned();
    assert!(msg.contains("another configuration"), "{msg}");
    assert_eq!(
        unsafe { pcsim_rt_restore(h2, buf.as_ptr(), n - 3, err.as_mut_ptr(), err.len()) },
        PCSIM_ERR_STATE
    );
    let mut small = vec![0u8; n - 1];
    assert_eq!(
        unsafe { pcsim_rt_save(h, small.as_mut_ptr(), n - 1, std::ptr::null_mut()) },
        PCSIM_ERR_ARGUMENT
    );
    // A caller's length far beyond the state's size is not an allocation request.
    assert_eq!(
        unsafe { pcsim_rt_save(h, buf.as_mut_ptr(), usize::MAX / 2, std::ptr::null_mut()) },
        PCSIM_OK
    );
    // A refused input leaves the catenary as it was: the saved bytes are the same.
    let (mut y, mut v) = (0.0, 0.0);
    let mut before = vec![0u8; n];
    assert_eq!(
        unsafe { pcsim_rt_save(h, before.as_mut_ptr(), n, std::ptr::null_mut()) },
        PCSIM_OK
    );
    assert_eq!(
        unsafe { pcsim_rt_step(h, f64::NAN, 100.0, &mut y, &mut v, std::ptr::null_mut()) },
        PCSIM_ERR_INPUT
    );
    let mut after = vec![0u8; n];
    assert_eq!(
        unsafe { pcsim_rt_save(h, after.as_mut_ptr(), n, std::ptr::null_mut()) },
        PCSIM_OK
    );
    assert_eq!(before, after);
    let d = run(h, 2000, 1000);
    assert_ne!(d.0.to_bits(), 0);
    // NULL handles and bad names.
    assert_eq!(
        unsafe {
            pcsim_rt_step(
                std::ptr::null_mut(),
                1.0,
                1.0,
                &mut y,
                &mut v,
                std::ptr::null_mut(),
            )
        },
        PCSIM_ERR_ARGUMENT
    );
    let bad = CString::new("no-such").unwrap();
    let p = unsafe { pcsim_rt_new(bad.as_ptr(), 0, 215.0, err.as_mut_ptr(), err.len()) };
    assert!(p.is_null());
    let msg = unsafe { std::ffi::CStr::from_ptr(err.as_ptr()) }
        .to_string_lossy()
        .into_owned();
    assert!(msg.contains("no-such"), "{msg}");
    // One flipped byte anywhere is refused (the checksum), the catenary unchanged.
    for i in [0, 9, 20, n / 2, n - 9, n - 1] {
        let mut d = buf.clone();
        d[i] ^= 0x01;
        assert_eq!(
            unsafe { pcsim_rt_restore(h2, d.as_ptr(), n, err.as_mut_ptr(), err.len()) },
            PCSIM_ERR_STATE,
            "byte {i}"
        );
    }
    for x in [h, h2, h3] {
        unsafe { pcsim_rt_free(x) };
    }
    unsafe { pcsim_rt_free(std::ptr::null_mut()) };
}

/// Issue 18: a force of 1e300 N (or 1e6 N, or NaN) is refused with its reason, never stepped
/// into a wire 1e294 m up with `PCSIM_OK`; the next good input steps as before.
#[test]
fn an_absurd_force_is_refused_with_its_reason() {
    let h = new(215.0);
    run(h, 0, 500);
    let x0 = unsafe { pcsim_rt_start_position(h) };
    let x = x0 + 222.0 / 3.6 * 0.5;
    let (mut y, mut v) = (0.0, 0.0);
    let mut msg = [0i8; 256];
    for f in [1e300, 1e6, f64::NAN, -1e300] {
        assert_eq!(
            unsafe { pcsim_rt_step(h, f, x, &mut y, &mut v, std::ptr::null_mut()) },
            PCSIM_ERR_INPUT,
            "{f}"
        );
        assert_eq!(
            unsafe { pcsim_rt_last_refusal(h, msg.as_mut_ptr(), msg.len()) },
            PCSIM_ERR_INPUT
        );
        let m = unsafe { std::ffi::CStr::from_ptr(msg.as_ptr()) }.to_string_lossy();
        assert!(
            m.contains("force_out_of_bound") || m.contains("not_finite"),
            "{f}: {m}"
        );
    }
    assert_eq!(
        unsafe { pcsim_rt_step(h, 85.0, x, &mut y, &mut v, std::ptr::null_mut()) },
        PCSIM_OK
    );
    assert!(y.abs() < 0.5, "{y}");
    assert_eq!(
        unsafe { pcsim_rt_last_refusal(h, msg.as_mut_ptr(), msg.len()) },
        PCSIM_OK
    );
    unsafe { pcsim_rt_free(h) };
}

/// Issue 19, item 2: a case file is read within the core's bound — `/dev/zero` is refused at the
/// limit with an error that says so, in bounded time and memory (it reached 21.5 GB before).
#[test]
fn a_case_file_of_unbounded_size_is_refused_at_the_limit() {
    let name = CString::new("/dev/zero").unwrap();
    let mut err = [0i8; 512];
    let t0 = std::time::Instant::now();
    let h = unsafe { pcsim_rt_new(name.as_ptr(), 1, 215.0, err.as_mut_ptr(), err.len()) };
    assert!(h.is_null());
    let msg = unsafe { std::ffi::CStr::from_ptr(err.as_ptr()) }
        .to_string_lossy()
        .into_owned();
    assert!(msg.contains("/dev/zero") && msg.contains("limit"), "{msg}");
    assert!(t0.elapsed() < std::time::Duration::from_secs(30));
    assert!(rss_kib() < 2 * 1024 * 1024, "{} KiB resident", rss_kib());
}

/// Issue 39, item 4: the README's warm-start pattern on a line of several tension lengths. The
/// windows along a line differ in size, so `pcsim_rt_state_size` (the largest) is longer than a
/// saved state: `pcsim_rt_save` says how many bytes it wrote, and `pcsim_rt_restore` takes that
/// length or the buffer's whole `pcsim_rt_state_size`, right after the save and after the window
/// has moved on, and continues bit for bit.
#[test]
fn issue_39_4_the_readme_warm_start_pattern_restores_on_a_line() {
    let name = CString::new("en50318-2018-like-simple").unwrap();
    let mut err = [0i8; 256];
    let h = unsafe { pcsim_rt_new(name.as_ptr(), 0, 240.0, err.as_mut_ptr(), err.len()) };
    assert!(!h.is_null());
    let n = unsafe { pcsim_rt_state_size(h) };
    let mut warm = vec![0u8; n];
    let mut used = 0usize;
    run(h, 0, 200);
    assert_eq!(
        unsafe { pcsim_rt_save(h, warm.as_mut_ptr(), n, &mut used) },
        PCSIM_OK
    );
    // On this line the first window is shorter than the largest: the case that failed.
    assert!(used > 40 && used < n, "written {used} of {n}");
    // The state format's own length is the one written.
    assert_eq!(
        u64::from_le_bytes(warm[24..32].try_into().unwrap()) as usize + 40,
        used
    );
    let restore = |len: usize| {
        let mut e = [0i8; 256];
        unsafe { pcsim_rt_restore(h, warm.as_ptr(), len, e.as_mut_ptr(), e.len()) }
    };
    // Right after the save, with the buffer's whole length (the README's pattern) and with the
    // length written.
    assert_eq!(restore(n), PCSIM_OK);
    assert_eq!(restore(used), PCSIM_OK);
    // Far enough for the window to move (a 240 m window at 222 km/h: several moves).
    let a = run(h, 200, 8000);
    assert_eq!(restore(n), PCSIM_OK);
    let b = run(h, 200, 8000);
    assert_eq!(
        (a.0.to_bits(), a.1.to_bits()),
        (b.0.to_bits(), b.1.to_bits())
    );
    // A length beyond the session's largest state, or short of the state, is still refused.
    let mut long = warm.clone();
    long.resize(n + 1, 0);
    assert_eq!(
        unsafe { pcsim_rt_restore(h, long.as_ptr(), n + 1, err.as_mut_ptr(), err.len()) },
        PCSIM_ERR_STATE
    );
    assert_eq!(restore(used - 1), PCSIM_ERR_STATE);
    unsafe { pcsim_rt_free(h) };
}

/// Issue 41, item 4: the C API's window follows the pantograph the case file names
/// (`run.window_pantograph`): on the 2018 line with two pantographs 200 m apart, the trailing
/// pantograph's window starts 200 m behind the leading one's, and steps as the session of that
/// pantograph in the core (the same heights).
#[test]
fn issue_41_4_a_case_file_picks_the_trailing_pantograph() {
    let (mut case, _) = pcsim_core::presets::load("en50318-2018-like-simple").unwrap();
    let offset = case.pantographs[1].offset_m();
    let dir = std::env::temp_dir().join(format!("pcsim-capi-trailing-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let open = |case: &pcsim_core::Case, name: &str| {
        let p = dir.join(name);
        std::fs::write(&p, case.to_toml_string()).unwrap();
        let path = CString::new(p.to_str().unwrap()).unwrap();
        let mut err = [0i8; 256];
        let h = unsafe { pcsim_rt_new(path.as_ptr(), 1, 215.0, err.as_mut_ptr(), err.len()) };
        assert!(!h.is_null());
        h
    };
    let lead = open(&case, "lead.toml");
    case.run.window_pantograph = Some("trailing".into());
    let trail = open(&case, "trailing.toml");
    let (x_lead, x_trail) = unsafe {
        (
            pcsim_rt_start_position(lead),
            pcsim_rt_start_position(trail),
        )
    };
    assert_eq!(x_trail, x_lead - offset);
    let mut core =
        pcsim_core::session::RealtimeSession::new(&case, 215.0, pcsim_core::session::Coupling::Hil)
            .unwrap();
    let dt = unsafe { pcsim_rt_dt(trail) };
    for k in 0..2000 {
        let x = x_trail + (k + 1) as f64 * dt * case.speed_m_s();
        let (mut y, mut v) = (0.0, 0.0);
        let s = unsafe { pcsim_rt_step(trail, 150.0, x, &mut y, &mut v, std::ptr::null_mut()) };
        assert_eq!(s, PCSIM_OK);
        let o = core.step(150.0, x).unwrap();
        assert_eq!((y, v), (o.wire_height_m, o.wire_velocity_m_s), "step {k}");
    }
    unsafe {
        pcsim_rt_free(lead);
        pcsim_rt_free(trail);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 43: a case whose pantograph has two collector strips (`benchmark-55m-two-strips`, as
/// a file) through the C API: the rig's force acts once at its position, so every output is the
/// core session's on that case and `benchmark-55m`'s (the same catenary) bit for bit.
#[test]
fn issue_43_1_a_two_strip_case_runs_through_the_c_api() {
    let (two, _) = pcsim_core::presets::load("benchmark-55m-two-strips").unwrap();
    let (one, _) = pcsim_core::presets::load("benchmark-55m").unwrap();
    let dir = std::env::temp_dir().join(format!("pcsim-capi-strips-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("two.toml");
    std::fs::write(&p, two.to_toml_string()).unwrap();
    let path = CString::new(p.to_str().unwrap()).unwrap();
    let mut err = [0i8; 256];
    let h = unsafe { pcsim_rt_new(path.as_ptr(), 1, 240.0, err.as_mut_ptr(), err.len()) };
    assert!(!h.is_null());
    use pcsim_core::session::{Coupling, RealtimeSession};
    let mut core = RealtimeSession::new(&two, 240.0, Coupling::Hil).unwrap();
    let mut plain = RealtimeSession::new(&one, 240.0, Coupling::Hil).unwrap();
    let (x0, dt) = unsafe { (pcsim_rt_start_position(h), pcsim_rt_dt(h)) };
    for k in 0..2000 {
        let x = x0 + (k + 1) as f64 * dt * two.speed_m_s();
        let f = 110.0 + 20.0 * (0.01 * k as f64).sin();
        let (mut y, mut v) = (0.0, 0.0);
        let s = unsafe { pcsim_rt_step(h, f, x, &mut y, &mut v, std::ptr::null_mut()) };
        assert_eq!(s, PCSIM_OK);
        let o = core.step(f, x).unwrap();
        assert_eq!((y, v), (o.wire_height_m, o.wire_velocity_m_s), "step {k}");
        assert_eq!(plain.step(f, x).unwrap(), o, "step {k}");
    }
    unsafe { pcsim_rt_free(h) };
    let _ = std::fs::remove_dir_all(&dir);
}
