//! The zoo of small models against their golden time histories (`data/golden/zoo/`, written by
//! `cargo run --release -p pcsim-core --example zoo_golden -- data/golden/zoo` before the core
//! restructure), and snapshots of each model's run statistics.
//!
//! The restructure (issue 9) reproduced the goldens bit for bit. The speed work (issue 11)
//! changed the arithmetic on purpose (one FFT per group of points instead of one sum per point,
//! fused multiply-adds on x86-64-v3), so the comparison allows [`TOL`] of each column's scale:
//! rounding, not method (a 1e-6 change of a load already fails, see the last test).

use pcsim_core::zoo;

fn golden(name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let path = format!(
        "{}/../../data/golden/zoo/{name}.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut lines = text.lines();
    let cols = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
        .collect();
    (cols, rows)
}

/// Allowed deviation from the goldens, relative to each column's largest magnitude.
const TOL: f64 = 1e-9;

/// Every recorded value within [`TOL`] of the golden one, relative to the largest magnitude in
/// its column (the time histories pass through zero).
fn check(name: &str) {
    let (cols, rows) = golden(name);
    let t = zoo::trace(name).unwrap();
    assert_eq!(t.columns, cols, "{name}: columns");
    assert_eq!(t.rows.len(), rows.len(), "{name}: rows");
    let mut worst: f64 = 0.0;
    for c in 0..cols.len() {
        let scale = rows.iter().map(|r| r[c].abs()).fold(1e-300, f64::max);
        for (k, (a, b)) in t.rows.iter().zip(&rows).enumerate() {
            worst = worst.max((a[c] - b[c]).abs() / scale);
            assert!(
                (a[c] - b[c]).abs() <= TOL * scale,
                "{name}: {} at row {k}: {} vs golden {} (scale {scale})",
                cols[c],
                a[c],
                b[c]
            );
        }
    }
    eprintln!("{name}: largest deviation {worst:.1e} of the column scale");
}

#[test]
fn taut_string_matches_its_golden_history() {
    check("taut_string");
}

#[test]
fn tensioned_beam_matches_its_golden_history() {
    check("tensioned_beam");
}

#[test]
fn one_span_matches_its_golden_history() {
    check("one_span");
}

#[test]
fn stitched_three_spans_matches_its_golden_history() {
    check("stitched_three_spans");
}

#[test]
fn two_pantographs_matches_its_golden_history() {
    check("two_pantographs");
}

/// Every zoo entry names its reference, and the golden it names exists.
#[test]
fn every_zoo_model_carries_its_reference() {
    for name in zoo::NAMES {
        let r = zoo::reference(name).unwrap_or_else(|| panic!("{name}: no reference"));
        let path = r
            .strip_prefix("golden ")
            .and_then(|s| s.split(';').next())
            .unwrap_or_else(|| panic!("{name}: `{r}` names no golden"));
        let full = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join(path);
        assert!(full.exists(), "{name}: {}", full.display());
    }
    assert!(zoo::reference("no-such").is_none());
}

#[test]
fn the_goldens_can_tell_a_wrong_answer() {
    // The same string with the moving force 1e-6 larger must fail the comparison.
    let mut m = zoo::model("taut_string").unwrap();
    match &mut m.model.pantographs[0].kind {
        pcsim_core::model::PantographKind::MovingForce { force_n, .. } => *force_n *= 1.0 + 1e-6,
        _ => unreachable!(),
    }
    let (_, rows) = golden("taut_string");
    let t = zoo::trace_of(&m);
    let c = 3; // load_height_m
    let scale = rows.iter().map(|r| r[c].abs()).fold(0.0, f64::max);
    let worst = t
        .rows
        .iter()
        .zip(&rows)
        .map(|(a, b)| (a[c] - b[c]).abs())
        .fold(0.0, f64::max);
    assert!(worst > TOL * scale, "{worst} vs scale {scale}");
}

#[test]
fn run_statistics_of_the_zoo() {
    for name in zoo::NAMES {
        let out = pcsim_core::simulate(&zoo::model(name).unwrap(), &mut |_| true).unwrap();
        insta::assert_debug_snapshot!(*name, out.run_statistics);
    }
}

#[test]
fn a_step_is_its_named_stages_in_order() {
    // `Integrator::step_stage` (the per-stage benches' entry) is the step's own stages: run in
    // `Stage::ALL`'s order they give the step's state bit for bit, on every zoo model.
    use pcsim_core::solve::Stage;
    for name in zoo::NAMES {
        let setup = zoo::model(name).unwrap();
        let integ = setup.integrator().unwrap();
        let (mut a, mut wa) = (integ.initial_state(setup.plan.start_m), integ.workspace());
        let (mut b, mut wb) = (a.clone(), integ.workspace());
        for _ in 0..50 {
            integ.step(&mut a, &mut wa);
            for s in Stage::ALL {
                integ.step_stage(s, &mut b, &mut wb);
            }
        }
        assert_eq!(a, b, "{name}");
    }
}
