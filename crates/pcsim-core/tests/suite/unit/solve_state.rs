//! The unit tests of `solve::state` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::model::Model;
use pcsim_core::solve::kernels::{self, Isa};

#[test]
fn all_finite_finds_any_non_finite_value() {
    for n in 0..11 {
        let v = vec![1.5; n];
        assert!(pcsim_core::solve::state::all_finite(&v));
        for i in 0..n {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut w = v.clone();
                w[i] = bad;
                assert!(
                    !pcsim_core::solve::state::all_finite(&w),
                    "n {n}, index {i}, {bad}"
                );
            }
        }
    }
    assert!(pcsim_core::solve::state::all_finite(&[
        f64::MAX,
        -f64::MAX,
        0.0,
        -0.0,
        1e-310
    ]));
    // Both instruction sets, past the kernel's eight- and four-wide parts.
    for isa in [Isa::Portable, Isa::best_available()] {
        for n in [0, 3, 4, 8, 13, 29] {
            let v = vec![-2.5e300; n];
            assert!(kernels::all_finite(isa, &v), "{isa:?} n {n}");
            for i in 0..n {
                let mut w = v.clone();
                w[i] = f64::INFINITY;
                assert!(!kernels::all_finite(isa, &w), "{isa:?} n {n}, index {i}");
            }
        }
    }
}
