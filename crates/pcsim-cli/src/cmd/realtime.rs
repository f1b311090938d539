//! `pcsim realtime`: the moving-window catenary (SIL) against the full model, for several window
//! lengths (paper §4.2, Figs. 8–9).

use anyhow::{Context, Result};
use clap::Args;
use pcsim_core::analysis::filter::lowpass_zero_phase;
use pcsim_core::analysis::stats::CUTOFF_HZ;
use pcsim_core::input::targets::target_value;
use pcsim_core::study::realtime::window_study;
use std::fmt::Write as _;
use std::path::PathBuf;

use crate::common::{apply, case_name, length, setup, shown, Ctx, Override};
use crate::output::write_file;
use crate::progress::Progress;

#[derive(Args)]
pub struct RealtimeArgs {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// Window lengths, comma-separated: m, or with a unit (215m, 0.215km).
    #[arg(long, value_delimiter = ',', required = true, value_name = "M")]
    window: Vec<String>,
    /// Train speed (default: the case's): km/h, or with a unit (250km/h, 69m/s).
    #[arg(long, value_name = "KM/H")]
    speed: Option<String>,
    /// The pantograph the window follows (the rig's): leading, trailing, a name or an index
    /// (sets the case's run.window_pantograph; default: the case's, else the leading one).
    #[arg(long, value_name = "NAME")]
    pantograph: Option<String>,
    /// Output directory.
    #[arg(long, default_value = "out/realtime")]
    out: PathBuf,
    /// No figures.
    #[arg(long)]
    no_plot: bool,
}

/// Measured reference values of `[paper_realtime]` when the case is the SYT preset at 222 km/h.
fn measured(case_name: &str, speed: f64) -> Option<(f64, f64)> {
    if case_name != "syt-7.0-9.8" || (speed - 222.0).abs() > 1e-9 {
        return None;
    }
    Some((
        target_value("paper_realtime", "measured_mean_n")?,
        target_value("paper_realtime", "measured_std_n")?,
    ))
}

/// The terminal's table of each window's statistics and errors against the full model (and the
/// paper's measurement, when it has one), returned as realtime.csv's text.
fn print_table(
    name: &str,
    case: &pcsim_core::Case,
    study: &pcsim_core::study::realtime::WindowStudy,
    together: usize,
) -> Result<String> {
    let full = &study.full;
    let runs = &study.windows;
    let fs = full.pantographs[0]
        .stats
        .context("the pantograph did not cross the analysis section")?;
    let reference = measured(name, case.run.speed_kmh);
    let cell = |v: Option<f64>| v.map(|x| format!("{x}")).unwrap_or_default();
    let mut table = String::from(crate::plot::realtime::HEADER);
    table.push('\n');
    println!(
        "{name} at {} km/h, 0–20 Hz contact force over {:?} m",
        case.run.speed_kmh, case.run.analysis_m
    );
    println!(
        "{:>10} {:>6} {:>6} {:>9} {:>8} {:>9} {:>9} {:>9}",
        "window [m]", "modes", "moves", "mean [N]", "σ [N]", "Δmean %", "Δσ %", "Δmax %"
    );
    for (r, e) in runs.iter().zip(study.errors_percent()) {
        let s = r
            .stats
            .context("window run did not cross the analysis section")?;
        let e = e.context("window run did not cross the analysis section")?;
        let _ = writeln!(
            table,
            "{},{},{},{:.4},{:.4},{:.3},{:.3},{:.4},{:.4},{},{},{:.3}",
            r.window_m,
            r.n_modes,
            r.moves,
            s.mean_n,
            s.std_n,
            e.mean_pct,
            e.sigma_pct,
            fs.mean_n,
            fs.std_n,
            cell(reference.map(|r| r.0)),
            cell(reference.map(|r| r.1)),
            e.max_pct
        );
        println!(
            "{:>10} {:>6} {:>6} {:>9.2} {:>8.2} {:>+9.2} {:>+9.2} {:>+9.2}",
            r.window_m, r.n_modes, r.moves, s.mean_n, s.std_n, e.mean_pct, e.sigma_pct, e.max_pct
        );
    }
    println!(
        "{:>10} {:>6} {:>6} {:>9.2} {:>8.2}   (the full model with pantograph {} alone)",
        "full", full.n_modes, "", fs.mean_n, fs.std_n, full.pantographs[0].name
    );
    if together > 1 {
        println!(
            "  the window and its reference carry one pantograph, the rig's: the case runs {together} together, and their waves change this one's force (pcsim run gives it among them)"
        );
    }
    if let Some((m, s)) = reference {
        println!(
            "{:>10} {:>6} {:>6} {:>9.2} {:>8.2}   (paper §4.2)",
            "measured", "", "", m, s
        );
    }
    Ok(table)
}

pub fn realtime(a: RealtimeArgs, ctx: &Ctx) -> Result<i32> {
    let (base, case_text) =
        crate::common::load_case_with_text(a.case.as_ref(), a.preset.as_deref())?;
    let mut overrides = Vec::new();
    if let Some(v) = &a.speed {
        overrides.push(Override::speed(v)?);
    }
    let case = crate::common::window_pantograph(apply(&base, &overrides)?, a.pantograph.as_deref());
    let together = case.pantographs.len();
    let case = pcsim_core::compile::window_case(&case)?;
    let windows: Vec<f64> = a
        .window
        .iter()
        .map(|w| length("--window", w))
        .collect::<Result<_>>()?;
    let s = setup(&case, &overrides, ctx)?;
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    let dt = s.options.dt_s;
    let od = crate::output::OutDir::begin(&a.out)?;
    let dir = od.path();
    // The case as given (every value with its source), for the report.
    crate::output::write_file(&dir.join("case.toml"), &case_text)?;
    let pb = Progress::run("full model", ctx.progress);
    let study = window_study(&case, &windows, None, &mut |f| {
        pb.set((f * 1000.0) as u64);
        true
    })?;
    pb.finish();
    let name = case_name(&case);
    let table = print_table(&name, &case, &study, together)?;
    let (full, runs) = (&study.full, &study.windows);
    write_file(&dir.join("realtime.csv"), table)?;
    // Time histories (0–20 Hz) of the full model and each window.
    let ts = filtered_histories(full, runs, dt);
    write_file(&dir.join("timeseries.csv"), ts)?;
    crate::output::write_manifest(
        dir,
        "realtime",
        crate::output::StudyManifest {
            case_name: Some(name.clone()),
            speed_kmh: Some(case.run.speed_kmh),
            analysis_m: Some(case.run.analysis_m),
            overrides: Some(overrides.iter().map(|o| o.flag.clone()).collect()),
            ..Default::default()
        },
    )?;
    let files = if a.no_plot {
        Vec::new()
    } else {
        od.in_target(&crate::plot::redraw_kind(
            dir,
            pcsim_core::study::StudyKind::Realtime,
        )?)
    };
    od.commit()?;
    println!(
        "wrote {} and {}",
        shown(&a.out, "realtime.csv"),
        shown(&a.out, "timeseries.csv")
    );
    if !a.no_plot {
        crate::plot::report(&files);
    }
    Ok(0)
}

/// timeseries.csv of a real-time study: the time, the position and the 0–20 Hz force of the full
/// model and of each window.
fn filtered_histories(
    full: &pcsim_core::analysis::record::RunOutput,
    runs: &[pcsim_core::study::realtime::WindowRun],
    dt: f64,
) -> String {
    let ff = lowpass_zero_phase(&full.pantographs[0].force_n, 1.0 / dt, CUTOFF_HZ);
    let wf: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| lowpass_zero_phase(&r.force_n, 1.0 / dt, CUTOFF_HZ))
        .collect();
    let mut ts = String::from("time_s,position_m,full_force_filtered_n");
    for r in runs {
        let _ = write!(ts, ",window_{}m_force_filtered_n", r.window_m);
    }
    ts.push('\n');
    let n = ff
        .len()
        .min(wf.iter().map(|v| v.len()).min().unwrap_or(usize::MAX));
    for k in 0..n {
        let _ = write!(
            ts,
            "{:.6},{:.4},{:.4}",
            full.time_s[k], full.pantographs[0].position_m[k], ff[k]
        );
        for w in &wf {
            let _ = write!(ts, ",{:.4}", w[k]);
        }
        ts.push('\n');
    }
    ts
}
