//! The figures of a window sweep (`pcsim window`), from its files: the error of σ against the
//! window length for every case (log axis, one figure per tension), and the accuracy-based
//! length against speed per tension with the energy-based lengths beside it (the paper's Fig. 7,
//! with the evidence).

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

use super::{figure, Figure, Line, PALETTE};

struct Row {
    index: usize,
    seed: String,
    speed: f64,
    tension: f64,
    length: Option<f64>,
    eva_fraction_max: Option<f64>,
    eva_step: Option<f64>,
}

fn read_rows(dir: &Path) -> Result<Vec<Row>> {
    let p = dir.join("window.csv");
    let text =
        std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut rows = Vec::new();
    for l in text.lines().skip(1).filter(|l| !l.is_empty()) {
        let f: Vec<&str> = l.split(',').collect();
        if f.len() < 19 {
            bail!("{}: bad row `{l}`", p.display());
        }
        rows.push(Row {
            index: f[0]
                .parse()
                .with_context(|| format!("{}: `{l}`", p.display()))?,
            seed: f[1].to_string(),
            speed: f[2]
                .parse()
                .with_context(|| format!("{}: `{l}`", p.display()))?,
            tension: f[3]
                .parse()
                .with_context(|| format!("{}: `{l}`", p.display()))?,
            length: f[5].parse().ok(),
            eva_step: f[10].parse().ok(),
            eva_fraction_max: f[13].parse().ok(),
        });
    }
    if rows.is_empty() {
        bail!("{} has no cases: nothing to plot", p.display());
    }
    Ok(rows)
}

/// Redraw a window sweep's figures.
pub fn redraw(dir: &Path) -> Result<Vec<PathBuf>> {
    let rows: Vec<Row> = read_rows(dir)?
        .into_iter()
        .filter(|r| r.seed == "0")
        .collect();
    let tol = crate::output::read_manifest(dir)?
        .and_then(|m| m.study.tolerances_pct)
        .map(|t| t.sigma_pct)
        .unwrap_or(3.0);
    let mut tensions: Vec<f64> = rows.iter().map(|r| r.tension).collect();
    tensions.sort_by(f64::total_cmp);
    tensions.dedup();
    let mut files = Vec::new();
    for (ti, &t) in tensions.iter().enumerate() {
        let mut lines = Vec::new();
        for r in rows.iter().filter(|r| r.tension == t) {
            let p = dir.join("cases").join(format!(
                "case{:04}_v{}_t{}_errors.csv",
                r.index, r.speed, r.tension
            ));
            let text = std::fs::read_to_string(&p)
                .with_context(|| format!("cannot read {}", p.display()))?;
            let pts: Vec<(f64, f64)> = text
                .lines()
                .skip(1)
                .filter_map(|l| {
                    let f: Vec<f64> = l.split(',').filter_map(|s| s.parse().ok()).collect();
                    (f.len() >= 3 && f[2].is_finite()).then(|| (f[0], f[2].abs().max(1e-3)))
                })
                .collect();
            lines.push(Line::new(format!("{} km/h", r.speed), pts).marked());
        }
        let title = format!("Window error against length: σ of the 0–20 Hz force, {t} kN");
        files.extend(figure(
            &dir.join(format!("window_errors_t{ti}")),
            &Figure {
                title: &title,
                x_label: "Window length [m]",
                y_label: "|σ error| against the full model [%]",
                lines,
                log_y: true,
                vmarks: Vec::new(),
                hmarks: vec![(tol, format!("tolerance {tol} %"))],
            },
        )?);
    }
    let mut lines = Vec::new();
    for (i, &t) in tensions.iter().enumerate() {
        let c = PALETTE[i % PALETTE.len()];
        let of = |f: &dyn Fn(&Row) -> Option<f64>| -> Vec<(f64, f64)> {
            rows.iter()
                .filter(|r| r.tension == t)
                .filter_map(|r| f(r).map(|v| (r.speed, v)))
                .collect()
        };
        lines.push(
            Line::new(format!("accuracy-based, {t} kN"), of(&|r| r.length))
                .styled(c, 3)
                .marked(),
        );
        lines.push(Line::dots(
            format!("energy: 99 % of the maximum, {t} kN"),
            of(&|r| r.eva_fraction_max),
            c,
        ));
        lines.push(
            Line::new(
                format!("energy: the paper's step criterion, {t} kN"),
                of(&|r| r.eva_step),
            )
            .styled(c, 1),
        );
    }
    // The axis is chosen by the lengths that matter (the accuracy-based one and the paper's step
    // criterion, 100–300 m): the 99 % lengths (often 700–1 400 m) would squash them, and are
    // named in a note when they lie above it.
    let mattering = rows
        .iter()
        .flat_map(|r| [r.length, r.eva_step])
        .flatten()
        .fold(160.0f64, f64::max);
    files.extend(crate::plot::clipped_figure(
        &dir.join("window_length"),
        &crate::plot::Clipped {
            figure: Figure {
                title: "Real-time window length: by accuracy against the full model, and by energy (Eq. 21)",
                x_label: "Speed [km/h]",
                y_label: "Window length [m]",
                lines,
                log_y: false,
                vmarks: Vec::new(),
                hmarks: vec![(160.0, "the paper: at least 160 m".into())],
            },
            y_max: 1.4 * mattering,
        },
    )?);
    Ok(files)
}
