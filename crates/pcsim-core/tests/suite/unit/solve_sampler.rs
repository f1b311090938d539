//! The unit tests of `solve::sampler` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::model::basis::SineBasis;
use pcsim_core::solve::kernels::{self, Isa};
use pcsim_core::solve::nufft::{NufftScratch, SineNufft};
use pcsim_core::solve::sampler::*;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner, FftPlannerScalar};
use std::sync::Arc;

/// Runs reproduce their list in its order: one run for a span-periodic group (output
/// indices a span's points apart, transform indices rising or falling by one), several for
/// a list with breaks, repeats and a lone point.
#[test]
fn runs_reproduce_their_pairs() {
    let regular: Vec<(usize, usize)> = (0..30).map(|s| (9 * s + 2, s)).collect();
    let falling: Vec<(usize, usize)> = (0..30).map(|s| (9 * s + 8, 59 - s)).collect();
    let broken = vec![
        (5, 1),
        (7, 2),
        (9, 3),
        (4, 4),
        (4, 4),
        (4, 4),
        (20, 0),
        (1, 9),
        (0, 10),
    ];
    for (list, n_runs) in [(&regular, 1), (&falling, 1), (&broken, 4), (&vec![], 0)] {
        let runs = Run::split(list);
        assert_eq!(runs.len(), n_runs, "{list:?}");
        let back: Vec<_> = runs
            .iter()
            .flat_map(|r| (0..r.len).map(move |k| r.at(k)))
            .collect();
        assert_eq!(&back, list);
    }
}

/// Offsets 5/55, 10.5/49.5, 17/43, 23.5/36.5 are mirror pairs: 10 offsets, 6 passes.
const OFFSETS: [f64; 10] = [0.0, 5.0, 10.5, 17.0, 23.5, 30.0, 36.5, 43.0, 49.5, 55.0];

fn xs_periodic_at(ns: usize, s: f64, offs: &[f64]) -> Vec<f64> {
    let mut xs = Vec::new();
    for k in 0..ns {
        for &d in offs {
            let x = k as f64 * s + d;
            if x > 0.0 {
                xs.push(x);
            }
        }
    }
    xs.push(13.7); // a stray point: dense path
    xs
}

#[test]
fn folded_path_equals_dense_path() {
    let (ns, s) = (12, 60.0);
    // The offsets less the middle one (30): 5 passes, so that the paired kernels also
    // meet a group alone.
    let odd: Vec<f64> = OFFSETS.iter().copied().filter(|&d| d != 30.0).collect();
    for (offs, passes) in [(&OFFSETS[..], 6), (&odd[..], 5)] {
        for isa in [Isa::Portable, Isa::best_available()] {
            for n in [700usize, 720, 1001] {
                let basis = SineBasis::new(ns as f64 * s, n);
                let xs = xs_periodic_at(ns, s, offs);
                let fast = PointSampler::new(&basis, &xs, Some(s), isa);
                let slow = PointSampler::new(&basis, &xs, None, isa);
                assert!(fast.n_folded() > 100);
                assert_eq!(fast.n_mode_passes(), passes);
                assert_eq!(slow.n_folded(), 0);
                let q: Vec<f64> = (0..n)
                    .map(|i| ((i * 37 % 101) as f64 - 50.0) / (1.0 + i as f64))
                    .collect();
                let (mut o1, mut o2) = (vec![0.0; xs.len()], vec![0.0; xs.len()]);
                let (mut s1, mut s2) = (fast.scratch(), slow.scratch());
                fast.gather(&q, 1, &mut o1, &mut s1);
                slow.gather(&q, 1, &mut o2, &mut s2);
                for j in 0..xs.len() {
                    assert!(
                        (o1[j] - o2[j]).abs() < 1e-10,
                        "gather j={j}: {} vs {}",
                        o1[j],
                        o2[j]
                    );
                }
                let f: Vec<f64> = (0..xs.len()).map(|j| ((j * 13 % 7) as f64) - 3.0).collect();
                let (mut g1, mut g2) = (vec![0.0; n], vec![0.0; n]);
                fast.scatter_add(&f, 1, &mut g1, &mut s1);
                slow.scatter_add(&f, 1, &mut g2, &mut s2);
                for k in 0..n {
                    assert!((g1[k] - g2[k]).abs() < 1e-9, "scatter k={k}");
                }
                // Three blocks at once (a pair, then one alone) equal three single calls.
                let q2: Vec<f64> = q.iter().rev().copied().collect();
                let q3: Vec<f64> = q.iter().map(|v| 0.5 * v - 1e-3).collect();
                let qs: Vec<f64> = [&q[..], &q2[..], &q3[..]].concat();
                let np = xs.len();
                let mut blocks = vec![0.0; 3 * np];
                fast.gather(&qs, 3, &mut blocks, &mut s1);
                for (b, qb) in [&q, &q2, &q3].iter().enumerate() {
                    let mut one = vec![0.0; np];
                    slow.gather(qb, 1, &mut one, &mut s2);
                    for j in 0..np {
                        assert!(
                            (blocks[b * np + j] - one[j]).abs() < 1e-10,
                            "gather block {b}"
                        );
                    }
                }
                let f2: Vec<f64> = f.iter().map(|v| 2.0 * v + 1.0).collect();
                let f3: Vec<f64> = f.iter().map(|v| v * v).collect();
                let fs: Vec<f64> = [&f[..], &f2[..], &f3[..]].concat();
                let mut out = vec![0.0; 3 * n];
                fast.scatter_add(&fs, 3, &mut out, &mut s1);
                for (b, fb) in [&f, &f2, &f3].iter().enumerate() {
                    let mut one = vec![0.0; n];
                    slow.scatter_add(fb, 1, &mut one, &mut s2);
                    for k in 0..n {
                        let (x, y) = (out[b * n + k], one[k]);
                        assert!((x - y).abs() < 1e-9 * (1.0 + y.abs()), "scatter block {b}");
                    }
                }
                // The scaled scatter: out += scale ⊙ Φᵀ f.
                let scale: Vec<f64> = (0..n).map(|k| -1.0 / (1.0 + k as f64)).collect();
                let mut sc_out = q.clone();
                fast.scatter_scaled(&f, &mut sc_out, &scale, &mut s1);
                for k in 0..n {
                    let want = q[k] + scale[k] * g2[k];
                    assert!(
                        (sc_out[k] - want).abs() < 1e-9 * (1.0 + want.abs()),
                        "scaled k={k}"
                    );
                }
            }
        }
    }
}

/// Issue 21, item 8: the points of random line layouts (runs of equal spans of 40–70 m, the
/// dropper layout scaled to each span, the supports, the line's ends), through the sampler
/// as a line's model builds it (no period), equal the dense sums within 1e-12 of `Σ|q|`
/// (`Σ|f|`), gather and scatter of two blocks, both instruction-set paths; the larger
/// layouts take the non-uniform transform, the smaller dense rows.
#[test]
fn random_line_layouts_equal_the_dense_sums() {
    let mut r = crate::unit::solve_nufft::rng(0x5eed);
    let mut rnd = move || 0.5 * (r() + 1.0);
    let layout = [2.5, 9.0, 16.0, 23.0, 30.0, 37.0, 44.0, 51.0, 57.5];
    let mut took_spread = 0;
    for spans_wanted in [6usize, 14, 31] {
        let mut spans = Vec::new();
        while spans.len() < spans_wanted {
            let count = 1 + (rnd() * 5.0) as usize;
            let len = (40.0 + 30.0 * rnd()).round();
            spans.extend(std::iter::repeat_n(len, count));
        }
        spans.truncate(spans_wanted);
        let l: f64 = spans.iter().sum();
        let mut xs = vec![0.0];
        let mut x0 = 0.0;
        for &s in &spans {
            xs.extend(layout.iter().map(|d| x0 + d * s / 60.0));
            x0 += s;
            xs.push(x0.min(l));
        }
        let n = l.round() as usize;
        let basis = SineBasis::new(l, n);
        for isa in [Isa::Portable, Isa::best_available()] {
            let sp = PointSampler::new(&basis, &xs, None, isa);
            took_spread += usize::from(sp.n_spread() > 0);
            let mut sc = sp.scratch();
            let np = xs.len();
            let q: Vec<f64> = (0..2 * n).map(|_| 2.0 * rnd() - 1.0).collect();
            let f: Vec<f64> = (0..2 * np).map(|_| 2.0 * rnd() - 1.0).collect();
            let mut out = vec![0.0; 2 * np];
            sp.gather(&q, 2, &mut out, &mut sc);
            let mut g = vec![0.0; 2 * n];
            sp.scatter_add(&f, 2, &mut g, &mut sc);
            let mut row = vec![0.0; n];
            for b in 0..2 {
                let qb = &q[b * n..(b + 1) * n];
                let fb = &f[b * np..(b + 1) * np];
                let qn: f64 = qb.iter().map(|v| v.abs()).sum();
                let fnorm: f64 = fb.iter().map(|v| v.abs()).sum();
                let mut dense = vec![0.0; n];
                for (j, &x) in xs.iter().enumerate() {
                    basis.fill_sines(x, &mut row);
                    let want: f64 = row.iter().zip(qb).map(|(a, c)| a * c).sum();
                    assert!(
                        (out[b * np + j] - want).abs() < 1e-12 * qn,
                        "{isa:?} {spans:?}: gather at {x}"
                    );
                    for (d, r) in dense.iter_mut().zip(&row) {
                        *d += fb[j] * r;
                    }
                }
                for m in 0..n {
                    assert!(
                        (g[b * n + m] - dense[m]).abs() < 1e-12 * fnorm,
                        "{isa:?} {spans:?}: scatter mode {m}"
                    );
                }
            }
        }
    }
    assert!(took_spread >= 2, "the largest layout takes the transform");
}

/// Points at arbitrary positions (a non-uniform line): beyond a few dozen they go to the
/// non-uniform transform, not to dense rows; gather, scatter (one to three blocks) and the
/// scaled scatter equal the dense sums within 1e-12 of `Σ|q|` (`Σ|f|`), on both paths.
#[test]
fn spread_path_equals_dense_sums() {
    let (l, n, np) = (1300.0, 1500usize, 300usize);
    let xs: Vec<f64> = (0..np)
        .map(|j| l * (((j * 7919 + 13) % 1000) as f64 + 0.37) / 1000.0)
        .collect();
    let basis = SineBasis::new(l, n);
    let mut rows = vec![vec![0.0; n]; np];
    for (r, &x) in rows.iter_mut().zip(&xs) {
        basis.fill_sines(x, r);
    }
    assert!(
        !spread_pays(35, 143),
        "the real-time windows stay on dense rows"
    );
    for isa in [Isa::Portable, Isa::best_available()] {
        let sp = PointSampler::new(&basis, &xs, None, isa);
        assert_eq!(sp.n_spread(), np);
        let mut sc = sp.scratch();
        let qs: Vec<f64> = (0..3 * n)
            .map(|i| ((i * 37 % 101) as f64 - 50.0) / 50.0)
            .collect();
        let fs: Vec<f64> = (0..3 * np).map(|j| ((j * 13 % 7) as f64) - 3.0).collect();
        for k in 1..=3 {
            let mut out = vec![0.0; k * np];
            sp.gather(&qs[..k * n], k, &mut out, &mut sc);
            let mut g = vec![0.25; k * n];
            sp.scatter_add(&fs[..k * np], k, &mut g, &mut sc);
            for b in 0..k {
                let qb = &qs[b * n..(b + 1) * n];
                let fb = &fs[b * np..(b + 1) * np];
                let (qn, fnorm): (f64, f64) = (
                    qb.iter().map(|v| v.abs()).sum(),
                    fb.iter().map(|v| v.abs()).sum(),
                );
                for j in 0..np {
                    let want: f64 = rows[j].iter().zip(qb).map(|(a, b)| a * b).sum();
                    assert!(
                        (out[b * np + j] - want).abs() < 1e-12 * qn,
                        "{isa:?} gather"
                    );
                }
                for m in 0..n {
                    let want = 0.25 + (0..np).map(|j| fb[j] * rows[j][m]).sum::<f64>();
                    assert!(
                        (g[b * n + m] - want).abs() < 1e-12 * fnorm,
                        "{isa:?} scatter"
                    );
                }
            }
        }
        let scale: Vec<f64> = (0..n).map(|m| -1.0 / (1.0 + m as f64)).collect();
        let mut o = vec![1.0; n];
        sp.scatter_scaled(&fs[..np], &mut o, &scale, &mut sc);
        let fnorm: f64 = fs[..np].iter().map(|v| v.abs()).sum();
        for m in 0..n {
            let want = 1.0 + scale[m] * (0..np).map(|j| fs[j] * rows[j][m]).sum::<f64>();
            assert!((o[m] - want).abs() < 1e-12 * fnorm, "{isa:?} scaled");
        }
    }
}
