//! `pcsim compare RUN MEASURED.csv`: a run's contact force beside a measured one (issue 22,
//! item 4), through the core's `analysis::compare` (filter, alignment, statistics, spectra,
//! span profile). This file reads the files, writes the outputs and draws the figures.

use anyhow::{Context, Result};
use clap::Args;
use pcsim_core::analysis::compare::{compare as compare_core, Comparison};
use pcsim_core::input::measured::MeasuredForce;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::common::{length, shown};
use crate::output::{write_file, write_manifest, OutDir};

#[derive(Args)]
pub struct CompareArgs {
    /// A run's output directory (`pcsim run … --out RUN`).
    run: PathBuf,
    /// Measured contact force: CSV with the header `position_m,force_n` (m along the track, N), at
    /// a uniform spacing, as a recording car gives it.
    measured: PathBuf,
    /// The run's pantograph to compare [default: the leading one].
    #[arg(long)]
    pantograph: Option<String>,
    /// Search the alignment within ± this length: m, or with a unit.
    #[arg(long, value_name = "M", default_value = "30")]
    search: String,
    /// Output directory (written as a whole).
    #[arg(long, default_value = "out/compare")]
    out: PathBuf,
    /// No figures.
    #[arg(long)]
    no_plot: bool,
    /// Exit with status 1 when the alignment is doubtful (a correlation below 0.5, or the shift
    /// at the edge of the search range); by default it is a warning in the outputs.
    #[arg(long)]
    strict: bool,
}

/// The run's trace of the pantograph named (none: the first).
fn trace_of<'a>(
    run: &'a crate::plot::run::PlotData,
    pantograph: Option<&str>,
) -> Result<&'a crate::plot::run::Trace> {
    Ok(match pantograph {
        Some(name) => run
            .traces
            .iter()
            .find(|t| t.name == name)
            .with_context(|| {
                format!(
                    "--pantograph {name}: the run has {}",
                    run.traces
                        .iter()
                        .map(|t| t.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })?,
        None => run.traces.first().context("the run has no pantograph")?,
    })
}

pub fn compare(a: CompareArgs) -> Result<i32> {
    let search_m = length("--search", &a.search)?;
    let run = crate::plot::run::read_run(&a.run)
        .with_context(|| format!("{} is not a run's output directory", a.run.display()))?;
    let trace = trace_of(&run, a.pantograph.as_deref())?;
    let text = crate::common::read_input(&a.measured)
        .with_context(|| format!("cannot read {}", a.measured.display()))?;
    let meas = MeasuredForce::from_csv(&text, &a.measured.display().to_string())?;
    let supports: Vec<f64> = if !run.supports_m.is_empty() {
        run.supports_m.clone()
    } else if let Some(s) = run.span_m {
        let last = trace.position_m.last().copied().unwrap_or(0.0);
        (0..=((last / s).ceil() as usize + 1))
            .map(|k| k as f64 * s)
            .collect()
    } else {
        Vec::new()
    };
    let c = compare_core(
        (&trace.position_m, &trace.force_n),
        &meas,
        run.speed_kmh / 3.6,
        run.analysis_m,
        search_m,
        &supports,
    )?;
    let od = OutDir::begin(&a.out)?;
    write_outputs(od.path(), &c)?;
    // The run's case as given (every value with its source), for the report.
    let case = a.run.join("case.toml");
    if case.is_file() {
        std::fs::copy(&case, od.path().join("case.toml"))
            .with_context(|| format!("cannot copy {}", case.display()))?;
    }
    write_manifest(
        od.path(),
        "compare",
        crate::output::StudyManifest {
            run: Some(a.run.display().to_string()),
            measured: Some(a.measured.display().to_string()),
            pantograph: Some(trace.name.clone()),
            case: Some(run.case_name.clone()),
            speed_kmh: Some(run.speed_kmh),
            correlation: Some(c.correlation),
            warnings: Some(c.warnings.clone()),
            ..Default::default()
        },
    )?;
    let files = if a.no_plot {
        Vec::new()
    } else {
        od.in_target(&crate::plot::compare::draw(
            od.path(),
            &format!("{} ({} pantograph)", run.case_name, trace.name),
        )?)
    };
    od.commit()?;
    println!(
        "{} pantograph of {} against {}: shift {:+.2} m ({} samples of {} m; searched ± {search_m} m), correlation {:.3}",
        trace.name,
        run.case_name,
        a.measured.display(),
        c.shift_m,
        c.shift_samples,
        meas.spacing_m,
        c.correlation
    );
    println!(
        "0–20 Hz contact force over {:?} m ({} samples):",
        c.section_m, c.simulated.samples
    );
    println!(
        "  {:<14} {:>10} {:>10} {:>10} {:>8}",
        "", "run", "measured", "difference", "%"
    );
    for ((name, s), (_, m)) in c.simulated.rows().iter().zip(c.measured.rows()) {
        println!(
            "  {name:<14} {s:>10.2} {m:>10.2} {:>+10.2} {:>+8.1}",
            m - s,
            100.0 * (m - s) / s.abs().max(1e-9)
        );
    }
    println!(
        "wrote {}, {}, {} and {}",
        shown(&a.out, "compare_stats.csv"),
        shown(&a.out, "compare.csv"),
        shown(&a.out, "compare_spectrum.csv"),
        shown(&a.out, "compare_profile.csv")
    );
    if !files.is_empty() {
        crate::plot::report(&files);
    }
    for w in &c.warnings {
        eprintln!("warning: {w}");
    }
    if a.strict && !c.warnings.is_empty() {
        eprintln!("--strict: the alignment is doubtful (above); the outputs are written");
        return Ok(1);
    }
    Ok(0)
}

fn write_outputs(dir: &Path, c: &Comparison) -> Result<()> {
    let mut t = String::from("quantity,run,measured,difference\n");
    let _ = writeln!(t, "shift_m,,{},", c.shift_m);
    let _ = writeln!(t, "correlation,,{},", c.correlation);
    for w in &c.warnings {
        // A doubtful alignment travels with the numbers it qualifies.
        let _ = writeln!(t, "warning,,\"{}\",", w.replace('"', "'"));
    }
    for ((name, s), (_, m)) in c.simulated.rows().iter().zip(c.measured.rows()) {
        let _ = writeln!(t, "{name},{s},{m},{}", m - s);
    }
    write_file(&dir.join("compare_stats.csv"), t)?;
    let mut t = String::from("position_m,run_force_filtered_n,measured_force_filtered_n\n");
    for ((x, s), m) in c.position_m.iter().zip(&c.simulated_n).zip(&c.measured_n) {
        let _ = writeln!(t, "{x:.4},{s:.4},{m:.4}");
    }
    write_file(&dir.join("compare.csv"), t)?;
    let mut t = String::from("frequency_per_m,run_psd_n2_m,measured_psd_n2_m\n");
    for r in &c.spectrum {
        let _ = writeln!(t, "{},{},{}", r[0], r[1], r[2]);
    }
    write_file(&dir.join("compare_spectrum.csv"), t)?;
    let mut t = String::from("span_fraction,run_mean_force_n,measured_mean_force_n\n");
    for r in &c.profile {
        let _ = writeln!(t, "{},{},{}", r[0], r[1], r[2]);
    }
    write_file(&dir.join("compare_profile.csv"), t)
}
