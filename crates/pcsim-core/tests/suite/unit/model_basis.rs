//! The unit tests of `model::basis` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::linalg::dot;
use pcsim_core::model::basis::*;
use std::f64::consts::PI;

#[test]
fn recurrence_matches_direct_sines() {
    let b = SineBasis::new(1800.0, 2000);
    let mut s = vec![0.0; 2000];
    let mut c = vec![0.0; 2000];
    for &x in &[0.0, 0.3, 17.25, 900.0, 1234.5, 1799.9] {
        b.fill_sines_cosines(x, &mut s, &mut c);
        for i in 0..2000 {
            let (es, ec) = (b.wavenumber(i) * x).sin_cos();
            assert!((s[i] - es).abs() < 1e-11, "x={x} i={i}: {} vs {es}", s[i]);
            assert!((c[i] - ec).abs() < 1e-11);
        }
    }
}

/// The four chains, their seeds turned block by block, against a direct call per mode (past
/// the eighth block, and at a phase of thousands of radians).
#[test]
fn four_chain_sines_match_direct_sines() {
    let b = SineBasis::new(1800.0, 2000);
    let mut s = vec![0.0; 2000];
    for &x in &[0.0, 0.3, 17.25, 900.0, 1234.5, 1799.9, -2.5] {
        b.fill_sines(x, &mut s);
        for (i, si) in s.iter().enumerate() {
            let e = (b.wavenumber(i) * x).sin();
            assert!((si - e).abs() < 1e-11, "x={x} i={i}: {si} vs {e}");
        }
    }
}

#[test]
fn derivatives_match_finite_differences() {
    let b = SineBasis::new(120.0, 50);
    let q: Vec<f64> = (0..50).map(|i| 1.0 / (1.0 + i as f64).powi(2)).collect();
    let (mut s, mut c) = (vec![0.0; 50], vec![0.0; 50]);
    let x = 37.3;
    let h = 1e-3;
    let [w, w1, w2] = b.eval_derivatives(&q, x, &mut s, &mut c);
    let wp = b.eval(&q, x + h, &mut s);
    let wm = b.eval(&q, x - h, &mut s);
    assert!((w1 - (wp - wm) / (2.0 * h)).abs() < 1e-6);
    assert!((w2 - (wp - 2.0 * w + wm) / (h * h)).abs() < 1e-4);
}
