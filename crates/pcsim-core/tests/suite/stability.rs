//! The time step against the coupled system's stability limit (issue 20, item 1).
//!
//! - The power iteration finds the highest frequency of a wire with a stiff point mass on a
//!   spring exactly (the secular equation of a rank-one update, solved by bisection).
//! - On `en50318-2002` (250 and 300 km/h) and `stitched-2018-like` (320 km/h), the largest
//!   accepted Δt gives σ within 2 % of the Δt = 0.25 ms value, and a Δt just above it is refused
//!   with the limiting element named.
//! - A support of 1e8 N/m (caught before only when the run blew up) is refused at the default
//!   Δt, naming the supports.

use pcsim_core::compile::Setup;
use pcsim_core::error::CaseError;
use pcsim_core::model::ModelBuilder;
use pcsim_core::solve::{stability, CompiledModel};
use pcsim_core::{presets, run_case};

fn limit(setup: &Setup) -> stability::CoupledLimit {
    let cm = CompiledModel::new(setup.model.clone(), &setup.plan, setup.options.isa).unwrap();
    stability::coupled_limit(&cm, &setup.plan).unwrap()
}

#[test]
fn power_iteration_finds_the_exact_highest_frequency_of_a_stiff_point() {
    // A 60 m string (16 kN, 1.07 kg/m, EI 150 N·m²), 120 modes, with a 0.9 kg steady arm on a
    // 2e6 N/m spring at 23.7 m: K = diag(k_j) + k0 φφᵀ, M = diag(m_j) + m0 φφᵀ.
    let (len, n, rho, t, ei) = (60.0, 120, 1.07, 16_000.0, 150.0);
    let (x0, m0, k0) = (23.7, 0.9, 2e6);
    let setup = Setup::from_builder(
        ModelBuilder::single_wire(len, n, rho, t, ei)
            .point_mass(x0, m0, k0)
            .build(),
    );
    let got = limit(&setup);
    // Exact: the largest root λ of 1 + (k0 − λ m0) Σ φ_j² / (k_j − λ m_j) = 0, above every k_j/m_j.
    let modes: Vec<(f64, f64, f64)> = (1..=n)
        .map(|j| {
            let kap = j as f64 * std::f64::consts::PI / len;
            let m = 0.5 * rho * len;
            let k = 0.5 * len * (t * kap * kap + ei * kap.powi(4));
            (m, k, (kap * x0).sin())
        })
        .collect();
    let secular = |l: f64| {
        1.0 + (k0 - l * m0)
            * modes
                .iter()
                .map(|(m, k, p)| p * p / (k - l * m))
                .sum::<f64>()
    };
    let top = modes.iter().map(|(m, k, _)| k / m).fold(0.0, f64::max);
    // Above the top pole the sum is negative and grows to 0: the secular function goes from +∞
    // (just above the pole, the term (k0 − λ m0)·(negative large) with k0 > λ m0) through zero.
    let (mut lo, mut hi) = (top * (1.0 + 1e-12), top * 1e3);
    assert!(secular(lo) * secular(hi) < 0.0, "bracket");
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if secular(lo) * secular(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let exact = (0.5 * (lo + hi)).sqrt();
    let rel = (got.omega_rad_s - exact).abs() / exact;
    assert!(
        rel < 1e-4,
        "power iteration ω = {} rad/s, exact {exact} rad/s (rel {rel:e})",
        got.omega_rad_s
    );
    assert!(
        got.omega_rad_s > top.sqrt() * 1.01,
        "the point raises the limit"
    );
    assert!(
        got.limiting.contains("steady_arm") || got.limiting.contains("steady arm"),
        "{}",
        got.limiting
    );
    assert!((got.dt_max_s - stability::MARGIN * 2.0 / exact).abs() < 1e-4 * got.dt_max_s);
}

/// σ of the leading pantograph at `dt`.
fn sigma(name: &str, speed_kmh: f64, dt: f64) -> f64 {
    let (mut c, _) = presets::load(name).unwrap();
    c.run.speed_kmh = speed_kmh;
    c.run.dt_s = dt;
    let out = run_case(&c, &mut |_| true).unwrap();
    out.pantographs[0].stats.unwrap().std_n
}

#[test]
fn every_accepted_step_gives_sigma_within_two_percent() {
    let cases = [
        ("en50318-2002", 250.0, "dropper"),
        ("en50318-2002", 300.0, "dropper"),
        ("stitched-2018-like", 320.0, "support"),
    ];
    std::thread::scope(|s| {
        let hs: Vec<_> = cases
            .iter()
            .map(|&(name, v, element)| {
                s.spawn(move || {
                    let (mut c, _) = presets::load(name).unwrap();
                    c.run.speed_kmh = v;
                    let lim = limit(&Setup::from_case(&c).unwrap());
                    // The largest accepted step (rounded down to 1 µs) against the converged one.
                    let dt = (lim.dt_max_s * 1e6).floor() * 1e-6;
                    let (s_ref, s_lim) = (sigma(name, v, 0.25e-3), sigma(name, v, dt));
                    let err = (s_lim - s_ref).abs() / s_ref;
                    assert!(
                        err < 0.02,
                        "{name} at {v} km/h: σ {s_lim:.3} N at Δt = {dt:e} s against {s_ref:.3} N at 0.25 ms ({:.2} %)",
                        100.0 * err
                    );
                    // Just above the limit: refused, naming Δt and the limiting element.
                    c.run.dt_s = lim.dt_max_s * 1.01;
                    let e = run_case(&c, &mut |_| true).unwrap_err().to_string();
                    assert!(e.contains("run.dt_s") && e.contains("coupled system") && e.contains(element), "{e}");
                })
            })
            .collect();
        for h in hs {
            h.join().unwrap();
        }
    });
}

#[test]
fn a_stiff_support_is_refused_before_the_run_naming_the_supports() {
    let (mut c, _) = presets::load("en50318-2002").unwrap();
    c.catenary.messenger_support.stiffness_n_per_m = 1e8;
    let setup = Setup::from_case(&c).unwrap();
    match setup.integrator() {
        Err(CaseError::Invalid { field, reason, .. }) => {
            assert_eq!(field, "run.dt_s");
            assert!(
                reason.contains("support") && reason.contains("1.000e8"),
                "{reason}"
            );
        }
        other => panic!("a 1e8 N/m support at Δt = 1 ms was not refused: {other:?}"),
    }
}

/// The cheap bound before the power iteration (each wire's highest mode alone, the Rayleigh
/// quotient's trial vector) is a lower bound of the coupled frequency the power iteration finds
/// on the presets; a case with far too many modes for its step is refused by it, naming the wire
/// and the field, without the iteration (found by the fuzz run: 100 modes per metre on a line,
/// where 3 000 iterations stopped at a third of the wires' own highest frequency).
#[test]
fn the_top_mode_bound_is_below_the_coupled_limit_and_refuses_at_once() {
    for name in [
        "en50318-2002",
        "stitched-2018-like",
        "stitched-2018-like-3d",
    ] {
        let (c, _) = presets::load(name).unwrap();
        let setup = Setup::from_case(&c).unwrap();
        let cm = CompiledModel::new(setup.model.clone(), &setup.plan, setup.options.isa).unwrap();
        let (w2, _) = stability::top_mode_bound(&cm).unwrap();
        let lim = stability::coupled_limit(&cm, &setup.plan).unwrap();
        assert!(
            w2.sqrt() <= lim.omega_rad_s * (1.0 + 1e-6),
            "{name}: bound {} rad/s above the coupled {} rad/s",
            w2.sqrt(),
            lim.omega_rad_s
        );
    }
    let mut c = presets::load("en50318-2018-like-stitched").unwrap().0;
    c.run.modes = None;
    c.run.modes_per_m = Some(100.0);
    match Setup::from_case(&c).and_then(|s| s.integrator().map(|_| ())) {
        Err(e) => {
            let e = e.to_string();
            assert!(
                e.contains("run.dt_s")
                    && e.contains("highest mode alone")
                    && e.contains("contact_wire"),
                "{e}"
            );
        }
        Ok(()) => panic!("100 modes per metre at 1 ms accepted"),
    }
}
