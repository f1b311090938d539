//! The cost of the real-time step contract (issue 18): the same HIL input stepped through the bare
//! window (`RealtimeCatenary`: set the input, step) and through the session (checks, save, step,
//! soundness). Run each under callgrind for instruction counts per step:
//!
//! ```sh
//! cargo build --release -p pcsim-core --example session_cost
//! valgrind --tool=callgrind target/release/examples/session_cost bare 20000
//! valgrind --tool=callgrind target/release/examples/session_cost session 20000
//! ```
//!
//! It prints the last height, so the two runs can be checked to step the same wire.

use pcsim_core::presets;
use pcsim_core::session::{Coupling, RealtimeSession};

fn main() {
    let mut args = std::env::args().skip(1);
    let which = args.next().unwrap_or_else(|| "session".into());
    let n: usize = args.next().map_or(20_000, |s| s.parse().expect("steps"));
    let case = pcsim_core::compile::window_case(&presets::load("syt-7.0-9.8").unwrap().0).unwrap();
    let v = case.run.speed_kmh / 3.6;
    let force = |k: usize| 85.0 + 20.0 * (k as f64 * 0.008).sin();
    let mut last = 0.0;
    if which == "bare" {
        let mut rt = pcsim_core::compile::realtime_window(&case, 215.0, Coupling::Hil).unwrap();
        let (x0, dt) = (rt.start_position_m(), rt.dt_s());
        for k in 0..n {
            rt.set_input(force(k), x0 + v * dt * k as f64);
            last = rt.step().wire_height_m;
        }
    } else {
        let mut rt = RealtimeSession::new(&case, 215.0, Coupling::Hil).unwrap();
        let (x0, dt) = (rt.start_position_m(), rt.dt_s());
        for k in 0..n {
            last = rt
                .step(force(k), x0 + v * dt * k as f64)
                .unwrap()
                .wire_height_m;
        }
    }
    println!("{which}: {n} steps, last height {last:e} m");
}
