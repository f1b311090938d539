//! The figures of a design search (`pcsim design`), from `design.csv` and `traces.csv`: the
//! objective's progress over the evaluations, and per speed the best design's contact force
//! against the base design's.

use anyhow::{Context, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::{figure, safe, Figure, Line, COLOURS};

/// (design, pantograph) → the force along the track, of one speed.
type Traces = BTreeMap<(String, String), Vec<(f64, f64)>>;

fn read_csv(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    let mut r =
        csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    let header = r.headers()?.iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|x| Ok(x?.iter().map(String::from).collect()))
        .collect::<Result<Vec<Vec<String>>>>()?;
    Ok((header, rows))
}

/// Redraw the figures of a design directory.
pub fn redraw(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let (h, rows) = read_csv(&dir.join("design.csv"))?;
    let col = |n: &str| h.iter().position(|c| c == n);
    let (Some(ci), Some(cp), Some(co), Some(cf)) = (
        col("evaluation"),
        col("phase"),
        col("objective"),
        col("feasible"),
    ) else {
        anyhow::bail!(
            "{}: not a design search's journal",
            dir.join("design.csv").display()
        );
    };
    let mut feasible = Vec::new();
    let mut infeasible = 0;
    let mut best_so_far = Vec::new();
    let mut best = f64::INFINITY;
    for r in rows.iter().filter(|r| r[cp] == "search") {
        let (Ok(i), Ok(o)) = (r[ci].parse::<f64>(), r[co].parse::<f64>()) else {
            infeasible += 1;
            continue;
        };
        if r[cf] == "true" {
            feasible.push((i, o));
            if o < best {
                best = o;
            }
            best_so_far.push((i, best));
        } else {
            infeasible += 1;
        }
    }
    let title = format!(
        "Design search: the objective over the evaluations ({} feasible, {infeasible} infeasible or failed, not drawn)",
        feasible.len()
    );
    files.extend(figure(
        &dir.join("design_progress"),
        &Figure {
            title: &title,
            x_label: "Evaluation",
            y_label: "Objective",
            lines: vec![
                Line::dots("feasible designs", feasible, COLOURS[0]),
                Line::new("best so far", best_so_far).styled(COLOURS[1], 2),
            ],
            log_y: false,
            vmarks: Vec::new(),
            hmarks: Vec::new(),
        },
    )?);
    let tp = dir.join("traces.csv");
    if tp.exists() {
        let (_, rows) = read_csv(&tp)?;
        let mut by_speed: BTreeMap<String, Traces> = BTreeMap::new();
        for r in &rows {
            let (Ok(x), Ok(f)) = (r[3].parse::<f64>(), r[4].parse::<f64>()) else {
                continue;
            };
            by_speed
                .entry(r[1].clone())
                .or_default()
                .entry((r[0].clone(), r[2].clone()))
                .or_default()
                .push((x, f));
        }
        for (speed, lines) in by_speed {
            let title = format!("Contact force at {speed} km/h: the best design against the base");
            let lines = lines
                .into_iter()
                .map(|((design, panto), pts)| {
                    let colour = if design == "best" {
                        COLOURS[1]
                    } else {
                        COLOURS[0]
                    };
                    Line::new(format!("{design}, {panto}"), pts).styled(colour, 1)
                })
                .collect();
            files.extend(figure(
                &dir.join(format!("design_force_{}", safe(&speed))),
                &Figure {
                    title: &title,
                    x_label: "Pantograph position [m]",
                    y_label: "Contact force (unfiltered) [N]",
                    lines,
                    log_y: false,
                    vmarks: Vec::new(),
                    hmarks: Vec::new(),
                },
            )?);
        }
    }
    Ok(files)
}
