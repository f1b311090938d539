//! `pcsim bench`: wall time against simulated time on one core, or the step-latency
//! distribution of the real-time window.

use anyhow::{bail, Result};
use clap::Args;
use pcsim_core::presets;
use std::time::Instant;

use crate::common::{apply, length, run_with_progress_quietly, Ctx, Override};

/// Without `--realtime`: the full model of a preset over its whole run, on one core. With
/// `--realtime`: the step latency of the real-time window.
#[derive(Args)]
pub struct BenchArgs {
    /// Preset to time [default: stitched-2018-like; with --realtime: syt-7.0-9.8].
    /// `en50318-2002` is extended to the benchmark set-up (30 spans, two pantographs 200 m apart).
    #[arg(long)]
    preset: Option<String>,
    /// Time the real-time window step instead of the full model.
    #[arg(long)]
    realtime: bool,
    /// Train speed: km/h, or with a unit [default: 320 km/h; with --realtime: the preset's].
    #[arg(long, value_name = "KM/H")]
    speed: Option<String>,
    /// Time step: s, or with a unit (1ms) [default: the preset's].
    #[arg(long, value_name = "S")]
    dt: Option<String>,
    /// Full model only: modes per wire [default: 1200].
    #[arg(long)]
    modes: Option<usize>,
    /// Full model with the en50318-2002 extension only: spans of 60 m [default: 30].
    #[arg(long)]
    spans: Option<usize>,
    /// --realtime only: window length, m or with a unit [default: 215 m].
    #[arg(long, value_name = "M")]
    window: Option<String>,
    /// --realtime only: steps to time [default: 1000000].
    #[arg(long)]
    steps: Option<usize>,
    /// --realtime only: coupling, hil or sil [default: hil].
    #[arg(long)]
    coupling: Option<String>,
    /// Runs to time; the report gives their median, minimum and maximum.
    #[arg(long, default_value_t = 5)]
    repeat: usize,
    /// Full model only: threads of the run (its per-group work split between basis groups;
    /// the same output bytes) [default: 1].
    #[arg(long, default_value_t = 1)]
    threads: usize,
}

/// Median, minimum and maximum of a non-empty list.
fn spread(v: &[f64]) -> (f64, f64, f64) {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    let med = if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    };
    (med, s[0], s[n - 1])
}

pub fn bench(a: BenchArgs, ctx: &Ctx) -> Result<i32> {
    if a.repeat == 0 || a.repeat > 1000 {
        bail!("--repeat {}: time between 1 and 1000 runs", a.repeat);
    }
    if a.realtime {
        for (flag, given) in [
            ("--modes", a.modes.is_some()),
            ("--spans", a.spans.is_some()),
            ("--threads", a.threads != 1),
        ] {
            if given {
                bail!("{flag} applies to the full model only, not to --realtime");
            }
        }
        return bench_realtime(&a, ctx);
    }
    for (flag, given) in [
        ("--window", a.window.is_some()),
        ("--steps", a.steps.is_some()),
        ("--coupling", a.coupling.is_some()),
    ] {
        if given {
            bail!("{flag} applies to --realtime only");
        }
    }
    let preset = a
        .preset
        .clone()
        .unwrap_or_else(|| "stitched-2018-like".into());
    let mut overrides = Vec::new();
    if let Some(v) = &a.speed {
        overrides.push(Override::speed(v)?);
    }
    if let Some(dt) = &a.dt {
        overrides.push(Override::dt(dt)?);
    }
    let modes = a.modes.unwrap_or(1200);
    let case = if preset == "en50318-2002" {
        presets::benchmark_case(320.0, modes, a.spans.unwrap_or(30))?
    } else {
        if a.spans.is_some() {
            bail!("--spans applies to the en50318-2002 benchmark extension only (preset `{preset}` keeps its spans)");
        }
        let mut c = presets::load(&preset)?.0;
        c.run.speed_kmh = 320.0;
        c.run.modes = Some(modes);
        c.run.modes_per_m = None;
        c
    };
    let case = apply(&case, &overrides)?;
    let ctx = &Ctx {
        threads: crate::common::threads_flag(a.threads, false)?,
        ..*ctx
    };
    let speed = case.run.speed_kmh;
    let mut walls = Vec::with_capacity(a.repeat);
    let mut last = None;
    for i in 0..a.repeat {
        let (out, wall, _) = run_with_progress_quietly(&case, &overrides, "bench", ctx, i > 0)?;
        walls.push(wall);
        last = Some(out);
    }
    let out = last.expect("at least one run");
    let sim = out.simulated_time_s();
    let steps = out.time_s.len();
    println!(
        "bench `{}`: {} spans x {:.0} m, {} modes/wire, {} pantograph(s), {:.0} km/h, dt {} s, kernels {}, {} run(s) on {} thread(s)",
        preset,
        case.catenary.spans,
        case.catenary.span_m,
        out.n_modes,
        out.pantographs.len(),
        speed,
        case.run.dt_s,
        pcsim_core::solve::Isa::detect().name(),
        a.repeat,
        out.threads
    );
    let (med, lo, hi) = spread(&walls);
    println!(
        "  wall {med:.3} s median (min {lo:.3}, max {hi:.3}) for {sim:.2} s simulated: {:.1}x faster than real time at the median (min {:.1}x, max {:.1}x)",
        sim / med,
        sim / hi,
        sim / lo
    );
    println!(
        "  {:.2} µs per step at the median ({steps} steps)",
        med / steps as f64 * 1e6
    );
    Ok(0)
}

/// A fixed amount of dependent arithmetic: the noise floor's workload.
fn spin(iters: u64) -> f64 {
    let mut x = 1.0f64;
    for _ in 0..iters {
        x = std::hint::black_box(x * 0.999_999_9 + 1e-9);
    }
    x
}

/// Latency percentiles (µs) of a list of nanosecond timings, sorted in place.
fn percentiles(ns: &mut [u64]) -> [f64; 4] {
    ns.sort_unstable();
    let q =
        |p: f64| ns[((p * (ns.len() - 1) as f64).round() as usize).min(ns.len() - 1)] as f64 / 1e3;
    [
        q(0.5),
        q(0.99),
        q(0.9999),
        *ns.last().unwrap_or(&0) as f64 / 1e3,
    ]
}

/// The machine's own noise: `steps` timings of a fixed workload as long as the median step
/// (`med_ns`). Its tail is what the operating system and the host add to any step.
fn noise_floor(med_ns: f64, steps: usize) {
    let probe = 20_000u64;
    let t0 = Instant::now();
    std::hint::black_box(spin(probe));
    let per_iter = (t0.elapsed().as_nanos() as f64 / probe as f64).max(0.01);
    let iters = ((med_ns / per_iter).round() as u64).max(1);
    let mut floor = vec![0u64; steps];
    for slot in floor.iter_mut() {
        let t0 = Instant::now();
        std::hint::black_box(spin(iters));
        *slot = t0.elapsed().as_nanos() as u64;
    }
    let f = percentiles(&mut floor);
    println!(
        "  noise floor: a fixed workload of {:.2} µs median, timed {steps} times, has p99.99 {:.2} µs and max {:.2} µs",
        f[0], f[2], f[3]
    );
}

/// The real-time bench's table: each latency's median over the runs, with their spread, and the
/// real-time factor (`runs`: per run, [median, p99, p99.99, max] of all steps, then median and max
/// of the moving steps, µs).
fn print_latencies(
    header: &str,
    runs: &[[f64; 6]],
    n_moves: usize,
    steps: usize,
    dt: f64,
    wall: f64,
) {
    println!("{header}");
    let col = |i: usize| spread(&runs.iter().map(|r| r[i]).collect::<Vec<_>>());
    let show = |name: &str, i: usize| {
        let (m, lo, hi) = col(i);
        println!("  {name:<22} {m:8.2} µs  (runs: {lo:.2} – {hi:.2})");
    };
    show("step, median", 0);
    show("step, p99", 1);
    show("step, p99.99", 2);
    show("step, max", 3);
    if n_moves > 0 {
        show("moving step, median", 4);
        show("moving step, max", 5);
    }
    noise_floor(col(0).0 * 1e3, steps);
    println!(
        "  real-time factor {:.0}x at the median ({} s simulated per run; last run {wall:.2} s wall)",
        dt / (col(0).0 * 1e-6),
        steps as f64 * dt
    );
}

/// Step-latency distribution of the real-time window catenary on one core, each step under the
/// whole step contract (`RealtimeSession::step`: input checks, save, step, soundness), as a rig
/// pays it.
fn bench_realtime(a: &BenchArgs, ctx: &Ctx) -> Result<i32> {
    use pcsim_core::compile::budget::check_len;
    use pcsim_core::solve::realtime::Coupling;
    let preset = a.preset.clone().unwrap_or_else(|| "syt-7.0-9.8".into());
    let case = pcsim_core::compile::window_case(&presets::load(&preset)?.0)?;
    let mut overrides = Vec::new();
    if let Some(v) = &a.speed {
        overrides.push(Override::speed(v)?);
    }
    if let Some(dt) = &a.dt {
        overrides.push(Override::dt(dt)?);
    }
    let case = apply(&case, &overrides)?;
    let speed = case.run.speed_kmh;
    let steps = a.steps.unwrap_or(1_000_000);
    if steps == 0 {
        bail!("--steps 0: time at least 1 step");
    }
    check_len(&ctx.budget, "--steps", steps, 2.0 * steps as f64)?;
    let window = match &a.window {
        Some(w) => length("--window", w)?,
        None => 215.0,
    };
    let coupling = match a.coupling.as_deref().unwrap_or("hil") {
        "hil" => Coupling::Hil,
        "sil" => Coupling::Sil,
        other => bail!("--coupling `{other}`: use hil or sil"),
    };
    crate::common::setup(&case, &overrides, ctx)?;
    let v = speed / 3.6;
    let x0 = case.run.start_m;
    let mut ns = vec![0u64; steps];
    // Per run: [median, p99, p99.99, max] of all steps, then median and max of the moving steps.
    let mut runs: Vec<[f64; 6]> = Vec::with_capacity(a.repeat);
    let mut header = String::new();
    let mut n_moves = 0;
    let mut wall = 0.0;
    for _ in 0..a.repeat {
        let mut rt = pcsim_core::session::RealtimeSession::new(&case, window, coupling)?;
        let dt = rt.dt_s();
        // The catenary ends: a run longer than one pass returns to the start state (untimed)
        // and drives the track again.
        let start = rt.state([0.0; 4]);
        let end_m = rt.model_length_m();
        let (mut pass_k, mut moves_before, mut passes) = (0usize, 0usize, 1);
        let mut move_ns = Vec::with_capacity(steps / 100 + 16);
        let mut guard = 0.0;
        let t_all = Instant::now();
        for (k, slot) in ns.iter_mut().enumerate() {
            if x0 + v * (pass_k as f64 * dt) > end_m {
                moves_before += rt.moves();
                rt.restore(&start).map_err(anyhow::Error::msg)?;
                (pass_k, passes) = (0, passes + 1);
            }
            let t = pass_k as f64 * dt;
            pass_k += 1;
            let moves = rt.moves();
            let t0 = Instant::now();
            let o = rt.step(85.0 + 15.0 * (7.3 * t).sin(), x0 + v * t);
            *slot = t0.elapsed().as_nanos() as u64;
            let o = o.map_err(|r| anyhow::anyhow!("step {k} was refused: {r}"))?;
            if rt.moves() != moves && move_ns.len() < move_ns.capacity() {
                move_ns.push(*slot);
            }
            guard += o.wire_height_m;
        }
        wall = t_all.elapsed().as_secs_f64();
        if !guard.is_finite() {
            bail!("the real-time run produced non-finite heights");
        }
        let p = percentiles(&mut ns);
        let mv = if move_ns.is_empty() {
            [0.0; 4]
        } else {
            percentiles(&mut move_ns)
        };
        runs.push([p[0], p[1], p[2], p[3], mv[0], mv[3]]);
        n_moves = move_ns.len();
        header = format!(
            "bench --realtime `{preset}`: window {} m, {} modes/wire, {:?} coupling, dt {} s, {:.0} km/h, kernels {}, {} run(s) of {} steps ({} window moves and {passes} pass(es) over the {end_m} m catenary each) on one core, each under the step contract",
            window,
            rt.n_modes(),
            coupling,
            dt,
            speed,
            pcsim_core::solve::Isa::detect().name(),
            a.repeat,
            steps,
            moves_before + rt.moves(),
        );
    }
    print_latencies(&header, &runs, n_moves, steps, case.run.dt_s, wall);
    Ok(0)
}
