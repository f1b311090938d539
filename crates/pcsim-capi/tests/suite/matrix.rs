//! Issue 51: the C API's table of docs/matrix.md. Every geometry family of the core's zoo
//! (`pcsim_core::zoo::geometries`), written as a case file and opened through `pcsim_rt_new`,
//! then stepped through `pcsim_rt_step` for a second of its run (a constant 100 N at the case's
//! speed): each cell runs (every step accepted, finite heights) or is refused by name (the
//! message names the field). Nothing is injected. `PCSIM_BLESS=1` rewrites the block; the test
//! fails while it differs.

use pcsim_capi::*;
use pcsim_core::zoo::geometries::{
    geometries, matrix_block, refused_field, render_front_end, with_matrix_block,
};
use std::ffi::{CStr, CString};

/// The window of the real-time cells, m (as the core's matrix).
const WINDOW_M: f64 = 180.0;

fn cell(dir: &std::path::Path, g: &str, case: &pcsim_core::Case) -> Result<(), String> {
    let path = dir.join(format!("{}.toml", g.replace([',', ' '], "_")));
    std::fs::write(&path, case.to_toml_string()).unwrap();
    let name = CString::new(path.display().to_string()).unwrap();
    let mut err = [0 as std::ffi::c_char; 1024];
    let h = unsafe { pcsim_rt_new(name.as_ptr(), 1, WINDOW_M, err.as_mut_ptr(), err.len()) };
    if h.is_null() {
        let msg = unsafe { CStr::from_ptr(err.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        return Err(refused_field(&msg)
            .unwrap_or_else(|| panic!("{g}: neither a handle nor a refusal by name: {msg}")));
    }
    let (dt, x0) = unsafe { (pcsim_rt_dt(h), pcsim_rt_start_position(h)) };
    let v = case.run.speed_kmh / 3.6;
    for k in 1..=(1.0 / dt) as usize {
        let (mut y, mut w) = (f64::NAN, f64::NAN);
        let s = unsafe {
            pcsim_rt_step(
                h,
                100.0,
                x0 + v * k as f64 * dt,
                &mut y,
                &mut w,
                std::ptr::null_mut(),
            )
        };
        assert!(
            s == PCSIM_OK && y.is_finite() && w.is_finite(),
            "{g}: step {k}: {s}"
        );
    }
    unsafe { pcsim_rt_free(h) };
    Ok(())
}

#[test]
fn issue_51_every_geometry_through_the_c_api_runs_or_is_refused_by_name() {
    let dir = std::env::temp_dir().join(format!("pcsim-capi-matrix-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rows: Vec<(&str, Vec<Result<(), String>>)> = geometries()
        .iter()
        .map(|(g, case)| (*g, vec![cell(&dir, g, case)]))
        .collect();
    let _ = std::fs::remove_dir_all(&dir);
    // The real-time window refuses a crosswind by name, and only that.
    for (g, cells) in &rows {
        match &cells[0] {
            Err(f) => assert!(g.contains("crosswind") && f == "wind", "{g}: {f}"),
            Ok(()) => assert!(!g.contains("crosswind"), "{g}"),
        }
    }
    let text = render_front_end(
        "C API (`pcsim_rt_new` on the case file, `pcsim_rt_step`)",
        &["real-time window (HIL)"],
        &rows,
    );
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/matrix.md");
    let doc = std::fs::read_to_string(path).unwrap_or_default();
    if std::env::var_os("PCSIM_BLESS").is_some() {
        std::fs::write(path, with_matrix_block(&doc, "capi", &text)).unwrap();
    }
    let doc = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        matrix_block(&doc, "capi") == Some(text.as_str()),
        "docs/matrix.md's C API table differs (PCSIM_BLESS=1 rewrites it):\n{text}"
    );
}
