//! The unit tests of `linalg` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::linalg::*;

#[test]
fn small_inverse_and_cholesky() {
    let a = [4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0];
    let inv = invert_small(&a, 3).unwrap();
    for i in 0..3 {
        for j in 0..3 {
            let s: f64 = (0..3).map(|k| a[i * 3 + k] * inv[k * 3 + j]).sum();
            assert!((s - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
        }
    }
    let mut l = a.to_vec();
    cholesky_in_place(&mut l, 3).unwrap();
    // L Lᵀ = A, with L below the diagonal and Lᵀ mirrored above it.
    for i in 0..3 {
        for j in 0..3 {
            let s: f64 = (0..=i.min(j)).map(|k| l[i * 3 + k] * l[j * 3 + k]).sum();
            assert!((s - a[i * 3 + j]).abs() < 1e-12);
            assert_eq!(l[i * 3 + j], l[j * 3 + i]);
        }
    }
}

#[test]
fn singular_and_indefinite_matrices_are_errors() {
    assert!(invert_small(&[1.0, 2.0, 2.0, 4.0], 2).is_none());
    let mut a = [1.0, 2.0, 2.0, 1.0];
    let e = cholesky_in_place(&mut a, 2).unwrap_err();
    assert_eq!(e.row, 1);
    assert!(e.pivot < 0.0);
}
