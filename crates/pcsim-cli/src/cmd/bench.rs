//! `pcsim bench`: wall time against simulated time on one core, or the step-latency
//! distribution of the real-time window.

use anyhow::{bail, Result};
use clap::Args;
use pcsim_core::input::case::PantographCase;
use pcsim_core::{presets, Case};
use std::time::Instant;

use crate::common::run_with_progress;

#[derive(Args)]
pub struct BenchArgs {
    /// Preset to time. `en50318-2002` is extended to the benchmark set-up (30 spans, two
    /// pantographs 200 m apart).
    #[arg(long)]
    preset: Option<String>,
    /// Time the real-time window step instead (default preset: syt-7.0-9.8).
    #[arg(long)]
    realtime: bool,
    /// Window length for --realtime, m.
    #[arg(long, default_value_t = 215.0)]
    window: f64,
    /// Steps to time for --realtime.
    #[arg(long, default_value_t = 1_000_000)]
    steps: usize,
    /// Coupling for --realtime: hil or sil.
    #[arg(long, default_value = "hil")]
    coupling: String,
    /// Train speed, km/h (default: 320 for the full model, the preset's for --realtime).
    #[arg(long)]
    speed: Option<f64>,
    /// Modes per wire (full model).
    #[arg(long, default_value_t = 1200)]
    modes: usize,
    /// Spans (60 m each), for the en50318-2002 extension.
    #[arg(long, default_value_t = 30)]
    spans: usize,
    /// Time step, s.
    #[arg(long)]
    dt: Option<f64>,
}

/// The benchmark case: the en50318-2002 catenary over `spans` spans with two pantographs
/// 200 m apart.
pub fn bench_case(speed_kmh: f64, modes: usize, spans: usize, dt: Option<f64>) -> Result<Case> {
    let mut c = presets::load("en50318-2002")?.0;
    c.catenary.spans = spans;
    let l = spans as f64 * c.catenary.span_m;
    c.run.modes = Some(modes);
    c.run.modes_per_m = None;
    c.run.speed_kmh = speed_kmh;
    if let Some(dt) = dt {
        c.run.dt_s = dt;
    }
    let mut trailing = c.pantographs[0].clone();
    if let PantographCase::Lumped { name, offset_m, .. } = &mut trailing {
        *name = "trailing".into();
        *offset_m = 200.0;
    }
    c.pantographs.push(trailing);
    c.run.start_m = 260.0;
    c.run.end_m = l - 240.0;
    c.run.analysis_m = [480.0, l - 300.0];
    Ok(c)
}

pub fn bench(a: BenchArgs, quiet: bool) -> Result<i32> {
    if a.realtime {
        return bench_realtime(&a);
    }
    let preset = a
        .preset
        .clone()
        .unwrap_or_else(|| "stitched-2018-like".into());
    let speed = a.speed.unwrap_or(320.0);
    let case = if preset == "en50318-2002" {
        bench_case(speed, a.modes, a.spans, a.dt)?
    } else {
        let mut c = presets::load(&preset)?.0;
        c.run.speed_kmh = speed;
        c.run.modes = Some(a.modes);
        c.run.modes_per_m = None;
        if let Some(dt) = a.dt {
            c.run.dt_s = dt;
        }
        c
    };
    let (out, wall, _) = run_with_progress(&case, "bench", quiet)?;
    let sim = out.simulated_time_s();
    println!(
        "bench `{}`: {} spans x {:.0} m, {} modes/wire, {} pantograph(s), {:.0} km/h, dt {} s",
        preset,
        case.catenary.spans,
        case.catenary.span_m,
        out.n_modes,
        out.pantographs.len(),
        speed,
        case.run.dt_s
    );
    println!(
        "  simulated {sim:.2} s in {wall:.3} s wall on one core: {:.1}x faster than real time",
        sim / wall
    );
    println!(
        "  {:.2} µs per step ({} steps)",
        wall / out.time_s.len() as f64 * 1e6,
        out.time_s.len()
    );
    Ok(0)
}

/// Step-latency distribution of the real-time window catenary on one core.
fn bench_realtime(a: &BenchArgs) -> Result<i32> {
    use pcsim_core::solve::realtime::{Coupling, RealtimeCatenary};
    let preset = a.preset.clone().unwrap_or_else(|| "syt-7.0-9.8".into());
    let mut case = presets::load(&preset)?.0;
    case.pantographs.truncate(1);
    if let Some(dt) = a.dt {
        case.run.dt_s = dt;
    }
    let speed = a.speed.unwrap_or(case.run.speed_kmh);
    case.run.speed_kmh = speed;
    let coupling = match a.coupling.as_str() {
        "hil" => Coupling::Hil,
        "sil" => Coupling::Sil,
        other => bail!("--coupling `{other}`: use hil or sil"),
    };
    let mut rt = RealtimeCatenary::new(&case, a.window, coupling)?;
    let dt = rt.dt_s();
    let v = speed / 3.6;
    let x0 = case.run.start_m;
    let mut ns = vec![0u64; a.steps];
    let mut move_ns = Vec::with_capacity(a.steps / 100 + 16);
    let mut guard = 0.0;
    let t_all = Instant::now();
    for (k, slot) in ns.iter_mut().enumerate() {
        let t = k as f64 * dt;
        rt.set_input(85.0 + 15.0 * (7.3 * t).sin(), x0 + v * t);
        let moves = rt.moves();
        let t0 = Instant::now();
        let o = rt.step();
        *slot = t0.elapsed().as_nanos() as u64;
        if rt.moves() != moves && move_ns.len() < move_ns.capacity() {
            move_ns.push(*slot);
        }
        guard += o.wire_height_m;
    }
    move_ns.sort_unstable();
    let wall = t_all.elapsed().as_secs_f64();
    if !guard.is_finite() {
        bail!("the real-time run produced non-finite heights");
    }
    let mut sorted = ns.clone();
    sorted.sort_unstable();
    let q = |p: f64| {
        sorted[((p * (sorted.len() - 1) as f64).round() as usize).min(sorted.len() - 1)] as f64
            / 1e3
    };
    println!(
        "bench --realtime `{preset}`: window {} m, {} modes/wire, {:?}, dt {} s, {} steps ({} window moves), {:.0} km/h",
        a.window,
        rt.n_modes(),
        coupling,
        dt,
        a.steps,
        rt.moves(),
        speed
    );
    println!(
        "  step latency: median {:.2} µs, p99 {:.2} µs, p99.99 {:.2} µs, max {:.2} µs",
        q(0.5),
        q(0.99),
        q(0.9999),
        *sorted.last().unwrap_or(&0) as f64 / 1e3
    );
    if !move_ns.is_empty() {
        println!(
            "  steps that move the window: median {:.2} µs, max {:.2} µs ({} moves)",
            move_ns[move_ns.len() / 2] as f64 / 1e3,
            *move_ns.last().unwrap_or(&0) as f64 / 1e3,
            move_ns.len()
        );
    }
    println!(
        "  real-time factor {:.0}x at the median ({} s simulated in {wall:.2} s)",
        dt / (q(0.5) * 1e-6),
        a.steps as f64 * dt
    );
    Ok(0)
}
