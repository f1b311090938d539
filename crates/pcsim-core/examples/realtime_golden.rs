//! Replay the scripted real-time input (`data/golden/realtime/script.csv`) through the core's
//! real-time window, as each front end did before issue 18, and write what each gave:
//!
//! - `before_capi.csv`: the C API and Python (`check_input`, then `step`; nothing else);
//! - `before_fmu.csv`: the FMU (`check_input`, save, step, soundness, roll back).
//!
//! ```sh
//! cargo run --release -p pcsim-core --example realtime_golden -- data/golden/realtime
//! ```
//!
//! Values are written in Rust's shortest round-trip form, so they read back bit for bit.

use pcsim_core::presets;
use pcsim_core::solve::realtime::{Coupling, RealtimeCatenary};
use std::fmt::Write as _;

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/golden/realtime".into());
    let text = std::fs::read_to_string(format!("{dir}/script.csv")).expect("script.csv");
    let rows: Vec<[f64; 3]> = text
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let (mut case, _) = presets::load("syt-7.0-9.8").unwrap();
    case.pantographs.truncate(1);
    let x0 = case.run.start_m;
    for fmu in [false, true] {
        let mut rt = RealtimeCatenary::new(&case, 215.0, Coupling::Hil).unwrap();
        let mut snap = rt.snapshot();
        let dt = rt.dt_s();
        let mut s = String::from("row,status,time_s,wire_height_m,wire_velocity_m_s\n");
        for (k, r) in rows.iter().enumerate() {
            let x = x0 + r[2];
            let elapsed = if k == 0 { f64::INFINITY } else { dt };
            let status = match rt.check_input(r[1], x, elapsed) {
                Err(_) => "refused",
                Ok(()) => {
                    if fmu {
                        rt.save(&mut snap);
                    }
                    rt.set_input(r[1], x);
                    let o = rt.step();
                    if fmu && !(rt.state_is_sound() && o.wire_height_m.is_finite()) {
                        rt.restore(&snap);
                        "rolled_back"
                    } else {
                        let _ = writeln!(
                            s,
                            "{k},ok,{:?},{:?},{:?}",
                            o.time_s, o.wire_height_m, o.wire_velocity_m_s
                        );
                        continue;
                    }
                }
            };
            let _ = writeln!(s, "{k},{status},,,");
        }
        let name = if fmu { "before_fmu.csv" } else { "before_capi.csv" };
        std::fs::write(format!("{dir}/{name}"), s).unwrap();
        println!("{dir}/{name}: {} rows, {} window moves", rows.len(), rt.moves());
    }
}
