//! The real-time window against the full model (the paper's Figs. 8–9): the 0–20 Hz force of each
//! window beside the full model's, and the mean and σ against the window length.

use anyhow::Result;
use pcsim_core::analysis::stats::ContactStats;
use pcsim_core::analysis::studies::WindowRun;
use std::path::{Path, PathBuf};

use super::{line_plot, Line};

/// What the window figures show.
pub struct RealtimeFigures<'a> {
    pub name: &'a str,
    pub speed_kmh: f64,
    pub analysis_m: [f64; 2],
    /// The full model's track positions and 0–20 Hz force.
    pub position_m: &'a [f64],
    pub full_filtered_n: &'a [f64],
    pub full_stats: ContactStats,
    pub windows: &'a [WindowRun],
    /// Each window's 0–20 Hz force.
    pub window_filtered_n: &'a [Vec<f64>],
    /// The measured mean and σ (paper §4.2), where the case is the measured one.
    pub measured: Option<(f64, f64)>,
}

/// Draw the figures into `dir`; returns the files written.
pub fn draw_realtime(dir: &Path, d: &RealtimeFigures) -> Result<Vec<PathBuf>> {
    let a_out = dir;
    let name = d.name;
    let fs = d.full_stats;
    let reference = d.measured;
    let runs = d.windows;
    let wf = d.window_filtered_n;
    let ff = d.full_filtered_n;
    let n = d.position_m.len();
    let pos = d.position_m;
    let sec = d.analysis_m;
    let pick = |v: &[f64]| -> Vec<(f64, f64)> {
        (0..n)
            .filter(|&k| pos[k] >= sec[0] && pos[k] <= sec[1])
            .map(|k| (pos[k], v[k]))
            .step_by(2)
            .collect()
    };
    let mut files = Vec::new();
    for (r, w) in runs.iter().zip(wf) {
        files.extend(line_plot(
            &a_out.join(format!("realtime_force_{}m", r.window_m)),
            &format!(
                "{name}, {} km/h: contact force (0–20 Hz), window {} m vs full model",
                d.speed_kmh, r.window_m
            ),
            "Position along the track [m]",
            "Contact force [N]",
            &[
                Line {
                    label: "full model".into(),
                    points: pick(ff),
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
            &a_out.join(format!("realtime_{q}_vs_window")),
            &format!(
                "{name}, {} km/h: {} of the 0–20 Hz contact force against window length",
                d.speed_kmh,
                if q == "mean" { "mean" } else { "σ" }
            ),
            "Window length d_e [m]",
            label,
            &lines,
            true,
        )?);
    }
    Ok(files)
}
