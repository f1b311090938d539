//! A zoo of small test models (after diffsol's `test_models`), shared by the tests, the benches
//! and the Python tests. Each is small enough to run in well under a second and exercises a
//! different part of the model:
//!
//! | name | what it is | what it exercises |
//! |---|---|---|
//! | `taut_string` | one wire, no bending stiffness, a constant moving force | the sine series, the modal damping, a moving point load |
//! | `tensioned_beam` | one wire with EI and a point mass on a spring | Eq. 12 with EI, the exact point mass (Woodbury) |
//! | `one_span` | one span of the simple catenary with its nine droppers, a lumped pantograph | droppers (Eq. 15), contact (Eq. 19), pantograph (Eq. 16), a window of a larger model |
//! | `stitched_three_spans` | three spans of the stitched catenary, one pantograph | stitch nodes, stitch droppers, support dampers, free steady arms |
//! | `two_pantographs` | six spans of the simple catenary, two pantographs 60 m apart | supports, steady arms, two contacts |
//!
//! Golden time histories of every zoo model are committed in `data/golden/zoo/`, written by
//! `cargo run --release -p pcsim-core --example zoo_golden -- data/golden/zoo`.

pub mod geometries;

use crate::compile::{Setup, Stepper};
use crate::input::case::{Damping, PantographCase};
use crate::input::presets;
use crate::model::ModelBuilder;
use crate::solve::Plan;

/// The names of the zoo models, in a fixed order.
pub const NAMES: &[&str] = &[
    "taut_string",
    "tensioned_beam",
    "one_span",
    "stitched_three_spans",
    "two_pantographs",
];

/// The reference each zoo model is checked against: its golden time history (made by
/// `examples/zoo_golden.rs` before the issue-9 restructure and compared by `tests/suite/zoo.rs`; the
/// exact solutions of `tests/suite/analytic.rs` are checked on models of their own).
pub fn reference(name: &str) -> Option<&'static str> {
    Some(match name {
        "taut_string" => "golden data/golden/zoo/taut_string.csv",
        "tensioned_beam" => "golden data/golden/zoo/tensioned_beam.csv",
        "one_span" => "golden data/golden/zoo/one_span.csv",
        "stitched_three_spans" => "golden data/golden/zoo/stitched_three_spans.csv",
        "two_pantographs" => "golden data/golden/zoo/two_pantographs.csv",
        _ => return None,
    })
}

/// Build a zoo model (with its plan and options) by name.
pub fn model(name: &str) -> Option<Setup> {
    Some(match name {
        "taut_string" => taut_string(),
        "tensioned_beam" => tensioned_beam(),
        "one_span" => one_span(),
        "stitched_three_spans" => stitched_three_spans(),
        "two_pantographs" => two_pantographs(),
        _ => return None,
    })
}

/// A 100 m string (20 kN, 1.35 kg/m, no EI), 100 modes, modal damping 1 %, crossed by a constant
/// 100 N force at 30 m/s from x = 10 m, for 1 s at Δt = 1 ms.
pub fn taut_string() -> Setup {
    Setup::from_builder(
        ModelBuilder::single_wire(100.0, 100, 1.35, 20_000.0, 0.0)
            .damping(&Damping::Modal { ratio: 0.01 })
            .moving_force("load", 100.0)
            .run(30.0, 10.0, 1.0, 1e-3)
            .build(),
    )
}

/// A 60 m tensioned beam (20 kN, EI 195 N·m², 1.35 kg/m), 120 modes, Rayleigh damping, a 1 kg
/// point mass on a 300 N/m spring at mid-length, crossed by a constant 150 N force at 40 m/s.
pub fn tensioned_beam() -> Setup {
    Setup::from_builder(
        ModelBuilder::single_wire(60.0, 120, 1.35, 20_000.0, 195.0)
            .damping(&Damping::Rayleigh {
                alpha: 0.05,
                beta: 1e-4,
            })
            .point_mass(30.0, 1.0, 300.0)
            .moving_force("load", 150.0)
            .run(40.0, 2.0, 1.0, 5e-4)
            .build(),
    )
}

/// The middle span of a three-span `en50318-2002` catenary (one mode per metre), as a window
/// model of its own: nine droppers, ends pinned at the supports, the two-mass pantograph at
/// 100 km/h from 5 m to 55 m of the span.
pub fn one_span() -> Setup {
    let (mut c, _) = presets::load("en50318-2002").expect("embedded preset");
    c.catenary.spans = 3;
    c.run.speed_kmh = 100.0;
    c.run.start_m = 65.0;
    c.run.end_m = 115.0;
    c.run.analysis_m = [65.0, 115.0];
    // A small model whose statistics include the start on purpose (its golden is the time
    // history).
    c.run.allow_start_transient = true;
    let full = Setup::from_case(&c).expect("zoo case is valid");
    let mut model = full.model.window(60.0, 60.0, 60, false);
    // A model of its own: its positions are its own coordinates (no track behind it).
    model.track_origin_m = 0.0;
    Setup {
        model,
        plan: Plan {
            start_m: full.plan.start_m - 60.0,
            duration_s: 50.0 / (100.0 / 3.6),
            analysis_m: [5.0, 55.0],
            ..full.plan
        },
        options: full.options,
        warnings: vec![],
    }
}

/// `stitched-2018-like` cut to three spans (one mode per metre), leading pantograph at 200 km/h.
pub fn stitched_three_spans() -> Setup {
    let (mut c, _) = presets::load("stitched-2018-like").expect("embedded preset");
    c.catenary.spans = 3;
    c.pantographs.truncate(1);
    c.run.speed_kmh = 200.0;
    c.run.modes = None;
    c.run.modes_per_m = Some(1.0);
    c.run.start_m = 20.0;
    c.run.end_m = 160.0;
    c.run.analysis_m = [60.0, 120.0];
    // A small model whose statistics include the start on purpose (its golden is the time
    // history).
    c.run.allow_start_transient = true;
    Setup::from_case(&c).expect("zoo case is valid")
}

/// `en50318-2002` over six spans with a second, identical pantograph 60 m behind, at 250 km/h.
pub fn two_pantographs() -> Setup {
    let (mut c, _) = presets::load("en50318-2002").expect("embedded preset");
    c.catenary.spans = 6;
    let mut trailing = c.pantographs[0].clone();
    if let PantographCase::Lumped { name, offset_m, .. } = &mut trailing {
        *name = "trailing".into();
        *offset_m = 60.0;
    }
    c.pantographs.push(trailing);
    c.run.speed_kmh = 250.0;
    c.run.start_m = 130.0;
    c.run.end_m = 290.0;
    c.run.analysis_m = [140.0, 280.0];
    // A small model whose statistics include the start on purpose (its golden is the time
    // history).
    c.run.allow_start_transient = true;
    Setup::from_case(&c).expect("zoo case is valid")
}

/// A recorded time history of a zoo model: the columns and one row every `every` steps.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    /// Column names with their units.
    pub columns: Vec<String>,
    /// One row per recorded step.
    pub rows: Vec<Vec<f64>>,
}

/// Steps between recorded rows of [`trace`].
pub const TRACE_EVERY: usize = 5;

/// Step a zoo model over its duration and record, every [`TRACE_EVERY`] steps: the time, per
/// pantograph its position, contact force, contact-wire height and velocity at the contact point
/// (and the head's height for a lumped pantograph), the number of slack droppers, and three modal
/// coordinates (contact wire modes 1 and N/2, messenger mode 1; 0 without a messenger).
pub fn trace(name: &str) -> Option<Trace> {
    Some(trace_of(&model(name)?))
}

/// [`trace`] of a given set-up (a zoo model, perhaps modified by a test).
pub fn trace_of(setup: &Setup) -> Trace {
    use crate::model::{Direction, PantographKind, WireRole};
    let model = &setup.model;
    let n_steps = setup.n_steps();
    let mut columns = vec!["time_s".to_string()];
    for p in &model.pantographs {
        for c in ["position_m", "force_n", "height_m", "velocity_m_s"] {
            columns.push(format!("{}_{c}", p.name));
        }
        if matches!(p.kind, PantographKind::Lumped(_)) {
            columns.push(format!("{}_head_m", p.name));
        }
    }
    columns.extend(
        ["slack_droppers", "qc_1", "qc_mid", "qm_1"]
            .iter()
            .map(|s| s.to_string()),
    );
    let cb = model
        .block(WireRole::Contact, Direction::Vertical)
        .expect("a contact wire");
    let mb = model.block(WireRole::Messenger, Direction::Vertical);
    let n = model.layout.blocks[cb].n_modes;
    let mut s = Stepper::new(setup).expect("zoo models are valid");
    let mut rows = Vec::new();
    for step in 1..=n_steps {
        s.step();
        if step % TRACE_EVERY != 0 {
            continue;
        }
        let mut row = vec![s.state.t];
        for (p, smp) in s.samples().iter().enumerate() {
            row.extend([
                smp.position_m,
                smp.force_n,
                smp.wire_height_m,
                smp.wire_velocity_m_s,
            ]);
            if s.model().pantographs[p].n_dof() > 0 {
                row.push(s.state.pantographs.u[s.integ.pantograph_dofs(p).start]);
            }
        }
        row.push(s.ws.slack_droppers() as f64);
        let qc = s.state.q(s.model(), cb);
        row.extend([qc[0], qc[n / 2]]);
        row.push(mb.map_or(0.0, |b| s.state.q(s.model(), b)[0]));
        rows.push(row);
    }
    Trace { columns, rows }
}

/// The byte spans `[start, end)` of the numbers in a case's TOML text (a leading minus
/// included), for the tests that mutate cases: `tests/suite/mutations.rs` (the core's proptest) and
/// the CLI's `tests/suite/fuzz_run.rs`.
pub fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit()
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
        if starts {
            let s = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
            let mut j = i;
            while j < b.len()
                && (b[j].is_ascii_digit() || matches!(b[j], b'.' | b'e' | b'E' | b'-' | b'+'))
            {
                j += 1;
            }
            out.push((s, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}
