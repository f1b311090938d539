//! The shared zoo of test models (after diffsol's test_models): short versions of the presets.
#![allow(dead_code)]

use pcsim_core::input::case::{Case, PantographCase};

pub use pcsim_core::zoo::geometries::{overlap_line, short_en50318, short_preset};

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
pub fn with_noise(measured: &mut pcsim_core::study::frf::Response, seed: u64) {
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
