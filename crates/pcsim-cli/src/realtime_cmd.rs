//! `pcsim realtime`: the moving-window catenary (SIL) against the full model, for several window
//! lengths (paper §4.2, Figs. 8–9).

use anyhow::{Context, Result};
use clap::Args;
use pcsim_core::filter::lowpass_zero_phase;
use pcsim_core::realtime::{run_window_sil, WindowRun};
use pcsim_core::sim::simulate;
use pcsim_core::stats::CUTOFF_HZ;
use pcsim_core::validation::TARGETS_TOML;
use pcsim_core::Model;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::PathBuf;

use crate::plots::{line_plot, Line};

#[derive(Args)]
pub struct RealtimeArgs {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// Window lengths, m (comma-separated).
    #[arg(long, value_delimiter = ',', required = true)]
    window: Vec<f64>,
    /// Train speed, km/h (default: the case's).
    #[arg(long)]
    speed: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "out/realtime")]
    out: PathBuf,
    /// No plots.
    #[arg(long)]
    no_plot: bool,
}

/// Measured reference values of `[paper_realtime]` when the case is the SYT preset at 222 km/h.
fn measured(case_name: &str, speed: f64) -> Option<(f64, f64)> {
    if case_name != "syt-7.0-9.8" || (speed - 222.0).abs() > 1e-9 {
        return None;
    }
    let v: toml::Value = toml::from_str(TARGETS_TOML).ok()?;
    let t = v.get("paper_realtime")?;
    Some((
        t.get("measured_mean_n")?.as_float()?,
        t.get("measured_std_n")?.as_float()?,
    ))
}

pub fn realtime(a: RealtimeArgs, quiet: bool) -> Result<i32> {
    let mut case = crate::commands::load_case(a.case.as_ref(), a.preset.as_deref())?;
    if let Some(v) = a.speed {
        case.run.speed_kmh = v;
    }
    case.pantographs.truncate(1);
    let (model, warnings) = Model::from_case(&case)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let dt = model.dt_s;
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let pb = crate::progress::bar("full model", quiet);
    let full = simulate(model, &mut |f| {
        pb.set_position((f * 1000.0) as u64);
        true
    })?;
    pb.finish_and_clear();
    let fs = full.pantographs[0]
        .stats
        .context("the pantograph did not cross the analysis section")?;
    let runs: Vec<WindowRun> = a
        .window
        .par_iter()
        .map(|&w| run_window_sil(&case, w))
        .collect::<Result<_, _>>()?;
    let name = if case.meta.name.is_empty() {
        "case".to_string()
    } else {
        case.meta.name.clone()
    };
    let reference = measured(&name, case.run.speed_kmh);
    // Table.
    let mut table =
        String::from("window_m,modes,moves,mean_n,std_n,mean_error_percent,std_error_percent\n");
    println!(
        "{name} at {} km/h, 0–20 Hz contact force over {:?} m",
        case.run.speed_kmh, case.run.analysis_m
    );
    println!(
        "{:>10} {:>6} {:>6} {:>9} {:>8} {:>9} {:>9}",
        "window [m]", "modes", "moves", "mean [N]", "σ [N]", "Δmean %", "Δσ %"
    );
    for r in &runs {
        let s = r
            .stats
            .context("window run did not cross the analysis section")?;
        let (em, es) = (
            100.0 * (s.mean_n - fs.mean_n) / fs.mean_n,
            100.0 * (s.std_n - fs.std_n) / fs.std_n,
        );
        let _ = writeln!(
            table,
            "{},{},{},{:.4},{:.4},{:.3},{:.3}",
            r.window_m, r.n_modes, r.moves, s.mean_n, s.std_n, em, es
        );
        println!(
            "{:>10} {:>6} {:>6} {:>9.2} {:>8.2} {:>+9.2} {:>+9.2}",
            r.window_m, r.n_modes, r.moves, s.mean_n, s.std_n, em, es
        );
    }
    let _ = writeln!(
        table,
        "full,{},0,{:.4},{:.4},0,0",
        full.n_modes, fs.mean_n, fs.std_n
    );
    println!(
        "{:>10} {:>6} {:>6} {:>9.2} {:>8.2}",
        "full", full.n_modes, "", fs.mean_n, fs.std_n
    );
    if let Some((m, s)) = reference {
        let _ = writeln!(table, "measured,,,{m},{s},,");
        println!(
            "{:>10} {:>6} {:>6} {:>9.2} {:>8.2}   (paper §4.2)",
            "measured", "", "", m, s
        );
    }
    std::fs::write(a.out.join("realtime.csv"), table)?;
    // Time histories (0–20 Hz) of the full model and each window.
    let ff = lowpass_zero_phase(&full.pantographs[0].force_n, 1.0 / dt, CUTOFF_HZ);
    let wf: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| lowpass_zero_phase(&r.force_n, 1.0 / dt, CUTOFF_HZ))
        .collect();
    let mut ts = String::from("time_s,position_m,full_force_filtered_n");
    for r in &runs {
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
    std::fs::write(a.out.join("timeseries.csv"), ts)?;
    println!(
        "wrote {}/realtime.csv and {}/timeseries.csv",
        a.out.display(),
        a.out.display()
    );
    if !a.no_plot {
        let pos = &full.pantographs[0].position_m;
        let sec = case.run.analysis_m;
        let pick = |v: &[f64]| -> Vec<(f64, f64)> {
            (0..n)
                .filter(|&k| pos[k] >= sec[0] && pos[k] <= sec[1])
                .map(|k| (pos[k], v[k]))
                .step_by(2)
                .collect()
        };
        let mut files = Vec::new();
        for (r, w) in runs.iter().zip(&wf) {
            files.extend(line_plot(
                &a.out.join(format!("realtime_force_{}m", r.window_m)),
                &format!(
                    "{name}, {} km/h: contact force (0–20 Hz), window {} m vs full model",
                    case.run.speed_kmh, r.window_m
                ),
                "Position along the track [m]",
                "Contact force [N]",
                &[
                    Line {
                        label: "full model".into(),
                        points: pick(&ff),
                    },
                    Line {
                        label: format!("window {} m", r.window_m),
                        points: pick(w),
                    },
                ],
                false,
            )?);
        }
        let mut sorted: Vec<&WindowRun> = runs.iter().collect();
        sorted.sort_by(|x, y| x.window_m.total_cmp(&y.window_m));
        let (x0, x1) = (
            sorted.first().map_or(0.0, |r| r.window_m),
            sorted.last().map_or(1.0, |r| r.window_m),
        );
        for (q, label, full_v, meas) in [
            (
                "mean",
                "Mean contact force [N]",
                fs.mean_n,
                reference.map(|r| r.0),
            ),
            (
                "std",
                "Standard deviation [N]",
                fs.std_n,
                reference.map(|r| r.1),
            ),
        ] {
            let mut lines = vec![
                Line {
                    label: "window model".into(),
                    points: sorted
                        .iter()
                        .filter_map(|r| {
                            r.stats
                                .map(|s| (r.window_m, if q == "mean" { s.mean_n } else { s.std_n }))
                        })
                        .collect(),
                },
                Line {
                    label: "full model".into(),
                    points: vec![(x0, full_v), (x1, full_v)],
                },
            ];
            if let Some(m) = meas {
                lines.push(Line {
                    label: "measured (paper §4.2)".into(),
                    points: vec![(x0, m), (x1, m)],
                });
            }
            files.extend(line_plot(
                &a.out.join(format!("realtime_{q}_vs_window")),
                &format!(
                    "{name}, {} km/h: {} of the 0–20 Hz contact force against window length",
                    case.run.speed_kmh,
                    if q == "mean" { "mean" } else { "σ" }
                ),
                "Window length d_e [m]",
                label,
                &lines,
                true,
            )?);
        }
        crate::plots::report(&files);
    }
    Ok(0)
}
