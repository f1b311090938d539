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

/// The upward zero crossings of `y(t)`, linear between samples, s.
pub fn zero_crossings(t: &[f64], y: &[f64]) -> Vec<f64> {
    (1..y.len())
        .filter(|&i| y[i - 1] < 0.0 && y[i] >= 0.0)
        .map(|i| t[i - 1] + (t[i] - t[i - 1]) * (-y[i - 1]) / (y[i] - y[i - 1]))
        .collect()
}

/// The mean period between the first and the last of the crossings `z`, s.
pub fn mean_period(z: &[f64]) -> f64 {
    (z[z.len() - 1] - z[0]) / (z.len() - 1) as f64
}

/// The first natural frequency of a string (length `l`, mass per metre `rho`, tension `t`) with a
/// point mass `m` at its centre, rad/s: the root of `cot(βL/2) = mβ/(2ρ)` below π/L, `ω = cβ`.
pub fn string_with_central_mass_omega(l: f64, rho: f64, t: f64, m: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let g = |b: f64| 1.0 / (b * l / 2.0).tan() - m * b / (2.0 * rho);
    let (mut lo, mut hi) = (1e-6, pi / l - 1e-9);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    (t / rho).sqrt() * 0.5 * (lo + hi)
}

/// The stepper of a hand-made model.
pub fn stepper(b: pcsim_core::model::ModelBuilder) -> pcsim_core::compile::Stepper {
    use pcsim_core::compile::{Setup, Stepper};
    Stepper::new(&Setup::from_builder(b.build())).unwrap()
}

/// The contact wire's vertical block of a stepper's model.
pub fn wire(s: &pcsim_core::compile::Stepper) -> usize {
    use pcsim_core::model::{Direction, WireRole};
    s.model()
        .block(WireRole::Contact, Direction::Vertical)
        .unwrap()
}

/// The first symmetric mode of a string of length `l` with `n` modes under tension `t`, as
/// stepped by `s`: started from the static shape under a unit load at the centre (mostly that
/// mode), its centre's displacement over `steps` steps, ω from the mean period, rad/s.
pub fn central_mode_omega(
    s: &mut pcsim_core::compile::Stepper,
    l: f64,
    n: usize,
    t: f64,
    steps: usize,
) -> f64 {
    use pcsim_core::model::basis::SineBasis;
    use pcsim_core::model::statics::modal_static_deflection;
    let b = wire(s);
    let basis = SineBasis::new(l, n);
    s.state
        .q_mut(s.integ.model(), b)
        .copy_from_slice(&modal_static_deflection(
            &basis,
            t,
            0.0,
            0.0,
            &[(l / 2.0, 1.0)],
        ));
    let mut row = vec![0.0; n];
    let (mut ts, mut ys) = (Vec::new(), Vec::new());
    for _ in 0..steps {
        s.step();
        ts.push(s.state.t);
        ys.push(basis.eval(s.state.q(s.model(), b), l / 2.0, &mut row));
    }
    2.0 * std::f64::consts::PI / mean_period(&zero_crossings(&ts, &ys))
}
