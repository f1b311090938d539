//! A run beside a measurement (issue 22, item 4): a synthetic "measurement" made from a run —
//! shifted, scaled, with noise added, at a recording car's spacing — gives the shift back within
//! one sample and the statistics within the noise.

use crate::common;

use pcsim_core::analysis::compare::compare;
use pcsim_core::input::measured::MeasuredForce;
use pcsim_core::run_case;

/// A seeded Gaussian (splitmix64 and Box–Muller).
fn gauss(state: &mut u64) -> f64 {
    let mut u = || {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let (a, b) = (u().max(1e-300), u());
    (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
}

#[test]
fn a_shifted_scaled_noisy_copy_of_a_run_is_aligned_and_compared() {
    let case = common::short_en50318(12, 250.0);
    let out = run_case(&case, &mut |_| true).unwrap();
    let p = &out.pantographs[0];
    let (x, f) = (&p.position_m, &p.force_n);
    let v = out.speed_m_s;
    let supports: Vec<f64> = (0..=12).map(|k| k as f64 * case.catenary.span_m).collect();
    let dxs = x[1] - x[0];
    let interp = |xq: f64| {
        let s = ((xq - x[0]) / dxs).clamp(0.0, (x.len() - 2) as f64);
        let k = s.floor() as usize;
        f[k] + (f[k + 1] - f[k]) * (s - k as f64)
    };
    let (scale, noise_n, dx) = (1.05, 5.0, 0.2);
    // Shifts of whole samples (the statistics, spectra and profiles are then compared at the
    // same points) and one between samples (found to the nearer sample).
    for (shift, seed) in [(7.4, 1u64), (-12.8, 2), (3.33, 3)] {
        // Measured position y is simulated position y + shift.
        let mut st = seed;
        let n = ((x[x.len() - 1] - x[0] - 30.0) / dx) as usize;
        let y0 = x[0] + 15.0 - shift;
        let mut text = String::from("position_m,force_n\n");
        for j in 0..n {
            let y = y0 + j as f64 * dx;
            let m = scale * interp(y + shift) + noise_n * gauss(&mut st);
            text += &format!("{y},{m}\n");
        }
        let meas = MeasuredForce::from_csv(&text, "synthetic.csv").unwrap();
        let c = compare((x, f), &meas, v, case.run.analysis_m, 30.0, &supports).unwrap();
        eprintln!(
            "shift {shift} m: found {} m (r = {:.4}); mean {:.2} / {:.2}, σ {:.2} / {:.2}, max {:.1} / {:.1}",
            c.shift_m, c.correlation, c.simulated.mean_n, c.measured.mean_n, c.simulated.std_n,
            c.measured.std_n, c.simulated.max_n, c.measured.max_n
        );
        assert!(
            (c.shift_m - shift).abs() <= dx,
            "shift {} m, found {} m",
            shift,
            c.shift_m
        );
        assert!(c.correlation > 0.99);
        if (shift / dx - (shift / dx).round()).abs() > 1e-6 {
            continue;
        }
        // The noise, filtered to 0–20 Hz at 347 Hz sampling, keeps about 1.7 N of its 5 N.
        let s = &c.simulated;
        let m = &c.measured;
        assert!((m.mean_n - scale * s.mean_n).abs() < 0.5, "mean");
        assert!(
            (m.std_n - scale * s.std_n).abs() < 0.5,
            "σ {} vs {}",
            m.std_n,
            scale * s.std_n
        );
        assert!((m.max_n - scale * s.max_n).abs() < 6.0, "max");
        assert!((m.min_n - scale * s.min_n).abs() < 6.0, "min");
        assert!(c.position_m.len() > 2000);
        // The spectra and the profiles follow each other: the measurement is 1.05 × the run.
        // The power below 0.2 1/m (wavelengths above 5 m; 20 Hz is 0.29 1/m at 250 km/h).
        let power = |i: usize| -> f64 {
            c.spectrum
                .iter()
                .filter(|b| b[0] <= 0.2)
                .map(|b| b[i])
                .sum()
        };
        let ratio = power(2) / power(1);
        assert!(
            (ratio - scale * scale).abs() < 0.05 * scale * scale,
            "power ratio {ratio}"
        );
        assert_eq!(c.profile.len(), 50);
        for b in &c.profile {
            assert!((b[2] - scale * b[1]).abs() < 2.0, "{b:?}");
        }
    }
    // A search too wide for the record is refused, naming the flag, before any work.
    let text: String = std::iter::once("position_m,force_n\n".to_string())
        .chain((0..200_000).map(|j| format!("{},{}\n", 0.01 * j as f64, 100.0)))
        .collect();
    let meas = MeasuredForce::from_csv(&text, "fine.csv").unwrap();
    let e = compare(
        (x, f),
        &meas,
        1.0,
        case.run.analysis_m,
        100_000.0,
        &supports,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("--search") && e.contains("narrow"), "{e}");
    // A record of another place is refused, naming it.
    let text: String = std::iter::once("position_m,force_n\n".to_string())
        .chain((0..500).map(|j| format!("{},{}\n", 5000.0 + 0.2 * j as f64, 100.0)))
        .collect();
    let meas = MeasuredForce::from_csv(&text, "far.csv").unwrap();
    let e = compare((x, f), &meas, v, case.run.analysis_m, 30.0, &supports)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("measured positions") && e.contains("5000"),
        "{e}"
    );
}
