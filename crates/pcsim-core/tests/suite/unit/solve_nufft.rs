//! The unit tests of `solve::nufft` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::model::basis::SineBasis;
use pcsim_core::solve::kernels::{self, Isa};
use pcsim_core::solve::nufft::*;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner, FftPlannerScalar};
use std::f64::consts::PI;
use std::sync::Arc;

/// A deterministic pseudo-random sequence in [−1, 1) (splitmix64); the sampler's tests use
/// it too.
pub(crate) fn rng(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// Random layouts (points anywhere in `[0, L]`, the ends included) and random modal
/// coordinates: the gather equals the dense sum `Σ q_m sin(κ_m x)` and the scatter the dense
/// transpose, within 1e-12 of `Σ|q|` (of `Σ|f|`), on both instruction-set paths, with one,
/// two and three blocks.
#[test]
fn the_transform_equals_the_dense_sums_on_random_layouts() {
    for isa in [Isa::Portable, Isa::best_available()] {
        for (seed, n, np, l) in [
            (1, 40, 7, 60.0),
            (2, 600, 230, 720.0),
            (3, 2400, 500, 1900.0),
        ] {
            let mut r = rng(seed);
            let basis = SineBasis::new(l, n);
            let mut xs: Vec<f64> = (0..np).map(|_| 0.5 * (r() + 1.0) * l).collect();
            xs[0] = 0.0;
            xs[1] = l;
            xs[2] = 1e-9 * l;
            let t = SineNufft::new(&basis, &xs, isa);
            let mut s = t.scratch();
            let mut worst: f64 = 0.0;
            for nb in 1..=3 {
                let q: Vec<f64> = (0..nb * n).map(|_| r()).collect();
                let mut out = vec![0.0; nb * np];
                t.gather(&q, nb, &mut out, &mut s);
                let f: Vec<f64> = (0..nb * np).map(|_| r()).collect();
                let mut qs = vec![0.5; nb * n];
                t.scatter_add(&f, nb, &mut qs, &mut s);
                let mut row = vec![0.0; n];
                for b in 0..nb {
                    let qb = &q[b * n..(b + 1) * n];
                    let scale: f64 = qb.iter().map(|v| v.abs()).sum();
                    let fscale: f64 = f[b * np..(b + 1) * np].iter().map(|v| v.abs()).sum();
                    let mut dense_q = vec![0.5; n];
                    for (p, &x) in xs.iter().enumerate() {
                        basis.fill_sines(x, &mut row);
                        let want: f64 = row.iter().zip(qb).map(|(a, b)| a * b).sum();
                        let got = out[b * np + p];
                        worst = worst.max((got - want).abs() / scale);
                        assert!(
                            (got - want).abs() < 1e-12 * scale,
                            "{isa:?} N {n} block {b} x {x}: {got} vs {want} ({:.1e} of Σ|q|)",
                            (got - want).abs() / scale
                        );
                        for (dq, rm) in dense_q.iter_mut().zip(&row) {
                            *dq += f[b * np + p] * rm;
                        }
                    }
                    for m in 0..n {
                        let got = qs[b * n + m];
                        worst = worst.max((got - dense_q[m]).abs() / fscale);
                        assert!(
                            (got - dense_q[m]).abs() < 1e-12 * fscale,
                            "{isa:?} N {n} block {b} mode {m}: {got} vs {}",
                            dense_q[m]
                        );
                    }
                }
            }
            eprintln!("{isa:?}, N = {n}, {np} points: worst error {worst:.1e} of Σ|q| (Σ|f|)");
        }
    }
}
