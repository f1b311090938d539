//! The figures of a comparison with a measurement (`pcsim compare`), from its written CSVs:
//! the aligned 0–20 Hz forces, their spectra and their averages over the spans.

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

use super::{figure, Figure, Line, COLOURS};

fn columns(path: &Path) -> Result<Vec<Vec<f64>>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    let n = rows.first().map_or(0, Vec::len);
    Ok((0..n)
        .map(|k| rows.iter().map(|r| r[k]).collect())
        .collect())
}

/// The three figures, from the written CSVs (so `pcsim plot DIR` draws the same).
pub fn draw(dir: &Path, title: &str) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let trio = |name: &str| columns(&dir.join(name));
    let f = trio("compare.csv")?;
    let pts = |k: usize, c: &[Vec<f64>]| {
        c[0].iter()
            .copied()
            .zip(c[k].iter().copied())
            .collect::<Vec<_>>()
    };
    files.extend(figure(
        &dir.join("compare_force"),
        &Figure {
            title: &format!("{title}: 0–20 Hz contact force, aligned"),
            x_label: "Position along the track (the run's) [m]",
            y_label: "Contact force, 0–20 Hz [N]",
            lines: vec![
                Line::new("run", pts(1, &f)).styled(COLOURS[0], 2),
                Line::new("measured (shifted)", pts(2, &f)).styled(COLOURS[1], 1),
            ],
            log_y: false,
            vmarks: Vec::new(),
            hmarks: Vec::new(),
        },
    )?);
    let s = trio("compare_spectrum.csv")?;
    files.extend(figure(
        &dir.join("compare_spectrum"),
        &Figure {
            title: &format!("{title}: power spectral density of the 0–20 Hz force"),
            x_label: "Spatial frequency [1/m]",
            y_label: "PSD [N²·m]",
            lines: vec![
                Line::new("run", pts(1, &s)).styled(COLOURS[0], 2),
                Line::new("measured", pts(2, &s))
                    .styled(COLOURS[1], 2)
                    .marked(),
            ],
            log_y: true,
            vmarks: Vec::new(),
            hmarks: Vec::new(),
        },
    )?);
    let p = trio("compare_profile.csv")?;
    files.extend(figure(
        &dir.join("compare_profile"),
        &Figure {
            title: &format!("{title}: 0–20 Hz force averaged over the spans"),
            x_label: "Position within the span (0 and 1: supports)",
            y_label: "Mean contact force [N]",
            lines: vec![
                Line::new("run", pts(1, &p)).styled(COLOURS[0], 2).marked(),
                Line::new("measured", pts(2, &p)).styled(COLOURS[1], 2),
            ],
            log_y: false,
            vmarks: Vec::new(),
            hmarks: Vec::new(),
        },
    )?);
    Ok(files)
}

/// Redraw a comparison's figures from its files.
pub fn redraw(dir: &Path) -> Result<Vec<PathBuf>> {
    // The manifest as it is (complete, or being written: the driver draws before it commits).
    let m = crate::output::read_manifest(dir)?.unwrap_or_default().study;
    let title = format!(
        "{} ({} pantograph)",
        m.case.as_deref().unwrap_or("run"),
        m.pantograph.as_deref().unwrap_or("")
    );
    draw(dir, &title)
}
