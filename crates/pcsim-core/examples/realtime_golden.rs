//! Replay the scripted real-time input (`data/golden/realtime/script.csv`) through the core's
//! real-time session and write `expected.csv`: for each row its status (`ok` or the refusal's
//! code) and, for a step taken, the time, the contact-wire height and its velocity. Every front
//! end (both FMUs, the C API, Python, `pcsim hil`) is tested against this file.
//!
//! ```sh
//! cargo run --release -p pcsim-core --example realtime_golden -- data/golden/realtime
//! ```
//!
//! The files `before_*.csv` beside it were made by this example's earlier form, before issue 18
//! (see the README there). Values are written in Rust's shortest round-trip form, so they read
//! back bit for bit.

use pcsim_core::presets;
use pcsim_core::session::{Coupling, RealtimeSession};
use std::fmt::Write as _;

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/golden/realtime".into());
    let text = std::fs::read_to_string(format!("{dir}/script.csv")).expect("script.csv");
    let (case, _) = presets::load("syt-7.0-9.8").unwrap();
    let mut rt = RealtimeSession::new(&case, 215.0, Coupling::Hil).unwrap();
    let x0 = rt.start_position_m();
    let mut s = String::from("row,status,time_s,wire_height_m,wire_velocity_m_s\n");
    for (k, l) in text.lines().skip(1).enumerate() {
        let v: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
        match rt.step(v[1], x0 + v[2]) {
            Ok(o) => writeln!(
                s,
                "{k},ok,{:?},{:?},{:?}",
                o.time_s, o.wire_height_m, o.wire_velocity_m_s
            ),
            Err(e) => writeln!(s, "{k},{},,,", e.code()),
        }
        .unwrap();
    }
    std::fs::write(format!("{dir}/expected.csv"), s).unwrap();
    println!("{dir}/expected.csv: {} window moves", rt.moves());
}
