//! Issue 43, item 3: a pantograph's frequency response at the head and a chain fitted to a
//! measured one. The receptance of a 2-mass chain against its closed form; the static limit of
//! a 3-mass chain; a fit recovering known parameters from a synthetic response with 2 % noise
//! within the uncertainty it reports; malformed measurements refused by line.

use pcsim_core::analysis::frf::{fit, Quantity, Response};
use pcsim_core::model::pantograph::Lumped;
use rustfft::num_complex::Complex;

fn chain(m: &[f64], k: &[f64], c: &[f64]) -> Lumped {
    Lumped {
        masses_kg: m.to_vec(),
        stiffness_n_per_m: k.to_vec(),
        damping_ns_per_m: c.to_vec(),
        uplift_n: 70.0,
        uplift_by_height: None,
        aero_coeffs_kmh: vec![0.0],
        strips: Vec::new(),
    }
}

/// The EN 50318:2002 reference pantograph (presets/en50318-2002.toml).
fn reference() -> Lumped {
    chain(&[7.2, 15.0], &[4200.0, 50.0], &[10.0, 90.0])
}

#[test]
fn issue_43_3_the_receptance_of_a_two_mass_chain_is_its_closed_form() {
    let p = reference();
    let (m1, m2, k1, k2, c1, c2) = (7.2, 15.0, 4200.0, 50.0, 10.0, 90.0);
    for f in [0.05, 0.3, 1.0, 2.7, 5.0, 12.0, 20.0, 60.0] {
        let w: f64 = 2.0 * std::f64::consts::PI * f;
        let z1 = Complex::new(k1, w * c1);
        let z2 = Complex::new(k2, w * c2);
        let d11 = z1 - w * w * m1;
        let d22 = z1 + z2 - w * w * m2;
        let exact = d22 / (d11 * d22 - z1 * z1);
        let h = p.receptance(w).unwrap();
        assert!(
            (h - exact).norm() <= 1e-12 * exact.norm(),
            "{f} Hz: {h} against {exact}"
        );
        // The apparent mass is −1/(ω² H).
        let a = Quantity::ApparentMass.of(&p, f).unwrap();
        assert!((a + (exact * w * w).inv()).norm() <= 1e-12 * a.norm());
    }
    // Far below every mode a chain is its springs in series; far above, the head's mass.
    let three = chain(
        &[6.0, 9.0, 12.0],
        &[7000.0, 12000.0, 80.0],
        &[20.0, 30.0, 60.0],
    );
    let h0 = three.receptance(1e-7).unwrap();
    let series: f64 = [7000.0, 12000.0, 80.0].iter().map(|k| 1.0 / k).sum();
    assert!((h0.re - series).abs() <= 1e-9 * series && h0.im.abs() < 1e-6 * series);
    let a = Quantity::ApparentMass.of(&three, 5e3).unwrap();
    assert!((a.re - 6.0).abs() < 0.01, "{a}");
}

#[test]
fn issue_43_3_a_fit_recovers_known_parameters_within_its_uncertainty() {
    let truth = reference();
    let f = Response::log_grid(0.2, 20.0, 120).unwrap();
    let mut measured = Response::of_model(&truth, Quantity::ApparentMass, &f).unwrap();
    // 2 % noise on the magnitude, 2 % of a radian on the phase (seeded).
    crate::common::with_noise(&mut measured, 43);
    measured.source = "synthetic".into();
    // Through its CSV text, as a lab would hand it over.
    let measured = Response::from_csv(&measured.to_csv(), "synthetic.csv").unwrap();
    let start = chain(&[9.0, 12.0], &[3300.0, 65.0], &[13.0, 70.0]);
    let r = fit(&start, &measured).unwrap();
    let truth_x = [7.2, 15.0, 4200.0, 50.0, 10.0, 90.0];
    assert!(
        r.residual_rms < 0.05 && r.residual_rms < r.start_residual_rms / 3.0,
        "{r:?}"
    );
    for (p, t) in r.parameters.iter().zip(truth_x) {
        assert!(!p.at_bound && p.std.is_finite() && p.std > 0.0, "{p:?}");
        assert!(
            (p.value - t).abs() <= 3.0 * p.std,
            "{}: {} ± {} against {t}",
            p.name,
            p.value,
            p.std
        );
    }
    // Without noise the fit is exact to the optimiser's tolerance.
    let clean = Response::of_model(&truth, Quantity::Receptance, &f).unwrap();
    let r = fit(&start, &clean).unwrap();
    for (p, t) in r.parameters.iter().zip(truth_x) {
        assert!(
            (p.value - t).abs() <= 1e-3 * t,
            "{}: {} against {t}",
            p.name,
            p.value
        );
    }
}

#[test]
fn issue_43_3_a_malformed_measurement_is_refused_by_line() {
    let good = "frequency_hz,magnitude_kg,phase_deg\n1,10,0\n2,11,-5\n3,12,-10\n4,13,-20\n";
    assert!(Response::from_csv(good, "m.csv").is_ok());
    for (text, says) in [
        ("", "empty"),
        ("frequency_hz,magnitude,phase_deg\n1,2,3\n", "with its unit"),
        (
            "frequency_hz,magnitude_kg,magnitude_m_per_n,phase_deg\n",
            "one of them",
        ),
        ("f,magnitude_kg,phase_deg\n1,2,3\n", "frequency_hz"),
        (
            "frequency_hz,magnitude_kg,phase_deg\n1,10,0\n1,11,0\n3,1,0\n4,1,0\n",
            "increase",
        ),
        (
            "frequency_hz,magnitude_kg,phase_deg\n1,10,0\n2,x,0\n3,1,0\n4,1,0\n",
            "not a number",
        ),
        (
            "frequency_hz,magnitude_kg,phase_deg\n1,10,0\n2,NaN,0\n3,1,0\n4,1,0\n",
            "not finite",
        ),
        (
            "frequency_hz,magnitude_kg,phase_deg\n1,-10,0\n2,1,0\n3,1,0\n4,1,0\n",
            "positive",
        ),
        (
            "frequency_hz,magnitude_kg,phase_deg\n0,10,0\n2,1,0\n3,1,0\n4,1,0\n",
            "positive",
        ),
        (
            "frequency_hz,magnitude_kg,phase_deg\n1,10,0,7\n",
            "4 values",
        ),
        (
            "frequency_hz,magnitude_kg,phase_deg\n1,10,0\n2,10,0\n",
            "at least 4",
        ),
    ] {
        let e = Response::from_csv(text, "m.csv").unwrap_err().to_string();
        assert!(e.contains("m.csv") && e.contains(says), "{text:?}: {e}");
    }
    // A start with a zero spring cannot be fitted on a logarithmic scale: refused by its field.
    let f = Response::log_grid(0.5, 10.0, 20).unwrap();
    let m = Response::of_model(&reference(), Quantity::Receptance, &f).unwrap();
    let e = fit(&chain(&[7.0, 15.0], &[4200.0, 0.0], &[10.0, 90.0]), &m).unwrap_err();
    assert!(e.to_string().contains("stiffness_n_per_m[1]"), "{e}");
}
