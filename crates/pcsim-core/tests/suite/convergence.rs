//! Convergence on the reference case (issue 2): halving the time step and raising the modes by
//! 50 % each change Fm by < 0.5 % and σ by < 2 %.

use pcsim_core::{presets, run_case, Case};

fn stats(case: &Case) -> (f64, f64) {
    let out = run_case(case, &mut |_| true).unwrap();
    let s = out.pantographs[0].stats.unwrap();
    (s.mean_n, s.std_n)
}

fn check(speed: f64) {
    let (mut base, _) = presets::load("en50318-2002").unwrap();
    base.run.speed_kmh = speed;
    let mut half_dt = base.clone();
    half_dt.run.dt_s /= 2.0;
    let mut more_modes = base.clone();
    more_modes.run.modes_per_m = base.run.modes_per_m.map(|d| d * 1.5);
    let (r0, r1, r2) = std::thread::scope(|s| {
        let a = s.spawn(|| stats(&base));
        let b = s.spawn(|| stats(&half_dt));
        let c = stats(&more_modes);
        (a.join().unwrap(), b.join().unwrap(), c)
    });
    for (label, r) in [("Δt/2", r1), ("1.5× modes", r2)] {
        let dm = (r.0 - r0.0).abs() / r0.0;
        let ds = (r.1 - r0.1).abs() / r0.1;
        eprintln!(
            "{speed} km/h {label}: Fm {:.2} -> {:.2} ({:.3} %), σ {:.2} -> {:.2} ({:.2} %)",
            r0.0,
            r.0,
            100.0 * dm,
            r0.1,
            r.1,
            100.0 * ds
        );
        assert!(
            dm < 0.005,
            "{speed} km/h, {label}: Fm changes by {:.3} %",
            100.0 * dm
        );
        assert!(
            ds < 0.02,
            "{speed} km/h, {label}: σ changes by {:.2} %",
            100.0 * ds
        );
    }
}

#[test]
fn converged_at_250_kmh() {
    check(250.0);
}

#[test]
fn converged_at_300_kmh() {
    check(300.0);
}
