//! Checks against analytic solutions: static deflection, natural frequencies (with and without
//! a point mass), wave-front arrival, and a constant moving load against the exact modal series.

use pcsim_core::input::case::Damping;
use pcsim_core::model::basis::SineBasis;
use pcsim_core::model::statics::modal_static_deflection;
use pcsim_core::model::ModelBuilder;
use std::f64::consts::PI;

use crate::common::{
    central_mode_omega, mean_period, stepper, string_with_central_mass_omega, wire, zero_crossings,
};

/// Deflection at the load point of a pinned tensioned Euler–Bernoulli beam under a point load
/// `F` at `a`: `F/T [a(L−a)/L − sinh(λa) sinh(λ(L−a)) / (λ sinh λL)]`, `λ = √(T/EI)`.
fn tensioned_beam_point_deflection(f: f64, a: f64, l: f64, t: f64, ei: f64) -> f64 {
    let lam = (t / ei).sqrt();
    let (x, y) = (lam * a, lam * (l - a));
    // sinh x sinh y / sinh(x+y), written without overflow.
    let ratio = (1.0 - (-2.0 * x).exp()) * (1.0 - (-2.0 * y).exp())
        / (2.0 * (1.0 - (-2.0 * (x + y)).exp()));
    f / t * (a * (l - a) / l - ratio / lam)
}

#[test]
fn static_point_load_on_tensioned_beam_modal_solution() {
    let (l, t, ei, f, a) = (100.0, 20_000.0, 195.0, 500.0, 37.0);
    let basis = SineBasis::new(l, 2000);
    let q = modal_static_deflection(&basis, t, ei, 0.0, &[(a, f)]);
    let mut row = vec![0.0; 2000];
    let w = basis.eval(&q, a, &mut row);
    let exact = tensioned_beam_point_deflection(f, a, l, t, ei);
    assert!(
        (w - exact).abs() < 1e-4 * exact.abs(),
        "modal {w} vs exact {exact}"
    );
    // EI matters: the pure-string answer differs by more than the tolerance.
    let string = f / t * a * (l - a) / l;
    assert!((string - exact).abs() > 1e-3 * exact);
}

#[test]
fn static_point_load_reached_by_the_time_integrator() {
    let (l, t, ei, f, a) = (100.0, 20_000.0, 195.0, 500.0, 37.0);
    let mut s = stepper(
        ModelBuilder::single_wire(l, 400, 1.35, t, ei)
            .damping(&Damping::Modal { ratio: 0.3 })
            .moving_force("load", f)
            .run(0.0, a, 20.0, 2e-4),
    );
    for _ in 0..100_000 {
        s.step();
    }
    let w = s.samples()[0].wire_height_m;
    let exact = tensioned_beam_point_deflection(f, a, l, t, ei);
    assert!(
        (w - exact).abs() < 5e-3 * exact,
        "integrated {w} vs exact {exact}"
    );
}

#[test]
fn natural_frequency_of_simply_supported_tensioned_beam() {
    // Beam-dominated parameters so that the EI κ⁴ term matters.
    let (l, rho, t, ei) = (50.0, 1.0, 1000.0, 5000.0);
    let mut s = stepper(ModelBuilder::single_wire(l, 100, rho, t, ei).run(0.0, 1.0, 1.0, 5e-5));
    let b = wire(&s);
    let k = 3;
    s.state.q_mut(s.integ.model(), b)[k - 1] = 0.01;
    let basis = SineBasis::new(l, 100);
    let x = l / (2.0 * k as f64); // antinode of mode k
    let mut row = vec![0.0; 100];
    let (mut ts, mut ys) = (Vec::new(), Vec::new());
    for _ in 0..40_000 {
        s.step();
        ts.push(s.state.t);
        ys.push(basis.eval(s.state.q(s.model(), b), x, &mut row));
    }
    let kap = k as f64 * PI / l;
    let omega = kap * ((t + ei * kap * kap) / rho).sqrt();
    let period = mean_period(&zero_crossings(&ts, &ys));
    let measured = 2.0 * PI / period;
    assert!(
        (measured - omega).abs() < 1e-4 * omega,
        "ω measured {measured} vs exact {omega}"
    );
}

#[test]
fn natural_frequency_of_string_with_central_point_mass() {
    // Symmetric modes: cot(βL/2) = m β / (2ρ), ω = c β. Exercises the exact (Woodbury) point
    // mass in the mass matrix.
    let (l, rho, t, m): (f64, f64, f64, f64) = (20.0, 1.0, 100.0, 2.0);
    let c = (t / rho).sqrt();
    let omega = string_with_central_mass_omega(l, rho, t, m);
    let n = 400;
    let mut s = stepper(
        ModelBuilder::single_wire(l, n, rho, t, 0.0)
            .point_mass(l / 2.0, m, 0.0)
            .run(0.0, 1.0, 1.0, 2e-4),
    );
    let measured = central_mode_omega(&mut s, l, n, t, 200_000);
    assert!(
        (measured - omega).abs() < 5e-3 * omega,
        "ω measured {measured} vs exact {omega}"
    );
    // Without the mass the frequency would be πc/L: the test can tell.
    assert!((PI * c / l - omega).abs() > 0.05 * omega);
}

#[test]
fn wave_front_arrives_at_the_wave_speed() {
    // Step force on a string: u(x, t) = F/(2T) (c t − |x − x0|)₊ until reflections arrive.
    let (l, rho, t, f, x0, x1): (f64, f64, f64, f64, f64, f64) =
        (400.0, 1.35, 20_000.0, 100.0, 100.0, 160.0);
    let c = (t / rho).sqrt();
    let n = 1600;
    let mut s = stepper(
        ModelBuilder::single_wire(l, n, rho, t, 0.0)
            .moving_force("load", f)
            .run(0.0, x0, 3.0, 2e-4),
    );
    let b = wire(&s);
    let basis = SineBasis::new(l, n);
    let mut row = vec![0.0; n];
    let arrival = (x1 - x0) / c;
    let reflection = (x0 + x1) / c;
    let scale = f / (2.0 * t) * (c * reflection - (x1 - x0));
    let mut checked = 0;
    for step in 1..=10_000 {
        s.step();
        if step % 250 != 0 {
            continue;
        }
        let time = s.state.t;
        let u = basis.eval(s.state.q(s.model(), b), x1, &mut row);
        let exact = f / (2.0 * t) * (c * time - (x1 - x0)).max(0.0);
        if time < 0.9 * arrival {
            assert!(
                u.abs() < 0.02 * scale,
                "t={time}: motion {u} before the front ({arrival} s)"
            );
            checked += 1;
        } else if time > 1.2 * arrival && time < 0.97 * reflection {
            assert!((u - exact).abs() < 0.03 * exact, "t={time}: {u} vs {exact}");
            checked += 1;
        }
    }
    assert!(checked > 20);
}

#[test]
fn constant_moving_load_matches_exact_modal_series() {
    // Undamped pinned beam, load F entering at x = 0 with speed v: per mode
    // q_k = 2F/(ρL) [sin Ω t − (Ω/ω) sin ω t] / (ω² − Ω²), Ω = κ v.
    let (l, rho, t, ei, f, v) = (100.0, 1.35, 20_000.0, 195.0, 100.0, 50.0);
    let n = 50;
    let dt = 2.5e-4;
    let mut s = stepper(
        ModelBuilder::single_wire(l, n, rho, t, ei)
            .moving_force("load", f)
            .run(v, 0.0, 2.0, dt),
    );
    let basis = SineBasis::new(l, n);
    let mut row = vec![0.0; n];
    let mut worst: f64 = 0.0;
    let mut peak: f64 = 0.0;
    for _ in 0..7600 {
        s.step();
        let time = s.state.t;
        let x = v * time;
        let mut q = vec![0.0; n];
        for (i, qi) in q.iter_mut().enumerate() {
            let kap = basis.wavenumber(i);
            let om = kap * ((t + ei * kap * kap) / rho).sqrt();
            let big = kap * v;
            *qi = 2.0 * f / (rho * l) * ((big * time).sin() - big / om * (om * time).sin())
                / (om * om - big * big);
        }
        let exact = basis.eval(&q, x, &mut row);
        let got = s.samples()[0].wire_height_m;
        worst = worst.max((got - exact).abs());
        peak = peak.max(exact.abs());
    }
    assert!(peak > 1e-3);
    assert!(worst < 5e-3 * peak, "max error {worst} against peak {peak}");
}
