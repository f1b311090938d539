//! The unit tests of `solve::kernels` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use std::sync::OnceLock;
// The kernels against their scalar references and each other, bit for bit where they must be.

use pcsim_core::solve::kernels::*;

fn data(n: usize, seed: u64) -> Vec<f64> {
    let mut x = seed;
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        })
        .collect()
}

#[test]
fn the_four_lane_sines_are_the_scalar_recurrences_bytes() {
    for n in [
        1usize, 3, 4, 5, 15, 16, 17, 33, 255, 256, 257, 271, 1200, 1203,
    ] {
        let b = pcsim_core::model::basis::SineBasis::new(1834.7, n);
        for x in [0.0, 0.3, 17.25, 911.1, 1834.6, -2.5] {
            let mut want = vec![0.0; n];
            b.fill_sines(x, &mut want);
            for isa in [Isa::Portable, Isa::best_available()] {
                let mut got = vec![9.0; n];
                fill_sines(isa, b.theta(x), &mut got);
                let same = got
                    .iter()
                    .zip(&want)
                    .all(|(g, w)| g.to_bits() == w.to_bits());
                assert!(same, "n {n}, x {x}, {isa:?}");
                // The fill with the row's sum against q: the same row, and dot's bytes.
                let q = data(n, 7);
                let mut row = vec![9.0; n];
                let d = fill_sines_dot(isa, b.theta(x), &mut row, &q);
                assert!(row
                    .iter()
                    .zip(&want)
                    .all(|(g, w)| g.to_bits() == w.to_bits()));
                assert_eq!(d.to_bits(), dot(isa, &q, &want).to_bits(), "n {n}, x {x}");
            }
        }
    }
}

/// The substitutions solve `A x = b` for a factored `A = L Lᵀ`, and are the per-row
/// [`dot`] substitutions' bytes on both paths (n = 23: the 16-wide, 4-wide and scalar parts).
#[test]
fn the_cholesky_substitutions_solve_and_keep_the_dot_kernels_bytes() {
    let n = 23;
    let g = data(n * n, 21);
    // A = G Gᵀ + n I: symmetric positive definite.
    let a: Vec<f64> = (0..n * n)
        .map(|ij| {
            let (i, j) = (ij / n, ij % n);
            let s: f64 = (0..n).map(|k| g[i * n + k] * g[j * n + k]).sum();
            s + if i == j { n as f64 } else { 0.0 }
        })
        .collect();
    let mut l = a.clone();
    pcsim_core::linalg::cholesky_in_place(&mut l, n).unwrap();
    let rhs = data(n, 22);
    for isa in [Isa::Portable, Isa::best_available()] {
        let (mut x, mut tmp) = (rhs.clone(), vec![0.0; n]);
        cholesky_solve(isa, &l, n, &mut x, &mut tmp);
        for i in 0..n {
            let ax: f64 = (0..n).map(|k| a[i * n + k] * x[k]).sum();
            assert!((ax - rhs[i]).abs() < 1e-12, "{isa:?} row {i}");
        }
        // The same substitutions, a call of the dot kernel per row.
        let (mut y, mut t) = (rhs.clone(), vec![0.0; n]);
        for i in 0..n {
            t[i] = (y[i] - dot(isa, &l[i * n..i * n + i], &t[..i])) / l[i * n + i];
        }
        for i in (0..n).rev() {
            y[i] = (t[i] - dot(isa, &l[i * n + i + 1..(i + 1) * n], &y[i + 1..n])) / l[i * n + i];
        }
        assert!(
            x.iter().zip(&y).all(|(u, v)| u.to_bits() == v.to_bits()),
            "{isa:?}"
        );
    }
}

/// The rows' updates with sixteen outputs held in registers are a row at a time's bytes on
/// both paths (`x_i ← α_j r_ji + x_i`, fused on the x86-64-v3 path, not on the portable
/// one), for lengths with a 16-wide, a 4-wide and a scalar part, and for no rows at all.
#[test]
fn the_rows_updates_are_a_row_at_a_times_bytes() {
    for (n, m) in [(1, 3), (7, 1), (16, 5), (23, 9), (143, 36), (40, 0)] {
        let rows = data(m * n, 31);
        let (ax, ay) = (data(m, 32), data(m, 33));
        for isa in [Isa::Portable, Isa::best_available()] {
            let (mut x, mut y) = (data(n, 34), data(n, 35));
            let (mut x1, mut y1) = (x.clone(), y.clone());
            axpy2_rows(isa, &rows, &ax, &ay, &mut x, &mut y);
            for j in 0..m {
                for i in 0..n {
                    let r = rows[j * n + i];
                    if isa == Isa::Portable {
                        x1[i] += ax[j] * r;
                        y1[i] += ay[j] * r;
                    } else {
                        x1[i] = ax[j].mul_add(r, x1[i]);
                        y1[i] = ay[j].mul_add(r, y1[i]);
                    }
                }
            }
            let same =
                |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(u, v)| u.to_bits() == v.to_bits());
            assert!(same(&x, &x1) && same(&y, &y1), "{isa:?} n {n} m {m}");
        }
    }
}

/// The capacitance matrix by rank-one updates is the entry-by-entry sum's bytes on both paths
/// (the implicit terms' matrix as `ImplicitPoints::new` built it before), for point counts
/// with and without a four-wide part and for no modes at all.
#[test]
fn the_capacitance_updates_are_the_entry_sums_bytes() {
    for (np, n) in [(1, 5), (3, 0), (4, 17), (9, 40), (37, 143)] {
        let rows_t = data(n * np, 51);
        let d: Vec<f64> = data(n, 52).iter().map(|v| 1.5 + v).collect();
        let mut want = vec![0.0; np * np];
        for i in 0..np {
            for j in 0..=i {
                let mut s = 0.0;
                for k in 0..n {
                    s += rows_t[k * np + i] * rows_t[k * np + j] / d[k];
                }
                want[i * np + j] = s;
            }
        }
        for isa in [Isa::Portable, Isa::best_available()] {
            let mut cap = vec![f64::NAN; np * np];
            capacitance(isa, &rows_t, np, &d, &mut cap);
            for i in 0..np {
                for j in 0..=i {
                    let (a, b) = (cap[i * np + j], want[i * np + j]);
                    assert_eq!(a.to_bits(), b.to_bits(), "{isa:?} np {np} n {n} ({i}, {j})");
                }
                assert!(cap[i * np + i + 1..(i + 1) * np].iter().all(|&v| v == 0.0));
            }
        }
    }
}

/// A fold or unfold of two groups in one pass is two passes' bytes, on both paths, with
/// and without a scale, for periods with and without 8- and 4-wide blocks of bins and mode
/// counts with a partial last row.
#[test]
fn two_groups_in_one_pass_are_two_passes_bytes() {
    let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(u, v)| u.to_bits() == v.to_bits());
    for (n, p) in [(5, 2), (37, 6), (61, 13), (143, 8), (250, 60), (1203, 60)] {
        let (q1, q2) = (data(n, 41), data(n, 42));
        let t: Vec<Vec<f64>> = (0..4).map(|i| data(n, 43 + i)).collect();
        let tabs = [&t[0][..], &t[1], &t[2], &t[3]];
        let scale = data(n, 47);
        for isa in [Isa::Portable, Isa::best_available()] {
            let what = format!("{isa:?} n {n} p {p}");
            // Folds.
            let (mut a, mut b) = (vec![9.0; 2 * p], vec![9.0; 2 * p]);
            fold1x2(isa, &q1, tabs, p, [&mut a, &mut b]);
            let (mut a1, mut b1) = (vec![0.0; 2 * p], vec![0.0; 2 * p]);
            fold1(isa, &q1, &t[0], &t[1], p, &mut a1);
            fold1(isa, &q1, &t[2], &t[3], p, &mut b1);
            assert!(same(&a, &a1) && same(&b, &b1), "fold1x2 {what}");
            let (mut a, mut b) = (vec![9.0; 4 * p], vec![9.0; 4 * p]);
            fold2x2(isa, &q1, &q2, tabs, p, [&mut a, &mut b]);
            let (mut a2, mut b2) = (vec![0.0; 4 * p], vec![0.0; 4 * p]);
            fold2(isa, &q1, &q2, &t[0], &t[1], p, &mut a2);
            fold2(isa, &q1, &q2, &t[2], &t[3], p, &mut b2);
            assert!(same(&a, &a2) && same(&b, &b2), "fold2x2 {what}");
            // Unfolds of those bins, onto outputs that already hold values.
            for sc in [&[][..], &scale] {
                let mut o = q2.clone();
                unfold1x2(isa, [&a1, &b1], tabs, p, &mut o, sc);
                let mut o1 = q2.clone();
                unfold1(isa, &a1, &t[0], &t[1], p, &mut o1, sc);
                unfold1(isa, &b1, &t[2], &t[3], p, &mut o1, sc);
                assert!(same(&o, &o1), "unfold1x2 {what} scaled {}", !sc.is_empty());
            }
            let (mut x, mut y) = (q1.clone(), q2.clone());
            unfold2x2(isa, [&a2, &b2], tabs, p, &mut x, &mut y);
            let (mut x1, mut y1) = (q1.clone(), q2.clone());
            unfold2(isa, &a2, &t[0], &t[1], p, &mut x1, &mut y1);
            unfold2(isa, &b2, &t[2], &t[3], p, &mut x1, &mut y1);
            assert!(same(&x, &x1) && same(&y, &y1), "unfold2x2 {what}");
        }
    }
}

#[test]
fn both_instruction_sets_agree_to_rounding() {
    let best = Isa::best_available();
    let (a, b, c) = (data(1203, 1), data(1203, 2), data(1203, 3));
    let d0 = dot(Isa::Portable, &a, &b);
    let d1 = dot(best, &a, &b);
    let exact: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
    assert!((d0 - exact).abs() < 1e-12 && (d1 - exact).abs() < 1e-12);
    let (x0, y0) = dot2(Isa::Portable, &c, &a, &b);
    let (x1, y1) = dot2(best, &c, &a, &b);
    assert!((x0 - x1).abs() < 1e-12 && (y0 - y1).abs() < 1e-12);
    for p in [4usize, 12, 60, 62, 120] {
        let mut o0 = vec![0.0; 4 * p];
        let mut o1 = vec![0.0; 4 * p];
        fold2(Isa::Portable, &a, &b, &c, &a, p, &mut o0);
        fold2(best, &a, &b, &c, &a, p, &mut o1);
        for (u, v) in o0.iter().zip(&o1) {
            assert!((u - v).abs() < 1e-12, "fold2 p={p}");
        }
        let mut s0 = vec![0.0; 2 * p];
        fold1(Isa::Portable, &b, &c, &a, p, &mut s0);
        for r in 0..p {
            assert!(
                (s0[r] - o0[2 * p + r]).abs() < 1e-12 && (s0[p + r] - o0[3 * p + r]).abs() < 1e-12
            );
        }
        let (mut u0, mut v0) = (b.clone(), c.clone());
        let (mut u1, mut v1) = (b.clone(), c.clone());
        unfold2(Isa::Portable, &o0, &a, &c, p, &mut u0, &mut v0);
        unfold2(best, &o0, &a, &c, p, &mut u1, &mut v1);
        for k in 0..a.len() {
            assert!((u0[k] - u1[k]).abs() < 1e-12 && (v0[k] - v1[k]).abs() < 1e-12);
        }
        // unfold1 with a scale equals unfold1 into zeros, then a scaled add.
        let mut w = vec![0.0; a.len()];
        unfold1(best, &o0, &a, &c, p, &mut w, &[]);
        let mut ws = b.clone();
        unfold1(best, &o0, &a, &c, p, &mut ws, &c);
        for k in 0..a.len() {
            assert!((ws[k] - (b[k] + c[k] * w[k])).abs() < 1e-12);
        }
    }
    let n = 37;
    let pm = data(n * n, 9);
    let (x, y) = (data(n, 10), data(n, 11));
    let mut o0 = vec![0.0; 2 * n];
    let mut o1 = vec![0.0; 2 * n];
    project2(Isa::Portable, &pm, n, &x, &y, &mut o0);
    project2(best, &pm, n, &x, &y, &mut o1);
    let mut o4 = vec![0.0; 4 * n];
    project4(best, &pm, n, [&y, &x, &y, &x], &mut o4);
    // A rectangular P (rows × columns, both odd and not multiples of four) on both paths.
    let (rows, cols) = (23, 37);
    for isa in [Isa::Portable, best] {
        let mut o = vec![0.0; 2 * rows];
        project2_rect(isa, &pm, (rows, cols), &x, &y, &mut o);
        for k in 0..rows {
            let ex: f64 = (0..cols).map(|j| pm[k * cols + j] * x[j]).sum();
            let ey: f64 = (0..cols).map(|j| pm[k * cols + j] * y[j]).sum();
            assert!((o[k] - ex).abs() < 1e-12 && (o[rows + k] - ey).abs() < 1e-12);
        }
    }
    for k in 0..n {
        let e: f64 = (0..n).map(|j| pm[k * n + j] * y[j]).sum();
        assert!((o0[n + k] - e).abs() < 1e-12 && (o1[n + k] - e).abs() < 1e-12);
        assert!((o4[k] - e).abs() < 1e-12 && (o4[2 * n + k] - e).abs() < 1e-12);
    }
}
