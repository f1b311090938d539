//! The real-time window against the full model (the paper's Figs. 8–9), drawn from the study's
//! files (`realtime.csv`, `timeseries.csv`, `pcsim.json`): the 0–20 Hz force of each window over
//! the full model's, the accuracy (relative error of the mean and σ) against the window length on
//! a logarithmic axis, and the mean and σ themselves.

use anyhow::{bail, Context, Result};
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

use super::{figure, Figure, Line};

/// The header of `realtime.csv`, the core's ([`REALTIME_HEADER`]).
use pcsim_core::study::realtime::REALTIME_HEADER as HEADER;

/// A CSV's header and its cells (`None` where empty or not a number).
type Table = (Vec<String>, Vec<Vec<Option<f64>>>);

fn parse_csv(path: &Path) -> Result<Table> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .with_context(|| format!("{} is empty", path.display()))?
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .filter(|l| !l.is_empty())
        .map(|l| {
            l.split(',')
                .map(|v| v.trim().parse().ok().filter(|x: &f64| x.is_finite()))
                .collect()
        })
        .collect();
    Ok((header, rows))
}

/// Redraw the window study's figures.
pub fn redraw(dir: &Path) -> Result<Vec<PathBuf>> {
    let m = crate::output::read_manifest(dir)?.unwrap_or_default().study;
    let name = m.case_name.unwrap_or_else(|| "case".into());
    let speed = m.speed_kmh.unwrap_or(0.0);
    let sec = m.analysis_m.unwrap_or([f64::NEG_INFINITY, f64::INFINITY]);
    let (h, rows) = parse_csv(&dir.join("realtime.csv"))?;
    if h.join(",") != HEADER {
        bail!(
            "{} is not a realtime.csv of this version of pcsim",
            dir.join("realtime.csv").display()
        );
    }
    if rows.is_empty() {
        bail!(
            "{} has no windows: nothing to plot",
            dir.join("realtime.csv").display()
        );
    }
    let (th, ts) = parse_csv(&dir.join("timeseries.csv"))?;
    if ts.is_empty() {
        bail!(
            "{} has no rows: nothing to plot",
            dir.join("timeseries.csv").display()
        );
    }
    let title = format!("{name}, {speed} km/h");
    let mut files = force_figures(dir, &title, sec, (&th, &ts))?;
    files.extend(accuracy_figures(dir, &title, &rows)?);
    Ok(files)
}

/// A row of a numeric CSV as read (empty cells `None`).
type Row = Vec<Option<f64>>;

/// Each window's 0–20 Hz force over the full model's, on a 240 m excerpt from the middle of the
/// analysis section `sec` (`th`, `ts`: timeseries.csv's header and rows).
fn force_figures(
    dir: &Path,
    title: &str,
    sec: [f64; 2],
    (th, ts): (&[String], &[Row]),
) -> Result<Vec<PathBuf>> {
    let col = |r: &Row, i: usize| r.get(i).copied().flatten();
    let mut files = Vec::new();
    let pos: Vec<f64> = ts.iter().map(|r| col(r, 1).unwrap_or(f64::NAN)).collect();
    // A 240 m excerpt from the middle of the analysis section: long enough for four spans of
    // 60 m, short enough to see every oscillation of the two traces.
    let (lo, hi) = if sec[0].is_finite() && sec[1].is_finite() {
        let mid = 0.5 * (sec[0] + sec[1]);
        let half = (0.5 * (sec[1] - sec[0])).min(120.0);
        (mid - half, mid + half)
    } else {
        (f64::NEG_INFINITY, f64::INFINITY)
    };
    let series = |i: usize| -> Vec<(f64, f64)> {
        ts.iter()
            .zip(&pos)
            .filter(|(_, &x)| x >= lo && x <= hi)
            .filter_map(|(r, &x)| col(r, i).map(|y| (x, y)))
            .collect()
    };
    let full = series(2);
    for (i, head) in th.iter().enumerate().skip(3) {
        let w = head
            .strip_prefix("window_")
            .and_then(|s| s.strip_suffix("m_force_filtered_n"))
            .unwrap_or(head);
        files.extend(figure(
            &dir.join(format!("realtime_force_{w}m")),
            &Figure {
                title: &format!(
                    "{title}: contact force (0–20 Hz), window {w} m over the full model, {lo:.0}–{hi:.0} m"
                ),
                x_label: "Position along the track [m]",
                y_label: "Contact force [N]",
                // The window's trace drawn thin over the full model's broad light trace: both
                // stay visible where they agree.
                lines: vec![
                    Line::new("full model", full.clone()).styled(RGBColor(140, 185, 230), 5),
                    Line::new(format!("window {w} m"), series(i))
                        .styled(RGBColor(200, 30, 30), 2),
                ],
                log_y: false,
                vmarks: vec![],
                hmarks: vec![],
            },
        )?);
    }
    Ok(files)
}

/// The accuracy of the windows against the full model (realtime.csv's `rows`): the errors
/// against the window length, and the mean and σ against it.
fn accuracy_figures(dir: &Path, title: &str, rows: &[Row]) -> Result<Vec<PathBuf>> {
    let col = |r: &Row, i: usize| r.get(i).copied().flatten();
    let mut files = Vec::new();
    let mut sorted: Vec<&Vec<Option<f64>>> = rows.iter().collect();
    sorted.sort_by(|a, b| {
        col(a, 0)
            .unwrap_or(0.0)
            .total_cmp(&col(b, 0).unwrap_or(0.0))
    });
    let pts = |i: usize, abs: bool| -> Vec<(f64, f64)> {
        sorted
            .iter()
            .filter_map(|r| {
                let v = col(r, i)?;
                Some((col(r, 0)?, if abs { v.abs() } else { v }))
            })
            .collect()
    };
    files.extend(figure(
        &dir.join("realtime_error_vs_window"),
        &Figure {
            title: &format!(
                "{title}: accuracy of the window against the full model (0–20 Hz force)"
            ),
            x_label: "Window length [m]",
            y_label: "|relative error| [%] (log scale)",
            lines: vec![
                Line::new("mean", pts(5, true)).marked(),
                Line::new("σ", pts(6, true)).marked(),
            ],
            log_y: true,
            vmarks: vec![],
            hmarks: vec![(1.0, "1 %".into()), (3.0, "3 %".into())],
        },
    )?);
    let (x0, x1) = (
        pts(0, false).first().map_or(0.0, |p| p.0),
        pts(0, false).last().map_or(1.0, |p| p.0),
    );
    for (q, label, i, full_i, meas_i) in [
        ("mean", "Mean contact force [N]", 3, 7, 9),
        ("std", "Standard deviation [N]", 4, 8, 10),
    ] {
        let mut lines = vec![Line::new("window model", pts(i, false)).marked()];
        if let Some(f) = col(sorted[0], full_i) {
            lines.push(Line::new("full model", vec![(x0, f), (x1, f)]));
        }
        if let Some(m) = col(sorted[0], meas_i) {
            lines.push(Line::new("measured (paper §4.2)", vec![(x0, m), (x1, m)]));
        }
        files.extend(figure(
            &dir.join(format!("realtime_{q}_vs_window")),
            &Figure {
                title: &format!(
                    "{title}: {} of the 0–20 Hz contact force against window length",
                    if q == "mean" { "mean" } else { "σ" }
                ),
                x_label: "Window length d_e [m]",
                y_label: label,
                lines,
                log_y: false,
                vmarks: vec![],
                hmarks: vec![],
            },
        )?);
    }
    Ok(files)
}
