//! The shared zoo of test models (after diffsol's test_models): short versions of the presets.
#![allow(dead_code)]

use pcsim_core::input::case::{Case, PantographCase};
use pcsim_core::presets;

/// The `en50318-2002` preset cut to `spans` spans with the pantograph run over the middle.
pub fn short_en50318(spans: usize, speed_kmh: f64) -> Case {
    let (mut c, _) = presets::load("en50318-2002").unwrap();
    c.catenary.spans = spans;
    let l = c.length_m();
    c.run.speed_kmh = speed_kmh;
    c.run.start_m = c.catenary.span_m;
    c.run.end_m = l - c.catenary.span_m;
    c.run.analysis_m = [2.0 * c.catenary.span_m, l - 2.0 * c.catenary.span_m];
    c
}

/// Replace the pantographs by one constant moving force.
pub fn with_moving_force(mut c: Case, force_n: f64) -> Case {
    c.pantographs = vec![PantographCase::MovingForce {
        name: "load".into(),
        offset_m: 0.0,
        force_n,
        lateral_force_n: 0.0,
    }];
    c
}

/// A preset cut to `spans` spans, leading pantograph only, run over the middle.
pub fn short_preset(name: &str, spans: usize, speed_kmh: f64) -> Case {
    let (mut c, _) = presets::load(name).unwrap();
    c.catenary.spans = spans;
    c.pantographs.truncate(1);
    let l = c.length_m();
    c.run.speed_kmh = speed_kmh;
    c.run.start_m = c.catenary.span_m;
    c.run.end_m = l - c.catenary.span_m;
    c.run.analysis_m = [2.0 * c.catenary.span_m, l - 2.0 * c.catenary.span_m];
    c.run.modes = None;
    c.run.modes_per_m = Some(1.0);
    c
}
