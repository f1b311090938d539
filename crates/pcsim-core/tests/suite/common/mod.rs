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

/// Two tension lengths of six 60 m spans with a 3-span overlap (180–360 m), the 2002 catenary,
/// 250 km/h over 60–480 m.
pub fn overlap_line() -> Case {
    use pcsim_core::input::case::{LineCase, OverlapCase, SpanRun, TensionLengthCase};
    let mut case = short_en50318(9, 250.0);
    let t = TensionLengthCase {
        span_runs: vec![SpanRun {
            count: 6,
            length_m: 60.0,
            track_radius_m: None,
            cant_m: None,
        }],
        spans_m: Vec::new(),
        droppers_m: Vec::new(),
        contact_height_m: Vec::new(),
        encumbrance_m: Vec::new(),
        stagger_m: Vec::new(),
        contact_wire: None,
        messenger: None,
        droppers: None,
        messenger_support: None,
        steady_arm: None,
    };
    case.line = Some(LineCase {
        tension_lengths: vec![t.clone(), t],
        overlaps: vec![OverlapCase {
            spans: 3,
            rise_m: 0.3,
            separation_m: 0.2,
        }],
    });
    case.catenary.spans = 9;
    case.run.start_m = 60.0;
    case.run.end_m = 480.0;
    case.run.analysis_m = [120.0, 420.0];
    case
}

/// The first pantograph's EN 50318 mean, σ and actual extremes of two runs agree within `tol`
/// relative (`what` names the comparison in the failure).
pub fn same_statistics(a: &pcsim_core::RunOutput, b: &pcsim_core::RunOutput, tol: f64, what: &str) {
    let (sa, sb) = (
        a.pantographs[0].stats.unwrap(),
        b.pantographs[0].stats.unwrap(),
    );
    for (name, x, y) in [
        ("mean", sa.mean_n, sb.mean_n),
        ("std", sa.std_n, sb.std_n),
        ("max", sa.actual_max_n, sb.actual_max_n),
        ("min", sa.actual_min_n, sb.actual_min_n),
    ] {
        assert!((x - y).abs() <= tol * x.abs(), "{what}, {name}: {x} vs {y}");
    }
}

/// `measured` with seeded noise: 2 % normal on the magnitude and 0.02 rad on the phase (a
/// lab's frequency response, for the fits' checks).
pub fn with_noise(measured: &mut pcsim_core::analysis::frf::Response, seed: u64) {
    use rustfft::num_complex::Complex;
    let mut rng = pcsim_core::model::wind_field::SplitMix64::new(seed);
    // Normal deviates (Box–Muller) from the seeded stream.
    let mut normal = || {
        let (u, v) = (rng.uniform().max(1e-300), rng.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    };
    for h in &mut measured.value {
        let (m, p) = (h.norm(), h.arg());
        *h = Complex::from_polar(m * (1.0 + 0.02 * normal()), p + 0.02 * normal());
    }
}
