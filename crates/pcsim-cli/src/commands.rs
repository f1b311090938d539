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
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

#[derive(Args)]
pub struct ValidateArgs {
    /// Validation to run.
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
    /// Train speed, km/h.
    #[arg(long, default_value_t = 320.0)]
    speed: f64,
    /// Modes per wire.
    #[arg(long, default_value_t = 1200)]
    modes: usize,
    /// Spans (60 m each).
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
    let (out, wall, warnings) = run_model(&case, "run", quiet)?;
    let summary = Summary::new(&out, wall, warnings);
    write_run(&a.out, &out, &summary)?;
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

pub fn validate(a: ValidateArgs, quiet: bool) -> Result<i32> {
    let (preset, table) = match a.name.as_str() {
        "en50318-2002" => ("en50318-2002", "en50318_2002"),
        other => bail!("unknown validation `{other}` (available: en50318-2002)"),
    };
    let base = presets::load(preset)?.0;
    let targets = target_cases(table)?;
    // Each speed runs single-threaded and deterministically; the speeds run side by side.
    let results: Vec<Result<(CaseRows, f64, f64)>> = std::thread::scope(|s| {
        let handles: Vec<_> = targets
            .iter()
            .map(|t| {
                let mut case = base.clone();
                case.run.speed_kmh = t.speed_kmh;
                let label = format!("{} km/h", t.speed_kmh);
                s.spawn(move || -> Result<(CaseRows, f64, f64)> {
                    let (out, wall, _) = run_model(&case, &label, quiet)?;
                    let stats = out.pantographs[0]
                        .stats
                        .context("pantograph did not cross the analysis section")?;
                    Ok((compare(&stats, t), wall, out.simulated_time_s()))
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
    let mut cases = Vec::new();
    for r in results {
        cases.push(r?);
    }
    let all_pass = cases.iter().all(|(c, _, _)| c.rows.iter().all(|r| r.pass));
    if a.json {
        let js = ValidationJson {
            all_pass,
            cases: cases.into_iter().map(|c| c.0).collect(),
        };
        println!("{}", serde_json::to_string_pretty(&js)?);
    } else {
        println!("EN 50318:2002 validation, preset `{preset}` (ranges from data/validation-targets.toml)");
        for (c, wall, sim) in &cases {
            println!(
                "\n{} km/h  ({sim:.1} s simulated in {wall:.1} s)",
                c.speed_kmh
            );
            println!(
                "  {:<28} {:>10} {:>18}  result",
                "quantity", "value", "range"
            );
            for r in &c.rows {
                println!(
                    "  {:<28} {:>10.1} {:>18}  {}",
                    r.quantity,
                    r.value,
                    format!("[{}, {}]", r.range[0], r.range[1]),
                    if r.pass { "pass" } else { "FAIL" }
                );
            }
        }
        let n: usize = cases.iter().map(|c| c.0.rows.len()).sum();
        let p: usize = cases
            .iter()
            .map(|c| c.0.rows.iter().filter(|r| r.pass).count())
            .sum();
        println!("\n{p} of {n} rows pass. Rows out of reach with the public data are explained in docs/validation.md.");
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
    c.run.analysis_m = [300.0, l - 300.0];
    Ok(c)
}

pub fn bench(a: BenchArgs, quiet: bool) -> Result<i32> {
    let case = bench_case(a.speed, a.modes, a.spans, a.dt)?;
    let (out, wall, _) = run_model(&case, "bench", quiet)?;
    let sim = out.simulated_time_s();
    println!(
        "bench: {} spans x {:.0} m, {} modes/wire, 2 pantographs 200 m apart, {:.0} km/h, dt {} s",
        a.spans, case.catenary.span_m, out.n_modes, a.speed, case.run.dt_s
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
