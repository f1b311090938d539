//! The real-time window on a line (issue 21, item 7): its set-up (a model per position), and the
//! wall time of a normal step and of a step that moves the window, in HIL mode over the whole
//! line. Noisy wall-clock figures (median and worst); for instructions run it under callgrind:
//!
//! ```sh
//! cargo build --release -p pcsim-core --example line_window_cost
//! target/release/examples/line_window_cost en50318-2018-like-simple 240
//! valgrind --tool=callgrind target/release/examples/line_window_cost en50318-2018-like-simple 240
//! ```

use pcsim_core::presets;
use pcsim_core::session::Coupling;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let preset = args
        .next()
        .unwrap_or_else(|| "en50318-2018-like-simple".into());
    let window_m: f64 = args.next().map_or(240.0, |s| s.parse().expect("window, m"));
    let case = pcsim_core::compile::window_case(&presets::load(&preset).unwrap().0).unwrap();
    let t0 = Instant::now();
    let mut rt = pcsim_core::compile::realtime_window(&case, window_m, Coupling::Hil).unwrap();
    let build_s = t0.elapsed().as_secs_f64();
    let (x0, dt) = (rt.start_position_m(), rt.dt_s());
    let v = case.run.speed_kmh / 3.6;
    let end = rt.model_length_m() - 1.0;
    let (mut normal, mut moving) = (Vec::new(), Vec::new());
    let mut k = 0usize;
    let mut last = 0.0;
    loop {
        let x = x0 + v * dt * k as f64;
        if x > end {
            break;
        }
        rt.set_input(90.0 + 20.0 * (k as f64 * 0.008).sin(), x);
        let moves = rt.moves();
        let t = Instant::now();
        last = rt.step().wire_height_m;
        let us = t.elapsed().as_secs_f64() * 1e6;
        if rt.moves() > moves {
            moving.push(us);
        } else {
            normal.push(us);
        }
        k += 1;
    }
    let med = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        (
            v.get(v.len() / 2).copied().unwrap_or(0.0),
            v.last().copied().unwrap_or(0.0),
        )
    };
    let (n_med, n_max) = med(&mut normal);
    let (m_med, m_max) = med(&mut moving);
    println!(
        "{preset}, window {window_m} m: {} positions, set-up {build_s:.2} s; {} steps: normal median {n_med:.2} µs (worst {n_max:.1}), {} moving steps median {m_med:.1} µs (worst {m_max:.1}); last height {last:e} m",
        rt.positions_m().len(),
        normal.len() + moving.len(),
        moving.len()
    );
}
