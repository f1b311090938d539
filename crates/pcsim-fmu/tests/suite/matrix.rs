//! Issue 51: the FMU's table of docs/matrix.md. Every geometry family of the core's zoo
//! (`pcsim_core::zoo::geometries`), written as a case file and given as the FMU's `case`
//! parameter, through the FMU's instance rules (the FMI 2.0 and 3.0 entry points only translate
//! to them; FMPy runs the built FMUs in `.ci/run`): initialised with a 180 m window, stepped for a
//! second with a constant 100 N at the case's speed. Each cell runs (every step `Ok`, the wire's
//! height finite) or is refused by name (the message names the field). Nothing is injected.
//! `PCSIM_BLESS=1` rewrites the block; the test fails while it differs.

use pcsim_core::zoo::geometries::{
    geometries, matrix_block, refused_field, render_front_end, with_matrix_block,
};
use pcsim_fmu::instance::{Instance, Status};
use pcsim_fmu::vars;

fn cell(dir: &std::path::Path, g: &str, case: &pcsim_core::Case) -> Result<(), String> {
    let path = dir.join(format!("{}.toml", g.replace([',', ' '], "_")));
    std::fs::write(&path, case.to_toml_string()).unwrap();
    let mut i = Instance::new(g);
    let ok = |r: Result<(), (Status, String)>| r.unwrap_or_else(|e| panic!("{g}: {}", e.1));
    ok(i.set_string(vars::VR_CASE, &path.display().to_string()));
    ok(i.set_real(vars::VR_WINDOW_LENGTH, 180.0));
    ok(i.setup_experiment(0.0));
    ok(i.enter_initialization());
    ok(i.set_real(vars::VR_CONTACT_FORCE, 100.0));
    if let Err((_, msg)) = i.exit_initialization() {
        return Err(refused_field(&msg)
            .unwrap_or_else(|| panic!("{g}: neither a model nor a refusal by name: {msg}")));
    }
    let (h, v) = (0.01, case.run.speed_kmh / 3.6);
    for k in 0..100 {
        let t = k as f64 * h;
        ok(i.set_real(vars::VR_PANTOGRAPH_POSITION, v * (t + h)));
        let s = i
            .do_step(t, h)
            .unwrap_or_else(|e| panic!("{g}: step {k}: {}", e.1));
        assert!(s == Status::Ok, "{g}: step {k}: {s:?}");
        let y = i.get_real(vars::VR_WIRE_HEIGHT).unwrap();
        assert!(y.is_finite(), "{g}: step {k}");
    }
    Ok(())
}

#[test]
fn issue_51_every_geometry_through_the_fmu_runs_or_is_refused_by_name() {
    let dir = std::env::temp_dir().join(format!("pcsim-fmu-matrix-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rows: Vec<(&str, Vec<Result<(), String>>)> = geometries()
        .iter()
        .map(|(g, case)| (*g, vec![cell(&dir, g, case)]))
        .collect();
    let _ = std::fs::remove_dir_all(&dir);
    for (g, cells) in &rows {
        match &cells[0] {
            Err(f) => assert!(g.contains("crosswind") && f == "wind", "{g}: {f}"),
            Ok(()) => assert!(!g.contains("crosswind"), "{g}"),
        }
    }
    let text = render_front_end(
        "FMU (FMI 2.0 and 3.0: the `case` parameter a case file, initialised and stepped)",
        &["real-time window (HIL)"],
        &rows,
    );
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/matrix.md");
    let doc = std::fs::read_to_string(path).unwrap_or_default();
    if std::env::var_os("PCSIM_BLESS").is_some() {
        std::fs::write(path, with_matrix_block(&doc, "fmu", &text)).unwrap();
    }
    let doc = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        matrix_block(&doc, "fmu") == Some(text.as_str()),
        "docs/matrix.md's FMU table differs (PCSIM_BLESS=1 rewrites it):\n{text}"
    );
}
