//! The unit tests of `analysis::fatigue` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::analysis::fatigue::*;
use pcsim_core::error::SimError;
use pcsim_core::model::elements::dropper::Droppers;
use pcsim_core::model::Attach;
use pcsim_core::solve::compiled::CompiledModel;
use pcsim_core::solve::run::Observer;
use pcsim_core::solve::state::State;
use pcsim_core::solve::workspace::Workspace;

/// A constant-amplitude sine of `n` periods between 100 and 300 N about 200 N: the standard's
/// procedure counts its `2n − 1` ranges of 200 N as half cycles (each contains the starting
/// point left in the deque) and the rise from and fall to 200 N as two halves of 100 N;
/// Miner's damage is then exactly `(2n − 1)/2 / N(200 N) + 1 / N(100 N)`.
#[test]
fn a_constant_amplitude_record_gives_its_cycles_and_miners_damage() {
    let n = 50;
    let x: Vec<f64> = (0..=n * 40)
        .map(|k| 200.0 + 100.0 * (2.0 * std::f64::consts::PI * k as f64 / 40.0).sin())
        .collect();
    let c = rainflow(&x);
    let count = |r: f64| -> f64 {
        c.iter()
            .filter(|c| (c.range - r).abs() < 1e-9)
            .map(|c| c.count)
            .sum()
    };
    assert_eq!(count(200.0), (2 * n - 1) as f64 / 2.0);
    assert_eq!(count(100.0), 1.0);
    assert_eq!(c.len(), 2 * n + 1);
    let sn = SnCurve {
        m: 5.0,
        stress_range_pa: 100e6,
        cycles: 2e6,
        area_m2: 10e-6,
    };
    // 200 N on 10 mm² is 20 MPa: N = 2e6 · 5⁵; 100 N: 2e6 · 10⁵.
    let want = (2 * n - 1) as f64 / 2.0 / (2e6 * 5f64.powi(5)) + 1.0 / (2e6 * 1e5);
    let d = sn.damage(&c);
    assert!((d - want).abs() < 1e-9 * want, "{d} vs {want}");
    assert_eq!(sn.cycles_to_failure(0.0), f64::INFINITY);
}

/// Streaming the reversals gives those of the whole series, plateaus and ties included.
#[test]
fn reversals_of_plateaus_and_ends() {
    let x = [1.0, 1.0, 2.0, 2.0, 2.0, 0.0, 0.0, 3.0, 3.0];
    assert_eq!(reversals(&x), vec![(0, 1.0), (4, 2.0), (6, 0.0), (8, 3.0)]);
    assert_eq!(reversals(&[]), vec![]);
    assert_eq!(reversals(&[4.0]), vec![(0, 4.0)]);
    assert_eq!(reversals(&[4.0, 5.0]), vec![(0, 4.0), (1, 5.0)]);
}
