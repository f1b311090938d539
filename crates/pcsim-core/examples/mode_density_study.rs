//! Issue 20, item 8: the lateral mode density study. The contact wire's static mid-span blow-off
//! under the steady crosswind of `stitched-2018-like-3d-crosswind` (turbulence off, 12 spans),
//! against the modes per metre of every wire's series (vertical, lateral and torsional share
//! them), with Δt scaled so that the coupled stability check accepts it. Prints a Markdown table
//! (docs/validation.md holds its output).
//!
//! cargo run --release -p pcsim-core --example mode_density_study

use pcsim_core::compile::{Setup, Stepper};
use pcsim_core::model::{Direction, WireRole};
use pcsim_core::presets;

fn main() {
    let (mut base, _) = presets::load("stitched-2018-like-3d-crosswind").unwrap();
    base.wind.as_mut().unwrap().turbulence_intensity = 0.0;
    base.catenary.spans = 12;
    base.pantographs.truncate(1);
    base.run.start_m = 100.0;
    base.run.end_m = 600.0;
    base.run.analysis_m = [200.0, 600.0];
    let span = base.catenary.span_m;
    println!("| modes per metre | modes per wire | mid-span blow-off (mm), spans 5–8 | against 6 per metre |");
    println!("|---|---|---|---|");
    let mut rows = Vec::new();
    for mpm in [0.667, 1.0, 1.25, 1.5, 2.0, 3.0, 4.0, 6.0] {
        let mut c = base.clone();
        c.run.modes = None;
        c.run.modes_per_m = Some(mpm);
        c.run.dt_s = 1e-3 * (0.6 / mpm).min(1.0);
        let setup = Setup::from_case(&c).unwrap();
        let s = Stepper::new(&setup).unwrap();
        let m = &setup.model;
        let b = m.block(WireRole::Contact, Direction::Lateral).unwrap();
        let q = s.state.q(m, b);
        let basis = m.layout.basis(b);
        let mut row = vec![0.0; q.len()];
        let mids: Vec<f64> = (5..9)
            .map(|k| basis.eval(q, (k as f64 + 0.5) * span, &mut row))
            .collect();
        let mean = mids.iter().sum::<f64>() / mids.len() as f64;
        rows.push((mpm, c.n_modes(), mean));
    }
    let reference = rows.last().unwrap().2;
    for (mpm, n, v) in rows {
        println!(
            "| {mpm} | {n} | {:.2} | {:+.2} % |",
            v * 1e3,
            100.0 * (v - reference) / reference
        );
    }
}
