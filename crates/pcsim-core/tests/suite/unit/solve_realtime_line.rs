//! The unit tests of `solve::realtime::line` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::error::CaseError;
use pcsim_core::model::ModelBuilder;
use pcsim_core::model::StaticShape;
use pcsim_core::solve::integrator::Integrator;
use pcsim_core::solve::kernels::Isa;
use pcsim_core::solve::plan::Plan;
use pcsim_core::solve::realtime::{basis_projection, line_origins, MAX_LINE_POSITIONS};
use pcsim_core::solve::state::State;
use pcsim_core::solve::workspace::Workspace;

/// A line's window takes its positions at supports, each next one the furthest within half a
/// window ahead; a window that would take more than [`MAX_LINE_POSITIONS`] positions is
/// refused, naming the window (the models are all built before the first step).
#[test]
pub(super) fn a_lines_window_positions_and_their_bound() {
    let line = |spans: usize| {
        let (mut m, _) =
            ModelBuilder::single_wire(60.0 * spans as f64, 4, 1.35, 20_000.0, 0.0).build();
        m.supports_m = (0..=spans).map(|k| 60.0 * k as f64).collect();
        m
    };
    // 240 m: moves of two 60 m spans (the furthest support within 120 m), from the support
    // at or behind the start less half a window, until the window reaches the end.
    let o = line_origins(&line(20), 240.0, 400.0).unwrap();
    assert_eq!(o.first(), Some(&240.0));
    assert!(o.windows(2).all(|w| w[1] - w[0] == 120.0), "{o:?}");
    assert!(o.last().unwrap() + 240.0 >= 1200.0);
    // A window no longer than a span cannot move by whole spans.
    let e = line_origins(&line(20), 60.0, 400.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("window_m") && e.contains("longest span"), "{e}");
    // 4 001 positions would be needed here.
    let e = line_origins(&line(4100), 100.0, 0.0)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("window_m") && e.contains("2000 positions"),
        "{e}"
    );
}
