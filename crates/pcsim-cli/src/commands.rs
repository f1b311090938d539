//! The subcommands.

use anyhow::{bail, Context, Result};
use clap::Args;
use pcsim_core::case::{Case, PantographCase};
use pcsim_core::model::Model;
use pcsim_core::sim::{simulate, RunOutput};
use pcsim_core::validation::{compare, target_cases, CaseRows};
use pcsim_core::{presets, SimError};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

use crate::output::{write_run, Summary};
use crate::progress::bar;

#[derive(Args)]
pub struct RunArgs {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name (see `pcsim presets`).
    #[arg(long)]
    preset: Option<String>,
    /// Override the train speed, km/h.
    #[arg(long)]
    speed: Option<f64>,
    /// Override the contact-wire tension, kN.
    #[arg(long)]
    tension: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Also draw the plots (SVG and PNG) into the output directory.
    #[arg(long)]
    plot: bool,
}

#[derive(Args)]
pub struct PlotArgs {
    /// Output directory of a finished `pcsim run`.
    dir: PathBuf,
}

#[derive(Args)]
pub struct ValidateArgs {
    /// Validation to run: en50318-2002 or seed-table1.
    #[arg(default_value = "en50318-2002")]
    name: String,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Exit with status 1 when a row fails.
    #[arg(long)]
    strict: bool,
}

#[derive(Args)]
pub struct PresetsArgs {
    /// `show NAME` prints a preset as an editable TOML case.
    action: Option<String>,
    name: Option<String>,
}

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
    /// Train speed, km/h.
    #[arg(long, default_value_t = 320.0)]
    speed: f64,
    /// Modes per wire.
    #[arg(long, default_value_t = 1200)]
    modes: usize,
    /// Spans (60 m each), for the en50318-2002 extension.
    #[arg(long, default_value_t = 30)]
    spans: usize,
    /// Time step, s.
    #[arg(long)]
    dt: Option<f64>,
}

/// Load a case from a file or a preset.
pub fn load_case(path: Option<&PathBuf>, preset: Option<&str>) -> Result<Case> {
    match (path, preset) {
        (Some(p), None) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("cannot read case file '{}'", p.display()))?;
            let (case, _) = Case::from_toml_str(&text)
                .with_context(|| format!("in case file '{}'", p.display()))?;
            Ok(case)
        }
        (None, Some(name)) => Ok(presets::load(name)?.0),
        (Some(_), Some(_)) => bail!("give a case file or --preset, not both"),
        (None, None) => bail!("give a case file or --preset NAME (see `pcsim presets`)"),
    }
}

fn run_model(case: &Case, label: &str, quiet: bool) -> Result<(RunOutput, f64, Vec<String>)> {
    let (model, warnings) = Model::from_case(case)?;
    let warnings: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let pb = bar(label, quiet);
    let t0 = Instant::now();
    let out = simulate(model, &mut |f| {
        pb.set_position((f * 1000.0) as u64);
        true
    })
    .map_err(|e: SimError| anyhow::anyhow!(e))?;
    pb.finish_and_clear();
    Ok((out, t0.elapsed().as_secs_f64(), warnings))
}

pub fn run(a: RunArgs, quiet: bool) -> Result<i32> {
    let mut case = load_case(a.case.as_ref(), a.preset.as_deref())?;
    if let Some(v) = a.speed {
        case.run.speed_kmh = v;
    }
    if let Some(t) = a.tension {
        case.catenary.contact_wire.tension_n = t * 1e3;
    }
    let (out, wall, warnings) = run_model(&case, "run", quiet)?;
    let summary = Summary::new(&case, &out, wall, warnings);
    write_run(&a.out, &out, &summary)?;
    if a.plot {
        let data = crate::plots::PlotData {
            case_name: summary.case_name.clone(),
            speed_kmh: summary.speed_kmh,
            span_m: Some(case.catenary.span_m),
            analysis_m: out.analysis_m,
            traces: out
                .pantographs
                .iter()
                .map(|p| crate::plots::Trace {
                    name: p.name.clone(),
                    position_m: p.position_m.clone(),
                    force_n: p.force_n.clone(),
                    force_filtered_n: p.force_filtered_n.clone(),
                    height_m: p.wire_height_m.clone(),
                })
                .collect(),
        };
        let files = crate::plots::draw_all(&a.out, &data)?;
        crate::plots::report(&files);
    }
    println!(
        "{} at {:.0} km/h: {:.2} s simulated in {:.2} s wall ({:.1}x real time), {} modes/wire",
        if case.meta.name.is_empty() {
            "case"
        } else {
            &case.meta.name
        },
        case.run.speed_kmh,
        out.simulated_time_s(),
        wall,
        out.simulated_time_s() / wall,
        out.n_modes
    );
    for p in &out.pantographs {
        match &p.stats {
            Some(s) => println!(
                "  {:<10} Fm {:6.1} N  σ {:5.1} N  (0-5 Hz {:4.1}, 5-20 Hz {:4.1})  max {:6.1}  min {:6.1}  uplift@support {:5.1} mm  loss {:.2} %",
                p.name, s.mean_n, s.std_n, s.std_0_5hz_n, s.std_5_20hz_n, s.actual_max_n, s.actual_min_n, s.max_uplift_at_support_mm, s.loss_of_contact_percent
            ),
            None => println!("  {:<10} did not cross the analysis section", p.name),
        }
    }
    println!(
        "wrote {}/summary.json and {}/timeseries.csv",
        a.out.display(),
        a.out.display()
    );
    Ok(0)
}

#[derive(Serialize)]
struct ValidationJson {
    all_pass: bool,
    cases: Vec<CaseRows>,
}

pub fn plot(a: PlotArgs) -> Result<i32> {
    let data = crate::plots::read_run(&a.dir)?;
    let files = crate::plots::draw_all(&a.dir, &data)?;
    crate::plots::report(&files);
    Ok(0)
}

pub fn validate(a: ValidateArgs, quiet: bool) -> Result<i32> {
    let (preset, table, title) = match a.name.as_str() {
        "en50318-2002" => ("en50318-2002", "en50318_2002", "EN 50318:2002 validation"),
        "seed-table1" => (
            "stitched-2018-like",
            "seed_table1",
            "The seed paper's Table 1 (ranges quoted there from EN 50318:2018; our model is built from public data, not the standard's)",
        ),
        other => bail!("unknown validation `{other}` (available: en50318-2002, seed-table1)"),
    };
    let base = presets::load(preset)?.0;
    let targets = target_cases(table)?;
    let mut speeds: Vec<f64> = targets.iter().map(|t| t.speed_kmh).collect();
    speeds.sort_by(f64::total_cmp);
    speeds.dedup();
    // Each speed runs once, single-threaded and deterministically; the speeds run side by side.
    let runs: Vec<Result<(RunOutput, f64)>> = std::thread::scope(|s| {
        let handles: Vec<_> = speeds
            .iter()
            .map(|&v| {
                let mut case = base.clone();
                case.run.speed_kmh = v;
                let label = format!("{v} km/h");
                s.spawn(move || -> Result<(RunOutput, f64)> {
                    let (out, wall, _) = run_model(&case, &label, quiet)?;
                    Ok((out, wall))
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err(anyhow::anyhow!("worker panicked")))
            })
            .collect()
    });
    let runs: Vec<(RunOutput, f64)> = runs.into_iter().collect::<Result<_>>()?;
    let mut cases = Vec::new();
    for t in &targets {
        let k = speeds
            .iter()
            .position(|&v| v == t.speed_kmh)
            .context("speed")?;
        let (out, wall) = &runs[k];
        let p = match &t.pantograph {
            Some(name) => out
                .pantographs
                .iter()
                .find(|p| &p.name == name)
                .with_context(|| format!("preset has no pantograph named `{name}`"))?,
            None => &out.pantographs[0],
        };
        let stats = p
            .stats
            .with_context(|| format!("{} pantograph did not cross the analysis section", p.name))?;
        cases.push((compare(&stats, t), *wall, out.simulated_time_s()));
    }
    let all_pass = cases.iter().all(|(c, _, _)| c.rows.iter().all(|r| r.pass));
    if a.json {
        let js = ValidationJson {
            all_pass,
            cases: cases.into_iter().map(|c| c.0).collect(),
        };
        println!("{}", serde_json::to_string_pretty(&js)?);
    } else {
        println!("{title}, preset `{preset}` (ranges from data/validation-targets.toml)");
        for (c, wall, sim) in &cases {
            let who = c
                .pantograph
                .as_deref()
                .map(|p| format!(", {p} pantograph"))
                .unwrap_or_default();
            println!(
                "\n{} km/h{who}  ({sim:.1} s simulated in {wall:.1} s)",
                c.speed_kmh
            );
            let paper = c.rows.iter().any(|r| r.paper_value.is_some());
            if paper {
                println!(
                    "  {:<26} {:>8} {:>6}  {:>8} {:>6}  {:>14}",
                    "quantity", "pcsim", "", "paper", "", "range"
                );
            } else {
                println!(
                    "  {:<26} {:>8} {:>6}  {:>14}",
                    "quantity", "value", "result", "range"
                );
            }
            for r in &c.rows {
                let mark = |p: bool| if p { "pass" } else { "FAIL" };
                let range = format!("[{}, {}]", r.range[0], r.range[1]);
                match (r.paper_value, r.paper_pass) {
                    (Some(pv), Some(pp)) => {
                        println!(
                            "  {:<26} {:>8.1} {:>6}  {:>8.1} {:>6}  {:>14}",
                            r.quantity,
                            r.value,
                            mark(r.pass),
                            pv,
                            mark(pp),
                            range
                        )
                    }
                    _ => println!(
                        "  {:<26} {:>8.1} {:>6}  {:>14}",
                        r.quantity,
                        r.value,
                        mark(r.pass),
                        range
                    ),
                }
            }
        }
        let n: usize = cases.iter().map(|c| c.0.rows.len()).sum();
        let p: usize = cases
            .iter()
            .map(|c| c.0.rows.iter().filter(|r| r.pass).count())
            .sum();
        let pp: usize = cases
            .iter()
            .map(|c| {
                c.0.rows
                    .iter()
                    .filter(|r| r.paper_pass == Some(true))
                    .count()
            })
            .sum();
        let has_paper = cases
            .iter()
            .any(|c| c.0.rows.iter().any(|r| r.paper_value.is_some()));
        if has_paper {
            println!("\n{p} of {n} rows pass (the paper's own values: {pp} of {n}). See docs/validation.md for the reasons.");
        } else {
            println!("\n{p} of {n} rows pass. Rows out of reach with the public data are explained in docs/validation.md.");
        }
    }
    Ok(if a.strict && !all_pass { 1 } else { 0 })
}

pub fn presets(a: PresetsArgs) -> Result<i32> {
    match (a.action.as_deref(), a.name.as_deref()) {
        (None, _) => {
            for p in presets::PRESETS {
                println!("{:<16} {}", p.name, p.summary);
            }
        }
        (Some("show"), Some(name)) => print!("{}", presets::find(name)?.toml),
        (Some("show"), None) => bail!("usage: pcsim presets show NAME"),
        (Some(other), _) => {
            bail!("unknown action `{other}` (use `pcsim presets` or `pcsim presets show NAME`)")
        }
    }
    Ok(0)
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
    let case = if preset == "en50318-2002" {
        bench_case(a.speed, a.modes, a.spans, a.dt)?
    } else {
        let mut c = presets::load(&preset)?.0;
        c.run.speed_kmh = a.speed;
        c.run.modes = Some(a.modes);
        c.run.modes_per_m = None;
        if let Some(dt) = a.dt {
            c.run.dt_s = dt;
        }
        c
    };
    let (out, wall, _) = run_model(&case, "bench", quiet)?;
    let sim = out.simulated_time_s();
    println!(
        "bench `{}`: {} spans x {:.0} m, {} modes/wire, {} pantograph(s), {:.0} km/h, dt {} s",
        preset,
        case.catenary.spans,
        case.catenary.span_m,
        out.n_modes,
        out.pantographs.len(),
        a.speed,
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
    use pcsim_core::realtime::{Coupling, RealtimeCatenary};
    let preset = a.preset.clone().unwrap_or_else(|| "syt-7.0-9.8".into());
    let mut case = presets::load(&preset)?.0;
    case.pantographs.truncate(1);
    if let Some(dt) = a.dt {
        case.run.dt_s = dt;
    }
    let speed = if a.speed == 320.0 {
        case.run.speed_kmh
    } else {
        a.speed
    };
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
