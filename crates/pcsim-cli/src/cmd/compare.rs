//! `pcsim compare RUN MEASURED.csv`: a run's contact force beside a measured one (issue 22,
//! item 4): the core's study `study::compare` (filter, alignment, statistics, spectra, span
//! profile, the tables and the answer) through the one driver. This file reads the run's
//! directory and the measured file into the study.

use anyhow::{Context, Result};
use clap::Args;
use pcsim_core::input::measured::MeasuredForce;
use pcsim_core::study::compare::CompareStudy;
use std::path::PathBuf;

use crate::common::length;

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

pub fn compare(a: CompareArgs, ctx: &crate::common::Ctx) -> Result<i32> {
    let search_m = length("--search", &a.search)?;
    let run = crate::plot::run::read_run(&a.run)
        .with_context(|| format!("{} is not a run's output directory", a.run.display()))?;
    let trace = trace_of(&run, a.pantograph.as_deref())?;
    let text = crate::common::read_input(&a.measured)
        .with_context(|| format!("cannot read {}", a.measured.display()))?;
    let measured_name = a.measured.display().to_string();
    let meas = MeasuredForce::from_csv(&text, &measured_name)?;
    let supports_m = pcsim_core::study::compare::support_positions(
        &run.supports_m,
        run.span_m,
        trace.position_m.last().copied().unwrap_or(0.0),
    );
    let study = CompareStudy {
        pantograph: trace.name.clone(),
        case_name: run.case_name.clone(),
        position_m: trace.position_m.clone(),
        force_n: trace.force_n.clone(),
        speed_kmh: run.speed_kmh,
        analysis_m: run.analysis_m,
        supports_m,
        measured: meas,
        measured_name,
        search_m,
    };
    // The run's case as given (every value with its source), for the report.
    let case = a.run.join("case.toml");
    let case_text = if case.is_file() {
        Some(
            std::fs::read_to_string(&case)
                .with_context(|| format!("cannot read {}", case.display()))?,
        )
    } else {
        None
    };
    let manifest = crate::output::StudyManifest {
        run: Some(a.run.display().to_string()),
        measured: Some(a.measured.display().to_string()),
        pantograph: Some(trace.name.clone()),
        case: Some(run.case_name.clone()),
        speed_kmh: Some(run.speed_kmh),
        ..Default::default()
    };
    let drive = crate::driver::Drive {
        out: &a.out,
        case_text: case_text.as_deref(),
        spec_text: None,
        plot: !a.no_plot,
        report: false,
        manifest,
        unit: "comparison",
    };
    let o = crate::driver::drive(&study, drive, ctx)?;
    if a.strict && !o.comparison.warnings.is_empty() {
        eprintln!("--strict: the alignment is doubtful (above); the outputs are written");
        return Ok(1);
    }
    Ok(0)
}
