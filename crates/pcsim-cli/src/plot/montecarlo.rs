//! The figures of a Monte Carlo study (`pcsim run --seeds N`), from `montecarlo.csv`:
//! histograms over the realisations of σ and of the minimum of the 0–20 Hz contact force, per
//! pantograph.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

use super::{figure, safe, Figure, Line};

/// Redraw the histograms of a Monte Carlo directory.
pub fn redraw(dir: &Path) -> Result<Vec<PathBuf>> {
    let p = dir.join("montecarlo.csv");
    let text =
        std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let rows: Vec<Vec<&str>> = lines
        .filter(|l| !l.is_empty())
        .map(|l| l.split(',').collect())
        .collect();
    if rows.is_empty() {
        bail!("{} has no realisations: nothing to plot", p.display());
    }
    let mut files = Vec::new();
    for (c, h) in header.iter().enumerate() {
        let (name, what, label) = if let Some(n) = h.strip_suffix("_std_n") {
            (n, "std", "σ of the 0–20 Hz contact force [N]")
        } else if let Some(n) = h.strip_suffix("_actual_min_n") {
            (n, "min", "Minimum of the 0–20 Hz contact force [N]")
        } else {
            continue;
        };
        let v: Vec<f64> = rows.iter().filter_map(|r| r.get(c)?.parse().ok()).collect();
        if v.is_empty() {
            continue;
        }
        let (lo, hi) = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, &x| {
            (a.0.min(x), a.1.max(x))
        });
        let bins = ((v.len() as f64).sqrt().ceil() as usize).clamp(5, 40);
        let w = ((hi - lo) / bins as f64).max(1e-9);
        let mut counts = vec![0usize; bins];
        for x in &v {
            counts[(((x - lo) / w) as usize).min(bins - 1)] += 1;
        }
        let mut stairs = Vec::new();
        for (i, &k) in counts.iter().enumerate() {
            stairs.push((lo + i as f64 * w, k as f64));
            stairs.push((lo + (i + 1) as f64 * w, k as f64));
        }
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let title = format!("Monte Carlo over {} realisations: {label}, {name}", v.len());
        files.extend(figure(
            &dir.join(format!("montecarlo_{what}_{}", safe(name))),
            &Figure {
                title: &title,
                x_label: label,
                y_label: "Realisations",
                lines: vec![Line::new(format!("{bins} bins"), stairs)],
                log_y: false,
                vmarks: vec![(mean, format!("mean {mean:.2}"))],
                hmarks: Vec::new(),
            },
        )?);
    }
    Ok(files)
}
