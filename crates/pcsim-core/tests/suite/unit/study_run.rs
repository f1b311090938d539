//! The unit tests of `study::run` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::analysis::events::{run_errors, AllowedErrors};
use pcsim_core::analysis::record::{simulate_with, DropperOptions, DropperRun, RunOutput};
use pcsim_core::analysis::report::{timeseries_columns, RunSummary};
use pcsim_core::analysis::sensitivity::{sensitivity, SensitivitySpec};
use pcsim_core::compile::{Budget, Setup};
use pcsim_core::error::{CaseError, SimError};
use pcsim_core::input::case::{Case, RangedValue};
use pcsim_core::study::run::push_fixed;
use pcsim_core::study::{Answer, Study, StudyFile, StudyKind};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::time::Instant;

/// The fast fixed-point writer gives `format!`'s bytes: edge cases, and 600 000 values of
/// every magnitude and sign (a seeded generator) at every precision `timeseries.csv` uses and more.
#[test]
fn push_fixed_writes_the_bytes_of_format() {
    let mut cases = vec![
        0.0,
        -0.0,
        -0.00001,
        -0.00005,
        0.00005,
        0.00015,
        1.23455,
        9.99995,
        -1e-300,
        0.5,
        1.5,
        2.5,
        -2.5,
        12_345_678.123_456_79,
        1e17,
        4.5e11,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MAX,
        f64::MIN_POSITIVE,
    ];
    let mut s: u64 = 0x9e37_79b9_7f4a_7c15;
    for _ in 0..200_000 {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let m = (s >> 11) as f64 / (1u64 << 53) as f64;
        let e = ((s & 0xff) as i32 % 24) - 12;
        let sign = if s & 0x100 != 0 { -1.0 } else { 1.0 };
        cases.push(sign * m * 10f64.powi(e));
        // Values on the decimal grid and half-way between its points, the hard cases.
        cases.push(((s >> 20) % 2_000_000) as f64 / 1e4 - 100.0);
        cases.push(((s >> 20) % 2_000_000) as f64 / 1e4 + 0.00005);
    }
    let mut out = Vec::new();
    for &x in &cases {
        for d in [0, 1, 4, 6, 9, 12] {
            out.clear();
            push_fixed(&mut out, x, d);
            assert_eq!(
                std::str::from_utf8(&out).unwrap(),
                format!("{x:.d$}"),
                "{x:e} at {d} decimals"
            );
        }
    }
}
